//! What a setup saw and did: fallbacks, counts and the warp it kept.

use std::fmt;

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::light::Light;

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
/// or SPPSM map it was
/// ([`ShadowSetup::map_diagnostics`](crate::ShadowSetup::map_diagnostics)).
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
    /// of [`ShadowSetup::maps`](crate::ShadowSetup::maps). Empty for a single map, whose
    /// diagnostics are the setup's.
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
    /// to the map's extents is counted whole without being opened: telling its boxes apart
    /// would open every subtree along the receivers' edges. So the count may include boxes
    /// of such a subtree that lie just beside the receivers, and depends on the hierarchy's
    /// shape.
    pub relevant_casters: usize,
    /// Caster boxes culled: outside the light frustum, beside the visible receivers as seen
    /// from the light, or behind them all (the casters less the relevant ones).
    pub culled_casters: usize,
    /// Relevant casters whose boxes' surfaces reach in front of a spot light's near plane
    /// inside its frustum, where the map clips them: their part within
    /// [`crate::SPOT_NEAR_FRACTION`] of the range casts no shadow. A box that holds all of
    /// that space, with the light inside it, loses nothing and is not counted. A point light
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
