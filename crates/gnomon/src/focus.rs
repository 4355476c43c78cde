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

use crate::bounds::{Aabb, BoxArrays, SceneBounds};
use crate::geometry::{ConvexPolyhedron, Plane};

use crate::light_space::{Extents, LightFrame, Projector};
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
    if mask == 0 {
        BoxSide::Inside
    } else {
        BoxSide::Straddles(mask)
    }
}

/// [`classify_boxes`]'s code for a box wholly outside one of the planes.
pub(crate) const OUTSIDE: u32 = u32::MAX;

/// Classifies every box against up to 31 planes, as [`classify_box`] does one: [`OUTSIDE`],
/// 0 (inside all planes) or the mask of the planes it straddles. One pass per plane over the
/// box arrays, without branches, so that it vectorises.
pub(crate) fn classify_boxes(
    boxes: &BoxArrays,
    planes: &[Plane],
    tolerance: f64,
    out: &mut Vec<u32>,
) {
    let n = boxes.len();
    out.clear();
    out.resize(n, 0);
    let ([cx, cy, cz], [hx, hy, hz]) = boxes.columns();
    for (k, plane) in planes.iter().enumerate().take(31) {
        let (m, a, o) = (plane.normal, plane.normal.abs(), plane.offset);
        for i in 0..n {
            let s = m.x * cx[i] + m.y * cy[i] + m.z * cz[i] + o;
            let r = a.x * hx[i] + a.y * hy[i] + a.z * hz[i];
            out[i] |= (u32::from(s - r < -tolerance) << k) | (u32::from(s + r <= tolerance) << 31);
        }
    }
    for code in out.iter_mut() {
        if *code & (1 << 31) != 0 {
            *code = OUTSIDE;
        }
    }
}

/// The codes of a part of a frame from the frame's: `frame_codes` against the frame's planes,
/// `planes` the part's, which equal the frame's except those named in `changed` (bits; a
/// part lies inside the frame). A box outside the frame is outside the part; one wholly
/// inside is tested against the changed planes only; one that straddles, against all.
pub(crate) fn refine_codes(
    frame_codes: &[u32],
    boxes: &[Aabb],
    arrays: &BoxArrays,
    planes: &[Plane],
    changed: u32,
    tolerance: f64,
) -> Vec<u32> {
    // Every box against the changed planes at once (the pass vectorises), their bits moved to
    // the planes' places.
    let indices: Vec<usize> = (0..planes.len())
        .filter(|i| changed & (1 << i) != 0)
        .collect();
    let changed_planes: Vec<Plane> = indices.iter().map(|&i| planes[i]).collect();
    // (A slice changes planes 0 and 1, a side one plane: the bits only shift.)
    let first = indices.first().copied().unwrap_or(0);
    let contiguous = indices.iter().enumerate().all(|(j, &i)| i == first + j);
    let mut against_changed = Vec::new();
    classify_boxes(arrays, &changed_planes, tolerance, &mut against_changed);
    frame_codes
        .iter()
        .zip(&against_changed)
        .zip(boxes)
        .map(|((&code, &new), aabb)| match (code, new) {
            (OUTSIDE, _) | (_, OUTSIDE) => OUTSIDE,
            (0, new) if contiguous => new << first,
            (0, new) => indices
                .iter()
                .enumerate()
                .filter(|(j, _)| new & (1 << j) != 0)
                .fold(0, |mask, (_, &i)| mask | 1 << i),
            _ => match classify_box(aabb, planes, tolerance) {
                BoxSide::Outside => OUTSIDE,
                BoxSide::Inside => 0,
                BoxSide::Straddles(mask) => mask,
            },
        })
        .collect()
}

/// An orthographic frame ready to project boxes of a [`BoxArrays`]: a box's image is its
/// projected centre plus and minus |R| times its half extents.
pub(crate) struct ParallelBoxes<'a> {
    boxes: &'a BoxArrays,
    axes: [DVec3; 3],
    abs_axes: [DVec3; 3],
}

impl<'a> ParallelBoxes<'a> {
    pub fn new(boxes: &'a BoxArrays, frame: &LightFrame) -> Self {
        let axes = [frame.right, frame.up, frame.forward];
        Self {
            boxes,
            axes,
            abs_axes: axes.map(DVec3::abs),
        }
    }

