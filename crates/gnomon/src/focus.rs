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

use std::sync::OnceLock;

use glam::{DVec2, DVec3};

use crate::bounds::SceneBounds;
use crate::boxes::{Aabb, BoxArrays};
use crate::bvh::{BoxPlanes, BoxTree, Classified, all_planes, grown, straddled};
use crate::geometry::{ConvexPolyhedron, Plane};

use crate::diagnostics::Diagnostics;
use crate::light_space::{AxisFrustum, Extents, LightFrame, Projector};
use crate::put_off::PutOff;

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

/// The classification of a part of a frame from the frame's: `frame` against the frame's
/// planes, `planes` the part's, which equal the frame's except those named in `changed`
/// (bits; a part lies inside the frame). What lies outside the frame lies outside the part;
/// what lies wholly inside is tested against the changed planes only (subtrees stay
/// subtrees); a box that crosses some of the frame's planes, against those and the changed
/// ones.
pub(crate) fn refine(
    frame: &Classified,
    scene: &SceneBounds,
    planes: &[Plane],
    changed: u32,
    tolerance: f64,
) -> Classified {
    let (tree, arrays) = (scene.receiver_tree(), scene.receiver_arrays());
    let mut out = Classified::default();
    // Room for every box the frame lists, so that the pushes below do not grow the lists.
    let listed = frame.boxes.len() + frame.cut.len();
    out.boxes.reserve(listed);
    out.cut.reserve(listed);
    tree.classify(
        arrays,
        planes,
        tolerance,
        frame.nodes.iter().map(|&n| (n as usize, changed)),
        &mut out,
    );
    let box_planes = BoxPlanes::new(planes);
    // A box the frame cuts is tested again against the planes it crosses and the changed
    // ones: it lies inside the others, which are the frame's.
    let boxes = frame.boxes.iter().map(|&i| (i, changed));
    let cut = frame.cut.iter().map(|&(i, mask)| (i, mask | changed));
    for (i, active) in boxes.chain(cut) {
        let (c, h) = (arrays.center_of(i as usize), arrays.half_of(i as usize));
        match box_planes.straddled(c, h, active, tolerance) {
            None => {}
            Some(0) => out.boxes.push(i),
            Some(mask) => out.cut.push((i, mask)),
        }
    }
    out
}

/// The most slices [`refine_slices`] takes in one walk (a cascade has at most eight).
pub(crate) const MAX_SLICES: usize = 8;

/// The near and far planes of cascade slices that share every other plane and differ only
/// in those two planes' offsets, tested against a box all at once.
struct SliceTests {
    near_normal: DVec3,
    far_normal: DVec3,
    abs_normal: DVec3,
    /// Each slice's near and far offsets.
    offsets: Vec<(f64, f64)>,
    tolerance: f64,
}

impl SliceTests {
    /// The tests of `slices`, or `None` where they do not share their other planes (or the
    /// near and far planes are not parallel), or are too many.
    fn new(slices: &[Vec<Plane>], tolerance: f64) -> Option<Self> {
        let first = slices.first()?;
        if slices.len() > MAX_SLICES || first.len() < 2 {
            return None;
        }
        let (near_normal, far_normal) = (first[0].normal, first[1].normal);
        let abs_normal = near_normal.abs();
        let shared = slices.iter().all(|planes| {
            planes.len() == first.len()
                && planes[0].normal == near_normal
                && planes[1].normal == far_normal
                && planes[2..] == first[2..]
        });
        if !shared || far_normal.abs() != abs_normal {
            return None;
        }
        let offsets = slices.iter().map(|p| (p[0].offset, p[1].offset)).collect();
        Some(Self {
            near_normal,
            far_normal,
            abs_normal,
            offsets,
            tolerance,
        })
    }

    /// A box's n . c against the near and far normals and its |n| . h.
    #[inline]
    fn dots(&self, (c, h): (DVec3, DVec3)) -> (f64, f64, f64) {
        (
            self.near_normal.dot(c),
            self.far_normal.dot(c),
            self.abs_normal.dot(h),
        )
    }

    /// The test of `straddled` against slice k's near (bit 0) and far (bit 1) planes among
    /// `active`, from the box's [`SliceTests::dots`].
    #[inline]
    fn test(
        &self,
        (near_dot, far_dot, reach): (f64, f64, f64),
        k: usize,
        active: u8,
    ) -> Option<u8> {
        let mut mask = 0u8;
        let offsets = self.offsets[k];
        for (bit, s) in [(1u8, near_dot + offsets.0), (2, far_dot + offsets.1)] {
            if active & bit == 0 {
                continue;
            }
            if s + reach <= self.tolerance {
                return None;
            }
            if s - reach < -self.tolerance {
                mask |= bit;
            }
        }
        Some(mask)
    }
}

/// [`refine`] of several slices of the frame's view at once. Each of `slices` is a slice's
/// planes: the frame's, but for its own near and far planes (bits 0 and 1, the changed ones).
/// A cascade's slices of one camera share the near planes' normal n and the far planes' -n.
/// So one walk of the frame's subtrees and boxes takes each one's n . c and |n| . h once and
/// tests them against every slice's two offsets, where a walk per slice would test the
/// frame's whole frontier again for each. Each slice gets what [`refine`] gives it, item for
/// item and in the same order: a slice's walk visits a subset of this walk's nodes, closed
/// under ancestors, in the same order. `None` where the slices do not share their planes so
/// (other normals, other side planes) or are more than [`MAX_SLICES`]: refine each then.
pub(crate) fn refine_slices(
    frame: &Classified,
    scene: &SceneBounds,
    slices: &[Vec<Plane>],
    tolerance: f64,
) -> Option<Vec<Classified>> {
    let tests = SliceTests::new(slices, tolerance)?;
    let (first, count) = (&slices[0], slices.len());
    let (tree, arrays) = (scene.receiver_tree(), scene.receiver_arrays());
    let listed = frame.boxes.len() + frame.cut.len();
    let mut out: Vec<Classified> = (0..count)
        .map(|_| Classified {
            nodes: Vec::with_capacity(32),
            boxes: Vec::with_capacity(listed),
            cut: Vec::with_capacity(listed),
        })
        .collect();
    // The frame's subtrees, with the slices still testing them (bit k: slice k) and the
    // planes each still tests (two bits per slice, slice k's at bits 2k and 2k + 1).
    let every = ((1u32 << count) - 1) as u8;
    let mut stack: Vec<(u32, u8, u16)> = Vec::with_capacity(64);
    stack.extend(frame.nodes.iter().map(|&n| (n, every, u16::MAX)));
    while let Some((node, live, planes)) = stack.pop() {
        let node = node as usize;
        let node_dots = tests.dots(tree.nodes.center_half(node));
        let (mut next_live, mut next_planes) = (0u8, 0u16);
        for_each_bit(live, |k| {
            match tests.test(node_dots, k, (planes >> (2 * k)) as u8 & 0b11) {
                None => {}
                Some(0) => out[k].nodes.push(node as u32),
                Some(mask) => {
                    next_live |= 1 << k;
                    next_planes |= u16::from(mask) << (2 * k);
                }
            }
        });
        if next_live == 0 {
            continue;
        }
        if tree.is_leaf(node) {
            for &i in tree.boxes_of(node) {
                let box_dots = tests.dots(arrays.center_half(i as usize));
                for_each_bit(next_live, |k| {
                    match tests.test(box_dots, k, (next_planes >> (2 * k)) as u8 & 0b11) {
                        None => {}
                        Some(0) => out[k].boxes.push(i),
                        Some(mask) => out[k].cut.push((i, u32::from(mask))),
                    }
                });
            }
        } else {
            for child in tree.children(node) {
                stack.push((child as u32, next_live, next_planes));
            }
        }
    }
    // The frame's boxes, against each slice's near and far planes.
    for &i in &frame.boxes {
        let box_dots = tests.dots(arrays.center_half(i as usize));
        for (k, out) in out.iter_mut().enumerate() {
            match tests.test(box_dots, k, 0b11) {
                None => {}
                Some(0) => out.boxes.push(i),
                Some(mask) => out.cut.push((i, u32::from(mask))),
            }
        }
    }
    // The frame's cut boxes: the planes they cross beyond the near and far ones are every
    // slice's, tested once.
    let side_planes = BoxPlanes::new(first);
    for &(i, mask) in &frame.cut {
        let (c, h) = arrays.center_half(i as usize);
        let Some(side) = side_planes.straddled(c, h, mask & !0b11, tolerance) else {
            continue;
        };
        let box_dots = tests.dots((c, h));
        for (k, out) in out.iter_mut().enumerate() {
            match tests.test(box_dots, k, 0b11).map(|m| side | u32::from(m)) {
                None => {}
                Some(0) => out.boxes.push(i),
                Some(mask) => out.cut.push((i, mask)),
            }
        }
    }
    Some(out)
}

