//! The scene bounds a setup is computed from: caster and receiver boxes and their hierarchies.

use glam::DVec3;

use crate::boxes::{Aabb, BoxArrays};
use crate::bvh::BoxTree;
use crate::error::SetupError;

/// What a shadow setup knows of the scene: boxes around the objects that cast shadows,
/// boxes around the objects that receive them, and the scene box that encloses it all.
///
/// The scene box bounds the convex body B (LiSPSM paper, section 3.3). If the given scene
/// box does not enclose every caster and receiver box it is grown to do so, and
/// [`SceneBounds::scene_box_grown`] says so. A box that is flat along some axis is thickened
/// by a millionth of its diagonal so that B is never a flat body.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBounds {
    casters: Vec<Aabb>,
    receivers: Vec<Aabb>,
    scene_box: Aabb,
    scene_box_grown: bool,
    caster_arrays: BoxArrays,
    receiver_arrays: BoxArrays,
    caster_tree: BoxTree,
    receiver_tree: BoxTree,
}

impl SceneBounds {
    /// Scene bounds from caster boxes, receiver boxes and an optional scene box.
    ///
    /// Without a scene box, the union of all boxes is used. Errors with
    /// [`SetupError::EmptyScene`] when there is neither a scene box nor any box.
    pub fn new(
        casters: Vec<Aabb>,
        receivers: Vec<Aabb>,
        scene_box: Option<Aabb>,
    ) -> Result<Self, SetupError> {
        let mut scene = Self::without_trees(casters, receivers, scene_box)?;
        scene.caster_tree = BoxTree::new(&scene.caster_arrays);
        scene.receiver_tree = BoxTree::new(&scene.receiver_arrays);
        Ok(scene)
    }

    /// The bounds with empty hierarchies (the callers make them).
    fn without_trees(
        casters: Vec<Aabb>,
        receivers: Vec<Aabb>,
        scene_box: Option<Aabb>,
    ) -> Result<Self, SetupError> {
        let union = casters
            .iter()
            .chain(receivers.iter())
            .copied()
            .reduce(|a, b| a.union(&b));
        let (scene_box, grown) = match (scene_box, union) {
            (Some(s), Some(u)) => {
                let grown = !s.contains_box(&u);
                (s.union(&u), grown)
            }
            (Some(s), None) => (s, false),
            (None, Some(u)) => (u, false),
            (None, None) => return Err(SetupError::EmptyScene),
        };
        let size = scene_box.max() - scene_box.min();
        let thickness = 1e-6 * size.length();
        let pad = DVec3::select(
            size.cmplt(DVec3::splat(thickness)),
            DVec3::splat(thickness),
            DVec3::ZERO,
        );
        Ok(Self {
            caster_arrays: BoxArrays::new(&casters),
            receiver_arrays: BoxArrays::new(&receivers),
            caster_tree: BoxTree::default(),
            receiver_tree: BoxTree::default(),
            casters,
            receivers,
            scene_box: scene_box.grown(pad),
            scene_box_grown: grown,
        })
    }

    /// Boxes around the shadow casters.
    pub fn casters(&self) -> &[Aabb] {
        &self.casters
    }

    /// Boxes around the shadow receivers.
    pub fn receivers(&self) -> &[Aabb] {
        &self.receivers
    }

    /// The scene box: the given one, grown to hold every box and thickened if flat.
    pub fn scene_box(&self) -> Aabb {
        self.scene_box
    }

    /// Whether the given scene box had to grow to hold every caster and receiver box.
    pub fn scene_box_grown(&self) -> bool {
        self.scene_box_grown
    }

    pub(crate) fn caster_arrays(&self) -> &BoxArrays {
        &self.caster_arrays
    }

    pub(crate) fn receiver_arrays(&self) -> &BoxArrays {
        &self.receiver_arrays
    }

    pub(crate) fn caster_tree(&self) -> &BoxTree {
        &self.caster_tree
    }

    pub(crate) fn receiver_tree(&self) -> &BoxTree {
        &self.receiver_tree
    }

