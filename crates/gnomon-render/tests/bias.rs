//! The default bias: no acne (a plane with no other caster under a grazing light is at most
//! 0.1% shadowed) and no peter-panning (the shadow of a box standing on the plane touches its
//! base), also in a scene modelled in millimetres.

mod common;

use glam::{DMat4, DVec3};
use gnomon::{
    Camera, Cube, DirectionalLight, DualParaboloid, Focused, Light, PointLight, ShadowTechnique,
    SpotLight, Technique, Uniform,
};
use gnomon_render::{Instance, MASK_EMPTY, MASK_UNLIT, RenderScene, RenderSettings};
use gnomon_scene::Shape;

const SIZE: u32 = 256;

fn instance(name: &str, mesh: usize, at: DVec3) -> Instance {
    Instance {
        name: name.into(),
        mesh,
        world_from_object: DMat4::from_translation(at),
        casts: true,
        receives: true,
        color: [0.7, 0.7, 0.7],
    }
}

/// A 100 m plane (a 0.2 m slab whose top is at y = 0), and optionally a 4 m box on it.
fn scene(with_box: bool) -> RenderScene {
    scaled_scene(with_box, 1.0)
}

/// [`scene`] in other units: every length times `unit`.
fn scaled_scene(with_box: bool, unit: f64) -> RenderScene {
    let mut scene = RenderScene {
        meshes: vec![
            Shape::Cuboid {
                half_extents: DVec3::new(50.0, 0.1, 50.0) * unit,
            }
            .mesh(),
            Shape::Cuboid {
                half_extents: DVec3::splat(2.0) * unit,
            }
            .mesh(),
        ],
        instances: vec![instance("ground", 0, DVec3::new(0.0, -0.1, 0.0) * unit)],
    };
    if with_box {
        scene
            .instances
            .push(instance("box", 1, DVec3::new(0.0, 2.0, 0.0) * unit));
    }
    scene
}

fn camera(eye: DVec3, target: DVec3) -> Camera {
    common::square_camera(eye, target, 0.5, 300.0)
}

/// A sun `elevation` degrees above the horizon, travelling along +x (and `z`).
fn sun(elevation: f64, z: f64) -> Light {
    let e = elevation.to_radians();
    Light::Directional(DirectionalLight::new(DVec3::new(e.cos(), -e.sin(), z)).unwrap())
}

/// The focused map's frame of `scene` (1024 maps) and the oracle's mask.
fn focused_with_oracle(
    renderer: &mut gnomon_render::Renderer,
    scene: &RenderScene,
    cam: &Camera,
    light: &Light,
    settings: &RenderSettings,
) -> (gnomon_render::Frame, common::OracleMask) {
    with_oracle(renderer, scene, &Focused, cam, light, settings)
}

/// `technique`'s frame of `scene` (1024 maps) and the oracle's mask.
fn with_oracle(
    renderer: &mut gnomon_render::Renderer,
    scene: &RenderScene,
    technique: &dyn ShadowTechnique,
    cam: &Camera,
    light: &Light,
    settings: &RenderSettings,
) -> (gnomon_render::Frame, common::OracleMask) {
    let (_, frame) = common::render(renderer, scene, technique, cam, light, 1024, settings);
    (frame, common::oracle(scene, cam, light, SIZE, SIZE))
}

/// The default bias shrinks with a small scene: the box on the plane modelled in millimetres
/// (every length a thousandth) casts the same shadow as in metres, against the exact shadows,
/// under a 3 and a 45 degree sun. (A 2 cm bias lit the millimetre scene's shadows away.)
#[test]
fn the_default_bias_shrinks_with_a_small_scene() {
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    for unit in [1.0, 1e-3] {
        let scene = scaled_scene(true, unit);
        let mut renderer = common::renderer(&scene);
        let cam = common::square_camera(
            DVec3::new(14.0, 9.0, 10.0) * unit,
            DVec3::new(3.0, 0.0, 0.0) * unit,
            0.5 * unit,
            300.0 * unit,
        );
        for elevation in [3.0f64, 45.0] {
            let light = sun(elevation, 0.3);
            let (frame, oracle) =
                focused_with_oracle(&mut renderer, &scene, &cam, &light, &settings);
            let a = common::agreement(&frame, &oracle, 0.0);
            println!(
                "unit {unit}, sun at {elevation} deg: {:.3}% of {} pixels agree ({} of {} \
                 shadowed found)",
                100.0 * a.fraction(),
                a.compared,
                a.shadowed_agreeing,
                a.shadowed
            );
            assert!(a.compared > 20_000 && a.shadowed > 2_000, "{a:?}");
            assert!(
                a.fraction() >= 0.995 && a.shadow_recall() >= 0.98,
                "unit {unit}, sun at {elevation} deg: {:.3}% agree, {} of {} shadowed found",
                100.0 * a.fraction(),
                a.shadowed_agreeing,
                a.shadowed
            );
        }
    }
}

