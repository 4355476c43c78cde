//! PSM measured from its matrix in the LiSPSM paper's ideal configuration (light
//! perpendicular to the view, z_n = 1, z_f = 100, scene box = the frustum's box): with no
//! slide the perspective aliasing error follows the PSM line z (z_f - z_n) / z_f (LiSPSM
//! paper, 4.3); with the default slide sqrt(z_n z_f) the virtual eye sits at n_opt and the
//! error is 9.9 at both z_n and z_f.

mod common;

use common::{Z_F, Z_N, distant_spot, dp_ds, ideal_map, ideal_map_lit_by, within};
use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, MapSettings, Psm, SceneBounds, compute_setup,
};

#[test]
fn no_slide_gives_the_psm_line() {
    let map = ideal_map(&Psm {
        slide_back: Some(0.0),
        limit: false,
    });
    for i in 0..=100 {
        let z = Z_N * (Z_F / Z_N).powf(i as f64 / 100.0);
        let expected = z * (Z_F - Z_N) / Z_F;
        let value = dp_ds(&map, z);
        assert!(
            within(value, expected, 0.03),
            "z = {z}: {value} vs PSM line {expected}"
        );
    }
}

#[test]
fn default_slide_equalises_near_and_far_like_lispsm() {
    let map = ideal_map(&Psm::default());
    let (near, far) = (dp_ds(&map, Z_N), dp_ds(&map, Z_F));
    println!("PSM, default slide: dp/ds(z_n) = {near:.4}, dp/ds(z_f) = {far:.4}");
    assert!(within(near, far, 0.02));
    assert!(within(near, 9.9, 0.03));
}

/// A spot light becomes a point light in PPS (Stamminger and Drettakis's point-light case);
/// one practically at infinity gives the directional light's numbers.
#[test]
fn distant_spot_light_gives_the_directional_numbers() {
    let map = ideal_map_lit_by(&Psm::default(), &distant_spot());
    let (near, far) = (dp_ds(&map, Z_N), dp_ds(&map, Z_F));
    println!("PSM, default slide, distant spot: dp/ds(z_n) = {near:.4}, dp/ds(z_f) = {far:.4}");
    assert!(within(near, far, 0.02));
    assert!(within(near, 9.9, 0.03));
}

#[test]
fn bad_slide_is_a_typed_error() {
    let camera = Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, Lens::default()).unwrap();
    let b = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0)).unwrap();
    let scene = SceneBounds::new(vec![b], vec![b], None).unwrap();
    let light = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
    for s in [-1.0, f64::NAN, f64::INFINITY] {
        let r = compute_setup(
            &Psm {
                slide_back: Some(s),
                limit: false,
            },
            &camera,
            &light,
            &scene,
            MapSettings::default(),
        );
        assert!(
            matches!(r, Err(gnomon::SetupError::InvalidParameter { .. })),
            "slide {s}: {r:?}"
        );
    }
}
