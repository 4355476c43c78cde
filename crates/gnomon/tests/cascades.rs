//! Cascades from their matrices: the split rules, the shadow distance and its fade, equal
//! texels, bad parameters, and stable cascades whose texel grid stays fixed in the world while
//! the camera dollies, pans and turns.

use glam::{DMat3, DVec3};
use gnomon::{
    Aabb, Camera, CascadeFit, CascadeSelect, CascadeSlices, CascadeSplit, Cascades,
    DirectionalLight, Lens, Light, MapSelection, MapSettings, SceneBounds, SetupError, ShadowMap,
    ShadowSetup, SpotLight, Technique, compute_setup,
};

/// A 2 km ground with a few buildings: a camera at street level sees it from its near plane
/// to its far plane.
fn city() -> SceneBounds {
    let ground = Aabb::new(
        DVec3::new(-1000.0, -1.0, -1000.0),
        DVec3::new(1000.0, 0.0, 1000.0),
    )
    .unwrap();
    let mut casters = Vec::new();
    for i in 0..10 {
        let min = DVec3::new(-200.0 + 40.0 * i as f64, 0.0, -60.0 - 25.0 * i as f64);
        casters.push(Aabb::new(min, min + DVec3::new(12.0, 20.0 + 5.0 * i as f64, 12.0)).unwrap());
    }
    let mut receivers = casters.clone();
    receivers.push(ground);
    SceneBounds::new(casters, receivers, None).unwrap()
}

fn street_camera(eye: DVec3, forward: DVec3) -> Camera {
    let lens = Lens {
        fov_y_degrees: 60.0,
        aspect: 16.0 / 9.0,
        near: 0.5,
        far: 400.0,
    };
    Camera::look_at(eye, eye + forward, DVec3::Y, lens).unwrap()
}

fn sun() -> Light {
    Light::Directional(DirectionalLight::new(DVec3::new(0.4, -0.8, -0.3)).unwrap())
}

fn setup(cascades: Cascades, camera: &Camera) -> ShadowSetup {
    compute_setup(
        &cascades,
        camera,
        &sun(),
        &city(),
        MapSettings::with_resolution(1024),
    )
    .unwrap()
}

