//! The plugin inside a Bevy app without a renderer: what it writes into Bevy's cascades,
//! against gnomon's own setup of the same camera, light and boxes.

use bevy::camera::primitives::Aabb as BevyAabb;
use bevy::camera::{Camera, Camera3d, PerspectiveProjection, Projection};
use bevy::light::cascade::{CascadeShadowConfig, Cascades as BevyCascades};
use bevy::light::{DirectionalLight, NotShadowCaster, NotShadowReceiver};
use bevy::math::{Mat4, Vec3, Vec4};
use bevy::mesh::Mesh3d;
use bevy::prelude::*;
use bevy_gnomon::gnomon::{
    self, CascadeFit, CascadeSelect, Cascades, Lens, Light, MapSettings, SceneBounds, Technique,
};
use bevy_gnomon::{GnomonScene, GnomonShadows, GnomonShadowsStatus};
use glam::DVec3;

mod bare;

const EYE: Vec3 = Vec3::new(-30.0, 6.0, -28.0);
const TARGET: Vec3 = Vec3::new(10.0, 0.0, 12.0);
const LIGHT_DIR: Vec3 = Vec3::new(0.45, -0.8, 0.25);
const LENS: (f32, f32, f32, f32) = (60.0, 16.0 / 9.0, 0.5, 200.0);

use bare::app;

/// A ground slab and a grid of boxes of varied heights: `(centre, half extents)`.
fn city() -> Vec<(Vec3, Vec3)> {
    let mut boxes = vec![(Vec3::new(0.0, -0.5, 0.0), Vec3::new(60.0, 0.5, 60.0))];
    for i in 0..8 {
        for j in 0..8 {
            let h = 1.0 + ((i * 7 + j * 3) % 5) as f32 * 1.5;
            let c = Vec3::new(-40.0 + 11.0 * i as f32, h, -40.0 + 11.0 * j as f32);
            boxes.push((c, Vec3::new(2.0, h, 2.0)));
        }
    }
    boxes
}

/// Spawns the boxes as meshes whose local box is the unit cube scaled by the transform.
fn spawn_boxes(app: &mut App, boxes: &[(Vec3, Vec3)]) -> Vec<Entity> {
    boxes
        .iter()
        .map(|&(c, h)| {
            app.world_mut()
                .spawn((
                    Mesh3d::default(),
                    BevyAabb::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0)),
                    Transform::from_translation(c).with_scale(h),
                ))
                .id()
        })
        .collect()
}

fn spawn_camera(app: &mut App, eye: Vec3, target: Vec3, order: isize) -> Entity {
    let (fov, aspect, near, far) = LENS;
    app.world_mut()
        .spawn((
            Camera3d::default(),
            Camera { order, ..default() },
            Projection::Perspective(PerspectiveProjection {
                fov: fov.to_radians(),
                aspect_ratio: aspect,
                near,
                far,
                ..default()
            }),
            Transform::from_translation(eye).looking_at(target, Vec3::Y),
        ))
        .id()
}

fn spawn_light(app: &mut App, shadows: Option<GnomonShadows>) -> Entity {
    let mut light = app.world_mut().spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::default().looking_to(LIGHT_DIR, Vec3::Y),
    ));
    if let Some(s) = shadows {
        light.insert(s);
    }
    light.id()
}

/// A city, one camera and a light, updated once.
fn scene_app(shadows: Option<GnomonShadows>) -> (App, Entity, Entity) {
    let mut app = app(shadows.is_some());
    spawn_boxes(&mut app, &city());
    let camera = spawn_camera(&mut app, EYE, TARGET, 0);
    let light = spawn_light(&mut app, shadows);
    app.update();
    (app, camera, light)
}

/// gnomon's own setup of the same scene, camera and light.
fn gnomon_setup(technique: &Technique, boxes: &[(Vec3, Vec3)]) -> gnomon::ShadowSetup {
    let d = |v: Vec3| DVec3::new(v.x.into(), v.y.into(), v.z.into());
    let aabbs: Vec<_> = boxes
        .iter()
        .map(|&(c, h)| gnomon::Aabb::from_center_half_extents(d(c), d(h)).unwrap())
        .collect();
    let scene = SceneBounds::new(aabbs.clone(), aabbs, None).unwrap();
    let (fov, aspect, near, far) = LENS;
    let lens = Lens {
        fov_y_degrees: f64::from(fov.to_radians()).to_degrees(),
        aspect: aspect.into(),
        near: near.into(),
        far: far.min(150.0).into(),
    };
    let view = Transform::from_translation(EYE).looking_at(TARGET, Vec3::Y);
    let camera =
        gnomon::Camera::look_at(d(EYE), d(EYE + *view.forward()), d(*view.up()), lens).unwrap();
    let light_dir = Transform::default()
        .looking_to(LIGHT_DIR, Vec3::Y)
        .forward();
    let light = Light::Directional(gnomon::DirectionalLight::new(d(*light_dir)).unwrap());
    gnomon::compute_setup(
        technique,
        &camera,
        &light,
        &scene,
        MapSettings::with_resolution(2048),
    )
    .unwrap()
}

