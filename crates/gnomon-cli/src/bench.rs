//! `gnomon bench`: frame times of shadow techniques on the same scene and views, measured in
//! one run (frames interleaved round-robin, so that a noisy machine slows every technique
//! alike), with each technique's ratio to a baseline (the focused shadow map unless
//! `--baseline` names another), view by view and on average over the views.

use std::time::Instant;

use clap::Args;
use gnomon::{Camera, Light, Technique};
use gnomon_render::{RenderSettings, Timings};
use serde_json::{Value, json};

use crate::CliError;
use crate::args::{SceneArgs, SuiteArgs, TechniqueParams, ViewListArgs};
use crate::names::Drawn;
use crate::render::{open_renderer, parse_size};

/// `gnomon bench`.
#[derive(Debug, Clone, Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    // With --suite: a report per scene (compare: a folder of its name under --out; bench:
    // views named SCENE/VIEW) and a summary over the suite.
    #[command(flatten)]
    pub suite: SuiteArgs,
    #[command(flatten)]
    pub views: ViewListArgs,
    /// What to time, comma-separated: shadow-map techniques and compare's rows (uniform,
    /// focused, lispsm, tsm, xpsm, psm, sppsm, cascades, cube, paraboloid, sppsm-same-texels,
    /// paraboloid-cube-texels, cascades-stable, cascades-lispsm, cascades-best; a row that
    /// cannot draw a view's light is not timed there), shadow volumes (volumes = z-fail, volumes-z-pass,
    /// volumes-per-caster), planar shadows on the ground (planar) and the focused map read as
    /// the lecture's other light-space maps (projective, object-id, id-depth).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "focused,volumes,volumes-per-caster"
    )]
    pub techniques: Vec<String>,
    /// Time the passes by the wall clock (each part submitted and waited for) even where the
    /// GPU has timestamps: to compare with wall-clock figures.
    #[arg(long)]
    pub wall_clock: bool,
    /// The technique every frame time is divided by (one of --techniques).
    #[arg(long, default_value = "focused")]
    pub baseline: String,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Timed frames per view and technique (after one untimed warm-up frame).
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "960x540", allow_hyphen_values = true, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// One thing timed: a row of shadow maps, the shadow volumes counted one way, or planar
/// shadows on the scene's ground.
enum Entry {
    Map(Box<crate::rows::Row>),
    Volumes(gnomon_render::StencilMode),
    Planar,
}

impl Entry {
    fn name(&self) -> &str {
        match self {
            Entry::Map(row) => &row.label,
            Entry::Volumes(mode) => Drawn::Volumes(*mode).name(),
            Entry::Planar => Drawn::Planar.name(),
        }
    }
}

/// A view to time: name, camera, lights.
type View = (String, Camera, Vec<Light>);

