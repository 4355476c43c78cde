//! False flicker in Bevy along gnomon flicker's dolly and pan paths: each frame drawn with
//! its own cascades and with the last frame's, for Bevy's cascades and the plugin's stable
//! and warped fits (the example's own code draws the frames).

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

use common::{NOT_JUDGED, options};

/// One frame of a camera path: the options moved by `offset` (world units).
fn moved(options: &args::Options, offset: bevy::math::Vec3) -> args::Options {
    args::Options {
        eye: options.eye + offset,
        target: options.target + offset,
        ..options.clone()
    }
}

/// False flicker along a camera path: in each frame after the first, the share of judged
/// pixels whose state differs between the frame drawn with its own cascades and drawn with
/// the last frame's. The camera, the scene and the sun are the same in both, so every such
/// pixel changed only because the maps did: the exact state does not change along a camera
/// path. (Comparing consecutive frames' pixels instead would count every edge the pixel grid
/// slides across.)
fn false_flicker(bevy: &mut headless::Headless, frames: &[args::Options]) -> f64 {
    bevy.set_view(&frames[0]);
    bevy.frames(2);
    bevy.frame_and_mask().unwrap();
    let mut last = bevy.cascades();
    let (mut judged, mut changed) = (0usize, 0usize);
    for options in &frames[1..] {
        bevy.move_camera(options);
        let (_, own) = bevy.frame_and_mask().unwrap();
        let current = bevy.cascades();
        bevy.hold(last);
        let held = bevy.mask_again().unwrap();
        bevy.hold(world::HeldCascades(None));
        for (&a, &b) in own.iter().zip(&held) {
            if a != NOT_JUDGED && b != NOT_JUDGED {
                judged += 1;
                changed += usize::from(a != b);
            }
        }
        last = current;
    }
    assert!(judged > 10_000, "{judged} judged");
    100.0 * changed as f64 / judged as f64
}

#[test]
fn stable_fits_do_not_flicker_along_dolly_and_pan_paths() {
    let loaded = world::load(None).unwrap();
    let all_views = loaded.views.clone();
    let names = std::env::var("GNOMON_BEVY_FLICKER_VIEWS").unwrap_or_else(|_| "street".into());
    let frame_count: usize = std::env::var("GNOMON_BEVY_FLICKER_FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let fits = ["bevy", "cascades --stable", "cascades"];
    let first = names.split(',').next().unwrap();
    let mut bevy = headless::Headless::new(&options(first, "bevy", &all_views), loaded);
    eprintln!("{:16} {:6} {}", "view", "path", fits.join(" | "));
    for name in names.split(',') {
        for path in ["dolly", "pan"] {
            let mut shares = Vec::new();
            for fit in fits {
                let start = options(name, fit, &all_views);
                let forward = (start.target - start.eye).normalize();
                let right = forward.cross(bevy::math::Vec3::Y).normalize();
                // gnomon flicker's default step: a thousandth of the far plane per frame.
                let step = start.far / 1000.0;
                let along = if path == "dolly" { forward } else { right };
                let frames: Vec<_> = (0..frame_count)
                    .map(|t| moved(&start, along * step * t as f32))
                    .collect();
                shares.push(false_flicker(&mut bevy, &frames));
            }
            let cells: Vec<String> = shares.iter().map(|s| format!("{s:.4}%")).collect();
            eprintln!("{:16} {:6} {}", name, path, cells.join("  "));
            assert!(
                shares[1] <= 0.01,
                "{name} {path}: the stable fit flickers on {:.4}%",
                shares[1]
            );
        }
    }
}
