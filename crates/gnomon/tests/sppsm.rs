//! SPPSM's theorem (Mikkelsen 2007, sections 3 and 5), numerically, over random cameras,
//! lights and scenes: the separating plane contains the light's eye point (a directional
//! light's direction lies in it); on the plane both maps cover a screen pixel with the same
//! area of texels, |det J| (relative 1e-3); off it, the side picks the map with the larger
//! |det J|. J is the Jacobian of a map's unnormalised texel coordinates by the screen
//! coordinates (s, t) at a fixed screen depth, as in the paper's section 3.1, measured by
//! finite differences of the camera's and the map's matrices (not by the formula the plane
//! comes from).

use glam::{DVec2, DVec3, DVec4};
use gnomon::{
    Aabb, Camera, DirectionalLight, Fallback, Lens, Light, Lispsm, MapSelection, MapSettings,
    PerspectiveMap, Psm, SceneBounds, SetupError, ShadowMap, ShadowSetup, ShadowTechnique,
    SpotLight, Sppsm, Tsm, Xpsm, compute_setup,
};
use proptest::prelude::*;
use proptest::test_runner::{RngAlgorithm, TestRng};

struct Config {
    camera: Camera,
    light: Light,
    scene: SceneBounds,
}

fn unit(rng: &mut TestRng) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if (0.1..=1.0).contains(&v.length()) {
            return v.normalize();
        }
    }
}

/// A 100 m scene of boxes on a ground slab, a camera above it looking into it, a sun or a
/// spot light.
fn config(seed: u64, spot: bool) -> Config {
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed.to_le_bytes().repeat(4));
    let mut casters = Vec::new();
    for _ in 0..12 {
        let c = DVec3::new(
            rng.random_range(-45.0..45.0),
            0.0,
            rng.random_range(-45.0..45.0),
        );
        let h = DVec3::new(
            rng.random_range(0.5..5.0),
            rng.random_range(1.0..15.0),
            rng.random_range(0.5..5.0),
        );
        casters.push(Aabb::new(c - h.with_y(0.0), c + h).unwrap());
    }
    let ground = Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
    let mut receivers = casters.clone();
    receivers.push(ground);
    let scene = SceneBounds::new(casters, receivers, None).unwrap();
    let eye = DVec3::new(
        rng.random_range(-60.0..60.0),
        rng.random_range(2.0..40.0),
        rng.random_range(-60.0..60.0),
    );
    let target = DVec3::new(
        rng.random_range(-30.0..30.0),
        0.0,
        rng.random_range(-30.0..30.0),
    );
    let lens = Lens {
        fov_y_degrees: 60.0,
        aspect: 1.5,
        near: rng.random_range(0.2..2.0),
        far: 250.0,
    };
    let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
    let mut d = unit(&mut rng);
    if d.y > -0.2 {
        d.y = -d.y.abs() - 0.2;
    }
    let light = if spot {
        let position = DVec3::new(
            rng.random_range(-40.0..40.0),
            rng.random_range(30.0..70.0),
            rng.random_range(-40.0..40.0),
        );
        let toward = (target - position).normalize();
        Light::Spot(SpotLight::new(position, toward, 60.0, 300.0).unwrap())
    } else {
        Light::Directional(DirectionalLight::new(d).unwrap())
    };
    Config {
        camera,
        light,
        scene,
    }
}

/// |det J| of `map` at the point with screen coordinates (s, t) and screen depth q, J by
/// central differences in s and t at fixed q; `None` where the map does not see the point.
fn screen_det_j(map: &ShadowMap, camera: &Camera, s: f64, t: f64, q: f64) -> Option<f64> {
    let world_from_clip = camera.clip_from_world().inverse();
    let texel = |s: f64, t: f64| {
        let p: DVec4 = world_from_clip * DVec4::new(s, t, q, 1.0);
        let clip = map.clip_from_world * (p.truncate() / p.w).extend(1.0);
        (clip.w > 0.0).then(|| clip.truncate().truncate() / clip.w * 0.5 * map.resolution as f64)
    };
    // Fourth-order central differences: the warped maps bend strongly near their centres of
    // projection, where a second-order difference is off by a percent at h = 1e-4.
    let h = 1e-5;
    let d = |f: &dyn Fn(f64) -> Option<DVec2>| -> Option<DVec2> {
        Some((f(-2.0 * h)? - 8.0 * f(-h)? + 8.0 * f(h)? - f(2.0 * h)?) / (12.0 * h))
    };
    let ds = d(&|e| texel(s + e, t))?;
    let dt = d(&|e| texel(s, t + e))?;
    Some((ds.x * dt.y - ds.y * dt.x).abs())
}

