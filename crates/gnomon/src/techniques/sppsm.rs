//! Separating-plane perspective shadow maps (SPPSM).
//!
//! Mikkelsen, "Separating-Plane Perspective Shadow Mapping" (2007).
//!
//! Two maps for the same camera and light: the focused map (FSM) and a perspective one (PSM
//! as in the paper, or LiSPSM, TSM, XPSM). For a map M (world to unnormalised texel
//! coordinates), the area a screen pixel covers in the map is |det J| (section 3.1); the paper
//! shows (sections 3.2, 5) that for maps sharing the light's projection the comparison
//! |det J_P| > |det J_F| is the side of a plane through the light's eye point (eq. 7):
//!
//! ```text
//! cbrt|det M_P| w_F - cbrt|det M_F| w_P > 0
//! ```
//!
//! where det M is the determinant of the map's rows (x, y, w) on the rays of the light and w
//! its homogeneous w. Every map here is constant along the light's rays (its rows x, y and w
//! vanish on the light's eye point), so the rows can be written in coordinates of the rays.
//! For a spot light these are the direction from the light, u = p - L, and det M is the
//! paper's det(A_34). For a directional light they are the light-plane coordinates (X, Y, 1)
//! of a point (p = X right + Y up + Z d). There the paper's 3x3 minor vanishes for
//! orthographic maps, but the same comparison holds with det M of the 2D projective map
//! (X, Y) -> texel: the Jacobian by the screen is that map's Jacobian times one shared by
//! both maps. The plane then contains the light direction.
//!
//! Iterative focusing (section 6): each map is refocused on the part of I (the scene seen by
//! the camera and the light) on its side of the plane, and the plane recomputed; in the last
//! iteration the plane is kept, so that I's part on the plane stays inside both focus regions
//! and the sign of the plane alone picks the map. (Ours, not the paper's: after two moves the
//! plane jumps to where its moves converge, `next_plane`.)
//! - The focused map is re-evaluated as the paper does, on the frame's part on its side of
//!   the plane ([`crate::techniques::basis::Part::Side`]: P, the visible receivers and the
//!   casters cut by it; the plane contains the light's rays, so a caster's part on the other
//!   side cannot shadow a receiver on this side). P, the receivers' classification against the
//!   view and the casters in light space are computed once for the frame and shared by both
//!   maps and every iteration. It is taken when it is no coarser in area than the focused
//!   map on all of I anywhere on its side (it can pick another light frame), else that map
//!   is cropped (below).
//! - The perspective map keeps its warp and is cropped: the smallest rectangle of its square
//!   around P's part on its side is stretched to the square (a 2D scale >= 1 and offset after
//!   the divide). Deviation from the paper, which re-evaluates the warp on the side: a warp
//!   fitted to less of I can come out coarser somewhere on its side (measured on the demo's
//!   named views, the re-evaluated PSM was coarser than PSM on all of I in 5 of 7), while a
//!   crop is finer along every direction everywhere it is read.
//!
//! Refocusing can overshoot: a map focused on less of I gets finer, the plane moves toward
//! the other map, whose side grows, and the plane can oscillate with a growing swing. So an
//! iteration's maps and plane are kept only when, at every vertex of P on each side, the map
//! read there is at least as fine in area as both techniques' own maps on all of I (exact
//! over P: see `no_coarser`). Else the last iteration that passed stays, down to both maps
//! on all of I with their exact plane. So every point of P reads a map at least as fine, in
//! area, as the better of the two techniques alone.
//!
//! Selection: [`MapSelection::Plane`], positive side = the perspective map (`maps[1]`),
//! negative side = the focused map (`maps[0]`). Degenerate cases, each reported as
//! [`Fallback::NoSeparatingPlane`]: when the perspective technique falls back (its warp is
//! undefined: view along the light, spot lights for TSM and XPSM, a flat B) the focused map
//! alone is used; when the plane's normal vanishes (both maps affine on the light's rays, as
//! TSM with parallel sides: one map is then finer by the same factor everywhere) the finer
//! map alone. Nothing visible gives the uniform map as for every technique.

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};

