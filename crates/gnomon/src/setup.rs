//! What a shadow setup returns, and the interface every technique implements.

use std::fmt;
use std::str::FromStr;

use glam::{DMat4, DVec3, DVec4};

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::error::SetupError;
use crate::light::{CubeFace, Light, PointLight};
use crate::samples::ViewSamples;
use crate::techniques::{
    Cascades, Cube, DualParaboloid, Focused, Lispsm, Psm, Sppsm, Tsm, Uniform, Xpsm,
};

/// Smallest supported shadow-map resolution, in texels.
pub const MIN_RESOLUTION: u32 = 8;
/// Largest supported shadow-map resolution, in texels.
pub const MAX_RESOLUTION: u32 = 32768;

/// Size of the shadow map(s) to set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapSettings {
    /// Width and height of each square shadow map, in texels.
    pub resolution: u32,
    /// Texels kept free on each side of the map: the focus region maps inside them, and the
    /// renderer keeps them cleared to the far depth, so that lookups outside the focus region
    /// (clamped to the edge) read as lit. The unit cube clipping blog post's border trick.
    pub viewport_inset: u32,
}

impl Default for MapSettings {
    /// 1024 x 1024 with a one-texel border.
    fn default() -> Self {
        Self {
            resolution: 1024,
            viewport_inset: 1,
        }
    }
}

impl MapSettings {
    /// A square map of `resolution` texels with the default one-texel border.
    pub fn with_resolution(resolution: u32) -> Self {
        Self {
            resolution,
            ..Self::default()
        }
    }

    pub(crate) fn validate(&self) -> Result<(), SetupError> {
        let ok = (MIN_RESOLUTION..=MAX_RESOLUTION).contains(&self.resolution)
            && self.viewport_inset < self.resolution / 4;
        if ok {
            Ok(())
        } else {
            Err(SetupError::InvalidResolution {
                resolution: self.resolution,
                viewport_inset: self.viewport_inset,
            })
        }
    }

    /// Half-size of the inset square in normalised device coordinates: points of the focus
    /// region land in `[-s, s]^2` with `s = 1 - 2 inset / resolution`.
    pub fn inset_ndc(&self) -> f64 {
        1.0 - 2.0 * self.viewport_inset as f64 / self.resolution as f64
    }
}

/// How a shadow map projects: parallel rays or rays from a point, through a matrix; or a
/// paraboloid, which no matrix is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapProjection {
    /// `w = 1` everywhere (directional lights, uniform and focused maps).
    Orthographic,
    /// `w` is the distance along the light's axis (spot lights) or a warp.
    Perspective,
    /// One hemisphere of a dual paraboloid map (Heidrich and Seidel 1998; Brabec, Annen and
    /// Seidel 2002): `clip_from_world` is only the affine map to the hemisphere's frame in
    /// units of the light's range (q, with q.z along the hemisphere's axis); a point lands at
    /// x, y = [`PARABOLOID_SCALE`] q.xy / (|q| + q.z) (scaled into the inset square), with
    /// depth |q| (the distance over the range). Straight edges map to curves, which the
    /// rasteriser draws straight between the vertices: the technique's known error.
    Paraboloid,
}

/// The angle in degrees by which each hemisphere of a dual paraboloid map reaches past 90
/// degrees, so that filtering near its rim reads texels that hold the casters.
pub const PARABOLOID_MARGIN_DEGREES: f64 = 3.0;

/// The scale from the paraboloid's q.xy / (|q| + q.z) (1 at 90 degrees) to the map's
/// normalised coordinates before the inset: the rim at 90 + [`PARABOLOID_MARGIN_DEGREES`]
/// lands on the map's edge (1 / tan(45 + margin / 2)).
pub const PARABOLOID_SCALE: f64 = 0.948_964_566_714_88;

