//! Object-ID shadow maps and IDs plus depth (the shadows lecture's "Object ID Shadows" and
//! "Combining Shadow and Object Maps") against the ray-cast oracle, which reports which object
//! the light meets first: object IDs agree between distinct objects away from the outlines the
//! light sees, with no bias at all; an object cannot shadow itself (the limit, asserted); IDs
//! plus depth agree everywhere, self-shadowing included. The aliasing at outlines is measured
//! and printed.

mod common;

use common::{cuboid, light_first, oracle, placed, renderer, square_camera};
use glam::{DMat4, DVec3};
use gnomon::{
    DirectionalLight, DualParaboloid, Focused, Light, MapSettings, PointLight, ShadowTechnique,
    SpotLight, compute_setup,
};
use gnomon_render::{DepthBias, MASK_EMPTY, MASK_LIT, MASK_UNLIT, MapRead, RenderScene};

const SIZE: u32 = 256;
const MAP: u32 = 2048;

/// A concave object: a U of three cuboids in one mesh (it shadows itself).
fn u_shape() -> gnomon_scene::Mesh {
    let mut mesh = gnomon_scene::Mesh::default();
    for (half, at) in [
        (DVec3::new(2.0, 0.4, 1.0), DVec3::new(0.0, 0.4, 0.0)),
        (DVec3::new(0.3, 1.5, 1.0), DVec3::new(-1.7, 2.3, 0.0)),
        (DVec3::new(0.3, 1.5, 1.0), DVec3::new(1.7, 2.3, 0.0)),
    ] {
        let part = cuboid(half).transformed(DMat4::from_translation(at));
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(part.positions);
        mesh.normals.extend(part.normals);
        mesh.indices.extend(part.indices.iter().map(|i| i + base));
    }
    mesh
}

/// A ground slab, a block standing on it, a floating slab, a pillar and a concave U: every
/// object casts and receives (the object-ID model: everything in the light's range is drawn
/// into the map).
fn scene() -> RenderScene {
    RenderScene {
        meshes: vec![
            cuboid(DVec3::new(20.0, 0.5, 20.0)),
            cuboid(DVec3::new(1.5, 2.0, 1.5)),
            cuboid(DVec3::new(1.5, 0.15, 1.0)),
            cuboid(DVec3::new(0.4, 3.0, 0.4)),
            u_shape(),
        ],
        instances: vec![
            placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), true),
            placed("block", 1, DVec3::new(4.0, 2.0, -2.0), true),
            placed("floating", 2, DVec3::new(-3.0, 5.0, 3.0), true),
            placed("pillar", 3, DVec3::new(-5.0, 3.0, -4.0), true),
            placed("u", 4, DVec3::new(1.0, 0.0, 5.0), true),
        ],
    }
}

/// The lights the tests judge: a low sun, a spot above the scene, a lamp among the objects.
fn lights() -> Vec<(&'static str, Light)> {
    vec![
        (
            "sun",
            Light::Directional(DirectionalLight::new(DVec3::new(0.6, -1.0, -0.35)).unwrap()),
        ),
        (
            "spot",
            Light::Spot(
                SpotLight::new(
                    DVec3::new(-6.0, 16.0, 10.0),
                    DVec3::new(0.35, -1.0, -0.5),
                    50.0,
                    60.0,
                )
                .unwrap(),
            ),
        ),
        (
            "lamp",
            Light::Point(PointLight::new(DVec3::new(-2.6, 4.2, 5.0), 60.0).unwrap()),
        ),
    ]
}

fn camera() -> gnomon::Camera {
    square_camera(
        DVec3::new(8.0, 20.0, 24.0),
        DVec3::new(0.0, 1.0, 0.0),
        1.0,
        200.0,
    )
}

/// The frame of `read` on `technique`'s maps (the focused maps: one per face for the lamp)
/// with `bias`, its setup, and the oracle.
fn frame(
    technique: &dyn ShadowTechnique,
    light: &Light,
    read: MapRead,
    bias: DepthBias,
) -> (
    gnomon_render::Frame,
    gnomon::ShadowSetup,
    common::OracleMask,
) {
    let scene = scene();
    let camera = camera();
    let mut renderer = renderer(&scene);
    let setup = compute_setup(
        technique,
        &camera,
        light,
        &scene.bounds().unwrap(),
        MapSettings::with_resolution(MAP),
    )
    .unwrap();
    let settings = gnomon_render::RenderSettings {
        read,
        bias,
        ..common::square_settings(SIZE)
    };
    let frame = renderer.render(&camera, light, &setup, &settings).unwrap();
    (frame, setup, oracle(&scene, &camera, light, SIZE, SIZE))
}

/// No bias of any kind: object IDs compare no depth between objects.
const NO_BIAS: DepthBias = DepthBias {
    constant_world: Some(0.0),
    slope_texels: 0.0,
    max_slope_world: Some(0.0),
    max_slope_texels: 0.0,
    normal_offset_texels: 0.0,
};

/// Whether pixel `i`'s 3x3 neighbourhood in the oracle has one mask value (away from shadow
/// and geometry edges in the image).
fn interior(o: &common::OracleMask, i: usize) -> bool {
    let (w, h) = (o.width as usize, o.height as usize);
    let (x, y) = (i % w, i / w);
    x > 0
        && y > 0
        && x + 1 < w
        && y + 1 < h
        && (0..3).all(|dy| (0..3).all(|dx| o.mask[(y + dy - 1) * w + x + dx - 1] == o.mask[i]))
}

