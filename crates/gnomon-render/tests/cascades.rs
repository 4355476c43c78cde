//! Cascades in the renderer: shadows end at the shadow distance (nothing beyond it is
//! shadowed; before it the one-tap mask agrees with the oracle, in the last 10% too, where
//! only the picture fades), the ground at a cascade's edge keeps its shadow under a low sun,
//! and stable cascades' pixels read the finest map that holds them (the tint shows the map).

mod common;

use glam::DVec3;
use gnomon::{CascadeFit, Cascades, DirectionalLight, Light, MapSelection, Technique};
use gnomon_render::{MASK_LIT, MASK_UNLIT, RenderScene, RenderSettings};

/// A long ground and a row of 12 m posts along the view, every 10 m from 10 to 190 m.
fn street() -> RenderScene {
    let mut meshes = vec![common::cuboid(DVec3::new(40.0, 0.5, 200.0))];
    let mut instances = vec![common::placed(
        "ground",
        0,
        DVec3::new(0.0, -0.5, -100.0),
        false,
    )];
    meshes.push(common::cuboid(DVec3::new(1.0, 6.0, 1.0)));
    for k in 1..20 {
        let at = DVec3::new(3.0, 6.0, -10.0 * k as f64);
        instances.push(common::placed(&format!("post {k}"), 1, at, true));
    }
    RenderScene { meshes, instances }
}

/// A camera at `eye` looking at `target`, up +Y, `fov_y_degrees` high, with the aspect of a
/// `size` image and the `(near, far)` planes.
fn camera(
    eye: DVec3,
    target: DVec3,
    fov_y_degrees: f64,
    size: (u32, u32),
    (near, far): (f64, f64),
) -> gnomon::Camera {
    let lens = gnomon::Lens {
        fov_y_degrees,
        aspect: size.0 as f64 / size.1 as f64,
        near,
        far,
    };
    gnomon::Camera::look_at(eye, target, DVec3::Y, lens).unwrap()
}

/// The street seen from 15 m up at 320x240, under a sun from the right (the posts' shadows
/// fall across the street toward -x), with a renderer of it.
struct StreetView {
    scene: RenderScene,
    renderer: gnomon_render::Renderer,
    camera: gnomon::Camera,
    light: Light,
    settings: RenderSettings,
}

fn street_view() -> StreetView {
    let scene = street();
    let renderer = common::renderer(&scene);
    let (width, height) = (320, 240);
    StreetView {
        camera: camera(
            DVec3::new(0.0, 15.0, 5.0),
            DVec3::new(0.0, 0.0, -100.0),
            50.0,
            (width, height),
            (0.5, 300.0),
        ),
        light: Light::Directional(DirectionalLight::new(DVec3::new(-1.0, -0.7, 0.1)).unwrap()),
        settings: RenderSettings {
            width,
            height,
            ..RenderSettings::default()
        },
        scene,
        renderer,
    }
}

/// The ray through pixel `(x, y)`'s centre of a `size` image, scaled to view depth 1
/// (forward . d = 1).
fn pixel_ray(camera: &gnomon::Camera, (x, y): (u32, u32), (width, height): (u32, u32)) -> DVec3 {
    let tan_y = (0.5 * camera.lens().fov_y_degrees).to_radians().tan();
    let ndc_x = (2.0 * x as f64 + 1.0) / width as f64 - 1.0;
    let ndc_y = 1.0 - (2.0 * y as f64 + 1.0) / height as f64;
    camera.forward()
        + camera.right() * (ndc_x * tan_y * camera.lens().aspect)
        + camera.up() * (ndc_y * tan_y)
}