use crate::bounds::SceneBounds;
use crate::diagnostics::{CastersBySide, Fallback};
use crate::error::SetupError;
use crate::frame::Frame;
use crate::geometry::{ConvexPolyhedron, Plane};
use crate::light::Light;
use crate::map::{MapProjection, MapSelection, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::{FocusBasis, Part};
use crate::techniques::focused::focused_map;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::{Focused, Lispsm, Psm, Tsm, Xpsm};

/// The perspective map of an SPPSM setup.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PerspectiveMap {
    /// Perspective shadow maps (the paper's choice).
    Psm(Psm),
    /// Light space perspective shadow maps.
    Lispsm(Lispsm),
    /// Trapezoidal shadow maps.
    Tsm(Tsm),
    /// Extended perspective shadow maps.
    Xpsm(Xpsm),
}

impl PerspectiveMap {
    /// The names [`PerspectiveMap::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["psm", "lispsm", "tsm", "xpsm"];

    /// The technique with default parameters by name.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name.to_ascii_lowercase().as_str() {
            "psm" => Self::Psm(Psm::default()),
            "lispsm" => Self::Lispsm(Lispsm::default()),
            "tsm" => Self::Tsm(Tsm::default()),
            "xpsm" => Self::Xpsm(Xpsm::default()),
            _ => return None,
        })
    }

    fn as_warp(&self) -> &dyn LimitedWarp {
        match self {
            Self::Psm(t) => t,
            Self::Lispsm(t) => t,
            Self::Tsm(t) => t,
            Self::Xpsm(t) => t,
        }
    }

    /// The technique's name.
    pub fn name(&self) -> &'static str {
        self.as_warp().name()
    }

    /// The same map without the warp limit: SPPSM picks the finer map per point itself.
    fn without_limit(self) -> Self {
        match self {
            Self::Psm(t) => Self::Psm(Psm { limit: false, ..t }),
            Self::Lispsm(t) => Self::Lispsm(Lispsm { limit: false, ..t }),
            Self::Tsm(t) => Self::Tsm(Tsm { limit: false, ..t }),
            Self::Xpsm(t) => Self::Xpsm(Xpsm { limit: false, ..t }),
        }
    }
}

/// Separating-plane perspective shadow maps (Mikkelsen 2007): the focused map and a
/// perspective map, each pixel reading the one with the better area sampling; see the module
/// documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sppsm {
    /// The perspective map: PSM, LiSPSM, TSM or XPSM (with its parameters).
    pub perspective: PerspectiveMap,
    /// Focusing iterations, 1 to 20: 1 focuses both maps on all of I.
    pub iterations: u32,
}

impl Default for Sppsm {
    /// PSM (as in the paper's implementation) and 10 iterations.
    fn default() -> Self {
        Self {
            perspective: PerspectiveMap::Psm(Psm::default()),
            iterations: 10,
        }
    }
}

impl Sppsm {
    /// The most focusing iterations allowed.
    pub const MAX_ITERATIONS: u32 = 20;

    fn validate(&self) -> Result<(), SetupError> {
        if !(1..=Self::MAX_ITERATIONS).contains(&self.iterations) {
            return Err(SetupError::InvalidParameter {
                name: "sppsm iterations (1 to 20)",
                value: self.iterations as f64,
            });
        }
        Ok(())
    }
}

/// A map's rows (x, y, w) on the light's rays, in unnormalised texel units: for a
/// directional light on the light-plane coordinates (X, Y, 1), for a spot light on the
/// direction u = p - L from the light. Rows of the returned matrix: x, y, w.
fn ray_rows(map: &ShadowMap, basis: &[DVec4; 3]) -> DMat3 {
    let m = map.clip_from_world;
    let texel = 0.5 * map.resolution as f64;
    let row = |r: usize| basis.map(|b| m.row(r).dot(b));
    let (x, y, w) = (row(0), row(1), row(3));
    // Unnormalised texel coordinates: (x + w, y + w) res / 2 over w; adding w to x and y
    // leaves the determinant alone, the scale does not.
    DMat3::from_cols_array(&[
        texel * x[0],
        texel * y[0],
        w[0],
        texel * x[1],
        texel * y[1],
        w[1],
        texel * x[2],
        texel * y[2],
        w[2],
    ])
}

