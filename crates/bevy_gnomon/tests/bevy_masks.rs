//! Shadows drawn by Bevy's renderer (headless, on the machine's GPU: lavapipe in CI) against
//! gnomon's exact shadow volumes of the same camera and sun, over the demo's sun views:
//! Bevy's default cascades and the plugin's default fit, at the same map size, number of
//! cascades, shadow distance (the view's far plane) and filter (Bevy's default, Gaussian).
//!
//! The example's own code draws the frames (`examples/scene`), so the test judges what a
//! user runs.

#[path = "../examples/scene/args.rs"]
#[allow(dead_code)]
mod args;
mod common;
#[path = "../examples/scene/headless.rs"]
#[allow(dead_code)]
mod headless;
#[path = "../examples/scene/world.rs"]
#[allow(dead_code)]
mod world;

use gnomon_render::{Gpu, MASK_EMPTY, RenderScene, RenderSettings, Renderer, StencilMode};
use gnomon_scene::{NamedView, ViewLight};

use common::{NOT_JUDGED, SIZE, options};

/// The exact mask of a view: gnomon's shadow volumes (z-fail) on the same camera and sun.
fn exact_mask(renderer: &mut Renderer, view: &NamedView) -> Vec<u8> {
    let (camera, light) = view
        .camera_and_light(f64::from(SIZE.0) / f64::from(SIZE.1))
        .unwrap();
    let settings = RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        ..RenderSettings::default()
    };
    renderer
        .render_volumes_lit_by(&camera, &[light], &settings, StencilMode::ZFail)
        .unwrap()
        .frame
        .mask
}

/// Wrong pixels over the pixels both masks judge, and how many those are.
fn wrong(bevy: &[u8], exact: &[u8]) -> (usize, usize) {
    let mut judged = 0;
    let mut wrong = 0;
    for (&b, &e) in bevy.iter().zip(exact) {
        if b == NOT_JUDGED || e == MASK_EMPTY {
            continue;
        }
        judged += 1;
        if b != e {
            wrong += 1;
        }
    }
    (wrong, judged)
}

#[test]
fn the_plugins_default_is_wrong_on_at_most_half_as_many_pixels_as_bevys() {
    let loaded = world::load(None).unwrap();
    let views: Vec<NamedView> = loaded
        .views
        .iter()
        .filter(|v| matches!(v.light, ViewLight::Directional { .. }))
        .cloned()
        .collect();
    let all_views = loaded.views.clone();
    let layout = gnomon_scene::demo();
    let mut oracle =
        Renderer::new(Gpu::new().unwrap(), &RenderScene::from_layout(&layout)).unwrap();
    let mut bevy = headless::Headless::new(&options(&views[0].name, "bevy", &all_views), loaded);
    // The default fit is warped: Bevy draws it right only where depth clipping can be
    // turned off.
    assert!(
        bevy.depth_clip_control(),
        "the device lacks DEPTH_CLIP_CONTROL"
    );
    // Bevy's cascades, the plugin's default, then any fits GNOMON_BEVY_FITS names
    // (semicolon-separated, as the example's --technique takes them) for the results table.
    let mut fits = vec!["bevy".to_string(), "cascades".to_string()];
    if let Ok(more) = std::env::var("GNOMON_BEVY_FITS") {
        fits.extend(more.split(';').map(str::to_string));
    }
    eprintln!("{:16} {}", "view", fits.join(" | "));
    let mut rows = Vec::new();
    for view in &views {
        let exact = exact_mask(&mut oracle, view);
        let mut shares = vec![0.0; fits.len()];
        for (k, shadows) in fits.iter().enumerate() {
            bevy.set_view(&options(&view.name, shadows, &all_views));
            bevy.frames(2);
            let (_, mask) = bevy.frame_and_mask().unwrap();
            if let Ok(dir) = std::env::var("GNOMON_BEVY_DUMP") {
                let path = format!("{dir}/{}-{k}.png", view.name);
                image::save_buffer(path, &mask, SIZE.0, SIZE.1, image::ExtendedColorType::L8)
                    .unwrap();
                let path = format!("{dir}/{}-exact.png", view.name);
                image::save_buffer(path, &exact, SIZE.0, SIZE.1, image::ExtendedColorType::L8)
                    .unwrap();
            }
            let (w, judged) = wrong(&mask, &exact);
            assert!(
                judged > (SIZE.0 * SIZE.1 / 10) as usize,
                "{}: {judged} judged",
                view.name
            );
            shares[k] = 100.0 * w as f64 / judged as f64;
        }
        let cells: Vec<String> = shares.iter().map(|s| format!("{s:.3}%")).collect();
        eprintln!("{:16} {}", view.name, cells.join("  "));
        rows.push(shares);
    }
    let mean = |k: usize| rows.iter().map(|r| r[k]).sum::<f64>() / rows.len() as f64;
    let cells: Vec<String> = (0..fits.len())
        .map(|k| format!("{:.3}%", mean(k)))
        .collect();
    eprintln!("{:16} {}", "mean", cells.join("  "));
    for (view, r) in views.iter().zip(&rows) {
        assert!(
            r[1] <= 0.5 * r[0],
            "{}: gnomon {:.3}% vs Bevy {:.3}%",
            view.name,
            r[1],
            r[0]
        );
    }
    assert!(mean(1) <= 0.5 * mean(0));
}