/// Calls `f` with the index of each set bit of `bits`, lowest first.
#[inline(always)]
fn for_each_bit(mut bits: u8, mut f: impl FnMut(usize)) {
    while bits != 0 {
        f(bits.trailing_zeros() as usize);
        bits &= bits - 1;
    }
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
        let (c, h) = self.boxes.center_half(i);
        self.extents_of(c, h)
    }

    /// The extents in the frame of the box with centre `c` and half extents `h`.
    #[inline(always)]
    pub fn extents_of(&self, c: DVec3, h: DVec3) -> Extents {
        let (a, h_axes) = (&self.axes, &self.abs_axes);
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

/// Room for the vertices of a cut box, enough for most (a box cut by one plane has at most
/// 13), so that the scratch buffers of the walks do not grow piece by piece.
const CUT_VERTICES: usize = 32;

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
    // clear room for 32 planes), larger ones for the rest.
    if mask.count_ones() == 1 {
        cut_by_one(
            aabb,
            &planes[mask.trailing_zeros() as usize],
            tolerance,
            out,
        )
    } else if mask.count_ones() <= 4 {
        cut_vertices::<4>(aabb, planes, mask, tolerance, out)
    } else if mask.count_ones() <= 8 {
        // A spot light's frustum and a side.
        cut_vertices::<8>(aabb, planes, mask, tolerance, out)
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
    let crossing = crossing_edges(&dist);
    for_each_edge(crossing.iter().fold(0, |m, x| m | x), |a, axis| {
        if crossing[axis] >> a & 1 != 0 {
            let b = a | 1 << axis;
            let (da, db) = (dist[a], dist[b]);
            out.push(corners[a] + (corners[b] - corners[a]) * (da / (da - db)));
        }
    });
    out.len() > start
}

/// The box's edges that cross a plane, from its corners' signed distances (corner `c` at
/// bit `c`, as [`Aabb::corners`] orders them): for each axis, bit `a` set where the edge from
/// corner `a` to corner `a` + that axis's bit has one end below 0 and the other not.
fn crossing_edges(dist: &[f64; 8]) -> [u8; 3] {
    let below = dist
        .iter()
        .enumerate()
        .fold(0u8, |m, (c, d)| m | u8::from(*d < 0.0) << c);
    // The corners without the axis's bit: x 0, 2, 4, 6; y 0, 1, 4, 5; z 0, 1, 2, 3.
    [
        (below ^ below >> 1) & 0b0101_0101,
        (below ^ below >> 2) & 0b0011_0011,
        (below ^ below >> 4) & 0b0000_1111,
    ]
}

/// Calls `f(a, axis)` for each corner `a` in `corners` (a bit mask), in increasing order, and
/// each axis 0, 1, 2 whose edge starts there (bit `axis` of `a` clear): the order in which a
/// walk over every edge would meet them.
fn for_each_edge(corners: u8, mut f: impl FnMut(usize, usize)) {
    for_each_bit(corners, |a| {
        for axis in 0..3 {
            if a & 1 << axis == 0 {
                f(a, axis);
            }
        }
    });
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
    let mut crossing = [[0u8; 3]; N];
    let mut any = 0;
    for (j, d) in dist[..k].iter().enumerate() {
        crossing[j] = crossing_edges(d);
        any |= crossing[j].iter().fold(0, |m, x| m | x);
    }
    for_each_edge(any, |a, axis| {
        let b = a | 1 << axis;
        for (j, d) in dist[..k].iter().enumerate() {
            if crossing[j][axis] >> a & 1 != 0 {
                let (da, db) = (d[a], d[b]);
                let p = corners[a] + (corners[b] - corners[a]) * (da / (da - db));
                if in_cut(p, &[j]) {
                    out.push(p);
                }
            }
        }
    });
    // One box face and two planes: where the two planes' line enters and leaves the box;
    // three planes.
    for j in 0..k {
        for l in j + 1..k {
            for p in line_through_box(&cut[j], &cut[l], aabb, tolerance)
                .into_iter()
                .flatten()
            {
                if in_cut(p, &[j, l]) {
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

/// Where the line of two planes enters and leaves a box: the points where it meets the
/// box's faces inside the box (the line clipped by the box's three slabs; a line parallel to
/// a slab counts as inside it within `tolerance`). `None` where the planes are parallel or
/// their line misses the box.
fn line_through_box(a: &Plane, b: &Plane, aabb: &Aabb, tolerance: f64) -> Option<[DVec3; 2]> {
    let dir = a.normal.cross(b.normal);
    let dd = dir.length_squared();
    if dd < 1e-24 {
        return None;
    }
    // The point of the line nearest the origin.
    let p0 = (b.normal.cross(dir) * -a.offset + dir.cross(a.normal) * -b.offset) / dd;
    let (lo, hi) = (aabb.min(), aabb.max());
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..3 {
        if dir[i] == 0.0 {
            if p0[i] < lo[i] - tolerance || p0[i] > hi[i] + tolerance {
                return None;
            }
        } else {
            let (u, v) = ((lo[i] - p0[i]) / dir[i], (hi[i] - p0[i]) / dir[i]);
            t0 = t0.max(u.min(v));
            t1 = t1.min(u.max(v));
        }
    }
    (t0 <= t1 && t0.is_finite() && t1.is_finite() && p0.is_finite())
        .then(|| [p0 + dir * t0, p0 + dir * t1])
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

/// The box (centre, half extents) around boxes `ids` of `arrays`, grown as a hierarchy's node
/// is ([`grown`]), so that it holds each box after rounding.
fn box_around(arrays: &BoxArrays, ids: impl Iterator<Item = usize>) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in ids {
        let (c, h) = arrays.center_half(i);
        (lo, hi) = (lo.min(c - h), hi.max(c + h));
    }
    grown(lo, hi)
}

/// How many receivers listed one by one [`VisibleScene::extents_under`] tests at once
/// against the box around them. Neighbours in the classification's order lie close, so the
/// box is little larger than theirs; the count was chosen by instruction counts
/// (`scripts/setup-instructions.sh`, CHANGELOG.md).
const RUN: usize = 4;

/// How a walk of the visible receivers ([`VisibleScene::extents_under`]) sees boxes and
/// points under its map (or maps: `E`).
pub(crate) struct ReceiverMap<N, R, B, X, P> {
    /// A subtree's node's image (it holds its boxes').
    pub node: N,
    /// The image of a world box (centre, half extents) around some receivers, which holds
    /// their bounds; read only where `prune_cuts`.
    pub region: R,
    /// A bound on a receiver's image (cheap; what decides whether the receiver adds
    /// anything).
    pub bound: B,
    /// The receiver's image given that bound (the bound itself where it is exact).
    pub exact: X,
    /// The image of points (a cut part's vertices).
    pub points: P,
    /// Whether a box's image bounds the image of any part of it, whole or cut: not for a
    /// point light, behind which a box's image is no bound (there runs of receivers are not
    /// taken whole, and a cut receiver is always cut).
    pub prune_cuts: bool,
}

/// What a walk of the visible receivers ([`VisibleScene::extents_under`]) gathers: the
/// extents of their images under one map, or under two at once ([`Both`]), so that one walk
/// serves both.
pub(crate) trait Gather: Copy {
    /// Whether these extents hold `image`.
    fn holds(&self, image: &Self) -> bool;
    /// Adds `image`, an item's image, where these extents do not hold `bound`, the bound that
    /// decided whether the item adds anything (it holds `image`, up to rounding).
    fn take(&mut self, bound: &Self, image: &Self);
    /// Adds `image`.
    fn merge(&mut self, image: &Self);
    /// The depth that orders a subtree's children, nearest the light first.
    fn near(&self) -> f64;
}

impl Gather for Extents {
    #[inline]
    fn holds(&self, image: &Self) -> bool {
        self.contains(image)
    }
    #[inline]
    fn take(&mut self, bound: &Self, image: &Self) {
        if !self.contains(bound) {
            *self = Extents::union(self, image);
        }
    }
    #[inline]
    fn merge(&mut self, image: &Self) {
        *self = Extents::union(self, image);
    }
    #[inline]
    fn near(&self) -> f64 {
        self.min.z
    }
}

/// Extents under two maps, gathered in one walk. Each map's are what a walk under it alone
/// gathers, to the bit. The walk opens a subtree or adds an item where either map's extents
/// do not hold its image, and each map takes an item only where its own do not hold the
/// item's bound. An item the other map needed is one that a walk under this map would have
/// passed by: its bound lies in what this map held. Children are ordered by the second
/// map's depth, as a walk under it alone orders them. The first map's extents must not
/// depend on the order; they do not where a box's bound is its image, as for a light frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Both {
    pub first: Extents,
    pub second: Extents,
}

impl Gather for Both {
    #[inline]
    fn holds(&self, image: &Self) -> bool {
        self.first.contains(&image.first) && self.second.contains(&image.second)
    }
    #[inline]
    fn take(&mut self, bound: &Self, image: &Self) {
        self.first.take(&bound.first, &image.first);
        self.second.take(&bound.second, &image.second);
    }
    #[inline]
    fn merge(&mut self, image: &Self) {
        self.first.merge(&image.first);
        self.second.merge(&image.second);
    }
    #[inline]
    fn near(&self) -> f64 {
        self.second.min.z
    }
}

/// What the camera sees of the scene, for one light: the view frustum inside the scene box
/// (P) and the visible parts of the receivers.
#[derive(Clone)]
pub(crate) struct VisibleScene {
    /// P: the view frustum clipped by the scene box (and the light frustum for a spot light).
    pub view_body: ConvexPolyhedron,
    /// Subtrees of the receivers' hierarchy wholly visible.
    nodes: Vec<u32>,
    /// Receivers wholly visible outside those subtrees.
    boxes: Vec<u32>,
    /// How many receivers are wholly visible.
    whole: usize,
    /// The vertices of the visible parts of the receivers that several planes cut.
    points: Vec<DVec3>,
    /// Each receiver that several planes cut, in order of index: (its index, the planes that
    /// cut it, where its vertices start and end in `points`).
    cuts: Vec<(u32, u32, u32, u32)>,
    /// The receivers that one plane cuts (most cut ones), with that plane (its index in
    /// `planes`). Their part inside it is never empty, and is cut only where it is read
    /// ([`cut_by_one`], cheap), so that a receiver whose whole box adds nothing to an extent
    /// is never cut.
    cut_once: Vec<(u32, u32)>,
    /// The planes the receivers were classified against.
    planes: Vec<Plane>,
    /// The tolerance the cuts are made with.
    tolerance: f64,
    /// The visible part of each receiver in `cuts`, as a polyhedron, each made on first
    /// use: a point light's faces cut it further by their frusta, each from the same part.
    cut_bodies: OnceLock<Vec<OnceLock<ConvexPolyhedron>>>,
}

/// A frame's cut receivers that a part of it may take instead of cutting them again: the
/// frame's visible scene and the bits of the planes the part changed. A receiver cut by the
/// same planes in both (none of them changed) has the same visible part.
#[derive(Clone, Copy)]
pub(crate) struct ReuseCuts<'a> {
    pub frame: &'a VisibleScene,
    pub changed: u32,
}

impl VisibleScene {
    /// The visible scene of P = `view_body` from the receivers' classification against
    /// `planes` (empty when P is): wholly visible subtrees and boxes are kept, cut boxes cut
    /// (or taken from `reuse`).
    pub fn from_classified(
        view_body: ConvexPolyhedron,
        scene: &SceneBounds,
        planes: &[Plane],
        classified: &Classified,
        tolerance: f64,
        reuse: Option<ReuseCuts<'_>>,
    ) -> Self {
        let mut visible = Self {
            view_body,
            nodes: Vec::new(),
            boxes: Vec::new(),
            whole: 0,
            points: Vec::new(),
            cuts: Vec::new(),
            cut_once: Vec::new(),
            planes: Vec::new(),
            tolerance,
            cut_bodies: OnceLock::new(),
        };
        if visible.view_body.is_empty() {
            return visible;
        }
        let tree = scene.receiver_tree();
        visible.nodes.clone_from(&classified.nodes);
        visible.boxes.clone_from(&classified.boxes);
        visible.whole = classified.boxes.len()
            + classified
                .nodes
                .iter()
                .map(|&n| tree.size(n as usize))
                .sum::<usize>();
        visible.planes = planes.to_vec();
        visible.cut_once.reserve(classified.cut.len());
        visible.points.reserve(64);
        let points = &mut visible.points;
        for &(i, mask) in &classified.cut {
            if mask.count_ones() == 1 {
                visible.cut_once.push((i, mask.trailing_zeros()));
                continue;
            }
            let start = points.len();
            let same = reuse
                .filter(|r| mask & r.changed == 0)
                .and_then(|r| r.frame.cut_of(i as usize, mask));
            let kept = match same {
                Some(vertices) => {
                    points.extend_from_slice(vertices);
                    true
                }
                None => box_cut_vertices(
                    &scene.receivers()[i as usize],
                    planes,
                    mask,
                    tolerance,
                    points,
                ),
            };
            if kept {
                visible
                    .cuts
                    .push((i, mask, start as u32, points.len() as u32));
            }
        }
        // Few receivers reach several planes (the view's edges): sorting them here is cheaper
        // than sorting every cut receiver.
        visible.cuts.sort_unstable_by_key(|c| c.0);
        visible
    }

    /// The vertices of receiver `i`'s visible part when the planes `mask` cut it.
    fn cut_of(&self, i: usize, mask: u32) -> Option<&[DVec3]> {
        let k = self.cuts.binary_search_by_key(&(i as u32), |c| c.0).ok()?;
        let (_, cut_by, start, end) = self.cuts[k];
        (cut_by == mask).then(|| &self.points[start as usize..end as usize])
    }

    /// How many receiver boxes have a visible part.
    pub fn visible_receivers(&self) -> usize {
        self.whole + self.cuts.len() + self.cut_once.len()
    }

    /// The wholly visible receivers' indices.
    fn whole_boxes<'s>(&'s self, tree: &'s BoxTree) -> impl Iterator<Item = usize> + 's {
        let in_nodes = self
            .nodes
            .iter()
            .flat_map(|&n| tree.boxes_of(n as usize).iter());
        in_nodes.chain(&self.boxes).map(|&i| i as usize)
    }

    /// Calls `f` with every vertex of the visible receiver parts (the corners of wholly
    /// visible boxes, the vertices of cut ones): their extents under any projective map are
    /// the extents of these points.
    pub fn for_each_vertex(&self, scene: &SceneBounds, mut f: impl FnMut(DVec3)) {
        for i in self.whole_boxes(scene.receiver_tree()) {
            for c in scene.receivers()[i].corners() {
                f(c);
            }
        }
        self.for_each_cut_vertex(scene, f);
    }

    /// Calls `f` with every vertex of the cut receivers' visible parts.
    pub fn for_each_cut_vertex(&self, scene: &SceneBounds, mut f: impl FnMut(DVec3)) {
        for p in &self.points {
            f(*p);
        }
        let mut scratch = Vec::with_capacity(CUT_VERTICES);
        for &(i, plane) in &self.cut_once {
            let plane = &self.planes[plane as usize];
            scratch.clear();
            cut_by_one(
                &scene.receivers()[i as usize],
                plane,
                self.tolerance,
                &mut scratch,
            );
            scratch.iter().for_each(|p| f(*p));
        }
    }

    /// The extents of the visible receiver parts under a map, or two at once ([`Gather`]), as
    /// `map` sees boxes and points ([`ReceiverMap`]). The parts that several planes cut come
    /// first (they reach the borders of the view), then the wholly visible receivers, nearest
    /// the light first, then those one plane cuts. A subtree or a cut receiver whose (whole)
    /// image lies inside what is gathered so far adds nothing and is neither opened nor cut,
    /// so that the work grows with the receivers near the border of the visible region, not
    /// with their number. The receivers listed one by one (those of the leaves a plane
    /// crosses, mostly held) are also taken [`RUN`] at a time where the map allows it: where
    /// the box around a run has a bound the extents hold, none of them is looked at.
    pub fn extents_under<E, N, R, B, X, P>(
        &self,
        scene: &SceneBounds,
        map: ReceiverMap<N, R, B, X, P>,
    ) -> E
    where
        E: Gather,
        N: Fn(usize) -> E,
        R: Fn(DVec3, DVec3) -> E,
        B: Fn(usize) -> E,
        X: Fn(usize, E) -> E,
        P: Fn(&[DVec3]) -> E,
    {
        let ReceiverMap {
            node: node_image,
            region: region_bound,
            bound: box_bound,
            exact: box_image,
            points: points_image,
            prune_cuts,
        } = map;
        let tree = scene.receiver_tree();
        let arrays = scene.receiver_arrays();
        let mut ext = points_image(&self.points);
        let add_box = |ext: &mut E, i: usize| {
            let bound = box_bound(i);
            if !ext.holds(&bound) {
                ext.take(&bound, &box_image(i, bound));
            }
        };
        // Whether the extents hold the bound of the box around a run of receivers (neighbours
        // in the classification's order), so that none of them, nor a part of one, adds.
        let run_held = |ext: &E, (c, h): (DVec3, DVec3)| ext.holds(&region_bound(c, h));
        for run in self.boxes.chunks(RUN) {
            let ids = run.iter().map(|&i| i as usize);
            if prune_cuts && run.len() > 1 && run_held(&ext, box_around(arrays, ids)) {
                continue;
            }
            for &i in run {
                add_box(&mut ext, i as usize);
            }
        }
        let mut stack: Vec<(usize, E)> = self
            .nodes
            .iter()
            .map(|&n| (n as usize, node_image(n as usize)))
            .collect();
        while let Some((node, image)) = stack.pop() {
            if ext.holds(&image) {
                continue;
            }
            if tree.is_leaf(node) {
                for &i in tree.boxes_of(node) {
                    add_box(&mut ext, i as usize);
                }
            } else {
                let [a, b] = tree.children(node).map(|c| (c, node_image(c)));
                if a.1.near() < b.1.near() {
                    stack.extend([b, a]);
                } else {
                    stack.extend([a, b]);
                }
            }
        }
        let mut scratch = Vec::with_capacity(CUT_VERTICES);
        for run in self.cut_once.chunks(RUN) {
            let ids = run.iter().map(|c| c.0 as usize);
            if prune_cuts && run.len() > 1 && run_held(&ext, box_around(arrays, ids)) {
                continue;
            }
            for &(i, plane) in run {
                let plane = &self.planes[plane as usize];
                let bound = prune_cuts.then(|| box_bound(i as usize));
                if bound.is_some_and(|bound| ext.holds(&bound)) {
                    continue;
                }
                scratch.clear();
                let aabb = &scene.receivers()[i as usize];
                cut_by_one(aabb, plane, self.tolerance, &mut scratch);
                let image = points_image(&scratch);
                match bound {
                    Some(bound) => ext.take(&bound, &image),
                    None => ext.merge(&image),
                }
            }
        }
        ext
    }

    /// Whether every point of the visible receiver parts passes `pred`, whose passing points
    /// must form a convex set (a half-space, a cone). A box then passes when its corners do
    /// (`corners_pass`, which must say whether `pred` holds at all eight), so a subtree whose
    /// node's corners pass is not opened.
    pub fn all(
        &self,
        scene: &SceneBounds,
        pred: impl Fn(DVec3) -> bool,
        corners_pass: impl Fn(&Aabb) -> bool,
    ) -> bool {
        if !self.points.iter().all(|p| pred(*p)) {
            return false;
        }
        if !self
            .boxes
            .iter()
            .all(|&i| corners_pass(&scene.receivers()[i as usize]))
        {
            return false;
        }
        let tree = scene.receiver_tree();
        let mut stack: Vec<usize> = self.nodes.iter().map(|&n| n as usize).collect();
        while let Some(node) = stack.pop() {
            if corners_pass(&tree.node_box(node)) {
                continue;
            }
            if !tree.is_leaf(node) {
                stack.extend(tree.children(node));
            } else if !tree
                .boxes_of(node)
                .iter()
                .all(|&i| corners_pass(&scene.receivers()[i as usize]))
            {
                return false;
            }
        }
        let mut scratch = Vec::with_capacity(CUT_VERTICES);
        for &(i, plane) in &self.cut_once {
            let plane = &self.planes[plane as usize];
            let aabb = &scene.receivers()[i as usize];
            if corners_pass(aabb) {
                continue;
            }
            scratch.clear();
            cut_by_one(aabb, plane, self.tolerance, &mut scratch);
            if !scratch.iter().all(|p| pred(*p)) {
                return false;
            }
        }
        true
    }

    /// The extents of the visible receiver parts under `projector`.
    pub fn receiver_extents(&self, scene: &SceneBounds, projector: &Projector) -> Extents {
        let points_image = |points: &[DVec3]| projector.points_extents(points);
        let tree = scene.receiver_tree();
        match projector {
            Projector::Parallel(frame) => {
                let nodes = ParallelBoxes::new(&tree.nodes, frame);
                let boxes = ParallelBoxes::new(scene.receiver_arrays(), frame);
                self.extents_under(
                    scene,
                    ReceiverMap {
                        node: |n| nodes.extents(n),
                        region: |c, h| boxes.extents_of(c, h),
                        bound: |i| boxes.extents(i),
                        exact: |_, exact| exact,
                        points: points_image,
                        prune_cuts: true,
                    },
                )
            }
            // Wholly visible receivers lie in front of the light (inside its frustum), where a
            // box's image holds the images of the boxes inside it.
            Projector::Point { .. } => self.extents_under(
                scene,
                ReceiverMap {
                    node: |n| projector.box_extents(&tree.node_box(n)),
                    // Not asked for: a box around receivers may reach behind the light.
                    region: |_, _| Extents::ALL,
                    bound: |i| projector.box_extents(&scene.receivers()[i]),
                    exact: |_, exact| exact,
                    points: points_image,
                    prune_cuts: false,
                },
            ),
        }
    }
}

/// A cube face's frustum as its own map sees it: its planes (near, far, then the four sides,
/// [`crate::light::SpotLight::frustum_planes`]) and the closed form of a box's part inside
/// it ([`AxisFrustum`]: a face's frame has world axes), whose tangent of the half-angle
/// makes the sides the map's square `|x|, |y| <= tangent`. Since the sides are the light's
/// rays through the square's edges, the image of a part in front of the light
/// (beyond its near plane) cut by the sides is the image of the uncut part clamped to the
/// square, and a box's part needs no cut at all.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceFrustum {
    pub planes: [Plane; 6],
    pub axis: AxisFrustum,
}

impl FaceFrustum {
    /// The bits of the near and far planes in `planes`.
    pub const NEAR_FAR: u32 = 0b11;

    /// `e` clamped to the square in x and y, or empty where it misses it.
    pub fn clamp(&self, e: Extents) -> Extents {
        let c = e.within_square(self.axis.tangent());
        if c.is_empty() { Extents::EMPTY } else { c }
    }
}

/// A caster walk's images under a cube face's own projector. Each box's is the image of its
/// part inside the face's frustum ([`AxisFrustum::box_extents`]), so that the walk cuts no
/// box. It walks with the near plane alone as its cutting plane, which keeps the boxes that
/// cross it apart for [`AxisFrustum::clips_tip`].
pub(crate) struct FaceImages<'a> {
    pub scene: &'a SceneBounds,
    pub projector: &'a Projector,
    pub frustum: &'a FaceFrustum,
}

impl CasterImages for FaceImages<'_> {
    const AFFINE: bool = false;
    const EXACT: bool = true;
    fn node(&self, n: usize) -> Extents {
        let tree = self.scene.caster_tree();
        self.frustum.axis.box_extents(&tree.node_box(n))
    }
    fn caster(&self, i: usize) -> Extents {
        self.frustum.axis.box_extents(&self.scene.casters()[i])
    }
    fn point(&self, p: DVec3) -> DVec3 {
        self.projector.project(p)
    }
    fn clips_near(&self, i: usize) -> bool {
        self.frustum.axis.clips_tip(&self.scene.casters()[i])
    }
}

impl VisibleScene {
    /// The extents, under a cube face's own `projector`, of the visible receiver parts
    /// inside its `frustum`, straight from this scene (cut by the view's `view_planes`
    /// alone): the same as [`Self::receiver_extents`] of the scene cut by the frustum. A
    /// whole box's part, and a bound of a subtree's, is a closed form
    /// ([`AxisFrustum::box_extents`]); a subtree whose bound adds nothing to the extents
    /// gathered so far is not opened. A part the view cuts, in front of the light's near
    /// plane, is cut by the frustum's sides only where its clamped image
    /// ([`FaceFrustum::clamp`], which holds the image of its cut) adds to the extents.
    pub fn extents_in_frustum(
        &self,
        scene: &SceneBounds,
        view_planes: &[Plane],
        frustum: &FaceFrustum,
        projector: &Projector,
    ) -> Extents {
        let tolerance = self.tolerance;
        let (arrays, receivers) = (scene.receiver_arrays(), scene.receivers());
        let image = |points: &[DVec3]| projector.points_extents(points);
        let against_frustum =
            |c: DVec3, h: DVec3| straddled(c, h, &frustum.planes, all_planes(6), tolerance);
        let mut scratch = Vec::with_capacity(CUT_VERTICES);
        // Adds the part inside the frustum planes `frustum_mask` of the visible part (`view`) of
        // receiver `i`, given an image `bound` that holds its part's (and is its image where
        // `exact` and no plane of the frustum cuts it).
        let mut add = |ext: &mut Extents,
                       i: usize,
                       view: ViewPart<'_>,
                       frustum_mask: u32,
                       bound: Extents,
                       exact: bool| {
            let b = frustum.clamp(bound);
            if b.is_empty() || ext.contains(&b) {
                return;
            }
            if frustum_mask == 0 && exact {
                *ext = ext.union(&b);
                return;
            }
            scratch.clear();
            let kept = match view {
                ViewPart::Cut(k) => {
                    let cut = (0..6)
                        .filter(|j| frustum_mask & (1 << j) != 0)
                        .map(|j| &frustum.planes[j]);
                    let part = self
                        .cut_body(k, receivers, view_planes)
                        .clip_all(cut, tolerance);
                    scratch.extend_from_slice(part.points());
                    !part.is_empty()
                }
                ViewPart::CutOnce(plane) => {
                    let mut cut = [*plane; 7];
                    cut[1..].copy_from_slice(&frustum.planes);
                    box_cut_vertices(
                        &receivers[i],
                        &cut,
                        1 | frustum_mask << 1,
                        tolerance,
                        &mut scratch,
                    )
                }
            };
            if kept {
                *ext = ext.union(&image(&scratch));
            }
        };
        let mut ext = self.whole_extents_in_frustum(scene, frustum);
        // The parts the view cuts, once the whole boxes have grown the extents (so that more
        // of them add nothing). Where one lies in front of the light (inside its near plane)
        // its points' image bounds its part's; else the image of the whole box's part does.
        // The near plane is left out of a cut where the box misses the frustum's tip: the
        // sides keep nothing nearer.
        let planes_of = |i: usize, m: u32| {
            if m & 1 != 0 && !frustum.axis.meets_tip(&receivers[i]) {
                m & !1
            } else {
                m
            }
        };
        for (k, &(i, _, start, end)) in self.cuts.iter().enumerate() {
            let i = i as usize;
            if let Some(m) = against_frustum(arrays.center_of(i), arrays.half_of(i)) {
                let (bound, exact) = if m & FaceFrustum::NEAR_FAR == 0 {
                    (image(&self.points[start as usize..end as usize]), true)
                } else {
                    (frustum.axis.box_extents(&receivers[i]), false)
                };
                add(&mut ext, i, ViewPart::Cut(k), planes_of(i, m), bound, exact);
            }
        }
        for &(i, plane) in &self.cut_once {
            let (i, plane) = (i as usize, &self.planes[plane as usize]);
            if let Some(m) = against_frustum(arrays.center_of(i), arrays.half_of(i)) {
                let bound = frustum.axis.box_extents(&receivers[i]);
                add(
                    &mut ext,
                    i,
                    ViewPart::CutOnce(plane),
                    planes_of(i, m),
                    bound,
                    false,
                );
            }
        }
        ext
    }

    /// The image of the receivers the view sees whole (inside subtrees and listed boxes)
    /// under `frustum`'s axis-aligned projector: a subtree whose node's image adds nothing is
    /// not opened.
    fn whole_extents_in_frustum(&self, scene: &SceneBounds, frustum: &FaceFrustum) -> Extents {
        let (tree, receivers) = (scene.receiver_tree(), scene.receivers());
        let mut ext = Extents::EMPTY;
        let whole_box = |ext: &mut Extents, i: usize| {
            *ext = ext.union(&frustum.axis.box_extents(&receivers[i]));
        };
        for &i in &self.boxes {
            whole_box(&mut ext, i as usize);
        }
        let mut stack: Vec<usize> = self.nodes.iter().map(|&n| n as usize).collect();
        while let Some(node) = stack.pop() {
            if ext.contains(&frustum.axis.box_extents(&tree.node_box(node))) {
                continue;
            }
            if tree.is_leaf(node) {
                for &i in tree.boxes_of(node) {
                    whole_box(&mut ext, i as usize);
                }
            } else {
                stack.extend(tree.children(node));
            }
        }
        ext
    }

    /// The part of `cuts[k]`'s receiver that several of `view_planes` cut, as a polyhedron
    /// made once and shared by every face.
    fn cut_body(&self, k: usize, receivers: &[Aabb], view_planes: &[Plane]) -> &ConvexPolyhedron {
        self.cut_bodies
            .get_or_init(|| vec![OnceLock::new(); self.cuts.len()])[k]
            .get_or_init(|| {
                let (i, view_mask, _, _) = self.cuts[k];
                let cut = (0..view_planes.len())
                    .filter(|j| view_mask & (1 << j) != 0)
                    .map(|j| &view_planes[j]);
                ConvexPolyhedron::from_box(&receivers[i as usize]).clip_all(cut, self.tolerance)
            })
    }
}

/// Which part of a receiver the view sees, for [`VisibleScene::extents_in_frustum`].
#[derive(Clone, Copy)]
enum ViewPart<'p> {
    /// The box inside one plane.
    CutOnce(&'p Plane),
    /// The part of the receiver of `cuts[k]`, which several planes cut.
    Cut(usize),
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
/// extents under `projector`), in x and y only as far as they lie over the receivers (grown
/// by the culling slack) and in depth only as far as the receivers' farthest point: what unit
/// cube clipping reads. A caster is cut by `cut_planes` (a spot light's frustum, its near
/// plane first when `light_near_first`, and a side's plane) and culled when nothing of it is
/// left, when it lies beside the receivers as seen from the light, or wholly behind them.
/// Counts go into `diagnostics`.
///
/// The casters' hierarchy is walked from the root. A subtree whose node lies beside or behind
/// the receivers is culled whole. One whose node lies inside every cutting plane and whose
/// image over the receivers adds nothing to the extents gathered so far is counted whole
/// without being opened; it may hold boxes just beside the receivers (see
/// [`crate::Diagnostics::relevant_casters`]). One that could add only in x and y is put off,
/// and opened at the end where the extents still do not hold it, the farthest-reaching first
/// ([`PutOff`]). Children nearer the light are opened first, so that the nearest caster (the
/// near plane) is found early.
pub(crate) fn caster_extents(
    scene: &SceneBounds,
    projector: &Projector,
    receivers: &Extents,
    cut_planes: &[Plane],
    light_near_first: bool,
    tolerance: f64,
    diagnostics: &mut Diagnostics,
) -> Extents {
    let tree = scene.caster_tree();
    let walked = match projector {
        Projector::Parallel(frame) => {
            let images = ParallelImages {
                nodes: ParallelBoxes::new(&tree.nodes, frame),
                boxes: ParallelBoxes::new(scene.caster_arrays(), frame),
                projector,
            };
            walk_casters(
                scene,
                &images,
                receivers,
                cut_planes,
                light_near_first,
                tolerance,
            )
        }
        Projector::Point { .. } => {
            let images = MapImages {
                node: |n: usize| projector.box_extents(&tree.node_box(n)),
                caster: |i: usize| projector.box_extents(&scene.casters()[i]),
                point: |p: DVec3| projector.project(p),
                holds_cut_parts: false,
            };
            walk_casters(
                scene,
                &images,
                receivers,
                cut_planes,
                light_near_first,
                tolerance,
            )
        }
    };
    walked.count_into(scene, diagnostics);
    walked.extents
}

/// How a caster walk sees boxes and points under a map: x and y in the map, z a depth along
/// the light (nearer is smaller).
pub(crate) trait CasterImages {
    /// Whether the map is affine: a node's image then holds its boxes' images whatever
    /// planes cut them; a projective map's holds them only where the node lies in front of
    /// its centre (inside every cutting plane, which keep the casters there).
    const AFFINE: bool;
    /// The image of node `n` of the casters' hierarchy.
    fn node(&self, n: usize) -> Extents;
    /// The image of caster `i`.
    fn caster(&self, i: usize) -> Extents;
    /// The image of a point.
    fn point(&self, p: DVec3) -> DVec3;
    /// A depth that orders children nearest the light first, where the map has one.
    fn order(&self, _center: DVec3) -> f64 {
        0.0
    }
    /// Whether `node` and `caster` give the images of their boxes' parts inside the walk's
    /// cutting planes and the map's frustum (a cube face's, [`FaceImages`]): no box is then
    /// cut, and [`CasterImages::clips_near`] says which the light's near plane clips.
    const EXACT: bool = false;
    /// For [`CasterImages::EXACT`] images: whether the light's near plane (the first cutting
    /// plane, which caster `i` crosses) clips part of the caster from the map.
    fn clips_near(&self, _i: usize) -> bool {
        false
    }
    /// Whether [`CasterImages::node`] and [`CasterImages::caster`] hold the image of every part
    /// of a box, cut or not ([`Extents::ALL`] where the map has none for part of it). A
    /// subtree beside the receivers is then culled before it is opened. That keeps the walk
    /// to the boxes near the view when the cutting planes run across the whole scene.
    fn holds_cut_parts(&self) -> bool {
        Self::AFFINE || Self::EXACT
    }
}

/// A directional light's frame: boxes projected from their centres and half extents.
struct ParallelImages<'a> {
    nodes: ParallelBoxes<'a>,
    boxes: ParallelBoxes<'a>,
    projector: &'a Projector,
}

impl CasterImages for ParallelImages<'_> {
    const AFFINE: bool = true;
    fn node(&self, n: usize) -> Extents {
        self.nodes.extents(n)
    }
    fn caster(&self, i: usize) -> Extents {
        self.boxes.extents(i)
    }
    fn point(&self, p: DVec3) -> DVec3 {
        self.projector.project(p)
    }
    fn order(&self, center: DVec3) -> f64 {
        self.projector.frame().forward.dot(center)
    }
}

