//! `gnomon flicker`: how much shadows swim and shimmer while the camera or the sun moves.
//!
//! Measured on surface points, not screen pixels: the points the first frame's pixels see
//! (one per pixel of `--size`), fixed in the world. In every frame of the path each point is
//! looked up in that frame's maps as the main pass reads them (`Renderer::lit_at_points`:
//! the selected map, the normal offset, one tap). A point is judged in a transition when the
//! light reaches its face (N.L > 0.1) in both frames.
//! - `false_flicker`: the share of judged points whose lit/shadowed state changes from one
//!   frame to the next while the exact state does not. For the camera paths the exact state
//!   never changes (the scene and the light stand still); for `sun` it is the exact shadow
//!   volumes' mask at the same pixel (the camera stands still, so the points stay the
//!   pixels').
//! - `edge_swim_px`: per transition, those false changes over the length of the map's shadow
//!   boundaries in the first frame's pixel grid (neighbouring judged points whose states
//!   differ): a boundary that moves by d pixels changes about d points per pixel of its
//!   length. The mean over the transitions, in pixels of `--size`.

use std::time::Instant;

use clap::{Args, ValueEnum};
use glam::{DQuat, DVec3};
use gnomon::{Camera, DirectionalLight, Light, ShadowTechnique};
use gnomon_render::{MASK_LIT, RenderSettings, ShadowedLight, StencilMode};
use serde_json::json;

use crate::CliError;
use crate::args::{LightArgs, SceneArgs, TechniqueParams, ViewArgs, timed_setup};
use crate::render::{open_renderer, parse_size};

/// How the camera or the light moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PathArg {
    /// Forward along the view direction.
    Dolly,
    /// Sideways, to the image's right.
    Pan,
    /// Turning in place about the world's up axis.
    Turn,
    /// Circling the target about the world's up axis, looking at it.
    Orbit,
    /// The camera still, the sun turning about the world's up axis.
    Sun,
}

/// `gnomon flicker`.
#[derive(Debug, Clone, Args)]
pub struct FlickerArgs {
    /// The path.
    #[arg(long, value_enum, default_value = "dolly")]
    pub path: PathArg,
    /// Frames along the path (2 to 1000).
    #[arg(long, default_value_t = 30)]
    pub frames: usize,
    /// How far each frame moves: world units for dolly and pan (default: a thousandth of
    /// the far plane), degrees for turn, orbit and sun (default 0.2).
    #[arg(long, allow_hyphen_values = true)]
    pub step: Option<f64>,
    /// The rows measured, by compare's names (techniques, sppsm-same-texels, the cascade
    /// rows), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "focused,lispsm,sppsm,cascades-lispsm,cascades-stable"
    )]
    pub techniques: Vec<String>,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub light: LightArgs,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// The first frame's size, WIDTHxHEIGHT: one measured point per pixel (at most 512 on
    /// a side).
    #[arg(long, value_parser = parse_size, allow_hyphen_values = true, default_value = "320x180")]
    pub size: (u32, u32),
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The camera and light of frame `t`.
fn frame_at(
    path: PathArg,
    step: f64,
    camera: &Camera,
    light: &Light,
    target: DVec3,
    t: usize,
) -> Result<(Camera, Light), CliError> {
    let (eye, forward, up, lens) = (camera.eye(), camera.forward(), camera.up(), camera.lens());
    let turn = DQuat::from_rotation_y((step * t as f64).to_radians());
    let look = |eye: DVec3, forward: DVec3| Camera::look_at(eye, eye + forward, up, lens);
    let moved = match path {
        PathArg::Dolly => look(eye + forward * (step * t as f64), forward)?,
        PathArg::Pan => look(eye + camera.right() * (step * t as f64), forward)?,
        PathArg::Turn => look(eye, turn * forward)?,
        PathArg::Orbit => {
            let eye = target + turn * (eye - target);
            Camera::look_at(eye, target, up, lens)?
        }
        PathArg::Sun => *camera,
    };
    let light = match (path, light) {
        (PathArg::Sun, Light::Directional(d)) => {
            Light::Directional(DirectionalLight::new(turn * d.direction())?)
        }
        (PathArg::Sun, Light::Spot(_)) => {
            return Err(CliError::usage(
                "--path sun turns a directional light; give --light-dir or a named --view",
            ));
        }
        _ => *light,
    };
    Ok((moved, light))
}

