//! `gnomon demo`: a scene (the built-in demo by default) from its named views with every
//! technique, the exact shadow volumes and soft shadows, written as a gallery
//! ([`crate::gallery`]): a front page of the rows that differ, and every cell on a second page.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use gnomon_render::{RenderSettings, Renderer, StencilMode};
use gnomon_scene::NamedView;
use serde_json::json;

use crate::CliError;
use crate::args::{SceneArgs, TechniqueParams, ViewListArgs};
use crate::gallery::{Cell, CellWriter, Kind, ViewCells};
use crate::render::{SoftArgs, open_renderer};
use crate::report::row_record;
use crate::rows::{Commands, Row, RowScene};

/// `gnomon demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub views: ViewListArgs,
    /// Where to write the gallery (index.html, all.html, setups.json and the images).
    #[arg(long, default_value = "gnomon-demo")]
    pub out: PathBuf,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Image width in pixels, 64 to 4096 (the height follows at 16:9).
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(64..=4096))]
    pub width: u32,
    #[command(flatten)]
    pub params: TechniqueParams,
}

/// The radius of the area lights of the gallery's soft row: the sun's angular radius
/// (degrees), and for spot and point lights a street lamp's globe of 25 cm (world units).
fn soft_radius(light: &gnomon::Light) -> f64 {
    match light {
        gnomon::Light::Directional(_) => 0.27,
        _ => 0.25,
    }
}

/// The hard lights that sample each area light in the gallery's soft row (a picture;
/// `compare --pcf pcss` measures with 64 by default).
const SOFT_SAMPLES: usize = 32;

/// The map technique the gallery softens with PCSS (it takes every kind of light).
const PCSS_TECHNIQUE: &str = "lispsm";

/// Each map's light-view thumbnail, in texels: the page shows them a few hundred pixels wide.
const LIGHT_VIEW_SIZE: u32 = 384;

/// Everything a demo run shares between its views, made once.
struct Demo<'a> {
    args: &'a DemoArgs,
    options: String,
    renderer: Renderer,
    settings: RenderSettings,
    rows: Vec<Row>,
    row_scene: RowScene,
    planar: Option<gnomon::planar::PlanarReceiver>,
    pcss_row: Row,
    cells: CellWriter,
}

/// Runs `gnomon demo`: load, draw every view, write the pages.
pub fn run(args: &DemoArgs) -> Result<(), CliError> {
    let started = Instant::now();
    let loaded = args.scene.load()?;
    let views = args.views.select(&loaded.views)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| CliError::runtime(format!("cannot create {}: {e}", args.out.display())))?;
    let mut demo = Demo::open(args, &loaded, views.len())?;
    let mut drawn = Vec::with_capacity(views.len());
    for view in &views {
        drawn.push(demo.draw_view(view)?);
    }
    demo.cells.progress.set_message("writing the pages");
    let page = crate::gallery::Page {
        scene: &loaded.name,
        size: demo.size(),
        shadow_map: args.shadow_map,
        device: demo.renderer.gpu().describe(),
    };
    crate::gallery::write(&args.out, &page, &drawn)?;
    crate::render::write_text(
        &args.out.join("setups.json"),
        &serde_json::to_string_pretty(demo.cells.records()).expect("JSON of plain values"),
    )?;
    demo.cells.progress.inc(1);
    demo.cells.progress.finish_and_clear();
    eprintln!(
        "gnomon demo: {} views, {} frames on {} in {:.1} s",
        views.len(),
        demo.cells.progress.length().unwrap_or(0) - 1,
        demo.renderer.gpu().describe(),
        started.elapsed().as_secs_f64()
    );
    crate::say!("wrote {}", args.out.join("index.html").display());
    Ok(())
}

