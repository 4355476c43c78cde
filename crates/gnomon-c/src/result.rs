//! A setup as the caller-owned result struct: fixed-size arrays, no pointers, so that a C
//! or C++ engine can keep one per light and refill it every frame without allocating.

use gnomon::{CubeFace, Fallback, MapProjection, MapSelection, ShadowMap, ShadowSetup};

use crate::types::GNOMON_MAX_MAPS;

/// The most view depths a cascade selection has (one more than its maps).
pub const GNOMON_MAX_VIEW_DEPTHS: usize = GNOMON_MAX_MAPS + 1;

/// `w` is 1: parallel rays (a sun's uniform and focused maps).
pub const GNOMON_PROJECTION_ORTHOGRAPHIC: u32 = 0;
/// `w` varies: a spot light, a cube face or a warp.
pub const GNOMON_PROJECTION_PERSPECTIVE: u32 = 1;
/// One hemisphere of a dual paraboloid map: `clip_from_world` only moves a point into the
/// hemisphere's frame in units of the range; the paraboloid's divide is the shader's.
pub const GNOMON_PROJECTION_PARABOLOID: u32 = 2;

/// One map: every relevant point lands inside the map's inset square.
pub const GNOMON_SELECTION_SINGLE: u32 = 0;
/// SPPSM: `plane_world` separates the two maps; points where
/// `dot(plane_world, (p, 1)) >= 0` read map 1 (the perspective map), the others map 0.
pub const GNOMON_SELECTION_PLANE: u32 = 1;
/// Cascades: map i covers view depths `view_depths[i]` to `view_depths[i + 1]`.
pub const GNOMON_SELECTION_CASCADES: u32 = 2;
/// A point light's two paraboloid hemispheres around `axis` at `position`: map 0 for
/// points on the axis's side, map 1 for the others.
pub const GNOMON_SELECTION_DUAL_PARABOLOID: u32 = 3;
/// A point light's cube faces: `faces[i]` is map i's face (0 +x, 1 -x, 2 +y, 3 -y, 4 +z,
/// 5 -z); faces that see nothing have no map.
pub const GNOMON_SELECTION_CUBE_FACES: u32 = 4;

/// One shadow map.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonMap {
    /// World to the map's clip space, column-major.
    pub clip_from_world: [f64; 16],
    /// The same as floats, for uploading.
    pub clip_from_world_f32: [f32; 16],
    /// The depth row: depth = dot(depth_from_world, (x, y, z, 1)).
    pub depth_from_world: [f64; 4],
    /// The same as floats.
    pub depth_from_world_f32: [f32; 4],
    /// Texels on a side.
    pub resolution: u32,
    /// Texels kept free at each side.
    pub viewport_inset: u32,
    /// GNOMON_PROJECTION_ORTHOGRAPHIC, _PERSPECTIVE or _PARABOLOID.
    pub projection: u32,
    /// 1 where the map is one of several cascades and `view_depth_range` holds its view
    /// depths (its slice and the blend band before it), else 0.
    pub has_view_depth_range: u32,
    /// Near and far view depth, along the camera's forward axis.
    pub view_depth_range: [f64; 2],
    /// This map's fallbacks: bit (1 << code) for each GNOMON_FALLBACK_* code it took.
    pub fallbacks: u32,
    /// How far the warp limit weakened this map's warp (1 = full strength); NaN where it
    /// did not.
    pub warp_strength: f64,
}

/// How a point picks its map.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonSelection {
    /// One of the GNOMON_SELECTION_* kinds.
    pub kind: u32,
    /// SPPSM's separating plane (a, b, c, d).
    pub plane_world: [f64; 4],
    /// Cascades: how many slices (maps).
    pub cascade_count: u32,
    /// Cascades: z_0 < z_1 < ... < z_count (cascade_count + 1 used).
    pub view_depths: [f64; GNOMON_MAX_VIEW_DEPTHS],
    /// Cascades: the blend band into the next map, as a fraction of each slice.
    pub blend: f64,
    /// Cascades: where shadows begin to fade out (the last view depth if they do not).
    pub fade_start: f64,
    /// Cascades: 1 where a point reads the first map that holds it (stable cascades), 0
    /// where it reads its view depth's map.
    pub by_coverage: u32,
    /// Dual paraboloid and cube faces: the light's position.
    pub position: [f64; 3],
    /// Dual paraboloid: the axis of map 0's hemisphere.
    pub axis: [f64; 3],
    /// Cube faces: how many faces have maps.
    pub face_count: u32,
    /// Cube faces: map i's face (0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z).
    pub faces: [u32; 6],
}