/// One row's tallies over the transitions.
#[derive(Default)]
struct Tally {
    judged: u64,
    false_changes: u64,
    swim: Vec<f64>,
}

/// The camera path, checked before any work: every frame's camera and light.
struct Plan {
    camera: Camera,
    light: Light,
    target: DVec3,
    step: f64,
    frames: Vec<(Camera, Light)>,
}

/// The measured points (what the first frame's pixels see) and where they lie in its grid.
struct Points {
    /// Position and normal of each point.
    points: Vec<(DVec3, DVec3)>,
    /// Each point's pixel.
    present: Vec<usize>,
    /// Each pixel's point (`usize::MAX`: none), for the boundary length.
    slot: Vec<usize>,
    size: (u32, u32),
}

/// Runs `gnomon flicker`.
pub fn run(args: &FlickerArgs) -> Result<(), CliError> {
    let started = Instant::now();
    check_sizes(args)?;
    let loaded = args.scene.load()?;
    let plan = plan(args, &loaded)?;
    let rows = crate::rows::rows(&args.techniques, &args.params, args.shadow_map, false)?;
    if let Some(r) = rows
        .iter()
        .find(|r| r.read != gnomon_render::MapRead::Depth)
    {
        return Err(CliError::usage(format!(
            "flicker measures shadow maps read by depth; {} is not measured yet",
            r.label
        )));
    }
    let bounds = loaded.scene.bounds()?;
    let mut renderer = open_renderer(&loaded.scene, args.size, Some(args.shadow_map))?;
    let points = Points::surface(&mut renderer, &plan.camera, args.size)?;
    let tallies = measure(args, &plan, &rows, &mut renderer, &bounds, &points)?;
    let results: Vec<_> = rows
        .iter()
        .zip(&tallies)
        .map(|(row, tally)| result(args, &plan, &loaded.options, row, tally))
        .collect();
    report(args, &plan, points.points.len(), &results);
    if !args.json {
        eprintln!(
            "measured in {:.1} s on {}",
            started.elapsed().as_secs_f64(),
            renderer.gpu().describe()
        );
    }
    Ok(())
}

fn check_sizes(args: &FlickerArgs) -> Result<(), CliError> {
    if !(2..=1000).contains(&args.frames) {
        return Err(CliError::usage(format!(
            "--frames must be 2 to 1000 (got {})",
            args.frames
        )));
    }
    let (width, height) = args.size;
    if width > 512 || height > 512 {
        return Err(CliError::usage(format!(
            "--size {width}x{height}: at most 512 on a side (one point per pixel)"
        )));
    }
    Ok(())
}

/// The first camera and light, the step and every frame's camera and light: a bad path fails
/// before any work.
fn plan(args: &FlickerArgs, loaded: &crate::args::LoadedScene) -> Result<Plan, CliError> {
    let (width, height) = args.size;
    let camera = args
        .view
        .camera_with_aspect(&loaded.views, width as f64 / height as f64)?;
    let light = args
        .light
        .main_light(&args.view, &loaded.views, "flicker")?;
    let target = match (args.view.target, args.view.named(&loaded.views)?) {
        (Some(t), _) => t,
        (None, Some(v)) => v.target,
        (None, None) => camera.eye() + camera.forward(),
    };
    let step = match args.step {
        Some(s) if !(s.is_finite() && s > 0.0 && s <= 1e6) => {
            return Err(CliError::usage(format!(
                "--step must be positive and finite (got {s})"
            )));
        }
        Some(s) => s,
        None => match args.path {
            PathArg::Dolly | PathArg::Pan => camera.lens().far / 1000.0,
            _ => 0.2,
        },
    };
    let frames = (0..args.frames)
        .map(|t| frame_at(args.path, step, &camera, &light, target, t))
        .collect::<Result<_, _>>()?;
    Ok(Plan {
        camera,
        light,
        target,
        step,
        frames,
    })
}

impl Points {
    /// What the first frame's pixels see.
    fn surface(
        renderer: &mut gnomon_render::Renderer,
        camera: &Camera,
        size: (u32, u32),
    ) -> Result<Self, CliError> {
        let grid = renderer.surface_points(camera, size)?;
        let present: Vec<usize> = (0..grid.len()).filter(|&i| grid[i].is_some()).collect();
        let points: Vec<(DVec3, DVec3)> = present.iter().filter_map(|&i| grid[i]).collect();
        if points.is_empty() {
            return Err(CliError::usage(
                "the first frame sees no surface to measure",
            ));
        }
        let mut slot = vec![usize::MAX; grid.len()];
        for (k, &i) in present.iter().enumerate() {
            slot[i] = k;
        }
        Ok(Self {
            points,
            present,
            slot,
            size,
        })
    }