/// The results of one scene (one per view and entry), and the renderer's description and
/// timing source.
type SceneTimes = (Vec<serde_json::Value>, (String, &'static str));

/// Times every entry on each of `views` of one scene (frames interleaved).
fn time_views(
    args: &BenchArgs,
    entries: &[Entry],
    baseline: usize,
    loaded: &crate::args::LoadedScene,
    views: &[View],
    started: Instant,
) -> Result<SceneTimes, CliError> {
    let mut results = Vec::new();
    let mut renderer = open_renderer(&loaded.scene, args.size, Some(args.shadow_map))?;
    renderer.use_wall_clock(args.wall_clock);
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
        ..RenderSettings::default()
    };
    eprintln!(
        "gnomon bench: {} views x {} techniques x {} frames at {}x{} on {}; pass times from {}",
        views.len(),
        entries.len(),
        args.frames,
        args.size.0,
        args.size.1,
        renderer.gpu().describe(),
        renderer.timing_source().name()
    );
    let device = (renderer.gpu().describe(), renderer.timing_source().name());
    let projective = entries
        .iter()
        .any(|e| matches!(e, Entry::Map(row) if row.projective()));
    let timer = Timer {
        row_scene: crate::rows::RowScene::new(&loaded.scene, projective)?,
        // Planar shadows fall on the scene's ground.
        receiver: entries
            .iter()
            .any(|e| matches!(e, Entry::Planar))
            .then(|| crate::render::planar_receiver(&loaded.scene, None))
            .transpose()?,
        settings,
    };
    for (v, (view, camera, lights)) in views.iter().enumerate() {
        let samples = lights
            .iter()
            .map(|light| renderer.view_samples(camera, light))
            .collect::<Result<Vec<_>, _>>()?;
        let scene = (camera, lights.as_slice(), samples.as_slice());
        for entry in entries {
            timer.frame(&mut renderer, entry, scene)?; // warm-up
        }
        let mut times: Vec<Vec<(f64, Timings)>> = vec![Vec::new(); entries.len()];
        for _ in 0..args.frames {
            for (k, entry) in entries.iter().enumerate() {
                times[k].push(timer.frame(&mut renderer, entry, scene)?);
            }
        }
        results.extend(view_results(view, entries, &times, baseline, lights));
        eprintln!(
            "[{}/{}] {view} done ({:.1} s)",
            v + 1,
            views.len(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok((results, device))
}

/// What every timed frame of one scene shares.
struct Timer {
    row_scene: crate::rows::RowScene,
    receiver: Option<gnomon::planar::PlanarReceiver>,
    settings: RenderSettings,
}

impl Timer {
    /// One frame: its time in ms (setup + shadow pass + main pass) and its timings. The view
    /// samples are a fact of the view, drawn once per view (an engine takes them from its
    /// last frame), and not timed.
    fn frame(
        &self,
        renderer: &mut gnomon_render::Renderer,
        entry: &Entry,
        (camera, lights, samples): (&Camera, &[Light], &[gnomon::ViewSamples]),
    ) -> Result<(f64, Timings), CliError> {
        let settings = &self.settings;
        let frame = match entry {
            Entry::Map(row) if row.refuses(lights).is_some() => {
                return Ok((f64::NAN, Timings::default()));
            }
            Entry::Map(row) => {
                let lit = (camera, lights, samples);
                let drawn = self.row_scene.draw(renderer, row, lit, settings)?;
                let t = drawn.frame.timings;
                return Ok((drawn.setup_us / 1e3 + t.shadow_pass_ms + t.main_pass_ms, t));
            }
            Entry::Volumes(mode) => {
                self.row_scene.restore(renderer)?;
                renderer.render_volumes_lit_by(camera, lights, settings, *mode)?
            }
            Entry::Planar => {
                self.row_scene.restore(renderer)?;
                let Some(receiver) = &self.receiver else {
                    return Err(CliError::runtime("planar shadows without a receiver"));
                };
                renderer.render_planar_lit_by(camera, lights, receiver, settings)?
            }
        };
        let t = frame.frame.timings;
        Ok((t.shadow_pass_ms + t.main_pass_ms, t))
    }
}

/// One view's results: each entry's mean frame and pass times and its ratio to the baseline.
fn view_results(
    view: &str,
    entries: &[Entry],
    times: &[Vec<(f64, Timings)>],
    baseline: usize,
    lights: &[Light],
) -> Vec<Value> {
    let baseline_ms = mean_sd(&times[baseline].iter().map(|t| t.0).collect::<Vec<_>>()).0;
    let mut results = Vec::new();
    for (entry, samples) in entries.iter().zip(times) {
        if let Entry::Map(row) = entry
            && let Some(why) = row.refuses(lights)
        {
            results.push(crate::report::skipped_record(Some(view), entry.name(), why));
            continue;
        }
        let total: Vec<f64> = samples.iter().map(|t| t.0).collect();
        let shadow: Vec<f64> = samples.iter().map(|t| t.1.shadow_pass_ms).collect();
        let main: Vec<f64> = samples.iter().map(|t| t.1.main_pass_ms).collect();
        let (mean, sd) = mean_sd(&total);
        let figures = json!({
            "frame_ms": mean,
            "frame_ms_sd": sd,
            "shadow_pass_ms": mean_sd(&shadow).0,
            "main_pass_ms": mean_sd(&main).0,
            "vs_baseline": mean / baseline_ms,
        });
        results.push(crate::report::row_record(Some(view), entry.name(), figures));
    }
    results
}

/// Mean and standard deviation.
fn mean_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Runs `gnomon bench`.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let (entries, baseline) = entries(args)?;
    if args.frames == 0 {
        return Err(CliError::usage("--frames must be at least 1"));
    }
    let scenes = scenes(args)?;
    let aspect = args.size.0 as f64 / args.size.1 as f64;
    let started = Instant::now();
    let mut results = Vec::new();
    let mut device = (String::new(), "");
    for (stem, loaded) in &scenes {
        let views = views_of(args, stem, loaded, aspect)?;
        let (times, on) = time_views(args, &entries, baseline, loaded, &views, started)?;
        results.extend(times);
        device = on;
    }
    let summary = summary(&entries, &results);
    let baseline_name = entries[baseline].name();
    if args.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "device": device.0,
                "timing": device.1,
                "baseline": baseline_name,
                "summary": summary,
                "size": [args.size.0, args.size.1],
                "shadow_map": args.shadow_map,
                "frames": args.frames,
                "results": results,
            }))
            .expect("JSON of plain values")
        );
    } else {
        print_table(&results, baseline_name);
        print_summary(&summary, baseline_name);
    }
    Ok(())
}

