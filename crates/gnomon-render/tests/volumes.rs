//! Stenciled shadow volumes against the ray-cast oracle: exact to the pixel (at least 99.9%
//! of the pixels with N.L > 0.1 away from lit/shadow boundaries agree), directional and spot
//! lights, the demo scene and real meshes (the bunny and a knot, fetched by
//! scripts/fetch-meshes.sh), including a camera standing inside a shadow volume and casters
//! cut by the near plane, where z-fail and the per-caster choice stay exact and z-pass is
//! wrong; several lights add up.

mod common;

use std::path::PathBuf;

use glam::DVec3;
use gnomon::{Camera, DirectionalLight, Light, SpotLight};
use gnomon_render::{RenderScene, RenderSettings, Renderer, StencilMode};
use gnomon_scene::Mesh;

const SIZE: u32 = 256;

/// A ground slab and a 40 m tower at the origin.
fn tower_scene() -> RenderScene {
    common::box_on_ground(100.0, "tower", DVec3::new(5.0, 20.0, 5.0), DVec3::ZERO)
}

fn sun(x: f64, y: f64, z: f64) -> Light {
    Light::Directional(DirectionalLight::new(DVec3::new(x, y, z)).unwrap())
}

#[test]
fn volumes_agree_with_exact_shadows() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    // A camera standing in a tower's shadow, low on the ground (its own scene, so that the
    // view is known): the near plane cuts the tower's volume.
    let low_sun = DVec3::new(1.0, -0.5, 0.3).normalize();
    let away = DVec3::new(low_sun.x, 0.0, low_sun.z).normalize();
    let eye_in_shadow = away * 20.0 + DVec3::Y * 1.5;
    let views = [
        (
            "overview, high sun",
            common::square_camera(DVec3::new(230.0, 200.0, 230.0), DVec3::ZERO, 1.0, 800.0),
            sun(0.5, -1.0, 0.3),
        ),
        (
            "city, spot light",
            common::square_camera(
                DVec3::new(-40.0, 150.0, 120.0),
                DVec3::new(0.0, 0.0, -10.0),
                1.0,
                500.0,
            ),
            Light::Spot(
                SpotLight::new(
                    DVec3::new(10.0, 90.0, 30.0),
                    DVec3::new(-0.1, -1.0, -0.3),
                    50.0,
                    400.0,
                )
                .unwrap(),
            ),
        ),
        (
            "camera inside a shadow volume",
            // Looking down across the shadow's edge, so that the view holds lit ground too.
            common::square_camera(
                eye_in_shadow,
                eye_in_shadow + away.cross(DVec3::Y) * 16.0 - DVec3::Y * 6.0,
                0.5,
                600.0,
            ),
            Light::Directional(DirectionalLight::new(low_sun).unwrap()),
        ),
    ];
    let tower = tower_scene();
    let mut tower_renderer = common::renderer(&tower);
    let mut failures = Vec::new();
    for (name, camera, light) in &views {
        let (scene, renderer) = if name.contains("inside") {
            (&tower, &mut tower_renderer)
        } else {
            (&scene, &mut renderer)
        };
        let inside = name.contains("inside");
        failures.extend(compare_modes(renderer, scene, name, camera, light, inside));
    }
    assert!(failures.is_empty(), "below 99.9%: {failures:?}");
}

/// The exact volumes lit by a point light (the core's extrusion from its position) agree with
/// the oracle in every named point-light view of the demo, with each counting.
#[test]
fn point_light_volumes_agree_with_exact_shadows() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let mut failures = Vec::new();
    let mut lamps = 0;
    for view in gnomon_scene::DEMO_VIEWS {
        let (camera, light) = view.camera_and_light(1.0).unwrap();
        if !matches!(light, Light::Point(_)) {
            continue;
        }
        lamps += 1;
        failures.extend(compare_modes(
            &mut renderer,
            &scene,
            view.name,
            &camera,
            &light,
            false,
        ));
    }
    assert_eq!(lamps, 3);
    assert!(failures.is_empty(), "below 99.9%: {failures:?}");
}