    /// Whether the light reaches each point's face (N.L > 0.1).
    fn facing(&self, light: &Light) -> Vec<bool> {
        self.points
            .iter()
            .map(|(p, n)| {
                let to_light = match light {
                    Light::Directional(d) => -d.direction(),
                    Light::Spot(s) => (s.position() - *p).normalize_or_zero(),
                    Light::Point(l) => (l.position() - *p).normalize_or_zero(),
                };
                n.dot(to_light) > 0.1
            })
            .collect()
    }

    /// The length in pixels of a frame's shadow boundaries: neighbouring facing points whose
    /// states differ.
    fn boundary(&self, lit: &[bool], facing: &[bool]) -> u64 {
        let (width, height) = self.size;
        let mut boundary = 0u64;
        for (k, &i) in self.present.iter().enumerate() {
            let (x, y) = (i as u32 % width, i as u32 / width);
            for neighbour in [
                (x + 1 < width).then(|| i + 1),
                (y + 1 < height).then(|| i + width as usize),
            ]
            .into_iter()
            .flatten()
            {
                let j = self.slot[neighbour];
                if j != usize::MAX && facing[k] && facing[j] && lit[k] != lit[j] {
                    boundary += 1;
                }
            }
        }
        boundary
    }
}

/// The state of every facing point that the light's frame and the one before both judge.
struct Transition<'a> {
    lit: &'a [bool],
    facing: &'a [bool],
    before: &'a [bool],
    facing_before: &'a [bool],
    /// Where the exact state changed (the sun path); `None`: it did not.
    exact_changed: Option<&'a [bool]>,
}

impl Tally {
    /// Counts a transition's false changes and its edge swim.
    fn add(&mut self, points: &Points, t: &Transition<'_>) {
        let mut changes = 0u64;
        for k in 0..t.lit.len() {
            if !(t.facing[k] && t.facing_before[k]) {
                continue;
            }
            self.judged += 1;
            let exact_changed = t.exact_changed.is_some_and(|c| c[k]);
            if t.lit[k] != t.before[k] && !exact_changed {
                changes += 1;
            }
        }
        self.false_changes += changes;
        let boundary = points.boundary(t.before, t.facing_before);
        if boundary > 0 {
            self.swim.push(changes as f64 / boundary as f64);
        }
    }
}

/// Every row along the path: each frame's maps looked up at the points, each transition
/// tallied.
fn measure(
    args: &FlickerArgs,
    plan: &Plan,
    rows: &[crate::rows::Row],
    renderer: &mut gnomon_render::Renderer,
    bounds: &gnomon::SceneBounds,
    points: &Points,
) -> Result<Vec<Tally>, CliError> {
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
        ..RenderSettings::default()
    };
    let progress = crate::output::progress_bar(args.frames * rows.len());
    let mut tallies: Vec<Tally> = rows.iter().map(|_| Tally::default()).collect();
    let mut previous: Vec<Option<Vec<bool>>> = vec![None; rows.len()];
    // Each row's technique for the next frame (adaptive cascades learn the count kept).
    let mut techniques: Vec<gnomon::Technique> = rows.iter().map(|row| row.technique).collect();
    let mut previous_exact: Option<Vec<bool>> = None;
    let mut previous_facing: Option<Vec<bool>> = None;
    for (t, (camera_t, light_t)) in plan.frames.iter().enumerate() {
        let facing = points.facing(light_t);
        // The exact state changes only when the sun moves (the camera is then still, and the
        // points are its pixels).
        let exact = match args.path {
            PathArg::Sun => Some(exact_lit(renderer, (camera_t, light_t), &settings, points)?),
            _ => None,
        };
        let exact_changed = match (&exact, &previous_exact) {
            (Some(now), Some(then)) => Some(
                now.iter()
                    .zip(then)
                    .map(|(a, b)| a != b)
                    .collect::<Vec<bool>>(),
            ),
            _ => None,
        };
        let samples = renderer.view_samples(camera_t, light_t)?;
        for (r, row) in rows.iter().enumerate() {
            progress.set_message(format!("frame {t}: {}", row.label));
            let (setup, _) = timed_setup(
                &techniques[r],
                camera_t,
                light_t,
                bounds,
                row.resolution,
                Some(&samples),
            )?;
            let shadowed = [ShadowedLight {
                light: light_t,
                setup: &setup,
            }];
            let lit = renderer.lit_at_points(camera_t, &shadowed, &settings, &points.points)?;
            if let (Some(before), Some(facing_before)) = (&previous[r], &previous_facing) {
                let transition = Transition {
                    lit: &lit,
                    facing: &facing,
                    before,
                    facing_before,
                    exact_changed: exact_changed.as_deref(),
                };
                tallies[r].add(points, &transition);
            }
            previous[r] = Some(lit);
            techniques[r] = techniques[r].for_next_frame(&setup);
            progress.inc(1);
        }
        previous_exact = exact;
        previous_facing = Some(facing);
    }
    progress.finish_and_clear();
    Ok(tallies)
}