/// The basis in which the maps' rows are compared: for a directional light (right, 0),
/// (up, 0), (0, 1); for a spot (or point) light the world axes as directions from the light.
fn ray_basis(light: &Light) -> [DVec4; 3] {
    match light {
        Light::Directional(d) => {
            let forward = d.direction();
            let right = forward.any_orthonormal_vector();
            let up = right.cross(forward);
            [right.extend(0.0), up.extend(0.0), DVec4::W]
        }
        Light::Spot(_) | Light::Point(_) => [DVec4::X, DVec4::Y, DVec4::Z],
    }
}

/// The world plane (n, d) of a 3-vector of coefficients `l` in [`ray_basis`]: for a
/// directional light their combination of the basis, for a spot (or point) light the plane
/// through the light with normal `l`.
fn ray_plane(light: &Light, l: DVec3) -> DVec4 {
    match light {
        Light::Directional(_) => {
            let [right, up, w] = ray_basis(light);
            l.x * right + l.y * up + l.z * w
        }
        Light::Spot(_) | Light::Point(_) => {
            let position = light.position().unwrap_or(DVec3::ZERO);
            l.extend(-l.dot(position))
        }
    }
}

/// The separating plane of eq. 7 in world space, normalised (|n| = 1): positive where the
/// perspective map covers a pixel with more texels (larger |det J|) than the focused map.
/// `None` when the plane is undefined: its normal vanishes (both maps affine on the light's
/// rays, one then finer by the same factor everywhere) or a map is singular on the rays.
pub fn separating_plane(
    focused: &ShadowMap,
    perspective: &ShadowMap,
    light: &Light,
) -> Option<DVec4> {
    let basis = ray_basis(light);
    let (f, p) = (ray_rows(focused, &basis), ray_rows(perspective, &basis));
    let (det_f, det_p) = (f.determinant().abs().cbrt(), p.determinant().abs().cbrt());
    // Rows of a DMat3 built column by column: row 2 (w) is (col0.z, col1.z, col2.z).
    let w = |m: &DMat3| DVec3::new(m.x_axis.z, m.y_axis.z, m.z_axis.z);
    let coefficients = det_p * w(&f) - det_f * w(&p);
    let plane = ray_plane(light, coefficients);
    let length = plane.truncate().length();
    if !(length.is_finite() && length > 1e-12 * (det_p * w(&f).length() + det_f * w(&p).length()))
        || det_f == 0.0
        || det_p == 0.0
    {
        return None;
    }
    Some(plane / length)
}

/// |det J| of a map at a world point, J the Jacobian of its unnormalised texel coordinates
/// with respect to the light-ray coordinates of [`separating_plane`] (the screen's Jacobian
/// is this times a factor both maps share): |det M| / w^3.
pub fn ray_area_density(map: &ShadowMap, light: &Light, p: DVec3) -> f64 {
    AreaDensity::new(map, light).at(p)
}

/// [`ray_area_density`] of one map at many points: |det M| and the map's w row, made once.
struct AreaDensity {
    det: f64,
    w: DVec4,
}

impl AreaDensity {
    fn new(map: &ShadowMap, light: &Light) -> Self {
        let basis = ray_basis(light);
        Self {
            det: ray_rows(map, &basis).determinant().abs(),
            w: map.clip_from_world.row(3),
        }
    }

    fn at(&self, p: DVec3) -> f64 {
        self.det / self.w.dot(p.extend(1.0)).abs().powi(3)
    }
}

/// `plane` (n, d with |n| = 1, n . p + d >= 0 inside) as a [`Plane`].
fn side_plane(plane: DVec4) -> Plane {
    Plane {
        normal: plane.truncate(),
        offset: plane.w,
    }
}

/// The vertices of `body` on the positive side of `plane`.
fn points_on_side(body: &ConvexPolyhedron, tolerance: f64, plane: DVec4) -> Vec<DVec3> {
    body.clip(&side_plane(plane), tolerance).vertices(tolerance)
}