impl<'a> Demo<'a> {
    /// The renderer, the rows (every technique, the cascade rows, the lecture's other map
    /// reads), planar shadows where the scene has a ground, and a progress bar over every
    /// frame of every view and the pages.
    fn open(
        args: &'a DemoArgs,
        loaded: &crate::args::LoadedScene,
        views: usize,
    ) -> Result<Self, CliError> {
        let (width, height) = (args.width, args.width * 9 / 16);
        let renderer = open_renderer(&loaded.scene, (width, height), Some(args.shadow_map))?;
        let names: Vec<String> = std::iter::once("all")
            .chain(crate::names::MAP_READS.iter().map(|(n, _)| *n))
            .map(String::from)
            .collect();
        let rows = crate::rows::rows(&names, &args.params, args.shadow_map, true)?;
        let row_scene = RowScene::new(&loaded.scene, rows.iter().any(|r| r.projective()))?;
        let planar = crate::render::planar_receiver(&loaded.scene, None).ok();
        let pcss_row = crate::rows::row(PCSS_TECHNIQUE, &args.params, args.shadow_map)?;
        // Every map row, planar, the volumes, the soft reference and PCSS per view; the pages.
        let per_view = rows.len() + 3 + usize::from(planar.is_some());
        let cells = CellWriter::new(&args.out, views * per_view + 1);
        Ok(Self {
            args,
            options: loaded.options.clone(),
            renderer,
            settings: RenderSettings {
                width,
                height,
                light_view: true,
                light_view_size: LIGHT_VIEW_SIZE,
                metrics: true,
                ..RenderSettings::default()
            },
            rows,
            row_scene,
            planar,
            pcss_row,
            cells,
        })
    }

    fn size(&self) -> (u32, u32) {
        (self.settings.width, self.settings.height)
    }

    /// One view: every map row, planar shadows, the exact volumes, the soft reference and
    /// PCSS; then each map cell's wrong pixels against the volumes, keeping only the pixels
    /// the front page may show.
    fn draw_view(&mut self, view: &NamedView) -> Result<ViewCells, CliError> {
        let (width, height) = self.size();
        let camera = view.camera(width as f64 / height as f64)?;
        let lights = view.lights()?;
        let samples = lights
            .iter()
            .map(|light| self.renderer.view_samples(&camera, light))
            .collect::<Result<Vec<_>, _>>()?;
        let mut cells = Vec::new();
        for i in 0..self.rows.len() {
            cells.push(self.map_cell(view, &camera, &lights, &samples, i)?);
        }
        self.row_scene.restore(&mut self.renderer)?;
        if self.planar.is_some() {
            cells.push(self.planar_cell(view, &camera, &lights)?);
        }
        let exact = self.volumes_cell(view, &camera, &lights)?;
        let (soft, factor) = self.soft_cell(view, &camera, &lights)?;
        let pcss = self.pcss_cell(view, &camera, &lights, &samples, &factor)?;
        cells.extend([exact, soft, pcss]);
        let mut drawn = ViewCells {
            view: view.clone(),
            directional: matches!(lights[0], gnomon::Light::Directional(_)),
            cells,
        };
        drawn.judge_against_exact();
        drawn.keep_front_pixels_only();
        Ok(drawn)
    }

