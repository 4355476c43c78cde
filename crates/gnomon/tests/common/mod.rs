//! The LiSPSM paper's ideal configuration (section 4.3), shared by the tests that measure
//! perspective aliasing from a technique's matrix: directional light perpendicular to the
//! view, z_n = 1, z_f = 100, the scene box = the view frustum's box.

#![allow(dead_code)]

use glam::DVec3;
use gnomon::analysis::IdealConfiguration;
use gnomon::{Light, MapSettings, ShadowMap, ShadowTechnique, SpotLight, compute_setup};

pub const Z_N: f64 = 1.0;
pub const Z_F: f64 = 100.0;

/// The paper's ideal configuration for z_n = 1, z_f = 100.
pub fn ideal() -> IdealConfiguration {
    IdealConfiguration::new(Z_N, Z_F, 90.0).unwrap()
}

/// The technique's map in the ideal configuration (asserting that no fallback fired).
pub fn ideal_map(technique: &dyn ShadowTechnique) -> ShadowMap {
    ideal_map_lit_by(technique, &ideal().light().unwrap())
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
    map_in(&ideal(), technique, light)
}

/// The technique's map in `config` under `light` (asserting that no fallback fired).
pub fn map_in(
    config: &IdealConfiguration,
    technique: &dyn ShadowTechnique,
    light: &Light,
) -> ShadowMap {
    let setup = compute_setup(
        technique,
        &config.camera().unwrap(),
        light,
        &config.scene().unwrap(),
        MapSettings::with_resolution(1024),
    )
    .unwrap();
    assert_eq!(setup.fallback(), None);
    setup.maps[0]
}

/// dp/ds = (z_n / z) dz/ds at z in the ideal configuration.
pub fn dp_ds(map: &ShadowMap, z: f64) -> f64 {
    gnomon::analysis::view_axis_dp_ds(map, &ideal(), z).unwrap()
}

/// Whether `value` is within the relative `tolerance` of `expected`.
pub fn within(value: f64, expected: f64, tolerance: f64) -> bool {
    (value / expected - 1.0).abs() <= tolerance
}