fn ndc(m: &Mat4, p: Vec3) -> Vec3 {
    let c = *m * p.extend(1.0);
    c.truncate() / c.w
}

/// Points spread over the city's volume.
fn probes() -> Vec<Vec3> {
    (0..200)
        .map(|i| {
            let t = i as f32;
            Vec3::new(
                ((t * 0.618).fract() - 0.5) * 90.0,
                (t * 0.377).fract() * 10.0,
                ((t * 0.291).fract() - 0.5) * 90.0,
            )
        })
        .collect()
}

fn status(app: &App, light: Entity) -> GnomonShadowsStatus {
    app.world()
        .get::<GnomonShadowsStatus>(light)
        .unwrap()
        .clone()
}

fn cascades_of(app: &App, light: Entity, camera: Entity) -> Vec<bevy::light::cascade::Cascade> {
    app.world().get::<BevyCascades>(light).unwrap().cascades[&camera].clone()
}

#[test]
fn the_default_writes_gnomons_cascades_with_bevys_reversed_depth() {
    let (app, camera, light) = scene_app(Some(GnomonShadows::default()));
    let report = status(&app, light);
    assert_eq!(report.error, None);
    let setup = gnomon_setup(&GnomonShadows::default().technique, &city());
    let written = cascades_of(&app, light, camera);
    assert_eq!(written.len(), setup.maps.len());
    assert_eq!(report.maps, setup.maps.len());
    let mut compared = 0;
    for (bevy_map, map) in written.iter().zip(&setup.maps) {
        for p in probes() {
            let Some(q) = map.project(DVec3::new(p.x.into(), p.y.into(), p.z.into())) else {
                continue;
            };
            if q.z.abs() > 2.0 {
                continue;
            }
            let b = ndc(&bevy_map.clip_from_world, p);
            let tolerance = 1e-3 * (1.0 + q.x.abs().max(q.y.abs()) as f32);
            assert!((b.x - q.x as f32).abs() < tolerance, "x {} vs {}", b.x, q.x);
            assert!((b.y - q.y as f32).abs() < tolerance, "y {} vs {}", b.y, q.y);
            assert!(
                (b.z - (1.0 - q.z as f32)).abs() < 1e-3,
                "z {} vs 1 - {}",
                b.z,
                q.z
            );
            compared += 1;
        }
        // The shadow view's frame: its projection after its view is the same matrix.
        let product = bevy_map.clip_from_cascade * bevy_map.world_from_cascade.inverse();
        assert!(
            product.abs_diff_eq(
                bevy_map.clip_from_world,
                1e-3 * bevy_map
                    .clip_from_world
                    .abs()
                    .to_cols_array()
                    .iter()
                    .cloned()
                    .fold(1.0, f32::max)
            )
        );
    }
    assert!(compared > 100, "{compared} probes compared");
}

#[test]
fn bounds_and_overlap_let_bevy_read_each_map_only_where_it_was_fitted() {
    let (app, camera, light) = scene_app(Some(GnomonShadows::default()));
    let config = app.world().get::<CascadeShadowConfig>(light).unwrap();
    let setup = gnomon_setup(&GnomonShadows::default().technique, &city());
    assert_eq!(config.bounds.len(), setup.maps.len());
    assert_eq!(cascades_of(&app, light, camera).len(), config.bounds.len());
    for (i, map) in setup.maps.iter().enumerate() {
        let [start, end] = map.view_depth_range.unwrap();
        // Bevy reads map i up to its bound.
        assert!((f64::from(config.bounds[i]) - end).abs() < 1e-3 * end);
        if i > 0 {
            // ... and from where it starts blending it in, which the map must cover.
            let band_start = f64::from((1.0 - config.overlap_proportion) * config.bounds[i - 1]);
            assert!(
                band_start >= start - 1e-3,
                "band {band_start} before map start {start}"
            );
            assert!(band_start < end);
        }
    }
    assert!(config.overlap_proportion > 0.0 && config.overlap_proportion < 0.5);
}

