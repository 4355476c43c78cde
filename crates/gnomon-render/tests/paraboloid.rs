//! Point-light maps against exact shadows. Dual paraboloid maps are drawn exactly: each texel of a hemisphere holds the distance along
//! its own direction to the nearest triangle that direction meets (the depth pass casts the
//! texel's ray at its triangle), not a triangle drawn with straight edges between its
//! corners' places in the map. A lamp 3 m beside an overhanging block 40 m wide, whose
//! underside lies half a metre below the lamp, shadows the ground behind a row of posts. The
//! underside's two large triangles have their corners near the lower hemisphere's rim: drawn
//! with straight edges between them they cover the directions toward the ground, where the
//! underside's plane lies nearer than the ground, and shadow the whole street (a block of
//! this kind was wrong on half the pixels of a random scene). And a lamp a hand's breadth from
//! a wall does not shine through it.

mod common;

use glam::{DMat4, DVec3};
use gnomon::{
    Camera, Cube, DualParaboloid, Focused, Lens, Light, Lispsm, PointLight, ShadowTechnique,
    SpotLight,
};
use gnomon_render::{RenderScene, RenderSettings};
use gnomon_scene::{SceneLayout, SceneObject, Shape};

const LAMP: DVec3 = DVec3::new(0.0, 2.5, 3.0);

fn street() -> SceneLayout {
    let cuboid = |name: &str, half: DVec3, at: DVec3, casts: bool| SceneObject {
        name: name.into(),
        shape: Shape::Cuboid { half_extents: half },
        world_from_object: DMat4::from_translation(at),
        casts,
        receives: true,
    };
    let mut objects = vec![
        cuboid(
            "ground",
            DVec3::new(60.0, 0.25, 60.0),
            DVec3::new(0.0, -0.25, 0.0),
            false,
        ),
        // The block: its face toward the lamp at z = 0, its underside at y = 2.
        cuboid(
            "block",
            DVec3::new(20.0, 10.0, 4.0),
            DVec3::new(0.0, 12.0, -4.0),
            true,
        ),
    ];
    // Posts between the lamp and the open street, and one leaning on the wall.
    for (k, x) in [-6.0, -2.5, 1.5, 5.0].into_iter().enumerate() {
        objects.push(cuboid(
            &format!("post_{k}"),
            DVec3::new(0.3, 1.5, 0.3),
            DVec3::new(x, 1.5, 7.0 + 0.5 * k as f64),
            true,
        ));
    }
    objects.push(cuboid(
        "crate",
        DVec3::new(0.8, 0.6, 0.8),
        DVec3::new(-3.0, 0.6, 1.0),
        true,
    ));
    SceneLayout {
        name: "wall street".into(),
        objects,
    }
}

#[test]
fn paraboloid_maps_beside_an_overhang_agree_with_exact_shadows() {
    let scene = RenderScene::from_layout(&street());
    let mut renderer = common::renderer(&scene);
    assert!(
        renderer.exact_paraboloids(),
        "lavapipe and llvmpipe have storage buffers in vertex shaders: the exact pass must run"
    );
    let light = Light::Point(PointLight::new(LAMP, 80.0).unwrap());
    // From the street toward the wall, and along the wall (the crate's shadow on it).
    let cameras = [
        (DVec3::new(3.0, 9.0, 22.0), DVec3::new(-1.0, 0.0, 3.0)),
        (DVec3::new(14.0, 4.0, 6.0), DVec3::new(-4.0, 1.0, 1.0)),
    ];
    judge(&scene, &mut renderer, &light, &cameras, POINT_MAPS, 500);
}

