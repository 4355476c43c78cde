//! Focusing: what the camera sees of the receivers, which casters can shadow it, and the unit
//! cube clipping rule that turns both into a map's extents.
//!
//! The rule (unit cube clipping blog post): in the light's clip space,
//! - XY = the intersection of the casters' and the receivers' extents: a receiver point
//!   outside the casters' extents can not be in shadow, a caster point outside the
//!   receivers' extents shadows nothing visible; points outside read the map's cleared
//!   border and come out lit;
//! - near = the casters' minimum depth: nothing that casts a shadow is clipped, and a
//!   receiver nearer than every caster compares below 0 and comes out lit;
//! - far = the receivers' maximum depth: every visible receiver compares inside [0, 1].

use glam::DVec3;

use crate::bounds::{Aabb, SceneBounds};
use crate::camera::Camera;
use crate::geometry::{ConvexPolyhedron, Plane};
use crate::light_space::{Extents, Projector};
use crate::setup::Diagnostics;

/// How an axis-aligned box lies against a set of planes.
pub(crate) enum BoxSide {
    /// Wholly outside one of the planes.
    Outside,
    /// Wholly inside all planes.
    Inside,
    /// Crosses some planes: the bits of the mask name them.
    Straddles(u32),
}

/// Classifies a box against up to 32 planes (`tolerance` in world units).
pub(crate) fn classify_box(aabb: &Aabb, planes: &[Plane], tolerance: f64) -> BoxSide {
    let c = aabb.center();
    let e = aabb.half_extents();
    let mut mask = 0u32;
    for (i, plane) in planes.iter().enumerate() {
        let r = plane.normal.abs().dot(e);
        let s = plane.distance(c);
        if s + r <= tolerance {
            return BoxSide::Outside;
        }
        if s - r < -tolerance {
            mask |= 1 << i;
        }
    }
    if mask == 0 { BoxSide::Inside } else { BoxSide::Straddles(mask) }
}

/// The part of a box inside a set of planes, as vertices appended to `out`; `false` (and
/// nothing appended) when nothing is left.
pub(crate) fn clip_box(aabb: &Aabb, planes: &[Plane], tolerance: f64, out: &mut Vec<DVec3>) -> bool {
    match classify_box(aabb, planes, tolerance) {
        BoxSide::Outside => false,
        BoxSide::Inside => {
            out.extend_from_slice(&aabb.corners());
            true
        }
        BoxSide::Straddles(mask) => {
            let crossing = planes.iter().enumerate().filter(|(i, _)| mask & (1 << i) != 0).map(|(_, p)| p);
            let clipped = ConvexPolyhedron::from_box(aabb).clip_all(crossing, tolerance);
            if clipped.is_empty() {
                return false;
            }
            out.extend(clipped.vertices(tolerance));
            true
        }
    }
}

/// A part of a receiver that the camera can see.
enum ReceiverPart {
    /// The whole box is visible.
    Whole(Aabb),
    /// The visible part's vertices, a range in [`VisibleScene::points`].
    Clipped(std::ops::Range<usize>),
}

/// What the camera sees of the scene, for one light: the view frustum inside the scene box
/// (P) and the visible parts of the receivers.
pub(crate) struct VisibleScene {
    /// P: the view frustum clipped by the scene box (and the light frustum for a spot light).
    pub view_body: ConvexPolyhedron,
    receivers: Vec<ReceiverPart>,
    points: Vec<DVec3>,
}

impl VisibleScene {
    /// `light_planes`: the spot light's frustum, if any.
    pub fn new(camera: &Camera, scene: &SceneBounds, light_planes: Option<&[Plane; 6]>, tolerance: f64) -> Self {
        let mut planes: Vec<Plane> = camera.frustum_planes().to_vec();
        if let Some(lp) = light_planes {
            planes.extend_from_slice(lp);
        }
        let scene_box = scene.scene_box();
        let view_body = ConvexPolyhedron::from_hexahedron(&camera.frustum_corners())
            .clip_all(&box_planes(&scene_box), tolerance)
            .clip_all(light_planes.into_iter().flatten(), tolerance);
        let mut receivers = Vec::new();
        let mut points = Vec::new();
        if !view_body.is_empty() {
            for r in scene.receivers() {
                match classify_box(r, &planes, tolerance) {
                    BoxSide::Outside => {}
                    BoxSide::Inside => receivers.push(ReceiverPart::Whole(*r)),
                    BoxSide::Straddles(_) => {
                        let start = points.len();
                        if clip_box(r, &planes, tolerance, &mut points) {
                            receivers.push(ReceiverPart::Clipped(start..points.len()));
                        }
                    }
                }
            }
        }
        Self { view_body, receivers, points }
    }