/// A projective map given by its images of nodes, casters and points.
pub(crate) struct MapImages<N, C, P> {
    pub node: N,
    pub caster: C,
    pub point: P,
    /// Whether `node` and `caster` give [`Extents::ALL`] for a box the map has no image of
    /// in part (see [`CasterImages::holds_cut_parts`]).
    pub holds_cut_parts: bool,
}

impl<N, C, P> CasterImages for MapImages<N, C, P>
where
    N: Fn(usize) -> Extents,
    C: Fn(usize) -> Extents,
    P: Fn(DVec3) -> DVec3,
{
    const AFFINE: bool = false;
    fn node(&self, n: usize) -> Extents {
        (self.node)(n)
    }
    fn caster(&self, i: usize) -> Extents {
        (self.caster)(i)
    }
    fn point(&self, p: DVec3) -> DVec3 {
        (self.point)(p)
    }
    fn holds_cut_parts(&self) -> bool {
        self.holds_cut_parts
    }
}

/// What a caster walk gathers: the extents (see [`caster_extents`]), how many casters are
/// relevant and how many of those the light's near plane cuts.
pub(crate) struct WalkedCasters {
    pub extents: Extents,
    pub relevant: usize,
    pub near_clipped: usize,
}

impl WalkedCasters {
    /// Puts the walk's caster counts into `diagnostics`.
    pub fn count_into(&self, scene: &SceneBounds, diagnostics: &mut Diagnostics) {
        diagnostics.relevant_casters = self.relevant;
        diagnostics.culled_casters = scene.casters().len() - self.relevant;
        diagnostics.casters_clipped_by_light_near = self.near_clipped;
    }
}

