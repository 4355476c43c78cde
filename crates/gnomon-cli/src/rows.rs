//! The rows of `compare` and `flicker`: a label, a technique with its parameters, its maps'
//! resolution, and the parameters that give it (for the command that reproduces a cell).
//! A row is named by a technique of [`crate::names`] or one of its fixed rows
//! (`sppsm-same-texels`, `paraboloid-cube-texels`, [`crate::names::CASCADE_ROWS`]).

use gnomon::{ShadowTechnique, Technique};
use gnomon_render::MapRead;

use crate::CliError;
use crate::args::{TechniqueParams, timed_setup};
use crate::names::{CASCADE_ROWS, PARABOLOID_CUBE_TEXELS, SPPSM_SAME_TEXELS};

/// One row.
#[derive(Debug, Clone)]
pub struct Row {
    /// Its name in tables.
    pub label: String,
    /// The technique with its parameters.
    pub technique: Technique,
    /// The resolution of its maps (the setup's `--shadow-map`).
    pub resolution: u32,
    /// The options that give it.
    pub params: TechniqueParams,
    /// How its maps are read: by depth, or (on the focused maps) as another of the
    /// lecture's light-space maps ([`crate::names::MAP_READS`]).
    pub read: MapRead,
}

impl Row {
    /// Its `--technique` name on the command line.
    pub fn technique_name(&self) -> &'static str {
        match self.read {
            MapRead::Depth => self.technique.name(),
            read => crate::names::read_name(read),
        }
    }

    /// Whether it draws projective texture shadows (its scene's ground a receiver only).
    pub fn projective(&self) -> bool {
        self.read == MapRead::Coverage
    }

    /// The renderer's settings of this row: `base`, with the row's map read.
    pub fn settings(&self, base: &gnomon_render::RenderSettings) -> gnomon_render::RenderSettings {
        gnomon_render::RenderSettings {
            read: self.read,
            ..*base
        }
    }

    /// Why the row cannot draw `lights` (`cube` and `paraboloid` take point lights only;
    /// SPPSM and the cascades take no point light), or `None` when it can.
    pub fn refuses(&self, lights: &[gnomon::Light]) -> Option<&'static str> {
        let refused = lights.iter().find(|l| !self.technique.takes(l))?;
        Some(match refused {
            gnomon::Light::Point(_) => "takes no point light",
            _ => "takes point lights only",
        })
    }
}

/// The options of a fixed row, parsed by the one definition of the technique options.
#[derive(clap::Parser)]
struct RowOptions {
    #[command(flatten)]
    params: TechniqueParams,
}

fn fixed_row_params(options: &str) -> TechniqueParams {
    use clap::Parser;
    RowOptions::try_parse_from(std::iter::once("row").chain(options.split_whitespace()))
        .expect("the fixed rows' options parse")
        .params
}

/// The row named `name`: a technique (with `params` applied, at `shadow_map`), or a fixed
/// row (`sppsm-same-texels`: SPPSM with two maps of half the area; the cascade rows with
/// their own options).
pub fn row(name: &str, params: &TechniqueParams, shadow_map: u32) -> Result<Row, CliError> {
    let name = name.trim();
    if name == SPPSM_SAME_TEXELS {
        return Ok(Row {
            label: name.into(),
            technique: params.apply(Technique::Sppsm(Default::default())),
            resolution: ((shadow_map as f64) / std::f64::consts::SQRT_2).round() as u32,
            params: *params,
            read: MapRead::Depth,
        });
    }
    if name == PARABOLOID_CUBE_TEXELS {
        return Ok(Row {
            label: name.into(),
            technique: params.apply(Technique::Paraboloid(Default::default())),
            resolution: ((shadow_map as f64) * 3f64.sqrt()).round() as u32,
            params: *params,
            read: MapRead::Depth,
        });
    }
    if let Some((label, options)) = CASCADE_ROWS.iter().find(|(n, _)| *n == name) {
        let params = fixed_row_params(options);
        return Ok(Row {
            label: (*label).into(),
            technique: params.apply(Technique::Cascades(Default::default())),
            resolution: shadow_map,
            params,
            read: MapRead::Depth,
        });
    }
    if let Some((label, read)) = crate::names::MAP_READS.iter().find(|(n, _)| *n == name) {
        return Ok(Row {
            label: (*label).into(),
            technique: params.apply(Technique::Focused(Default::default())),
            resolution: shadow_map,
            params: *params,
            read: *read,
        });
    }
    let technique = crate::names::parse_map(name).map_err(|e| {
        CliError::usage(format!(
            "{e}; rows: {SPPSM_SAME_TEXELS}, {PARABOLOID_CUBE_TEXELS}, {}",
            CASCADE_ROWS.map(|r| r.0).join(", ")
        ))
    })?;
    Ok(Row {
        label: technique.name().to_string(),
        technique: params.apply(technique),
        resolution: shadow_map,
        params: *params,
        read: MapRead::Depth,
    })
}

