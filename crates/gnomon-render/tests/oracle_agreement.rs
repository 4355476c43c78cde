//! `render --mask` against the ray-cast oracle: for views where the focused map is not
//! undersampled, at least 99.5% of the pixels with N.L > 0.1 that are not next to a
//! lit/shadow boundary agree, directional and spot lights.

mod common;

use glam::DVec3;
use gnomon::{
    Camera, CascadeFit, Cascades, DirectionalLight, Focused, Lens, Light, Lispsm, PerspectiveMap,
    Psm, SpotLight, Sppsm, Technique,
};
use gnomon_render::{RenderScene, RenderSettings};

const SIZE: u32 = 256;

struct View {
    name: &'static str,
    eye: DVec3,
    target: DVec3,
    far: f64,
    light: Light,
}

fn sun(x: f64, y: f64, z: f64) -> Light {
    Light::Directional(DirectionalLight::new(DVec3::new(x, y, z)).unwrap())
}

fn views() -> Vec<View> {
    vec![
        View {
            name: "overview, high sun",
            eye: DVec3::new(230.0, 200.0, 230.0),
            target: DVec3::ZERO,
            far: 800.0,
            light: sun(0.5, -1.0, 0.3),
        },
        View {
            name: "overview, low sun",
            eye: DVec3::new(-230.0, 220.0, 200.0),
            target: DVec3::new(0.0, 0.0, 0.0),
            far: 800.0,
            light: sun(1.0, -0.45, -0.35),
        },
        View {
            name: "park from above, sun toward the camera",
            eye: DVec3::new(140.0, 120.0, 40.0),
            target: DVec3::new(130.0, 0.0, 130.0),
            far: 400.0,
            light: sun(-0.3, -0.8, -0.6),
        },
        View {
            name: "city, spot light",
            eye: DVec3::new(-40.0, 150.0, 120.0),
            target: DVec3::new(-80.0, 0.0, -60.0),
            far: 500.0,
            light: Light::Spot(
                SpotLight::new(
                    DVec3::new(0.0, 120.0, 40.0),
                    DVec3::new(-0.6, -1.0, -0.8),
                    40.0,
                    400.0,
                )
                .unwrap(),
            ),
        },
        View {
            name: "park, spot light",
            eye: DVec3::new(60.0, 90.0, 60.0),
            target: DVec3::new(130.0, 0.0, 130.0),
            far: 400.0,
            light: Light::Spot(
                SpotLight::new(
                    DVec3::new(170.0, 60.0, 60.0),
                    DVec3::new(-0.5, -1.0, 1.0),
                    35.0,
                    300.0,
                )
                .unwrap(),
            ),
        },
    ]
}