/// The walk of [`caster_extents`] under any map (`images`).
pub(crate) fn walk_casters<I: CasterImages>(
    scene: &SceneBounds,
    images: &I,
    receivers: &Extents,
    cut_planes: &[Plane],
    light_near_first: bool,
    tolerance: f64,
) -> WalkedCasters {
    let (tree, arrays) = (scene.caster_tree(), scene.caster_arrays());
    let (xy_slack, over, mut ext) = walk_bounds(receivers);
    let mut relevant = 0;
    let mut near_clipped = 0;
    let mut cuts = BoxCuts {
        scene,
        cut_planes,
        light_near_first,
        tolerance,
        scratch: Vec::with_capacity(CUT_VERTICES),
        near_tip: None,
    };
    // Nodes with the cutting planes they may cross, and whether to open the node without a
    // test (one taken from the put-off subtrees).
    let mut stack = Vec::with_capacity(64);
    if !tree.is_empty() {
        stack.push((0usize, all_planes(cut_planes.len()), false));
    }
    // Subtrees counted whole while the extents did not yet hold them in x and y (early in the
    // walk they are small), to be opened at the end if they still do not.
    let mut put_off = PutOff::new(&over);
    let whole = images.holds_cut_parts();
    let beside = |e: &Extents| !receivers.xy_overlaps(e, xy_slack) || e.min.z > receivers.max.z;
    loop {
        while let Some((node, active, open)) = stack.pop() {
            let Some(active) = cuts.crossed(&tree.nodes, node, active) else {
                continue;
            };
            // A node's image holds its boxes' (for a point light, where the node lies in
            // front of it: inside every plane of its frustum, or where the images are of the
            // parts inside it).
            if !open && (active == 0 || whole) {
                match node_step(images.node(node), active == 0, beside, &ext, &over) {
                    NodeStep::Open => {}
                    NodeStep::Cull => continue,
                    NodeStep::Count => {
                        relevant += tree.size(node);
                        continue;
                    }
                    NodeStep::PutOff(image) => {
                        relevant += tree.size(node);
                        put_off.push(node, image);
                        continue;
                    }
                }
            }
            if !tree.is_leaf(node) {
                let mut children = tree.children(node);
                let depth = |n: usize| images.order(tree.nodes.center_of(n));
                if depth(children[0]) < depth(children[1]) {
                    children.swap(0, 1);
                }
                stack.extend(children.map(|child| (child, active, false)));
                continue;
            }
            for &i in tree.boxes_of(node) {
                let i = i as usize;
                let code = cuts.crossed(arrays, i, active);
                let (box_ext, crosses_near) = match code {
                    None => continue,
                    Some(0) => (images.caster(i), false),
                    Some(mask) => match cuts.image(images, i, mask) {
                        Some(cut) => cut,
                        None => continue,
                    },
                };
                if beside(&box_ext) {
                    continue;
                }
                relevant += 1;
                near_clipped += usize::from(crosses_near);
                ext = ext.union(&box_ext.clamped_to(&over));
            }
        }
        // A put-off subtree lies no nearer than the casters gathered when it was counted, so
        // only its x and y can add: opened (and counted again) where the extents do not hold
        // them now.
        match put_off.pop(&ext) {
            Some(node) => {
                relevant -= tree.size(node);
                stack.push((node, 0, true));
            }
            None => break,
        }
    }
    WalkedCasters {
        extents: ext,
        relevant,
        near_clipped,
    }
}