    /// The extents of box `i` in the frame.
    #[inline(always)]
    pub fn extents(&self, i: usize) -> Extents {
        let (b, a, h_axes) = (self.boxes, &self.axes, &self.abs_axes);
        let c = DVec3::new(b.center[0][i], b.center[1][i], b.center[2][i]);
        let h = DVec3::new(b.half[0][i], b.half[1][i], b.half[2][i]);
        let pc = DVec3::new(a[0].dot(c), a[1].dot(c), a[2].dot(c));
        let ph = DVec3::new(h_axes[0].dot(h), h_axes[1].dot(h), h_axes[2].dot(h));
        Extents {
            min: pc - ph,
            max: pc + ph,
        }
    }
}

/// The corners of world boxes in a light frame, from their projected centres and half
/// extents: the frame's images of the world axes, computed once.
pub(crate) struct LightCorners {
    axes: [DVec3; 3],
}

impl LightCorners {
    pub fn new(frame: &LightFrame) -> Self {
        let to = |p: DVec3| DVec3::new(frame.right.dot(p), frame.up.dot(p), frame.forward.dot(p));
        Self {
            axes: [to(DVec3::X), to(DVec3::Y), to(DVec3::Z)],
        }
    }

    /// The eight corners of the box with projected centre `c` and half extents `h`.
    #[inline(always)]
    pub fn corners(&self, c: DVec3, h: DVec3) -> [DVec3; 8] {
        let [ex, ey, ez] = self.axes;
        let (dx, dy, dz) = (ex * h.x, ey * h.y, ez * h.z);
        let (a, b) = (c - dx, c + dx);
        let (a0, a1, b0, b1) = (a - dy, a + dy, b - dy, b + dy);
        [
            a0 - dz,
            a0 + dz,
            a1 - dz,
            a1 + dz,
            b0 - dz,
            b0 + dz,
            b1 - dz,
            b1 + dz,
        ]
    }
}

/// The extents of the boxes `indices` under an orthographic frame.
pub(crate) fn parallel_extents(
    boxes: &BoxArrays,
    frame: &LightFrame,
    indices: &[usize],
) -> Extents {
    let projected = ParallelBoxes::new(boxes, frame);
    indices
        .iter()
        .fold(Extents::EMPTY, |ext, &i| ext.union(&projected.extents(i)))
}

/// The vertices of a box cut by the planes named in `mask` (the box lies inside the others),
/// appended to `out` without allocating; `false` when nothing is left.
///
/// Every vertex of the cut box is where three of its bounding planes meet: three box faces (a
/// corner), two box faces and a plane (an edge crossing the plane), one box face and two
/// planes, or three planes. All four kinds are enumerated and the feasible points kept.
/// Duplicates may appear; they do not change extents.
pub(crate) fn box_cut_vertices(
    aabb: &Aabb,
    planes: &[Plane],
    mask: u32,
    tolerance: f64,
    out: &mut Vec<DVec3>,
) -> bool {
    // Most cut boxes cross one or two planes: small arrays for them (so that a call does not
    // clear room for 32 planes), the full size for the rest.
    if mask.count_ones() == 1 {
        cut_by_one(
            aabb,
            &planes[mask.trailing_zeros() as usize],
            tolerance,
            out,
        )
    } else if mask.count_ones() <= 4 {
        cut_vertices::<4>(aabb, planes, mask, tolerance, out)
    } else {
        cut_vertices::<32>(aabb, planes, mask, tolerance, out)
    }
}

/// [`box_cut_vertices`] for one cutting plane (most cut boxes): the corners inside it and
/// where the box's edges cross it.
fn cut_by_one(aabb: &Aabb, plane: &Plane, tolerance: f64, out: &mut Vec<DVec3>) -> bool {
    let start = out.len();
    let corners = aabb.corners();
    let dist = corners.map(|c| plane.distance(c));
    for (c, d) in corners.iter().zip(&dist) {
        if *d >= -tolerance {
            out.push(*c);
        }
    }
    for a in 0..8 {
        for bit in [1, 2, 4] {
            let b = a | bit;
            if a & bit != 0 {
                continue;
            }
            let (da, db) = (dist[a], dist[b]);
            if (da < 0.0) != (db < 0.0) && da != db {
                out.push(corners[a] + (corners[b] - corners[a]) * (da / (da - db)));
            }
        }
    }
    out.len() > start
}

