//! Planar projected shadows against the ray-cast oracle: exact on the ground where its model
//! holds (casters above the plane), one darkening however many shadows overlap, and the
//! technique's limit (a receiver off the plane gets no shadow) asserted as such.

mod common;

use common::{cuboid, interior_at_height, oracle, placed, renderer, square_camera};
use glam::DVec3;
use gnomon::geometry::Plane;
use gnomon::planar::PlanarReceiver;
use gnomon::{Aabb, DirectionalLight, Light, PointLight, SpotLight};
use gnomon_render::{MASK_EMPTY, MASK_LIT, MASK_UNLIT, RenderScene, RenderSettings};

const SIZE: u32 = 256;

/// A ground slab (top at y = 0, half size 20) with a floating box, a box standing on it and
/// a box floating above that one (which shadows its top face, off the ground's plane).
fn scene() -> RenderScene {
    RenderScene {
        meshes: vec![
            cuboid(DVec3::new(20.0, 0.5, 20.0)),
            cuboid(DVec3::new(2.5, 0.5, 2.0)),
            cuboid(DVec3::new(2.0, 1.5, 2.0)),
            cuboid(DVec3::new(1.0, 0.25, 1.0)),
        ],
        instances: vec![
            placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), true),
            placed("floating", 1, DVec3::new(-6.0, 3.5, 2.0), true),
            placed("block", 2, DVec3::new(6.0, 1.5, -2.0), true),
            placed("lid", 3, DVec3::new(6.0, 5.5, -2.0), true),
        ],
    }
}

fn ground_receiver() -> PlanarReceiver {
    let slab = Aabb::new(DVec3::new(-20.0, -1.0, -20.0), DVec3::new(20.0, 0.0, 20.0)).unwrap();
    PlanarReceiver::new(Plane::through_point(DVec3::ZERO, DVec3::Y), &slab, 1e-9).unwrap()
}

fn settings() -> RenderSettings {
    common::square_settings(SIZE)
}

#[test]
fn planar_shadows_agree_with_the_oracle_on_the_ground() {
    let scene = scene();
    let mut renderer = renderer(&scene);
    let camera = square_camera(
        DVec3::new(4.0, 28.0, 30.0),
        DVec3::new(0.0, 0.0, 0.0),
        1.0,
        200.0,
    );
    let receiver = ground_receiver();
    let lights = [
        Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.3)).unwrap()),
        Light::Point(PointLight::new(DVec3::new(-2.0, 14.0, 6.0), 80.0).unwrap()),
        Light::Spot(
            SpotLight::new(
                DVec3::new(2.0, 16.0, 10.0),
                DVec3::new(-0.1, -1.0, -0.5),
                60.0,
                80.0,
            )
            .unwrap(),
        ),
    ];
    for light in &lights {
        let frame = renderer
            .render_planar_lit_by(&camera, std::slice::from_ref(light), &receiver, &settings())
            .unwrap()
            .frame;
        let exact = oracle(&scene, &camera, light, SIZE, SIZE);
        let (mut compared, mut agreeing, mut shadowed, mut found) = (0, 0, 0, 0);
        for i in 0..exact.mask.len() {
            if exact.mask[i] == MASK_EMPTY
                || exact.n_dot_l[i] <= 0.1
                || !interior_at_height(&exact, i, 0.0)
            {
                continue;
            }
            compared += 1;
            agreeing += usize::from(frame.mask[i] == exact.mask[i]);
            if exact.mask[i] == MASK_UNLIT {
                shadowed += 1;
                found += usize::from(frame.mask[i] == MASK_UNLIT);
            }
        }
        let share = agreeing as f64 / compared as f64;
        assert!(compared > 10_000, "{light:?}: {compared} ground pixels");
        assert!(
            shadowed > 300,
            "{light:?}: {shadowed} shadowed ground pixels"
        );
        assert!(
            share >= 0.995,
            "{light:?}: {share} of {compared} ground pixels agree"
        );
        assert!(
            found as f64 >= 0.99 * shadowed as f64,
            "{light:?}: {found} of {shadowed}"
        );
    }
}