/// `map` cropped to the part of its square where `points` land: the same warp with the
/// smallest rectangle around the points' images (within the inset square) stretched to the
/// inset square, a 2D scale and offset after the divide. Every point of that rectangle is
/// then sampled at least as finely along both map axes as before. `None` when a point lies behind a
/// perspective map's centre, or no point lands inside the inset square.
fn crop(map: &ShadowMap, points: &[DVec3]) -> Option<ShadowMap> {
    let s = map.inset_ndc();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in points {
        let clip = map.clip_from_world * p.extend(1.0);
        // (NaN-safe: a NaN w is not positive either.)
        if clip.w.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let ndc = DVec2::new(clip.x, clip.y) / clip.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    // A texel's margin against rounding, within the inset square.
    let margin = 2.0 / map.resolution as f64;
    let lo = (lo - margin).max(DVec2::splat(-s));
    let hi = (hi + margin).min(DVec2::splat(s));
    if !(lo.x < hi.x && lo.y < hi.y) {
        return None;
    }
    // ndc' = a ndc + b maps [lo, hi] to [-s, s]; on clip rows: x' = a x + b w.
    let a = 2.0 * s / (hi - lo);
    let b = -s * (hi + lo) / (hi - lo);
    let m = map.clip_from_world;
    let (x, y, w) = (m.row(0), m.row(1), m.row(3));
    let mut cropped = *map;
    cropped.clip_from_world =
        DMat4::from_cols(a.x * x + b.x * w, a.y * y + b.y * w, m.row(2), w).transpose();
    Some(cropped)
}

/// Whether `map` samples at least as finely in area (|det J| on the light's rays) as
/// `reference` at every point of the convex hull of `points`. Checking the points is exact:
/// the ratio of the two densities is a constant times (w_reference / w_map)^3, and a ratio of
/// affine functions positive on a convex polytope takes its extremes at its vertices.
fn no_coarser(map: &ShadowMap, reference: &ShadowMap, light: &Light, points: &[DVec3]) -> bool {
    let (ours, theirs) = (
        AreaDensity::new(map, light),
        AreaDensity::new(reference, light),
    );
    points
        .iter()
        .all(|p| ours.at(*p) >= theirs.at(*p) * (1.0 - 1e-9))
}

/// How many caster boxes lie wholly on each side of `plane`, or straddle it: through the
/// casters' hierarchy, a subtree wholly on one side counted whole.
fn casters_by_side(scene: &SceneBounds, plane: DVec4) -> CastersBySide {
    let mut counts = CastersBySide::default();
    let (tree, arrays) = (scene.caster_tree(), scene.caster_arrays());
    let n = plane.truncate();
    let side = |c: DVec3, h: DVec3| {
        let d = n.dot(c) + plane.w;
        let r = n.abs().dot(h);
        if d - r >= 0.0 {
            Some(true)
        } else if d + r <= 0.0 {
            Some(false)
        } else {
            None
        }
    };
    let mut count = |side: Option<bool>, k: usize| match side {
        Some(true) => counts.perspective_only += k,
        Some(false) => counts.focused_only += k,
        None => counts.both += k,
    };
    let mut stack = if tree.is_empty() {
        Vec::new()
    } else {
        vec![0usize]
    };
    while let Some(node) = stack.pop() {
        match side(tree.nodes.center_of(node), tree.nodes.half_of(node)) {
            Some(whole) => count(Some(whole), tree.size(node)),
            None if tree.is_leaf(node) => {
                for &i in tree.boxes_of(node) {
                    let i = i as usize;
                    count(side(arrays.center_of(i), arrays.half_of(i)), 1);
                }
            }
            None => stack.extend(tree.children(node)),
        }
    }
    counts
}

/// Whether the plane `next` is `plane` up to `settle` (world units) in its offset and
/// round-off in its normal.
fn converged(plane: DVec4, next: DVec4, settle: f64) -> bool {
    (next.truncate() - plane.truncate()).length() <= 1e-9 && (next.w - plane.w).abs() <= settle
}

/// The plane the next refocusing uses, after it moved from `plane` to `next`, and the move
/// to remember (`last_step`: the offset's previous move along the same normal, if any). The
/// offset converges geometrically, each move about the same ratio r of the one before
/// (|r| < 1/2; a negative r swings the plane across its limit). So from two moves it settles
/// at `next + step r / (1 - r)` (Aitken's extrapolation). The plane jumps there, which saves
/// a refocusing of the focused map, and the moves start again. Where the moves do not shrink
/// so (the normal turns, |r| >= 1/2), it is `next`. Where the jump overshoots, the maps there
/// are kept only as any iteration's are: when no point reads a coarser map than either
/// technique alone.
fn next_plane(plane: DVec4, next: DVec4, last_step: Option<f64>) -> (DVec4, Option<f64>) {
    let same_normal = (next.truncate() - plane.truncate()).length() <= 1e-9;
    let step = next.w - plane.w;
    match last_step {
        Some(previous) if same_normal && previous != 0.0 => {
            let r = step / previous;
            if r != 0.0 && r.abs() < 0.5 {
                (next + DVec4::W * (step * r / (1.0 - r)), None)
            } else {
                (next, Some(step))
            }
        }
        _ => (next, same_normal.then_some(step)),
    }
}

/// How little the plane's offset must move for the refocusing to stop: a tenth of a texel of
/// `focused` where it is orthographic, else (or when the map says nothing) a millionth of
/// `scene_scale`. `focused` is the focused map on all of I, whose texels are the coarsest
/// the side maps can have. The plane moves about a sixth as far each time, and a move of a
/// tenth of a texel changes the maps and the side a point reads by as little, so stopping
/// there saves refocusings that change nothing visible.
fn settle_distance(focused: &ShadowMap, scene_scale: f64) -> f64 {
    let floor = 1e-6 * scene_scale;
    if focused.projection != MapProjection::Orthographic {
        return floor;
    }
    // Clip x and y per world unit along the map's axes; a texel is 2 / resolution of clip.
    let rows = focused.clip_from_world;
    let per_world = rows
        .row(0)
        .truncate()
        .length()
        .max(rows.row(1).truncate().length());
    let texel = 2.0 / (per_world * f64::from(focused.resolution));
    if texel.is_finite() && texel > 0.0 {
        (0.1 * texel).max(floor)
    } else {
        floor
    }
}

impl ShadowTechnique for Sppsm {
    fn name(&self) -> &'static str {
        "sppsm"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let Light::Point(_) = input.light {
            // Several maps per light do not fit a point light's one map per cube face.
            return Err(SetupError::PointLightUnsupported {
                technique: self.name(),
            });
        }
        self.validate()?;
        input.map.validate()?;
        // P, the receivers against the view and B once for both maps; each refocusing cuts
        // them to a side of the plane.
        let frame = Frame::new(input);
        let whole = FocusBasis::new(&frame, Part::Whole);
        let focused = focused_map(input, &whole).clone();
        let perspective = self
            .perspective
            .without_limit()
            .as_warp()
            .setup_with(input, &whole)?;
        let single = |mut setup: ShadowSetup, fallback: Option<Fallback>| {
            setup.technique = self.name();
            if let Some(f) = fallback {
                setup.diagnostics.fallbacks.insert(0, f);
            }
            Ok(setup)
        };
        // Nothing visible: the uniform map, as every technique gives.
        if focused.fallback() == Some(Fallback::NoVisibleReceiver)
            || focused.fallback() == Some(Fallback::SpotLightMissesView)
        {
            return single(focused, None);
        }
        if !perspective.diagnostics.fallbacks.is_empty()
            && perspective.fallback() != Some(Fallback::NoCasterForReceivers)
        {
            // Say why: the perspective map's own fallbacks follow.
            let mut setup = focused;
            for f in &perspective.diagnostics.fallbacks {
                if !setup.diagnostics.fallbacks.contains(f) {
                    setup.diagnostics.fallbacks.push(*f);
                }
            }
            return single(setup, Some(Fallback::NoSeparatingPlane));
        }
        let Some(plane) = separating_plane(&focused.maps[0], &perspective.maps[0], input.light)
        else {
            // No plane: eq. 7's plane has a vanishing normal (both maps affine on the light's
            // rays, as TSM with parallel sides), so one map is finer by the same factor
            // everywhere, or a map is singular. The finer map alone.
            let finer = finer_alone(input.light, &frame, focused, perspective);
            return single(finer, Some(Fallback::NoSeparatingPlane));
        };
        let (focused_kept, perspective_kept, plane) =
            self.refocused(input, &frame, (&focused, &perspective), plane);
        let mut diagnostics = focused.diagnostics.clone();
        diagnostics.casters_by_side = Some(casters_by_side(input.scene, plane));
        diagnostics.maps = vec![focused.map_diagnostics(0), perspective.map_diagnostics(0)];
        for f in perspective.diagnostics.fallbacks {
            if !diagnostics.fallbacks.contains(&f) {
                diagnostics.fallbacks.push(f);
            }
        }
        Ok(ShadowSetup {
            technique: self.name(),
            maps: vec![focused_kept, perspective_kept],
            selection: MapSelection::Plane { plane_world: plane },
            diagnostics,
        })
    }
}