/// [`box_cut_vertices`] with room for `N` cutting planes (at least the bits of `mask`).
fn cut_vertices<const N: usize>(
    aabb: &Aabb,
    planes: &[Plane],
    mask: u32,
    tolerance: f64,
    out: &mut Vec<DVec3>,
) -> bool {
    let mut cut = [Plane {
        normal: DVec3::ZERO,
        offset: 0.0,
    }; N];
    let mut k = 0;
    for (i, plane) in planes.iter().enumerate() {
        if mask & (1 << i) != 0 {
            cut[k] = *plane;
            k += 1;
        }
    }
    let cut = &cut[..k];
    let start = out.len();
    let in_cut = |p: DVec3, skip: &[usize]| {
        cut.iter()
            .enumerate()
            .all(|(i, pl)| skip.contains(&i) || pl.distance(p) >= -tolerance)
    };
    let corners = aabb.corners();
    // Each corner's distance to each cutting plane, computed once.
    let mut dist = [[0.0f64; 8]; N];
    for (j, pl) in cut.iter().enumerate() {
        for (c, corner) in corners.iter().enumerate() {
            dist[j][c] = pl.distance(*corner);
        }
    }
    // Three box faces: corners.
    for (c, corner) in corners.iter().enumerate() {
        if (0..k).all(|j| dist[j][c] >= -tolerance) {
            out.push(*corner);
        }
    }
    // Two box faces and a plane: box edges crossing a plane.
    for a in 0..8 {
        for bit in [1, 2, 4] {
            if a & bit != 0 {
                continue;
            }
            let b = a | bit;
            for (j, d) in dist[..k].iter().enumerate() {
                let (da, db) = (d[a], d[b]);
                if (da < 0.0) != (db < 0.0) && da != db {
                    let p = corners[a] + (corners[b] - corners[a]) * (da / (da - db));
                    if in_cut(p, &[j]) {
                        out.push(p);
                    }
                }
            }
        }
    }
    // One box face and two planes; three planes.
    let face_planes = crate::focus::box_planes(aabb);
    for j in 0..k {
        for l in j + 1..k {
            for face in &face_planes {
                if let Some(p) = meet(&cut[j], &cut[l], face)
                    && aabb.contains_point(p, tolerance)
                    && in_cut(p, &[j, l])
                {
                    out.push(p);
                }
            }
            for m in l + 1..k {
                if let Some(p) = meet(&cut[j], &cut[l], &cut[m])
                    && aabb.contains_point(p, tolerance)
                    && in_cut(p, &[j, l, m])
                {
                    out.push(p);
                }
            }
        }
    }
    out.len() > start
}

/// The point where three planes meet, if they meet in one point.
fn meet(a: &Plane, b: &Plane, c: &Plane) -> Option<DVec3> {
    let bc = b.normal.cross(c.normal);
    let det = a.normal.dot(bc);
    if det.abs() < 1e-12 {
        return None;
    }
    let p = (-a.offset * bc
        - b.offset * c.normal.cross(a.normal)
        - c.offset * a.normal.cross(b.normal))
        / det;
    p.is_finite().then_some(p)
}

/// What the camera sees of the scene, for one light: the view frustum inside the scene box
/// (P) and the visible parts of the receivers.
#[derive(Clone)]
pub(crate) struct VisibleScene {
    /// P: the view frustum clipped by the scene box (and the light frustum for a spot light).
    pub view_body: ConvexPolyhedron,
    /// Receivers wholly visible, as indices into the scene's receivers.
    whole: Vec<usize>,
    /// How many receivers are partly visible.
    clipped: usize,
    /// The vertices of the visible parts of the partly visible receivers.
    points: Vec<DVec3>,
    /// Each partly visible receiver, in order: (its index, where its vertices start and end
    /// in `points`).
    cuts: Vec<(u32, u32, u32)>,
}

/// A frame's cut receivers that a part of it may take instead of cutting them again: the
/// frame's visible scene, its codes, and the bits of the planes the part changed. A receiver
/// cut by the same planes in both (none of them changed) has the same visible part.
#[derive(Clone, Copy)]
pub(crate) struct ReuseCuts<'a> {
    pub frame: &'a VisibleScene,
    pub codes: &'a [u32],
    pub changed: u32,
}

