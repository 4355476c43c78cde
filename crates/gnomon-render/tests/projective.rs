//! Projective texture shadows (the shadows lecture's light maps) against the ray-cast oracle:
//! exact where their model holds (receivers that cast nothing, behind the casters), and the
//! failure mode asserted: a receiver between the light and a caster gets its shadow too.

mod common;

use common::{cuboid, interior_at_height, oracle, placed, renderer, square_camera};
use glam::DVec3;
use gnomon::{DirectionalLight, Focused, Light, MapSettings, compute_setup};
use gnomon_render::{MASK_LIT, MASK_UNLIT, RenderScene, RenderSettings};

const SIZE: u32 = 256;

/// A ground that only receives, a box standing on it and one floating; with `plate`, a
/// plate that only receives floating above the floating box (between it and the sun).
fn scene(plate: bool) -> RenderScene {
    let mut instances = vec![
        placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), false),
        placed("block", 1, DVec3::new(4.0, 2.0, -2.0), true),
        placed("floating", 1, DVec3::new(-4.0, 5.0, 2.0), true),
    ];
    if plate {
        instances.push(placed("plate", 2, DVec3::new(-4.0, 10.0, 2.0), false));
    }
    RenderScene {
        meshes: vec![
            cuboid(DVec3::new(20.0, 0.5, 20.0)),
            cuboid(DVec3::new(1.5, 2.0, 1.5)),
            cuboid(DVec3::new(1.0, 0.1, 1.0)),
        ],
        instances,
    }
}

fn settings() -> RenderSettings {
    RenderSettings {
        read: gnomon_render::MapRead::Coverage,
        ..common::square_settings(SIZE)
    }
}

/// The projective frame of `scene` (focused 2048 maps) and the oracle's mask.
fn frame_and_oracle(
    scene: &RenderScene,
    camera: &gnomon::Camera,
    sun: &Light,
) -> (gnomon_render::Frame, common::OracleMask) {
    let mut renderer = renderer(scene);
    let bounds = scene.bounds().unwrap();
    let setup = compute_setup(
        &Focused,
        camera,
        sun,
        &bounds,
        MapSettings::with_resolution(2048),
    )
    .unwrap();
    let frame = renderer.render(camera, sun, &setup, &settings()).unwrap();
    (frame, oracle(scene, camera, sun, SIZE, SIZE))
}

#[test]
fn projective_shadows_agree_with_the_oracle_on_a_receiver_behind_the_casters() {
    let scene = scene(false);
    let camera = square_camera(DVec3::new(6.0, 26.0, 28.0), DVec3::ZERO, 1.0, 200.0);
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.3)).unwrap());
    let (frame, exact) = frame_and_oracle(&scene, &camera, &sun);
    let (mut compared, mut agreeing, mut shadowed) = (0, 0, 0);
    for i in 0..exact.mask.len() {
        if exact.n_dot_l[i] > 0.1 && interior_at_height(&exact, i, 0.0) {
            compared += 1;
            agreeing += usize::from(frame.mask[i] == exact.mask[i]);
            shadowed += usize::from(exact.mask[i] == MASK_UNLIT);
        }
    }
    let share = agreeing as f64 / compared as f64;
    assert!(compared > 10_000 && shadowed > 300, "{compared} {shadowed}");
    assert!(share >= 0.99, "{share} of {compared} ground pixels agree");
    // The casters are lit: no pixel of the block's sunlit top is shadowed.
    let top = (0..exact.mask.len())
        .filter(|&i| exact.mask[i] == MASK_LIT && interior_at_height(&exact, i, 4.0))
        .collect::<Vec<_>>();
    assert!(top.len() > 50);
    assert!(top.iter().all(|&i| frame.mask[i] == MASK_LIT));
}

#[test]
fn a_receiver_between_the_light_and_a_caster_gets_its_shadow() {
    let scene = scene(true);
    let camera = square_camera(
        DVec3::new(-4.0, 26.0, 22.0),
        DVec3::new(-4.0, 6.0, 2.0),
        1.0,
        200.0,
    );
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.0, -1.0, 0.05)).unwrap());
    let (frame, exact) = frame_and_oracle(&scene, &camera, &sun);
    // The plate's top (y = 10.1) lies above the floating box: lit in fact, shadowed by the
    // light map, which has no depth.
    let plate: Vec<usize> = (0..exact.mask.len())
        .filter(|&i| interior_at_height(&exact, i, 10.1))
        .collect();
    assert!(plate.len() > 100, "{} plate pixels", plate.len());
    assert!(plate.iter().all(|&i| exact.mask[i] == MASK_LIT));
    let shadowed = plate
        .iter()
        .filter(|&&i| frame.mask[i] == MASK_UNLIT)
        .count();
    assert!(
        shadowed * 10 >= plate.len() * 9,
        "{shadowed} of {} plate pixels shadowed",
        plate.len()
    );
}