/// Renders a view with z-fail, z-pass and per caster and compares each with the oracle.
/// Returns the failures: z-fail or per caster below 99.9%; z-pass below 99.9% where
/// `z_pass_wrong` is false, or above 99% where it is true (a volume reaches the near plane).
fn compare_modes(
    renderer: &mut Renderer,
    scene: &RenderScene,
    name: &str,
    camera: &Camera,
    light: &Light,
    z_pass_wrong: bool,
) -> Vec<String> {
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    let oracle = common::oracle(scene, camera, light, SIZE, SIZE);
    let mut failures = Vec::new();
    let mut line = format!("{name}:");
    let mut compared = (0, 0);
    for mode in [
        StencilMode::ZFail,
        StencilMode::ZPass,
        StencilMode::PerCaster,
    ] {
        let drawn = renderer
            .render_volumes(camera, light, &settings, mode)
            .unwrap();
        let a = common::agreement(&drawn.frame, &oracle, 0.1);
        line += &format!(
            " {mode:?} {:.3}% ({} z-fail, {} z-pass casters);",
            100.0 * a.fraction(),
            drawn.stats.z_fail_casters,
            drawn.stats.z_pass_casters
        );
        assert!(a.compared > 3000, "{name}: {} pixels compared", a.compared);
        assert!(a.shadowed > 100, "{name}: {} shadowed", a.shadowed);
        assert!(
            a.compared - a.shadowed > 100,
            "{name}: {} lit",
            a.compared - a.shadowed
        );
        compared = (a.compared, a.shadowed);
        if mode == StencilMode::ZPass && z_pass_wrong {
            if a.fraction() > 0.99 {
                failures.push(format!(
                    "{name}: z-pass agreed {:.3}% though a volume reaches the near plane",
                    100.0 * a.fraction()
                ));
            }
        } else if a.fraction() < 0.999 {
            failures.push(format!("{name} ({mode:?}): {:.3}%", 100.0 * a.fraction()));
        }
        if mode == StencilMode::PerCaster && z_pass_wrong && drawn.stats.z_fail_casters == 0 {
            failures.push(format!("{name}: no caster sent to z-fail"));
        }
    }
    println!(
        "{line} of {} pixels ({} shadowed in the oracle)",
        compared.0, compared.1
    );
    failures
}

/// Where the real meshes are: $GNOMON_MESH_DIR, else assets/meshes/ at the workspace root.
fn mesh_dir() -> PathBuf {
    std::env::var_os("GNOMON_MESH_DIR").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes"),
        PathBuf::from,
    )
}

/// A real mesh; fails (never skips) when it has not been fetched.
fn real_mesh(file: &str) -> Mesh {
    let path = mesh_dir().join(file);
    Mesh::load(&path)
        .unwrap_or_else(|e| panic!("{e}: run scripts/fetch-meshes.sh first (scripts/test.sh does)"))
}