impl VisibleScene {
    /// The visible scene of P = `view_body` from each receiver's code against `planes` (as
    /// [`classify_boxes`] gives them; empty when P is): wholly visible boxes are kept, cut
    /// ones cut (or taken from `reuse`).
    pub fn from_codes(
        view_body: ConvexPolyhedron,
        scene: &SceneBounds,
        planes: &[Plane],
        codes: &[u32],
        tolerance: f64,
        reuse: Option<ReuseCuts<'_>>,
    ) -> Self {
        let mut whole = Vec::new();
        let mut points = Vec::new();
        let mut cuts = Vec::new();
        if !view_body.is_empty() {
            for (i, &code) in codes.iter().enumerate() {
                match code {
                    OUTSIDE => {}
                    0 => whole.push(i),
                    mask => {
                        let start = points.len();
                        let same = reuse
                            .filter(|r| r.codes[i] == mask && mask & r.changed == 0)
                            .and_then(|r| r.frame.cut_of(i));
                        let kept = match same {
                            Some(vertices) => {
                                points.extend_from_slice(vertices);
                                true
                            }
                            None => box_cut_vertices(
                                &scene.receivers()[i],
                                planes,
                                mask,
                                tolerance,
                                &mut points,
                            ),
                        };
                        if kept {
                            cuts.push((i as u32, start as u32, points.len() as u32));
                        }
                    }
                }
            }
        }
        Self {
            view_body,
            whole,
            clipped: cuts.len(),
            points,
            cuts,
        }
    }

    /// The vertices of receiver `i`'s visible part when it is cut.
    fn cut_of(&self, i: usize) -> Option<&[DVec3]> {
        let k = self.cuts.binary_search_by_key(&(i as u32), |c| c.0).ok()?;
        let (_, start, end) = self.cuts[k];
        Some(&self.points[start as usize..end as usize])
    }

    /// How many receiver boxes have a visible part.
    pub fn visible_receivers(&self) -> usize {
        self.whole.len() + self.clipped
    }

    /// Calls `f` with every vertex of the visible receiver parts (the corners of wholly
    /// visible boxes, the vertices of cut ones): their extents under any projective map are
    /// the extents of these points.
    pub fn for_each_vertex(&self, scene: &SceneBounds, mut f: impl FnMut(DVec3)) {
        for &i in &self.whole {
            for c in scene.receivers()[i].corners() {
                f(c);
            }
        }
        for p in &self.points {
            f(*p);
        }
    }

    /// The visible receiver parts in `frame`'s coordinates (right . p, up . p, forward . p):
    /// each whole box as its projected centre and half extents (its corners are the centre
    /// plus and minus the half extents times `frame`'s images of the world axes, see
    /// [`LightCorners`]), appended to `boxes`, and the vertices of the cut ones, to `points`.
    pub fn parts_in(
        &self,
        scene: &SceneBounds,
        frame: &LightFrame,
        boxes: &mut Vec<(DVec3, DVec3)>,
        points: &mut Vec<DVec3>,
    ) {
        let to = |p: DVec3| DVec3::new(frame.right.dot(p), frame.up.dot(p), frame.forward.dot(p));
        boxes.extend(self.whole.iter().map(|&i| {
            let b = &scene.receivers()[i];
            (to(b.center()), b.half_extents())
        }));
        points.extend(self.points.iter().map(|p| to(*p)));
    }