    /// How many receiver boxes have a visible part.
    pub fn visible_receivers(&self) -> usize {
        self.receivers.len()
    }

    /// The extents of the visible receiver parts under `projector`.
    pub fn receiver_extents(&self, projector: &Projector) -> Extents {
        let mut ext = Extents::EMPTY;
        for part in &self.receivers {
            match part {
                ReceiverPart::Whole(b) => ext = ext.union(&projector.box_extents(b)),
                ReceiverPart::Clipped(range) => {
                    for p in &self.points[range.clone()] {
                        ext.add(projector.project(*p));
                    }
                }
            }
        }
        ext
    }
}

/// The six planes of a box, normals inward.
pub(crate) fn box_planes(b: &Aabb) -> [Plane; 6] {
    let (lo, hi) = (b.min(), b.max());
    [
        Plane::through_point(lo, DVec3::X),
        Plane::through_point(hi, -DVec3::X),
        Plane::through_point(lo, DVec3::Y),
        Plane::through_point(hi, -DVec3::Y),
        Plane::through_point(lo, DVec3::Z),
        Plane::through_point(hi, -DVec3::Z),
    ]
}

/// The extents of the casters that can shadow the visible receivers (`receivers`, their
/// extents under `projector`). A caster is culled when it lies outside the light frustum
/// (`light_planes`, spot lights), beside the receivers as seen from the light, or wholly
/// behind them. Counts go into `diagnostics`.
pub(crate) fn caster_extents(
    scene: &SceneBounds,
    projector: &Projector,
    receivers: &Extents,
    light_planes: Option<&[Plane; 6]>,
    tolerance: f64,
    diagnostics: &mut Diagnostics,
) -> Extents {
    let mut ext = Extents::EMPTY;
    let mut relevant = 0;
    let mut near_clipped = 0;
    let mut scratch = Vec::new();
    for caster in scene.casters() {
        let (box_ext, crosses_near) = match light_planes {
            None => (projector.box_extents(caster), false),
            Some(planes) => match classify_box(caster, planes, tolerance) {
                BoxSide::Outside => continue,
                BoxSide::Inside => (projector.box_extents(caster), false),
                BoxSide::Straddles(mask) => {
                    scratch.clear();
                    if !clip_box(caster, planes, tolerance, &mut scratch) {
                        continue;
                    }
                    let mut e = Extents::EMPTY;
                    for p in &scratch {
                        e.add(projector.project(*p));
                    }
                    // Plane 0 is the light's near plane.
                    (e, mask & 1 != 0)
                }
            },
        };
        let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
        if !receivers.xy_overlaps(&box_ext, xy_slack) || box_ext.min.z > receivers.max.z {
            continue;
        }
        relevant += 1;
        near_clipped += usize::from(crosses_near);
        ext = ext.union(&box_ext);
    }
    diagnostics.relevant_casters = relevant;
    diagnostics.culled_casters = scene.casters().len() - relevant;
    diagnostics.casters_clipped_by_light_near = near_clipped;
    ext
}

/// Unit cube clipping (see the module documentation): the region a focused map covers, from
/// the visible receivers' and the relevant casters' extents. `body`, B's extents when B is
/// usable, raises the near plane to B's nearest point: caster points nearer to the light lie
/// outside B and can shadow nothing visible. `None` when no caster is relevant.
pub(crate) fn unit_cube_clip(receivers: &Extents, casters: &Extents, body: Option<&Extents>) -> Option<Extents> {
    if casters.is_empty() || receivers.is_empty() {
        return None;
    }
    let mut near = casters.min.z;
    if let Some(b) = body {
        near = near.max(b.min.z);
    }
    let far = receivers.max.z;
    let mut lo = receivers.min.max(casters.min).truncate();
    let mut hi = receivers.max.min(casters.max).truncate();
    // Casters that only touch the receivers' rectangle (within the culling slack) leave an
    // inverted interval: collapse it to its middle, padding gives it a size.
    let mid = 0.5 * (lo + hi);
    lo = lo.min(mid);
    hi = hi.max(mid);
    Some(Extents { min: lo.extend(near.min(far)), max: hi.extend(far) })
}
