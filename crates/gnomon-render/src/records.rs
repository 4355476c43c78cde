//! The records the shaders read, built in f64 on the CPU relative to the camera and rounded to
//! f32 last, so that a scene far from the origin keeps its precision: per map (`GpuMap`), per
//! light (`GpuLight`), the frame's (`GpuFrame`) and the per-pass slots (`GpuSlot`). Their
//! layouts match `wgsl/lookup.wgsl` and `wgsl/passes.wgsl`.

use glam::{DMat3, DMat4, DVec3, DVec4};
use gnomon::{Camera, Light, MapProjection, MapSelection, ShadowMap, ShadowSetup};

use crate::{DepthBias, Filter, InvalidInput, RenderError};

/// The most lights with shadow maps in one frame (`GNOMON_MAX_LIGHTS` in the WGSL).
pub const MAX_LIGHTS: usize = 4;
/// The most shadow maps in one frame, over all lights (`GNOMON_MAX_MAPS` in the WGSL): room
/// for 8 cascades plus 6 cube faces for each of three lights.
pub const MAX_MAPS: usize = 48;

/// `GnomonLight.info.x`.
pub(crate) const LIGHT_DIRECTIONAL: u32 = 0;
pub(crate) const LIGHT_SPOT: u32 = 1;
pub(crate) const LIGHT_POINT: u32 = 2;
/// `GnomonLight.info.y`.
pub(crate) const SELECT_SINGLE: u32 = 0;
pub(crate) const SELECT_PLANE: u32 = 1;
pub(crate) const SELECT_CASCADES: u32 = 2;
pub(crate) const SELECT_CUBE: u32 = 3;
pub(crate) const SELECT_CASCADES_BY_COVER: u32 = 4;
/// `GnomonMap.info.y`.
pub(crate) const MAP_PERSPECTIVE: u32 = 1;
pub(crate) const MAP_PARABOLOID: u32 = 2;

/// `GnomonMap`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuMap {
    pub clip_from_camera: [[f32; 4]; 4],
    pub depth_from_camera: [f32; 4],
    pub rect: [f32; 4],
    pub bias: [f32; 4],
    pub slope_cap: [f32; 4],
    pub info: [u32; 4],
}

/// `GnomonLight`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuLight {
    pub vector: [f32; 4],
    pub spot: [f32; 4],
    pub range: [f32; 4],
    pub info: [u32; 4],
    pub params: [[f32; 4]; 4],
}

/// `GnomonShadows`: every light and map of a frame.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuShadows {
    pub lights: [GpuLight; MAX_LIGHTS],
    pub maps: [GpuMap; MAX_MAPS],
    pub info: [u32; 4],
}

/// `Frame` of passes.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuFrame {
    pub clip_from_camera: [[f32; 4]; 4],
    pub infinite_clip_from_camera: [[f32; 4]; 4],
    pub shading: [f32; 4],
}

/// `Slot` of passes.wgsl (one per dynamic offset).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuSlot {
    pub map: u32,
    pub light: u32,
    pub unused: [u32; 2],
}

/// One instance of the vertex stream `Instance` of passes.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuInstance {
    pub camera_from_object: [[f32; 4]; 4],
    pub normal: [[f32; 4]; 3],
    pub color: [f32; 4],
}

impl GpuInstance {
    /// `camera_from_object` = view_from_world world_from_object, multiplied in f64.
    pub fn new(view_from_world: DMat4, world_from_object: DMat4, color: [f32; 4]) -> Self {
        let camera_from_object = view_from_world * world_from_object;
        let n = DMat3::from_mat4(camera_from_object).inverse().transpose();
        Self {
            camera_from_object: mat(camera_from_object),
            normal: [
                vec4(n.x_axis, 0.0),
                vec4(n.y_axis, 0.0),
                vec4(n.z_axis, 0.0),
            ],
            color,
        }
    }
}

/// A light and the shadow maps the core computed for it.
#[derive(Debug, Clone, Copy)]
pub struct ShadowedLight<'a> {
    /// The light.
    pub light: &'a Light,
    /// Its shadow setup (from [`gnomon::compute_setup`] for the same camera and light).
    pub setup: &'a ShadowSetup,
}

impl<'a> ShadowedLight<'a> {
    /// The lights paired with their setups, in order (`setups[i]` is `lights[i]`'s).
    pub fn pairs(lights: &'a [Light], setups: &'a [ShadowSetup]) -> Vec<Self> {
        lights
            .iter()
            .zip(setups)
            .map(|(light, setup)| Self { light, setup })
            .collect()
    }
}

/// Where a map lives in the shadow-map array: its layer and its size in texels (maps smaller
/// than the layers take the layer's top-left corner).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MapSlot {
    pub layer: u32,
    pub layer_size: u32,
}

/// f64 to f32 columns.
pub(crate) fn mat(m: DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}

fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

/// A row vector r (r . (x, 1) on world points) as the row on view-space points.
pub(crate) fn row_in_camera(row_world: DVec4, world_from_camera: DMat4) -> DVec4 {
    world_from_camera.transpose() * row_world
}

/// The record of one map.
pub(crate) fn map_record(
    map: &ShadowMap,
    world_from_camera: DMat4,
    slot: MapSlot,
    bias: &DepthBias,
    scene_diagonal: f64,
) -> GpuMap {
    let depth_per_world = map.depth_from_world.truncate().length();
    let (constant_world, max_slope_world) = bias.world(scene_diagonal);
    let scale = map.resolution as f64 / slot.layer_size as f64;
    GpuMap {
        clip_from_camera: mat(map.clip_from_world * world_from_camera),
        depth_from_camera: row_in_camera(map.depth_from_world, world_from_camera)
            .as_vec4()
            .to_array(),
        rect: [0.0, 0.0, scale as f32, scale as f32],
        bias: [
            (constant_world * depth_per_world) as f32,
            bias.slope_texels as f32,
            (max_slope_world * depth_per_world) as f32,
            bias.normal_offset_texels as f32,
        ],
        slope_cap: [bias.max_slope_texels as f32, 0.0, 0.0, 0.0],
        info: [
            slot.layer,
            match map.projection {
                MapProjection::Orthographic => 0,
                MapProjection::Perspective => MAP_PERSPECTIVE,
                MapProjection::Paraboloid => MAP_PARABOLOID,
            },
            map.resolution,
            map.viewport_inset,
        ],
    }
}