/// What `gnomon_setup` fills: the maps, the selection and the fallbacks.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonSetupResult {
    /// How many of `maps` are used.
    pub map_count: u32,
    /// The maps, in the selection's order.
    pub maps: [GnomonMap; GNOMON_MAX_MAPS],
    /// How a point picks among them.
    pub selection: GnomonSelection,
    /// The setup's first fallback (a GNOMON_FALLBACK_* code), or GNOMON_FALLBACK_NONE.
    pub fallback: u32,
    /// Every fallback it took: bit (1 << code) for each.
    pub fallbacks: u32,
}

/// No fallback.
pub const GNOMON_FALLBACK_NONE: u32 = 0;
/// No receiver is visible: the map covers the whole scene.
pub const GNOMON_FALLBACK_NO_VISIBLE_RECEIVER: u32 = 1;
/// The view is parallel to the light: the light frame is fixed by the light alone.
pub const GNOMON_FALLBACK_LIGHT_PARALLEL_TO_VIEW: u32 = 2;
/// The spot light cannot see the view frustum: the map covers the whole scene.
pub const GNOMON_FALLBACK_SPOT_LIGHT_MISSES_VIEW: u32 = 3;
/// The spot light's frustum misses the scene box: the map covers the whole cone.
pub const GNOMON_FALLBACK_SPOT_LIGHT_MISSES_SCENE: u32 = 4;
/// No caster can shadow a visible receiver: the map fits the visible receivers.
pub const GNOMON_FALLBACK_NO_CASTER_FOR_RECEIVERS: u32 = 5;
/// The focus body B is empty or flat: the depth range comes from the casters.
pub const GNOMON_FALLBACK_DEGENERATE_FOCUS_BODY: u32 = 6;
/// TSM and XPSM warp only for suns: a spot light gets the focused map.
pub const GNOMON_FALLBACK_SPOT_LIGHT_NOT_WARPED: u32 = 7;
/// SPPSM: no separating plane; one map alone is used.
pub const GNOMON_FALLBACK_NO_SEPARATING_PLANE: u32 = 8;
/// The warp was weakened where it would sample the view more coarsely than the focused map.
pub const GNOMON_FALLBACK_WARP_LIMITED: u32 = 9;
/// Even a weakened warp was coarser than the focused map: the focused map is used.
pub const GNOMON_FALLBACK_WARP_COARSER_THAN_FOCUSED: u32 = 10;
/// Stable cascades need a sun: a spot light's cascades are fitted.
pub const GNOMON_FALLBACK_STABLE_NEEDS_DIRECTIONAL_LIGHT: u32 = 11;

/// Each fallback's code (its bit in the masks is 1 << code; gnomon_fallback_name names it).
pub(crate) fn fallback_code(f: Fallback) -> u32 {
    match f {
        Fallback::NoVisibleReceiver => GNOMON_FALLBACK_NO_VISIBLE_RECEIVER,
        Fallback::LightParallelToView => GNOMON_FALLBACK_LIGHT_PARALLEL_TO_VIEW,
        Fallback::SpotLightMissesView => GNOMON_FALLBACK_SPOT_LIGHT_MISSES_VIEW,
        Fallback::SpotLightMissesScene => GNOMON_FALLBACK_SPOT_LIGHT_MISSES_SCENE,
        Fallback::NoCasterForReceivers => GNOMON_FALLBACK_NO_CASTER_FOR_RECEIVERS,
        Fallback::DegenerateFocusBody => GNOMON_FALLBACK_DEGENERATE_FOCUS_BODY,
        Fallback::SpotLightNotWarped => GNOMON_FALLBACK_SPOT_LIGHT_NOT_WARPED,
        Fallback::NoSeparatingPlane => GNOMON_FALLBACK_NO_SEPARATING_PLANE,
        Fallback::WarpLimited => GNOMON_FALLBACK_WARP_LIMITED,
        Fallback::WarpCoarserThanFocused => GNOMON_FALLBACK_WARP_COARSER_THAN_FOCUSED,
        Fallback::StableNeedsDirectionalLight => GNOMON_FALLBACK_STABLE_NEEDS_DIRECTIONAL_LIGHT,
    }
}

/// Every fallback, so that a code can be named.
pub(crate) const FALLBACKS: [Fallback; 11] = [
    Fallback::NoVisibleReceiver,
    Fallback::LightParallelToView,
    Fallback::SpotLightMissesView,
    Fallback::SpotLightMissesScene,
    Fallback::NoCasterForReceivers,
    Fallback::DegenerateFocusBody,
    Fallback::SpotLightNotWarped,
    Fallback::NoSeparatingPlane,
    Fallback::WarpLimited,
    Fallback::WarpCoarserThanFocused,
    Fallback::StableNeedsDirectionalLight,
];

fn mask(fallbacks: &[Fallback]) -> u32 {
    fallbacks.iter().fold(0, |m, f| m | 1 << fallback_code(*f))
}