#[test]
fn a_caster_is_nearer_the_light_than_what_it_shadows_in_bevys_depth() {
    let (app, camera, light) = scene_app(Some(GnomonShadows::default()));
    let written = cascades_of(&app, light, camera);
    let ground = Vec3::new(0.0, 0.0, 0.0);
    let light_dir = LIGHT_DIR.normalize();
    // A point above the ground along the ray toward the light.
    let caster = ground - light_dir * 5.0;
    for map in &written {
        let (g, c) = (
            ndc(&map.clip_from_world, ground),
            ndc(&map.clip_from_world, caster),
        );
        if g.x.abs() < 1.0 && g.y.abs() < 1.0 && (0.0..=1.0).contains(&g.z) {
            assert!(
                c.z > g.z,
                "reversed depth: caster {} must exceed receiver {}",
                c.z,
                g.z
            );
            assert!(
                (c.x - g.x).abs() < 1e-3 && (c.y - g.y).abs() < 1e-3,
                "same texel"
            );
        }
    }
}

#[test]
fn an_orthographic_fit_gets_its_own_texel_size() {
    let technique = Technique::Focused(gnomon::Focused);
    let shadows = GnomonShadows {
        technique,
        ..default()
    };
    let (app, camera, light) = scene_app(Some(shadows));
    let written = cascades_of(&app, light, camera);
    let setup = gnomon_setup(&technique, &city());
    assert_eq!(written.len(), 1);
    let m = setup.maps[0].clip_from_world;
    // The map spans 2 in x and y over the world lengths 2 / |row|.
    let width = 2.0 / m.row(0).truncate().length();
    let height = 2.0 / m.row(1).truncate().length();
    let expected = (width * height).sqrt() / 2048.0;
    let got = f64::from(written[0].texel_size);
    assert!(
        (got - expected).abs() < 1e-4 * expected,
        "{got} vs {expected}"
    );
}

#[test]
fn a_warped_maps_texel_size_is_measured_inside_the_cascade() {
    let (app, camera, light) = scene_app(Some(GnomonShadows::default()));
    let written = cascades_of(&app, light, camera);
    // LiSPSM cascades: finer near the camera, each positive and finite.
    for c in &written {
        assert!(c.texel_size.is_finite() && c.texel_size > 0.0);
    }
    assert!(
        written
            .windows(2)
            .all(|w| w[0].texel_size < w[1].texel_size)
    );
}

#[test]
fn not_shadow_caster_and_not_shadow_receiver_are_honoured() {
    let mut app = app(true);
    let boxes = city();
    let entities = spawn_boxes(&mut app, &boxes);
    app.world_mut()
        .entity_mut(entities[1])
        .insert(NotShadowCaster);
    app.world_mut()
        .entity_mut(entities[2])
        .insert(NotShadowReceiver);
    app.world_mut()
        .entity_mut(entities[3])
        .insert((NotShadowCaster, NotShadowReceiver));
    spawn_camera(&mut app, EYE, TARGET, 0);
    spawn_light(&mut app, Some(GnomonShadows::default()));
    app.update();
    let scene = app.world().resource::<GnomonScene>();
    let bounds = scene.bounds.as_ref().unwrap();
    assert_eq!(scene.len(), boxes.len() - 1);
    assert_eq!(bounds.casters().len(), boxes.len() - 2);
    assert_eq!(bounds.receivers().len(), boxes.len() - 2);
    // Taking a caster's marker away makes it cast again.
    app.world_mut()
        .entity_mut(entities[1])
        .remove::<NotShadowCaster>();
    app.update();
    let bounds = app
        .world()
        .resource::<GnomonScene>()
        .bounds
        .clone()
        .unwrap();
    assert_eq!(bounds.casters().len(), boxes.len() - 1);
}