    /// The same scene with its boxes moved (an animated scene's next frame): `casters` and
    /// `receivers` hold as many boxes as before, in the same order. The hierarchies over
    /// them are refitted rather than built again (each node's box recomputed from its
    /// children), which costs one pass over the boxes; the scene box is the given one grown
    /// to hold every box, as in [`SceneBounds::new`].
    ///
    /// Errors: [`SetupError::BoxCountChanged`] when a count differs (build new bounds with
    /// [`SceneBounds::new`] then), [`SetupError::EmptyScene`] as in `new`.
    pub fn with_boxes_moved(
        &self,
        casters: Vec<Aabb>,
        receivers: Vec<Aabb>,
        scene_box: Option<Aabb>,
    ) -> Result<Self, SetupError> {
        if casters.len() != self.casters.len() || receivers.len() != self.receivers.len() {
            return Err(SetupError::BoxCountChanged {
                casters: (self.casters.len(), casters.len()),
                receivers: (self.receivers.len(), receivers.len()),
            });
        }
        let (mut caster_tree, mut receiver_tree) =
            (self.caster_tree.clone(), self.receiver_tree.clone());
        let mut moved = Self::without_trees(casters, receivers, scene_box)?;
        caster_tree.refit(&moved.caster_arrays);
        receiver_tree.refit(&moved.receiver_arrays);
        moved.caster_tree = caster_tree;
        moved.receiver_tree = receiver_tree;
        Ok(moved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_boxes() {
        assert!(matches!(
            Aabb::new(DVec3::ONE, DVec3::ZERO),
            Err(SetupError::InvertedBox { .. })
        ));
        assert!(matches!(
            Aabb::new(DVec3::ONE, DVec3::ONE),
            Err(SetupError::EmptyBox { .. })
        ));
        assert!(matches!(
            Aabb::new(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ONE),
            Err(SetupError::NonFinite { .. })
        ));
        assert!(matches!(
            Aabb::new(DVec3::ZERO, DVec3::new(f64::INFINITY, 1.0, 1.0)),
            Err(SetupError::NonFinite { .. })
        ));
        // A flat box is a valid receiver (a ground quad).
        assert!(Aabb::new(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0)).is_ok());
    }

    #[test]
    fn scene_box_grows_and_thickens() {
        let ground = Aabb::new(DVec3::new(-10.0, 0.0, -10.0), DVec3::new(10.0, 0.0, 10.0)).unwrap();
        let post = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 5.0, 1.0)).unwrap();
        let small = Aabb::new(DVec3::ZERO, DVec3::ONE).unwrap();
        let scene = SceneBounds::new(vec![post], vec![ground], Some(small)).unwrap();
        assert!(scene.scene_box_grown());
        assert!(scene.scene_box().contains_box(&ground));
        assert!(scene.scene_box().contains_box(&post));
        let flat = SceneBounds::new(vec![], vec![ground], None).unwrap();
        assert!(!flat.scene_box_grown());
        assert!(flat.scene_box().max().y > 0.0 && flat.scene_box().min().y < 0.0);
        assert_eq!(
            SceneBounds::new(vec![], vec![], None),
            Err(SetupError::EmptyScene)
        );
    }

    /// Moved boxes give the setups that bounds built anew on them give, and a changed
    /// count is refused.
    #[test]
    fn moved_boxes_refit_the_hierarchies() {
        use crate::camera::{Camera, Lens};
        use crate::light::{DirectionalLight, Light};
        use crate::map::MapSettings;
        use crate::setup::{Technique, compute_setup};
        let grid = |shift: f64| -> Vec<Aabb> {
            (0..400)
                .map(|k| {
                    let (i, j) = ((k % 20) as f64, (k / 20) as f64);
                    // Every third box moves along x and up.
                    let d = if k % 3 == 0 { shift } else { 0.0 };
                    let lo = DVec3::new(-50.0 + 5.0 * i + d, d, -50.0 + 5.0 * j);
                    Aabb::new(lo, lo + DVec3::new(2.0, 3.0 + (k % 7) as f64, 2.0)).unwrap()
                })
                .collect()
        };
        let ground =
            Aabb::new(DVec3::new(-60.0, -1.0, -60.0), DVec3::new(60.0, 0.0, 60.0)).unwrap();
        let with_ground = |mut v: Vec<Aabb>| {
            v.push(ground);
            v
        };
        let before = SceneBounds::new(grid(0.0), with_ground(grid(0.0)), None).unwrap();
        let camera = Camera::look_at(
            DVec3::new(-40.0, 20.0, 50.0),
            DVec3::new(10.0, 0.0, -10.0),
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let light = Light::Directional(DirectionalLight::new(DVec3::new(0.4, -1.0, -0.2)).unwrap());
        for shift in [0.5, 7.0, 40.0] {
            let moved = before
                .with_boxes_moved(grid(shift), with_ground(grid(shift)), None)
                .unwrap();
            let fresh = SceneBounds::new(grid(shift), with_ground(grid(shift)), None).unwrap();
            assert_eq!(moved.scene_box(), fresh.scene_box());
            for name in ["focused", "lispsm", "cascades", "sppsm"] {
                let technique: Technique = name.parse().unwrap();
                let a = compute_setup(&technique, &camera, &light, &moved, MapSettings::default())
                    .unwrap();
                let b = compute_setup(&technique, &camera, &light, &fresh, MapSettings::default())
                    .unwrap();
                for (ma, mb) in a.maps.iter().zip(&b.maps) {
                    assert!(
                        ma.clip_from_world.abs_diff_eq(mb.clip_from_world, 1e-9),
                        "{name} at {shift}"
                    );
                }
                // The count depends on the hierarchy's shape (see `relevant_casters`).
                assert_eq!(
                    a.diagnostics.relevant_casters > 0,
                    b.diagnostics.relevant_casters > 0
                );
            }
        }
        assert!(matches!(
            before.with_boxes_moved(grid(1.0), grid(1.0), None),
            Err(SetupError::BoxCountChanged { .. })
        ));
    }
}
