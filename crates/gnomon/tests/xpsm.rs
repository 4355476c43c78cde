//! XPSM's back-projection clamp, measured from the matrix: the warp w (the clip-space w of the
//! map) is at least epsilon_W over the whole convex body B, also with the camera inside the
//! scene and the light nearly along the view (where the unclamped warp would reach w <= 0).

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, MapSettings, SceneBounds, SetupError, Xpsm,
    compute_setup, convex_body_b,
};

fn scene() -> SceneBounds {
    let ground = Aabb::new(
        DVec3::new(-200.0, -1.0, -200.0),
        DVec3::new(200.0, 0.0, 200.0),
    )
    .unwrap();
    let block = Aabb::new(DVec3::new(-20.0, 0.0, -20.0), DVec3::new(20.0, 40.0, 20.0)).unwrap();
    SceneBounds::new(vec![ground, block], vec![ground, block], None).unwrap()
}

#[test]
fn w_stays_above_epsilon_over_b() {
    let lens = Lens {
        fov_y_degrees: 70.0,
        aspect: 1.5,
        near: 0.5,
        far: 500.0,
    };
    let mut clamped = 0;
    for (k, (eye, target)) in [
        (DVec3::new(0.0, 5.0, 150.0), DVec3::new(0.0, 0.0, 0.0)),
        (
            DVec3::new(150.0, 2.0, 150.0),
            DVec3::new(-150.0, 2.0, -150.0),
        ),
        (DVec3::new(-100.0, 60.0, 0.0), DVec3::new(100.0, 0.0, 10.0)),
    ]
    .into_iter()
    .enumerate()
    {
        let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
        // Light travelling nearly along the view: the map's y axis is close to world up, and
        // the view frustum reaches far below the eye in it (w would go negative there).
        let sun = Light::Directional(
            DirectionalLight::new(camera.forward() + DVec3::new(0.05, -0.25, 0.0)).unwrap(),
        );
        for coef in [0.01, 0.05, 1.0] {
            // The chapter's warp and its clamp (the limit is tested on its own).
            let xpsm = Xpsm {
                coef,
                limit: false,
                ..Xpsm::default()
            };
            let setup =
                compute_setup(&xpsm, &camera, &sun, &scene(), MapSettings::default()).unwrap();
            assert_eq!(setup.fallback(), None, "view {k}, coef {coef}");
            let w_row = setup.maps[0].clip_from_world.row(3);
            let body = convex_body_b(&camera, &sun, &scene()).vertices(1e-9);
            let w_min = body
                .iter()
                .map(|p| w_row.dot(p.extend(1.0)))
                .fold(f64::INFINITY, f64::min);
            assert!(
                w_min >= xpsm.epsilon_w - 1e-9,
                "view {k}, coef {coef}: w = {w_min} on B"
            );
            clamped += usize::from((w_min - xpsm.epsilon_w).abs() < 1e-6);
        }
    }
    // The strong warps hit the clamp.
    assert!(clamped >= 2, "the clamp was reached {clamped} times");
}

#[test]
fn bad_parameters_are_typed_errors() {
    let camera = Camera::look_at(
        DVec3::new(0.0, 5.0, 150.0),
        DVec3::ZERO,
        DVec3::Y,
        Lens::default(),
    )
    .unwrap();
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.4, -1.0, 0.3)).unwrap());
    for xpsm in [
        Xpsm {
            coef: 0.0,
            ..Xpsm::default()
        },
        Xpsm {
            coef: f64::NAN,
            ..Xpsm::default()
        },
        Xpsm {
            epsilon_w: 0.0,
            ..Xpsm::default()
        },
        Xpsm {
            epsilon_w: 1.0,
            ..Xpsm::default()
        },
    ] {
        let r = compute_setup(&xpsm, &camera, &sun, &scene(), MapSettings::default());
        assert!(
            matches!(r, Err(SetupError::InvalidParameter { .. })),
            "{xpsm:?}: {r:?}"
        );
    }
}