#[test]
fn moved_meshes_are_refitted_to_the_same_bounds_as_a_rebuild() {
    let mut app = app(true);
    let mut boxes = city();
    let entities = spawn_boxes(&mut app, &boxes);
    let camera = spawn_camera(&mut app, EYE, TARGET, 0);
    let light = spawn_light(&mut app, Some(GnomonShadows::default()));
    app.update();
    let rebuilds = app.world().resource::<GnomonScene>().rebuilds;
    for (k, &i) in [5usize, 17, 40].iter().enumerate() {
        boxes[i].0 += Vec3::new(3.0, 2.0 + k as f32, -4.0);
        app.world_mut()
            .get_mut::<Transform>(entities[i])
            .unwrap()
            .translation = boxes[i].0;
    }
    app.update();
    let scene = app.world().resource::<GnomonScene>();
    assert_eq!(
        scene.rebuilds, rebuilds,
        "a move refits, it does not rebuild"
    );
    let written = cascades_of(&app, light, camera);

    let (fresh, fresh_camera, fresh_light) = {
        let mut fresh = self::app(true);
        spawn_boxes(&mut fresh, &boxes);
        let c = spawn_camera(&mut fresh, EYE, TARGET, 0);
        let l = spawn_light(&mut fresh, Some(GnomonShadows::default()));
        fresh.update();
        (fresh, c, l)
    };
    let rebuilt = fresh
        .world()
        .resource::<GnomonScene>()
        .bounds
        .clone()
        .unwrap();
    let refitted = scene.bounds.as_ref().unwrap();
    assert_eq!(refitted.casters(), rebuilt.casters());
    assert_eq!(refitted.scene_box(), rebuilt.scene_box());
    let expected = cascades_of(&fresh, fresh_light, fresh_camera);
    for (a, b) in written.iter().zip(&expected) {
        assert_eq!(a.clip_from_world, b.clip_from_world);
    }
}

#[test]
fn added_and_despawned_meshes_rebuild_the_bounds() {
    let (mut app, _, _) = scene_app(Some(GnomonShadows::default()));
    let before = app.world().resource::<GnomonScene>().len();
    let extra = spawn_boxes(&mut app, &[(Vec3::new(70.0, 3.0, 0.0), Vec3::splat(3.0))]);
    app.update();
    let scene = app.world().resource::<GnomonScene>();
    assert_eq!(scene.len(), before + 1);
    assert!(scene.bounds.as_ref().unwrap().scene_box().max().x >= 73.0 - 1e-6);
    app.world_mut().despawn(extra[0]);
    app.update();
    assert_eq!(app.world().resource::<GnomonScene>().len(), before);
}

#[test]
fn techniques_bevy_cannot_draw_are_refused_and_bevys_cascades_kept() {
    let (bevy_app, bevy_camera, bevy_light) = scene_app(None);
    let bevys = cascades_of(&bevy_app, bevy_light, bevy_camera);
    let refused = [
        Technique::Sppsm(Default::default()),
        Technique::Tsm(Default::default()),
        Technique::Psm(Default::default()),
        Technique::Cascades(Cascades {
            fit: CascadeFit::Tsm(Default::default()),
            ..Default::default()
        }),
        Technique::Cascades(Cascades {
            count: 6,
            ..Default::default()
        }),
        Technique::Cascades(Cascades {
            stable: true,
            select: CascadeSelect::Coverage,
            ..Default::default()
        }),
        Technique::Cube(Default::default()),
    ];
    for technique in refused {
        let (app, camera, light) = scene_app(Some(GnomonShadows {
            technique,
            ..default()
        }));
        let report = status(&app, light);
        let error = report.error.expect("refused");
        assert!(error.starts_with("Bevy cannot draw"), "{error}");
        assert!(!error.contains('\n'));
        let kept = cascades_of(&app, light, camera);
        assert_eq!(kept.len(), bevys.len());
        for (a, b) in kept.iter().zip(&bevys) {
            assert_eq!(a.clip_from_world, b.clip_from_world);
        }
    }
}

#[test]
fn every_drawable_fit_is_written() {
    let fits = [
        Technique::Uniform(gnomon::Uniform),
        Technique::Lispsm(Default::default()),
        Technique::Xpsm(Default::default()),
        Technique::Cascades(Cascades {
            fit: CascadeFit::Focused,
            ..Default::default()
        }),
        Technique::Cascades(Cascades {
            fit: CascadeFit::Xpsm(Default::default()),
            count: 3,
            ..Default::default()
        }),
        Technique::Cascades(Cascades {
            stable: true,
            ..Default::default()
        }),
    ];
    for technique in fits {
        let (app, camera, light) = scene_app(Some(GnomonShadows {
            technique,
            ..default()
        }));
        let report = status(&app, light);
        assert_eq!(report.error, None, "{technique:?}");
        let setup = gnomon_setup(
            &match technique {
                Technique::Cascades(c) if c.select == CascadeSelect::Auto => {
                    Technique::Cascades(Cascades {
                        select: CascadeSelect::ViewDepth,
                        ..c
                    })
                }
                t => t,
            },
            &city(),
        );
        let written = cascades_of(&app, light, camera);
        assert_eq!(written.len(), setup.maps.len(), "{technique:?}");
        for (b, m) in written.iter().zip(&setup.maps) {
            let row = |r: Vec4| [r.x, r.y, r.z, r.w].map(f64::from);
            let flipped = m.clip_from_world.row(3) - m.clip_from_world.row(2);
            let got = row(b.clip_from_world.row(2));
            let scale = flipped.abs().max_element().max(1.0);
            for k in 0..4 {
                assert!((got[k] - flipped[k]).abs() < 1e-5 * scale, "{technique:?}");
            }
        }
    }
}

