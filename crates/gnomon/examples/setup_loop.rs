//! Runs one of the setup benches' setups in a loop, so that `valgrind --tool=callgrind` can
//! count its instructions (`scripts/setup-instructions.sh`): on a noisy machine the count says
//! more than a timing, and it is the same on every run.
//!
//! `cargo run --release -p gnomon-core --example setup_loop -- SETUP BOXES ITERATIONS`, SETUP one
//! of [`SETUPS`]; the scene, camera and lights are the criterion bench's
//! (`benches/common/city.rs`); the `street_` setups use its street city and camera.

use std::hint::black_box;
use std::process::ExitCode;

#[path = "../benches/common/city.rs"]
mod city;

use city::{
    adaptive_cascades, bench_camera, city, lamp, lamp_over_city, spot, street_camera, street_city,
    sun,
};
use gnomon::{
    Cascades, Cube, Focused, Lispsm, MapSettings, SetupError, ShadowSetup, ShadowTechnique, Sppsm,
    ViewSamples, compute_setup, compute_setup_with_samples,
};

/// The setups, named as the criterion bench names them (at 1000 boxes, `setup/NAME/1000`).
const SETUPS: [&str; 13] = [
    "focused_directional",
    "lispsm_directional",
    "lispsm_directional_given_samples",
    "cascades_4_lispsm_directional_given_samples",
    "cascades_adaptive_directional_given_samples",
    "cascades_4_stable_directional",
    "sppsm_directional",
    "cube_point_given_samples",
    "cube_point_over_city_given_samples",
    "focused_spot",
    "street_focused",
    "street_lispsm",
    "street_sppsm",
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parsed = match args.as_slice() {
        [name, boxes, iterations] => SETUPS
            .iter()
            .find(|s| *s == name)
            .zip(boxes.parse::<usize>().ok().filter(|n| *n > 0))
            .zip(iterations.parse::<usize>().ok()),
        _ => None,
    };
    let Some(((name, boxes), iterations)) = parsed else {
        eprintln!(
            "usage: setup_loop SETUP BOXES ITERATIONS (SETUP: {}; BOXES at least 1)",
            SETUPS.join(", ")
        );
        return ExitCode::from(2);
    };
    let (camera, scene) = if name.starts_with("street_") {
        (street_camera(), street_city(boxes))
    } else {
        (bench_camera(), city(boxes, true))
    };
    let settings = MapSettings::with_resolution(2048);
    let light = match *name {
        "cube_point_given_samples" => lamp(250.0),
        "cube_point_over_city_given_samples" => lamp_over_city(),
        "focused_spot" => spot(),
        _ => sun(),
    };
    let samples = ViewSamples::new(&camera, &light, &scene);
    let given = |technique: &dyn ShadowTechnique| {
        compute_setup_with_samples(technique, &camera, &light, &scene, settings, &samples)
    };
    let casting = |technique: &dyn ShadowTechnique| {
        compute_setup(technique, &camera, &light, &scene, settings)
    };
    let run = || -> Result<ShadowSetup, SetupError> {
        match *name {
            "lispsm_directional" => casting(&Lispsm::default()),
            "lispsm_directional_given_samples" => given(&Lispsm::default()),
            "cascades_4_lispsm_directional_given_samples" => given(&Cascades::default()),
            "cascades_adaptive_directional_given_samples" => given(&adaptive_cascades()),
            "cascades_4_stable_directional" => casting(&Cascades {
                stable: true,
                ..Cascades::default()
            }),
            "sppsm_directional" | "street_sppsm" => casting(&Sppsm::default()),
            "street_lispsm" => casting(&Lispsm::default()),
            "cube_point_given_samples" | "cube_point_over_city_given_samples" => given(&Cube),
            _ => casting(&Focused),
        }
    };
    for _ in 0..iterations {
        if let Err(e) = black_box(run()) {
            eprintln!("setup_loop: {name}: {e}");
            return ExitCode::from(2);
        }
    }
    ExitCode::SUCCESS
}