/// The record of one light whose maps (none without a setup: shadow volumes) start at
/// `first_map`.
pub(crate) fn light_record(
    light: &Light,
    setup: Option<&ShadowSetup>,
    view_from_world: DMat4,
    world_from_camera: DMat4,
    first_map: usize,
) -> Result<GpuLight, RenderError> {
    let (vector, spot, range, kind) = match light {
        Light::Directional(d) => (
            vec4(view_from_world.transform_vector3(d.direction()), 0.0),
            [0.0; 4],
            [0.0; 4],
            LIGHT_DIRECTIONAL,
        ),
        Light::Spot(s) => (
            vec4(view_from_world.transform_point3(s.position()), 1.0),
            vec4(
                view_from_world.transform_vector3(s.direction()),
                s.half_angle().cos(),
            ),
            [s.range() as f32, s.near() as f32, 0.0, 0.0],
            LIGHT_SPOT,
        ),
        Light::Point(p) => (
            vec4(view_from_world.transform_point3(p.position()), 1.0),
            [0.0; 4],
            [p.range() as f32, p.near() as f32, 0.0, 0.0],
            LIGHT_POINT,
        ),
    };
    let (selection, params) = selection_record(setup, view_from_world, world_from_camera)?;
    let map_count = setup.map_or(0, |s| s.maps.len() as u32);
    Ok(GpuLight {
        vector,
        spot,
        range,
        info: [kind, selection, first_map as u32, map_count],
        params,
    })
}

/// The filter's code (`GnomonShadows.info.y`).
pub(crate) fn filter_code(filter: Filter) -> u32 {
    match filter {
        Filter::None => 0,
        Filter::Hardware2x2 => 1,
        Filter::Pcf5x5 => 2,
        Filter::Pcss => 3,
    }
}

/// Reversed Z: view to clip space with depth 1 at the near plane and 0 at the far plane
/// (`1 - d` of [`Camera::clip_from_view`], formed in f64 so that far depths keep the float
/// format's precision near 0).
pub(crate) fn reversed_clip_from_view(camera: &Camera) -> DMat4 {
    // z' = w - z: the row of z becomes row_w - row_z.
    let mut rows = camera.clip_from_view().transpose();
    rows.z_axis = rows.w_axis - rows.z_axis;
    rows.transpose()
}

/// How the shader picks a light's map (its selection code) and the selection's parameters:
/// the plane, the cascades' depths and blend, or the cube's axes and face maps.
fn selection_record(
    setup: Option<&ShadowSetup>,
    view_from_world: DMat4,
    world_from_camera: DMat4,
) -> Result<(u32, [[f32; 4]; 4]), RenderError> {
    let mut params = [[0.0f32; 4]; 4];
    let selection = match setup.map(|s| (s, s.selection, s.maps.len())) {
        None | Some((_, MapSelection::Single, 1)) => SELECT_SINGLE,
        Some((
            _,
            selection @ (MapSelection::Plane { .. } | MapSelection::DualParaboloid { .. }),
            2,
        )) => {
            // SPPSM's plane, or the one across a point light's paraboloid axis.
            let plane_world = selection
                .two_map_plane()
                .expect("a selection by a plane has one");
            params[0] = row_in_camera(plane_world, world_from_camera)
                .as_vec4()
                .to_array();
            SELECT_PLANE
        }
        Some((_, MapSelection::Cascades(c), n)) if n == c.count => {
            // z_0 ..= z_K in params[0].x to params[2].x, then the blend and the fade's start;
            // params[3] the view-depth row in camera space.
            for (j, depth) in c.depths().iter().enumerate() {
                params[j / 4][j % 4] = *depth as f32;
            }
            params[2][1] = c.blend as f32;
            params[2][2] = c.fade_start as f32;
            params[3] = row_in_camera(c.depth_row_world, world_from_camera)
                .as_vec4()
                .to_array();
            // By coverage, the shader reads each map's square from its record.
            if c.by_coverage {
                SELECT_CASCADES_BY_COVER
            } else {
                SELECT_CASCADES
            }
        }
        Some((_, MapSelection::CubeFaces(faces), n)) if n == faces.faces().len() => {
            // params[0..3].xyz: the world axes x, y, z in view space (a direction's major
            // world axis picks its face); the map of face k (+x, -x, +y, -y, +z, -z) relative
            // to the first, or -1 for none: faces 0 to 2 in params[0..3].w, 3 to 5 in
            // params[3].xyz.
            for (param, axis) in params.iter_mut().zip(DVec3::AXES) {
                *param = vec4(view_from_world.transform_vector3(axis), 0.0);
            }
            for face in gnomon::CubeFace::ALL {
                let k = face.index();
                let map = faces.map_of(face).map_or(-1.0, |m| m as f32);
                if k < 3 {
                    params[k][3] = map;
                } else {
                    params[3][k - 3] = map;
                }
            }
            SELECT_CUBE
        }
        Some((setup, selection, n)) => {
            return Err(InvalidInput::MapsForSelection {
                technique: setup.technique.to_string(),
                maps: n,
                selection: selection.kind(),
            }
            .into());
        }
    };
    Ok((selection, params))
}