/// One shadow map: where world points land in it and how deep they are.
///
/// A point that lands outside the map's inset square, behind its near plane or beyond its far
/// plane reads as lit: a focused map covers only what the camera can see being shadowed, so a
/// point outside it has no caster in the map. Many of the frame's points lie outside one
/// cascade's map; that is expected, and the selection ([`MapSelection`]) routes them to the
/// map that holds them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowMap {
    /// World to the map's clip space. After the divide by `w`, x and y in [-1, 1] cover the
    /// whole map (+y up, so texture v = 0.5 - 0.5 y); the focus region lands inside the inset
    /// square `[-s, s]^2` (see [`MapSettings::inset_ndc`]); z is in [0, 1] for every relevant
    /// point, so the rasteriser clips none: from the near (0) to the far plane (1) of the focus
    /// region for a directional light's uniform, focused, LiSPSM and XPSM maps; from 0 at the
    /// near plane toward 0.5 for maps seen from a point (spot lights, cube faces: their near
    /// planes lie at a millionth of the range, and the usual z would crowd every point within
    /// f32 roundings of 1, where a rasteriser clips some); the constant 0.5 for TSM and PSM.
    /// Depth comparisons use [`ShadowMap::depth_from_world`].
    pub clip_from_world: DMat4,
    /// A row taking a world point (x, y, z, 1) to a depth that is linear along the light, 0 at
    /// the focus region's near plane and 1 at its far plane. A depth bias of `b` world units is
    /// `b * depth_from_world.xyz().length()` in these units, whatever the warp.
    pub depth_from_world: DVec4,
    /// Width and height in texels.
    pub resolution: u32,
    /// Texels kept free on each side.
    pub viewport_inset: u32,
    /// Orthographic or perspective.
    pub projection: MapProjection,
    /// A cascade's view depths, near and far along the camera's forward axis: its slice and
    /// the blend band before it, where the selection by depth reads this map. `None` for a
    /// map that is not one of several slices (stable cascades picked by coverage may also
    /// read a map beyond its far depth).
    pub view_depth_range: Option<[f64; 2]>,
}

impl ShadowMap {
    /// Where `p` lands: normalised device coordinates (x, y in [-1, 1] across the map; z the
    /// clip-space depth). Points behind a perspective map's centre (w <= 0) give `None`, and
    /// so do points beyond a paraboloid hemisphere's rim (whose z is then its depth).
    pub fn project(&self, p: DVec3) -> Option<DVec3> {
        if self.projection == MapProjection::Paraboloid {
            let q = self.clip_from_world.transform_point3(p);
            let d = q.length();
            let rim = -PARABOLOID_MARGIN_DEGREES.to_radians().sin();
            let s = PARABOLOID_SCALE * self.inset_ndc();
            return (d > 0.0 && q.z >= rim * d).then(|| {
                let xy = q.truncate() * (s / (d + q.z));
                xy.extend(d)
            });
        }
        let clip = self.clip_from_world * p.extend(1.0);
        (clip.w > 0.0).then(|| clip.truncate() / clip.w)
    }

    /// The depth `p` is compared at (see [`ShadowMap::depth_from_world`]; a paraboloid
    /// map's: the distance from the light over its range).
    pub fn linear_depth(&self, p: DVec3) -> f64 {
        if self.projection == MapProjection::Paraboloid {
            return self.clip_from_world.transform_point3(p).length();
        }
        self.depth_from_world.dot(p.extend(1.0))
    }

    /// World units per unit of linear depth.
    pub fn depth_range_world(&self) -> f64 {
        1.0 / self.depth_from_world.truncate().length()
    }

    /// Half-size of the inset square in normalised device coordinates.
    pub fn inset_ndc(&self) -> f64 {
        MapSettings {
            resolution: self.resolution,
            viewport_inset: self.viewport_inset,
        }
        .inset_ndc()
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.clip_from_world.is_finite() && self.depth_from_world.is_finite()
    }
}

/// How a pixel picks the map it reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MapSelection {
    /// There is one map.
    Single,
    /// Two maps and a world plane (a, b, c, d) with (a, b, c) of unit length: a point p
    /// reads `maps[1]` where a p.x + b p.y + c p.z + d > 0, else `maps[0]` (SPPSM: the
    /// perspective map on the positive side, the focused map on the other).
    Plane {
        /// The plane, world space.
        plane_world: DVec4,
    },
    /// One map per slice of the view by depth along the camera's forward axis (cascades);
    /// stable cascades may pick by coverage instead ([`CascadeSlices::by_coverage`]).
    Cascades(CascadeSlices),
    /// A point light's dual paraboloid maps: `maps[0]` is the hemisphere around `axis`,
    /// `maps[1]` the other; a point reads `maps[0]` where (p - position) . axis >= 0.
    DualParaboloid {
        /// The light's position, world space.
        position: DVec3,
        /// The first hemisphere's axis (unit).
        axis: DVec3,
    },
    /// A point light's cube: one map per face that has one, in the order of
    /// [`CubeFaceMaps::faces`]; a point reads the map of the face its direction from the
    /// light falls in ([`crate::PointLight::face_of`]), and a point of a face without a map
    /// reads as lit.
    CubeFaces(CubeFaceMaps),
}