/// Rows by name (`all`: every map technique; `projective`, `object-id`, `id-depth`: the
/// focused maps read as the lecture's other light-space maps), each named once; `params` must be read by one of
/// the techniques (the fixed rows keep their own). With `expand`, SPPSM is followed by
/// `sppsm-same-texels`, paraboloid by `paraboloid-cube-texels` and cascades by the cascade rows (`compare`'s tables).
pub fn rows(
    names: &[String],
    params: &TechniqueParams,
    shadow_map: u32,
    expand: bool,
) -> Result<Vec<Row>, CliError> {
    // `all`: every map technique, then the other names given.
    let names: Vec<String> = if names.iter().any(|t| t.trim() == "all") {
        Technique::NAMES
            .iter()
            .map(|n| n.to_string())
            .chain(
                names
                    .iter()
                    .filter(|t| t.trim() != "all" && !Technique::NAMES.contains(&t.trim()))
                    .cloned(),
            )
            .collect()
    } else {
        names.to_vec()
    };
    let mut rows: Vec<Row> = Vec::new();
    for name in &names {
        let r = row(name, params, shadow_map)?;
        if rows.iter().any(|u| u.label == r.label) {
            return Err(CliError::usage(format!(
                "--techniques names {} twice",
                r.label
            )));
        }
        rows.push(r);
    }
    let own: Vec<Technique> = rows
        .iter()
        .filter(|r| r.params == *params)
        .map(|r| r.technique)
        .collect();
    if !own.is_empty() {
        params.check_used_by(&own)?;
    }
    if !expand {
        return Ok(rows);
    }
    let mut expanded = Vec::new();
    for r in rows {
        let extras: Vec<&str> = match r.technique {
            Technique::Sppsm(_) if r.label == "sppsm" => vec![SPPSM_SAME_TEXELS],
            Technique::Paraboloid(_) if r.label == "paraboloid" => vec![PARABOLOID_CUBE_TEXELS],
            Technique::Cascades(_) if r.label == "cascades" => {
                CASCADE_ROWS.iter().map(|(n, _)| *n).collect()
            }
            _ => Vec::new(),
        };
        // A row already added as another's extra (cascades-stable after cascades) stays
        // where it was.
        if !expanded.iter().any(|u: &Row| u.label == r.label) {
            expanded.push(r);
        }
        for extra in extras {
            if !expanded.iter().any(|u: &Row| u.label == extra) {
                expanded.push(row(extra, params, shadow_map)?);
            }
        }
    }
    Ok(expanded)
}

/// What the reproduce commands of one run share: the scene's options, the run's technique
/// parameters and map size (for what draws no row of its own), the image size.
pub struct Commands<'a> {
    pub scene_options: &'a str,
    pub params: &'a TechniqueParams,
    pub shadow_map: u32,
    pub size: (u32, u32),
}

impl Commands<'_> {
    /// The `gnomon render` command that draws `name` in `view`: a map row's with its
    /// technique, parameters and map size, else (the volumes, planar shadows) with the run's;
    /// `extra` its output options.
    pub fn render(
        &self,
        view: &gnomon_scene::NamedView,
        row: Option<&Row>,
        name: &str,
        extra: &str,
    ) -> String {
        let (technique, params, resolution) = match row {
            Some(r) => (Some(&r.technique), &r.params, r.resolution),
            None => (None, self.params, self.shadow_map),
        };
        crate::args::render_command(
            self.scene_options,
            view,
            (technique, name),
            params,
            resolution,
            self.size,
            extra,
        )
    }
}

/// A scene's bounds as each thing drawn needs them: as drawn, and with the ground a receiver
/// only (what projective shadows draw: a casting ground would cover the whole light map),
/// with the ground's instances, so that a renderer shared by several techniques draws each
/// as it should.
pub struct RowScene {
    bounds: gnomon::SceneBounds,
    receiving_ground: Option<gnomon::SceneBounds>,
    grounds: Vec<usize>,
}