/// A caster walk's bounds from the receivers' extents: the slack of its x and y tests, what
/// matters of a caster (its part over the receivers' columns, nearer than their far), and the
/// empty extents it gathers into. Their far depth is the receivers', since what lies farther
/// does not matter, so that a node's far side never keeps it open.
#[inline(always)]
fn walk_bounds(receivers: &Extents) -> (f64, Extents, Extents) {
    let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
    let over = Extents {
        min: (receivers.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
        max: (receivers.max.truncate() + xy_slack).extend(receivers.max.z),
    };
    let gathered = Extents {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY.with_z(over.max.z),
    };
    (xy_slack, over, gathered)
}

/// What a caster walk does with a node, from its image.
enum NodeStep {
    /// Beside or behind the receivers: none of its boxes matters.
    Cull,
    /// Nothing its boxes hold over the receivers can add: counted, not opened.
    Count,
    /// Only its x and y may add: counted, and opened at the end if they still do.
    PutOff(Extents),
    /// Opened now.
    Open,
}

/// The step for a node whose `image` holds its boxes' (`uncut`: no cutting plane crosses
/// it), against what is gathered so far (`ext`) and what matters of a caster (`over`).
#[inline(always)]
fn node_step(
    image: Extents,
    uncut: bool,
    beside: impl Fn(&Extents) -> bool,
    ext: &Extents,
    over: &Extents,
) -> NodeStep {
    if beside(&image) {
        NodeStep::Cull
    } else if uncut && ext.contains(&image.clamped_to(over)) {
        NodeStep::Count
    } else if uncut && over.contains(&image) && image.min.z >= ext.min.z {
        // Wholly over the receivers (so not held: the test above took it), no nearer than
        // what is gathered: only its x and y may add, which the extents may hold once they
        // have grown.
        NodeStep::PutOff(image)
    } else {
        NodeStep::Open
    }
}

/// What a caster walk needs to cut a leaf's box by the planes it crosses: the planes, the
/// scratch buffer its cut vertices go to, and the light frustum's tip (see [`NearTip`]),
/// made when a caster first crosses the near plane.
struct BoxCuts<'a> {
    scene: &'a SceneBounds,
    cut_planes: &'a [Plane],
    light_near_first: bool,
    tolerance: f64,
    scratch: Vec<DVec3>,
    near_tip: Option<NearTip>,
}