/// The faces of a point light's cube that have maps, in the order of the maps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubeFaceMaps {
    /// The light's position, world space.
    pub position: DVec3,
    faces: [CubeFace; 6],
    count: usize,
}

impl CubeFaceMaps {
    /// No face yet, for a light at `position`.
    pub fn new(position: DVec3) -> Self {
        Self {
            position,
            faces: CubeFace::ALL,
            count: 0,
        }
    }

    /// Adds the next map's face (at most six, each once).
    pub fn push(&mut self, face: CubeFace) {
        assert!(
            self.count < 6 && !self.faces().contains(&face),
            "each face has at most one map"
        );
        self.faces[self.count] = face;
        self.count += 1;
    }

    /// The faces with maps, in the order of the maps.
    pub fn faces(&self) -> &[CubeFace] {
        &self.faces[..self.count]
    }

    /// The index of `face`'s map, if it has one.
    pub fn map_of(&self, face: CubeFace) -> Option<usize> {
        self.faces().iter().position(|f| *f == face)
    }
}

/// The most cascades a setup has.
pub const MAX_CASCADES: usize = 8;

/// How cascaded maps split the view: map i covers view depth (distance along the camera's
/// forward axis) from `view_depths[i]` to `view_depths[i + 1]`; in the last `blend` fraction of
/// a slice the next map is blended in; from `fade_start` to the last depth (the shadow
/// distance) shadows fade out, and beyond it nothing is shadowed. With `by_coverage` (stable
/// cascades), a point reads the first map whose square holds it, which may be a nearer
/// slice's (finer) map than its view depth's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CascadeSlices {
    /// The number of slices (maps), 1 to [`MAX_CASCADES`].
    pub count: usize,
    /// z_0 < z_1 < ... < z_count (entries after `count` are unused).
    pub view_depths: [f64; MAX_CASCADES + 1],
    /// The blend band, as a fraction of each slice (0 to 0.5).
    pub blend: f64,
    /// Where the fade to unshadowed begins (z_count when there is no fade).
    pub fade_start: f64,
    /// The world row whose dot with (p, 1) is p's view depth (the camera's forward axis).
    pub depth_row_world: DVec4,
    /// Selection by coverage (stable cascades): a point reads the first map up to its view
    /// depth's slice's that holds it ([`CascadeSlices::covers`]); `false` picks by view depth
    /// alone. The nearer slices' maps are finer, and a stable map's square (around its
    /// slice's bounding sphere) reaches past its slice's far plane, so picking by coverage
    /// reads finer texels there than picking by depth; the squares are fixed in the world as
    /// the maps are, so what a point reads changes only where a square moves by a texel.
    pub by_coverage: bool,
}

impl CascadeSlices {
    /// The view depths z_0 ..= z_count.
    pub fn depths(&self) -> &[f64] {
        &self.view_depths[..=self.count]
    }

    /// Map `i`'s view depths, near and far: its slice, and the blend band at the end of slice
    /// i - 1, where the selection by depth already reads it.
    pub fn map_view_depths(&self, i: usize) -> [f64; 2] {
        let z = &self.view_depths;
        let near = if i == 0 {
            z[0]
        } else {
            z[i] - self.blend * (z[i] - z[i - 1])
        };
        [near, z[i + 1]]
    }

    /// The shadow distance: the last view depth.
    pub fn shadow_distance(&self) -> f64 {
        self.view_depths[self.count]
    }

    /// The slice of view depth `depth` (the first below z_0, the last beyond the end).
    pub fn slice_of(&self, depth: f64) -> usize {
        (1..self.count)
            .take_while(|&i| depth >= self.view_depths[i])
            .count()
    }

    /// The texels a map picked by coverage keeps clear of its square's edge (a 5x5 filter
    /// reaches 2, the normal offset 1).
    pub const COVER_MARGIN_TEXELS: u32 = 4;