#[test]
fn custom_views_agree_with_exact_shadows() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    let mut failures = Vec::new();
    for view in views() {
        let lens = Lens {
            fov_y_degrees: 60.0,
            aspect: 1.0,
            near: 1.0,
            far: view.far,
        };
        let camera = Camera::look_at(view.eye, view.target, DVec3::Y, lens).unwrap();
        let oracle = common::oracle(&scene, &camera, &view.light, SIZE, SIZE);
        // Spot lights: also the warps that take the spot through its own perspective (at full
        // strength: the warp itself is judged, not the limit), and SPPSM with them (two maps,
        // the plane through the light).
        let techniques = match view.light {
            Light::Spot(_) => vec![
                Technique::Focused(Focused),
                Technique::Lispsm(Lispsm {
                    limit: false,
                    ..Lispsm::default()
                }),
                Technique::Psm(Psm {
                    limit: false,
                    ..Psm::default()
                }),
                Technique::Sppsm(Sppsm::default()),
                Technique::Sppsm(Sppsm {
                    perspective: PerspectiveMap::Lispsm(Lispsm::default()),
                    iterations: 10,
                }),
                Technique::Cascades(Cascades {
                    fit: CascadeFit::Lispsm(Lispsm {
                        limit: false,
                        ..Lispsm::default()
                    }),
                    ..Cascades::default()
                }),
            ],
            Light::Directional(_) | Light::Point(_) => vec![Technique::Focused(Focused)],
        };
        for technique in techniques {
            let (setup, frame) = common::render(
                &mut renderer,
                &scene,
                &technique,
                &camera,
                &view.light,
                2048,
                &settings,
            );
            let a = common::agreement(&frame, &oracle, 0.1);
            println!(
                "{} ({}): {:.3}% of {} pixels agree ({} shadowed in the oracle), fallback {:?}",
                view.name,
                setup.technique,
                100.0 * a.fraction(),
                a.compared,
                a.shadowed,
                setup.fallback()
            );
            assert!(
                a.compared > 5000,
                "{}: too few pixels compared ({})",
                view.name,
                a.compared
            );
            assert!(
                a.shadowed > 100,
                "{}: the view shows too little shadow ({})",
                view.name,
                a.shadowed
            );
            // (A cascade's slice that the spot cannot see names SpotLightMissesView.)
            if setup.technique != "focused" && setup.technique != "cascades" {
                assert_eq!(
                    setup.fallback(),
                    None,
                    "{}: the spot light is warped",
                    view.name
                );
            }
            if a.fraction() < 0.995 {
                failures.push(format!(
                    "{} ({}): {:.3}%",
                    view.name,
                    setup.technique,
                    100.0 * a.fraction()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "below 99.5% agreement: {failures:?}");
}

/// Agreement of every technique for every named view of the demo (printed with
/// `--nocapture`), each at least 99.5% at 640x360 (compare's size) with 2048 maps, and at
/// least 95% of the shadowed pixels found in shadow, over at least ten in every view (at
/// 320x180 the overview judged none), so that a renderer drawing no shadows fails.
#[test]
fn named_views_report() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (width, height) = (640, 360);
    let settings = RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    };
    for view in gnomon_scene::DEMO_VIEWS {
        let (camera, light) = view.camera_and_light(width as f64 / height as f64).unwrap();
        let oracle = common::oracle(&scene, &camera, &light, width, height);
        // Every technique, and the cascades stable and with focused maps sharing one map's
        // texels.
        let mut techniques = gnomon::Technique::all();
        techniques.push(Technique::Cascades(Cascades {
            stable: true,
            ..Cascades::default()
        }));
        techniques.push(Technique::Cascades(Cascades {
            fit: CascadeFit::Focused,
            equal_texels: true,
            ..Cascades::default()
        }));
        for technique in techniques.into_iter().filter(|t| t.takes(&light)) {
            let (_, frame) = common::render(
                &mut renderer,
                &scene,
                &technique,
                &camera,
                &light,
                2048,
                &settings,
            );
            let a = common::agreement(&frame, &oracle, 0.1);
            println!(
                "{:<15} {:<8} {:.3}% of {} pixels agree ({} shadowed)",
                view.name,
                describe(&technique),
                100.0 * a.fraction(),
                a.compared,
                a.shadowed
            );
            // Dual paraboloid maps too: their depth pass casts each texel's ray at the
            // triangle (the lamp_by_wall wall's two large triangles were 97.7% with distances
            // interpolated between the vertices, 99.931% with straight edges).
            let (bound, recall) = (0.995, 0.95);
            assert!(
                a.fraction() >= bound,
                "{} {technique:?}: {:.3}%",
                view.name,
                100.0 * a.fraction()
            );
            // Shadows judged in every view, and found: a renderer that draws none fails.
            assert!(
                a.shadowed >= 10 && a.shadow_recall() >= recall,
                "{} {technique:?}: {} of {} shadowed pixels found",
                view.name,
                a.shadowed_agreeing,
                a.shadowed
            );
        }
    }
}

/// A technique's name, with the cascades' fit and whether stable.
fn describe(technique: &Technique) -> String {
    match technique {
        Technique::Cascades(c) if c.stable => "cascades (stable)".to_string(),
        Technique::Cascades(c) => format!("cascades ({})", c.fit.name()),
        other => gnomon::ShadowTechnique::name(other).to_string(),
    }
}
