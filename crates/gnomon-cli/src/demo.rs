//! `gnomon demo`: a scene (the built-in demo by default) from its named views with every
//! technique and with exact shadow volumes, written as images with an `index.html` that shows
//! them side by side.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use gnomon_render::{RenderSettings, ShadowedLight, StencilMode};
use serde_json::json;

use crate::CliError;
use crate::args::render_command;
use crate::args::{SceneArgs, TechniqueParams, ViewListArgs, light_setups};
use crate::render::{open_renderer, write_frame, write_text};
use crate::report;

/// `gnomon demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub views: ViewListArgs,
    /// Where to write the results.
    #[arg(long, default_value = "gnomon-demo")]
    pub out: PathBuf,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Image width in pixels, 64 to 4096 (the height follows at 16:9).
    #[arg(long, default_value_t = 960, value_parser = clap::value_parser!(u32).range(64..=4096))]
    pub width: u32,
    #[command(flatten)]
    pub params: TechniqueParams,
}

/// The radius of the area lights of the gallery's soft column: the sun's angular radius
/// (degrees), and for spot and point lights a street lamp's globe of 25 cm (world units).
fn soft_radius(light: &gnomon::Light) -> f64 {
    match light {
        gnomon::Light::Directional(_) => 0.27,
        _ => 0.25,
    }
}

/// The hard lights that sample each area light in the gallery's soft column (a picture;
/// `compare --pcf pcss` measures with 64 by default).
const SOFT_SAMPLES: usize = 32;

/// The map technique the gallery softens with PCSS (it takes every kind of light).
const PCSS_TECHNIQUE: &str = "lispsm";

/// Writes `frame` as `STEM.png` in `out` (and with `light_view` its maps as the light sees
/// them, `STEM_light.png`) and gives its gallery cell: the images, `caption` and the command
/// that draws it.
fn cell(
    out: &std::path::Path,
    stem: &str,
    frame: &gnomon_render::Frame,
    light_view: bool,
    caption: &str,
    command: &str,
) -> Result<String, CliError> {
    let light = light_view.then(|| out.join(format!("{stem}_light.png")));
    write_frame(
        frame,
        &out.join(format!("{stem}.png")),
        None,
        light.as_deref(),
    )?;
    let light_image = if light_view {
        format!("<br><img src=\"{stem}_light.png\" width=240>")
    } else {
        String::new()
    };
    Ok(format!(
        "<td><img src=\"{stem}.png\" width=480>{light_image}<br>{caption}<br><code>{command}</code></td>"
    ))
}