    /// Whether `map` (orthographic, as stable cascades' are) holds world point `p` for the
    /// selection by coverage: its clip x and y within the map's inset square less
    /// [`CascadeSlices::COVER_MARGIN_TEXELS`] texels on every side, so that a filter or the
    /// normal offset around the point stays inside.
    pub fn covers(map: &ShadowMap, p: DVec3) -> bool {
        let border = (map.viewport_inset + Self::COVER_MARGIN_TEXELS) as f64;
        let limit = 1.0 - 2.0 * border / map.resolution as f64;
        let h = p.extend(1.0);
        let (x, y) = (map.clip_from_world.row(0), map.clip_from_world.row(1));
        x.dot(h).abs().max(y.dot(h).abs()) <= limit
    }

    /// The map of `maps` (the cascades') world point `p` reads, outside any blend band: its
    /// view depth's slice's, or by coverage the first up to that one that holds it.
    pub fn map_of(&self, maps: &[ShadowMap], p: DVec3) -> usize {
        let slice = self.slice_of(self.depth_row_world.dot(p.extend(1.0)));
        if !self.by_coverage {
            return slice;
        }
        (0..slice.min(maps.len()))
            .find(|&i| Self::covers(&maps[i], p))
            .unwrap_or(slice)
    }
}

impl MapSelection {
    /// The name used in JSON output.
    pub fn kind(&self) -> &'static str {
        match self {
            MapSelection::Single => "single",
            MapSelection::Plane { .. } => "plane",
            MapSelection::Cascades(_) => "cascades",
            MapSelection::CubeFaces(_) => "cube_faces",
            MapSelection::DualParaboloid { .. } => "dual_paraboloid",
        }
    }

    /// Which of `maps` (the setup's, [`ShadowSetup::maps`]) the world point `p` reads;
    /// `None` where no map covers it (a cube face without a map: the point reads as lit).
    pub fn map_for(&self, maps: &[ShadowMap], p: DVec3) -> Option<usize> {
        match self {
            MapSelection::Single => Some(0),
            MapSelection::Plane { .. } | MapSelection::DualParaboloid { .. } => {
                let plane = self.two_map_plane()?;
                Some(usize::from(plane.dot(p.extend(1.0)) > 0.0))
            }
            MapSelection::Cascades(slices) => Some(slices.map_of(maps, p)),
            MapSelection::CubeFaces(faces) => faces.map_of(PointLight::face_of(p - faces.position)),
        }
    }

    /// For the selections of two maps by a plane, the world plane (a, b, c, d) whose positive
    /// side reads `maps[1]`: SPPSM's, or the plane through a point light across its
    /// paraboloid maps' axis (the far side of the first hemisphere).
    pub fn two_map_plane(&self) -> Option<DVec4> {
        match self {
            MapSelection::Plane { plane_world } => Some(*plane_world),
            MapSelection::DualParaboloid { position, axis } => {
                Some((-*axis).extend(axis.dot(*position)))
            }
            _ => None,
        }
    }
}

/// How a two-map setup's caster boxes fall on its plane (what each depth pass draws).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CastersBySide {
    /// Wholly on the focused map's side: drawn into it only.
    pub focused_only: usize,
    /// Wholly on the perspective map's side: drawn into it only.
    pub perspective_only: usize,
    /// Straddling the plane: drawn into both.
    pub both: usize,
}

/// A degenerate but valid configuration and what the technique did about it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// No receiver box has a visible part (inside the view frustum and, for a spot light, the
    /// light frustum). Nothing visible can be shadowed; the uniform map is returned.
    NoVisibleReceiver,
    /// The view direction is (anti)parallel to the light direction, so the view-aligned
    /// light frame is undefined; the frame fixed by the light direction alone is used.
    LightParallelToView,
    /// The spot light's frustum does not meet the view frustum inside the scene box: nothing
    /// visible is lit by it; the uniform map is returned.
    SpotLightMissesView,
    /// The spot light's frustum does not meet the scene box: the map covers the whole cone.
    SpotLightMissesScene,
    /// No caster overlaps the visible receivers as seen from the light: nothing visible can
    /// be shadowed; the map is fitted to the visible receivers alone.
    NoCasterForReceivers,
    /// The convex body B came out empty or flat (the view frustum only grazes the scene box);
    /// the depth range is taken from the casters alone (a warp falls back to the focused map).
    DegenerateFocusBody,
    /// The technique's paper defines its warp for directional lights only (TSM, XPSM); for a
    /// spot light the focused map is used.
    SpotLightNotWarped,
    /// SPPSM: the separating plane is undefined: the perspective map fell back (the focused
    /// map alone is used), or one map is finer by the same factor everywhere (it alone is
    /// used).
    NoSeparatingPlane,
    /// The warp at the technique's strength would sample the visible lit receivers more
    /// coarsely than the focused map it starts from (the 95th percentile of pixels per texel
    /// over [`crate::ViewSamples`]); it was weakened until it does not
    /// ([`Diagnostics::warp_strength`] says how far).
    WarpLimited,
    /// Even a weakened warp samples the visible lit receivers more coarsely than the focused
    /// map; the focused map is used.
    WarpCoarserThanFocused,
    /// Stable cascades snap a directional light's texel grid to the world; a spot light's
    /// cascades are fitted like unstable ones.
    StableNeedsDirectionalLight,
}