impl BoxCuts<'_> {
    /// The planes of `active` box `i` of `boxes` crosses (`Some(0)`: none, or none left to
    /// test), or `None` where it lies outside one of them.
    #[inline(always)]
    fn crossed(&self, boxes: &BoxArrays, i: usize, active: u32) -> Option<u32> {
        match active {
            0 => Some(0),
            active => straddled(
                boxes.center_of(i),
                boxes.half_of(i),
                self.cut_planes,
                active,
                self.tolerance,
            ),
        }
    }

    /// The image of caster `i`'s part inside the planes of `mask` it crosses, and whether
    /// the light's near plane clips it; `None` where no part is inside.
    #[inline(always)]
    fn image<I: CasterImages>(
        &mut self,
        images: &I,
        i: usize,
        mask: u32,
    ) -> Option<(Extents, bool)> {
        let near = self.light_near_first && mask & 1 != 0;
        if I::EXACT {
            return Some((images.caster(i), near && images.clips_near(i)));
        }
        self.scratch.clear();
        let (caster, planes, tolerance) =
            (&self.scene.casters()[i], self.cut_planes, self.tolerance);
        if !box_cut_vertices(caster, planes, mask, tolerance, &mut self.scratch) {
            return None;
        }
        let e = points_image(images, &self.scratch);
        let near_cut = near
            && self
                .near_tip
                .get_or_insert_with(|| NearTip::new(self.scene, planes, tolerance))
                .clips(caster, mask, tolerance);
        Some((e, near_cut))
    }
}

