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
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP)]
    pub shadow_map: u32,
    /// Image width in pixels, 64 to 4096 (the height follows at 16:9).
    #[arg(long, default_value_t = 960, value_parser = clap::value_parser!(u32).range(64..=4096))]
    pub width: u32,
    #[command(flatten)]
    pub params: TechniqueParams,
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
    // Every map technique, planar shadows, then the shadow volumes.
    let per_view = techniques.len() + 1 + usize::from(planar.is_some());
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
            let light_view = args.out.join(format!("{stem}_light.png"));
            write_frame(
                &frame,
                &args.out.join(format!("{stem}.png")),
                None,
                Some(&light_view),
            )?;
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
            cells.push_str(&format!(
                "<td><img src=\"{stem}.png\" width=480><br><img src=\"{stem}_light.png\" width=240>\
                 <br>{} &middot; setup {setup_us:.0} &micro;s &middot; shadow pass {:.1} ms &middot; \
                 main pass {:.1} ms &middot; fallback {fallback}<br><code>{command}</code></td>",
                row.label,
                timings.shadow_pass_ms,
                timings.main_pass_ms
            ));
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
            write_frame(
                &drawn.frame,
                &args.out.join(format!("{stem}.png")),
                None,
                None,
            )?;
            let timings = drawn.frame.timings;
            eprintln!(
                "[{:>2}/{total}] {:<15} {:<8} {} flattened triangles  flattening and stencil {:>6.1} ms  shading {:>6.1} ms",
                v * per_view + per_view - 1,
                view.name,
                crate::names::PLANAR,
                drawn.stats.triangles,
                timings.shadow_pass_ms,
                timings.main_pass_ms,
            );
            cells.push_str(&format!(
                "<td><img src=\"{stem}.png\" width=480><br>planar projected shadows (the ground \
                 only) &middot; {} flattened triangles &middot; flattening and stencil {:.1} ms \
                 &middot; shading {:.1} ms<br><code>{}</code></td>",
                drawn.stats.triangles,
                timings.shadow_pass_ms,
                timings.main_pass_ms,
                crate::args::render_command_of(
                    &loaded.options,
                    view,
                    (None, crate::names::PLANAR),
                    &args.params,
                    args.shadow_map,
                    (width, height),
                    &format!(" --out {stem}.png"),
                )
            ));
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
        write_frame(
            &drawn.frame,
            &args.out.join(format!("{stem}.png")),
            None,
            None,
        )?;
        let (timings, stats) = (drawn.frame.timings, drawn.stats);
        volume_sums[0] += timings.shadow_pass_ms;
        volume_sums[1] += timings.main_pass_ms;
        eprintln!(
            "[{:>2}/{total}] {:<15} {:<8} {} volume triangles ({} casters z-pass, {} z-fail)  extrusion and stencil {:>6.1} ms  shading {:>6.1} ms",
            v * per_view + per_view,
            view.name,
            "volumes",
            stats.triangles,
            stats.z_pass_casters,
            stats.z_fail_casters,
            timings.shadow_pass_ms,
            timings.main_pass_ms,
        );
        cells.push_str(&format!(
            "<td><img src=\"{stem}.png\" width=480><br>exact shadow volumes &middot; {} triangles \
             ({} casters z-pass, {} z-fail) &middot; extrusion and stencil {:.1} ms &middot; \
             shading {:.1} ms<br><code>{}</code></td>",
            stats.triangles,
            stats.z_pass_casters,
            stats.z_fail_casters,
            timings.shadow_pass_ms,
            timings.main_pass_ms,
            render_command(
                &loaded.options,
                view,
                None,
                &args.params,
                args.shadow_map,
                (width, height),
                &format!(" --stencil per-caster --out {stem}.png"),
            )
        ));
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
        .chain(["<th>volumes (exact)</th>".to_string()])
        .collect();
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>gnomon demo</title>\
         <style>body{{font-family:sans-serif}} td,th{{vertical-align:top;padding:6px}}</style>\
         <h1>gnomon demo: {} scene</h1><p>Each cell: the frame, and below it the shadow map as the \
         light sees it with the camera's view frustum in red; the last column has the exact \
         shadows of stenciled shadow volumes. {}x{} pixels, {}x{} shadow maps, \
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
