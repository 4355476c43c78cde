//! A bounding volume hierarchy over a scene's boxes (one for the casters, one for the
//! receivers), built once with the [`crate::SceneBounds`] and refitted when boxes move, so that
//! a frame's work grows with what it sees and with the borders of its regions, not with the
//! number of objects.
//!
//! A node's box holds the boxes of its subtree, so a test that fails or passes for the node
//! fails or passes for all of them: a node wholly outside a plane has every box outside, one
//! wholly inside has every box inside, and a node's extents under a light's projector hold
//! every box's. Traversals use this twice: classification stops at the nodes that lie wholly
//! inside or outside (only boxes near a plane are tested one by one), and extents stop at the
//! nodes whose image lies inside what has been gathered so far (see `focus/casters.rs`).

use glam::{DVec3, DVec4};

use crate::boxes::{Aabb, BoxArrays};
use crate::geometry::Plane;

/// Boxes per leaf at most.
const LEAF_SIZE: usize = 4;

/// The hierarchy: nodes in an array (a parent before its children, the two children of a
/// node side by side), each covering a contiguous range of `order`.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct BoxTree {
    /// Node boxes as centres and half extents (node i at index i), grown by a few ulps so
    /// that every box of the subtree lies inside after rounding.
    pub nodes: BoxArrays,
    /// The first of an inner node's two children; 0 for a leaf (the root is never a child).
    left: Vec<u32>,
    /// Where a node's boxes start in `order`, and how many it holds.
    start: Vec<u32>,
    size: Vec<u32>,
    /// Box indices, ordered so that every node's boxes are contiguous.
    order: Vec<u32>,
}

