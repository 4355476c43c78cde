//! `gnomon render` and `gnomon export`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use gnomon::ShadowTechnique;
use gnomon_render::{
    DepthBias, Filter, Frame, Gpu, RenderScene, RenderSettings, Renderer, StencilMode,
};

use crate::args::{LightArgs, SceneArgs, TechniqueParams, ViewArgs, timed_setup};
use crate::names::{Drawn, drawn_scene};
use crate::{CliError, heatmap};

/// Shadow-map filtering on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PcfArg {
    /// One tap.
    None,
    /// Hardware 2x2 bilinear comparison.
    #[value(name = "2x2")]
    Hardware2x2,
    /// 5x5 percentage closer filtering.
    #[value(name = "5x5")]
    Pcf5x5,
    /// Percentage-closer soft shadows of an area light of --area-light's radius (blocker
    /// search, penumbra from the blockers' distance; footprints carried into each map by its
    /// Jacobian, so warped maps and cascades soften right).
    Pcss,
}

impl From<PcfArg> for Filter {
    fn from(p: PcfArg) -> Self {
        match p {
            PcfArg::None => Filter::None,
            PcfArg::Hardware2x2 => Filter::Hardware2x2,
            PcfArg::Pcf5x5 => Filter::Pcf5x5,
            PcfArg::Pcss => Filter::Pcss,
        }
    }
}

/// How shadow volumes are counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StencilArg {
    /// Count faces behind the surface (Carmack's reverse).
    ZFail,
    /// Count faces in front of the surface.
    ZPass,
    /// Per caster: z-pass without caps where its volume cannot reach the near plane, z-fail
    /// elsewhere (exact, and faster).
    PerCaster,
}

/// `gnomon render`.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub light: LightArgs,
    #[command(flatten)]
    pub draw: DrawArgs,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", allow_hyphen_values = true, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Where to write the image (PNG).
    #[arg(long, default_value = "frame.png")]
    pub out: PathBuf,
    /// Also write the direct-light mask (PNG, one value per pixel sampled at its centre:
    /// 255 lit, 0 not lit, 128 no geometry). With soft shadows (--area-light for the
    /// volumes, --pcf pcss for a map) it is the main light's shadow factor instead: 255 x the
    /// factor, 0 where there is no geometry.
    #[arg(long)]
    pub mask: Option<PathBuf>,
    /// Also write the shadow map as the light sees it, with the view frustum over it (PNG;
    /// SPPSM: both maps side by side, the focused one on the left).
    #[arg(long)]
    pub light_view: Option<PathBuf>,
    /// Also write the per-pixel sampling error as a heat map with a legend (PNG): pixels per
    /// texel along the worst direction, from the shader's derivatives of the shadow
    /// coordinate; 1 = one texel per pixel (white), warmer = undersampled, blue = more than
    /// one texel per pixel.
    #[arg(long)]
    pub error_map: Option<PathBuf>,
    /// Print a JSON summary on stdout: timings, fallback, and the sampling error's
    /// percentiles (p50, p95, p99, max) over the visible pixels that face the light
    /// (N.L > 0.1).
    #[arg(long)]
    pub json: bool,
}

