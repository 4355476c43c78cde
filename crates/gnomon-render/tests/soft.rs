//! Soft shadows from a cluster of hard lights drawn with exact volumes (the shadows
//! lecture's "Stenciled Shadow Volumes for Simulating Soft Shadows") against the ray-cast
//! oracle with the same light points, and their convergence with the number of samples.

mod common;

use common::{box_on_ground, oracle, renderer, square_camera};
use glam::DVec3;
use gnomon::area_light::area_light_samples;
use gnomon::{DirectionalLight, Light, PointLight, SpotLight};
use gnomon_render::{MASK_LIT, RenderScene, StencilMode};

fn scene() -> RenderScene {
    // A tall box on a slab: its shadow's penumbra widens away from its base.
    box_on_ground(20.0, "tower", DVec3::new(1.5, 4.0, 1.5), DVec3::ZERO)
}

/// A spot light above and beside the tower.
fn spot() -> Light {
    Light::Spot(
        SpotLight::new(
            DVec3::new(8.0, 14.0, 6.0),
            DVec3::new(-0.6, -1.0, -0.5),
            50.0,
            80.0,
        )
        .unwrap(),
    )
}

fn camera() -> gnomon::Camera {
    square_camera(
        DVec3::new(14.0, 18.0, 20.0),
        DVec3::new(-2.0, 0.0, -2.0),
        1.0,
        200.0,
    )
}

#[test]
fn the_cluster_agrees_with_the_oracle_of_the_same_light_points() {
    let scene = scene();
    let mut renderer = renderer(&scene);
    let camera = camera();
    let size = 128;
    let n = 16;
    let lights = [
        (
            Light::Directional(DirectionalLight::new(DVec3::new(-0.6, -1.0, -0.4)).unwrap()),
            10.0,
        ),
        (spot(), 2.0),
        (
            Light::Point(PointLight::new(DVec3::new(6.0, 12.0, 5.0), 80.0).unwrap()),
            1.5,
        ),
    ];
    for (light, radius) in lights {
        let facing = -DVec3::Y;
        let cluster = area_light_samples(&light, radius, n, facing).unwrap();
        let soft = renderer
            .render_soft_volumes(
                &camera,
                std::slice::from_ref(&cluster),
                &common::square_settings(size),
                StencilMode::ZFail,
            )
            .unwrap();
        // The oracle's factor: the share of the same light points each pixel sees.
        let mut exact = vec![0.0f64; (size * size) as usize];
        for sample in &cluster {
            let o = oracle(&scene, &camera, sample, size, size);
            for (e, m) in exact.iter_mut().zip(&o.mask) {
                *e += f64::from(u8::from(*m == MASK_LIT)) / n as f64;
            }
        }
        let (mut compared, mut within, mut penumbra) = (0, 0, 0);
        for (f, e) in soft.factor.iter().zip(&exact) {
            let Some(f) = f else { continue };
            compared += 1;
            within += usize::from((*f as f64 - e).abs() <= 1.0 / n as f64 + 1e-6);
            penumbra += usize::from(*e > 0.0 && *e < 1.0);
        }
        let share = within as f64 / compared as f64;
        assert!(penumbra > 80, "{light:?}: {penumbra} penumbra pixels");
        assert!(
            share >= 0.995,
            "{light:?}: {share} of {compared} within 1/N"
        );
    }
}

#[test]
fn more_samples_change_the_penumbra_by_less_than_one_percent() {
    let scene = scene();
    let mut renderer = renderer(&scene);
    let camera = camera();
    let size = 96;
    let spot = spot();
    let mut factor = |n: usize| {
        let cluster = area_light_samples(&spot, 2.0, n, DVec3::ZERO).unwrap();
        renderer
            .render_soft_volumes(
                &camera,
                &[cluster],
                &common::square_settings(size),
                StencilMode::ZFail,
            )
            .unwrap()
            .factor
    };
    let (coarse, fine) = (factor(64), factor(256));
    let (mut sum, mut count) = (0.0f64, 0usize);
    for (c, f) in coarse.iter().zip(&fine) {
        // The penumbra: where the reference (256 samples) is neither fully lit nor fully
        // shadowed.
        if let (Some(c), Some(f)) = (c, f)
            && *f > 0.0
            && *f < 1.0
        {
            sum += (c - f).abs() as f64;
            count += 1;
        }
    }
    assert!(count > 200, "{count} penumbra pixels");
    let mean = sum / count as f64;
    // The bound. The 256 samples contain the 64 (progressive clusters, see
    // gnomon::area_light): with two unrelated Vogel spirals this measured 1.07% here.
    assert!(
        mean < 0.01,
        "mean difference {mean} over {count} penumbra pixels"
    );
}
