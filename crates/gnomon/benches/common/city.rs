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

/// Grid pitch of [`street_city`] in metres: 9 m blocks and 6 m streets.
const STREET_PITCH: f64 = 15.0;

/// A city of `n` boxes that grows outward on a fixed 15 m grid (its side grows as sqrt(n)),
/// casters and receivers, on a ground slab under it all. Seen by [`street_camera`], whose far
/// plane stays inside the city from 10^3 boxes on, the part the camera sees and the casters
/// up-sun of it are the same at every size: setup time should not grow with `n`.
pub fn street_city(n: usize) -> SceneBounds {
    let side = (n as f64).sqrt().ceil() as usize;
    let first = -((side / 2) as f64);
    let mut boxes = Vec::with_capacity(n);
    for k in 0..n {
        let i = first + (k % side) as f64;
        let j = first + (k / side) as f64;
        let h = 2.0 + ((k * 7919) % 38) as f64;
        let min = DVec3::new(i * STREET_PITCH, 0.0, j * STREET_PITCH);
        let size = DVec3::new(0.6 * STREET_PITCH, h, 0.6 * STREET_PITCH);
        boxes.push(Aabb::new(min, min + size).unwrap());
    }
    let half = (side as f64 / 2.0 + 1.0) * STREET_PITCH;
    let ground = Aabb::new(DVec3::new(-half, -1.0, -half), DVec3::new(half, 0.0, half)).unwrap();
    let mut receivers = boxes.clone();
    receivers.push(ground);
    SceneBounds::new(boxes, receivers, None).unwrap()
}

/// A pedestrian's camera in a street of [`street_city`], looking along it; far plane 150 m.
pub fn street_camera() -> Camera {
    let x = 0.8 * STREET_PITCH;
    Camera::look_at(
        DVec3::new(x, 1.7, 0.0),
        DVec3::new(x, 1.0, -100.0),
        DVec3::Y,
        Lens {
            near: 0.5,
            far: 150.0,
            ..Lens::default()
        },
    )
    .unwrap()
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