impl Fallback {
    /// A short snake_case name, for JSON and logs.
    pub fn name(&self) -> &'static str {
        match self {
            Fallback::NoVisibleReceiver => "no_visible_receiver",
            Fallback::LightParallelToView => "light_parallel_to_view",
            Fallback::SpotLightMissesView => "spot_light_misses_view",
            Fallback::SpotLightMissesScene => "spot_light_misses_scene",
            Fallback::NoCasterForReceivers => "no_caster_for_receivers",
            Fallback::DegenerateFocusBody => "degenerate_focus_body",
            Fallback::SpotLightNotWarped => "spot_light_not_warped",
            Fallback::NoSeparatingPlane => "no_separating_plane",
            Fallback::WarpLimited => "warp_limited",
            Fallback::WarpCoarserThanFocused => "warp_coarser_than_focused",
            Fallback::StableNeedsDirectionalLight => "stable_needs_directional_light",
        }
    }

    /// What happened and what was done, in a sentence.
    pub fn reason(&self) -> &'static str {
        match self {
            Fallback::NoVisibleReceiver => {
                "no receiver is visible; the map covers the whole scene (uniform map)"
            }
            Fallback::LightParallelToView => {
                "the view direction is parallel to the light; the light frame is fixed by the light direction alone"
            }
            Fallback::SpotLightMissesView => {
                "the spot light cannot see the view frustum; the map covers the whole scene (uniform map)"
            }
            Fallback::SpotLightMissesScene => {
                "the spot light's frustum misses the scene box; the map covers the whole cone"
            }
            Fallback::NoCasterForReceivers => {
                "no caster can shadow a visible receiver; the map is fitted to the visible receivers"
            }
            Fallback::DegenerateFocusBody => {
                "the focus body B is empty or flat; the depth range comes from the casters alone"
            }
            Fallback::SpotLightNotWarped => {
                "this technique's warp is defined for directional lights only; the focused map is used"
            }
            Fallback::NoSeparatingPlane => {
                "the separating plane is undefined: the perspective map fell back (the focused map alone is used) or one map is finer by the same factor everywhere (it alone is used)"
            }
            Fallback::WarpLimited => {
                "at full strength the warp would sample the visible receivers more coarsely than the focused map; it was weakened"
            }
            Fallback::WarpCoarserThanFocused => {
                "even weakened, the warp samples the visible receivers more coarsely than the focused map; the focused map is used"
            }
            Fallback::StableNeedsDirectionalLight => {
                "stable cascades snap a directional light's texel grid; the spot light's cascades are fitted like unstable ones"
            }
        }
    }
}

impl fmt::Display for Fallback {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.name(), self.reason())
    }
}

/// Which rotation about the light direction a map uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightFrameKind {
    /// Fixed by the light direction alone (does not move with the camera).
    Fixed,
    /// The map's +y is the view direction projected onto the shadow-map plane (LiSPSM paper,
    /// section 3.4).
    ViewAligned,
}

impl LightFrameKind {
    /// A short snake_case name.
    pub fn name(&self) -> &'static str {
        match self {
            LightFrameKind::Fixed => "fixed",
            LightFrameKind::ViewAligned => "view_aligned",
        }
    }
}

/// What one map of a setup fell back to, so that a caller can tell which cascade, cube face
/// or SPPSM map it was ([`ShadowSetup::map_diagnostics`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MapDiagnostics {
    /// The fallbacks that fired for this map, in order.
    pub fallbacks: Vec<Fallback>,
    /// This map's share of the warp strength (see [`Diagnostics::warp_strength`]).
    pub warp_strength: Option<f64>,
}

