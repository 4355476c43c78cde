//! `gnomon compare`: every technique against the exact shadow volumes, view by view: an image
//! grid (frame, mask errors, sampling error map) and a table per view (wrong pixels, the
//! sampling error's percentiles, setup and frame times), as Markdown and JSON.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use gnomon_render::{
    Filter, Frame, MaskErrors, PixelVerdict, RenderSettings, ShadowedLight, StencilMode,
};
use serde_json::{Value, json};

use crate::args::render_command;
use crate::args::{SceneArgs, SuiteArgs, TechniqueParams, ViewListArgs};
use crate::render::{open_renderer, parse_size, write_png, write_text};
use crate::rows::light_setups;
use crate::{CliError, heatmap};

/// The largest frame side `compare` takes (its grids hold many frames).
const MAX_COMPARE_SIZE: u32 = 4096;
/// `gnomon compare`.
#[derive(Debug, Clone, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    // With --suite: a report per scene (compare: a folder of its name under --out; bench:
    // views named SCENE/VIEW) and a summary over the suite.
    #[command(flatten)]
    pub suite: SuiteArgs,
    #[command(flatten)]
    pub views: ViewListArgs,
    /// The shadow-map techniques: `all` (every map technique) or names, comma-separated, and
    /// `projective`, `object-id`, `id-depth` and `planar` (planar shadows on the ground); the exact shadow volumes are
    /// always drawn: they are the reference.
    #[arg(long, value_delimiter = ',', default_value = "all")]
    pub techniques: Vec<String>,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// The maps' filter; with `--area-light R` each view also gets the soft shadows of its
    /// area lights as a cluster of --area-samples hard lights with exact volumes, and each
    /// row read by depth the penumbra error of its filter against them (the mean absolute
    /// difference of the shadow factor over the union of both penumbrae): PCSS's with
    /// `--pcf pcss`, the hard shadows' with another filter.
    #[command(flatten)]
    pub soft: crate::render::SoftArgs,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", allow_hyphen_values = true, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Where to write the report (index.md, report.json, one grid image per view).
    #[arg(long, default_value = "gnomon-compare")]
    pub out: PathBuf,
}

/// What `compare` draws against the exact volumes: the map techniques' rows, and planar
/// shadows where asked.
struct Rows<'a> {
    techniques: &'a [crate::rows::Row],
    planar: bool,
}

/// Colours of the mask-error image.
const FALSE_SHADOW: [u8; 3] = [230, 30, 30];
const MISSED_SHADOW: [u8; 3] = [30, 110, 245];

/// Compares a map's mask with the exact one on the pixels with N.L > 0.1 (`n_dot_l`, the
/// view's), and draws the frame in grey with false shadow in red and missed shadow in blue.
fn mask_errors(map: &Frame, n_dot_l: &[f32], exact: &Frame) -> (MaskErrors, Vec<u8>) {
    mask_errors_of(&map.color, &map.mask, n_dot_l, &exact.mask)
}

/// [`mask_errors`] over a frame's colour and mask and the exact mask.
pub(crate) fn mask_errors_of(
    color: &[u8],
    mask: &[u8],
    n_dot_l: &[f32],
    exact: &[u8],
) -> (MaskErrors, Vec<u8>) {
    let mut errors = MaskErrors::default();
    let mut image = Vec::with_capacity(color.len());
    for (i, rgba) in color.chunks_exact(4).enumerate() {
        let grey = (0.3 * rgba[0] as f64 + 0.59 * rgba[1] as f64 + 0.11 * rgba[2] as f64) as u8;
        let verdict = PixelVerdict::of(mask[i], exact[i], n_dot_l[i]);
        errors.add(verdict);
        let rgb = match verdict {
            PixelVerdict::FalseShadow => FALSE_SHADOW,
            PixelVerdict::MissedShadow => MISSED_SHADOW,
            _ => [grey / 2 + 64; 3],
        };
        image.extend_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
    }
    (errors, image)
}