fn slices(setup: &ShadowSetup) -> CascadeSlices {
    match setup.selection {
        MapSelection::Cascades(c) => c,
        other => panic!("not cascades: {other:?}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

#[test]
fn the_split_rules_cut_the_view_as_their_formulas_say() {
    let camera = street_camera(DVec3::new(0.0, 2.0, 0.0), DVec3::new(0.0, -0.05, -1.0));
    let (n, f) = (0.5f64, 400.0f64);
    let k = 4;
    let log = |i: usize| n * (f / n).powf(i as f64 / k as f64);
    let uniform = |i: usize| n + (f - n) * i as f64 / k as f64;
    for (split, expected) in [
        (CascadeSplit::Log, (0..=k).map(log).collect::<Vec<_>>()),
        (CascadeSplit::Uniform, (0..=k).map(uniform).collect()),
        // lambda weighs the logarithmic split (Zhang et al.): at 0.5 a swapped weight would
        // not show, at 0.2 and 0.8 it does.
        (
            CascadeSplit::Practical { lambda: 0.5 },
            (0..=k).map(|i| 0.5 * log(i) + 0.5 * uniform(i)).collect(),
        ),
        (
            CascadeSplit::Practical { lambda: 0.2 },
            (0..=k).map(|i| 0.2 * log(i) + 0.8 * uniform(i)).collect(),
        ),
        (
            CascadeSplit::Practical { lambda: 0.8 },
            (0..=k).map(|i| 0.8 * log(i) + 0.2 * uniform(i)).collect(),
        ),
    ] {
        let s = setup(
            Cascades {
                split,
                count: k,
                ..Cascades::default()
            },
            &camera,
        );
        assert_eq!(s.maps.len(), k);
        let depths = slices(&s).depths().to_vec();
        assert!(
            depths.iter().zip(&expected).all(|(a, b)| close(*a, *b)),
            "{split:?}: {depths:?} vs {expected:?}"
        );
        // Each view depth's map is its slice's.
        for (i, window) in depths.windows(2).enumerate() {
            let p = camera.eye() + camera.forward() * (0.5 * (window[0] + window[1]));
            assert_eq!(s.map_for(p), Some(i));
        }
    }
    // Explicit distances, a shadow distance that cuts the view (and fades over its last 10%),
    // equal texels.
    let mut depths = [0.0; 7];
    depths[..2].copy_from_slice(&[10.0, 40.0]);
    let s = setup(
        Cascades {
            count: 3,
            split: CascadeSplit::Distances { count: 2, depths },
            shadow_distance: Some(150.0),
            equal_texels: true,
            fit: CascadeFit::Focused,
            ..Cascades::default()
        },
        &camera,
    );
    let c = slices(&s);
    assert_eq!(c.depths(), &[0.5, 10.0, 40.0, 150.0]);
    assert!(close(c.fade_start, 135.0), "{}", c.fade_start);
    assert!(
        s.maps.iter().all(|m| m.resolution == 591),
        "{:?}",
        s.maps[0].resolution
    );
}

#[test]
fn a_distant_view_cuts_only_the_visible_scene() {
    // From 2 km away the scene begins about 1 km along the view: the slices start there.
    let camera = street_camera(DVec3::new(0.0, 300.0, 2200.0), DVec3::new(0.0, -0.1, -1.0));
    let camera = Camera::from_view_from_world(
        camera.view_from_world(),
        Lens {
            far: 4000.0,
            ..camera.lens()
        },
    )
    .unwrap();
    let c = slices(&setup(Cascades::default(), &camera));
    assert!(c.depths()[0] > 1000.0, "{:?}", c.depths());
    assert!(c.shadow_distance() < 3500.0, "{:?}", c.depths());
}

#[test]
fn bad_cascade_parameters_are_typed_errors() {
    let camera = street_camera(DVec3::new(0.0, 2.0, 0.0), DVec3::NEG_Z);
    let mut three = [0.0; 7];
    three[..3].copy_from_slice(&[5.0, 3.0, 50.0]);
    let bad = [
        Cascades {
            count: 0,
            ..Cascades::default()
        },
        Cascades {
            count: 9,
            ..Cascades::default()
        },
        Cascades {
            blend: 0.6,
            ..Cascades::default()
        },
        Cascades {
            split: CascadeSplit::Practical { lambda: 1.5 },
            ..Cascades::default()
        },
        Cascades {
            shadow_distance: Some(0.1),
            ..Cascades::default()
        },
        Cascades {
            shadow_distance: Some(f64::NAN),
            ..Cascades::default()
        },
        // Decreasing distances, and a count that does not match.
        Cascades {
            split: CascadeSplit::Distances {
                count: 3,
                depths: three,
            },
            ..Cascades::default()
        },
        Cascades {
            count: 3,
            split: CascadeSplit::Distances {
                count: 3,
                depths: three,
            },
            ..Cascades::default()
        },
    ];
    for cascades in bad {
        let result = compute_setup(&cascades, &camera, &sun(), &city(), MapSettings::default());
        assert!(
            matches!(result, Err(SetupError::InvalidParameter { .. })),
            "{cascades:?}: {result:?}"
        );
    }
    // Coverage needs stable maps: a fitted map holds only its slice.
    let fitted_by_coverage = Cascades {
        select: CascadeSelect::Coverage,
        ..Cascades::default()
    };
    let result = compute_setup(
        &fitted_by_coverage,
        &camera,
        &sun(),
        &city(),
        MapSettings::default(),
    );
    assert_eq!(result.unwrap_err(), SetupError::CoverageNeedsStable);
}

/// Stable cascades pick by coverage (unless asked for view depth): a point reads the first
/// map whose square, less the margin, holds it, never a later map than its view depth's
/// slice's; points beyond a slice's far plane read a nearer (finer) slice's map where its
/// square reaches them, and every map a point reads holds it. Fitted cascades, stable ones
/// asked for view depth and stable ones under a spot light (which fall back to fitted maps)
/// pick by view depth.
#[test]
fn stable_cascades_pick_the_finest_map_that_holds_a_point() {
    let camera = street_camera(DVec3::new(-30.0, 2.0, 20.0), DVec3::new(0.2, -0.05, -1.0));
    let stable = Cascades {
        stable: true,
        ..Cascades::default()
    };
    let s = setup(stable, &camera);
    let c = slices(&s);
    assert!(c.by_coverage, "stable cascades pick by coverage");
    // A map holds what lies COVER_MARGIN_TEXELS texels and its inset inside its square's edge.
    for map in &s.maps {
        let border = (map.viewport_inset + CascadeSlices::COVER_MARGIN_TEXELS) as f64;
        let edge = 1.0 - 2.0 * border / map.resolution as f64;
        let world_from_clip = map.clip_from_world.inverse();
        for (x, y, held) in [
            (edge - 1e-6, 0.0, true),
            (edge + 1e-6, 0.0, false),
            (0.3, -edge + 1e-6, true),
            (0.3, -edge - 1e-6, false),
        ] {
            let p = world_from_clip.project_point3(DVec3::new(x, y, 0.5));
            assert_eq!(CascadeSlices::covers(map, p), held, "({x}, {y})");
        }
    }
    let covers = |i: usize, p: DVec3| CascadeSlices::covers(&s.maps[i], p);
    let (mut finer, mut judged) = (0, 0);
    let lens = camera.lens();
    for a in 0..40 {
        for b in 0..40 {
            for d in 0..40 {
                // Points over the view frustum, out to the shadow distance.
                let depth = lens.near + (lens.far - lens.near) * ((d as f64 + 0.5) / 40.0).powi(2);
                let ndc = glam::DVec2::new(a as f64 / 19.5 - 1.0, b as f64 / 19.5 - 1.0);
                let tan_y = (0.5 * lens.fov_y_degrees.to_radians()).tan();
                let view = DVec3::new(ndc.x * tan_y * lens.aspect, ndc.y * tan_y, -1.0) * depth;
                let p = camera.view_from_world().inverse().transform_point3(view);
                let slice = c.slice_of(c.depth_row_world.dot(p.extend(1.0)));
                let i = s.map_for(p).unwrap();
                judged += 1;
                assert!(i <= slice, "{p}: map {i} beyond slice {slice}");
                assert!((0..i).all(|j| !covers(j, p)), "{p}: a finer map holds it");
                if i < slice {
                    finer += 1;
                    assert!(covers(i, p));
                }
                // The map read holds the point in its square (its own slice's by the sphere).
                let q = s.maps[i].clip_from_world.project_point3(p);
                assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{p}: {q}");
            }
        }
    }
    println!("{finer} of {judged} points read a finer map than their slice's");
    assert!(
        finer * 10 > judged,
        "{finer} of {judged} points read a finer map than their slice's"
    );
    // View depth on request, for fitted cascades, and where stable falls back to fitted maps.
    let spot =
        Light::Spot(SpotLight::new(DVec3::new(0.0, 80.0, 0.0), DVec3::NEG_Y, 70.0, 500.0).unwrap());
    for (cascades, light) in [
        (
            Cascades {
                select: CascadeSelect::ViewDepth,
                ..stable
            },
            sun(),
        ),
        (Cascades::default(), sun()),
        (stable, spot),
    ] {
        let s = compute_setup(
            &cascades,
            &camera,
            &light,
            &city(),
            MapSettings::with_resolution(1024),
        )
        .unwrap();
        assert!(!slices(&s).by_coverage, "{cascades:?}");
    }
}

/// A camera at each frame of a path.
type CameraPath = Box<dyn Fn(usize) -> Camera>;

/// The world-to-texel map of a cascade: its linear part (texels per world unit along x and y)
/// and where the world origin lands, in texels.
fn texel_map(map: &ShadowMap) -> (DMat3, [f64; 2]) {
    let m = map.clip_from_world;
    let scale = 0.5 * map.resolution as f64;
    let linear = DMat3::from_cols(
        m.row(0).truncate() * scale,
        m.row(1).truncate() * scale,
        DVec3::ZERO,
    );
    (linear, [m.row(0).w * scale, m.row(1).w * scale])
}

#[test]
fn stable_cascades_keep_their_texel_grid_in_the_world() {
    let stable = Cascades {
        stable: true,
        count: 4,
        ..Cascades::default()
    };
    let start = DVec3::new(-30.0, 2.0, 20.0);
    let forward = DVec3::new(0.2, -0.05, -1.0).normalize();
    let paths: [(&str, CameraPath); 3] = [
        (
            "dolly",
            Box::new(move |t| street_camera(start + forward * (0.37 * t as f64), forward)),
        ),
        (
            "pan",
            Box::new(move |t| {
                let right = forward.cross(DVec3::Y).normalize();
                street_camera(start + right * (0.29 * t as f64), forward)
            }),
        ),
        (
            "turn",
            Box::new(move |t| {
                let turn = glam::DQuat::from_rotation_y(0.013 * t as f64);
                street_camera(start, turn * forward)
            }),
        ),
    ];
    for (name, camera_at) in paths {
        let first = setup(stable, &camera_at(0));
        assert_eq!(first.fallback(), None, "{name}");
        let mut moved = 0;
        for t in 1..40 {
            let s = setup(stable, &camera_at(t));
            assert_eq!(slices(&s).depths(), slices(&first).depths(), "{name}");
            for (i, (a, b)) in first.maps.iter().zip(&s.maps).enumerate() {
                let ((la, oa), (lb, ob)) = (texel_map(a), texel_map(b));
                assert!(
                    la.abs_diff_eq(lb, 1e-12 * la.x_axis.length()),
                    "{name}, frame {t}, cascade {i}: the texel grid turned or scaled"
                );
                for axis in 0..2 {
                    let shift = ob[axis] - oa[axis];
                    assert!(
                        (shift - shift.round()).abs() < 1e-6,
                        "{name}, frame {t}, cascade {i}: moved by {shift} texels"
                    );
                    moved += usize::from(shift.round() != 0.0);
                }
            }
        }
        // The maps do follow the camera (by whole texels).
        assert!(moved > 10, "{name}: {moved}");
    }
}

/// Adaptive cascades are the setup of the number of cascades n (1 to K) where the median
/// undersampling over the view samples last fell: each number up to n has a lower median
/// than the one before, and n + 1 (if n < K) does not; the same maps, to the bit, as that
/// number's setup; over street views and suns, both a grazing sun (where slicing at equal
/// texels does not pay) and a high one. Given the previous frame's number, the hysteresis.
#[test]
fn adaptive_cascades_keep_the_count_where_the_median_undersampling_stops_falling() {
    let scene = city();
    let mut counts = Vec::new();
    let mut stopped_early = false;
    let (mut kept_previous, mut switched) = (false, false);
    for (i, (eye, forward, sun)) in [
        (
            DVec3::new(0.0, 2.0, 50.0),
            DVec3::new(0.0, -0.05, -1.0),
            DVec3::new(0.4, -0.8, -0.3),
        ),
        (
            DVec3::new(-30.0, 40.0, 80.0),
            DVec3::new(0.3, -0.4, -1.0),
            DVec3::new(-0.2, -1.0, 0.1),
        ),
        (
            DVec3::new(10.0, 1.7, 0.0),
            DVec3::new(-1.0, 0.0, -0.6),
            DVec3::new(-0.97, -0.08, -0.2),
        ),
        (
            DVec3::new(0.0, 120.0, 150.0),
            DVec3::new(0.0, -0.6, -1.0),
            DVec3::new(0.1, -0.05, -1.0),
        ),
        // Two cascades undersample more than one, four less: the search stops at one.
        (
            DVec3::new(27.4, 75.7, 40.75),
            DVec3::new(0.54, -0.15, -0.378),
            DVec3::new(-0.1155, -0.213, -0.0779),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let camera = street_camera(eye, forward);
        let light = Light::Directional(DirectionalLight::new(sun).unwrap());
        let settings = MapSettings::with_resolution(1024);
        let samples = gnomon::ViewSamples::new(&camera, &light, &scene);
        let base = Cascades {
            count: 4,
            equal_texels: true,
            blend: 0.0,
            ..Cascades::default()
        };
        let run = |c: Cascades| {
            gnomon::compute_setup_with_samples(&c, &camera, &light, &scene, settings, &samples)
                .unwrap()
        };
        let adaptive = run(Cascades {
            adaptive: true,
            ..base
        });
        let medians: Vec<f64> = (1..=4)
            .map(|count| {
                let fixed = run(Cascades { count, ..base });
                samples.setup_undersampling_quantile(&fixed, 0.5).unwrap()
            })
            .collect();
        // The first number whose successor does not lower the median (or K).
        let count = 1 + (0..3).find(|&i| medians[i + 1] >= medians[i]).unwrap_or(3);
        assert_eq!(adaptive.maps.len(), count, "view {i}: medians {medians:?}");
        assert_eq!(
            adaptive.maps,
            run(Cascades { count, ..base }).maps,
            "view {i}"
        );
        let least = medians.iter().copied().fold(f64::INFINITY, f64::min);
        stopped_early |= medians[count - 1] > least;
        counts.push(count);
        // Given the previous frame's number p (5 reads as 4), the setup stays at p unless the
        // number found has a median more than ADAPTIVE_HYSTERESIS lower.
        for previous in 1..=5 {
            let p = previous.min(4);
            let switches =
                medians[count - 1] < (1.0 - gnomon::ADAPTIVE_HYSTERESIS) * medians[p - 1];
            let expected = if switches { count } else { p };
            let next = run(Cascades {
                adaptive: true,
                adaptive_previous: Some(previous),
                ..base
            });
            assert_eq!(
                next.maps,
                run(Cascades {
                    count: expected,
                    ..base
                })
                .maps,
                "view {i}, previous {previous}: medians {medians:?}"
            );
            if p != count {
                kept_previous |= !switches;
                switched |= switches;
            }
        }
    }
    // The views do not all pick the same number: the choice depends on the view.
    assert!(counts.iter().any(|c| *c != counts[0]), "counts {counts:?}");
    // And one view's search stops before a number with a lower median.
    assert!(stopped_early, "counts {counts:?}");
    // The previous frame's number is kept somewhere, and left somewhere.
    assert!(kept_previous && switched);
}

/// A frame loop hands adaptive cascades the number kept; a previous number of 0 is refused.
#[test]
fn adaptive_cascades_learn_the_previous_frames_count() {
    let adaptive = Technique::Cascades(Cascades {
        adaptive: true,
        ..Cascades::default()
    });
    let camera = street_camera(DVec3::new(0.0, 2.0, 50.0), DVec3::new(0.0, -0.05, -1.0));
    let scene = city();
    let settings = MapSettings::with_resolution(1024);
    let setup = compute_setup(&adaptive, &camera, &sun(), &scene, settings).unwrap();
    match adaptive.for_next_frame(&setup) {
        Technique::Cascades(c) => assert_eq!(c.adaptive_previous, Some(setup.maps.len())),
        other => panic!("{other:?}"),
    }
    // Other techniques (and fixed cascades) keep no state.
    let fixed = Technique::Cascades(Cascades::default());
    assert_eq!(fixed.for_next_frame(&setup), fixed);
    let zero = Cascades {
        adaptive: true,
        adaptive_previous: Some(0),
        ..Cascades::default()
    };
    assert!(matches!(
        compute_setup(&zero, &camera, &sun(), &scene, settings),
        Err(SetupError::InvalidParameter { .. })
    ));
}

#[test]
fn adaptive_cascades_refuse_explicit_split_distances() {
    let camera = street_camera(DVec3::new(0.0, 2.0, 50.0), DVec3::new(0.0, -0.05, -1.0));
    let mut depths = [0.0; gnomon::MAX_CASCADES - 1];
    depths[0] = 20.0;
    let c = Cascades {
        count: 2,
        split: CascadeSplit::Distances { count: 1, depths },
        adaptive: true,
        ..Cascades::default()
    };
    let result = compute_setup(
        &c,
        &camera,
        &sun(),
        &city(),
        MapSettings::with_resolution(1024),
    );
    assert!(
        matches!(result, Err(SetupError::InvalidParameter { .. })),
        "{result:?}"
    );
}