/// What a technique saw and did, beyond the matrices.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostics {
    /// Every fallback that fired, in order (over all maps: [`Diagnostics::maps`] says which).
    pub fallbacks: Vec<Fallback>,
    /// Setups of several maps (cascades, cube faces, SPPSM): one entry per map, in the order
    /// of [`ShadowSetup::maps`]. Empty for a single map, whose diagnostics are the setup's.
    pub maps: Vec<MapDiagnostics>,
    /// The light frame the map(s) use.
    pub light_frame: LightFrameKind,
    /// The angle gamma between the view direction and the light direction, in degrees
    /// (LiSPSM paper, section 4.4): 90 is the ideal case, 0 and 180 the miner's lamp and
    /// dueling frusta.
    pub gamma_degrees: f64,
    /// Receiver boxes with a visible part.
    pub visible_receivers: usize,
    /// Caster boxes not culled in light space: every caster that can shadow a visible
    /// receiver is among them. A subtree of the casters' hierarchy whose image adds nothing
    /// to the map's extents is counted whole without being opened (telling its boxes apart
    /// would open every subtree along the receivers' edges), so the count may include boxes
    /// of such a subtree that lie just beside the receivers, and depends on the hierarchy's
    /// shape.
    pub relevant_casters: usize,
    /// Caster boxes culled: outside the light frustum, beside the visible receivers as seen
    /// from the light, or behind them all (the casters less the relevant ones).
    pub culled_casters: usize,
    /// Relevant casters whose boxes' surfaces reach in front of a spot light's near plane
    /// inside its frustum, where the map clips them (their part within
    /// [`crate::SPOT_NEAR_FRACTION`] of the range casts no shadow; a box that holds all of
    /// that space, with the light inside it, loses nothing and is not counted); a point light
    /// counts them once per cube face.
    pub casters_clipped_by_light_near: usize,
    /// Number of vertices of the convex body B (0 when not computed or empty).
    pub focus_body_vertices: usize,
    /// Whether the scene box had to grow to hold every box.
    pub scene_box_grown: bool,
    /// Two-map setups (SPPSM): how the caster boxes fall on the plane.
    pub casters_by_side: Option<CastersBySide>,
    /// Warps with the limit on: the fraction of the technique's warp strength used (1: the
    /// full warp; less: weakened, [`Fallback::WarpLimited`]; 0: the focused map,
    /// [`Fallback::WarpCoarserThanFocused`]). `None` where no limit ran (for a point light:
    /// the smallest over its faces).
    pub warp_strength: Option<f64>,
    /// A point light's cube faces without a map: no visible receiver in the face's frustum,
    /// or none that a caster can shadow. (For a point light the caster counts above are
    /// summed over the faces with maps; each visible receiver counts once.)
    pub cube_faces_skipped: usize,
}

impl Diagnostics {
    pub(crate) fn new(camera: &Camera, light: &Light, scene: &SceneBounds) -> Self {
        let cos = camera.forward().dot(light.direction()).clamp(-1.0, 1.0);
        Self {
            fallbacks: Vec::new(),
            maps: Vec::new(),
            light_frame: LightFrameKind::Fixed,
            gamma_degrees: cos.acos().to_degrees(),
            visible_receivers: 0,
            relevant_casters: 0,
            culled_casters: 0,
            casters_clipped_by_light_near: 0,
            focus_body_vertices: 0,
            scene_box_grown: scene.scene_box_grown(),
            casters_by_side: None,
            warp_strength: None,
            cube_faces_skipped: 0,
        }
    }
}

/// The result of a setup: the shadow maps, how a pixel picks one, and diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowSetup {
    /// The technique's name.
    pub technique: &'static str,
    /// The shadow maps.
    pub maps: Vec<ShadowMap>,
    /// How a pixel picks its map.
    pub selection: MapSelection,
    /// What the technique saw and did.
    pub diagnostics: Diagnostics,
}

impl ShadowSetup {
    /// The first fallback that fired, if any.
    pub fn fallback(&self) -> Option<Fallback> {
        self.diagnostics.fallbacks.first().copied()
    }

    /// What map `index` fell back to: its own entry where the setup has several maps, else
    /// the setup's diagnostics.
    pub fn map_diagnostics(&self, index: usize) -> MapDiagnostics {
        match self.diagnostics.maps.get(index) {
            Some(map) if self.diagnostics.maps.len() == self.maps.len() => map.clone(),
            _ => MapDiagnostics {
                fallbacks: self.diagnostics.fallbacks.clone(),
                warp_strength: self.diagnostics.warp_strength,
            },
        }
    }