impl BoxTree {
    /// The hierarchy over `boxes`: each node split at the middle of its boxes' centres'
    /// bounds along their longest side.
    pub fn new(boxes: &BoxArrays) -> Self {
        let n = boxes.len();
        let mut tree = Self {
            order: (0..n as u32).collect(),
            ..Self::default()
        };
        if n == 0 {
            return tree;
        }
        tree.push_node(0, n);
        // The centres, permuted with `order` (so that a node's are contiguous in memory).
        let mut centers: Vec<DVec3> = (0..n).map(|i| boxes.center_of(i)).collect();
        let mut stack = vec![0usize];
        while let Some(node) = stack.pop() {
            let (start, size) = (tree.start[node] as usize, tree.size[node] as usize);
            if size <= LEAF_SIZE {
                continue;
            }
            let range = &mut tree.order[start..start + size];
            let cents = &mut centers[start..start + size];
            let (lo, hi) = cents
                .iter()
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), c| {
                    (lo.min(*c), hi.max(*c))
                });
            // Split at the middle of the centres' bounds along their longest side (a
            // partition, no sort); where that leaves a side empty (every centre in one
            // place), in two halves by count.
            let axis = (hi - lo).max_position();
            let middle = 0.5 * (lo[axis] + hi[axis]);
            let mut mid = 0;
            for k in 0..size {
                if cents[k][axis] < middle {
                    range.swap(k, mid);
                    cents.swap(k, mid);
                    mid += 1;
                }
            }
            if mid == 0 || mid == size {
                mid = size / 2;
            }
            let left = tree.left.len();
            tree.left[node] = left as u32;
            tree.push_node(start, mid);
            tree.push_node(start + mid, size - mid);
            stack.extend([left, left + 1]);
        }
        tree.refit(boxes);
        tree
    }

    fn push_node(&mut self, start: usize, size: usize) {
        self.left.push(0);
        self.start.push(start as u32);
        self.size.push(size as u32);
        self.nodes.push(DVec3::ZERO, DVec3::ZERO);
    }

    /// Recomputes every node's box from `boxes` (the same number of boxes the tree was built
    /// on, moved): children first, then their parents. The tree's shape is kept; a scene
    /// whose boxes moved far apart is still correct, only slower to traverse.
    pub fn refit(&mut self, boxes: &BoxArrays) {
        let count = self.left.len();
        let mut lo = vec![DVec3::ZERO; count];
        let mut hi = vec![DVec3::ZERO; count];
        for node in (0..count).rev() {
            let (a, b) = if self.is_leaf(node) {
                self.boxes_of(node).iter().fold(
                    (DVec3::INFINITY, DVec3::NEG_INFINITY),
                    |(a, b), &i| {
                        let (c, h) = (boxes.center_of(i as usize), boxes.half_of(i as usize));
                        (a.min(c - h), b.max(c + h))
                    },
                )
            } else {
                let l = self.left[node] as usize;
                (lo[l].min(lo[l + 1]), hi[l].max(hi[l + 1]))
            };
            lo[node] = a;
            hi[node] = b;
            let (c, h) = grown(a, b);
            self.nodes.set(node, c, h);
        }
    }

    /// Whether the tree has no node (no boxes).
    pub fn is_empty(&self) -> bool {
        self.left.is_empty()
    }

    /// Whether `node` is a leaf.
    #[inline]
    pub fn is_leaf(&self, node: usize) -> bool {
        self.left[node] == 0
    }

    /// An inner node's two children.
    #[inline]
    pub fn children(&self, node: usize) -> [usize; 2] {
        let l = self.left[node] as usize;
        [l, l + 1]
    }

    /// The indices of the boxes under `node`.
    #[inline]
    pub fn boxes_of(&self, node: usize) -> &[u32] {
        let start = self.start[node] as usize;
        &self.order[start..start + self.size[node] as usize]
    }

    /// How many boxes lie under `node`.
    #[inline]
    pub fn size(&self, node: usize) -> usize {
        self.size[node] as usize
    }

    /// Node `node`'s box.
    pub fn node_box(&self, node: usize) -> Aabb {
        let (c, h) = (self.nodes.center_of(node), self.nodes.half_of(node));
        Aabb::from_min_max_unchecked(c - h, c + h)
    }

    /// Classifies the subtrees `roots` (each with the bits of the planes still to test: its
    /// boxes lie inside the others) against `planes`, as [`crate::focus::classify_box`] does
    /// one box. Subtrees wholly inside all planes go to `out.nodes`, boxes of a leaf that lie
    /// wholly inside to `out.boxes`, and boxes that cross some planes to `out.cut` with the
    /// mask of those planes. What lies wholly outside one plane is dropped.
    pub fn classify(
        &self,
        boxes: &BoxArrays,
        planes: &[Plane],
        tolerance: f64,
        roots: impl IntoIterator<Item = (usize, u32)>,
        out: &mut Classified,
    ) {
        // Deep enough for a walk down a balanced hierarchy of 10^5 boxes without growing.
        let mut stack: Vec<(usize, u32)> = Vec::with_capacity(64);
        stack.extend(roots);
        out.nodes.reserve(32);
        out.boxes.reserve(64);
        out.cut.reserve(64);
        let planes = BoxPlanes::new(planes);
        while let Some((node, active)) = stack.pop() {
            let (c, h) = self.nodes.center_half(node);
            let Some(mask) = planes.straddled(c, h, active, tolerance) else {
                continue;
            };
            if mask == 0 {
                out.nodes.push(node as u32);
            } else if self.is_leaf(node) {
                for &i in self.boxes_of(node) {
                    let (c, h) = boxes.center_half(i as usize);
                    match planes.straddled(c, h, mask, tolerance) {
                        None => {}
                        Some(0) => out.boxes.push(i),
                        Some(cut) => out.cut.push((i, cut)),
                    }
                }
            } else {
                for child in self.children(node) {
                    stack.push((child, mask));
                }
            }
        }
    }
}

/// Where a box lies against planes (a, b, c, d) that it must reach: `None` when wholly on
/// the negative side of one, else the bits of those among `active` it crosses.
#[inline]
fn reaches(c: DVec3, h: DVec3, planes: &[DVec4], active: u32) -> Option<u32> {
    let mut mask = 0u32;
    let mut bits = active;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let n = planes[k].truncate();
        let (s, r) = (n.dot(c) + planes[k].w, n.abs().dot(h));
        if s + r < 0.0 {
            return None;
        }
        if s - r < 0.0 {
            mask |= 1 << k;
        }
    }
    Some(mask)
}