#[test]
fn nothing_is_shadowed_beyond_the_shadow_distance() {
    let StreetView {
        scene,
        mut renderer,
        camera,
        light,
        settings,
    } = street_view();
    let (width, height) = (settings.width, settings.height);
    let distance = 50.0;
    let technique = Technique::Cascades(Cascades {
        shadow_distance: Some(distance),
        fit: CascadeFit::Focused,
        ..Cascades::default()
    });
    let (setup, frame) = common::render(
        &mut renderer,
        &scene,
        &technique,
        &camera,
        &light,
        2048,
        &settings,
    );
    let MapSelection::Cascades(slices) = setup.selection else {
        panic!("{:?}", setup.selection);
    };
    assert_eq!(slices.shadow_distance(), distance);
    let oracle = common::oracle(&scene, &camera, &light, width, height);
    // Each ground pixel's view depth, from the ray through its centre.
    let (mut near_shadowed, mut near_agree, mut far_shadowed, mut far_lit) = (0, 0, 0, 0);
    let (mut band_shadowed, mut band_agree) = (0, 0);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let d = pixel_ray(&camera, (x, y), (width, height));
            // Shadowed in the oracle, on a surface facing the light (the ground: the posts'
            // faces the camera sees face away from the sun).
            if d.y >= 0.0 || oracle.mask[i] != 0 || oracle.n_dot_l[i] <= 0.1 {
                continue;
            }
            // On the ground (y = 0) at view depth t (forward . d = 1).
            let t = -camera.eye().y / d.y;
            if t < 0.85 * distance {
                near_shadowed += 1;
                near_agree += usize::from(frame.mask[i] == MASK_UNLIT);
            } else if (0.91 * distance..0.99 * distance).contains(&t) {
                band_shadowed += 1;
                band_agree += usize::from(frame.mask[i] == MASK_UNLIT);
            } else if t > 1.02 * distance {
                far_shadowed += 1;
                far_lit += usize::from(frame.mask[i] == MASK_LIT);
            }
        }
    }
    println!(
        "near: {near_agree} of {near_shadowed} shadowed; fade band: {band_agree} of \
         {band_shadowed} shadowed; far: {far_lit} of {far_shadowed} lit"
    );
    assert!(
        near_shadowed > 200 && band_shadowed > 20 && far_shadowed > 50,
        "{near_shadowed} {band_shadowed} {far_shadowed}"
    );
    assert!(
        band_agree * 100 >= band_shadowed * 97,
        "{band_agree} of {band_shadowed}"
    );
    assert!(
        near_agree * 100 >= near_shadowed * 97,
        "{near_agree} of {near_shadowed}"
    );
    assert_eq!(far_lit, far_shadowed);
}

/// The ground nearest the camera lies at the edge of the first cascade's map, and under a low
/// sun a map is fine along the world's up. The normal offset moves a lookup along the
/// ground's normal (up): measured by the texel's largest side, it ran several of those fine
/// texels past the edge into the cleared border, and the ground there read as lit (random
/// scene 227: 3.8% of the pixels missed their shadow). Here a wall ahead shadows all the
/// ground between it and the camera, the sun 6.5 degrees high beyond it: every interior
/// ground pixel agrees with the oracle, the nearest rows too.
#[test]
fn the_ground_at_the_edge_of_a_cascade_keeps_its_shadow_under_a_low_sun() {
    let scene = RenderScene {
        meshes: vec![
            common::cuboid(DVec3::new(150.0, 0.5, 150.0)),
            common::cuboid(DVec3::new(60.0, 5.0, 0.5)),
        ],
        instances: vec![
            common::placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), false),
            common::placed("wall", 1, DVec3::new(0.0, 5.0, -40.0), true),
        ],
    };
    let mut renderer = common::renderer(&scene);
    let (width, height) = (320, 180);
    let camera = camera(
        DVec3::new(0.0, 1.7, 0.0),
        DVec3::new(0.0, 1.7, -100.0),
        60.0,
        (width, height),
        (0.1, 100.0),
    );
    // Travelling toward the camera, 6.5 degrees down: the wall's shadow reaches past it.
    let elevation = 6.5f64.to_radians();
    let light = Light::Directional(
        DirectionalLight::new(DVec3::new(
            0.2 * elevation.cos(),
            -elevation.sin(),
            elevation.cos(),
        ))
        .unwrap(),
    );
    let settings = RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    };
    let oracle = common::oracle(&scene, &camera, &light, width, height);
    for technique in [
        Technique::Cascades(Cascades {
            equal_texels: true,
            blend: 0.0,
            ..Cascades::default()
        }),
        Technique::Cascades(Cascades {
            fit: CascadeFit::Focused,
            equal_texels: true,
            blend: 0.0,
            ..Cascades::default()
        }),
    ] {
        let (_, frame) = common::render(
            &mut renderer,
            &scene,
            &technique,
            &camera,
            &light,
            1024,
            &settings,
        );
        let mut ground = 0;
        let mut lit = 0;
        for i in 0..frame.mask.len() {
            if common::interior_at_height(&oracle, i, 0.0) {
                assert_eq!(
                    oracle.mask[i], MASK_UNLIT,
                    "the wall shadows all the ground seen"
                );
                ground += 1;
                lit += usize::from(frame.mask[i] == MASK_LIT);
            }
        }
        println!("{technique:?}: {lit} of {ground} ground pixels read lit");
        assert!(ground > 10_000, "{ground} ground pixels");
        assert!(
            lit == 0,
            "{lit} of {ground} shadowed ground pixels read lit"
        );
    }
}