/// What is drawn and how: the technique, its parameters, the map, filtering, bias and tint;
/// shared by `render` and `view` (one definition of each option).
#[derive(Debug, Clone, Args)]
pub struct DrawArgs {
    /// The shadow technique: a shadow-map technique, `volumes` (exact stenciled shadow
    /// volumes; `volumes-z-pass`, `volumes-per-caster` name a way of counting them), `planar`
    /// (planar projected shadows on the ground, or --receiver-plane; nothing else is
    /// shadowed), or the focused map read as the shadows lecture's other light-space maps:
    /// `projective` (light maps: coverage, casters lit), `object-id` (another object's ID
    /// shadows; no bias, no self-shadowing), `id-depth` (IDs, and depth within an object):
    /// the names of [`crate::names`].
    #[arg(long, default_value = "focused", value_parser = crate::names::drawn_arg)]
    pub technique: Drawn,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Shadow-map resolution in texels (square).
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Shadow volumes: how the stencil counts (z-fail is exact wherever the camera is;
    /// z-pass is wrong where a volume reaches the near plane; per-caster is exact and uses
    /// z-pass where it can).
    /// (Default z-fail.)
    #[arg(long, value_enum)]
    pub stencil: Option<StencilArg>,
    #[command(flatten)]
    pub soft: SoftArgs,
    /// Constant depth bias in world units, 0 to 10^4 (default: 2 cm, scaled down in scenes
    /// whose box is under 10 m across, so that a tabletop or a scene in millimetres keeps its
    /// shadows).
    #[arg(long, value_parser = parse_bias_world, allow_hyphen_values = true)]
    pub bias_constant: Option<f64>,
    /// Slope-scaled depth bias, in texels of depth slope, 0 to 64.
    #[arg(long, default_value_t = DepthBias::default().slope_texels, value_parser = parse_texels, allow_hyphen_values = true)]
    pub bias_slope: f64,
    /// Normal offset, in texels, 0 to 64.
    #[arg(long, default_value_t = DepthBias::default().normal_offset_texels, value_parser = parse_texels, allow_hyphen_values = true)]
    pub normal_offset: f64,
    /// Tint pixels by the map they read: SPPSM's (red: the perspective map, blue: the focused
    /// map, as in the paper's figures), the cascades', a point light's cube faces or
    /// hemispheres.
    #[arg(long)]
    pub tint: bool,
    /// Planar shadows: the receiver plane A,B,C,D (A x + B y + C z + D = 0, receiving where
    /// positive), its part inside the scene's box (default: the top face of the scene's
    /// ground).
    #[arg(long, value_parser = crate::args::parse_plane, allow_hyphen_values = true)]
    pub receiver_plane: Option<[f64; 4]>,
}

/// The shadow maps' filter and the lights' areas (soft shadows), shared by `render`, `view`
/// and `compare` (one definition of each option).
#[derive(Debug, Clone, Args)]
pub struct SoftArgs {
    /// Shadow-map filtering.
    #[arg(long, value_enum, default_value = "2x2")]
    pub pcf: PcfArg,
    /// Soft shadows: each light an area light of this radius (spot and point lights: a disc
    /// of R world units; directional: R degrees, the sun's is 0.27). The exact volumes sample
    /// it by --area-samples hard lights whose frames are averaged (the disc perpendicular to
    /// a spot's direction or facing the scene's centre from a point light), and --mask then
    /// writes the main light's shadow factor (255 x the share of its samples that reach a
    /// pixel; 0 where there is no geometry); a shadow-map technique softens by it with
    /// --pcf pcss.
    #[arg(long, allow_hyphen_values = true)]
    pub area_light: Option<f64>,
    /// The hard lights sampling each area light, 1 to 4096 (default 64).
    #[arg(long, requires = "area_light")]
    pub area_samples: Option<usize>,
}

impl SoftArgs {
    /// Whether the maps are filtered with PCSS.
    pub fn pcss(&self) -> bool {
        self.pcf == PcfArg::Pcss
    }

    /// The area lights' radius PCSS softens with (0 without PCSS).
    pub fn pcss_radius(&self) -> f64 {
        if self.pcss() {
            self.area_light.unwrap_or(0.0)
        } else {
            0.0
        }
    }

    /// The options that differ from their defaults, as written on a command line (each with
    /// a leading space).
    pub fn non_default_flags(&self) -> String {
        let mut flags = String::new();
        if self.pcf != PcfArg::Hardware2x2 {
            let value = self.pcf.to_possible_value().expect("no skipped values");
            flags += &format!(" --pcf {}", value.get_name());
        }
        if let Some(r) = self.area_light {
            flags += &format!(" --area-light {r}");
        }
        if let Some(n) = self.area_samples {
            flags += &format!(" --area-samples {n}");
        }
        flags
    }

