//! Which boxes lie inside a set of planes (the view's frustum, its depth slices), as boxes,
//! as parts cut by the planes, or by a hierarchy's subtrees.

use glam::DVec3;

use crate::bounds::SceneBounds;
use crate::boxes::Aabb;
use crate::bvh::{BoxPlanes, Classified};
use crate::geometry::Plane;

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
pub(super) fn for_each_bit(mut bits: u8, mut f: impl FnMut(usize)) {
    while bits != 0 {
        f(bits.trailing_zeros() as usize);
        bits &= bits - 1;
    }
}