#[test]
fn grazing_light_on_a_plane_gives_no_acne() {
    let scene = scene(false);
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    let cam = camera(DVec3::new(-30.0, 25.0, 30.0), DVec3::new(5.0, 0.0, -5.0));
    let mut lights: Vec<(String, Light)> = [1.0f64, 3.0, 10.0, 30.0]
        .iter()
        .map(|deg| {
            let e = deg.to_radians();
            (
                format!("sun at {deg} degrees"),
                Light::Directional(
                    DirectionalLight::new(DVec3::new(e.cos(), -e.sin(), 0.3)).unwrap(),
                ),
            )
        })
        .collect();
    lights.push((
        "spot 2 m above the plane".into(),
        Light::Spot(
            SpotLight::new(
                DVec3::new(-40.0, 2.0, 0.0),
                DVec3::new(1.0, -0.05, 0.0),
                60.0,
                150.0,
            )
            .unwrap(),
        ),
    ));
    for technique in [Technique::Focused(Focused), Technique::Uniform(Uniform)] {
        for (name, light) in &lights {
            let (_, frame) = common::render(
                &mut renderer,
                &scene,
                &technique,
                &cam,
                light,
                1024,
                &settings,
            );
            let oracle = common::oracle(&scene, &cam, light, SIZE, SIZE);
            // Plane pixels the light reaches (the oracle: N.L > 0, nothing casts on the plane).
            let lit: Vec<usize> = (0..frame.mask.len())
                .filter(|&i| oracle.mask[i] == gnomon_render::MASK_LIT)
                .collect();
            let shadowed = lit.iter().filter(|&&i| frame.mask[i] == MASK_UNLIT).count();
            let fraction = shadowed as f64 / lit.len() as f64;
            println!(
                "{technique:?}, {name}: {shadowed} of {} lit plane pixels shadowed ({:.4}%)",
                lit.len(),
                100.0 * fraction
            );
            assert!(
                lit.len() > 10_000,
                "{name}: the plane covers too little of the image"
            );
            assert!(
                fraction <= 0.001,
                "{technique:?}, {name}: acne on {:.3}% of the plane",
                100.0 * fraction
            );
        }
    }
}

#[test]
fn shadow_of_a_box_touches_its_base() {
    let scene = scene(true);
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    // The camera looks at the box's +x side, where the shadow of a light travelling +x falls.
    let cam = camera(DVec3::new(14.0, 9.0, 10.0), DVec3::new(3.0, 0.0, 0.0));
    for elevation in [20.0f64, 45.0, 70.0] {
        let light = sun(elevation, 0.0);
        let (frame, oracle) = focused_with_oracle(&mut renderer, &scene, &cam, &light, &settings);
        // Ground points a few centimetres beside the base, on the shadow side: in shadow.
        let clip_from_world = cam.clip_from_world();
        let mut checked = 0;
        for k in 0..=20 {
            let z = -1.8 + 3.6 * k as f64 / 20.0;
            for gap in [0.05, 0.15, 0.3] {
                let p = clip_from_world.project_point3(DVec3::new(2.0 + gap, 0.0, z));
                let (px, py) = (
                    ((p.x + 1.0) * 0.5 * SIZE as f64) as usize,
                    ((1.0 - p.y) * 0.5 * SIZE as f64) as usize,
                );
                let value = frame.mask[py * SIZE as usize + px];
                assert_ne!(value, MASK_EMPTY);
                assert_eq!(
                    value, MASK_UNLIT,
                    "sun at {elevation} deg: ground {gap} m from the base at z = {z} is lit"
                );
                checked += 1;
            }
        }
        // And the whole frame agrees with the exact shadows.
        let a = common::agreement(&frame, &oracle, 0.1);
        println!(
            "sun at {elevation} deg: {checked} base points shadowed; {:.3}% of {} pixels agree",
            100.0 * a.fraction(),
            a.compared
        );
        assert!(a.fraction() >= 0.995);
    }
}

/// The slope-scaled bias alone (no normal offset) keeps tilted and curved receivers free of
/// acne: a slab tilted 35 degrees and a sphere, each lit well (N.L > 0.3) from a moderate
/// angle, are at most 0.2% shadowed where nothing else can cast on them. (A flat plane facing
/// the light needs only the constant bias, so it cannot tell a missing slope bias.)
#[test]
fn tilted_and_curved_receivers_need_no_normal_offset() {
    acne_on_tilted_and_curved_receivers(1.0);
}

