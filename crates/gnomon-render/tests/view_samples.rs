//! The renderer's view samples: on a scene of boxes, what its pixels see is what the core's
//! rays through the same grid find (same points, same normals, so the same undersampling of a
//! map), and the warp limit decides the same from either.

mod common;

use glam::DVec3;
use gnomon::{
    DirectionalLight, Light, Lispsm, MapSettings, Technique, Tsm, ViewSamples, Xpsm, compute_setup,
    compute_setup_with_samples, undersampling,
};
use gnomon_render::{RenderScene, Renderer};

/// A ground slab and a row of boxes of different heights.
fn boxes() -> RenderScene {
    let mut meshes = vec![common::cuboid(DVec3::new(60.0, 0.5, 60.0))];
    let mut instances = vec![common::placed(
        "ground",
        0,
        DVec3::new(0.0, -0.5, 0.0),
        false,
    )];
    for k in 0..6 {
        let half = DVec3::new(3.0, 2.0 + 2.0 * k as f64, 3.0);
        meshes.push(common::cuboid(half));
        let at = DVec3::new(
            -35.0 + 14.0 * k as f64,
            half.y,
            -10.0 + 5.0 * (k % 3) as f64,
        );
        instances.push(common::placed(&format!("box {k}"), k + 1, at, true));
    }
    RenderScene { meshes, instances }
}

#[test]
fn the_pixels_see_what_the_core_rays_find_on_boxes() {
    let scene = boxes();
    let mut renderer: Renderer = common::renderer(&scene);
    let bounds = scene.bounds().unwrap();
    let views = [
        (DVec3::new(0.0, 12.0, 55.0), DVec3::new(0.0, 2.0, 0.0)),
        (DVec3::new(-50.0, 30.0, 30.0), DVec3::new(10.0, 0.0, -10.0)),
        (DVec3::new(40.0, 3.0, 40.0), DVec3::new(-20.0, 4.0, -20.0)),
    ];
    let suns = [
        DVec3::new(0.3, -1.0, -0.2),
        DVec3::new(-0.8, -0.3, 0.4),
        DVec3::new(0.1, -0.2, 1.0),
    ];
    let mut same_decision = 0;
    let mut decisions = 0;
    for (eye, target) in views {
        let lens = gnomon::Lens {
            fov_y_degrees: 60.0,
            aspect: 16.0 / 9.0,
            near: 0.5,
            far: 300.0,
        };
        let camera = gnomon::Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
        for sun in suns {
            let light = Light::Directional(DirectionalLight::new(sun).unwrap());
            let gpu = renderer.view_samples(&camera, &light).unwrap();
            let cpu = ViewSamples::new(&camera, &light, &bounds);
            let at = format!("eye {eye}, sun {sun}");
            assert!(cpu.len() > 100, "{at}: {} samples", cpu.len());
            // Rasterisation and ray casting differ only at box edges (and by f32).
            let diff = gpu.len().abs_diff(cpu.len());
            assert!(
                diff * 50 <= cpu.len(),
                "{at}: {} against {}",
                gpu.len(),
                cpu.len()
            );
            let map = compute_setup(
                &gnomon::Focused,
                &camera,
                &light,
                &bounds,
                MapSettings::with_resolution(1024),
            )
            .unwrap()
            .maps[0];
            let (mut matched, mut close) = (0, 0);
            // The same pixel: rays from the eye within 1/50 of a pixel's angle. (Rasterisers
            // snap vertices to a sub-pixel grid, 1/256 of a pixel on an NVIDIA H200: on the
            // ground seen at 4 degrees from eye [40, 3, 40] that moved points 8 cm along it,
            // 1/850 of a pixel across the ray.)
            let pixel =
                lens.fov_y_degrees.to_radians() / f64::from(ViewSamples::grid(lens.aspect).1);
            let ray = |p: DVec3| (p - eye).normalize();
            let mut worst = 0.0f64;
            for s in cpu.samples() {
                let Some(t) = gpu.samples().iter().min_by(|a, b| {
                    (a.position - s.position)
                        .length()
                        .total_cmp(&(b.position - s.position).length())
                }) else {
                    continue;
                };
                if ray(t.position).angle_between(ray(s.position)) < pixel / 50.0
                    && t.normal.dot(s.normal) > 1.0 - 1e-6
                {
                    matched += 1;
                    // The same point up to that snap: the same undersampling to within the
                    // points' distance over their depth.
                    let (u, v) = (undersampling(&map, s), undersampling(&map, t));
                    let apart = (t.position - s.position).length() / s.view_depth;
                    worst = worst.max((u / v - 1.0).abs() - 2.0 * apart);
                    close += usize::from((u / v - 1.0).abs() < 1e-3 + 2.0 * apart);
                }
            }
            assert!(
                matched * 50 >= cpu.len() * 48,
                "{at}: {matched} of {}",
                cpu.len()
            );
            assert_eq!(close, matched, "{at}: undersampling apart by {worst}");
            for technique in [
                Technique::Lispsm(Lispsm::default()),
                Technique::Tsm(Tsm::default()),
                Technique::Xpsm(Xpsm::default()),
            ] {
                let map = MapSettings::with_resolution(2048);
                let from_gpu =
                    compute_setup_with_samples(&technique, &camera, &light, &bounds, map, &gpu)
                        .unwrap();
                let from_cpu = compute_setup(&technique, &camera, &light, &bounds, map).unwrap();
                decisions += 1;
                same_decision += usize::from(
                    from_gpu.diagnostics.warp_strength == from_cpu.diagnostics.warp_strength,
                );
            }
        }
    }
    // Near the threshold a sample or two can tip the decision.
    assert!(
        same_decision * 10 >= decisions * 8,
        "{same_decision} of {decisions}"
    );
}
