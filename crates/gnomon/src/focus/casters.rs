//! The caster walks: which casters can shadow the visible receivers under a map, and the
//! extents they reach (unit cube clipping's near plane and x, y).

use glam::DVec3;

use crate::bounds::SceneBounds;
use crate::boxes::{Aabb, BoxArrays};
use crate::bvh::{all_planes, straddled};
use crate::geometry::Plane;

use crate::diagnostics::Diagnostics;
use crate::light_space::{Extents, Projector};
use crate::put_off::PutOff;

use super::cuts::{CUT_VERTICES, FaceFrustum, ParallelBoxes, box_cut_vertices};

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
                cut_node_outside: |_, _: &Extents| None,
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
    /// Whether node `n`, which cutting planes cross, lies wholly outside `over` (beside or
    /// behind the receivers: see [`outside`]), every part of its boxes, cut or not; `None`
    /// where the map cannot tell. A subtree outside is culled before it is opened, which keeps
    /// the walk to the boxes near the view when the cutting planes run across the whole scene.
    /// Only a cull can follow, so a map may answer with less work than the node's image.
    fn cut_node_outside(&self, n: usize, over: &Extents) -> Option<bool> {
        (Self::AFFINE || Self::EXACT).then(|| outside(&self.node(n), over))
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

/// A projective map given by its images of nodes, casters and points, and its test of
/// nodes that cutting planes cross ([`CasterImages::cut_node_outside`]).
pub(crate) struct MapImages<N, C, P, K> {
    pub node: N,
    pub caster: C,
    pub point: P,
    pub cut_node_outside: K,
}

impl<N, C, P, K> CasterImages for MapImages<N, C, P, K>
where
    N: Fn(usize) -> Extents,
    C: Fn(usize) -> Extents,
    P: Fn(DVec3) -> DVec3,
    K: Fn(usize, &Extents) -> Option<bool>,
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
    fn cut_node_outside(&self, n: usize, over: &Extents) -> Option<bool> {
        (self.cut_node_outside)(n, over)
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
    let (over, mut ext) = walk_bounds(receivers);
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
    loop {
        while let Some((node, active, open)) = stack.pop() {
            let Some(active) = cuts.crossed(&tree.nodes, node, active) else {
                continue;
            };
            if !open {
                match node_step(images, node, active, &ext, &over) {
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
                if outside(&box_ext, &over) {
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

/// A caster walk's bounds from the receivers' extents: what matters of a caster (its part
/// over the receivers' columns, grown by a slack for rounding, nearer than their far), and
/// the empty extents it gathers into. Their far depth is the receivers', since what lies
/// farther does not matter, so that a node's far side never keeps it open.
#[inline(always)]
fn walk_bounds(receivers: &Extents) -> (Extents, Extents) {
    let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
    let over = Extents {
        min: (receivers.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
        max: (receivers.max.truncate() + xy_slack).extend(receivers.max.z),
    };
    let gathered = Extents {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY.with_z(over.max.z),
    };
    (over, gathered)
}

/// Whether an image lies wholly outside what matters of a caster (`over`, see
/// [`walk_bounds`]): beside the receivers' columns or behind their far.
#[inline(always)]
fn outside(image: &Extents, over: &Extents) -> bool {
    !(over.min.x <= image.max.x
        && image.min.x <= over.max.x
        && over.min.y <= image.max.y
        && image.min.y <= over.max.y)
        || image.min.z > over.max.z
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

/// The step for node `n` (`active`: the cutting planes that cross it) against what is
/// gathered so far (`ext`) and what matters of a caster (`over`). A node that cutting planes
/// cross can only be culled whole, where the map tells that its boxes' parts all lie outside;
/// one that none crosses is culled, counted, put off or opened from its image, which holds
/// its boxes'.
#[inline(always)]
fn node_step<I: CasterImages>(
    images: &I,
    n: usize,
    active: u32,
    ext: &Extents,
    over: &Extents,
) -> NodeStep {
    if active != 0 {
        return match images.cut_node_outside(n, over) {
            Some(true) => NodeStep::Cull,
            _ => NodeStep::Open,
        };
    }
    let image = images.node(n);
    if outside(&image, over) {
        NodeStep::Cull
    } else if ext.contains(&image.clamped_to(over)) {
        NodeStep::Count
    } else if over.contains(&image) && image.min.z >= ext.min.z {
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
pub(super) fn points_image<I: CasterImages>(images: &I, points: &[DVec3]) -> Extents {
    let mut e = Extents::EMPTY;
    for p in points {
        e.add(images.point(*p));
    }
    e
}

/// A caster walk's images under a cube face's own projector. Each box's is the image of its
/// part inside the face's frustum ([`AxisFrustum::box_extents`]), so that the walk cuts no
/// box. It walks with the near plane alone as its cutting plane, which keeps the boxes that
/// cross it apart for [`AxisFrustum::clips_tip`].
///
/// [`AxisFrustum::box_extents`]: crate::light_space::AxisFrustum::box_extents
/// [`AxisFrustum::clips_tip`]: crate::light_space::AxisFrustum::clips_tip
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
