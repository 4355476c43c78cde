//! PSM measured from its matrix in the LiSPSM paper's ideal configuration (light
//! perpendicular to the view, z_n = 1, z_f = 100, scene box = the frustum's box): with no
//! slide the perspective aliasing error follows the PSM line z (z_f - z_n) / z_f (LiSPSM
//! paper, 4.3); with the default slide sqrt(z_n z_f) the virtual eye sits at n_opt and the
//! error is 9.9 at both z_n and z_f.

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, MapSettings, Psm, SceneBounds, ShadowMap,
    compute_setup,
};

const Z_N: f64 = 1.0;
const Z_F: f64 = 100.0;

fn ideal_map(psm: Psm) -> ShadowMap {
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
    let light = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
    let setup = compute_setup(
        &psm,
        &camera,
        &light,
        &scene,
        MapSettings::with_resolution(1024),
    )
    .unwrap();
    assert_eq!(setup.fallback(), None);
    setup.maps[0]
}

/// s of the point at distance z along the view axis: the map coordinate (x or y, whichever
/// runs along the view) normalised to [0, 1].
fn s(map: &ShadowMap, z: f64) -> f64 {
    let a = map.project(DVec3::new(0.0, 0.0, -Z_N)).unwrap();
    let b = map.project(DVec3::new(0.0, 0.0, -Z_F)).unwrap();
    let p = map.project(DVec3::new(0.0, 0.0, -z)).unwrap();
    if (b.x - a.x).abs() > (b.y - a.y).abs() {
        0.5 * (p.x + 1.0)
    } else {
        0.5 * (p.y + 1.0)
    }
}

fn dp_ds(map: &ShadowMap, z: f64) -> f64 {
    let h = 1e-5 * z;
    let (a, b) = ((z - h).max(Z_N), (z + h).min(Z_F));
    (Z_N / z) / ((s(map, b) - s(map, a)) / (b - a)).abs()
}

fn within(value: f64, expected: f64, tolerance: f64) -> bool {
    (value / expected - 1.0).abs() <= tolerance
}

#[test]
fn no_slide_gives_the_psm_line() {
    let map = ideal_map(Psm {
        slide_back: Some(0.0),
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
    let map = ideal_map(Psm::default());
    let (near, far) = (dp_ds(&map, Z_N), dp_ds(&map, Z_F));
    println!("PSM, default slide: dp/ds(z_n) = {near:.4}, dp/ds(z_f) = {far:.4}");
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