/// Whether the light's maps cover `p`: inside a spot light's cone beyond its near plane
/// (nearer, or far to the side, its projection is singular or ill-conditioned, and no map
/// holds the point); anywhere for a sun.
fn lit_region(light: &Light, p: DVec3) -> bool {
    match light {
        Light::Directional(_) => true,
        Light::Spot(s) => {
            let q = p - s.position();
            let along = s.direction().dot(q);
            along >= s.near() && along >= q.length() * s.half_angle().cos()
        }
        Light::Point(_) => unreachable!("SPPSM refuses point lights"),
    }
}

/// Screen coordinates (s, t, q) of a world point.
fn screen(camera: &Camera, p: DVec3) -> Option<DVec3> {
    let c = camera.clip_from_world() * p.extend(1.0);
    (c.w > 0.0).then(|| c.truncate() / c.w)
}

/// The configuration's setup for `technique`, with 1024x1024 maps.
fn setup_with(cfg: &Config, technique: &dyn ShadowTechnique) -> ShadowSetup {
    compute_setup(
        technique,
        &cfg.camera,
        &cfg.light,
        &cfg.scene,
        MapSettings::with_resolution(1024),
    )
    .unwrap()
}

/// Of `tries` random points of the scene box, those the camera sees and the light's maps
/// cover.
fn visible_points(cfg: &Config, rng: &mut TestRng, tries: usize) -> Vec<DVec3> {
    let (lo, hi) = (cfg.scene.scene_box().min(), cfg.scene.scene_box().max());
    (0..tries)
        .map(|_| {
            DVec3::new(
                rng.random_range(lo.x..hi.x),
                rng.random_range(lo.y..hi.y),
                rng.random_range(lo.z..hi.z),
            )
        })
        .filter(|p| {
            screen(&cfg.camera, *p)
                .is_some_and(|c| c.x.abs() < 1.0 && c.y.abs() < 1.0 && (0.0..1.0).contains(&c.z))
                && lit_region(&cfg.light, *p)
        })
        .collect()
}

fn check(seed: u64, spot: bool, perspective: PerspectiveMap) -> Result<bool, String> {
    let cfg = config(seed, spot);
    let technique = Sppsm {
        perspective,
        iterations: 1,
    };
    let setup = compute_setup(
        &technique,
        &cfg.camera,
        &cfg.light,
        &cfg.scene,
        MapSettings::with_resolution(1024),
    )
    .map_err(|e| e.to_string())?;
    let MapSelection::Plane { plane_world: plane } = setup.selection else {
        return Ok(false);
    };
    let n = plane.truncate();
    // The plane contains the light's eye point.
    match &cfg.light {
        Light::Directional(d) => {
            let along = n.dot(d.direction()).abs();
            if along > 1e-9 {
                return Err(format!("light direction leaves the plane: n.d = {along}"));
            }
        }
        Light::Spot(s) => {
            let off = (n.dot(s.position()) + plane.w).abs();
            if off > 1e-7 * s.position().length().max(1.0) {
                return Err(format!("light position off the plane by {off}"));
            }
        }
        Light::Point(_) => unreachable!("SPPSM refuses point lights"),
    }
    let (focused, perspective) = (&setup.maps[0], &setup.maps[1]);
    let mut rng = TestRng::from_seed(
        RngAlgorithm::ChaCha,
        &(seed ^ 0x5eed).to_le_bytes().repeat(4),
    );
    let scene_box = cfg.scene.scene_box();
    let (mut on_plane, mut off_plane) = (0, 0);
    for _ in 0..400 {
        // A random visible point in the scene box.
        let (lo, hi) = (scene_box.min(), scene_box.max());
        let p = DVec3::new(
            rng.random_range(lo.x..hi.x),
            rng.random_range(lo.y..hi.y),
            rng.random_range(lo.z..hi.z),
        );
        let Some(c) = screen(&cfg.camera, p) else {
            continue;
        };
        if !(c.x.abs() < 0.95 && c.y.abs() < 0.95 && (0.0..0.999).contains(&c.z)) {
            continue;
        }
        let (s, t, q) = (c.x, c.y, c.z);
        if !lit_region(&cfg.light, p) {
            continue;
        }
        let side = n.dot(p) + plane.w;
        let (Some(f), Some(pp)) = (
            screen_det_j(focused, &cfg.camera, s, t, q),
            screen_det_j(perspective, &cfg.camera, s, t, q),
        ) else {
            continue;
        };
        // The side picks the larger |det J| (ties within round-off allowed).
        let tie = (f - pp).abs() <= 1e-5 * f.max(pp);
        if !tie && (side > 0.0) != (pp > f) {
            return Err(format!(
                "at {p} (side {side}): |det J| focused {f}, perspective {pp}"
            ));
        }
        off_plane += 1;
        // The same point moved onto the plane (along the plane's normal): equal |det J|.
        let on = p - n * side;
        if let Some(c) = screen(&cfg.camera, on)
            && lit_region(&cfg.light, on)
            && c.x.abs() < 1.0
            && c.y.abs() < 1.0
            && (0.0..1.0).contains(&c.z)
            && let (Some(f), Some(pp)) = (
                screen_det_j(focused, &cfg.camera, c.x, c.y, c.z),
                screen_det_j(perspective, &cfg.camera, c.x, c.y, c.z),
            )
        {
            let relative = (f / pp - 1.0).abs();
            if relative > 1e-3 {
                return Err(format!(
                    "on the plane at {on}: |det J| focused {f}, perspective {pp} ({relative})"
                ));
            }
            on_plane += 1;
        }
    }
    if off_plane < 20 || on_plane < 5 {
        return Ok(false);
    }
    Ok(true)
}