fn face_code(face: CubeFace) -> u32 {
    match face {
        CubeFace::PosX => 0,
        CubeFace::NegX => 1,
        CubeFace::PosY => 2,
        CubeFace::NegY => 3,
        CubeFace::PosZ => 4,
        CubeFace::NegZ => 5,
    }
}

fn map(setup: &ShadowSetup, i: usize, m: &ShadowMap) -> GnomonMap {
    let clip = m.clip_from_world.to_cols_array();
    let depth = m.depth_from_world.to_array();
    let own = setup.map_diagnostics(i);
    GnomonMap {
        clip_from_world: clip,
        clip_from_world_f32: clip.map(|v| v as f32),
        depth_from_world: depth,
        depth_from_world_f32: depth.map(|v| v as f32),
        resolution: m.resolution,
        viewport_inset: m.viewport_inset,
        projection: match m.projection {
            MapProjection::Orthographic => GNOMON_PROJECTION_ORTHOGRAPHIC,
            MapProjection::Perspective => GNOMON_PROJECTION_PERSPECTIVE,
            MapProjection::Paraboloid => GNOMON_PROJECTION_PARABOLOID,
        },
        has_view_depth_range: u32::from(m.view_depth_range.is_some()),
        view_depth_range: m.view_depth_range.unwrap_or([0.0; 2]),
        fallbacks: mask(&own.fallbacks),
        warp_strength: own.warp_strength.unwrap_or(f64::NAN),
    }
}

fn selection(setup: &ShadowSetup) -> GnomonSelection {
    let mut s = GnomonSelection {
        kind: GNOMON_SELECTION_SINGLE,
        plane_world: [0.0; 4],
        cascade_count: 0,
        view_depths: [0.0; GNOMON_MAX_VIEW_DEPTHS],
        blend: 0.0,
        fade_start: 0.0,
        by_coverage: 0,
        position: [0.0; 3],
        axis: [0.0; 3],
        face_count: 0,
        faces: [0; 6],
    };
    match setup.selection {
        MapSelection::Single => {}
        MapSelection::Plane { plane_world } => {
            s.kind = GNOMON_SELECTION_PLANE;
            s.plane_world = plane_world.to_array();
        }
        MapSelection::Cascades(c) => {
            s.kind = GNOMON_SELECTION_CASCADES;
            s.cascade_count = c.count as u32;
            s.view_depths[..=c.count].copy_from_slice(c.depths());
            (s.blend, s.fade_start) = (c.blend, c.fade_start);
            s.by_coverage = u32::from(c.by_coverage);
        }
        MapSelection::DualParaboloid { position, axis } => {
            s.kind = GNOMON_SELECTION_DUAL_PARABOLOID;
            (s.position, s.axis) = (position.to_array(), axis.to_array());
        }
        MapSelection::CubeFaces(c) => {
            s.kind = GNOMON_SELECTION_CUBE_FACES;
            s.position = c.position.to_array();
            s.face_count = c.faces().len() as u32;
            for (slot, face) in s.faces.iter_mut().zip(c.faces()) {
                *slot = face_code(*face);
            }
        }
    }
    s
}

/// An unused slot of [`GnomonSetupResult::maps`].
const NO_MAP: GnomonMap = GnomonMap {
    clip_from_world: [0.0; 16],
    clip_from_world_f32: [0.0; 16],
    depth_from_world: [0.0; 4],
    depth_from_world_f32: [0.0; 4],
    resolution: 0,
    viewport_inset: 0,
    projection: GNOMON_PROJECTION_ORTHOGRAPHIC,
    has_view_depth_range: 0,
    view_depth_range: [0.0; 2],
    fallbacks: 0,
    warp_strength: f64::NAN,
};

/// The result struct of `setup` (the core never makes more than [`GNOMON_MAX_MAPS`] maps).
pub(crate) fn setup_result(setup: &ShadowSetup) -> Result<GnomonSetupResult, String> {
    if setup.maps.len() > GNOMON_MAX_MAPS {
        return Err(format!(
            "the setup has {} maps, more than GNOMON_MAX_MAPS ({GNOMON_MAX_MAPS})",
            setup.maps.len()
        ));
    }
    let mut maps = [NO_MAP; GNOMON_MAX_MAPS];
    for (i, m) in setup.maps.iter().enumerate() {
        maps[i] = map(setup, i, m);
    }
    Ok(GnomonSetupResult {
        map_count: setup.maps.len() as u32,
        maps,
        selection: selection(setup),
        fallback: setup.fallback().map_or(GNOMON_FALLBACK_NONE, fallback_code),
        fallbacks: mask(&setup.diagnostics.fallbacks),
    })
}
