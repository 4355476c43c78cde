//! The scene, camera and lights of the setup benches, shared by `benches/setup.rs` (criterion)
//! and `examples/setup_loop.rs` (instruction counts, `scripts/setup-instructions.sh`), so that
//! both measure the same setups.

#![allow(dead_code)]

use glam::DVec3;
use gnomon::{
    Aabb, Camera, Cascades, DirectionalLight, Lens, Light, PointLight, SceneBounds, SpotLight,
};

/// A 400 m city of `n` boxes on a grid, 2 to 40 m tall, on a ground slab: casters, and also
/// receivers when `boxes_receive`.
pub fn city(n: usize, boxes_receive: bool) -> SceneBounds {
    let side = (n as f64).sqrt().ceil() as usize;
    let pitch = 380.0 / side as f64;
    let mut boxes = Vec::with_capacity(n);
    for k in 0..n {
        let (i, j) = ((k % side) as f64, (k / side) as f64);
        let h = 2.0 + ((k * 7919) % 38) as f64;
        let min = DVec3::new(-190.0 + i * pitch, 0.0, -190.0 + j * pitch);
        boxes.push(Aabb::new(min, min + DVec3::new(0.6 * pitch, h, 0.6 * pitch)).unwrap());
    }
    let ground = Aabb::new(
        DVec3::new(-200.0, -1.0, -200.0),
        DVec3::new(200.0, 0.0, 200.0),
    )
    .unwrap();
    let mut receivers = if boxes_receive {
        boxes.clone()
    } else {
        Vec::new()
    };
    receivers.push(ground);
    SceneBounds::new(boxes, receivers, None).unwrap()
}

/// The camera over the city's corner, looking across it.
pub fn bench_camera() -> Camera {
    Camera::look_at(
        DVec3::new(-150.0, 30.0, 180.0),
        DVec3::new(20.0, 0.0, -20.0),
        DVec3::Y,
        Lens::default(),
    )
    .unwrap()
}

/// The sun.
pub fn sun() -> Light {
    Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, -0.3)).unwrap())
}

/// A spot light high over the city.
pub fn spot() -> Light {
    Light::Spot(
        SpotLight::new(
            DVec3::new(0.0, 120.0, 100.0),
            DVec3::new(0.0, -1.0, -0.8),
            45.0,
            400.0,
        )
        .unwrap(),
    )
}

/// A lamp among the buildings, in the camera's view: `range` 250 m lights most of the city,
/// 40 m is a street lamp's reach.
pub fn lamp(range: f64) -> Light {
    Light::Point(PointLight::new(DVec3::new(-40.0, 10.0, 60.0), range).unwrap())
}

/// A lamp 20 m over the city's tallest buildings (outside the scene box, where each cube
/// face builds its B).
pub fn lamp_over_city() -> Light {
    Light::Point(PointLight::new(DVec3::new(-40.0, 60.0, 60.0), 250.0).unwrap())
}

/// compare's `cascades-best`: 1 to 4 LiSPSM cascades chosen per view, at one map's texels,
/// no blend band.
pub fn adaptive_cascades() -> Cascades {
    Cascades {
        adaptive: true,
        equal_texels: true,
        blend: 0.0,
        ..Cascades::default()
    }
}