impl BoxTree {
    /// Appends to `out` the boxes that reach the positive side of every plane (some point
    /// with a x + b y + c z + d >= 0), up to 32 planes. A subtree wholly on the positive side
    /// of all is taken whole; one wholly on the negative side of one is dropped.
    pub fn reaching(&self, boxes: &BoxArrays, planes: &[DVec4], out: &mut Vec<u32>) {
        if self.is_empty() {
            return;
        }
        let mut stack = vec![(0usize, all_planes(planes.len().min(32)))];
        while let Some((node, active)) = stack.pop() {
            let Some(mask) = reaches(
                self.nodes.center_of(node),
                self.nodes.half_of(node),
                planes,
                active,
            ) else {
                continue;
            };
            if mask == 0 {
                out.extend_from_slice(self.boxes_of(node));
            } else if self.is_leaf(node) {
                for &i in self.boxes_of(node) {
                    let (c, h) = (boxes.center_of(i as usize), boxes.half_of(i as usize));
                    if reaches(c, h, planes, mask).is_some() {
                        out.push(i);
                    }
                }
            } else {
                for child in self.children(node) {
                    stack.push((child, mask));
                }
            }
        }
    }
}

/// A bounding volume hierarchy over boxes, for culling many of them against a few planes
/// (gnomon's renderer culls each shadow map's casters with one; an engine can do the same):
/// built once, refitted when the boxes move.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BoxIndex {
    tree: BoxTree,
    arrays: BoxArrays,
}

impl BoxIndex {
    /// The index over `boxes` (their order gives their indices).
    pub fn new(boxes: &[Aabb]) -> Self {
        let arrays = BoxArrays::new(boxes);
        Self {
            tree: BoxTree::new(&arrays),
            arrays,
        }
    }

    /// How many boxes.
    pub fn len(&self) -> usize {
        self.arrays.len()
    }

    /// Whether there is no box.
    pub fn is_empty(&self) -> bool {
        self.arrays.len() == 0
    }

    /// The same boxes moved: the hierarchy keeps its shape and its nodes are recomputed (one
    /// pass over the boxes). A different number of boxes builds it anew.
    pub fn refit(&mut self, boxes: &[Aabb]) {
        if boxes.len() != self.len() {
            *self = Self::new(boxes);
            return;
        }
        self.arrays = BoxArrays::new(boxes);
        self.tree.refit(&self.arrays);
    }

    /// The indices of the boxes that reach the positive side of every plane `(a, b, c, d)`
    /// (some point with `a x + b y + c z + d >= 0`; up to 32 planes), in increasing order,
    /// appended to `out`.
    pub fn reaching(&self, planes: &[DVec4], out: &mut Vec<u32>) {
        let start = out.len();
        self.tree.reaching(&self.arrays, planes, out);
        out[start..].sort_unstable();
    }
}

/// The planes among `active` that the box (centre `c`, half extents `h`) crosses, or `None`
/// when it lies wholly outside one of them (the tests of [`crate::focus::classify_box`]).
#[inline]
pub(crate) fn straddled(
    c: DVec3,
    h: DVec3,
    planes: &[Plane],
    active: u32,
    tolerance: f64,
) -> Option<u32> {
    straddled_by(c, h, active, tolerance, |k| {
        let plane = &planes[k];
        (plane.normal, plane.normal.abs(), plane.offset)
    })
}

/// [`straddled`] with plane `k` given as (normal, |normal|, offset).
#[inline]
fn straddled_by(
    c: DVec3,
    h: DVec3,
    active: u32,
    tolerance: f64,
    plane: impl Fn(usize) -> (DVec3, DVec3, f64),
) -> Option<u32> {
    let mut mask = 0u32;
    let mut bits = active;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let (normal, abs_normal, offset) = plane(k);
        let r = abs_normal.dot(h);
        let s = normal.dot(c) + offset;
        if s + r <= tolerance {
            return None;
        }
        if s - r < -tolerance {
            mask |= 1 << k;
        }
    }
    Some(mask)
}

/// Planes ready for [`straddled`]'s test of many boxes: each normal with its absolute value
/// (a box's reach across the plane is |n| . h), made once per walk.
pub(crate) struct BoxPlanes {
    /// Room for the 32 planes a mask can name, so that a plane is read by its bit's index
    /// without a bounds check (and the planes need no allocation).
    planes: [(DVec3, DVec3, f64); 32],
}

