//! Four LiSPSM cascades over a street of towers: prints each cascade's view depths, its
//! projection, its fallbacks and which map a few points read.
//!
//! `cargo run -p gnomon-core --example cascades`

use glam::DVec3;
use gnomon::{
    Aabb, Camera, Cascades, DirectionalLight, Lens, Light, MapSettings, SceneBounds, SetupError,
    compute_setup,
};

fn main() -> Result<(), SetupError> {
    let lens = Lens {
        near: 0.5,
        far: 300.0,
        ..Lens::default()
    };
    let eye = DVec3::new(0.0, 1.7, 0.0);
    let camera = Camera::look_at(eye, DVec3::new(0.0, 1.0, -100.0), DVec3::Y, lens)?;
    let light = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -0.6, -0.4))?);
    let ground = Aabb::new(
        DVec3::new(-500.0, -1.0, -500.0),
        DVec3::new(500.0, 0.0, 500.0),
    )?;
    let towers = (0..20)
        .map(|i| {
            let min = DVec3::new(-40.0 + 4.0 * i as f64, 0.0, -10.0 - 15.0 * i as f64);
            Aabb::new(min, min + DVec3::new(3.0, 12.0, 3.0))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut receivers = towers.clone();
    receivers.push(ground);
    let scene = SceneBounds::new(towers, receivers, None)?;

    let setup = compute_setup(
        &Cascades::default(),
        &camera,
        &light,
        &scene,
        MapSettings::with_resolution(2048),
    )?;
    for (i, map) in setup.maps.iter().enumerate() {
        let [near, far] = map
            .view_depth_range
            .expect("a cascade serves a range of view depths");
        let own = setup.map_diagnostics(i);
        let fallbacks: Vec<&str> = own.fallbacks.iter().map(|f| f.name()).collect();
        println!(
            "cascade {i}: view depths {near:.1} to {far:.1}, {:?}, fallbacks [{}]",
            map.projection,
            fallbacks.join(", ")
        );
    }
    // A point reads the map its view depth picks; a point outside every map reads as lit.
    for z in [-5.0, -40.0, -120.0, -280.0] {
        let p = DVec3::new(0.0, 0.0, z);
        match setup.map_for(p) {
            Some(i) => println!("the ground at z = {z} reads cascade {i}"),
            None => println!("the ground at z = {z} reads no map: lit"),
        }
    }
    Ok(())
}