/// The same scene 200 times larger (a slab 6 km across, texels of about 10 m): the slope
/// bias's cap grows with the texels (three texel widths), where a cap of 1 m held the slope
/// term to a tenth of a texel and the slab and the sphere were speckled with acne (the
/// suite's terrain was, over its slopes).
#[test]
fn tilted_and_curved_receivers_need_no_normal_offset_at_kilometre_scale() {
    acne_on_tilted_and_curved_receivers(200.0);
}

/// The same under a lamp over the scene, 200 times larger, for both point-light techniques:
/// a dual paraboloid map's depth is a distance along each texel's own direction, and its
/// slope bias's cap grows with the texel's width there too (with a cap of 1 m the slab and
/// the sphere were speckled with acne, as the suite's terrain was under a lamp 4 km up).
#[test]
fn tilted_and_curved_receivers_need_no_normal_offset_under_a_lamp_at_kilometre_scale() {
    let unit = 200.0;
    let lamp =
        Light::Point(PointLight::new(DVec3::new(2.0, 28.0, 6.0) * unit, 100.0 * unit).unwrap());
    let techniques: [(&str, &dyn ShadowTechnique); 2] =
        [("paraboloid", &DualParaboloid), ("cube", &Cube)];
    for (name, technique) in techniques {
        let (shadowed, judged) = acne_under(unit, &lamp, technique);
        println!("{name}: {shadowed} of {judged} well-lit pixels shadowed");
        assert!(judged > 5000, "{name}: {judged} pixels judged");
        assert!(
            shadowed as f64 <= 0.002 * judged as f64,
            "{name}: acne on {shadowed} of {judged} pixels"
        );
    }
}

/// The tilted slab and sphere of the tests above, every length times `unit`: at most 0.2% of
/// their well-lit pixels shadowed under suns 25 and 50 degrees high, without normal offset.
fn acne_on_tilted_and_curved_receivers(unit: f64) {
    for elevation in [25.0f64, 50.0] {
        let (shadowed, judged) = acne_under(unit, &sun(elevation, -0.2), &Focused);
        println!(
            "{unit} m units, sun at {elevation} degrees: {shadowed} of {judged} well-lit pixels shadowed"
        );
        assert!(judged > 5000, "{judged} pixels judged");
        assert!(
            shadowed as f64 <= 0.002 * judged as f64,
            "acne on {:.3}%",
            100.0 * shadowed as f64 / judged as f64
        );
    }
}

/// The tilted slab and sphere, every length times `unit`, under `light` with `technique`'s
/// 1024 maps and no normal offset: how many of the pixels the oracle sees lit at N.L > 0.3
/// the maps shadow, and of how many.
fn acne_under(unit: f64, light: &Light, technique: &dyn ShadowTechnique) -> (usize, usize) {
    let tilt = DMat4::from_rotation_z(35f64.to_radians());
    let scene = RenderScene {
        meshes: vec![
            Shape::Cuboid {
                half_extents: DVec3::new(15.0, 0.2, 15.0) * unit,
            }
            .mesh(),
            Shape::Sphere { radius: 6.0 * unit }.mesh(),
        ],
        instances: vec![
            Instance {
                world_from_object: DMat4::from_translation(DVec3::new(-12.0, 0.0, 0.0) * unit)
                    * tilt,
                ..instance("tilted slab", 0, DVec3::ZERO)
            },
            instance("sphere", 1, DVec3::new(14.0, 0.0, 0.0) * unit),
        ],
    };
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        bias: gnomon_render::DepthBias {
            normal_offset_texels: 0.0,
            ..gnomon_render::DepthBias::default()
        },
        ..RenderSettings::default()
    };
    let cam = common::square_camera(
        DVec3::new(0.0, 30.0, 40.0) * unit,
        DVec3::ZERO,
        0.5 * unit,
        300.0 * unit,
    );
    let (frame, oracle) = with_oracle(&mut renderer, &scene, technique, &cam, light, &settings);
    let judged: Vec<usize> = (0..frame.mask.len())
        .filter(|&i| oracle.mask[i] == gnomon_render::MASK_LIT && oracle.n_dot_l[i] > 0.3)
        .collect();
    let shadowed = judged
        .iter()
        .filter(|&&i| frame.mask[i] == MASK_UNLIT)
        .count();
    (shadowed, judged.len())
}
