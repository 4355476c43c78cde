//! `gnomon demo`: the built-in scene from its named views with every technique.
//!
//! Until the renderer lands this writes the shadow setups (JSON) and an index page that
//! lists them; the renderer issue turns it into images side by side.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use glam::DVec3;
use gnomon::{
    Camera, DirectionalLight, Lens, Light, MapSettings, ShadowTechnique, Technique, compute_setup,
};
use gnomon_scene::DEMO_VIEWS;
use serde_json::json;

use crate::UsageError;
use crate::report;

/// `gnomon demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {
    /// Where to write the results.
    #[arg(long, default_value = "gnomon-demo")]
    pub out: PathBuf,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = 2048)]
    pub shadow_map: u32,
}

/// Runs `gnomon demo`.
pub fn run(args: &DemoArgs) -> Result<(), UsageError> {
    let layout = gnomon_scene::demo();
    let scene = layout.bounds()?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| UsageError(format!("cannot create {}: {e}", args.out.display())))?;
    let mut rows = Vec::new();
    let mut all = Vec::new();
    for view in DEMO_VIEWS {
        let camera = Camera::look_at(
            DVec3::from_array(view.eye),
            DVec3::from_array(view.target),
            DVec3::Y,
            Lens {
                far: view.far,
                ..Lens::default()
            },
        )?;
        let light = Light::Directional(DirectionalLight::new(DVec3::from_array(
            view.light_direction,
        ))?);
        for technique in Technique::all() {
            let start = Instant::now();
            let setup = compute_setup(
                &technique,
                &camera,
                &light,
                &scene,
                MapSettings::with_resolution(args.shadow_map),
            )?;
            let micros = start.elapsed().as_secs_f64() * 1e6;
            let fallback = setup.fallback().map_or("none", |f| f.name());
            println!(
                "{:<15} {:<8} {:>8.1} us  fallback {:<24} frame {}",
                view.name,
                technique.name(),
                micros,
                fallback,
                setup.diagnostics.light_frame.name()
            );
            rows.push(format!(
                "<tr><td>{}</td><td>{}</td><td>{:.1}</td><td>{}</td><td>{}</td></tr>",
                view.name,
                technique.name(),
                micros,
                fallback,
                setup.diagnostics.relevant_casters
            ));
            all.push(json!({"view": view.name, "description": view.description, "setup": report::setup_json(&setup)}));
        }
    }
    let json_path = args.out.join("setups.json");
    let html_path = args.out.join("index.html");
    write(
        &json_path,
        &serde_json::to_string_pretty(&all).expect("JSON of plain values"),
    )?;
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>gnomon demo</title><h1>gnomon demo: {}</h1>\
         <p>Shadow setups of the demo scene's named views (images come with the renderer).</p>\
         <table border=1 cellpadding=4><tr><th>view</th><th>technique</th><th>setup (us)</th>\
         <th>fallback</th><th>relevant casters</th></tr>{}</table>\
         <p>Matrices: <a href=setups.json>setups.json</a></p>",
        layout.name,
        rows.join("")
    );
    write(&html_path, &html)?;
    println!("wrote {} and {}", html_path.display(), json_path.display());
    Ok(())
}

fn write(path: &std::path::Path, text: &str) -> Result<(), UsageError> {
    std::fs::write(path, text)
        .map_err(|e| UsageError(format!("cannot write {}: {e}", path.display())))
}
