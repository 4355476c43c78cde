//! The scene in Bevy: gnomon-scene's meshes as Bevy meshes, one camera, one sun, lit so that
//! a frame's brightness says whether a pixel is in shadow.

use std::path::Path;

use bevy::asset::RenderAssetUsages;
use bevy::camera::{Exposure, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::light::cascade::{CascadeShadowConfig, CascadeShadowConfigBuilder, Cascades};
use bevy::light::{DirectionalLightShadowMap, GlobalAmbientLight};
use bevy::light::{NotShadowCaster, NotShadowReceiver, SimulationLightSystems};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::renderer::RenderDevice;
use bevy::render::settings::WgpuFeatures;
use bevy::render::view::Msaa;
use bevy_gnomon::{DepthClipControl, GnomonShadowSystems, GnomonShadows, GnomonShadowsPlugin};
use glam::DMat4;
use gnomon_scene::{NamedView, SceneFile};

use crate::args::{Options, Shadows};

/// One placed mesh.
pub struct Placed {
    pub mesh: gnomon_scene::Mesh,
    pub world_from_object: DMat4,
    pub casts: bool,
    pub receives: bool,
}

/// A scene's meshes and named views.
pub struct Loaded {
    pub objects: Vec<Placed>,
    pub views: Vec<NamedView>,
}

/// The demo, or a scene file (one line on error).
pub fn load(scene_file: Option<&Path>) -> Result<Loaded, String> {
    let Some(path) = scene_file else {
        let layout = gnomon_scene::demo();
        let objects = layout
            .objects
            .iter()
            .map(|o| Placed {
                mesh: o.shape.mesh(),
                world_from_object: o.world_from_object,
                casts: o.casts,
                receives: o.receives,
            })
            .collect();
        return Ok(Loaded {
            objects,
            views: gnomon_scene::demo_views(),
        });
    };
    let file = SceneFile::load(path).map_err(|e| e.to_string())?;
    for note in &file.notes {
        eprintln!("warning: {note}");
    }
    let objects = file
        .objects
        .iter()
        .map(|o| Placed {
            mesh: file.meshes[o.mesh].clone(),
            world_from_object: o.world_from_object,
            casts: o.casts,
            receives: o.receives,
        })
        .collect();
    Ok(Loaded {
        objects,
        views: file.views,
    })
}

/// The sun's illuminance: a white surface facing it reads 0.8 in linear colour at the
/// camera's exposure (ev100 0: 1 / 1.2), so that no lit pixel saturates.
const SUN_LUX: f32 = 0.8 * std::f32::consts::PI * 1.2;

/// Bevy's mesh for a gnomon-scene mesh, flat-shaded: a facet turned from the sun is dark
/// as the exact shadows (drawn from the facets) have it, where a smooth normal would light
/// it and leave the mask a band of doubtful pixels along every curved terminator.
fn bevy_mesh(mesh: &gnomon_scene::Mesh) -> Mesh {
    let f = |v: &glam::DVec3| [v.x as f32, v.y as f32, v.z as f32];
    let mut bevy = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_POSITION,
        mesh.positions.iter().map(f).collect::<Vec<_>>(),
    )
    .with_inserted_indices(Indices::U32(mesh.indices.clone()));
    bevy.duplicate_vertices();
    bevy.compute_flat_normals();
    bevy
}

/// The scene's objects: white, rough, without specular reflection, so that a pixel's
/// brightness is the sun's N.L (times the shadow).
pub fn spawn_scene(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    loaded: &Loaded,
) {
    let material = materials.add(StandardMaterial {
        base_color: Color::WHITE,
        perceptual_roughness: 1.0,
        reflectance: 0.0,
        ..default()
    });
    for object in &loaded.objects {
        let transform = Transform::from_matrix(Mat4::from_cols_array(
            &object.world_from_object.as_mat4().to_cols_array(),
        ));
        let mut entity = commands.spawn((
            Mesh3d(meshes.add(bevy_mesh(&object.mesh))),
            MeshMaterial3d(material.clone()),
            transform,
        ));
        if !object.casts {
            entity.insert(NotShadowCaster);
        }
        if !object.receives {
            entity.insert(NotShadowReceiver);
        }
    }
}