    /// What the cells' reproduce commands share.
    fn commands(&self) -> Commands<'_> {
        Commands {
            scene_options: &self.options,
            params: &self.args.params,
            shadow_map: self.args.shadow_map,
            size: self.size(),
        }
    }

    /// Row `i` (a shadow-map technique) on `view`, or a cell that says why it is not drawn.
    fn map_cell(
        &mut self,
        view: &NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
        samples: &[gnomon::ViewSamples],
        i: usize,
    ) -> Result<Cell, CliError> {
        let row = &self.rows[i];
        let stem = format!("{}_{}", view.name, row.label);
        if let Some(why) = row.refuses(lights) {
            let label = row.label.clone();
            return Ok(self.cells.skipped(&view.name, &label, why));
        }
        let lit = (camera, lights, samples);
        let drawn = (self.row_scene).draw(&mut self.renderer, row, lit, &self.settings)?;
        let (setups, setup_us, frame) = (drawn.setups, drawn.setup_us, drawn.frame);
        let t = frame.timings;
        let command = self.commands().render(
            view,
            Some(row),
            row.technique_name(),
            &format!(" --out {stem}.png --light-view {stem}_light.png"),
        );
        let cell = Cell {
            figures: format!(
                "setup {setup_us:.0} µs · shadow pass {:.1} ms · main pass {:.1} ms",
                t.shadow_pass_ms, t.main_pass_ms
            ),
            fallbacks: crate::gallery::fallback_words(&setups[0]),
            light_view: true,
            ..Cell::drawn(&view.name, &row.label, stem, command, Kind::Map, &frame)
        };
        let record = json!({
            "setup_us": setup_us,
            "shadow_pass_ms": t.shadow_pass_ms,
            "main_pass_ms": t.main_pass_ms,
            "setup": gnomon_tools::setup_json(&setups[0]),
        });
        let record = row_record(Some(&view.name), &row.label, record);
        self.cells.write(cell, &frame, record)
    }

    /// Planar projected shadows on the ground (nothing else receives: the limit).
    fn planar_cell(
        &mut self,
        view: &NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
    ) -> Result<Cell, CliError> {
        let receiver = self.planar.as_ref().expect("asked where there is a ground");
        let drawn = self
            .renderer
            .render_planar_lit_by(camera, lights, receiver, &self.settings)?;
        let stem = format!("{}_planar", view.name);
        let t = drawn.frame.timings;
        let command = (self.commands()).render(
            view,
            None,
            crate::names::PLANAR,
            &format!(" --out {stem}.png"),
        );
        let cell = Cell {
            figures: format!(
                "{} flattened triangles · flattening and stencil {:.1} ms · shading {:.1} ms",
                drawn.stats.triangles, t.shadow_pass_ms, t.main_pass_ms
            ),
            ..Cell::drawn(
                &view.name,
                crate::names::PLANAR,
                stem,
                command,
                Kind::Planar,
                &drawn.frame,
            )
        };
        let record = json!({
            "flattened_triangles": drawn.stats.triangles,
            "flattening_and_stencil_ms": t.shadow_pass_ms,
            "shading_ms": t.main_pass_ms,
        });
        let record = row_record(Some(&view.name), crate::names::PLANAR, record);
        self.cells.write(cell, &drawn.frame, record)
    }

    /// Exact shadows: stenciled shadow volumes, z-pass or z-fail chosen per caster.
    fn volumes_cell(
        &mut self,
        view: &NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
    ) -> Result<Cell, CliError> {
        let drawn = self.renderer.render_volumes_lit_by(
            camera,
            lights,
            &self.settings,
            StencilMode::PerCaster,
        )?;
        let stem = format!("{}_volumes", view.name);
        let (t, stats) = (drawn.frame.timings, drawn.stats);
        let command = self.commands().render(
            view,
            None,
            "volumes",
            &format!(" --stencil per-caster --out {stem}.png"),
        );
        let cell = Cell {
            figures: format!(
                "{} volume triangles ({} casters z-pass, {} z-fail) · extrusion and stencil \
                 {:.1} ms · shading {:.1} ms",
                stats.triangles,
                stats.z_pass_casters,
                stats.z_fail_casters,
                t.shadow_pass_ms,
                t.main_pass_ms
            ),
            ..Cell::drawn(
                &view.name,
                "volumes",
                stem,
                command,
                Kind::Exact,
                &drawn.frame,
            )
        };
        let record = json!({
            "stencil": "per-caster",
            "volume_triangles": stats.triangles,
            "extrusion_and_stencil_ms": t.shadow_pass_ms,
            "shading_ms": t.main_pass_ms,
        });
        let record = row_record(Some(&view.name), "volumes", record);
        self.cells.write(cell, &drawn.frame, record)
    }

    /// The soft args of the view's main light as an area light.
    fn soft_args(lights: &[gnomon::Light], pcf: crate::render::PcfArg) -> SoftArgs {
        SoftArgs {
            pcf,
            area_light: Some(soft_radius(&lights[0])),
            area_samples: (pcf != crate::render::PcfArg::Pcss).then_some(SOFT_SAMPLES),
        }
    }

    /// Soft shadows of the main light as an area light: the reference, a cluster of hard
    /// lights with exact volumes; also its shadow factor, which PCSS is judged against.
    fn soft_cell(
        &mut self,
        view: &NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
    ) -> Result<(Cell, Vec<Option<f32>>), CliError> {
        let soft = Self::soft_args(lights, crate::render::PcfArg::Hardware2x2);
        let clusters = soft
            .area_clusters(lights, &self.row_scene.bounds().scene_box())?
            .expect("an area light is given");
        let reference = self.renderer.render_soft_volumes(
            camera,
            &clusters,
            &self.settings,
            StencilMode::PerCaster,
        )?;
        let stem = format!("{}_soft", view.name);
        let t = reference.frame.timings;
        let extra = format!("{} --out {stem}.png", soft.non_default_flags());
        let command = self.commands().render(view, None, "volumes", &extra);
        let cell = Cell {
            figures: format!(
                "{SOFT_SAMPLES} hard lights with exact volumes · {:.1} ms",
                t.shadow_pass_ms + t.main_pass_ms
            ),
            ..Cell::drawn(
                &view.name,
                "soft",
                stem,
                command,
                Kind::Soft,
                &reference.frame,
            )
        };
        let record = json!({
            "area_light": soft.area_light,
            "area_samples": SOFT_SAMPLES,
            "ms": t.shadow_pass_ms + t.main_pass_ms,
        });
        let record = row_record(Some(&view.name), "soft-volumes", record);
        let cell = self.cells.write(cell, &reference.frame, record)?;
        Ok((cell, reference.factor))
    }

    /// PCSS on the LiSPSM map with the same area light, and its penumbra error against the
    /// reference's shadow factor.
    fn pcss_cell(
        &mut self,
        view: &NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
        samples: &[gnomon::ViewSamples],
        reference: &[Option<f32>],
    ) -> Result<Cell, CliError> {
        let label = format!("pcss ({PCSS_TECHNIQUE})");
        if let Some(why) = self.pcss_row.refuses(lights) {
            return Ok(self.cells.skipped(&view.name, &label, why));
        }
        let pcss = Self::soft_args(lights, crate::render::PcfArg::Pcss);
        let settings = RenderSettings {
            filter: gnomon_render::Filter::Pcss,
            area_light_radius: pcss.pcss_radius(),
            light_view: false,
            ..self.settings
        };
        let lit = (camera, lights, samples);
        let drawn = (self.row_scene).draw(&mut self.renderer, &self.pcss_row, lit, &settings)?;
        let (setup_us, frame) = (drawn.setup_us, drawn.frame);
        let error = gnomon_render::penumbra_error(
            reference,
            frame.shadow.as_deref().expect("a map frame has its factor"),
            &frame.metrics.as_ref().expect("asked for").n_dot_l,
        );
        let stem = format!("{}_pcss", view.name);
        let t = frame.timings;
        let extra = format!("{} --out {stem}.png", pcss.non_default_flags());
        let row = Some(&self.pcss_row);
        let command = (self.commands()).render(view, row, self.pcss_row.technique_name(), &extra);
        let cell = Cell {
            figures: format!(
                "penumbra error {:.3} against the reference over {} pixels · shadow pass {:.1} \
                 ms · main pass {:.1} ms",
                error.mean, error.pixels, t.shadow_pass_ms, t.main_pass_ms
            ),
            ..Cell::drawn(&view.name, &label, stem, command, Kind::Soft, &frame)
        };
        let record = json!({
            "map_technique": PCSS_TECHNIQUE,
            "area_light": pcss.area_light,
            "penumbra_error": error.mean,
            "penumbra_pixels": error.pixels,
            "setup_us": setup_us,
            "shadow_pass_ms": t.shadow_pass_ms,
            "main_pass_ms": t.main_pass_ms,
        });
        let record = row_record(Some(&view.name), "pcss", record);
        self.cells.write(cell, &frame, record)
    }
}