/// Runs `gnomon demo`.
pub fn run(args: &DemoArgs) -> Result<(), CliError> {
    let started = Instant::now();
    let loaded = args.scene.load()?;
    let views = args.views.select(&loaded.views)?;
    let scene = &loaded.scene;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| CliError::runtime(format!("cannot create {}: {e}", args.out.display())))?;
    let width = args.width;
    let height = width * 9 / 16;
    let mut renderer = open_renderer(scene, (width, height), Some(args.shadow_map))?;
    eprintln!("gnomon demo: rendering on {}", renderer.gpu().describe());
    let settings = RenderSettings {
        width,
        height,
        light_view: true,
        ..RenderSettings::default()
    };
    // Every technique, SPPSM with the texels of one map, the cascade rows, and the focused
    // map read as the lecture's other light-space maps (projective, object IDs, IDs and
    // depth).
    let names: Vec<String> = std::iter::once("all")
        .chain(crate::names::MAP_READS.iter().map(|(n, _)| *n))
        .map(String::from)
        .collect();
    let techniques = crate::rows::rows(&names, &args.params, args.shadow_map, true)?;
    let row_scene =
        crate::rows::RowScene::new(&loaded.scene, techniques.iter().any(|r| r.projective()))?;
    // Planar shadows where the scene has a ground to fall on.
    let planar = crate::render::planar_receiver(&loaded.scene, None).ok();
    let pcss_row = crate::rows::row(PCSS_TECHNIQUE, &args.params, args.shadow_map)?;
    // Every map technique, planar shadows, the shadow volumes, then soft shadows: the area
    // light as a cluster of hard lights with exact volumes, and PCSS.
    let per_view = techniques.len() + 3 + usize::from(planar.is_some());
    let total = views.len() * per_view;
    let mut rows = String::new();
    let mut all = Vec::new();
    let mut sums = [0.0f64; 3];
    let mut volume_sums = [0.0f64; 2];
    for (v, view) in views.iter().enumerate() {
        let camera = view.camera(width as f64 / height as f64)?;
        // Every light of the view (a scene file's view may have several).
        let lights = view.lights()?;
        let mut cells = String::new();
        // What the pixels see from each light, once per view, shared by every technique.
        let samples = lights
            .iter()
            .map(|light| renderer.view_samples(&camera, light))
            .collect::<Result<Vec<_>, _>>()?;
        for (t, row) in techniques.iter().enumerate() {
            if let Some(why) = row.refuses(&lights) {
                cells.push_str(&format!("<td>{}: not drawn ({why})</td>", row.label));
                all.push(json!({ "view": view.name, "technique": row.label, "skipped": why }));
                continue;
            }
            let row_bounds = row_scene.prepare(&mut renderer, row.projective())?;
            let (setups, setup_us) = light_setups(row, &camera, &lights, row_bounds, &samples)?;
            let setup = &setups[0];
            let shadowed = ShadowedLight::pairs(&lights, &setups);
            let frame = renderer.render_lights(&camera, &shadowed, &row.settings(&settings))?;
            let stem = format!("{}_{}", view.name, row.label);
            let timings = frame.timings;
            sums[0] += setup_us;
            sums[1] += timings.shadow_pass_ms;
            sums[2] += timings.main_pass_ms;
            let fallback = setup.fallback().map_or("none", |f| f.name());
            eprintln!(
                "[{:>2}/{total}] {:<15} {:<8} setup {:>7.1} us  shadow pass {:>6.1} ms  main pass {:>6.1} ms  fallback {fallback}",
                v * per_view + t + 1,
                view.name,
                row.label,
                setup_us,
                timings.shadow_pass_ms,
                timings.main_pass_ms,
            );
            let command = crate::args::render_command_of(
                &loaded.options,
                view,
                (Some(&row.technique), row.technique_name()),
                &row.params,
                row.resolution,
                (width, height),
                &format!(" --out {stem}.png --light-view {stem}_light.png"),
            );
            let caption = format!(
                "{} &middot; setup {setup_us:.0} &micro;s &middot; shadow pass {:.1} ms &middot; \
                 main pass {:.1} ms &middot; fallback {fallback}",
                row.label, timings.shadow_pass_ms, timings.main_pass_ms
            );
            cells.push_str(&cell(&args.out, &stem, &frame, true, &caption, &command)?);
            all.push(json!({
                "view": view.name,
                "technique": row.label,
                "setup_us": setup_us,
                "shadow_pass_ms": timings.shadow_pass_ms,
                "main_pass_ms": timings.main_pass_ms,
                "setup": report::setup_json(setup),
            }));
        }
        row_scene.restore(&mut renderer)?;
        if let Some(receiver) = &planar {
            // Planar projected shadows on the ground (nothing else receives: the limit).
            let drawn = renderer.render_planar_lit_by(&camera, &lights, receiver, &settings)?;
            let stem = format!("{}_planar", view.name);
            let timings = drawn.frame.timings;
            eprintln!(
                "[{:>2}/{total}] {:<15} {:<8} {} flattened triangles  flattening and stencil {:>6.1} ms  shading {:>6.1} ms",
                v * per_view + per_view - 3,
                view.name,
                crate::names::PLANAR,
                drawn.stats.triangles,
                timings.shadow_pass_ms,
                timings.main_pass_ms,
            );
            let caption = format!(
                "planar projected shadows (the ground only) &middot; {} flattened triangles \
                 &middot; flattening and stencil {:.1} ms &middot; shading {:.1} ms",
                drawn.stats.triangles, timings.shadow_pass_ms, timings.main_pass_ms,
            );
            let command = crate::args::render_command_of(
                &loaded.options,
                view,
                (None, crate::names::PLANAR),
                &args.params,
                args.shadow_map,
                (width, height),
                &format!(" --out {stem}.png"),
            );
            cells.push_str(&cell(
                &args.out,
                &stem,
                &drawn.frame,
                false,
                &caption,
                &command,
            )?);
            all.push(json!({
                "view": view.name,
                "technique": crate::names::PLANAR,
                "flattened_triangles": drawn.stats.triangles,
                "flattening_and_stencil_ms": timings.shadow_pass_ms,
                "shading_ms": timings.main_pass_ms,
            }));
        }
        // Exact shadows: stenciled shadow volumes, z-pass or z-fail chosen per caster.
        let drawn =
            renderer.render_volumes_lit_by(&camera, &lights, &settings, StencilMode::PerCaster)?;
        let stem = format!("{}_volumes", view.name);
        let (timings, stats) = (drawn.frame.timings, drawn.stats);
        volume_sums[0] += timings.shadow_pass_ms;
        volume_sums[1] += timings.main_pass_ms;
        eprintln!(
            "[{:>2}/{total}] {:<15} {:<8} {} volume triangles ({} casters z-pass, {} z-fail)  extrusion and stencil {:>6.1} ms  shading {:>6.1} ms",
            v * per_view + per_view - 2,
            view.name,
            "volumes",
            stats.triangles,
            stats.z_pass_casters,
            stats.z_fail_casters,
            timings.shadow_pass_ms,
            timings.main_pass_ms,
        );
        let caption = format!(
            "exact shadow volumes &middot; {} triangles ({} casters z-pass, {} z-fail) &middot; \
             extrusion and stencil {:.1} ms &middot; shading {:.1} ms",
            stats.triangles,
            stats.z_pass_casters,
            stats.z_fail_casters,
            timings.shadow_pass_ms,
            timings.main_pass_ms,
        );
        let command = render_command(
            &loaded.options,
            view,
            None,
            &args.params,
            args.shadow_map,
            (width, height),
            &format!(" --stencil per-caster --out {stem}.png"),
        );
        cells.push_str(&cell(
            &args.out,
            &stem,
            &drawn.frame,
            false,
            &caption,
            &command,
        )?);
        all.push(json!({
            "view": view.name,
            "technique": "volumes",
            "stencil": "per-caster",
            "volume_triangles": stats.triangles,
            "z_pass_casters": stats.z_pass_casters,
            "z_fail_casters": stats.z_fail_casters,
            "extrusion_and_stencil_ms": timings.shadow_pass_ms,
            "shading_ms": timings.main_pass_ms,
        }));
        // Soft shadows of the main light as an area light: the cluster reference, then PCSS.
        let soft = crate::render::SoftArgs {
            pcf: crate::render::PcfArg::Hardware2x2,
            area_light: Some(soft_radius(&lights[0])),
            area_samples: Some(SOFT_SAMPLES),
        };
        let clusters = soft
            .area_clusters(&lights, &row_scene.bounds().scene_box())?
            .expect("an area light is given");
        let reference =
            renderer.render_soft_volumes(&camera, &clusters, &settings, StencilMode::PerCaster)?;
        let stem = format!("{}_soft", view.name);
        let t = reference.frame.timings;
        eprintln!(
            "[{:>2}/{total}] {:<15} {:<8} {SOFT_SAMPLES} hard lights with volumes  {:>6.1} ms",
            v * per_view + per_view - 1,
            view.name,
            "soft",
            t.shadow_pass_ms + t.main_pass_ms,
        );
        let radius_words = match lights[0] {
            gnomon::Light::Directional(_) => format!("{} degrees", soft_radius(&lights[0])),
            _ => format!("{} m", soft_radius(&lights[0])),
        };
        let caption = format!(
            "soft shadows of an area light of {radius_words} (the reference): {SOFT_SAMPLES} \
             hard lights with exact volumes, averaged &middot; {:.1} ms",
            t.shadow_pass_ms + t.main_pass_ms,
        );
        let command = render_command(
            &loaded.options,
            view,
            None,
            &args.params,
            args.shadow_map,
            (width, height),
            &format!("{} --out {stem}.png", soft.non_default_flags()),
        );
        cells.push_str(&cell(
            &args.out,
            &stem,
            &reference.frame,
            false,
            &caption,
            &command,
        )?);
        all.push(json!({
            "view": view.name,
            "technique": "soft-volumes",
            "area_light": soft.area_light,
            "area_samples": SOFT_SAMPLES,
            "ms": t.shadow_pass_ms + t.main_pass_ms,
        }));
        let pcss = crate::render::SoftArgs {
            pcf: crate::render::PcfArg::Pcss,
            area_samples: None,
            ..soft
        };
        let stem = format!("{}_pcss", view.name);
        let label = format!("pcss ({PCSS_TECHNIQUE})");
        if let Some(why) = pcss_row.refuses(&lights) {
            cells.push_str(&format!("<td>{label}: not drawn ({why})</td>"));
        } else {
            let row_bounds = row_scene.prepare(&mut renderer, false)?;
            let (setups, setup_us) =
                light_setups(&pcss_row, &camera, &lights, row_bounds, &samples)?;
            let shadowed = ShadowedLight::pairs(&lights, &setups);
            let frame = renderer.render_lights(
                &camera,
                &shadowed,
                &RenderSettings {
                    filter: gnomon_render::Filter::Pcss,
                    area_light_radius: pcss.pcss_radius(),
                    metrics: true,
                    ..settings
                },
            )?;
            let error = gnomon_render::penumbra_error(
                &reference.factor,
                frame.shadow.as_deref().expect("a map frame has its factor"),
                &frame.metrics.as_ref().expect("asked for").n_dot_l,
            );
            let t = frame.timings;
            eprintln!(
                "[{:>2}/{total}] {:<15} {:<8} setup {:>7.1} us  shadow pass {:>6.1} ms  main pass {:>6.1} ms  penumbra error {:.4}",
                v * per_view + per_view,
                view.name,
                "pcss",
                setup_us,
                t.shadow_pass_ms,
                t.main_pass_ms,
                error.mean,
            );
            let caption = format!(
                "{label}, the same area light &middot; penumbra error {:.3} (against the \
                 reference, over {} pixels) &middot; shadow pass {:.1} ms &middot; main pass \
                 {:.1} ms",
                error.mean, error.pixels, t.shadow_pass_ms, t.main_pass_ms,
            );
            let command = crate::args::render_command_of(
                &loaded.options,
                view,
                (Some(&pcss_row.technique), pcss_row.technique_name()),
                &pcss_row.params,
                pcss_row.resolution,
                (width, height),
                &format!("{} --out {stem}.png", pcss.non_default_flags()),
            );
            cells.push_str(&cell(&args.out, &stem, &frame, false, &caption, &command)?);
            all.push(json!({
                "view": view.name,
                "technique": "pcss",
                "map_technique": PCSS_TECHNIQUE,
                "area_light": pcss.area_light,
                "penumbra_error": error.mean,
                "penumbra_pixels": error.pixels,
                "setup_us": setup_us,
                "shadow_pass_ms": t.shadow_pass_ms,
                "main_pass_ms": t.main_pass_ms,
            }));
        }
        rows.push_str(&format!(
            "<tr><th>{}<br><small>{}</small></th>{cells}</tr>",
            view.name, view.description
        ));
    }
    let header: String = techniques
        .iter()
        .map(|t| format!("<th>{}</th>", t.label))
        .chain(
            planar
                .as_ref()
                .map(|_| "<th>planar (the ground)</th>".to_string()),
        )
        .chain([
            "<th>volumes (exact)</th>".to_string(),
            "<th>soft (reference)</th>".to_string(),
            format!("<th>pcss ({PCSS_TECHNIQUE})</th>"),
        ])
        .collect();
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>gnomon demo</title>\
         <style>body{{font-family:sans-serif}} td,th{{vertical-align:top;padding:6px}}</style>\
         <h1>gnomon demo: {} scene</h1><p>Each cell: the frame, and below it the shadow map as the \
         light sees it with the camera's view frustum in red; then the exact \
         shadows of stenciled shadow volumes, and soft shadows of the main light as an area \
         light (the sun's 0.27 degrees, a lamp's 25 cm globe): the reference (a cluster of hard \
         lights with exact volumes) and PCSS. {}x{} pixels, {}x{} shadow maps, \
         rendered on {}.</p><table><tr><th>view</th>{header}</tr>{rows}</table>\
         <p>Setups and timings: <a href=setups.json>setups.json</a></p>",
        loaded.name,
        width,
        height,
        args.shadow_map,
        args.shadow_map,
        renderer.gpu().describe()
    );
    let write = |name: &str, text: &str| write_text(&args.out.join(name), text);
    write("index.html", &html)?;
    write(
        "setups.json",
        &serde_json::to_string_pretty(&all).expect("JSON of plain values"),
    )?;
    let maps = all
        .iter()
        .filter(|e| e["skipped"].is_null() && e["setup_us"].is_number())
        .count()
        .max(1) as f64;
    let views = views.len() as f64;
    eprintln!(
        "mean over {maps} shadow-map frames: setup {:.1} us, shadow pass {:.1} ms, main pass {:.1} ms; \
         over {views} shadow-volume frames: extrusion and stencil {:.1} ms, shading {:.1} ms; \
         {:.1} s in all (pass times from {})",
        sums[0] / maps,
        sums[1] / maps,
        sums[2] / maps,
        volume_sums[0] / views,
        volume_sums[1] / views,
        started.elapsed().as_secs_f64(),
        renderer.timing_source().name()
    );
    crate::say!("wrote {}", args.out.join("index.html").display());
    Ok(())
}