/// The exact shadow volumes' state at the points (the camera stands still: they are its
/// pixels).
fn exact_lit(
    renderer: &mut gnomon_render::Renderer,
    (camera, light): (&Camera, &Light),
    settings: &RenderSettings,
    points: &Points,
) -> Result<Vec<bool>, CliError> {
    let volumes = renderer.render_volumes(camera, light, settings, StencilMode::ZFail)?;
    Ok(points
        .present
        .iter()
        .map(|&i| volumes.frame.mask[i] == MASK_LIT)
        .collect())
}

fn path_name(path: PathArg) -> String {
    path.to_possible_value()
        .map_or("dolly".into(), |v| v.get_name().to_string())
}

/// One row's figures, with the command that measures it alone.
fn result(
    args: &FlickerArgs,
    plan: &Plan,
    scene_options: &str,
    row: &crate::rows::Row,
    tally: &Tally,
) -> serde_json::Value {
    let false_flicker = tally.false_changes as f64 / tally.judged.max(1) as f64;
    let swim = if tally.swim.is_empty() {
        0.0
    } else {
        tally.swim.iter().sum::<f64>() / tally.swim.len() as f64
    };
    let (camera, step) = (&plan.camera, plan.step);
    let (width, height) = args.size;
    let light_option = crate::args::light_option(&plan.light);
    let v = |a: DVec3| format!("{},{},{}", a.x, a.y, a.z);
    let scene_options = if scene_options.is_empty() {
        String::new()
    } else {
        format!(" {scene_options}")
    };
    let mut command = format!(
        "gnomon flicker{scene_options} --eye={} --target={} --up={} --fov {} --near {} --far {} {light_option} --path {} --frames {} --step {step} --size {width}x{height} --shadow-map {} --techniques {}",
        v(camera.eye()),
        v(plan.target),
        v(camera.up()),
        camera.lens().fov_y_degrees,
        camera.lens().near,
        camera.lens().far,
        path_name(args.path),
        args.frames,
        args.shadow_map,
        row.label,
    );
    if row.params == args.params {
        for (_, flag) in args.params.flags() {
            command += &format!(" {flag}");
        }
    }
    let figures = json!({
        "command": command,
        "false_flicker": false_flicker,
        "edge_swim_px": swim,
        "judged": tally.judged,
        "false_changes": tally.false_changes,
        "setup_technique": row.technique.name(),
    });
    crate::report::row_record(None, &row.label, figures)
}

/// Prints the rows as JSON or as a table.
fn report(args: &FlickerArgs, plan: &Plan, points: usize, results: &[serde_json::Value]) {
    let path_name = path_name(args.path);
    let view_name = args.view.view.clone().unwrap_or_else(|| "custom".into());
    let step = plan.step;
    if args.json {
        let report = json!({
            "path": path_name,
            "frames": args.frames,
            "step": step,
            "view": view_name,
            "size": [args.size.0, args.size.1],
            "shadow_map": args.shadow_map,
            "points": points,
            "techniques": results,
        });
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&report).expect("JSON of plain values")
        );
        return;
    }
    crate::say!(
        "flicker along {path_name} ({} frames, step {step}) from {view_name}: {points} points, {} maps",
        args.frames,
        args.shadow_map
    );
    crate::say!("technique            false flicker   edge swim (px)");
    for r in results {
        crate::say!(
            "{:<20} {:>12.4}%   {:>14.4}",
            r["technique"].as_str().unwrap_or_default(),
            100.0 * r["false_flicker"].as_f64().unwrap_or(0.0),
            r["edge_swim_px"].as_f64().unwrap_or(0.0)
        );
    }
}