fn perspective_maps() -> [PerspectiveMap; 4] {
    [
        PerspectiveMap::Psm(Psm::default()),
        PerspectiveMap::Lispsm(Lispsm::default()),
        PerspectiveMap::Tsm(Tsm::default()),
        PerspectiveMap::Xpsm(Xpsm::default()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 150, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn the_plane_separates_the_better_map(seed in any::<u64>(), spot in any::<bool>(), which in 0usize..4) {
        if let Err(e) = check(seed, spot, perspective_maps()[which]) {
            prop_assert!(false, "seed {seed}, spot {spot}, {}: {e}", perspective_maps()[which].name());
        }
    }
}

/// The property test above is not vacuous: most configurations get a plane that is checked
/// at many points, for every perspective map (TSM and XPSM under suns only: their warps are
/// for directional lights). A configuration without a plane passes the property silently;
/// this count keeps those few.
#[test]
fn most_configurations_get_a_checked_plane() {
    for perspective in perspective_maps() {
        for spot in [false, true] {
            let warps_spots = matches!(
                perspective,
                PerspectiveMap::Psm(_) | PerspectiveMap::Lispsm(_)
            );
            if spot && !warps_spots {
                continue;
            }
            let checked = (0..60u64)
                .filter(|seed| check(*seed, spot, perspective).unwrap())
                .count();
            println!(
                "{} (spot {spot}): {checked} of 60 configurations checked",
                perspective.name()
            );
            // Every perspective map warps in most views (TSM too: its default projection
            // point balances the ends of the view; the 80% rule at 80% of the depth often gave
            // parallel sides, no plane).
            let least = 45;
            assert!(
                checked > least,
                "{} (spot {spot}): {checked} of 60",
                perspective.name()
            );
        }
    }
}

#[test]
fn undefined_planes_fall_back_to_the_focused_map() {
    // The view along the light: every warp falls back, so the plane is undefined.
    let cfg = config(7, false);
    let camera = Camera::look_at(
        DVec3::new(0.0, 80.0, 0.0),
        DVec3::ZERO,
        DVec3::Z,
        cfg.camera.lens(),
    )
    .unwrap();
    let sun = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
    let setup = compute_setup(
        &Sppsm::default(),
        &camera,
        &sun,
        &cfg.scene,
        MapSettings::default(),
    )
    .unwrap();
    assert_eq!(setup.maps.len(), 1);
    assert_eq!(setup.selection, MapSelection::Single);
    assert_eq!(setup.fallback(), Some(Fallback::NoSeparatingPlane));
    // TSM under a spot light: no warp, no plane.
    let cfg = config(3, true);
    let setup = compute_setup(
        &Sppsm {
            perspective: PerspectiveMap::Tsm(Tsm::default()),
            iterations: 10,
        },
        &cfg.camera,
        &cfg.light,
        &cfg.scene,
        MapSettings::default(),
    )
    .unwrap();
    assert_eq!(setup.fallback(), Some(Fallback::NoSeparatingPlane));
    assert!(
        setup
            .diagnostics
            .fallbacks
            .contains(&Fallback::SpotLightNotWarped)
    );
}

#[test]
fn bad_iterations_are_typed_errors() {
    let cfg = config(1, false);
    for iterations in [0, 21] {
        let e = compute_setup(
            &Sppsm {
                iterations,
                ..Sppsm::default()
            },
            &cfg.camera,
            &cfg.light,
            &cfg.scene,
            MapSettings::default(),
        )
        .unwrap_err();
        assert!(matches!(e, SetupError::InvalidParameter { .. }), "{e}");
    }
}

/// Refocusing (section 6): with iterations each map covers less of I than on all of it, and
/// the diagnostics say how the casters fall on the plane.
#[test]
fn iterations_refocus_each_map_on_its_side() {
    let mut tighter = 0;
    for seed in 0..40u64 {
        let cfg = config(seed, false);
        let setup = |iterations| {
            compute_setup(
                &Sppsm {
                    iterations,
                    ..Sppsm::default()
                },
                &cfg.camera,
                &cfg.light,
                &cfg.scene,
                MapSettings::with_resolution(1024),
            )
            .unwrap()
        };
        let (one, ten) = (setup(1), setup(10));
        if one.maps.len() < 2 || ten.maps.len() < 2 {
            continue;
        }
        let sides = ten.diagnostics.casters_by_side.unwrap();
        assert_eq!(
            sides.focused_only + sides.perspective_only + sides.both,
            cfg.scene.casters().len()
        );
        // The focused map's texel area in world units shrinks (more texels per metre).
        let texel_area = |m: &ShadowMap| {
            let l = m.clip_from_world;
            (l.row(0).truncate().cross(l.row(1).truncate())).length()
        };
        if texel_area(&ten.maps[0]) > texel_area(&one.maps[0]) * 1.01 {
            tighter += 1;
        }
    }
    assert!(
        tighter > 10,
        "the focused map got tighter in {tighter} of 40"
    );
}

/// Focused on all of I (one iteration), the two maps are the focused and the perspective
/// technique's own, so each point of I reads a map exactly as fine, in area, as the better
/// of the two techniques alone; refocused (10 iterations), at least as fine. (Refocusing can
/// overshoot and the plane oscillate, as in seed 34: such iterations are not kept.)
#[test]
fn every_point_reads_a_map_as_fine_as_the_better_technique_alone() {
    for iterations in [1, 10] {
        reads_the_better_technique_everywhere(iterations);
    }
}

fn reads_the_better_technique_everywhere(iterations: u32) {
    use gnomon::techniques::ray_area_density;
    let (mut checked, mut coarser) = (0, 0);
    for seed in 0..60u64 {
        let cfg = config(seed, seed % 3 == 0);
        let one = Sppsm {
            iterations,
            ..Sppsm::default()
        };
        let (both, focused, psm) = (
            setup_with(&cfg, &one),
            setup_with(&cfg, &gnomon::Focused),
            // SPPSM's perspective map runs without the warp limit.
            setup_with(
                &cfg,
                &Psm {
                    limit: false,
                    ..Psm::default()
                },
            ),
        );
        if both.maps.len() < 2 {
            continue;
        }
        let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed.to_le_bytes().repeat(4));
        for p in visible_points(&cfg, &mut rng, 300) {
            let density = |m: &ShadowMap| ray_area_density(m, &cfg.light, p);
            let chosen = density(&both.maps[both.map_for(p).unwrap()]);
            let best_alone = density(&focused.maps[0]).max(density(&psm.maps[0]));
            checked += 1;
            if chosen < (1.0 - 1e-9) * best_alone {
                coarser += 1;
            }
        }
    }
    println!(
        "{iterations} iterations: {coarser} of {checked} points coarser than the better \
         technique alone"
    );
    assert!(checked > 2000, "{checked}");
    assert_eq!(coarser, 0, "{coarser} of {checked}");
}

/// Refocused, each map stays at least as fine as its technique's own map on all of I,
/// wherever it is read: the perspective map (cropped to its side, same warp) along every
/// direction, the focused map in area. Checked at random visible points on each side of the
/// plane, for every perspective technique, suns and spot lights.
#[test]
fn refocused_maps_are_no_coarser_than_the_techniques_alone() {
    use gnomon::techniques::ray_area_density;
    // d(ndc.xy)/d(world) applied to v, at p.
    let ndc_derivative = |m: &ShadowMap, p: DVec3, v: DVec3| -> DVec2 {
        let rows = m.clip_from_world;
        let c = rows * p.extend(1.0);
        let d = rows * v.extend(0.0);
        DVec2::new(d.x * c.w - c.x * d.w, d.y * c.w - c.y * d.w) / (c.w * c.w)
    };
    let (mut refocused, mut checked) = (0, 0);
    for seed in 0..60u64 {
        for perspective in perspective_maps() {
            let spot = seed % 3 == 0;
            if spot
                && !matches!(
                    perspective,
                    PerspectiveMap::Psm(_) | PerspectiveMap::Lispsm(_)
                )
            {
                continue;
            }
            let cfg = config(seed, spot);
            let both = setup_with(
                &cfg,
                &Sppsm {
                    perspective,
                    iterations: 10,
                },
            );
            // SPPSM's perspective map runs without the warp limit.
            let alone = match perspective {
                PerspectiveMap::Psm(t) => setup_with(&cfg, &Psm { limit: false, ..t }),
                PerspectiveMap::Lispsm(t) => setup_with(&cfg, &Lispsm { limit: false, ..t }),
                PerspectiveMap::Tsm(t) => setup_with(&cfg, &Tsm { limit: false, ..t }),
                PerspectiveMap::Xpsm(t) => setup_with(&cfg, &Xpsm { limit: false, ..t }),
            };
            let focused = setup_with(&cfg, &gnomon::Focused);
            if both.maps.len() < 2 {
                continue;
            }
            if both.maps[1] != alone.maps[0] {
                refocused += 1;
            }
            let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed.to_le_bytes().repeat(4));
            for p in visible_points(&cfg, &mut rng, 200) {
                checked += 1;
                if both.map_for(p) == Some(1) {
                    let v = unit(&mut rng);
                    let (mine, theirs) = (
                        ndc_derivative(&both.maps[1], p, v).length(),
                        ndc_derivative(&alone.maps[0], p, v).length(),
                    );
                    // (Along the light's rays both are zero up to round-off.)
                    let scale = [DVec3::X, DVec3::Y, DVec3::Z]
                        .map(|axis| ndc_derivative(&alone.maps[0], p, axis).length())
                        .into_iter()
                        .fold(0.0, f64::max);
                    assert!(
                        mine >= theirs * (1.0 - 1e-9) - 1e-9 * scale,
                        "seed {seed}, {}: at {p} along {v}: {mine} < {theirs}",
                        perspective.name()
                    );
                } else {
                    let density = |m: &ShadowMap| ray_area_density(m, &cfg.light, p);
                    let (mine, theirs) = (density(&both.maps[0]), density(&focused.maps[0]));
                    assert!(
                        mine >= theirs * (1.0 - 1e-9),
                        "seed {seed}, {}: at {p}: focused {mine} < {theirs}",
                        perspective.name()
                    );
                }
            }
        }
    }
    println!("{refocused} perspective maps refocused; {checked} points checked");
    assert!(checked > 10_000, "{checked}");
    assert!(refocused > 50, "{refocused}");
}

