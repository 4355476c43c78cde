//! What each map of a setup says of itself: a cascade's view-depth range, and which map fell
//! back (per-map diagnostics), over many cameras and lights.

use glam::DVec3;
use gnomon::{
    Aabb, Camera, CascadeFit, Cascades, Cube, DirectionalLight, Fallback, Focused, Lens, Light,
    Lispsm, MapProjection, MapSelection, MapSettings, PointLight, SceneBounds, ShadowSetup,
    ShadowTechnique, Sppsm, compute_setup,
};
use proptest::prelude::*;

/// A ground with a row of towers: near ones and far ones, so that slices see different things.
fn city() -> SceneBounds {
    let ground = Aabb::new(
        DVec3::new(-600.0, -1.0, -600.0),
        DVec3::new(600.0, 0.0, 600.0),
    )
    .unwrap();
    let mut casters = Vec::new();
    for i in 0..12 {
        let min = DVec3::new(-150.0 + 30.0 * i as f64, 0.0, -20.0 - 30.0 * i as f64);
        casters.push(Aabb::new(min, min + DVec3::new(8.0, 10.0 + 4.0 * i as f64, 8.0)).unwrap());
    }
    let mut receivers = casters.clone();
    receivers.push(ground);
    SceneBounds::new(casters, receivers, None).unwrap()
}

fn camera(eye: DVec3, yaw: f64, pitch: f64, near: f64) -> Camera {
    let forward = DVec3::new(
        yaw.sin() * pitch.cos(),
        pitch.sin(),
        -yaw.cos() * pitch.cos(),
    );
    let lens = Lens {
        fov_y_degrees: 60.0,
        aspect: 16.0 / 9.0,
        near,
        far: 400.0,
    };
    Camera::look_at(eye, eye + forward, DVec3::Y, lens).unwrap()
}

fn sun(azimuth: f64, elevation: f64) -> Light {
    let d = DVec3::new(
        azimuth.cos() * elevation.cos(),
        -elevation.sin(),
        azimuth.sin() * elevation.cos(),
    );
    Light::Directional(DirectionalLight::new(d).unwrap())
}

fn set(fallbacks: &[Fallback]) -> Vec<&'static str> {
    let mut names: Vec<&str> = fallbacks.iter().map(|f| f.name()).collect();
    names.sort_unstable();
    names.dedup();
    names
}

/// Every map has its own diagnostics, and together they name exactly the setup's fallbacks.
fn check_per_map(setup: &ShadowSetup) {
    let n = setup.maps.len();
    let own: Vec<_> = (0..n).map(|i| setup.map_diagnostics(i)).collect();
    let union: Vec<Fallback> = own.iter().flat_map(|d| d.fallbacks.clone()).collect();
    assert_eq!(set(&union), set(&setup.diagnostics.fallbacks));
    if n > 1 {
        assert_eq!(setup.diagnostics.maps.len(), n);
    }
    // The setup's warp strength is the weakest of its maps'.
    let weakest = own
        .iter()
        .filter_map(|d| d.warp_strength)
        .min_by(f64::total_cmp);
    assert_eq!(weakest, setup.diagnostics.warp_strength);
}

