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
use gnomon_render::{Frame, MASK_EMPTY, PixelMetrics, RenderScene, RenderSettings, StencilMode};

#[test]
fn each_pixel_reads_the_map_with_the_better_area_sampling() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
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
    let mut render = |t: &Technique| {
        common::render(&mut renderer, &scene, t, &camera, &light, 1024, &settings).1
    };
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
        &mut renderer,
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

/// p99 (nearest rank) of `values` over the pixels facing the light, as `gnomon compare`
/// reports it.
fn p99(metrics: &PixelMetrics, values: &[f32]) -> f32 {
    let mut v: Vec<f32> = (0..values.len())
        .filter(|&i| metrics.lit_facing(i))
        .map(|i| values[i])
        .collect();
    v.sort_by(f32::total_cmp);
    v[((0.99 * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)]
}

/// The must-show, in every named view of the demo at `gnomon compare`'s settings
/// (640x360, 1024 maps, PSM with 10 iterations): SPPSM's area undersampling p99 (pixels per
/// texel area, the paper's measure) is no worse than that of the better of its two maps alone
/// (focused, PSM), and its wrong pixels against the exact shadow volumes are no more over all
/// views, and within a tenth of the better map's in each.
#[test]
fn every_named_view_is_no_worse_than_the_better_map_alone() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (width, height) = (640, 360);
    let settings = RenderSettings {
        width,
        height,
        metrics: true,
        ..RenderSettings::default()
    };
    let mut totals = [0usize; 3];
    for view in gnomon_scene::DEMO_VIEWS {
        let (camera, light) = view.camera_and_light(width as f64 / height as f64).unwrap();
        if matches!(light, gnomon::Light::Point(_)) {
            // SPPSM takes no point light.
            continue;
        }
        let exact = renderer
            .render_volumes(&camera, &light, &settings, StencilMode::ZFail)
            .unwrap()
            .frame;
        let mut render = |t: &Technique| {
            common::render(&mut renderer, &scene, t, &camera, &light, 1024, &settings).1
        };
        let frames = [
            render(&Technique::Sppsm(Sppsm::default())),
            render(&Technique::Focused(Focused)),
            render(&Technique::Psm(Psm::default())),
        ];
        // Wrong pixels: N.L > 0.1, the map's mask differs from the exact one.
        let wrong = |frame: &Frame| {
            let m = frame.metrics.as_ref().unwrap();
            (0..frame.mask.len())
                .filter(|&i| {
                    let (mine, truth) = (frame.mask[i], exact.mask[i]);
                    mine != MASK_EMPTY && truth != MASK_EMPTY && m.n_dot_l[i] > 0.1 && mine != truth
                })
                .count()
        };
        let counts = frames.each_ref().map(wrong);
        let area = frames.each_ref().map(|f| {
            p99(
                f.metrics.as_ref().unwrap(),
                &f.metrics.as_ref().unwrap().area,
            )
        });
        println!(
            "{}: wrong pixels sppsm {} focused {} psm {}; area p99 {:.3} {:.3} {:.3}",
            view.name, counts[0], counts[1], counts[2], area[0], area[1], area[2]
        );
        for k in 0..3 {
            totals[k] += counts[k];
        }
        assert!(
            area[0] <= area[1].min(area[2]) * 1.001,
            "{}: area p99 {area:?}",
            view.name
        );
        // Wrong pixels per view within a tenth (and ten pixels) of the better map's: which
        // map reads a pixel is chosen by area (the paper's measure), and the few hundred
        // wrong pixels of a view are mostly terminator pixels that the depth bias decides
        // (in low_sun the focused map alone has 246, SPPSM 261, since the normal offset is
        // measured along the normal's image in the map).
        let better = counts[1].min(counts[2]);
        assert!(
            counts[0] as f64 <= 1.1 * better as f64 + 10.0,
            "{}: wrong pixels {counts:?}",
            view.name
        );
    }
    println!("wrong pixels over all views: {totals:?}");
    // Over all views, strictly no worse than either map alone.
    assert!(
        totals[0] <= totals[1].min(totals[2]),
        "wrong pixels over all views {totals:?}"
    );
}