impl BoxPlanes {
    /// The first 32 of `planes` (a mask names no more).
    pub fn new(planes: &[Plane]) -> Self {
        let mut out = [(DVec3::ZERO, DVec3::ZERO, 0.0); 32];
        for (slot, p) in out.iter_mut().zip(planes) {
            *slot = (p.normal, p.normal.abs(), p.offset);
        }
        Self { planes: out }
    }

    /// [`straddled`] against these planes.
    #[inline]
    pub fn straddled(&self, c: DVec3, h: DVec3, active: u32, tolerance: f64) -> Option<u32> {
        straddled_by(c, h, active, tolerance, |k| self.planes[k & 31])
    }
}

/// The box from `lo` to `hi` as centre and half extents, a few ulps larger, so that c +- h
/// holds `lo` and `hi` (and every box inside them) after rounding: a node's box, or any box
/// a walk tests in place of the boxes inside it.
pub(crate) fn grown(lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
    let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    (c, h + (c.abs() + h) * (4.0 * f64::EPSILON))
}

/// The bits of planes `0..count`.
pub(crate) fn all_planes(count: usize) -> u32 {
    if count >= 32 {
        u32::MAX
    } else {
        (1u32 << count) - 1
    }
}

/// Boxes of a tree against a set of planes: what [`BoxTree::classify`] gives.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Classified {
    /// Subtrees wholly inside every plane.
    pub nodes: Vec<u32>,
    /// Boxes wholly inside every plane (outside those subtrees).
    pub boxes: Vec<u32>,
    /// Boxes that cross some planes, with the mask of those planes, in the walk's order.
    pub cut: Vec<(u32, u32)>,
}

/// Random scenes for the tests that compare the hierarchies' walks with a pass over every box.
#[cfg(test)]
pub(crate) mod test_scenes {
    use glam::DVec3;

    use crate::bounds::SceneBounds;
    use crate::boxes::Aabb;
    use crate::camera::{Camera, Lens};

    /// Boxes (corner, size, kind: 0 casts, 1 receives, 2 both) above a ground that receives.
    pub fn mixed(boxes: &[([f64; 3], [f64; 3], u8)]) -> SceneBounds {
        let (mut casters, mut receivers) = (Vec::new(), Vec::new());
        for (lo, size, kind) in boxes {
            let lo = DVec3::from_array(*lo).with_y(lo[1].abs() * 0.3);
            let b = Aabb::new(lo, lo + DVec3::from_array(*size)).unwrap();
            if *kind != 1 {
                casters.push(b);
            }
            if *kind != 0 {
                receivers.push(b);
            }
        }
        let ground = Aabb::new(DVec3::new(-70.0, -1.0, -70.0), DVec3::new(70.0, 0.0, 70.0));
        receivers.push(ground.unwrap());
        SceneBounds::new(casters, receivers, None).unwrap()
    }