#[test]
fn object_ids_agree_with_the_oracle_between_distinct_objects() {
    let scene = scene();
    for (name, light) in lights() {
        let (frame, setup, exact) = frame(&Focused, &light, MapRead::ObjectId, NO_BIAS);
        // Outlines within two texels of the finest map (a point light's faces share a size).
        let first = light_first(&scene, &light, &exact, &setup.maps[0], 2.0);
        let (mut compared, mut agreeing, mut shadowed) = (0usize, 0usize, 0usize);
        let (mut self_shadowed, mut self_lit) = (0usize, 0usize);
        let (mut outline, mut outline_wrong) = (0usize, 0usize);
        for i in 0..exact.mask.len() {
            if exact.mask[i] == MASK_EMPTY || exact.n_dot_l[i] <= 0.1 || !interior(&exact, i) {
                continue;
            }
            // Self-shadowed: the light reaches the point's own object first, yet it is dark.
            if exact.mask[i] == MASK_UNLIT
                && exact.in_light[i]
                && first.objects[i] == exact.objects[i]
            {
                self_shadowed += 1;
                self_lit += usize::from(frame.mask[i] == MASK_LIT);
                continue;
            }
            if first.near_outline[i] {
                outline += 1;
                outline_wrong += usize::from(frame.mask[i] != exact.mask[i]);
                continue;
            }
            compared += 1;
            agreeing += usize::from(frame.mask[i] == exact.mask[i]);
            shadowed += usize::from(exact.mask[i] == MASK_UNLIT);
        }
        let share = agreeing as f64 / compared as f64;
        println!(
            "{name}: object IDs agree on {:.3}% of {compared} pixels ({shadowed} shadowed); \
             near outlines {outline_wrong} of {outline} wrong; {self_lit} of {self_shadowed} \
             self-shadowed pixels lit",
            100.0 * share
        );
        assert!(
            compared > 10_000 && shadowed > 300,
            "{name}: {compared} {shadowed}"
        );
        assert!(share >= 0.995, "{name}: {share} of {compared} agree");
        // The limit: the concave U does not shadow itself.
        assert!(
            self_shadowed > 50,
            "{name}: {self_shadowed} self-shadowed pixels"
        );
        assert!(
            self_lit * 10 >= self_shadowed * 9,
            "{name}: {self_lit} of {self_shadowed} self-shadowed pixels read lit"
        );
    }
}

#[test]
fn ids_and_depth_agree_with_the_oracle_everywhere() {
    let scene = scene();
    for (name, light) in lights() {
        let (frame, setup, exact) = frame(&Focused, &light, MapRead::IdDepth, DepthBias::default());
        let agreement = common::agreement(&frame, &exact, 0.1);
        let first = light_first(&scene, &light, &exact, &setup.maps[0], 2.0);
        // The U's shadows on itself are found (the depth within one object).
        let (mut self_shadowed, mut found) = (0usize, 0usize);
        for i in 0..exact.mask.len() {
            if exact.mask[i] == MASK_UNLIT
                && exact.in_light[i]
                && exact.n_dot_l[i] > 0.1
                && interior(&exact, i)
                && first.objects[i] == exact.objects[i]
            {
                self_shadowed += 1;
                found += usize::from(frame.mask[i] == MASK_UNLIT);
            }
        }
        println!(
            "{name}: IDs and depth agree on {:.3}% of {} pixels ({} shadowed); {found} of \
             {self_shadowed} self-shadowed pixels shadowed",
            100.0 * agreement.fraction(),
            agreement.compared,
            agreement.shadowed
        );
        assert!(
            agreement.compared > 10_000 && agreement.shadowed > 300,
            "{name}: {agreement:?}"
        );
        assert!(agreement.fraction() >= 0.99, "{name}: {agreement:?}");
        assert!(
            self_shadowed > 50 && found * 10 >= self_shadowed * 9,
            "{name}: {found} of {self_shadowed}"
        );
    }
}

/// The lamp's dual paraboloid maps write IDs too (the exact paraboloid pass's ID entry points):
/// IDs and depth agree with the oracle as the cube faces do.
#[test]
fn paraboloid_maps_write_ids_and_depth() {
    let lamp = &lights()[2].1;
    for read in [MapRead::IdDepth, MapRead::ObjectId] {
        let (frame, _, exact) = frame(&DualParaboloid, lamp, read, DepthBias::default());
        let agreement = common::agreement(&frame, &exact, 0.1);
        println!(
            "lamp, paraboloid, {read:?}: {:.3}% of {} pixels agree ({} shadowed)",
            100.0 * agreement.fraction(),
            agreement.compared,
            agreement.shadowed
        );
        assert!(
            agreement.compared > 10_000 && agreement.shadowed > 300,
            "{read:?}: {agreement:?}"
        );
        // (Object IDs alone miss the U's shadow on itself, the limit the other tests assert:
        // 206 pixels here.)
        assert!(agreement.fraction() >= 0.99, "{read:?}: {agreement:?}");
    }
}
