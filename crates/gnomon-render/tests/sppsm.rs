//! SPPSM in the renderer: each pixel reads the map its side of the plane picks (the tint shows
//! both maps in use), and with both maps focused on all of I (one iteration, the maps then
//! equal the focused and the perspective technique's own) every pixel's area undersampling
//! (pixels per texel area, 1 / |det J|, the paper's measure) is that of the better of the two
//! maps alone.

mod common;

use glam::DVec3;
use gnomon::{
    Camera, DirectionalLight, Focused, Lens, Light, PerspectiveMap, Psm, Sppsm, Technique,
};
use gnomon_render::{RenderScene, RenderSettings};

#[test]
fn each_pixel_reads_the_map_with_the_better_area_sampling() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let renderer = common::renderer(&scene);
    let (width, height) = (256, 144);
    let settings = RenderSettings {
        width,
        height,
        metrics: true,
        ..RenderSettings::default()
    };
    let lens = Lens {
        aspect: width as f64 / height as f64,
        far: 400.0,
        ..Lens::default()
    };
    // The low-sun view of the demo: PSM wins near the camera, the focused map far away.
    let camera = Camera::look_at(
        DVec3::new(120.0, 25.0, 190.0),
        DVec3::new(0.0, 5.0, 0.0),
        DVec3::Y,
        lens,
    )
    .unwrap();
    let light = Light::Directional(DirectionalLight::new(DVec3::new(1.0, -0.18, 0.3)).unwrap());
    let sppsm = Technique::Sppsm(Sppsm {
        perspective: PerspectiveMap::Psm(Psm::default()),
        iterations: 1,
    });
    let render =
        |t: &Technique| common::render(&renderer, &scene, t, &camera, &light, 1024, &settings).1;
    let (focused, psm, both) = (
        render(&Technique::Focused(Focused)),
        render(&Technique::Psm(Psm::default())),
        render(&sppsm),
    );
    let (f, p, s) = (
        focused.metrics.unwrap(),
        psm.metrics.unwrap(),
        both.metrics.unwrap(),
    );
    let (mut compared, mut better, mut from_psm) = (0, 0, 0);
    for i in 0..s.area.len() {
        if !(s.lit_facing(i) && f.lit_facing(i) && p.lit_facing(i)) {
            continue;
        }
        compared += 1;
        let best = f.area[i].min(p.area[i]);
        if s.area[i] <= best * 1.01 {
            better += 1;
        }
        if (s.area[i] - p.area[i]).abs() < (s.area[i] - f.area[i]).abs() {
            from_psm += 1;
        }
    }
    println!("{better} of {compared} pixels read the better map; {from_psm} read PSM's");
    assert!(compared > 10_000, "{compared}");
    // (Not quite all: a pixel whose 2x2 quad spans two surfaces has derivatives across the
    // edge, not at a point.)
    assert!(
        better as f64 >= 0.998 * compared as f64,
        "{better} of {compared}"
    );
    // Both maps are in use.
    assert!(
        from_psm > compared / 10 && compared - from_psm > compared / 10,
        "{from_psm}"
    );

    // The tint shows it: red where the perspective map is read, blue elsewhere.
    let tinted = common::render(
        &renderer,
        &scene,
        &sppsm,
        &camera,
        &light,
        1024,
        &RenderSettings {
            tint: true,
            ..settings
        },
    )
    .1;
    let (mut red, mut blue) = (0, 0);
    for (i, px) in tinted.color.chunks_exact(4).enumerate() {
        if !s.measured(i) {
            continue;
        }
        let (r, b) = (px[0] as i32, px[2] as i32);
        red += usize::from(r > b + 20);
        blue += usize::from(b > r + 20);
    }
    println!("tint: {red} red, {blue} blue pixels");
    assert!(red > 1000 && blue > 1000, "{red} red, {blue} blue");
}