/// The camera: no tonemapping, no dithering, no MSAA, ev100 0, looking from the options' eye.
pub fn spawn_camera(commands: &mut Commands, options: &Options, target: Option<RenderTarget>) {
    let mut camera = commands.spawn((
        Camera3d::default(),
        projection(options),
        Tonemapping::None,
        // Dithering would move an object's id colour between neighbours (false edges).
        DebandDither::Disabled,
        Msaa::Off,
        Exposure { ev100: 0.0 },
        camera_transform(options),
    ));
    if let Some(target) = target {
        camera.insert(target);
    }
}

fn projection(options: &Options) -> Projection {
    let (w, h) = options.size;
    Projection::Perspective(PerspectiveProjection {
        fov: options.fov_degrees.to_radians(),
        aspect_ratio: w as f32 / h as f32,
        near: options.near,
        far: options.far,
        ..default()
    })
}

fn camera_transform(options: &Options) -> Transform {
    Transform::from_translation(options.eye)
        .looking_at(options.target, up_for(options.target - options.eye))
}

/// Moves the camera alone (a camera path).
pub fn move_camera(world: &mut World, options: &Options) {
    let mut cameras = world.query_filtered::<&mut Transform, With<Camera3d>>();
    for mut transform in cameras.iter_mut(world) {
        *transform = camera_transform(options);
    }
}

/// Cascades drawn instead of those built this frame: the flicker test draws a frame's camera
/// with the last frame's maps, so that what changed between the two masks is what the maps'
/// change did.
#[derive(Resource, Default, Clone)]
pub struct HeldCascades(pub Option<(CascadeShadowConfig, Cascades)>);

fn hold_cascades(
    held: Res<HeldCascades>,
    mut suns: Query<(&mut CascadeShadowConfig, &mut Cascades), With<DirectionalLight>>,
) {
    if let Some((config, cascades)) = &held.0 {
        for (mut c, mut k) in &mut suns {
            *c = config.clone();
            *k = cascades.clone();
        }
    }
}

/// Moves the camera to `options`' view and puts a new sun in the old one's place (its
/// direction, its shadows Bevy's or gnomon's), so that nothing of the last view's cascades
/// stays.
pub fn set_view(world: &mut World, options: &Options) {
    let mut cameras = world.query_filtered::<(&mut Transform, &mut Projection), With<Camera3d>>();
    for (mut transform, mut lens) in cameras.iter_mut(world) {
        *transform = camera_transform(options);
        *lens = projection(options);
    }
    let mut suns = world.query_filtered::<Entity, With<DirectionalLight>>();
    let old: Vec<Entity> = suns.iter(world).collect();
    for sun in old {
        world.despawn(sun);
    }
    let mut commands = world.commands();
    spawn_sun(&mut commands, options);
    world.flush();
}

/// The sun, with Bevy's default cascades reaching the far plane (the same shadow distance
/// as gnomon's), and gnomon's fit when asked.
pub fn spawn_sun(commands: &mut Commands, options: &Options) -> Entity {
    let config = CascadeShadowConfigBuilder {
        maximum_distance: options.far,
        ..default()
    }
    .build();
    let mut sun = commands.spawn((
        DirectionalLight {
            illuminance: SUN_LUX,
            shadow_maps_enabled: true,
            shadow_depth_bias: options.depth_bias,
            shadow_normal_bias: options.normal_bias,
            ..default()
        },
        config,
        Transform::default().looking_to(options.light_dir, up_for(options.light_dir)),
    ));
    if options.shadows == Shadows::Gnomon {
        sun.insert(gnomon_shadows(options));
    }
    sun.id()
}

