//! What a shadow setup returns: the maps, how a pixel picks one, and the map settings.

use glam::{DMat4, DVec3, DVec4};

use crate::diagnostics::{Diagnostics, Fallback, MapDiagnostics};
use crate::error::SetupError;
use crate::light::{CubeFace, PointLight};
use crate::{MAX_RESOLUTION, MIN_RESOLUTION};

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
    /// Seidel 2002). `clip_from_world` is only the affine map to the hemisphere's frame in
    /// units of the light's range (q, with q.z along the hemisphere's axis). A point lands at
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
    /// whole map (+y up, so texture v = 0.5 - 0.5 y), and the focus region lands inside the
    /// inset square `[-s, s]^2` (see [`MapSettings::inset_ndc`]). z is in [0, 1] for every
    /// relevant point, so the rasteriser clips none. For a directional light's uniform,
    /// focused, LiSPSM and XPSM maps it runs from the focus region's near plane (0) to its far
    /// plane (1). Maps seen from a point (spot lights, cube faces) run from 0 at the near plane
    /// toward 0.5: their near planes lie at a millionth of the range, and the usual z would
    /// crowd every point within f32 roundings of 1, where a rasteriser clips some. TSM and PSM
    /// have the constant 0.5. Depth comparisons use [`ShadowMap::depth_from_world`].
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
    /// Two maps and a world plane (a, b, c, d) with (a, b, c) of unit length. A point p
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
/// forward axis) from `view_depths[i]` to `view_depths[i + 1]`. In the last `blend` fraction
/// of a slice the next map is blended in. From `fade_start` to the last depth (the shadow
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
    /// slice's bounding sphere) reaches past its slice's far plane. So picking by coverage
    /// reads finer texels there than picking by depth. The squares are fixed in the world as
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