#[test]
fn overlapping_shadows_darken_the_ground_once() {
    // Two boxes at different heights whose shadows overlap under a tilted sun.
    let scene = RenderScene {
        meshes: vec![
            cuboid(DVec3::new(20.0, 0.5, 20.0)),
            cuboid(DVec3::new(2.5, 0.5, 2.0)),
        ],
        instances: vec![
            placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), true),
            placed("low", 1, DVec3::new(-1.5, 2.5, 0.0), true),
            placed("high", 1, DVec3::new(1.5, 5.5, 0.0), true),
        ],
    };
    let mut renderer = renderer(&scene);
    let camera = square_camera(
        DVec3::new(0.0, 30.0, 26.0),
        DVec3::new(0.0, 0.0, 4.0),
        1.0,
        200.0,
    );
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.0, -1.0, 0.8)).unwrap());
    let frame = renderer
        .render_planar_lit_by(&camera, &[sun], &ground_receiver(), &settings())
        .unwrap()
        .frame;
    let exact = oracle(&scene, &camera, &sun, SIZE, SIZE);
    // The shadows on the ground: z shifted by 0.8 per unit of height. The low box spans
    // x in [-4, 1], y in [2, 3]; the high one x in [-1, 4], y in [5, 6].
    let in_low = |p: DVec3| (-4.0..=1.0).contains(&p.x) && (-2.0 + 1.6..=2.0 + 2.4).contains(&p.z);
    let in_high = |p: DVec3| (-1.0..=4.0).contains(&p.x) && (-2.0 + 4.0..=2.0 + 4.8).contains(&p.z);
    let (mut overlap, mut colours) = (0usize, Vec::new());
    for i in 0..frame.mask.len() {
        if frame.mask[i] != MASK_UNLIT || !interior_at_height(&exact, i, 0.0) {
            continue;
        }
        let p = exact.points[i].unwrap();
        overlap += usize::from(in_low(p) && in_high(p));
        colours.push(&frame.color[i * 4..i * 4 + 3]);
    }
    assert!(overlap > 50, "{overlap} pixels where both shadows fall");
    assert!(colours.len() > overlap + 50);
    // Flat ground under ambient light alone: one colour, overlap or not.
    for c in 0..3 {
        let (lo, hi) = colours
            .iter()
            .fold((255u8, 0u8), |(lo, hi), v| (lo.min(v[c]), hi.max(v[c])));
        assert!(hi - lo <= 1, "channel {c}: {lo} to {hi}");
    }
}

#[test]
fn a_receiver_off_the_plane_gets_no_shadow() {
    // The technique's limit: the lid's shadow on the block's top face (y = 3), which the
    // oracle shadows, is lit.
    let scene = scene();
    let mut renderer = renderer(&scene);
    let camera = square_camera(
        DVec3::new(10.0, 24.0, 16.0),
        DVec3::new(6.0, 3.0, -2.0),
        1.0,
        200.0,
    );
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.1, -1.0, 0.05)).unwrap());
    let frame = renderer
        .render_planar_lit_by(&camera, &[sun], &ground_receiver(), &settings())
        .unwrap()
        .frame;
    let exact = oracle(&scene, &camera, &sun, SIZE, SIZE);
    let (mut shadowed, mut lit) = (0, 0);
    for i in 0..exact.mask.len() {
        if exact.mask[i] == MASK_UNLIT && interior_at_height(&exact, i, 3.0) {
            shadowed += 1;
            lit += usize::from(frame.mask[i] == MASK_LIT);
        }
    }
    assert!(
        shadowed > 100,
        "{shadowed} shadowed pixels on the block's top"
    );
    assert_eq!(
        lit, shadowed,
        "planar shadows fall on the ground plane only"
    );
}