/// The plugin's component for the options.
pub fn gnomon_shadows(options: &Options) -> GnomonShadows {
    GnomonShadows {
        technique: options.technique,
        shadow_distance: options.far,
    }
}

/// +Y, unless `direction` is straight up or down (then +Z).
fn up_for(direction: Vec3) -> Vec3 {
    if direction.normalize().cross(Vec3::Y).length() < 1e-4 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// Where the camera draws: the window (`None`) or an image.
#[derive(Resource)]
pub struct Target(pub Option<RenderTarget>);

#[derive(Resource)]
struct Scene(Loaded);

/// The scene's named views.
#[derive(Resource, Clone)]
pub struct Views(pub Vec<NamedView>);

#[derive(Resource, Clone)]
pub struct Settings(pub Options);

/// What both runs share: the plugin, no ambient light, a black sky, the map size, and the
/// scene spawned at startup.
pub fn configure(app: &mut App, options: &Options, loaded: Loaded) {
    app.add_plugins(GnomonShadowsPlugin)
        .insert_resource(GlobalAmbientLight::NONE)
        .insert_resource(ClearColor(Color::BLACK))
        .insert_resource(DirectionalLightShadowMap {
            size: options.shadow_map as usize,
        })
        .insert_resource(Views(loaded.views.clone()))
        .insert_resource(Scene(loaded))
        .insert_resource(Settings(options.clone()))
        .init_resource::<HeldCascades>()
        .add_systems(Startup, (spawn, tell_device))
        .add_systems(
            PostUpdate,
            hold_cascades
                .after(GnomonShadowSystems::FitCascades)
                .before(SimulationLightSystems::UpdateLightFrusta),
        );
}

/// Tells the plugin whether this device draws warped maps right.
fn tell_device(mut commands: Commands, device: Option<Res<RenderDevice>>) {
    if let Some(device) = device {
        let clips = device.features().contains(WgpuFeatures::DEPTH_CLIP_CONTROL);
        commands.insert_resource(DepthClipControl(clips));
    }
}

fn spawn(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    scene: Res<Scene>,
    settings: Res<Settings>,
    target: Res<Target>,
) {
    spawn_scene(&mut commands, &mut meshes, &mut materials, &scene.0);
    spawn_camera(&mut commands, &settings.0, target.0.clone());
    spawn_sun(&mut commands, &settings.0);
}

/// Each object's own material and an unlit one in its id's colour (its index from 1, in
/// 24 bits), for the mask's edges.
#[derive(Resource, Default)]
struct IdMaterials(Vec<(Entity, Handle<StandardMaterial>, Handle<StandardMaterial>)>);

/// Draws each object unlit in its id's colour (`true`) or with its own material (`false`).
pub fn show_ids(world: &mut World, on: bool) {
    if !world.contains_resource::<IdMaterials>() {
        let mut objects = world.query::<(Entity, &MeshMaterial3d<StandardMaterial>)>();
        let own: Vec<_> = objects.iter(world).map(|(e, m)| (e, m.0.clone())).collect();
        let mut materials = world.resource_mut::<Assets<StandardMaterial>>();
        let table = own
            .into_iter()
            .enumerate()
            .map(|(i, (entity, material))| {
                let id = i as u32 + 1;
                let colour = Color::srgb_u8(id as u8, (id >> 8) as u8, (id >> 16) as u8);
                let unlit = materials.add(StandardMaterial {
                    base_color: colour,
                    unlit: true,
                    ..default()
                });
                (entity, material, unlit)
            })
            .collect();
        world.insert_resource(IdMaterials(table));
    }
    let table = std::mem::take(&mut world.resource_mut::<IdMaterials>().0);
    for (entity, own, id) in &table {
        let material = if on { id } else { own };
        world
            .entity_mut(*entity)
            .insert(MeshMaterial3d(material.clone()));
    }
    world.resource_mut::<IdMaterials>().0 = table;
}