/// One row of a scene's summary: the technique, its mean and worst wrong-pixel share over
/// the views, its mean undersampling p99, mean penumbra error (PCSS), mean setup (us) and
/// frame (ms).
pub(crate) struct SummaryRow {
    label: String,
    wrong: Vec<f64>,
    p99: Vec<f64>,
    penumbra: Vec<f64>,
    setup_us: Vec<f64>,
    frame_ms: Vec<f64>,
}

/// `x` with two decimals, or `-` where it is not a number (a row without maps has no
/// sampling error).
fn two_places(x: f64) -> String {
    if x.is_nan() {
        "-".into()
    } else {
        format!("{x:.2}")
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Runs `gnomon compare`.
pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    let started = Instant::now();
    // Planar shadows are a row of their own (no maps); the rest are map techniques.
    let planar = args
        .techniques
        .iter()
        .any(|t| t.trim() == crate::names::PLANAR);
    let names: Vec<String> = args
        .techniques
        .iter()
        .filter(|t| t.trim() != crate::names::PLANAR)
        .cloned()
        .collect();
    let techniques = crate::rows::rows(&names, &args.params, args.shadow_map, true)?;
    if techniques.is_empty() && !planar {
        return Err(CliError::usage("nothing to compare"));
    }
    if args.soft.pcss() && args.soft.area_light.is_none() {
        return Err(CliError::usage(
            "--pcf pcss softens by the lights' size: give --area-light R (degrees for a sun, \
             whose is 0.27; world units for spot and point lights)",
        ));
    }
    let rows = Rows {
        techniques: &techniques,
        planar,
    };
    // A view's grid holds three frames per technique and the volumes: larger frames make
    // grids too large to hold and write.
    if args.size.0 > MAX_COMPARE_SIZE || args.size.1 > MAX_COMPARE_SIZE {
        return Err(CliError::usage(format!(
            "--size {}x{}: compare's grids take frames of at most {MAX_COMPARE_SIZE} on a side",
            args.size.0, args.size.1
        )));
    }
    let Some(folder) = &args.suite.suite else {
        let loaded = args.scene.load()?;
        compare_scene(args, &rows, &loaded, &args.out, started)?;
        crate::say!("wrote {}", args.out.join("index.md").display());
        return Ok(());
    };
    if args.views.views.iter().any(|v| v.trim() != "all") {
        return Err(CliError::usage(
            "--suite compares every view of each scene; drop --views",
        ));
    }
    // Every scene file loaded before any work: a missing model fails at once.
    let scenes = crate::args::suite_scenes(folder)?;
    let mut markdown = format!(
        "# gnomon compare: the suite in {}\n\nEach scene's report is in its folder; the \
         figures are means over its named views ({}x{} pixels, {}x{} shadow maps). Wrong \
         pixels against the exact shadow volumes; undersampling p99 in pixels per texel.\n\n\
         | scene | views | technique | mean wrong pixels | worst view | mean undersampling p99 | \
         setup (us) | frame (ms) |\n| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |\n",
        folder.display(),
        args.size.0,
        args.size.1,
        args.shadow_map,
        args.shadow_map
    );
    let mut json_scenes = Vec::new();
    for (stem, loaded) in &scenes {
        eprintln!("compare: scene {stem} ({} views)", loaded.views.len());
        let out = args.out.join(stem);
        let rows = compare_scene(args, &rows, loaded, &out, started)?;
        let mut json_rows = Vec::new();
        for r in &rows {
            let _ = writeln!(
                markdown,
                "| [{stem}]({}/index.md) | {} | {} | {:.3}% | {:.3}% | {} | {:.1} | {:.1} |",
                stem.replace(' ', "%20"),
                r.wrong.len(),
                r.label,
                mean(&r.wrong),
                r.wrong.iter().copied().fold(0.0, f64::max),
                two_places(mean(&r.p99)),
                mean(&r.setup_us),
                mean(&r.frame_ms)
            );
            json_rows.push(json!({
                "technique": r.label,
                "mean_wrong_percent": mean(&r.wrong),
                "worst_wrong_percent": r.wrong.iter().copied().fold(0.0, f64::max),
                "mean_undersampling_p99": mean(&r.p99),
                "mean_setup_us": mean(&r.setup_us),
                "mean_frame_ms": mean(&r.frame_ms),
            }));
        }
        json_scenes.push(json!({ "scene": stem, "name": loaded.name, "techniques": json_rows }));
    }
    write_text(&args.out.join("index.md"), &markdown)?;
    write_text(
        &args.out.join("suite.json"),
        &serde_json::to_string_pretty(&json!({ "scenes": json_scenes }))
            .expect("JSON of plain values"),
    )?;
    eprintln!(
        "compared {} scenes in {:.1} s",
        scenes.len(),
        started.elapsed().as_secs_f64()
    );
    crate::say!("wrote {}", args.out.join("index.md").display());
    Ok(())
}

/// Compares `techniques` over the chosen views of one scene, writing its report into `out`;
/// returns its summary rows.
fn compare_scene(
    args: &CompareArgs,
    compared: &Rows<'_>,
    loaded: &crate::args::LoadedScene,
    out: &std::path::Path,
    started: Instant,
) -> Result<Vec<SummaryRow>, CliError> {
    let techniques = compared.techniques;
    // Planar shadows fall on the scene's ground (a scene without one says so in its rows).
    let receiver = compared
        .planar
        .then(|| crate::render::planar_receiver(&loaded.scene, None));
    let planar_rows = usize::from(compared.planar);
    let views = args.views.select(&loaded.views)?;
    let scene = &loaded.scene;
    let row_scene = crate::rows::RowScene::new(scene, techniques.iter().any(|r| r.projective()))?;
    let bounds = row_scene.bounds();
    std::fs::create_dir_all(out)
        .map_err(|e| CliError::runtime(format!("cannot create {}: {e}", out.display())))?;
    let mut renderer = open_renderer(scene, args.size, Some(args.shadow_map))?;
    let (width, height) = args.size;
    let settings = RenderSettings {
        width,
        height,
        filter: args.soft.pcf.into(),
        area_light_radius: args.soft.pcss_radius(),
        metrics: true,
        ..RenderSettings::default()
    };
    let pcss = args.soft.pcss();
    // PCSS filters maps read by depth; rows that read IDs or coverage keep the default filter
    // (and their commands say nothing of it).
    let row_settings = |row: &crate::rows::Row| {
        if row.read == gnomon_render::MapRead::Depth {
            row.settings(&settings)
        } else {
            row.settings(&RenderSettings {
                filter: Filter::default(),
                area_light_radius: 0.0,
                ..settings
            })
        }
    };
    // A map's command: the filter and the area light (the samples are the reference's).
    let map_soft = crate::render::SoftArgs {
        area_samples: None,
        area_light: args.soft.area_light.filter(|_| pcss),
        ..args.soft.clone()
    };
    let soft_flags = |row: &crate::rows::Row| {
        if row.read == gnomon_render::MapRead::Depth {
            map_soft.non_default_flags()
        } else {
            String::new()
        }
    };
    let progress =
        indicatif::ProgressBar::new((views.len() * (techniques.len() + planar_rows + 1)) as u64);
    progress.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} ({elapsed})")
            .expect("a valid template"),
    );
    let mut markdown = format!(
        "# gnomon compare: {} scene\n\n{}x{} pixels, {}x{} shadow maps, rendered on {}. Wrong \
         pixels: share of the pixels with N.L > 0.1 whose one-tap shadow-map mask differs from \
         the exact shadow volumes' (false shadow: shadowed by the map, lit in fact; missed \
         shadow: the reverse). SPPSM comes twice: its two maps at the size above each, and \
         (sppsm-same-texels) two maps of half the area, the texels of one map; dual paraboloid maps \
         likewise (paraboloid-cube-texels: two maps with the texels of a cube's six faces). A row \
         that cannot draw a view's light (cube and paraboloid: point lights only; SPPSM and \
         cascades: no point light) says n/a. Undersampling: pixels per texel along the worst direction \
         (1 = one texel per pixel), over the same pixels; area p99: pixels per texel in area \
         (1 / |det J|, the measure SPPSM's plane compares). Frame: setup + shadow pass + main pass \
         (pass times from {}).\n\n\
         Each grid has one row per technique in the table's order, then the exact shadow \
         volumes; columns: the frame, the mask errors (red: false shadow, blue: missed \
         shadow), the sampling error map.{}\n",
        loaded.name,
        width,
        height,
        args.shadow_map,
        args.shadow_map,
        renderer.gpu().describe(),
        renderer.timing_source().name(),
        if let Some(radius) = args.soft.area_light {
            format!(
                " Area lights of radius {radius} (degrees for a sun, world units for spot and \
                 point lights){}; penumbra error: \
                 the mean absolute difference of the first light's shadow factor from the soft \
                 shadows of the same area light ({} hard lights with exact volumes, the third \
                 column of the volumes' row) over the pixels with N.L > 0.1 where either lies \
                 between 0.02 and 0.98 (the union of both penumbrae).",
                if pcss {
                    ", maps read by depth filtered with their PCSS"
                } else {
                    ", maps filtered without them (hard shadows)"
                },
                args.soft
                    .area_samples
                    .unwrap_or(crate::render::DEFAULT_AREA_SAMPLES)
            )
        } else {
            String::new()
        }
    );
    // One untimed frame first: the first draw compiles the pipelines. Its map is the first
    // row's that takes the first view's light (a row that refuses it is left out of that
    // view below, and must not fail the run here).
    if let Some(view) = views.first() {
        let (camera, light) = view.camera_and_light(width as f64 / height as f64)?;
        if let Some(row) = techniques
            .iter()
            .find(|row| row.refuses(std::slice::from_ref(&light)).is_none())
        {
            let samples = vec![renderer.view_samples(&camera, &light)?];
            let (setups, _) = light_setups(row, &camera, &[light], bounds, &samples)?;
            renderer.render(&camera, &light, &setups[0], &settings)?;
        }
        renderer.render_volumes(&camera, &light, &settings, StencilMode::ZFail)?;
    }
    let mut report = Vec::new();
    let mut summary: Vec<SummaryRow> = techniques
        .iter()
        .map(|t| t.label.clone())
        .chain(compared.planar.then(|| crate::names::PLANAR.to_string()))
        .map(|label| SummaryRow {
            label,
            wrong: Vec::new(),
            p99: Vec::new(),
            penumbra: Vec::new(),
            setup_us: Vec::new(),
            frame_ms: Vec::new(),
        })
        .collect();
    for view in &views {
        let camera = view.camera(width as f64 / height as f64)?;
        // Every light of the view (a scene file's view may have several).
        let lights = view.lights()?;
        progress.set_message(format!("{}: volumes", view.name));
        let exact =
            renderer.render_volumes_lit_by(&camera, &lights, &settings, StencilMode::ZFail)?;
        // With PCSS, the soft shadows of the view's area lights: the reference of the
        // penumbrae.
        let soft = match args.soft.area_clusters(&lights, &bounds.scene_box())? {
            Some(clusters) => {
                progress.set_message(format!("{}: soft volumes", view.name));
                Some(renderer.render_soft_volumes(
                    &camera,
                    &clusters,
                    &settings,
                    StencilMode::ZFail,
                )?)
            }
            None => None,
        };
        // What the pixels see from each light, once per view, shared by every technique.
        let samples = lights
            .iter()
            .map(|light| renderer.view_samples(&camera, light))
            .collect::<Result<Vec<_>, _>>()?;
        let exact_ms = exact.frame.timings.shadow_pass_ms + exact.frame.timings.main_pass_ms;
        progress.inc(1);
        // The grid: cells of the frame's size (the error map's legend lies over its bottom).
        let grid_width = 3 * width;
        let grid_height = height * ((techniques.len() + planar_rows) as u32 + 1);
        let mut grid = vec![255u8; (grid_width * grid_height * 4) as usize];
        let mut paste = |image: &[u8], column: u32, row: u32| {
            let line = (width * 4) as usize;
            for y in 0..height {
                let from = y as usize * line;
                let to = (((row * height + y) * grid_width + column * width) * 4) as usize;
                grid[to..to + line].copy_from_slice(&image[from..from + line]);
            }
        };
        let mut rows = Vec::new();
        // N.L of the view's pixels (for the rows without maps): a map row's metrics.
        let mut view_n_dot_l: Option<Vec<f32>> = None;
        for (k, entry) in techniques.iter().enumerate() {
            progress.set_message(format!("{}: {}", view.name, entry.label));
            if let Some(why) = entry.refuses(&lights) {
                // Its grid row stays empty; the summary leaves this view out for it.
                rows.push(json!({ "technique": entry.label, "skipped": why }));
                progress.inc(1);
                continue;
            }
            let row_bounds = row_scene.prepare(&mut renderer, entry.projective())?;
            let (setups, setup_us) = light_setups(entry, &camera, &lights, row_bounds, &samples)?;
            let setup = &setups[0];
            let shadowed = ShadowedLight::pairs(&lights, &setups);
            let frame = renderer.render_lights(&camera, &shadowed, &row_settings(entry))?;
            let metrics = frame.metrics.as_ref().expect("metrics asked for");
            let (errors, error_image) = mask_errors(&frame, &metrics.n_dot_l, &exact.frame);
            if view_n_dot_l.is_none() {
                view_n_dot_l = Some(metrics.n_dot_l.clone());
            }
            let t = frame.timings;
            let frame_ms = setup_us / 1e3 + t.shadow_pass_ms + t.main_pass_ms;
            let undersampling = heatmap::percentiles(metrics, &metrics.undersampling);
            // PCSS filters maps read by depth; the other reads take one tap.
            let penumbra = soft
                .as_ref()
                .filter(|_| entry.read == gnomon_render::MapRead::Depth)
                .map(|soft| {
                    gnomon_render::penumbra_error(
                        &soft.factor,
                        frame.shadow.as_deref().expect("a map frame has its factor"),
                        &metrics.n_dot_l,
                    )
                });
            paste(&frame.color, 0, k as u32);
            paste(&error_image, 1, k as u32);
            paste(&heatmap::draw(metrics, width, height), 2, k as u32);
            summary[k].wrong.push(errors.wrong_percent());
            summary[k]
                .p99
                .push(undersampling["p99"].as_f64().unwrap_or(f64::NAN));
            summary[k].setup_us.push(setup_us);
            summary[k].frame_ms.push(frame_ms);
            if let Some(p) = penumbra {
                summary[k].penumbra.push(p.mean);
            }
            // sppsm-same-texels is sppsm at its own map size.
            let command = crate::args::render_command_of(
                &loaded.options,
                view,
                (Some(&entry.technique), entry.technique_name()),
                &entry.params,
                entry.resolution,
                (width, height),
                &format!(
                    "{} --out frame.png --mask mask.png --error-map error.png",
                    soft_flags(entry)
                ),
            );
            rows.push(json!({
                "technique": entry.label,
                "command": command,
                "shadow_map": entry.resolution,
                "maps": setup.maps.len(),
                "fallback": setup.fallback().map(|f| f.name()),
                "wrong_percent": errors.wrong_percent(),
                "false_shadow_percent": errors.false_shadow_percent(),
                "missed_shadow_percent": errors.missed_shadow_percent(),
                "compared_pixels": errors.compared,
                "undersampling": undersampling,
                "area_undersampling": heatmap::percentiles(metrics, &metrics.area),
                "penumbra_error": penumbra.map(|p| p.mean),
                "penumbra_pixels": penumbra.map(|p| p.pixels),
                "setup_us": setup_us,
                "frame_ms": frame_ms,
            }));
            progress.inc(1);
        }
        row_scene.restore(&mut renderer)?;
        if let Some(receiver) = &receiver {
            let k = techniques.len();
            progress.set_message(format!("{}: planar", view.name));
            match receiver {
                Ok(receiver) => {
                    let n_dot_l = match view_n_dot_l.take() {
                        Some(n) => n,
                        None => {
                            // No map row drew this view: the focused map's frame gives N.L.
                            let focused =
                                crate::rows::row("focused", &args.params, args.shadow_map)?;
                            let (setups, _) =
                                light_setups(&focused, &camera, &lights, bounds, &samples)?;
                            let shadowed = ShadowedLight::pairs(&lights, &setups);
                            let frame = renderer.render_lights(&camera, &shadowed, &settings)?;
                            frame.metrics.expect("metrics asked for").n_dot_l
                        }
                    };
                    let frame = renderer
                        .render_planar_lit_by(&camera, &lights, receiver, &settings)?
                        .frame;
                    let (errors, error_image) = mask_errors(&frame, &n_dot_l, &exact.frame);
                    let t = frame.timings;
                    let frame_ms = t.shadow_pass_ms + t.main_pass_ms;
                    paste(&frame.color, 0, k as u32);
                    paste(&error_image, 1, k as u32);
                    summary[k].wrong.push(errors.wrong_percent());
                    summary[k].p99.push(f64::NAN);
                    summary[k].setup_us.push(0.0);
                    summary[k].frame_ms.push(frame_ms);
                    let command = crate::args::render_command_of(
                        &loaded.options,
                        view,
                        (None, crate::names::PLANAR),
                        &args.params,
                        args.shadow_map,
                        (width, height),
                        " --out frame.png --mask mask.png",
                    );
                    rows.push(json!({
                        "technique": crate::names::PLANAR,
                        "command": command,
                        "maps": 0,
                        "wrong_percent": errors.wrong_percent(),
                        "false_shadow_percent": errors.false_shadow_percent(),
                        "missed_shadow_percent": errors.missed_shadow_percent(),
                        "compared_pixels": errors.compared,
                        "setup_us": 0.0,
                        "frame_ms": frame_ms,
                    }));
                }
                Err(e) => rows.push(json!({
                    "technique": crate::names::PLANAR,
                    "skipped": e.message,
                })),
            }
            progress.inc(1);
        }
        let row = (techniques.len() + planar_rows) as u32;
        paste(&exact.frame.color, 0, row);
        if let Some(soft) = &soft {
            paste(&soft.frame.color, 2, row);
        }
        let exact_mask: Vec<u8> = exact
            .frame
            .mask
            .iter()
            .flat_map(|&m| [m, m, m, 255])
            .collect();
        paste(&exact_mask, 1, row);
        let grid_path = out.join(format!("{}.png", view.name));
        write_png(
            &grid_path,
            grid_width,
            grid_height,
            image::ColorType::Rgba8,
            &grid,
        )?;
        let _ = write!(
            markdown,
            "\n## {} ({})\n\nExact shadow volumes: frame {exact_ms:.1} ms.\n\n\
             | technique | wrong pixels | false shadow | missed shadow | undersampling p50 | p95 | p99 | max | area p99 | penumbra error | setup (us) | frame (ms) | fallback |\n\
             | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |\n",
            view.name, view.description
        );
        for r in &rows {
            if let Some(why) = r["skipped"].as_str() {
                let label = r["technique"].as_str().unwrap_or_default();
                let _ = writeln!(markdown, "| {label} | n/a: {why} ||||||||||||");
                continue;
            }
            let u = &r["undersampling"];
            let f = |v: &Value| v.as_f64().map_or("-".to_string(), |x| format!("{x:.2}"));
            let _ = writeln!(
                markdown,
                "| {} | {:.3}% | {:.3}% | {:.3}% | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {} |",
                r["technique"].as_str().unwrap_or_default(),
                r["wrong_percent"].as_f64().unwrap_or_default(),
                r["false_shadow_percent"].as_f64().unwrap_or_default(),
                r["missed_shadow_percent"].as_f64().unwrap_or_default(),
                f(&u["p50"]),
                f(&u["p95"]),
                f(&u["p99"]),
                f(&u["max"]),
                f(&r["area_undersampling"]["p99"]),
                r["penumbra_error"]
                    .as_f64()
                    .map_or("-".to_string(), |x| format!("{x:.4}")),
                r["setup_us"].as_f64().unwrap_or_default(),
                r["frame_ms"].as_f64().unwrap_or_default(),
                r["fallback"].as_str().unwrap_or("none"),
            );
        }
        let volumes_command = render_command(
            &loaded.options,
            view,
            None,
            &args.params,
            args.shadow_map,
            (width, height),
            " --out frame.png --mask mask.png",
        );
        let mut labels: Vec<&str> = rows
            .iter()
            .map(|r| r["technique"].as_str().unwrap_or_default())
            .collect();
        labels.push("exact shadow volumes");
        let _ = writeln!(
            markdown,
            "\n![{}]({}.png)\n\nGrid rows, top to bottom: {}. Columns: the frame, the mask \
             errors (red: false shadow, blue: missed shadow), the sampling error map.\n\n\
             Each row from the command line:\n",
            view.name,
            view.name,
            labels.join(", ")
        );
        for r in &rows {
            let _ = writeln!(
                markdown,
                "- {}: `{}`",
                r["technique"].as_str().unwrap_or_default(),
                r["command"].as_str().unwrap_or_default()
            );
        }
        let _ = writeln!(markdown, "- exact shadow volumes: `{volumes_command}`");
        let soft_command = soft.as_ref().map(|_| {
            let mut flags = args.soft.clone();
            flags.pcf = crate::render::PcfArg::Hardware2x2;
            render_command(
                &loaded.options,
                view,
                None,
                &args.params,
                args.shadow_map,
                (width, height),
                &format!(
                    "{} --out soft.png --mask soft-factor.png",
                    flags.non_default_flags()
                ),
            )
        });
        if let Some(command) = &soft_command {
            let _ = writeln!(
                markdown,
                "- soft shadows of the area light (the penumbrae's reference; the exact volumes' \
                 row, third column): `{command}`"
            );
        }
        report.push(json!({
            "view": view.name,
            "description": view.description,
            "eye": view.eye.to_array(),
            "target": view.target.to_array(),
            "far": view.far,
            "up": view.up.to_array(),
            "fov": view.fov_y_degrees,
            "near": view.near,
            "light": crate::report::view_light_json(&view.light),
            "more_lights": view.more_lights.iter().map(crate::report::view_light_json).collect::<Vec<_>>(),
            "volumes_command": volumes_command,
            "volumes_frame_ms": exact_ms,
            "soft_command": soft_command,
            "techniques": rows,
        }));
    }
    progress.finish_and_clear();
    let _ = write!(
        markdown,
        "\n## Over all views\n\n| technique | mean wrong pixels | worst view | mean undersampling p99 | mean penumbra error |\n| --- | ---: | ---: | ---: | ---: |\n"
    );
    for row in &summary {
        let worst = row.wrong.iter().copied().fold(0.0, f64::max);
        let penumbra = if row.penumbra.is_empty() {
            "-".to_string()
        } else {
            format!("{:.4}", mean(&row.penumbra))
        };
        let _ = writeln!(
            markdown,
            "| {} | {:.3}% | {worst:.3}% | {} | {penumbra} |",
            row.label,
            mean(&row.wrong),
            two_places(mean(&row.p99))
        );
    }
    let write = |name: &str, text: &str| write_text(&out.join(name), text);
    write("index.md", &markdown)?;
    write(
        "report.json",
        &serde_json::to_string_pretty(&json!({
            "scene": loaded.name,
            "size": [width, height],
            "shadow_map": args.shadow_map,
            "device": renderer.gpu().describe(),
            "timing": renderer.timing_source().name(),
            "views": report,
        }))
        .expect("JSON of plain values"),
    )?;
    eprintln!(
        "compared {} techniques over {} views of {} ({:.1} s so far)",
        techniques.len(),
        views.len(),
        loaded.name,
        started.elapsed().as_secs_f64()
    );
    Ok(summary)
}
