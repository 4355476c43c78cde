//! Geometry the setups are built from: planes, convex polyhedra clipped by planes, 2D convex
//! hulls.

mod hull2d;
mod plane;
mod polyhedron;

pub use hull2d::convex_hull_2d;
pub use plane::Plane;
pub use polyhedron::ConvexPolyhedron;