#[test]
fn each_camera_gets_its_own_list_read_by_one_set_of_bounds() {
    let mut app = app(true);
    spawn_boxes(&mut app, &city());
    let first = spawn_camera(&mut app, EYE, TARGET, 0);
    let second = spawn_camera(&mut app, Vec3::new(35.0, 12.0, 30.0), Vec3::ZERO, 1);
    let light = spawn_light(&mut app, Some(GnomonShadows::default()));
    app.update();
    assert_eq!(status(&app, light).error, None);
    let bounds = app
        .world()
        .get::<CascadeShadowConfig>(light)
        .unwrap()
        .bounds
        .clone();
    let (a, b) = (
        cascades_of(&app, light, first),
        cascades_of(&app, light, second),
    );
    assert_eq!(a.len(), bounds.len());
    assert_eq!(b.len(), bounds.len());
    assert_ne!(a[0].clip_from_world, b[0].clip_from_world);
}

#[test]
fn an_orthographic_camera_is_reported_in_one_line() {
    let mut app = app(true);
    spawn_boxes(&mut app, &city());
    app.world_mut().spawn((
        Camera3d::default(),
        Projection::Orthographic(OrthographicProjection::default_3d()),
        Transform::from_translation(EYE).looking_at(TARGET, Vec3::Y),
    ));
    let light = spawn_light(&mut app, Some(GnomonShadows::default()));
    app.update();
    let error = status(&app, light).error.unwrap();
    assert!(error.contains("not perspective"), "{error}");
}

#[test]
fn removing_the_component_gives_bevy_its_own_cascades_back() {
    let (bevy_app, bevy_camera, bevy_light) = scene_app(None);
    let bevys = cascades_of(&bevy_app, bevy_light, bevy_camera);
    let bevy_config = bevy_app
        .world()
        .get::<CascadeShadowConfig>(bevy_light)
        .unwrap()
        .clone();

    let (mut app, camera, light) = scene_app(Some(GnomonShadows::default()));
    assert_ne!(
        app.world()
            .get::<CascadeShadowConfig>(light)
            .unwrap()
            .bounds,
        bevy_config.bounds
    );
    app.world_mut().entity_mut(light).remove::<GnomonShadows>();
    app.update();
    let config = app.world().get::<CascadeShadowConfig>(light).unwrap();
    assert_eq!(config.bounds, bevy_config.bounds);
    assert_eq!(config.overlap_proportion, bevy_config.overlap_proportion);
    let back = cascades_of(&app, light, camera);
    assert_eq!(back.len(), bevys.len());
    for (a, b) in back.iter().zip(&bevys) {
        assert_eq!(a.clip_from_world, b.clip_from_world);
    }
    // And gnomon's again when it comes back.
    app.world_mut()
        .entity_mut(light)
        .insert(GnomonShadows::default());
    app.update();
    assert_eq!(status(&app, light).error, None);
    assert_ne!(
        cascades_of(&app, light, camera)[0].clip_from_world,
        bevys[0].clip_from_world
    );
}

#[test]
fn without_depth_clip_control_warped_fits_are_refused_and_orthographic_ones_drawn() {
    for (technique, drawn) in [
        (GnomonShadows::default().technique, false),
        (Technique::Xpsm(Default::default()), false),
        (
            Technique::Cascades(Cascades {
                fit: CascadeFit::Focused,
                ..Default::default()
            }),
            true,
        ),
        (
            Technique::Cascades(Cascades {
                stable: true,
                ..Default::default()
            }),
            true,
        ),
    ] {
        let mut app = app(true);
        app.insert_resource(bevy_gnomon::DepthClipControl(false));
        spawn_boxes(&mut app, &city());
        spawn_camera(&mut app, EYE, TARGET, 0);
        let light = spawn_light(
            &mut app,
            Some(GnomonShadows {
                technique,
                ..default()
            }),
        );
        app.update();
        let error = status(&app, light).error;
        assert_eq!(error.is_none(), drawn, "{technique:?}: {error:?}");
        if let Some(e) = error {
            assert!(e.contains("DEPTH_CLIP_CONTROL"), "{e}");
        }
    }
}