/// What `--techniques` names, checked (each once, its parameters read), and the baseline's
/// index among them.
fn entries(args: &BenchArgs) -> Result<(Vec<Entry>, usize), CliError> {
    let entries = args
        .techniques
        .iter()
        .map(
            |t| match crate::names::VOLUMES.iter().find(|(n, _)| *n == t.trim()) {
                Some((_, mode)) => Ok(Entry::Volumes(*mode)),
                None if t.trim() == crate::names::PLANAR => Ok(Entry::Planar),
                None => crate::rows::row(t, &args.params, args.shadow_map)
                    .map(|r| Entry::Map(Box::new(r))),
            },
        )
        .collect::<Result<Vec<_>, CliError>>()?;
    if entries.is_empty() {
        return Err(CliError::usage("--techniques names nothing to time"));
    }
    // The parameters given must be read by a row that takes them (fixed rows keep their own).
    let maps: Vec<Technique> = entries
        .iter()
        .filter_map(|e| match e {
            Entry::Map(row) if row.params == args.params => Some(row.technique),
            _ => None,
        })
        .collect();
    if !maps.is_empty() {
        args.params.check_used_by(&maps)?;
    }
    for (k, e) in entries.iter().enumerate() {
        if entries[..k].iter().any(|f| f.name() == e.name()) {
            return Err(CliError::usage(format!(
                "--techniques names {} twice",
                e.name()
            )));
        }
    }
    let baseline = entries
        .iter()
        .position(|e| e.name() == args.baseline.trim())
        .ok_or_else(|| {
            CliError::usage(format!(
                "--baseline '{}' is not among --techniques ({})",
                args.baseline,
                entries
                    .iter()
                    .map(Entry::name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
    Ok((entries, baseline))
}

/// The scenes: the one given, or every scene file of --suite (all loaded before any work).
fn scenes(args: &BenchArgs) -> Result<Vec<(String, crate::args::LoadedScene)>, CliError> {
    match &args.suite.suite {
        None => Ok(vec![(String::new(), args.scene.load()?)]),
        Some(folder) => {
            if args.views.views.iter().any(|v| v.trim() != "all") {
                return Err(CliError::usage(
                    "--suite times every view of each scene; drop --views",
                ));
            }
            crate::args::suite_scenes(folder)
        }
    }
}

/// The chosen views of a scene with their cameras and every light (a scene file's view may
/// have several); in a suite, a view is named by its scene too.
fn views_of(
    args: &BenchArgs,
    stem: &str,
    loaded: &crate::args::LoadedScene,
    aspect: f64,
) -> Result<Vec<View>, CliError> {
    args.views
        .select(&loaded.views)?
        .into_iter()
        .map(|v| {
            let camera = v.camera(aspect)?;
            let lights = v.lights()?;
            let name = if stem.is_empty() {
                v.name.clone()
            } else {
                format!("{stem}/{}", v.name)
            };
            Ok((name, camera, lights))
        })
        .collect()
}

/// Each technique's ratio to the baseline over the views: mean, smallest, largest.
fn summary(entries: &[Entry], results: &[Value]) -> Vec<Value> {
    entries
        .iter()
        .map(|entry| {
            let ratios: Vec<f64> = results
                .iter()
                .filter(|r| r["technique"] == entry.name())
                .filter_map(|r| r["vs_baseline"].as_f64())
                .collect();
            // No ratio where the technique or the baseline refuses every view's light.
            let figure = |f: f64| (!ratios.is_empty()).then_some(f);
            json!({
                "technique": entry.name(),
                "mean_vs_baseline": figure(mean_sd(&ratios).0),
                "min_vs_baseline": figure(ratios.iter().copied().fold(f64::INFINITY, f64::min)),
                "max_vs_baseline": figure(ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
            })
        })
        .collect()
}

/// A line per view and technique.
fn print_table(results: &[Value], baseline_name: &str) {
    crate::say!(
        "{:<16} {:<20} {:>10} {:>8} {:>10} {:>10} {:>11}",
        "view",
        "technique",
        "frame ms",
        "sd",
        "shadow ms",
        "main ms",
        format!("vs {baseline_name}")
    );
    for r in results {
        if let Some(why) = r["skipped"].as_str() {
            crate::say!(
                "{:<16} {:<20} not timed: {why}",
                r["view"].as_str().unwrap_or_default(),
                r["technique"].as_str().unwrap_or_default()
            );
            continue;
        }
        crate::say!(
            "{:<16} {:<20} {:>10.2} {:>8.2} {:>10.2} {:>10.2} {:>11}",
            r["view"].as_str().unwrap_or_default(),
            r["technique"].as_str().unwrap_or_default(),
            r["frame_ms"].as_f64().unwrap_or_default(),
            r["frame_ms_sd"].as_f64().unwrap_or_default(),
            r["shadow_pass_ms"].as_f64().unwrap_or_default(),
            r["main_pass_ms"].as_f64().unwrap_or_default(),
            // (None where the baseline refuses the view's light.)
            r["vs_baseline"]
                .as_f64()
                .map_or("n/a".to_string(), |v| format!("{v:.2}x")),
        );
    }
}

/// Each technique's ratio to the baseline over the views.
fn print_summary(summary: &[Value], baseline_name: &str) {
    crate::say!("\nframe time / {baseline_name}'s over the views: mean (smallest, largest)");
    for s in summary {
        let technique = s["technique"].as_str().unwrap_or_default();
        match (
            s["mean_vs_baseline"].as_f64(),
            s["min_vs_baseline"].as_f64(),
            s["max_vs_baseline"].as_f64(),
        ) {
            (Some(mean), Some(min), Some(max)) => {
                crate::say!("{technique:<20} {mean:>6.2}x ({min:.2}x, {max:.2}x)")
            }
            _ => crate::say!(
                "{technique:<20}    n/a (no view whose light both it and {baseline_name} take)"
            ),
        }
    }
}