    /// Which map the world point `p` reads ([`MapSelection::map_for`] over these maps).
    pub fn map_for(&self, p: DVec3) -> Option<usize> {
        self.selection.map_for(&self.maps, p)
    }
}

/// Everything a technique needs: borrowed, so a setup per frame allocates little.
#[derive(Debug, Clone, Copy)]
pub struct SetupInput<'a> {
    /// The camera.
    pub camera: &'a Camera,
    /// The light.
    pub light: &'a Light,
    /// The scene's bounds.
    pub scene: &'a SceneBounds,
    /// The map size.
    pub map: MapSettings,
    /// What the pixels see of the lit receivers, when the caller has them for this frame
    /// (the warp limit compares maps on them); `None`: a technique that needs them casts
    /// them itself.
    pub samples: Option<&'a ViewSamples>,
}

/// A shadow-map technique: camera, light and scene bounds in, shadow maps out.
pub trait ShadowTechnique {
    /// The technique's name (`uniform`, `focused`, ...).
    fn name(&self) -> &'static str;

    /// Computes the shadow maps for one frame. A point light's are the technique's map of
    /// each cube face ([`crate::techniques::Cube`]'s module documentation); techniques with
    /// several maps per light (SPPSM, cascades) refuse point lights.
    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError>;
}

/// Every technique gnomon has, by name, for command lines and configuration files.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Technique {
    /// Uniform shadow map (SSM).
    Uniform(Uniform),
    /// Focused shadow map with unit cube clipping (FSM).
    Focused(Focused),
    /// Light space perspective shadow map (LiSPSM).
    Lispsm(Lispsm),
    /// Trapezoidal shadow map (TSM).
    Tsm(Tsm),
    /// Extended perspective shadow map (XPSM).
    Xpsm(Xpsm),
    /// Perspective shadow map (PSM).
    Psm(Psm),
    /// Separating-plane perspective shadow maps (SPPSM): the focused map and a perspective
    /// one.
    Sppsm(Sppsm),
    /// Cascaded shadow maps: a map per slice of the view, each fitted by a single-map
    /// technique, or stable cascades.
    Cascades(Cascades),
    /// A point light's cube maps, each face focused.
    Cube(Cube),
    /// A point light's two paraboloid maps.
    Paraboloid(DualParaboloid),
}

impl Technique {
    /// The names [`Technique::from_str`] accepts.
    pub const NAMES: &'static [&'static str] = &[
        "uniform",
        "focused",
        "psm",
        "lispsm",
        "tsm",
        "xpsm",
        "sppsm",
        "cascades",
        "cube",
        "paraboloid",
    ];

    /// Each technique with default parameters.
    pub fn all() -> Vec<Technique> {
        Self::NAMES
            .iter()
            .map(|n| n.parse().expect("every listed name parses"))
            .collect()
    }

    /// Whether the technique takes `light`: `cube` and `paraboloid` take point lights only; SPPSM and the
    /// cascades (several maps per light) take every light but point lights; the others take
    /// every light (a point light per cube face).
    pub fn takes(&self, light: &Light) -> bool {
        let point = matches!(light, Light::Point(_));
        match self {
            Technique::Cube(_) | Technique::Paraboloid(_) => point,
            Technique::Sppsm(_) | Technique::Cascades(_) => !point,
            _ => true,
        }
    }

    /// The technique for the next frame of a frame loop whose last setup with it was
    /// `setup`: adaptive cascades learn the number of cascades kept
    /// ([`Cascades::adaptive_previous`](crate::Cascades::adaptive_previous)); every other
    /// technique is unchanged (they keep no state between frames).
    pub fn for_next_frame(&self, setup: &ShadowSetup) -> Technique {
        match self {
            Technique::Cascades(c) if c.adaptive => Technique::Cascades(crate::Cascades {
                adaptive_previous: Some(setup.maps.len().max(1)),
                ..*c
            }),
            other => *other,
        }
    }

    fn as_dyn(&self) -> &dyn ShadowTechnique {
        match self {
            Technique::Uniform(t) => t,
            Technique::Focused(t) => t,
            Technique::Lispsm(t) => t,
            Technique::Tsm(t) => t,
            Technique::Xpsm(t) => t,
            Technique::Psm(t) => t,
            Technique::Sppsm(t) => t,
            Technique::Cascades(t) => t,
            Technique::Cube(t) => t,
            Technique::Paraboloid(t) => t,
        }
    }
}

