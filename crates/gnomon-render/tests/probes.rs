//! Probes read the maps as the main pass does: at the surface points a frame's pixels see,
//! `lit_at_points` gives the frame's own mask (focused, LiSPSM and cascades, on the demo's
//! named views), even when the renderer last drew another light's maps.

mod common;

use glam::DVec3;
use gnomon::{Cascades, DirectionalLight, Light, Lispsm, ShadowTechnique, Technique};
use gnomon_render::{MASK_LIT, MASK_UNLIT, RenderScene, RenderSettings, ShadowedLight};

#[test]
fn probes_at_the_pixels_points_give_the_frames_mask() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (width, height) = (192, 108);
    let settings = RenderSettings {
        width,
        height,
        metrics: true,
        ..RenderSettings::default()
    };
    for view in ["street", "low_sun", "light_behind"] {
        let view = gnomon_scene::DEMO_VIEWS
            .iter()
            .find(|v| v.name == view)
            .unwrap();
        let (camera, light) = view.camera_and_light(width as f64 / height as f64).unwrap();
        for technique in [
            Technique::Focused(gnomon::Focused),
            Technique::Lispsm(Lispsm::default()),
            Technique::Cascades(Cascades::default()),
        ] {
            let (setup, frame) = common::render(
                &mut renderer,
                &scene,
                &technique,
                &camera,
                &light,
                2048,
                &settings,
            );
            // The sun from the opposite side drawn last: the probes must draw this setup's
            // own maps, not read the ones left from the frame before.
            common::render(
                &mut renderer,
                &scene,
                &technique,
                &camera,
                &opposite(&light),
                2048,
                &settings,
            );
            let points = renderer.surface_points(&camera, (width, height)).unwrap();
            let judged: Vec<usize> = (0..points.len())
                .filter(|&i| {
                    points[i].is_some()
                        && frame.metrics.as_ref().unwrap().n_dot_l[i] > 0.1
                        && frame.mask[i] != 128
                })
                .collect();
            let lit = renderer
                .lit_at_points(
                    &camera,
                    &[ShadowedLight {
                        light: &light,
                        setup: &setup,
                    }],
                    &settings,
                    &judged
                        .iter()
                        .map(|&i| points[i].unwrap())
                        .collect::<Vec<_>>(),
                )
                .unwrap();
            let (mut agree, mut shadowed) = (0, 0);
            for (k, &i) in judged.iter().enumerate() {
                let expected = frame.mask[i];
                assert!(expected == MASK_LIT || expected == MASK_UNLIT);
                shadowed += usize::from(expected == MASK_UNLIT);
                agree += usize::from(lit[k] == (expected == MASK_LIT));
            }
            println!(
                "{} {}: {agree} of {} agree ({shadowed} shadowed)",
                view.name,
                technique.name(),
                judged.len()
            );
            assert!(judged.len() > 5000 && shadowed > 100, "{}", view.name);
            assert!(
                agree * 1000 >= judged.len() * 998,
                "{} {}: {agree} of {}",
                view.name,
                technique.name(),
                judged.len()
            );
        }
    }
}

/// The sun at the same height from the opposite side.
fn opposite(light: &Light) -> Light {
    let Light::Directional(sun) = light else {
        panic!("the views named here are lit by the sun");
    };
    let d = sun.direction();
    Light::Directional(DirectionalLight::new(DVec3::new(-d.x, d.y, -d.z)).unwrap())
}