    /// Each light's cluster of samples for `--area-light` (`None` without it), the disc of a
    /// point light facing the centre of `scene_box`.
    pub fn area_clusters(
        &self,
        lights: &[gnomon::Light],
        scene_box: &gnomon::Aabb,
    ) -> Result<Option<Vec<Vec<gnomon::Light>>>, CliError> {
        let Some(radius) = self.area_light else {
            return Ok(None);
        };
        let samples = self.area_samples.unwrap_or(DEFAULT_AREA_SAMPLES);
        lights
            .iter()
            .map(|light| {
                let facing = match light {
                    gnomon::Light::Point(p) => scene_box.center() - p.position(),
                    _ => glam::DVec3::ZERO,
                };
                gnomon::area_light::area_light_samples(light, radius, samples, facing)
                    .map_err(CliError::from)
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// Refuses an `--area-light` radius `lights` cannot take (negative; over 45 degrees for a
    /// directional light).
    pub fn check_area_light(&self, lights: &[gnomon::Light]) -> Result<(), CliError> {
        if let Some(radius) = self.area_light {
            for light in lights {
                gnomon::area_light::check_radius(light, radius)
                    .map_err(|e| CliError::usage(format!("--area-light: {e}")))?;
            }
        }
        Ok(())
    }
}

impl DrawArgs {
    /// The renderer's settings of a `size` image: filtering, bias and tint.
    pub fn settings(&self, size: (u32, u32)) -> RenderSettings {
        RenderSettings {
            width: size.0,
            height: size.1,
            filter: self.soft.pcf.into(),
            bias: DepthBias {
                constant_world: self.bias_constant,
                slope_texels: self.bias_slope,
                normal_offset_texels: self.normal_offset,
                ..DepthBias::default()
            },
            tint: self.tint,
            read: self.technique.map_read(),
            area_light_radius: self.soft.pcss_radius(),
            ..RenderSettings::default()
        }
    }

    /// The options of filtering, bias, tint and counting that differ from their defaults, as
    /// they are written on a command line (each with a leading space).
    #[cfg(feature = "viewer")]
    pub fn non_default_flags(&self) -> String {
        let mut flags = self.soft.non_default_flags();
        let defaults = DepthBias::default();
        if let Some(bias) = self.bias_constant {
            flags += &format!(" --bias-constant {bias}");
        }
        if self.bias_slope != defaults.slope_texels {
            flags += &format!(" --bias-slope {}", self.bias_slope);
        }
        if self.normal_offset != defaults.normal_offset_texels {
            flags += &format!(" --normal-offset {}", self.normal_offset);
        }
        if let Some(stencil) = self.stencil {
            let value = stencil.to_possible_value().expect("no skipped values");
            flags += &format!(" --stencil {}", value.get_name());
        }
        if self.tint {
            flags += " --tint";
        }
        if let Some(p) = self.receiver_plane {
            flags += &format!(" --receiver-plane={},{},{},{}", p[0], p[1], p[2], p[3]);
        }
        flags
    }

    /// Refuses the options that only `technique` does not read: `--receiver-plane` without
    /// planar shadows, `--stencil` without the volumes.
    pub fn check_read(&self) -> Result<(), CliError> {
        if self.receiver_plane.is_some() && self.technique != Drawn::Planar {
            return Err(CliError::usage(format!(
                "--receiver-plane places planar shadows; technique {} does not read it",
                self.technique.name()
            )));
        }
        let soft = &self.soft;
        match (self.technique, soft.pcss()) {
            (Drawn::Map(_), true) if soft.area_light.is_none() => {
                return Err(CliError::usage(
                    "--pcf pcss softens by the light's size: give --area-light R (degrees for \
                     a sun, whose is 0.27; world units for spot and point lights)",
                ));
            }
            (Drawn::Map(_), true) | (Drawn::Volumes(_), false) => {}
            (Drawn::Volumes(_) | Drawn::Planar | Drawn::Read(_), true) => {
                return Err(CliError::usage(format!(
                    "--pcf pcss filters shadow maps read by depth; technique {} reads none",
                    self.technique.name()
                )));
            }
            _ if soft.area_light.is_some() => {
                return Err(CliError::usage(format!(
                    "--area-light softens the exact shadow volumes, or a shadow map with --pcf \
                     pcss; technique {} without --pcf pcss does not read it",
                    self.technique.name()
                )));
            }
            _ => {}
        }
        if soft.area_samples.is_some() && !matches!(self.technique, Drawn::Volumes(_)) {
            return Err(CliError::usage(format!(
                "--area-samples samples the exact volumes' area light; technique {} does not \
                 read it",
                self.technique.name()
            )));
        }
        if self.stencil.is_some() && !matches!(self.technique, Drawn::Volumes(_)) {
            return Err(CliError::usage(format!(
                "--stencil counts shadow volumes; technique {} draws none",
                self.technique.name()
            )));
        }
        Ok(())
    }

    /// The counting of shadow volumes: `--stencil` for `volumes`, else the one the name
    /// gives; an error where both are given.
    pub fn stencil_mode(&self, named: StencilMode) -> Result<StencilMode, CliError> {
        match (self.stencil, self.technique.name()) {
            (None, _) => Ok(named),
            (Some(stencil), "volumes") => Ok(match stencil {
                StencilArg::ZFail => StencilMode::ZFail,
                StencilArg::ZPass => StencilMode::ZPass,
                StencilArg::PerCaster => StencilMode::PerCaster,
            }),
            (Some(_), name) => Err(CliError::usage(format!(
                "--technique {name} names the counting already; drop --stencil"
            ))),
        }
    }
}

/// The hard lights sampling an area light unless `--area-samples` says otherwise.
pub const DEFAULT_AREA_SAMPLES: usize = gnomon::area_light::BASE_AREA_SAMPLES;

/// A bias in world units: a number from 0 to 10^4.
fn parse_bias_world(s: &str) -> Result<f64, String> {
    parse_range(s, 0.0, 1e4, "world units")
}

/// A bias in texels: a number from 0 to 64.
fn parse_texels(s: &str) -> Result<f64, String> {
    parse_range(s, 0.0, 64.0, "texels")
}

fn parse_range(s: &str, lo: f64, hi: f64, unit: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !(v.is_finite() && (lo..=hi).contains(&v)) {
        return Err(format!("{s} must be from {lo} to {hi} {unit}"));
    }
    Ok(v)
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got '{s}'"))?;
    let parse = |v: &str| {
        let v = v.trim();
        if v.starts_with('-') {
            return Err(format!(
                "'{s}' has a negative size: give WIDTHxHEIGHT in pixels"
            ));
        }
        v.parse::<u32>()
            .map_err(|_| format!("'{v}' is not a size in pixels"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!(
            "image size {w}x{h} must be within 1..=16384 on each side"
        ));
    }
    Ok((w, h))
}

/// Writes a text file.
pub fn write_text(path: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(path, text)
        .map_err(|e| CliError::runtime(format!("cannot write {}: {e}", path.display())))
}

/// Writes an image file.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    color: image::ColorType,
    bytes: &[u8],
) -> Result<(), CliError> {
    image::save_buffer(path, bytes, width, height, color)
        .map_err(|e| CliError::runtime(format!("cannot write {}: {e}", path.display())))
}

/// Writes a frame's image, and its mask and light view where asked.
pub fn write_frame(
    frame: &Frame,
    out: &Path,
    mask: Option<&Path>,
    light_view: Option<&Path>,
) -> Result<(), CliError> {
    write_png(
        out,
        frame.width,
        frame.height,
        image::ColorType::Rgba8,
        &frame.color,
    )?;
    if let Some(path) = mask {
        write_png(
            path,
            frame.width,
            frame.height,
            image::ColorType::L8,
            &frame.mask,
        )?;
    }
    if let (Some(path), Some(view)) = (light_view, &frame.light_view) {
        write_png(
            path,
            view.width,
            view.height,
            image::ColorType::Rgba8,
            &view.rgba,
        )?;
    }
    Ok(())
}

/// The process's GPU, opened on first use and kept: a suite's scenes share it (see
/// [`Gpu::new`] for why a device is not dropped and opened again). The lock is held while it
/// opens, so that two callers never open two and drop one.
fn process_gpu() -> Result<Gpu, CliError> {
    static GPU: std::sync::Mutex<Option<Gpu>> = std::sync::Mutex::new(None);
    let mut kept = GPU
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(gpu) = kept.as_ref() {
        return Ok(gpu.clone());
    }
    let gpu = Gpu::new()?;
    *kept = Some(gpu.clone());
    Ok(gpu)
}

/// Opens the GPU and refuses, before any rendering, an image or shadow map larger than its
/// largest texture (exit code 2); then builds the renderer.
pub fn open_renderer(
    scene: &RenderScene,
    image: (u32, u32),
    shadow_map: Option<u32>,
) -> Result<Renderer, CliError> {
    let gpu = process_gpu()?;
    let max = gpu.max_texture_size();
    if image.0 > max || image.1 > max {
        return Err(CliError::usage(format!(
            "image size {}x{} exceeds this GPU's largest texture, {max} on a side ({})",
            image.0,
            image.1,
            gpu.describe()
        )));
    }
    if let Some(size) = shadow_map.filter(|s| *s > max) {
        return Err(CliError::usage(format!(
            "--shadow-map {size} exceeds this GPU's largest texture, {max} on a side ({})",
            gpu.describe()
        )));
    }
    Ok(Renderer::new(gpu, scene)?)
}

/// Runs `gnomon render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    check_render_outputs(args)?;
    let loaded = args.scene.load()?;
    let scene = drawn_scene(args.draw.technique, loaded.scene);
    let bounds = scene.bounds()?;
    let camera = args.view.drawn_camera(&loaded.views, args.size)?;
    // Every light of the view (a scene file's view may have several), the first the main one.
    let lights = args.light.lights(&args.view, &loaded.views)?;
    args.draw.check_read()?;
    args.draw.soft.check_area_light(&lights)?;
    let technique = match args.draw.technique {
        Drawn::Volumes(mode) => return run_volumes(args, &scene, &camera, &lights, mode),
        Drawn::Planar => return run_planar(args, &scene, &camera, &lights),
        drawn => drawn.map_technique().expect("a map technique"),
    };
    let technique = checked_technique(args, technique, &camera, &lights, &bounds)?;
    let mut renderer = open_renderer(&scene, args.size, Some(args.draw.shadow_map))?;
    let lit = (&camera, lights.as_slice(), &bounds);
    let (setups, setup_us) = setups_seen(&mut renderer, &technique, lit, args.draw.shadow_map)?;
    if args.draw.tint && setups[0].maps.len() < 2 {
        return Err(tint_needs_two_maps(&technique));
    }
    let settings = RenderSettings {
        light_view: args.light_view.is_some(),
        metrics: args.error_map.is_some() || args.json,
        ..args.draw.settings(args.size)
    };
    let shadowed = gnomon_render::ShadowedLight::pairs(&lights, &setups);
    let mut frame = renderer.render_lights(&camera, &shadowed, &settings)?;
    if args.draw.soft.pcss() {
        soft_mask(&mut frame);
    }
    if let (Some(path), Some(metrics)) = (&args.error_map, &frame.metrics) {
        // The frame's size (the legend lies over its bottom strip).
        let image = heatmap::draw(metrics, frame.width, frame.height);
        write_png(
            path,
            frame.width,
            frame.height,
            image::ColorType::Rgba8,
            &image,
        )?;
    }
    let casters = scene.instances.iter().filter(|i| i.casts).count();
    if args.json {
        print_frame_json(
            &renderer,
            &technique,
            (&setups[0], setup_us),
            &frame,
            casters,
        );
    }
    write_frame(
        &frame,
        &args.out,
        args.mask.as_deref(),
        args.light_view.as_deref(),
    )?;
    print_closing_line(args, &renderer, (&setups[0], setup_us), &frame, casters);
    for (light, setup) in lights.iter().zip(&setups) {
        if let Some(warning) = near_clip_warning(light, &setup.diagnostics) {
            eprintln!("warning: {warning}");
        }
    }
    Ok(())
}

/// Every output checked before any work.
fn check_render_outputs(args: &RenderArgs) -> Result<(), CliError> {
    let png: &[&str] = &["png"];
    let mut outputs = vec![("--out", args.out.as_path(), png)];
    for (option, path) in [
        ("--mask", &args.mask),
        ("--light-view", &args.light_view),
        ("--error-map", &args.error_map),
    ] {
        if let Some(path) = path {
            outputs.push((option, path.as_path(), png));
        }
    }
    crate::output::check_outputs(&outputs)
}

/// The technique with the options' parameters, refused before the GPU opens where they are
/// bad: the setup once from the boxes alone (microseconds) for every light.
fn checked_technique(
    args: &RenderArgs,
    technique: gnomon::Technique,
    camera: &gnomon::Camera,
    lights: &[gnomon::Light],
    bounds: &gnomon::SceneBounds,
) -> Result<gnomon::Technique, CliError> {
    let technique = args.draw.params.apply(technique);
    args.draw.params.check_used_by(&[technique])?;
    // Before any work where the technique says (SPPSM may still fall back to one map; a
    // point light's maps are its cube faces or hemispheres).
    if args.draw.tint
        && !matches!(
            technique,
            gnomon::Technique::Sppsm(_) | gnomon::Technique::Cascades(_)
        )
        && !matches!(lights[0], gnomon::Light::Point(_))
    {
        return Err(tint_needs_two_maps(&technique));
    }
    for light in lights {
        timed_setup(
            &technique,
            camera,
            light,
            bounds,
            args.draw.shadow_map,
            None,
        )?;
    }
    Ok(technique)
}

/// Each light's setup with what the renderer's pixels see from it; the times add up.
fn setups_seen(
    renderer: &mut Renderer,
    technique: &gnomon::Technique,
    (camera, lights, bounds): (&gnomon::Camera, &[gnomon::Light], &gnomon::SceneBounds),
    shadow_map: u32,
) -> Result<(Vec<gnomon::ShadowSetup>, f64), CliError> {
    let mut setups = Vec::with_capacity(lights.len());
    let mut setup_us = 0.0;
    for light in lights {
        let samples = renderer.view_samples(camera, light)?;
        let (setup, us) =
            timed_setup(technique, camera, light, bounds, shadow_map, Some(&samples))?;
        setups.push(setup);
        setup_us += us;
    }
    Ok((setups, setup_us))
}

/// Soft shadows: the mask becomes the main light's shadow factor, as the volumes' is.
fn soft_mask(frame: &mut gnomon_render::Frame) {
    let Some(factor) = frame.shadow.as_deref() else {
        return;
    };
    frame.mask = frame
        .mask
        .iter()
        .zip(factor)
        .map(|(&m, f)| {
            if m == gnomon_render::MASK_EMPTY {
                0
            } else {
                (f.clamp(0.0, 1.0) * 255.0).round() as u8
            }
        })
        .collect();
}

/// `render --json`: the frame's times, casters and sampling error.
fn print_frame_json(
    renderer: &Renderer,
    technique: &gnomon::Technique,
    (setup, setup_us): (&gnomon::ShadowSetup, f64),
    frame: &gnomon_render::Frame,
    casters: usize,
) {
    let t = frame.timings;
    let metrics = frame.metrics.as_ref().expect("metrics asked for");
    let summary = serde_json::json!({
        "technique": technique.name(),
        "device": renderer.gpu().describe(),
        "timing": renderer.timing_source().name(),
        "fallback": setup.fallback().map(|f| f.name()),
        "setup_us": setup_us,
        "casters": casters,
        "casters_drawn": frame.casters_drawn,
        "shadow_pass_ms": t.shadow_pass_ms,
        "main_pass_ms": t.main_pass_ms,
        "undersampling": heatmap::percentiles(metrics, &metrics.undersampling),
        "area_undersampling": heatmap::percentiles(metrics, &metrics.area),
    });
    crate::say!(
        "{}",
        serde_json::to_string_pretty(&summary).expect("JSON of plain values")
    );
}

/// What was drawn, how fast, and the files written.
fn print_closing_line(
    args: &RenderArgs,
    renderer: &Renderer,
    (setup, setup_us): (&gnomon::ShadowSetup, f64),
    frame: &gnomon_render::Frame,
    casters: usize,
) {
    let t = frame.timings;
    let drawn: Vec<String> = frame.casters_drawn.iter().map(|n| n.to_string()).collect();
    eprintln!(
        "{} on {}: setup {:.1} us, casters drawn {} of {casters}, shadow pass {:.2} ms, main pass {:.2} ms ({}){}; wrote {}",
        args.draw.technique.name(),
        renderer.gpu().describe(),
        setup_us,
        drawn.join(" + "),
        t.shadow_pass_ms,
        t.main_pass_ms,
        t.source.name(),
        setup
            .fallback()
            .map(|f| format!(", fallback {}", f.name()))
            .unwrap_or_default(),
        written_files(args)
    );
}

/// Every file a `render` wrote, for its closing line: the frame and each optional image asked
/// for (those checked before any work, so each named one was written).
fn written_files(args: &RenderArgs) -> String {
    let mut files = vec![args.out.display().to_string()];
    for (what, path) in [
        ("mask", &args.mask),
        ("light view", &args.light_view),
        ("error map", &args.error_map),
    ] {
        if let Some(path) = path {
            files.push(format!("{} ({what})", path.display()));
        }
    }
    files.join(", ")
}

/// What a spot or point light's maps leave out: the parts of casters nearer to the light than
/// its near plane (a millionth of its range, `gnomon::SPOT_NEAR_FRACTION`), counted by
/// `diagnostics.casters_clipped_by_light_near` (for a point light, once per cube face).
fn near_clip_warning(light: &gnomon::Light, diagnostics: &gnomon::Diagnostics) -> Option<String> {
    let near = match light {
        gnomon::Light::Spot(spot) => spot.near(),
        gnomon::Light::Point(point) => point.near(),
        gnomon::Light::Directional(_) => return None,
    };
    let clipped = diagnostics.casters_clipped_by_light_near;
    (clipped > 0).then(|| {
        format!(
            "{clipped} caster box(es) reach within the light's near distance ({near:.3e} m, \
             a millionth of its range): any surface that near casts no shadow in the maps (the \
             exact volumes keep it)"
        )
    })
}

/// `gnomon render --technique volumes`.
fn run_volumes(
    args: &RenderArgs,
    scene: &RenderScene,
    camera: &gnomon::Camera,
    lights: &[gnomon::Light],
    named: StencilMode,
) -> Result<(), CliError> {
    if args.light_view.is_some() || args.error_map.is_some() || args.json {
        return Err(CliError::usage(
            "--light-view, --error-map and --json describe a shadow map; shadow volumes have none",
        ));
    }
    // `--stencil` picks the counting for `volumes`; a `volumes-*` name already did.
    let mode = args.draw.stencil_mode(named)?;
    let mut renderer = open_renderer(scene, args.size, None)?;
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
        ..RenderSettings::default()
    };
    if let Some(clusters) = args
        .draw
        .soft
        .area_clusters(lights, &scene.bounds()?.scene_box())?
    {
        let soft = renderer.render_soft_volumes(camera, &clusters, &settings, mode)?;
        write_frame(&soft.frame, &args.out, args.mask.as_deref(), None)?;
        let t = soft.frame.timings;
        eprintln!(
            "soft volumes ({}) on {}: {} samples per light, {} volume triangles in all, \
             extrusion and stencil {:.2} ms, shading {:.2} ms ({}); wrote {}",
            Drawn::Volumes(mode).name(),
            renderer.gpu().describe(),
            clusters[0].len(),
            soft.triangles,
            t.shadow_pass_ms,
            t.main_pass_ms,
            t.source.name(),
            written_files(args)
        );
        return Ok(());
    }
    let drawn = renderer.render_volumes_lit_by(camera, lights, &settings, mode)?;
    write_frame(&drawn.frame, &args.out, args.mask.as_deref(), None)?;
    let (t, stats) = (drawn.frame.timings, drawn.stats);
    eprintln!(
        "volumes ({}) on {}: {} volume triangles ({} casters z-fail, {} z-pass{}{}), \
         extrusion and stencil {:.2} ms, shading {:.2} ms ({}); wrote {}",
        Drawn::Volumes(mode).name(),
        renderer.gpu().describe(),
        stats.triangles,
        stats.z_fail_casters,
        stats.z_pass_casters,
        stats
            .near_clip_fallback
            .map(|_| "; the light lies in the near plane: all z-fail")
            .unwrap_or_default(),
        if renderer.volumes_have_float_depth() {
            ""
        } else {
            "; depth Depth24PlusStencil8, the device lacks DEPTH32FLOAT_STENCIL8"
        },
        t.shadow_pass_ms,
        t.main_pass_ms,
        t.source.name(),
        written_files(args)
    );
    Ok(())
}

/// The receiver of planar shadows: `plane` (A, B, C, D) inside the scene's box, else the top
/// face of the scene's ground.
pub fn planar_receiver(
    scene: &RenderScene,
    plane: Option<[f64; 4]>,
) -> Result<gnomon::planar::PlanarReceiver, CliError> {
    let bounds = scene.bounds()?;
    let tolerance = 1e-9 * (1.0 + bounds.scene_box().max().abs().max_element());
    let (plane, within) = match plane {
        Some(p) => {
            let normal = glam::DVec3::new(p[0], p[1], p[2]);
            let length = normal.length();
            (
                gnomon::geometry::Plane {
                    normal: normal / length,
                    offset: p[3] / length,
                },
                bounds.scene_box(),
            )
        }
        None => {
            let ground = scene
                .instances
                .iter()
                .find(|i| i.name == "ground")
                .and_then(|i| scene.instance_bounds(i).ok())
                .ok_or_else(|| {
                    CliError::usage(
                        "planar shadows fall on the scene's ground, and it has none: give --receiver-plane A,B,C,D",
                    )
                })?;
            (
                gnomon::geometry::Plane::through_point(ground.max(), glam::DVec3::Y),
                ground,
            )
        }
    };
    gnomon::planar::PlanarReceiver::new(plane, &within, tolerance).ok_or_else(|| {
        CliError::usage("--receiver-plane misses the scene's box: nothing can receive there")
    })
}

/// `gnomon render --technique planar`.
fn run_planar(
    args: &RenderArgs,
    scene: &RenderScene,
    camera: &gnomon::Camera,
    lights: &[gnomon::Light],
) -> Result<(), CliError> {
    if args.light_view.is_some() || args.error_map.is_some() || args.json {
        return Err(CliError::usage(
            "--light-view, --error-map and --json describe a shadow map; planar shadows have none",
        ));
    }
    let receiver = planar_receiver(scene, args.draw.receiver_plane)?;
    let mut renderer = open_renderer(scene, args.size, None)?;
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
        ..RenderSettings::default()
    };
    let drawn = renderer.render_planar_lit_by(camera, lights, &receiver, &settings)?;
    write_frame(&drawn.frame, &args.out, args.mask.as_deref(), None)?;
    let t = drawn.frame.timings;
    eprintln!(
        "planar on {}: {} flattened triangles of {} casters on a {}-sided receiver, \
         flattening and stencil {:.2} ms, shading {:.2} ms ({}); wrote {}",
        renderer.gpu().describe(),
        drawn.stats.triangles,
        drawn.stats.z_fail_casters / lights.len().max(1),
        receiver.polygon.len(),
        t.shadow_pass_ms,
        t.main_pass_ms,
        t.source.name(),
        written_files(args)
    );
    Ok(())
}

/// `gnomon export`.
#[derive(Debug, Clone, Args)]
pub struct ExportArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Where to write the scene's world-space triangles as Wavefront OBJ.
    #[arg(long)]
    pub obj: PathBuf,
}

/// Runs `gnomon export`.
pub fn export(args: &ExportArgs) -> Result<(), CliError> {
    crate::output::check_outputs(&[("--obj", args.obj.as_path(), &["obj"])])?;
    let loaded = args.scene.load()?;
    write_text(&args.obj, &loaded.scene.to_obj(&loaded.name))?;
    eprintln!(
        "wrote {} ({} triangles)",
        args.obj.display(),
        loaded.scene.triangle_count()
    );
    Ok(())
}

/// The `--stencil` value that picks `mode` where it is not the default (z-fail).
#[cfg(feature = "viewer")]
pub(crate) fn stencil_name(mode: StencilMode) -> Option<&'static str> {
    match mode {
        StencilMode::ZFail => None,
        StencilMode::ZPass => Some("z-pass"),
        StencilMode::PerCaster => Some("per-caster"),
    }
}

/// `--tint` with a setup of one map.
pub(crate) fn tint_needs_two_maps(technique: &gnomon::Technique) -> CliError {
    CliError::usage(format!(
        "--tint colours the maps of a technique with several (sppsm, cascades, any under a point light); {} has one map",
        technique.name()
    ))
}