impl RowScene {
    /// The bounds of `scene`, and where `projective` is drawn too, with its ground a
    /// receiver only.
    pub fn new(scene: &gnomon_render::RenderScene, projective: bool) -> Result<Self, CliError> {
        let grounds = scene
            .instances
            .iter()
            .enumerate()
            .filter(|(_, i)| i.name == "ground" && i.casts)
            .map(|(k, _)| k)
            .collect();
        let receiving_ground = if projective {
            Some(
                crate::names::drawn_scene(
                    crate::names::Drawn::Read(MapRead::Coverage),
                    scene.clone(),
                )
                .bounds()?,
            )
        } else {
            None
        };
        Ok(Self {
            bounds: scene.bounds()?,
            receiving_ground,
            grounds,
        })
    }

    /// The scene's bounds as drawn.
    pub fn bounds(&self) -> &gnomon::SceneBounds {
        &self.bounds
    }

    /// The bounds a technique sets up with, after making `renderer`'s ground cast as it
    /// draws: a receiver only where `projective`.
    pub fn prepare(
        &self,
        renderer: &mut gnomon_render::Renderer,
        projective: bool,
    ) -> Result<&gnomon::SceneBounds, CliError> {
        for &k in &self.grounds {
            renderer.set_instance_casts(k, !projective)?;
        }
        Ok(match (&self.receiving_ground, projective) {
            (Some(b), true) => b,
            _ => &self.bounds,
        })
    }

    /// Makes `renderer`'s ground cast again (before what reads no map: the volumes, planar
    /// shadows).
    pub fn restore(&self, renderer: &mut gnomon_render::Renderer) -> Result<(), CliError> {
        self.prepare(renderer, false).map(|_| ())
    }

    /// Draws `row` in one view, as every command that compares rows does: the scene as the
    /// row draws it, each light's setup with that light's view samples, then the frame with
    /// the row's settings over `base`.
    pub fn draw(
        &self,
        renderer: &mut gnomon_render::Renderer,
        row: &Row,
        (camera, lights, samples): (&gnomon::Camera, &[gnomon::Light], &[gnomon::ViewSamples]),
        base: &gnomon_render::RenderSettings,
    ) -> Result<RowFrame, CliError> {
        let bounds = self.prepare(renderer, row.projective())?;
        let (setups, setup_us) = light_setups(row, camera, lights, bounds, samples)?;
        let shadowed = gnomon_render::ShadowedLight::pairs(lights, &setups);
        let frame = renderer.render_lights(camera, &shadowed, &row.settings(base))?;
        Ok(RowFrame {
            setups,
            setup_us,
            frame,
        })
    }
}

/// One row drawn in one view.
pub struct RowFrame {
    /// Each light's setup.
    pub setups: Vec<gnomon::ShadowSetup>,
    /// Their setup time together, in microseconds.
    pub setup_us: f64,
    /// The frame.
    pub frame: gnomon_render::Frame,
}

/// A row's setup for each light (with that light's view samples) and their total time in
/// microseconds.
pub fn light_setups(
    row: &Row,
    camera: &gnomon::Camera,
    lights: &[gnomon::Light],
    bounds: &gnomon::SceneBounds,
    samples: &[gnomon::ViewSamples],
) -> Result<(Vec<gnomon::ShadowSetup>, f64), CliError> {
    let mut setups = Vec::with_capacity(lights.len());
    let mut total_us = 0.0;
    for (light, samples) in lights.iter().zip(samples) {
        let (setup, us) = timed_setup(
            &row.technique,
            camera,
            light,
            bounds,
            row.resolution,
            Some(samples),
        )?;
        setups.push(setup);
        total_us += us;
    }
    Ok((setups, total_us))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expanded_rows_name_each_row_once() {
        let names: Vec<String> = ["cascades", "cascades-stable", "sppsm", "focused"]
            .map(String::from)
            .to_vec();
        let rows = rows(&names, &TechniqueParams::default(), 1024, true).unwrap();
        let labels: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "cascades",
                "cascades-stable",
                "cascades-lispsm",
                "cascades-best",
                "sppsm",
                "sppsm-same-texels",
                "focused"
            ]
        );
    }
}
