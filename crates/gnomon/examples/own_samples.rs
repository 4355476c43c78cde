//! Handing the core the frame's own view samples: an engine with a depth and normal buffer
//! gives the surface points its pixels see, and the warp limit judges LiSPSM on them instead
//! of on rays cast at the receiver boxes.
//!
//! `cargo run -p gnomon-core --example own_samples`

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, Lispsm, MapSettings, SceneBounds, SetupError,
    ViewSamples, compute_setup_with_samples,
};

fn main() -> Result<(), SetupError> {
    let camera = Camera::look_at(
        DVec3::new(0.0, 3.0, 20.0),
        DVec3::ZERO,
        DVec3::Y,
        Lens::default(),
    )?;
    let light = Light::Directional(DirectionalLight::new(DVec3::new(-0.5, -1.0, -0.3))?);
    let ground = Aabb::new(DVec3::new(-50.0, -0.1, -50.0), DVec3::new(50.0, 0.0, 50.0))?;
    let pillar = Aabb::new(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 6.0, 1.0))?;
    let scene = SceneBounds::new(vec![pillar], vec![ground, pillar], None)?;

    // What the pixels see, as (position, normal): here a grid on the ground, as a readback
    // of the depth and normal buffers would give.
    let points = (0..32).flat_map(|i| {
        (0..16).map(move |j| {
            (
                DVec3::new(-16.0 + i as f64, 0.0, -10.0 + j as f64),
                DVec3::Y,
            )
        })
    });
    let own = ViewSamples::from_surface_points(&camera, &light, points);
    // What the core casts at the receiver boxes when no samples are handed in.
    let boxes = ViewSamples::new(&camera, &light, &scene);
    for (name, samples) in [("own samples", &own), ("box samples", &boxes)] {
        let setup = compute_setup_with_samples(
            &Lispsm::default(),
            &camera,
            &light,
            &scene,
            MapSettings::default(),
            samples,
        )?;
        let fallbacks: Vec<&str> = setup
            .diagnostics
            .fallbacks
            .iter()
            .map(|f| f.name())
            .collect();
        println!(
            "{name}: {} samples judged, warp strength {:?}, fallbacks {fallbacks:?}",
            samples.len(),
            setup.diagnostics.warp_strength,
        );
    }
    Ok(())
}
