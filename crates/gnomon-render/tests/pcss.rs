//! Percentage-closer soft shadows against the reference of soft shadows: the same area light
//! as a cluster of hard lights drawn with exact volumes (the shadows lecture's "Stenciled
//! Shadow Volumes for Simulating Soft Shadows"). The penumbra error (mean absolute difference
//! of the shadow factor over the union of both penumbrae) stays small for the focused map,
//! LiSPSM and cascades (the footprints carried into each map by its Jacobian), under a sun, a
//! spot and a lamp (its cube faces), with penumbrae that widen with the blocker's distance (a
//! floating slab against a box's base), and far below the error of hard shadows (PCSS with a
//! light of radius 0).

mod common;

use common::{cuboid, placed, renderer, square_camera};
use glam::DVec3;
use gnomon::area_light::area_light_samples;
use gnomon::{
    DirectionalLight, Light, MapSettings, PointLight, ShadowTechnique, SpotLight, Technique,
    compute_setup_with_samples,
};
use gnomon_render::{Filter, RenderScene, RenderSettings, Renderer, StencilMode, penumbra_error};

const SIZE: u32 = 256;
/// Light samples of the reference.
const SAMPLES: usize = 64;

/// A ground slab, a box on it (contact: a penumbra that starts at zero width) and a slab
/// floating 6 m up (a wide penumbra), all casting and receiving.
fn scene() -> RenderScene {
    RenderScene {
        meshes: vec![
            cuboid(DVec3::new(20.0, 0.5, 20.0)),
            cuboid(DVec3::new(1.5, 2.0, 1.5)),
            cuboid(DVec3::new(2.5, 0.15, 1.5)),
        ],
        instances: vec![
            placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), true),
            placed("block", 1, DVec3::new(4.0, 2.0, -3.0), true),
            placed("floating", 2, DVec3::new(-4.0, 6.0, 2.0), true),
        ],
    }
}

fn camera() -> gnomon::Camera {
    square_camera(
        DVec3::new(6.0, 22.0, 22.0),
        DVec3::new(0.0, 0.0, 0.0),
        1.0,
        200.0,
    )
}

/// The lights and their areas' radii: a sun 3 degrees wide (a hazy sky's), a spot of a 0.6 m
/// disc, a lamp of a 0.5 m disc (the reference's disc faces down, PCSS's each receiver).
fn lights() -> Vec<(&'static str, Light, f64)> {
    vec![
        (
            "sun",
            Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.35)).unwrap()),
            3.0,
        ),
        (
            "spot",
            Light::Spot(
                SpotLight::new(
                    DVec3::new(-9.0, 18.0, -6.0),
                    DVec3::new(0.45, -1.0, 0.35),
                    80.0,
                    80.0,
                )
                .unwrap(),
            ),
            0.6,
        ),
        (
            "lamp",
            Light::Point(PointLight::new(DVec3::new(-1.0, 12.0, -1.0), 80.0).unwrap()),
            0.5,
        ),
    ]
}

/// The reference's shadow factor (share of the light samples that reach each pixel).
fn reference(renderer: &mut Renderer, light: &Light, radius: f64) -> Vec<Option<f32>> {
    let cluster = area_light_samples(light, radius, SAMPLES, -DVec3::Y).unwrap();
    renderer
        .render_soft_volumes(
            &camera(),
            &[cluster],
            &common::square_settings(SIZE),
            StencilMode::ZFail,
        )
        .unwrap()
        .factor
}

/// PCSS's shadow factor with `technique`'s maps (2048 texels) and the light's N.L per pixel.
fn pcss(
    renderer: &mut Renderer,
    technique: &dyn ShadowTechnique,
    light: &Light,
    radius: f64,
) -> (Vec<f32>, Vec<f32>) {
    let camera = camera();
    let samples = renderer.view_samples(&camera, light).unwrap();
    let setup = compute_setup_with_samples(
        technique,
        &camera,
        light,
        &scene().bounds().unwrap(),
        MapSettings::with_resolution(2048),
        &samples,
    )
    .unwrap();
    let settings = RenderSettings {
        filter: Filter::Pcss,
        area_light_radius: radius,
        metrics: true,
        ..common::square_settings(SIZE)
    };
    let frame = renderer.render(&camera, light, &setup, &settings).unwrap();
    (frame.shadow.unwrap(), frame.metrics.unwrap().n_dot_l)
}

#[test]
fn pcss_follows_the_cluster_reference_on_every_fit() {
    let scene = scene();
    let mut renderer = renderer(&scene);
    for (name, light, radius) in lights() {
        let reference = reference(&mut renderer, &light, radius);
        for technique_name in ["focused", "lispsm", "cascades"] {
            let technique: Technique = technique_name.parse().unwrap();
            if !technique.takes(&light) {
                continue;
            }
            let (factor, n_dot_l) = pcss(&mut renderer, &technique, &light, radius);
            let error = penumbra_error(&reference, &factor, &n_dot_l);
            let (error, count) = (error.mean, error.pixels);
            let (hard, _) = pcss(&mut renderer, &technique, &light, 0.0);
            let hard_error = penumbra_error(&reference, &hard, &n_dot_l).mean;
            println!(
                "{name} {technique_name}: penumbra error {error:.4} over {count} pixels \
                 (hard shadows: {hard_error:.4})"
            );
            assert!(
                count > 500,
                "{name} {technique_name}: {count} penumbra pixels"
            );
            assert!(error < 0.06, "{name} {technique_name}: {error}");
            assert!(
                error * 2.0 < hard_error,
                "{name} {technique_name}: {error} {hard_error}"
            );
        }
    }
}