/// A lamp inside a closed lantern, 5 cm from its wall, with a range of 80 m: the wall is
/// nearer than a thousandth of the range, where the cube faces' near planes lay until they
/// were moved to a millionth (`SPOT_NEAR_FRACTION`), so the maps clipped it and the light
/// leaked through it onto the ground (a random scene's lamp inside a block was wrong on 8% of
/// its pixels). Everything outside the lantern is in shadow. A spot light there, shining at
/// the wall, has the same near plane and must not leak either.
#[test]
fn a_lamp_by_its_lantern_s_wall_does_not_shine_through_it() {
    let half = DVec3::splat(0.5);
    let centre = DVec3::new(0.0, 2.0, 0.0);
    let mut layout = street();
    layout.objects.truncate(1);
    layout.objects.push(SceneObject {
        name: "lantern".into(),
        shape: Shape::Cuboid { half_extents: half },
        world_from_object: DMat4::from_translation(centre),
        casts: true,
        receives: true,
    });
    let scene = RenderScene::from_layout(&layout);
    let mut renderer = common::renderer(&scene);
    let lamp = centre - DVec3::new(0.0, 0.0, 0.45);
    let light = Light::Point(PointLight::new(lamp, 80.0).unwrap());
    assert!(0.05 < 80.0 * 1e-3 && 0.05 > light_near(&light));
    // Over the ground beyond the wall by the lamp, and beside the lantern.
    let cameras = [
        (DVec3::new(2.0, 4.0, 6.0), DVec3::new(0.0, 0.0, -6.0)),
        (DVec3::new(-7.0, 3.0, -7.0), DVec3::new(0.0, 0.0, -2.0)),
    ];
    judge(&scene, &mut renderer, &light, &cameras, POINT_MAPS, 5_000);
    let spot = Light::Spot(SpotLight::new(lamp, DVec3::new(0.2, -0.5, -1.0), 60.0, 80.0).unwrap());
    let spot_maps: &[(&str, &dyn ShadowTechnique)] =
        &[("focused", &Focused), ("lispsm", &Lispsm::default())];
    judge(
        &scene,
        &mut renderer,
        &spot,
        &cameras[..1],
        spot_maps,
        5_000,
    );
}

/// The point-light techniques `judge` compares by default.
const POINT_MAPS: &[(&str, &dyn ShadowTechnique)] =
    &[("paraboloid", &DualParaboloid), ("cube", &Cube)];

fn light_near(light: &Light) -> f64 {
    match light {
        Light::Point(point) => point.near(),
        _ => unreachable!("a point light"),
    }
}

/// Renders `scene` under `light` from each camera (eye, target) with each of `techniques`
/// and requires 99.5% agreement with the oracle and 95% of its shadow found, over at least
/// `min_shadowed` shadowed pixels.
fn judge(
    scene: &RenderScene,
    renderer: &mut gnomon_render::Renderer,
    light: &Light,
    cameras: &[(DVec3, DVec3)],
    techniques: &[(&str, &dyn ShadowTechnique)],
    min_shadowed: usize,
) {
    let (width, height) = (320, 240);
    let settings = RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    };
    let lens = Lens {
        fov_y_degrees: 70.0,
        aspect: width as f64 / height as f64,
        near: 0.5,
        far: 200.0,
    };
    for &(eye, target) in cameras {
        let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
        let oracle = common::oracle(scene, &camera, light, width, height);
        for &(name, technique) in techniques {
            let (_, frame) =
                common::render(renderer, scene, technique, &camera, light, 1024, &settings);
            let a = common::agreement(&frame, &oracle, 0.1);
            println!(
                "eye {eye}: {name} {:.3}% of {} pixels agree ({} shadowed, {} found)",
                100.0 * a.fraction(),
                a.compared,
                a.shadowed,
                a.shadowed_agreeing
            );
            assert!(
                a.compared > 10_000,
                "too few pixels judged ({})",
                a.compared
            );
            assert!(
                a.shadowed > min_shadowed,
                "too little shadow judged ({})",
                a.shadowed
            );
            assert!(
                a.fraction() >= 0.995 && a.shadow_recall() >= 0.95,
                "eye {eye}: {name} agrees on {:.3}% ({} of {} shadowed pixels found)",
                100.0 * a.fraction(),
                a.shadowed_agreeing,
                a.shadowed
            );
        }
    }
}
