//! The LiSPSM paper's ideal configuration (section 4.3), shared by the tests that measure
//! perspective aliasing from a technique's matrix: directional light perpendicular to the
//! view, z_n = 1, z_f = 100, the scene box = the view frustum's box.

#![allow(dead_code)]

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, MapSettings, SceneBounds, ShadowMap,
    ShadowTechnique, SpotLight, compute_setup,
};

pub const Z_N: f64 = 1.0;
pub const Z_F: f64 = 100.0;

/// The technique's map in the ideal configuration (asserting that no fallback fired).
pub fn ideal_map(technique: &dyn ShadowTechnique) -> ShadowMap {
    let light = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
    ideal_map_lit_by(technique, &light)
}

/// A spot light so far above the ideal configuration (10^5 units, a cone of a few
/// hundredths of a degree around the frustum's box) that it is practically the directional
/// light straight down.
pub fn distant_spot() -> Light {
    let height = 1e5;
    Light::Spot(
        SpotLight::new(
            DVec3::new(0.0, height, -0.5 * (Z_N + Z_F)),
            -DVec3::Y,
            (100.0f64 / height).atan().to_degrees(),
            height + 100.0,
        )
        .unwrap(),
    )
}

/// The technique's map in the ideal configuration under `light` (asserting that no fallback
/// fired).
pub fn ideal_map_lit_by(technique: &dyn ShadowTechnique, light: &Light) -> ShadowMap {
    let lens = Lens {
        fov_y_degrees: 60.0,
        aspect: 1.0,
        near: Z_N,
        far: Z_F,
    };
    let camera = Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, lens).unwrap();
    let corners = camera.frustum_corners();
    let min = corners.iter().copied().reduce(DVec3::min).unwrap();
    let max = corners.iter().copied().reduce(DVec3::max).unwrap();
    let frustum_box = Aabb::new(min, max).unwrap();
    let scene = SceneBounds::new(vec![frustum_box], vec![frustum_box], Some(frustum_box)).unwrap();
    let setup = compute_setup(
        technique,
        &camera,
        light,
        &scene,
        MapSettings::with_resolution(1024),
    )
    .unwrap();
    assert_eq!(setup.fallback(), None);
    setup.maps[0]
}

/// s of the point at distance z along the view axis: the map coordinate (x or y, whichever
/// runs along the view) normalised to [0, 1].
pub fn s(map: &ShadowMap, z: f64) -> f64 {
    let a = map.project(DVec3::new(0.0, 0.0, -Z_N)).unwrap();
    let b = map.project(DVec3::new(0.0, 0.0, -Z_F)).unwrap();
    let p = map.project(DVec3::new(0.0, 0.0, -z)).unwrap();
    if (b.x - a.x).abs() > (b.y - a.y).abs() {
        0.5 * (p.x + 1.0)
    } else {
        0.5 * (p.y + 1.0)
    }
}

/// dp/ds = (z_n / z) dz/ds at z, by central differences (one-sided at the ends).
pub fn dp_ds(map: &ShadowMap, z: f64) -> f64 {
    let h = 1e-5 * z;
    let (a, b) = ((z - h).max(Z_N), (z + h).min(Z_F));
    (Z_N / z) / ((s(map, b) - s(map, a)) / (b - a)).abs()
}

/// Whether `value` is within the relative `tolerance` of `expected`.
pub fn within(value: f64, expected: f64, tolerance: f64) -> bool {
    (value / expected - 1.0).abs() <= tolerance
}