/// Without a plane because both maps are affine on the light's rays (TSM with parallel sides),
/// one map is finer by the same factor everywhere: SPPSM uses that one alone, whichever it is.
#[test]
fn affine_pairs_use_the_finer_map_alone() {
    use gnomon::techniques::ray_area_density;
    // The 80% rule at 80% of the depth: parallel sides in many views.
    let rule = Tsm {
        xi: -0.6,
        focus: Some(0.8),
        limit: false,
    };
    let (mut focused_chosen, mut tsm_chosen) = (0, 0);
    for seed in 0..200u64 {
        let cfg = config(seed, false);
        let both = setup_with(
            &cfg,
            &Sppsm {
                perspective: PerspectiveMap::Tsm(rule),
                iterations: 10,
            },
        );
        let (focused, tsm) = (setup_with(&cfg, &gnomon::Focused), setup_with(&cfg, &rule));
        if both.fallback() != Some(Fallback::NoSeparatingPlane)
            || !tsm.diagnostics.fallbacks.is_empty()
        {
            continue;
        }
        assert_eq!(both.maps.len(), 1);
        let p = cfg.camera.eye() + cfg.camera.forward() * 20.0;
        let density = |m: &ShadowMap| ray_area_density(m, &cfg.light, p);
        let (chosen, f, t) = (
            density(&both.maps[0]),
            density(&focused.maps[0]),
            density(&tsm.maps[0]),
        );
        assert!(
            chosen >= f.max(t) * (1.0 - 1e-9),
            "seed {seed}: {chosen} < max({f}, {t})"
        );
        if both.maps[0] == tsm.maps[0] {
            tsm_chosen += 1;
        } else {
            focused_chosen += 1;
        }
    }
    println!("no plane: focused map {focused_chosen} times, TSM's {tsm_chosen} times");
    assert!(focused_chosen > 0 && tsm_chosen > 0);
}