/// The tip of a spot light's frustum: the part nearer to the light than its near plane
/// (`planes[0]` of a walk's cutting planes) and inside the others, which the near plane clips
/// from the map.
pub(crate) struct NearTip {
    /// The cutting planes with the near plane flipped: their inside is the tip.
    planes: Vec<Plane>,
    /// The corners (least, greatest) of the box around the tip's part of the scene box;
    /// `None` when the tip misses the scene.
    bounds: Option<(DVec3, DVec3)>,
    /// The vertices of the tip's part of the scene box.
    corners: Vec<DVec3>,
    /// Vertices of a caster's cut.
    scratch: Vec<DVec3>,
}

impl NearTip {
    pub(crate) fn new(scene: &SceneBounds, cut_planes: &[Plane], tolerance: f64) -> Self {
        let mut planes = cut_planes.to_vec();
        planes[0] = cut_planes[0].flipped();
        let mut corners = Vec::new();
        let bounds = box_cut_vertices(
            &scene.scene_box(),
            &planes,
            all_planes(planes.len()),
            tolerance,
            &mut corners,
        )
        .then(|| {
            let lo = corners.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
            let hi = corners.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
            (lo, hi)
        });
        Self {
            planes,
            bounds,
            corners,
            scratch: Vec::new(),
        }
    }

    /// Whether part of `caster`'s surface lies in the tip, inside the planes of `mask` (those
    /// the caster crosses): the part the near plane clips away. A box that crosses the near
    /// plane only outside the light's frustum loses nothing, and nor does one that holds the
    /// whole tip (a lamp inside a box: its walls lie beyond the near plane).
    pub(crate) fn clips(&mut self, caster: &Aabb, mask: u32, tolerance: f64) -> bool {
        let Some((lo, hi)) = self.bounds else {
            return false;
        };
        if !((caster.min() - tolerance).cmple(hi).all()
            && (caster.max() + tolerance).cmpge(lo).all())
        {
            return false;
        }
        let (inner_lo, inner_hi) = (caster.min() + tolerance, caster.max() - tolerance);
        if self
            .corners
            .iter()
            .all(|p| p.cmpgt(inner_lo).all() && p.cmplt(inner_hi).all())
        {
            return false;
        }
        self.scratch.clear();
        box_cut_vertices(caster, &self.planes, mask, tolerance, &mut self.scratch)
    }
}

/// The extents of points under a caster walk's map.
fn points_image<I: CasterImages>(images: &I, points: &[DVec3]) -> Extents {
    let mut e = Extents::EMPTY;
    for p in points {
        e.add(images.point(*p));
    }
    e
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
    let (lo, hi) = clipped_rectangle(receivers, casters);
    Some(Extents {
        min: lo.extend(near.min(far)),
        max: hi.extend(far),
    })
}