impl Sppsm {
    /// The paper's iterative refocusing from the maps on all of I (`focused`, `perspective`)
    /// and their separating `plane`: each map refocused on its side, kept only where every
    /// point reads a map at least as fine as both alone; the maps and plane kept last.
    fn refocused(
        &self,
        input: &SetupInput<'_>,
        frame: &Frame,
        (focused, perspective): (&ShadowSetup, &ShadowSetup),
        mut plane: DVec4,
    ) -> (ShadowMap, ShadowMap, DVec4) {
        // P does not change between iterations; only its side of the plane does.
        let (body, body_tolerance) = (&frame.view_body, frame.tolerance);
        // The result so far: maps and the plane that picks between them. Both maps on all of
        // I with their exact plane (the theorem) is one, and the fallback.
        let mut kept = (focused.maps[0], perspective.maps[0], plane);
        let settle = settle_distance(&focused.maps[0], input.scene.scene_box().diagonal());
        // The plane's last move (see `next_plane`).
        let mut last_step = None;
        for iteration in 2..=self.iterations {
            // Each map on its side of the current plane; if a side has no receiver or a map
            // falls back, the result so far stays.
            let positive_points = points_on_side(body, body_tolerance, plane);
            if positive_points.is_empty() {
                break;
            }
            let negative = FocusBasis::new(frame, Part::Side(side_plane(-plane)));
            // P's part on the negative side is the side's own P.
            let negative_points = negative.visible.view_body.vertices(body_tolerance);
            if negative_points.is_empty() || negative.visible.visible_receivers() == 0 {
                break;
            }
            let f = Focused.setup_on(input, &negative);
            if !f.diagnostics.fallbacks.is_empty() {
                break;
            }
            // The focused map re-evaluated on its side (the paper's refocusing) is taken when
            // it is no coarser there than the focused map on all of I; else that map cropped
            // to P's part on the side.
            let focused_side =
                if no_coarser(&f.maps[0], &focused.maps[0], input.light, &negative_points) {
                    f.maps[0]
                } else {
                    crop(&focused.maps[0], &negative_points).unwrap_or(focused.maps[0])
                };
            // The perspective map keeps its warp and is cropped to P's part on its side: a
            // warp re-evaluated on the side can come out coarser somewhere there.
            let perspective_side =
                crop(&perspective.maps[0], &positive_points).unwrap_or(perspective.maps[0]);
            // Refocusing can overshoot: a map focused on less of I gets finer, which moves the
            // plane toward the other map, whose side then grows... (the plane can oscillate
            // with a growing swing). These maps with this plane are kept only when every
            // point of P reads a map at least as fine, in area, as both techniques alone.
            let alone = [&focused.maps[0], &perspective.maps[0]];
            if alone.iter().all(|reference| {
                no_coarser(&focused_side, reference, input.light, &negative_points)
                    && no_coarser(&perspective_side, reference, input.light, &positive_points)
            }) {
                kept = (focused_side, perspective_side, plane);
            }
            // In the last iteration the plane stays: I's part on it is inside both maps.
            if iteration == self.iterations {
                break;
            }
            match separating_plane(&focused_side, &perspective_side, input.light) {
                // Refocusing converges geometrically (the plane's offset moves about a sixth
                // as far each time); once it moves by less than `settle`, the next maps would
                // be the same to a small part of a texel.
                Some(next) if converged(plane, next, settle) => {
                    break;
                }
                Some(next) => (plane, last_step) = next_plane(plane, next, last_step),
                None => break,
            }
        }
        kept
    }
}