    /// A camera from `eye` to `target` (near 0.5, far 120), unless they nearly coincide or
    /// the view is nearly vertical.
    pub fn camera(eye: [f64; 3], target: [f64; 3]) -> Option<Camera> {
        let (eye, target) = (DVec3::from_array(eye), DVec3::from_array(target));
        if eye.distance(target) <= 1.0 || (target - eye).normalize().y.abs() >= 0.99 {
            return None;
        }
        let lens = Lens {
            near: 0.5,
            far: 120.0,
            ..Lens::default()
        };
        Camera::look_at(eye, target, DVec3::Y, lens).ok()
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::focus::{BoxSide, classify_box};

    fn arrays(boxes: &[Aabb]) -> BoxArrays {
        BoxArrays::new(boxes)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 500, failure_persistence: None, ..ProptestConfig::default() })]

        /// The index finds the boxes a pass over every box finds, before and after a refit.
        #[test]
        fn the_index_reaches_what_every_box_reaches(
            boxes in prop::collection::vec((prop::array::uniform3(-50.0f64..50.0), prop::array::uniform3(0.0f64..20.0)), 0..200),
            planes in prop::collection::vec(prop::array::uniform4(-1.0f64..1.0), 0..6),
            shift in prop::array::uniform3(-20.0f64..20.0),
        ) {
            let mut boxes: Vec<Aabb> = boxes.iter().filter_map(|(lo, size)| {
                let lo = DVec3::from_array(*lo);
                Aabb::new(lo, lo + DVec3::from_array(*size)).ok()
            }).collect();
            let planes: Vec<DVec4> = planes.iter().map(|p| DVec4::from_array(*p) * DVec4::new(1.0, 1.0, 1.0, 30.0)).collect();
            let mut index = BoxIndex::new(&boxes);
            for round in 0..2 {
                if round == 1 {
                    for b in boxes.iter_mut().step_by(3) {
                        let d = DVec3::from_array(shift);
                        *b = Aabb::new(b.min() + d, b.max() + d).unwrap();
                    }
                    index.refit(&boxes);
                }
                let mut got = Vec::new();
                index.reaching(&planes, &mut got);
                let want: Vec<u32> = (0..boxes.len() as u32).filter(|&i| {
                    let b = &boxes[i as usize];
                    planes.iter().all(|p| {
                        let n = p.truncate();
                        n.dot(b.center()) + p.w + n.abs().dot(b.half_extents()) >= 0.0
                    })
                }).collect();
                prop_assert_eq!(got, want);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 500, failure_persistence: None, ..ProptestConfig::default() })]

        /// The tree's classification gives every box the code the box gets alone, and its
        /// nodes hold their boxes, before and after a refit.
        #[test]
        fn tree_classification_matches_each_box(
            boxes in prop::collection::vec((prop::array::uniform3(-50.0f64..50.0), prop::array::uniform3(0.0f64..20.0)), 1..200),
            planes in prop::collection::vec((prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-30.0f64..30.0)), 1..8),
            shift in prop::array::uniform3(-20.0f64..20.0),
        ) {
            let mut boxes: Vec<Aabb> = boxes.iter().filter_map(|(lo, size)| {
                let lo = DVec3::from_array(*lo);
                Aabb::new(lo, lo + DVec3::from_array(*size)).ok()
            }).collect();
            prop_assume!(!boxes.is_empty());
            let planes: Vec<Plane> = planes.iter().filter_map(|(n, p)| {
                let n = DVec3::from_array(*n);
                (n.length() > 0.1).then(|| Plane::through_point(DVec3::from_array(*p), n.normalize()))
            }).collect();
            prop_assume!(!planes.is_empty());
            let mut tree = BoxTree::new(&arrays(&boxes));
            for round in 0..2 {
                if round == 1 {
                    // Every other box moves; the tree is refitted.
                    for (i, b) in boxes.iter_mut().enumerate() {
                        if i % 2 == 0 {
                            let d = DVec3::from_array(shift);
                            *b = Aabb::new(b.min() + d, b.max() + d).unwrap();
                        }
                    }
                    tree.refit(&arrays(&boxes));
                }
                let a = arrays(&boxes);
                for node in 0..tree.left.len() {
                    let nb = tree.node_box(node);
                    for &i in tree.boxes_of(node) {
                        prop_assert!(nb.contains_box(&boxes[i as usize]));
                    }
                }
                let mut out = Classified::default();
                tree.classify(&a, &planes, 1e-9, [(0, all_planes(planes.len()))], &mut out);
                let mut got = vec![None; boxes.len()];
                for &node in &out.nodes {
                    for &i in tree.boxes_of(node as usize) {
                        got[i as usize] = Some(0u32);
                    }
                }
                for &i in &out.boxes {
                    got[i as usize] = Some(0);
                }
                for &(i, mask) in &out.cut {
                    got[i as usize] = Some(mask);
                }
                for (i, b) in boxes.iter().enumerate() {
                    let want = match classify_box(b, &planes, 1e-9) {
                        BoxSide::Outside => None,
                        BoxSide::Inside => Some(0),
                        BoxSide::Straddles(mask) => Some(mask),
                    };
                    prop_assert_eq!(got[i], want, "box {}", i);
                }
            }
        }
    }
}