impl ShadowTechnique for Technique {
    fn name(&self) -> &'static str {
        self.as_dyn().name()
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        self.as_dyn().setup(input)
    }
}

/// The error for an unknown technique name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownTechnique(pub String);

impl fmt::Display for UnknownTechnique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown technique '{}' (known: {})",
            self.0,
            Technique::NAMES.join(", ")
        )
    }
}

impl std::error::Error for UnknownTechnique {}

impl FromStr for Technique {
    type Err = UnknownTechnique;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "uniform" | "ssm" => Ok(Technique::Uniform(Uniform)),
            "focused" | "fsm" => Ok(Technique::Focused(Focused)),
            "lispsm" => Ok(Technique::Lispsm(Lispsm::default())),
            "tsm" => Ok(Technique::Tsm(Tsm::default())),
            "xpsm" => Ok(Technique::Xpsm(Xpsm::default())),
            "psm" => Ok(Technique::Psm(Psm::default())),
            "sppsm" => Ok(Technique::Sppsm(Sppsm::default())),
            "cascades" | "csm" => Ok(Technique::Cascades(Cascades::default())),
            "cube" => Ok(Technique::Cube(Cube)),
            "paraboloid" | "dpsm" => Ok(Technique::Paraboloid(DualParaboloid)),
            _ => Err(UnknownTechnique(s.to_string())),
        }
    }
}

/// Computes a setup with `technique`: validates the map settings, runs the technique and
/// checks that every matrix is finite.
pub fn compute_setup(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
) -> Result<ShadowSetup, SetupError> {
    checked_setup(technique, camera, light, scene, map, None)
}

/// [`compute_setup`] with the frame's [`ViewSamples`]: what the renderer's pixels see (its
/// real surfaces, where the core knows only boxes), or samples shared by several setups of one
/// frame. The warp limit compares maps on them.
pub fn compute_setup_with_samples(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
    samples: &ViewSamples,
) -> Result<ShadowSetup, SetupError> {
    checked_setup(technique, camera, light, scene, map, Some(samples))
}

fn checked_setup(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
    samples: Option<&ViewSamples>,
) -> Result<ShadowSetup, SetupError> {
    map.validate()?;
    let setup = technique.setup(&SetupInput {
        camera,
        light,
        scene,
        map,
        samples,
    })?;
    if setup.maps.iter().all(ShadowMap::is_finite) {
        Ok(setup)
    } else {
        Err(SetupError::NumericalFailure {
            technique: technique.name(),
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::bounds::Aabb;
    use crate::camera::Lens;
    use crate::light::{DirectionalLight, PointLight, SpotLight};

    /// `Technique::takes` says what the setups themselves refuse: a technique takes a light
    /// exactly when its setup does not refuse it for its kind.
    #[test]
    fn takes_agrees_with_the_setups_refusals() {
        let ground =
            Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
        let block = Aabb::new(DVec3::new(-5.0, 0.0, -5.0), DVec3::new(5.0, 10.0, 5.0)).unwrap();
        let scene = SceneBounds::new(vec![block], vec![ground, block], None).unwrap();
        let camera = Camera::look_at(
            DVec3::new(30.0, 20.0, 30.0),
            DVec3::ZERO,
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let lights = [
            Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.2)).unwrap()),
            Light::Spot(
                SpotLight::new(DVec3::new(0.0, 40.0, 10.0), -DVec3::Y, 50.0, 100.0).unwrap(),
            ),
            Light::Point(PointLight::new(DVec3::new(8.0, 6.0, 8.0), 60.0).unwrap()),
        ];
        for technique in Technique::all() {
            for light in &lights {
                let result =
                    compute_setup(&technique, &camera, light, &scene, MapSettings::default());
                let refused = matches!(
                    result,
                    Err(SetupError::NeedsPointLight { .. }
                        | SetupError::PointLightUnsupported { .. })
                );
                assert_eq!(
                    technique.takes(light),
                    !refused,
                    "{} with {light:?}: {result:?}",
                    technique.name()
                );
                assert!(
                    refused || result.is_ok(),
                    "{}: {result:?}",
                    technique.name()
                );
            }
        }
    }
}
