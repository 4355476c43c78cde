//! The scene's bounds as gnomon sees them: the world boxes of the meshes that cast and
//! receive shadows, kept between frames.

use bevy_camera::primitives::Aabb as BevyAabb;
use bevy_ecs::entity::{Entity, EntityHashMap};
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use bevy_light::{NotShadowCaster, NotShadowReceiver};
use bevy_mesh::Mesh3d;
use bevy_transform::components::GlobalTransform;
use glam::DVec3;
use gnomon::{Aabb, SceneBounds};

/// The boxes gnomon fits to, one [`SceneBounds`] shared by every light and camera.
///
/// Rebuilt when a mesh entity is added or removed or changes its casting or receiving;
/// refitted (gnomon's `with_boxes_moved`, one pass over the boxes) when only transforms
/// or boxes changed.
#[derive(Resource, Default)]
pub struct GnomonScene {
    /// The bounds, `None` while no mesh casts or receives.
    pub bounds: Option<SceneBounds>,
    /// The mesh entities in order, with whether each casts and receives.
    entities: Vec<(Entity, Role)>,
    /// Each entity's place in `entities`.
    index: EntityHashMap<usize>,
    /// Each entity's world box, in the order of `entities`.
    boxes: Vec<Aabb>,
    /// How many times the bounds were built from scratch (a refit does not count).
    pub rebuilds: u64,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Role {
    casts: bool,
    receives: bool,
}

/// The mesh entities whose boxes matter.
type Meshes<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static BevyAabb,
        &'static GlobalTransform,
        Has<NotShadowCaster>,
        Has<NotShadowReceiver>,
    ),
    With<Mesh3d>,
>;

/// Entities whose box or transform changed since the last run.
type Moved<'w, 's> = Query<
    'w,
    's,
    (Entity, &'static BevyAabb, &'static GlobalTransform),
    (
        With<Mesh3d>,
        Or<(Changed<BevyAabb>, Changed<GlobalTransform>)>,
    ),
>;

/// Meshes, or their shadow roles, that came since the last run.
type Arrived = Or<(
    Added<BevyAabb>,
    Added<Mesh3d>,
    Added<NotShadowCaster>,
    Added<NotShadowReceiver>,
)>;

/// What makes the scene rebuild rather than refit: meshes or shadow roles that came or went.
#[derive(SystemParam)]
pub struct SceneChanges<'w, 's> {
    arrived: Query<'w, 's, (), (With<Mesh3d>, Arrived)>,
    removed_meshes: RemovedComponents<'w, 's, Mesh3d>,
    removed_casters: RemovedComponents<'w, 's, NotShadowCaster>,
    removed_receivers: RemovedComponents<'w, 's, NotShadowReceiver>,
}

impl SceneChanges<'_, '_> {
    /// Whether the set of boxes or their roles changed (reads every removal, so that none
    /// counts twice).
    fn rebuild(&mut self) -> bool {
        let removed = self.removed_meshes.read().count()
            + self.removed_casters.read().count()
            + self.removed_receivers.read().count();
        removed > 0 || !self.arrived.is_empty()
    }
}

/// Keeps [`GnomonScene`] in step with the mesh entities.
pub fn track_scene(
    mut scene: ResMut<GnomonScene>,
    meshes: Meshes,
    moved: Moved,
    mut changes: SceneChanges,
) {
    if changes.rebuild() {
        scene.rebuild(&meshes);
    } else if !moved.is_empty() {
        scene.refit(&moved);
    }
}

impl GnomonScene {
    fn rebuild(&mut self, meshes: &Meshes) {
        self.entities.clear();
        self.index.clear();
        self.boxes.clear();
        for (entity, aabb, transform, not_caster, not_receiver) in meshes {
            let role = Role {
                casts: !not_caster,
                receives: !not_receiver,
            };
            let Some(world_box) = world_box(aabb, transform) else {
                continue;
            };
            if role.casts || role.receives {
                self.index.insert(entity, self.entities.len());
                self.entities.push((entity, role));
                self.boxes.push(world_box);
            }
        }
        self.bounds = self.split(|casters, receivers| SceneBounds::new(casters, receivers, None));
        self.rebuilds += 1;
    }

    fn refit(&mut self, moved: &Moved) {
        for (entity, aabb, transform) in moved {
            if let (Some(&i), Some(b)) = (self.index.get(&entity), world_box(aabb, transform)) {
                self.boxes[i] = b;
            }
        }
        let Some(old) = self.bounds.take() else {
            return;
        };
        self.bounds =
            self.split(|casters, receivers| old.with_boxes_moved(casters, receivers, None));
    }

    /// The caster and receiver boxes in entity order, handed to `make`.
    fn split(
        &self,
        make: impl FnOnce(Vec<Aabb>, Vec<Aabb>) -> Result<SceneBounds, gnomon::SetupError>,
    ) -> Option<SceneBounds> {
        let pick = |keep: fn(&Role) -> bool| -> Vec<Aabb> {
            self.entities
                .iter()
                .zip(&self.boxes)
                .filter(|((_, role), _)| keep(role))
                .map(|(_, b)| *b)
                .collect()
        };
        make(pick(|r| r.casts), pick(|r| r.receives)).ok()
    }

    /// The number of mesh entities that cast or receive.
    pub fn len(&self) -> usize {
        self.entities.len()
    }

    /// Whether no mesh casts or receives.
    pub fn is_empty(&self) -> bool {
        self.entities.is_empty()
    }
}

/// The world box around a mesh's local box; `None` for non-finite transforms.
fn world_box(aabb: &BevyAabb, transform: &GlobalTransform) -> Option<Aabb> {
    let affine = transform.affine();
    let center = affine.transform_point3a(aabb.center);
    let m = affine.matrix3;
    let h = aabb.half_extents;
    // The box of a transformed box: each world half extent sums |m_ij| h_j.
    let half = m.x_axis.abs() * h.x + m.y_axis.abs() * h.y + m.z_axis.abs() * h.z;
    let to_d = |v: bevy_math::Vec3A| DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    Aabb::from_center_half_extents(to_d(center), to_d(half)).ok()
}
