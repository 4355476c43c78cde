//! Built-in scenes for gnomon: object layouts (shape, placement, caster and receiver flags)
//! and the world bounds that feed the core crate's shadow setup.
//!
//! The layouts carry no triangles: the renderer generates each shape's mesh from its
//! [`Shape`] and `world_from_object` transform, so the bounds here and the geometry there
//! describe the same objects. [`Mesh::load`] reads real meshes from OFF, OBJ, PLY, STL and
//! glTF 2.0 (`.gltf`, `.glb`) files; [`SceneFile`] reads a TOML scene of mesh files, a ground
//! slab and [`NamedView`]s.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod city;
mod demo;
mod format;
#[cfg(feature = "gltf")]
mod gltf;
mod load;
mod mesh;
mod readers;
mod scene_file;
#[cfg(feature = "scene-file")]
mod scene_toml;
mod terragen;
mod view;

use glam::{DMat4, DVec3};
use gnomon::{Aabb, SceneBounds, SetupError};

pub use city::{CITY_SIDE, city, city_views};
pub use demo::{DEMO_VIEWS, DemoLight, DemoView, GROUND_HALF_SIZE, demo, demo_views};
pub use format::{LoadError, MAX_MESH_BYTES, MeshFormat};
pub use load::{CREASE_DEGREES, MeshPart};
pub use mesh::{Cutout, Mesh, Wrap, obj_text};
pub use scene_file::{FileObject, MAX_SCENE_FILE_BYTES, SceneFile, SceneFileError};
pub use view::{NamedView, ViewLight, mesh_views};

/// The shape of an object, in its own space (centred on the origin unless said otherwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// An axis-aligned box with these half extents.
    Cuboid {
        /// Half the size along each axis.
        half_extents: DVec3,
    },
    /// A sphere.
    Sphere {
        /// Its radius.
        radius: f64,
    },
    /// A torus around the object's Y axis.
    Torus {
        /// Distance from the centre to the middle of the tube.
        major_radius: f64,
        /// The tube's radius.
        minor_radius: f64,
    },
    /// A (p, q) torus knot around the object's Y axis: the curve winds p times around the
    /// axis and q times through the hole, at distance `major_radius + minor_radius cos(q t)`
    /// from the axis; `tube_radius` is the thickness of the tube around the curve.
    TorusKnot {
        /// Windings around the axis.
        p: u32,
        /// Windings through the hole.
        q: u32,
        /// Radius of the torus the knot lies on.
        major_radius: f64,
        /// Radius of the knot's excursion around that torus's core circle.
        minor_radius: f64,
        /// Radius of the tube around the curve.
        tube_radius: f64,
    },
    /// A vertical cylinder standing on the origin (from y = 0 to y = height).
    Pole {
        /// Its radius.
        radius: f64,
        /// Its height.
        height: f64,
    },
}

impl Shape {
    /// The shape's bounds in its own space.
    pub fn local_bounds(&self) -> (DVec3, DVec3) {
        match *self {
            Shape::Cuboid { half_extents } => (-half_extents, half_extents),
            Shape::Sphere { radius } => (DVec3::splat(-radius), DVec3::splat(radius)),
            Shape::Torus {
                major_radius,
                minor_radius,
            } => {
                let h = DVec3::new(
                    major_radius + minor_radius,
                    minor_radius,
                    major_radius + minor_radius,
                );
                (-h, h)
            }
            Shape::TorusKnot {
                major_radius,
                minor_radius,
                tube_radius,
                ..
            } => {
                let r = major_radius + minor_radius + tube_radius;
                let h = DVec3::new(r, minor_radius + tube_radius, r);
                (-h, h)
            }
            Shape::Pole { radius, height } => (
                DVec3::new(-radius, 0.0, -radius),
                DVec3::new(radius, height, radius),
            ),
        }
    }

    /// A short name for listings.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Cuboid { .. } => "cuboid",
            Shape::Sphere { .. } => "sphere",
            Shape::Torus { .. } => "torus",
            Shape::TorusKnot { .. } => "torus_knot",
            Shape::Pole { .. } => "pole",
        }
    }
}

/// One object of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    /// A name for listings and error messages.
    pub name: String,
    /// Its shape in object space.
    pub shape: Shape,
    /// Object to world (rotation and translation).
    pub world_from_object: DMat4,
    /// Whether it casts shadows (is drawn into shadow maps).
    pub casts: bool,
    /// Whether it receives shadows.
    pub receives: bool,
}

impl SceneObject {
    /// The object's world-space bounds: its local box's corners transformed.
    pub fn world_bounds(&self) -> Result<Aabb, SetupError> {
        let (lo, hi) = self.shape.local_bounds();
        let local = Aabb::new(lo, hi)?;
        let mut min = DVec3::INFINITY;
        let mut max = DVec3::NEG_INFINITY;
        for c in local.corners() {
            let p = self.world_from_object.transform_point3(c);
            min = min.min(p);
            max = max.max(p);
        }
        Aabb::new(min, max)
    }
}

/// A named layout of objects.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneLayout {
    /// The scene's name.
    pub name: String,
    /// Its objects.
    pub objects: Vec<SceneObject>,
}

impl SceneLayout {
    /// The bounds the core's setup needs: caster boxes, receiver boxes, and the union as the
    /// scene box.
    pub fn bounds(&self) -> Result<SceneBounds, SetupError> {
        let mut casters = Vec::new();
        let mut receivers = Vec::new();
        for object in &self.objects {
            let b = object.world_bounds()?;
            if object.casts {
                casters.push(b);
            }
            if object.receives {
                receivers.push(b);
            }
        }
        SceneBounds::new(casters, receivers, None)
    }
}

/// The names [`by_name`] knows.
pub const SCENE_NAMES: &[&str] = &["demo", "city"];

/// A built-in scene's named views by name (empty for an unknown name).
pub fn views_by_name(name: &str) -> Vec<NamedView> {
    match name {
        "demo" => demo_views(),
        "city" => city_views(),
        _ => Vec::new(),
    }
}

/// A built-in scene by name.
pub fn by_name(name: &str) -> Option<SceneLayout> {
    match name {
        "demo" => Some(demo()),
        "city" => Some(city()),
        _ => None,
    }
}
