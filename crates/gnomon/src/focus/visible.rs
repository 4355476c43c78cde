//! The visible scene: the receiver boxes and parts the camera sees, and their extents under
//! a map, walked once per frame and shared by every map of the setup.

use std::sync::OnceLock;

use glam::DVec3;

use crate::bounds::SceneBounds;
use crate::boxes::Aabb;
use crate::bvh::{BoxTree, Classified, all_planes, straddled};
use crate::geometry::{ConvexPolyhedron, Plane};

use crate::light_space::{Extents, Projector};

use super::cuts::{
    CUT_VERTICES, FaceFrustum, ParallelBoxes, box_around, box_cut_vertices, cut_by_one,
};

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

impl VisibleScene {
    /// The extents, under a cube face's own `projector`, of the visible receiver parts
    /// inside its `frustum`, straight from this scene (cut by the view's `view_planes`
    /// alone): the same as [`Self::receiver_extents`] of the scene cut by the frustum. A
    /// whole box's part, and a bound of a subtree's, is a closed form
    /// ([`crate::light_space::AxisFrustum::box_extents`]); a subtree whose bound adds nothing
    /// to the extents gathered so far is not opened. A part the view cuts, in front of the light's near
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