/// Stable cascades picked by coverage: each ground pixel reads the map the core picks for its
/// point (`MapSelection::map_for`, shown by the tint), which for a good share of the pixels is
/// a nearer slice's (finer) map than their view depth's, and the one-tap mask agrees with the
/// oracle.
#[test]
fn stable_cascades_read_the_finest_map_that_holds_a_point() {
    let StreetView {
        scene,
        mut renderer,
        camera,
        light,
        settings,
    } = street_view();
    let (width, height) = (settings.width, settings.height);
    let technique = Technique::Cascades(Cascades {
        stable: true,
        blend: 0.0,
        ..Cascades::default()
    });
    let tinted = RenderSettings {
        tint: true,
        ..settings
    };
    let (setup, frame) = common::render(
        &mut renderer,
        &scene,
        &technique,
        &camera,
        &light,
        1024,
        &tinted,
    );
    let MapSelection::Cascades(slices) = setup.selection else {
        panic!("{:?}", setup.selection);
    };
    assert!(slices.by_coverage, "stable cascades pick by coverage");
    // The shader's palette for maps 0 to 3, as directions in colour space.
    let palette = [
        [0.55, 0.7, 1.0],
        [1.0, 0.55, 0.5],
        [0.55, 1.0, 0.55],
        [1.0, 0.9, 0.45],
    ]
    .map(|c| DVec3::from_array(c).normalize());
    let (mut ground, mut agree, mut finer) = (0, 0, 0);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let d = pixel_ray(&camera, (x, y), (width, height));
            let t = -camera.eye().y / d.y;
            let p = camera.eye() + d * t;
            // Lit ground on the street (|x| < 30) clear of the posts (they stand at x = 2 to
            // 4), within the shadow distance.
            if d.y >= 0.0 || p.x.abs() > 30.0 || p.x > 1.0 || t > 290.0 || frame.mask[i] != MASK_LIT
            {
                continue;
            }
            let px = &frame.color[4 * i..4 * i + 3];
            let colour = DVec3::new(px[0] as f64, px[1] as f64, px[2] as f64).normalize();
            let read = (0..setup.maps.len())
                .max_by(|a, b| colour.dot(palette[*a]).total_cmp(&colour.dot(palette[*b])))
                .unwrap();
            let expected = setup.map_for(p).unwrap();
            ground += 1;
            agree += usize::from(read == expected);
            finer += usize::from(expected < slices.slice_of(t));
        }
    }
    println!("{agree} of {ground} ground pixels read the core's map, {finer} a finer one");
    assert!(ground > 10_000, "{ground}");
    assert!(agree * 1000 >= ground * 995, "{agree} of {ground}");
    assert!(finer * 10 >= ground, "{finer} of {ground}");
    // The one-tap mask (untinted) against the oracle, over the interior pixels.
    let (_, frame) = common::render(
        &mut renderer,
        &scene,
        &technique,
        &camera,
        &light,
        1024,
        &settings,
    );
    let oracle = common::oracle(&scene, &camera, &light, width, height);
    let (mut judged, mut same) = (0, 0);
    for i in 0..frame.mask.len() {
        if common::interior_at_height(&oracle, i, 0.0) {
            judged += 1;
            same += usize::from(frame.mask[i] == oracle.mask[i]);
        }
    }
    println!("{same} of {judged} interior ground pixels agree with the oracle");
    assert!(
        judged > 10_000 && same * 100 >= judged * 99,
        "{same} of {judged}"
    );
}