/// The finer of the two maps on all of I, where they have no separating plane: one map is
/// finer by the same factor everywhere, so one point of P decides.
fn finer_alone(
    light: &Light,
    frame: &Frame,
    focused: ShadowSetup,
    perspective: ShadowSetup,
) -> ShadowSetup {
    let density = |setup: &ShadowSetup, p: DVec3| ray_area_density(&setup.maps[0], light, p);
    let perspective_finer = frame
        .view_body
        .vertices(frame.tolerance)
        .first()
        .is_some_and(|p| density(&perspective, *p) > density(&focused, *p) * (1.0 + 1e-9));
    if perspective_finer {
        perspective
    } else {
        focused
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::boxes::Aabb;

    #[test]
    fn refocusing_settles_at_a_tenth_of_the_focused_map_s_texel() {
        // An orthographic map 100 m wide (clip -1 to 1) at 1000 texels: 0.1 m texels.
        let map = |projection| ShadowMap {
            clip_from_world: DMat4::from_scale(DVec3::new(0.02, 0.02, 0.01)),
            depth_from_world: DVec4::Z,
            resolution: 1000,
            viewport_inset: 0,
            projection,
            view_depth_range: None,
        };
        let settle = settle_distance(&map(MapProjection::Orthographic), 500.0);
        assert!((settle - 0.01).abs() < 1e-12, "{settle}");
        // Perspective maps (spot lights) keep a millionth of the scene.
        assert_eq!(
            settle_distance(&map(MapProjection::Perspective), 500.0),
            5e-4
        );
        let plane = DVec4::new(1.0, 0.0, 0.0, 3.0);
        assert!(converged(plane, plane + DVec4::W * 0.009, settle));
        assert!(!converged(plane, plane + DVec4::W * 0.011, settle));
        let turned = DVec4::new(1.0, 1e-6, 0.0, 3.0);
        assert!(!converged(plane, turned, settle));
    }

    #[test]
    fn a_geometric_swing_jumps_to_its_limit() {
        // Offsets 10, 8, 8.4, 8.32, ...: each move -0.2 times the one before; the limit is
        // 10 - 2 / (1 + 0.2) = 8.333...
        let plane = |w: f64| DVec4::new(0.0, 0.0, 1.0, w);
        let (first, remembered) = next_plane(plane(10.0), plane(8.0), None);
        assert_eq!((first, remembered), (plane(8.0), Some(-2.0)));
        let (jumped, remembered) = next_plane(plane(8.0), plane(8.4), remembered);
        assert!((jumped.w - 25.0 / 3.0).abs() < 1e-12, "{jumped}");
        assert_eq!(remembered, None);
        // Moves that shrink slowly (r = 0.8), or along a turned normal, are followed.
        let (slow, _) = next_plane(plane(8.0), plane(6.4), Some(-2.0));
        assert_eq!(slow, plane(6.4));
        let turned = DVec4::new(0.0, 0.6, 0.8, 8.4);
        assert_eq!(next_plane(plane(8.0), turned, Some(-2.0)), (turned, None));
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

        /// Counting by side through the hierarchy counts every box as a pass over them does.
        #[test]
        fn casters_by_side_match_every_box(
            boxes in prop::collection::vec((prop::array::uniform3(-60.0f64..60.0), prop::array::uniform3(0.0f64..12.0)), 1..300),
            normal in prop::array::uniform3(-1.0f64..1.0),
            offset in -40.0f64..40.0,
        ) {
            let boxes: Vec<Aabb> = boxes.iter().filter_map(|(lo, size)| {
                let lo = DVec3::from_array(*lo);
                Aabb::new(lo, lo + DVec3::from_array(*size)).ok()
            }).collect();
            prop_assume!(!boxes.is_empty());
            let scene = SceneBounds::new(boxes.clone(), vec![], None).unwrap();
            let plane = DVec3::from_array(normal).extend(offset);
            let mut want = CastersBySide::default();
            for b in &boxes {
                let n = plane.truncate();
                let d = n.dot(b.center()) + plane.w;
                let r = n.abs().dot(b.half_extents());
                if d - r >= 0.0 {
                    want.perspective_only += 1;
                } else if d + r <= 0.0 {
                    want.focused_only += 1;
                } else {
                    want.both += 1;
                }
            }
            prop_assert_eq!(casters_by_side(&scene, plane), want);
        }
    }
}
