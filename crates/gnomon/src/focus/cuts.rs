//! Boxes under a light's frame: images of whole boxes, and the vertices of the part of a box
//! that planes cut; a cube face's frustum.

use glam::DVec3;

use crate::boxes::{Aabb, BoxArrays};
use crate::bvh::grown;
use crate::geometry::Plane;

use crate::light_space::{AxisFrustum, Extents, LightFrame};

use super::classify::for_each_bit;

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
pub(super) const CUT_VERTICES: usize = 32;

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
pub(super) fn cut_by_one(aabb: &Aabb, plane: &Plane, tolerance: f64, out: &mut Vec<DVec3>) -> bool {
    let corners = aabb.corners();
    let dist = corners.map(|c| plane.distance(c));
    let inside = corner_bits(&dist, |d| d >= -tolerance);
    // An edge that crosses the plane has an end inside it, so nothing is left without one.
    if inside == 0 {
        return false;
    }
    // At most the eight corners and the box's twelve edges.
    out.reserve(20);
    for_each_bit(inside, |c| out.push(corners[c]));
    let crossing = crossing_edges(&dist);
    for (axis, edges) in crossing.into_iter().enumerate() {
        for_each_bit(edges, |a| {
            let b = a | 1 << axis;
            let (da, db) = (dist[a], dist[b]);
            out.push(corners[a] + (corners[b] - corners[a]) * (da / (da - db)));
        });
    }
    true
}

/// The corners (bit `c` for corner `c`) whose distances pass `test`.
#[inline(always)]
fn corner_bits(dist: &[f64; 8], test: impl Fn(f64) -> bool) -> u8 {
    dist.iter()
        .enumerate()
        .fold(0u8, |m, (c, d)| m | u8::from(test(*d)) << c)
}

/// The box's edges that cross a plane, from its corners' signed distances (corner `c` at
/// bit `c`, as [`Aabb::corners`] orders them): for each axis, bit `a` set where the edge from
/// corner `a` to corner `a` + that axis's bit has one end below 0 and the other not.
fn crossing_edges(dist: &[f64; 8]) -> [u8; 3] {
    let below = corner_bits(dist, |d| d < 0.0);
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
pub(super) fn box_around(arrays: &BoxArrays, ids: impl Iterator<Item = usize>) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in ids {
        let (c, h) = arrays.center_half(i);
        (lo, hi) = (lo.min(c - h), hi.max(c + h));
    }
    grown(lo, hi)
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