/// A cascade map serves its slice and the blend band before it; a point's view depth reads a
/// map whose range holds it; the ranges tile z_0 to z_count with overlaps only at the bands.
fn check_ranges(setup: &ShadowSetup, blend: f64) {
    let MapSelection::Cascades(slices) = setup.selection else {
        panic!("not cascades");
    };
    let z = slices.depths();
    for (i, map) in setup.maps.iter().enumerate() {
        let [near, far] = map.view_depth_range.expect("a cascade map has its range");
        let band = if i == 0 {
            0.0
        } else {
            blend * (z[i] - z[i - 1])
        };
        assert!((near - (z[i] - band)).abs() <= 1e-9 * z[i].max(1.0), "{i}");
        assert_eq!(far, z[i + 1], "{i}");
    }
    for t in 0..=200 {
        let depth = (z[0] + (z[slices.count] - z[0]) * t as f64 / 200.0).min(z[slices.count]);
        let [near, far] = setup.maps[slices.slice_of(depth)].view_depth_range.unwrap();
        assert!(
            near <= depth && depth <= far,
            "{depth} read outside {near}..{far}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn cascades_say_their_depths_and_which_map_fell_back(
        x in -200.0..200.0f64,
        height in 1.5..120.0f64,
        yaw in -3.1..3.1f64,
        pitch in -0.9..0.3f64,
        near in prop::sample::select(vec![0.1, 0.5, 2.0]),
        azimuth in 0.0..std::f64::consts::TAU,
        // Grazing suns are drawn on purpose: their far slices fall back most.
        elevation in prop::sample::select(vec![0.05, 0.2, 0.6, 1.2, 1.55]),
        count in 1usize..=6,
        blend in prop::sample::select(vec![0.0, 0.1, 0.3]),
        stable in any::<bool>(),
    ) {
        let cascades = Cascades {
            count,
            blend,
            stable,
            fit: CascadeFit::Lispsm(Lispsm::default()),
            ..Cascades::default()
        };
        let camera = camera(DVec3::new(x, height, 50.0), yaw, pitch, near);
        let setup = compute_setup(
            &cascades,
            &camera,
            &sun(azimuth, elevation),
            &city(),
            MapSettings::with_resolution(1024),
        )
        .unwrap();
        check_per_map(&setup);
        check_ranges(&setup, blend);
        if !stable {
            check_warp_matches_fallbacks(&setup);
        }
    }
}

/// A fitted LiSPSM cascade's own diagnostics say what its map is: the focused (orthographic)
/// map where the warp was coarser than it, the full perspective warp where nothing fell back.
fn check_warp_matches_fallbacks(setup: &ShadowSetup) {
    for (i, map) in setup.maps.iter().enumerate() {
        let own = setup.map_diagnostics(i);
        if own.fallbacks.contains(&Fallback::WarpCoarserThanFocused) {
            assert_eq!(map.projection, MapProjection::Orthographic, "map {i}");
            assert_eq!(own.warp_strength, Some(0.0), "map {i}");
        }
        if own.fallbacks.is_empty() {
            assert_eq!(map.projection, MapProjection::Perspective, "map {i}");
            // Full strength, or unjudged where no view sample fell in the slice.
            assert!(matches!(own.warp_strength, None | Some(1.0)), "map {i}");
        }
    }
}

#[test]
fn a_cascade_that_fell_back_is_told_apart_from_one_that_did_not() {
    // Street-level views under a low sun: near slices see little, the far ones much.
    let mut mixed = 0;
    for yaw in [-2.5, -1.5, -0.5, 0.5, 1.5, 2.5] {
        for elevation in [0.1, 0.3, 0.8] {
            let camera = camera(DVec3::new(0.0, 1.7, 60.0), yaw, -0.05, 0.5);
            let setup = compute_setup(
                &Cascades::default(),
                &camera,
                &sun(0.7, elevation),
                &city(),
                MapSettings::with_resolution(2048),
            )
            .unwrap();
            check_warp_matches_fallbacks(&setup);
            let own: Vec<_> = (0..setup.maps.len())
                .map(|i| setup.map_diagnostics(i).fallbacks)
                .collect();
            mixed += usize::from(own.iter().any(|f| f != &own[0]));
        }
    }
    assert!(mixed > 0, "no view had cascades that differ");
}

#[test]
fn a_single_map_has_no_depth_range_and_the_setups_diagnostics() {
    let camera = camera(DVec3::new(0.0, 2.0, 50.0), 0.3, -0.1, 0.5);
    for technique in [&Focused as &dyn ShadowTechnique, &Lispsm::default()] {
        for elevation in [0.05, 0.6, 1.55] {
            let setup = compute_setup(
                technique,
                &camera,
                &sun(0.4, elevation),
                &city(),
                MapSettings::default(),
            )
            .unwrap();
            assert_eq!(setup.maps.len(), 1);
            assert_eq!(setup.maps[0].view_depth_range, None);
            let own = setup.map_diagnostics(0);
            assert_eq!(own.fallbacks, setup.diagnostics.fallbacks);
            assert_eq!(own.warp_strength, setup.diagnostics.warp_strength);
        }
    }
}

#[test]
fn cube_faces_and_sppsm_maps_each_have_diagnostics() {
    // A lamp among the towers, seen from above: several faces have something to shadow.
    let camera = camera(DVec3::new(0.0, 60.0, 0.0), 0.0, -0.6, 0.5);
    let lamp = Light::Point(PointLight::new(DVec3::new(0.0, 8.0, -170.0), 300.0).unwrap());
    let setups = [
        compute_setup(&Cube, &camera, &lamp, &city(), MapSettings::default()).unwrap(),
        compute_setup(
            &Lispsm::default(),
            &camera,
            &lamp,
            &city(),
            MapSettings::default(),
        )
        .unwrap(),
        compute_setup(
            &Sppsm::default(),
            &camera,
            &sun(0.4, 0.3),
            &city(),
            MapSettings::default(),
        )
        .unwrap(),
    ];
    for setup in &setups {
        assert!(setup.maps.len() > 1, "{}", setup.technique);
        assert!(setup.maps.iter().all(|m| m.view_depth_range.is_none()));
        check_per_map(setup);
    }
}