/// Unit cube clipping's x and y: the receivers' and the casters' rectangles intersected.
/// Casters that only touch the receivers' rectangle (within the culling slack) leave an
/// inverted interval: it collapses to its middle, and padding gives it a size.
pub(crate) fn clipped_rectangle(receivers: &Extents, casters: &Extents) -> (DVec2, DVec2) {
    let lo = receivers.min.max(casters.min).truncate();
    let hi = receivers.max.min(casters.max).truncate();
    let mid = 0.5 * (lo + hi);
    (lo.min(mid), hi.max(mid))
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

    /// The extents of the casters, caster by caster, as `caster_extents` defines them.
    fn casters_one_by_one(
        scene: &SceneBounds,
        projector: &Projector,
        receivers: &Extents,
        cut_planes: &[Plane],
        tolerance: f64,
    ) -> (Extents, usize) {
        let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
        let over = Extents {
            min: (receivers.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
            max: (receivers.max.truncate() + xy_slack).extend(receivers.max.z),
        };
        let mut ext = Extents::EMPTY;
        let mut relevant = 0;
        for caster in scene.casters() {
            let mut points = Vec::new();
            match classify_box(caster, cut_planes, tolerance) {
                BoxSide::Outside => continue,
                BoxSide::Inside => points.extend(caster.corners()),
                BoxSide::Straddles(mask) => {
                    if !box_cut_vertices(caster, cut_planes, mask, tolerance, &mut points) {
                        continue;
                    }
                }
            }
            let mut e = Extents::EMPTY;
            for p in &points {
                e.add(projector.project(*p));
            }
            if receivers.xy_overlaps(&e, xy_slack) && e.min.z <= receivers.max.z {
                relevant += 1;
                ext = ext.union(&e.clamped_to(&over));
            }
        }
        (ext, relevant)
    }

    fn close(a: &Extents, b: &Extents, eps: f64) -> bool {
        let same = |x: f64, y: f64| x == y || (x - y).abs() <= eps;
        (0..3).all(|k| same(a.min[k], b.min[k]) && same(a.max[k], b.max[k]))
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

        /// Walking the scene's hierarchies gives what a pass over every box gives: the same
        /// visible receivers, the same receiver extents, the same caster extents, and a
        /// count of casters that holds every relevant one, for directional and spot lights,
        /// with and without a cutting side plane.
        #[test]
        fn hierarchy_walks_match_every_box(
            boxes in prop::collection::vec((prop::array::uniform3(-60.0f64..60.0), prop::array::uniform3(0.2f64..12.0), 0u8..3), 1..300),
            eye in prop::array::uniform3(-80.0f64..80.0),
            target in prop::array::uniform3(-30.0f64..30.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            spot in any::<bool>(),
            side in prop::option::of(prop::array::uniform3(-1.0f64..1.0)),
        ) {
            use crate::bvh::test_scenes;
            use crate::frame::Frame;
            use crate::light::{DirectionalLight, Light, SpotLight};
            use crate::map::MapSettings;
            use crate::technique::SetupInput;
            use crate::techniques::basis::{FocusBasis, Part};
            let scene = test_scenes::mixed(&boxes);
            let camera = test_scenes::camera(eye, target);
            prop_assume!(camera.is_some());
            let camera = camera.unwrap();
            let target = DVec3::from_array(target);
            let direction = DVec3::from_array(light);
            prop_assume!(direction.length() > 0.1);
            let light = if spot {
                Light::Spot(SpotLight::new(DVec3::new(5.0, 60.0, -5.0), direction.with_y(-1.0), 50.0, 300.0).unwrap())
            } else {
                Light::Directional(DirectionalLight::new(direction.with_y(-direction.y.abs() - 0.1)).unwrap())
            };
            let input = SetupInput { camera: &camera, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            let part = match side {
                Some(n) if DVec3::from_array(n).length() > 0.1 => {
                    // A plane through the light's rays, as SPPSM's.
                    let n = DVec3::from_array(n).normalize();
                    let along = match &light { Light::Directional(d) => d.direction(), Light::Spot(s) => s.direction(), Light::Point(_) => unreachable!() };
                    let n = (n - along * n.dot(along)).normalize_or_zero();
                    prop_assume!(n.length() > 0.5);
                    let through = match &light { Light::Directional(_) => target, Light::Spot(s) => s.position(), Light::Point(_) => unreachable!() };
                    Part::Side(Plane::through_point(through, n))
                }
                _ => Part::Whole,
            };
            let basis = FocusBasis::new(&frame, part);
            let tolerance = frame.tolerance;
            let planes = match part {
                Part::Side(p) => { let mut v = frame.receiver_planes.clone(); v.push(p); v }
                _ => frame.receiver_planes.clone(),
            };
            // Visible receivers, one by one.
            let mut count = 0;
            let mut vertices = Vec::new();
            if !basis.visible.view_body.is_empty() {
                for r in scene.receivers() {
                    match classify_box(r, &planes, tolerance) {
                        BoxSide::Outside => {}
                        BoxSide::Inside => { count += 1; vertices.extend(r.corners()); }
                        BoxSide::Straddles(mask) => {
                            if box_cut_vertices(r, &planes, mask, tolerance, &mut vertices) { count += 1; }
                        }
                    }
                }
            }
            prop_assert_eq!(basis.visible.visible_receivers(), count);
            prop_assume!(count > 0);
            let projectors = match &light {
                Light::Directional(d) => vec![
                    Projector::Parallel(LightFrame::fixed(d.direction())),
                    Projector::Parallel(LightFrame::view_aligned(d.direction(), camera.forward()).unwrap_or(LightFrame::fixed(d.direction()))),
                ],
                Light::Spot(s) => vec![Projector::Point { frame: LightFrame::fixed(s.direction()), position: s.position() }],
                Light::Point(_) => unreachable!(),
            };
            for projector in &projectors {
                let mut want = Extents::EMPTY;
                for v in &vertices { want.add(projector.project(*v)); }
                let got = basis.visible.receiver_extents(&scene, projector);
                let eps = 1e-9 * (1.0 + (want.max - want.min).abs().max_element() + want.min.abs().max_element());
                prop_assert!(close(&got, &want, eps), "receivers {:?} vs {:?}", got, want);
                let mut diagnostics = crate::diagnostics::Diagnostics::new(&camera, &light, &scene);
                let got = caster_extents(&scene, projector, &want, &basis.caster_planes, spot, tolerance, &mut diagnostics);
                let (want_casters, relevant) = casters_one_by_one(&scene, projector, &want, &basis.caster_planes, tolerance);
                // Subtrees that add nothing are counted whole: at least the relevant ones.
                prop_assert!(diagnostics.relevant_casters >= relevant
                    && (diagnostics.relevant_casters > 0) == (relevant > 0),
                    "{} counted, {relevant} relevant", diagnostics.relevant_casters);
                // The far side is not gathered (see `caster_extents`).
                let near_side = |e: &Extents| Extents { min: e.min, max: e.max.with_z(0.0) };
                if relevant > 0 {
                    prop_assert!(close(&near_side(&got), &near_side(&want_casters), eps),
                        "casters {:?} vs {:?}", got, want_casters);
                } else {
                    prop_assert!(got.is_empty());
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

        /// A cube face's closed forms agree with cutting the box by the face's frustum planes:
        /// the image of the part inside (empty where nothing is), and whether the near plane
        /// clips part of its surface ([`NearTip`]). Boxes are drawn around the light, across
        /// the sides, the near plane (the light inside a box, or beside it within the near
        /// distance) and the far plane.
        #[test]
        fn cube_face_closed_forms_match_the_cut(
            face in 0usize..6,
            lo in prop::array::uniform3(-12.0f64..12.0),
            size in prop::array::uniform3(0.0f64..10.0),
            scale in prop::sample::select(vec![1.0, 1e-3, 1e-6]),
            range in prop::sample::select(vec![5.0, 20.0, 1e3]),
            resolution in prop::sample::select(vec![16u32, 1024]),
        ) {
            use crate::light::{CubeFace, PointLight};
            let lo = DVec3::from_array(lo) * scale;
            let aabb = Aabb::new(lo, lo + DVec3::from_array(size) * scale).unwrap();
            let point = PointLight::new(DVec3::ZERO, range).unwrap();
            let spot = point.face_light(CubeFace::ALL[face], resolution);
            let frame = LightFrame::fixed(spot.direction());
            let projector = Projector::Point { frame, position: spot.position() };
            let t = spot.half_angle().tan();
            let axis = AxisFrustum::new(&frame, spot.position(), t, spot.near(), spot.range()).unwrap();
            let planes = spot.frustum_planes(frame.up);
            // The cut keeps points within a round-off of the planes (as the setups' tolerance
            // does): a flat box's vertices on a side plane come out a rounding off its face.
            let tol = 1e-12 * aabb.min().abs().max(aabb.max().abs()).max_element();
            let mut cut = Vec::new();
            let kept = box_cut_vertices(&aabb, &planes, all_planes(6), tol, &mut cut);
            let closed = axis.box_extents(&aabb);
            let scale = range.max(1.0);
            if kept {
                let mut slow = Extents::EMPTY;
                for p in &cut {
                    slow.add(projector.project(*p));
                }
                // A part thinner than round-off may come out empty in one and not the other.
                if !closed.is_empty() {
                    prop_assert!(close(&closed, &slow, 1e-9 * scale), "{closed:?} vs cut {slow:?}");
                } else {
                    prop_assert!((slow.max - slow.min).max_element() <= 1e-9 * scale, "{slow:?}");
                }
            } else {
                prop_assert!(closed.is_empty() || (closed.max - closed.min).max_element() <= 1e-9 * scale, "{closed:?}");
            }
            let scene = SceneBounds::new(vec![aabb], vec![aabb], None).unwrap();
            let mask = straddled(aabb.center(), aabb.half_extents(), &planes, all_planes(6), tol);
            if let Some(mask) = mask.filter(|m| m & 1 != 0) {
                let by_cut = NearTip::new(&scene, &planes, tol).clips(&aabb, mask, tol);
                prop_assert_eq!(axis.clips_tip(&aabb), by_cut);
            }
        }

        /// The allocation-free cut agrees with the general polyhedron clipper.
        #[test]
        fn box_cut_matches_polyhedron_clipping(
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..8.0),
            planes in prop::collection::vec((prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-10.0f64..10.0)), 1..12),
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