    /// The extents of the visible receiver parts under `projector`.
    pub fn receiver_extents(&self, scene: &SceneBounds, projector: &Projector) -> Extents {
        let mut ext = match projector {
            Projector::Parallel(frame) => {
                parallel_extents(scene.receiver_arrays(), frame, &self.whole)
            }
            Projector::Point { .. } => {
                let mut ext = Extents::EMPTY;
                for &i in &self.whole {
                    ext = ext.union(&projector.box_extents(&scene.receivers()[i]));
                }
                ext
            }
        };
        for p in &self.points {
            ext.add(projector.project(*p));
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
/// extents under `projector`). A caster is cut by `cut_planes` (a spot light's frustum, its
/// near plane first when `light_near_first`, and a side's plane) and culled when nothing of
/// it is left, when it lies beside the receivers as seen from the light, or wholly behind
/// them. `cached`: every caster's extents under `projector` when the frame has them. Counts
/// go into `diagnostics`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn caster_extents(
    scene: &SceneBounds,
    projector: &Projector,
    receivers: &Extents,
    cut_planes: &[Plane],
    light_near_first: bool,
    cached: Option<&crate::frame::LightBoxes>,
    tolerance: f64,
    diagnostics: &mut Diagnostics,
) -> Extents {
    let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
    let mut ext = Extents::EMPTY;
    let mut relevant = 0;
    let mut near_clipped = 0;
    let parallel = match projector {
        Projector::Parallel(frame) => Some(ParallelBoxes::new(scene.caster_arrays(), frame)),
        Projector::Point { .. } => None,
    };
    // A whole caster's extents: the frame's, else projected.
    let whole = |i: usize| match (cached, &parallel) {
        (Some(boxes), _) => boxes.get(i),
        (None, Some(projected)) => projected.extents(i),
        (None, None) => projector.box_extents(&scene.casters()[i]),
    };
    if let (true, Some(boxes)) = (cut_planes.is_empty(), cached) {
        // The frame's boxes: cull in one pass, then accumulate.
        let mut kept = Vec::new();
        let all = (f64::NEG_INFINITY, f64::INFINITY);
        boxes.overlapping(receivers, xy_slack, receivers.max.z, all, &mut kept);
        for &i in &kept {
            ext = ext.union(&boxes.get(i as usize));
        }
        relevant = kept.len();
    } else if cut_planes.is_empty() {
        // One pass: project, cull, accumulate.
        let mut add = |box_ext: Extents| {
            if receivers.xy_overlaps(&box_ext, xy_slack) && box_ext.min.z <= receivers.max.z {
                relevant += 1;
                ext = ext.union(&box_ext);
            }
        };
        match &parallel {
            Some(projected) => (0..scene.casters().len()).for_each(|i| add(projected.extents(i))),
            None => scene
                .casters()
                .iter()
                .for_each(|c| add(projector.box_extents(c))),
        }
    } else {
        let mut scratch = Vec::new();
        let mut codes = Vec::new();
        classify_boxes(scene.caster_arrays(), cut_planes, tolerance, &mut codes);
        for (i, caster) in scene.casters().iter().enumerate() {
            let (box_ext, crosses_near) = match codes[i] {
                OUTSIDE => continue,
                0 => (whole(i), false),
                mask => {
                    scratch.clear();
                    if !box_cut_vertices(caster, cut_planes, mask, tolerance, &mut scratch) {
                        continue;
                    }
                    let mut e = Extents::EMPTY;
                    for p in &scratch {
                        e.add(projector.project(*p));
                    }
                    (e, light_near_first && mask & 1 != 0)
                }
            };
            if !receivers.xy_overlaps(&box_ext, xy_slack) || box_ext.min.z > receivers.max.z {
                continue;
            }
            relevant += 1;
            near_clipped += usize::from(crosses_near);
            ext = ext.union(&box_ext);
        }
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
pub(crate) fn unit_cube_clip(
    receivers: &Extents,
    casters: &Extents,
    body: Option<&Extents>,
) -> Option<Extents> {
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
    Some(Extents {
        min: lo.extend(near.min(far)),
        max: hi.extend(far),
    })
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn unit(v: [f64; 3]) -> DVec3 {
        let v = DVec3::from_array(v);
        if v.length() < 1e-3 {
            DVec3::X
        } else {
            v.normalize()
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

        /// The allocation-free cut agrees with the general polyhedron clipper.
        #[test]
        fn box_cut_matches_polyhedron_clipping(
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..8.0),
            planes in prop::collection::vec((prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-10.0f64..10.0)), 1..7),
        ) {
            let lo = DVec3::from_array(lo);
            let size = DVec3::from_array(size);
            prop_assume!(size.max_element() > 0.1);
            let aabb = Aabb::new(lo, lo + size).unwrap();
            let planes: Vec<Plane> = planes.iter().map(|(n, p)| Plane::through_point(DVec3::from_array(*p), unit(*n))).collect();
            let tol = 1e-9;
            let clipped = ConvexPolyhedron::from_box(&aabb).clip_all(&planes, tol);
            let mut fast = Vec::new();
            let mask = (1u32 << planes.len()) - 1;
            let any = box_cut_vertices(&aabb, &planes, mask, tol, &mut fast);
            let exact = clipped.vertices(tol);
            // Both find every vertex of the other (up to touching, measure-zero results).
            if !exact.is_empty() {
                prop_assert!(any);
                for v in &exact {
                    prop_assert!(fast.iter().any(|f| f.distance(*v) < 1e-6), "missing {v}: fast {fast:?} exact {exact:?}");
                }
            }
            for f in &fast {
                prop_assert!(exact.is_empty() || exact.iter().any(|v| f.distance(*v) < 1e-6) || clipped.is_empty(),
                    "extra {f}: fast {fast:?} exact {exact:?}");
            }
        }
    }
}