#[test]
fn real_meshes_agree_with_exact_shadows() {
    let mut failures = Vec::new();
    for file in ["bunny00.off", "knot1.off"] {
        let mesh = real_mesh(file);
        // 10 m tall, standing at the origin; about 10 m across.
        let scene = RenderScene::mesh_on_ground(file, mesh, 10.0).unwrap();
        let mut renderer = common::renderer(&scene);
        let views = [
            (
                "oblique, sun",
                common::square_camera(
                    DVec3::new(14.0, 12.0, 20.0),
                    DVec3::new(0.0, 3.0, 0.0),
                    1.0,
                    200.0,
                ),
                sun(0.5, -1.0, -0.3),
                false,
            ),
            (
                "from above, spot light",
                common::square_camera(
                    DVec3::new(-6.0, 25.0, 14.0),
                    DVec3::new(0.0, 2.0, -2.0),
                    1.0,
                    200.0,
                ),
                Light::Spot(
                    SpotLight::new(
                        DVec3::new(8.0, 18.0, 6.0),
                        DVec3::new(-0.5, -1.0, -0.4),
                        50.0,
                        100.0,
                    )
                    .unwrap(),
                ),
                false,
            ),
            (
                "low sun toward the camera",
                common::square_camera(
                    DVec3::new(-3.0, 4.0, 22.0),
                    DVec3::new(0.0, 2.0, 0.0),
                    1.0,
                    200.0,
                ),
                sun(0.2, -0.35, 1.0),
                false,
            ),
            (
                // The near plane (6 m ahead of the eye) cuts the mesh; the sun behind the
                // camera casts the cut mesh's shadow ahead.
                "near plane through the caster",
                common::square_camera(
                    DVec3::new(5.0, 7.0, 7.0),
                    DVec3::new(-3.0, 0.0, -15.0),
                    6.0,
                    200.0,
                ),
                sun(0.3, -1.0, -0.8),
                true,
            ),
        ];
        for (view, camera, light, z_pass_wrong) in &views {
            let name = format!("{file}, {view}");
            failures.extend(compare_modes(
                &mut renderer,
                &scene,
                &name,
                camera,
                light,
                *z_pass_wrong,
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// sRGB-encoded 8 bits to linear.
fn linear(v: u8) -> f64 {
    let c = v as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn several_lights_add_up_each_with_exact_shadows() {
    let scene = RenderScene::mesh_on_ground("knot", real_mesh("knot1.off"), 10.0).unwrap();
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    let camera = common::square_camera(
        DVec3::new(14.0, 12.0, 20.0),
        DVec3::new(0.0, 3.0, 0.0),
        1.0,
        200.0,
    );
    let sun = sun(0.5, -1.0, -0.3);
    let spot = Light::Spot(
        SpotLight::new(
            DVec3::new(-9.0, 16.0, 4.0),
            DVec3::new(0.5, -1.0, -0.2),
            55.0,
            100.0,
        )
        .unwrap(),
    );
    // A spot light pointing at the sky lights nothing: the ambient term alone.
    let none =
        Light::Spot(SpotLight::new(DVec3::new(0.0, 50.0, 0.0), DVec3::Y, 10.0, 100.0).unwrap());
    let mut render = |lights: &[Light]| {
        renderer
            .render_volumes_lit_by(&camera, lights, &settings, StencilMode::PerCaster)
            .unwrap()
    };
    let both = render(&[sun, spot]);
    let (only_sun, only_spot, ambient) = (render(&[sun]), render(&[spot]), render(&[none]));
    assert_eq!(both.frame.light_masks.len(), 2);
    // Each light's mask is its own, and exact.
    for (k, (light, alone)) in [(sun, &only_sun), (spot, &only_spot)].iter().enumerate() {
        assert_eq!(both.frame.light_masks[k], alone.frame.mask, "light {k}");
        let oracle = common::oracle(&scene, &camera, light, SIZE, SIZE);
        let a = common::mask_agreement(&both.frame.light_masks[k], &oracle, 0.1);
        println!(
            "light {k}: {:.3}% of {} pixels ({} shadowed)",
            100.0 * a.fraction(),
            a.compared,
            a.shadowed
        );
        assert!(a.fraction() >= 0.999 && a.shadowed > 100 && a.compared > 3000);
    }
    // The frame's mask: lit by either.
    for (i, m) in both.frame.mask.iter().enumerate() {
        assert_eq!(
            *m,
            both.frame.light_masks[0][i].max(both.frame.light_masks[1][i])
        );
    }
    // Light adds up: both = sun + spot - ambient, in linear colour, to 8-bit rounding.
    let mut off = 0;
    let mut lit_by_both = 0;
    for i in 0..both.frame.color.len() {
        if i % 4 == 3 {
            continue;
        }
        let expected = linear(only_sun.frame.color[i]) + linear(only_spot.frame.color[i])
            - linear(ambient.frame.color[i]);
        // (Where both lights together exceed white, the image clips.)
        let saturated = both.frame.color[i] == 255 && expected > 1.0;
        if !saturated && (linear(both.frame.color[i]) - expected).abs() > 0.01 {
            off += 1;
        }
        lit_by_both += usize::from(
            both.frame.light_masks[0][i / 4] == gnomon_render::MASK_LIT
                && both.frame.light_masks[1][i / 4] == gnomon_render::MASK_LIT,
        );
    }
    println!("colour channels off by more than 0.01: {off}; lit by both: {lit_by_both}");
    assert!(
        lit_by_both > 3000,
        "{lit_by_both} channels lit by both lights"
    );
    assert_eq!(off, 0);
    assert_eq!(both.stats.z_pass_casters + both.stats.z_fail_casters, 2);
}

/// Volumes shade like the shadow maps: the ambient pass plus the light's added direct term
/// give the colours of the maps' single pass (one-tap lookups), for a caster that receives
/// shadows and for one that does not (never shadowed, lit once).
/// The frames of the focused map (`map_size` texels) and of the z-fail volumes, one camera
/// and light.
fn focused_and_volumes(
    renderer: &mut Renderer,
    scene: &RenderScene,
    camera: &Camera,
    light: &Light,
    map_size: u32,
    settings: &RenderSettings,
) -> (gnomon_render::Frame, gnomon_render::Frame) {
    let (_, map) = common::render(
        renderer,
        scene,
        &gnomon::Focused,
        camera,
        light,
        map_size,
        settings,
    );
    let volumes = renderer
        .render_volumes(camera, light, settings, StencilMode::ZFail)
        .unwrap()
        .frame;
    (map, volumes)
}

#[test]
fn volumes_shade_like_the_maps() {
    for receives in [true, false] {
        let mut scene = RenderScene::mesh_on_ground("knot", real_mesh("knot1.off"), 10.0).unwrap();
        scene.instances[1].receives = receives;
        let mut renderer = common::renderer(&scene);
        let settings = RenderSettings {
            width: SIZE,
            height: SIZE,
            filter: gnomon_render::Filter::None,
            ..RenderSettings::default()
        };
        let camera = common::square_camera(
            DVec3::new(14.0, 12.0, 20.0),
            DVec3::new(0.0, 3.0, 0.0),
            1.0,
            200.0,
        );
        let light = sun(0.5, -1.0, -0.3);
        let (map, volumes) =
            focused_and_volumes(&mut renderer, &scene, &camera, &light, 2048, &settings);
        let channels = map.color.len() / 4 * 3;
        let differing = map
            .color
            .iter()
            .zip(&volumes.color)
            .enumerate()
            .filter(|(i, (a, b))| i % 4 != 3 && a.abs_diff(**b) > 2)
            .count();
        println!("receives {receives}: {differing} of {channels} colour channels differ");
        assert!(
            differing * 200 < channels,
            "receives {receives}: {differing} of {channels} channels differ"
        );
    }
}

/// The volumes draw the scene through an infinite projection (their caps at infinity must not
/// be clipped), yet the picture ends at the camera's far plane as the maps' does: a far plane
/// that cuts the ground leaves the same pixels empty in both (the volumes once drew the
/// ground out to the horizon).
#[test]
fn the_volumes_end_at_the_far_plane_as_the_maps_do() {
    let scene = tower_scene();
    let mut renderer = common::renderer(&scene);
    let settings = common::square_settings(SIZE);
    // Eye 10 m up looking down the ground at 45 degrees: the far plane, 14 m away, cuts the
    // ground across the middle of the picture.
    let eye = DVec3::new(-40.0, 10.0, 0.0);
    let camera = common::square_camera(eye, eye + DVec3::new(10.0, -10.0, 0.0), 1.0, 14.0);
    let light = sun(0.5, -1.0, 0.3);
    let (map, volumes) =
        focused_and_volumes(&mut renderer, &scene, &camera, &light, 1024, &settings);
    let empty = |mask: &[u8]| {
        mask.iter()
            .map(|&m| m == gnomon_render::MASK_EMPTY)
            .collect::<Vec<_>>()
    };
    let (map_empty, volumes_empty) = (empty(&map.mask), empty(&volumes.mask));
    let pixels = map_empty.len();
    let map_count = map_empty.iter().filter(|&&e| e).count();
    let differing = map_empty
        .iter()
        .zip(&volumes_empty)
        .filter(|(a, b)| a != b)
        .count();
    println!("{map_count} of {pixels} pixels empty in the map's frame, {differing} differ");
    // The far plane leaves a large part empty (above the cut), and both agree on it up to
    // the cut's row of pixels.
    assert!(map_count > pixels / 5, "{map_count} of {pixels}");
    assert!(
        differing <= 2 * SIZE as usize,
        "{differing} of {pixels} pixels empty in one frame only"
    );
}

/// A spot light and the camera inside a closed caster (the demo's `block_1_1`): its walls are
/// lit from inside, and everything outside it is in its shadow. (The closed volume is built
/// from the light-facing triangles, and inside a closed mesh there are none: the dark cap
/// alone once shadowed every pixel.)
#[test]
fn a_spot_light_inside_a_closed_caster_lights_its_walls() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let camera = common::square_camera(
        DVec3::new(-118.0, 20.0, -118.0),
        DVec3::new(-100.0, 10.0, -118.0),
        1.0,
        800.0,
    );
    let light = Light::Spot(
        SpotLight::new(
            DVec3::new(-118.0, 30.0, -118.0),
            DVec3::new(1.0, -0.5, 0.0),
            60.0,
            100.0,
        )
        .unwrap(),
    );
    let oracle = common::oracle(&scene, &camera, &light, SIZE, SIZE);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    for mode in [StencilMode::ZFail, StencilMode::PerCaster] {
        let drawn = renderer
            .render_volumes(&camera, &light, &settings, mode)
            .unwrap();
        let a = common::agreement(&drawn.frame, &oracle, 0.1);
        println!(
            "{mode:?}: {:.3}% of {} ({} shadowed)",
            100.0 * a.fraction(),
            a.compared,
            a.shadowed
        );
        // The walls the spot faces are lit: many pixels judged, most of them lit.
        assert!(
            a.compared > 5000 && a.compared - a.shadowed > 5000,
            "{mode:?}: {a:?}"
        );
        assert!(a.fraction() >= 0.999, "{mode:?}: {a:?}");
    }
}

/// A light straight down, the camera inside a block looking up at its ceiling, which faces
/// away from the light: every pixel whose surface faces away from the light reads not lit,
/// and the walls edge-on to the light (N.L = 0) too.
#[test]
fn surfaces_facing_away_from_a_light_straight_down_read_not_lit() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let camera = common::square_camera_up(
        DVec3::new(0.0, 5.0, 0.0),
        DVec3::new(0.0, 300.0, 0.0),
        DVec3::new(0.0, 0.0, -1.0),
        1.0,
        800.0,
    );
    let light = Light::Directional(DirectionalLight::new(DVec3::NEG_Y).unwrap());
    let oracle = common::oracle(&scene, &camera, &light, SIZE, SIZE);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    for mode in [StencilMode::ZFail, StencilMode::PerCaster] {
        let drawn = renderer
            .render_volumes(&camera, &light, &settings, mode)
            .unwrap();
        let (mut judged, mut lit) = (0, 0);
        for (i, m) in oracle.mask.iter().enumerate() {
            if *m != gnomon_render::MASK_EMPTY && oracle.n_dot_l[i] <= 1e-9 {
                judged += 1;
                lit += usize::from(drawn.frame.mask[i] == gnomon_render::MASK_LIT);
            }
        }
        println!("{mode:?}: {lit} of {judged} pixels facing away read lit");
        assert!(judged > 10_000, "{mode:?}: only {judged} pixels judged");
        assert_eq!(
            lit, 0,
            "{mode:?}: {lit} of {judged} pixels facing away read lit"
        );
    }
}

/// Per-caster counting with both kinds in one stencil, overlapping: a wall whose shadow holds
/// the camera (z-fail: its volume reaches the near plane) and, inside that shadow, a small
/// box whose own shadow falls there too (z-pass). Where the two overlap the count is 2; with
/// z-fail's increment and decrement swapped the two would cancel there.
#[test]
fn per_caster_counts_add_up_where_z_fail_and_z_pass_shadows_overlap() {
    use common::{cuboid, placed as place};
    let scene = RenderScene {
        meshes: vec![
            cuboid(DVec3::new(60.0, 0.5, 60.0)),
            cuboid(DVec3::new(30.0, 10.0, 0.5)),
            cuboid(DVec3::new(1.0, 0.75, 1.0)),
        ],
        instances: vec![
            place("ground", 0, DVec3::new(0.0, -0.5, 0.0), false),
            place("wall", 1, DVec3::new(0.0, 10.0, 8.5), true),
            place("box", 2, DVec3::new(0.0, 0.75, -3.0), true),
        ],
    };
    let mut renderer = common::renderer(&scene);
    let camera = common::square_camera(
        DVec3::new(0.0, 2.0, 5.0),
        DVec3::new(0.0, 0.0, -10.0),
        1.0,
        200.0,
    );
    // Sideways too, so that the box's own shadow lies beside it, in view.
    let light = Light::Directional(DirectionalLight::new(DVec3::new(1.0, -1.0, -1.0)).unwrap());
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        ..RenderSettings::default()
    };
    let oracle = common::oracle(&scene, &camera, &light, SIZE, SIZE);
    let drawn = renderer
        .render_volumes(&camera, &light, &settings, StencilMode::PerCaster)
        .unwrap();
    assert!(
        drawn.stats.z_fail_casters >= 1 && drawn.stats.z_pass_casters >= 1,
        "{:?}",
        drawn.stats
    );
    let a = common::agreement(&drawn.frame, &oracle, 0.1);
    println!(
        "{:.3}% of {} ({} shadowed)",
        100.0 * a.fraction(),
        a.compared,
        a.shadowed
    );
    assert!(a.shadowed > 5000, "{a:?}");
    assert!(a.fraction() >= 0.999, "{a:?}");
}
