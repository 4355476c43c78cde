//! Exact shadows: stenciled shadow volumes (the shadows lecture's "Shadow Volumes" slides;
//! Crow 1977, Heidmann 1991, z-fail after
//! Carmack and Everitt and Kilgard 2002).
//!
//! [`MeshTopology`] welds a mesh's vertices and builds its edge-to-triangle adjacency,
//! checking that it is a closed 2-manifold with consistent winding; [`extrude_volume`] turns
//! it, for one light, into the volume's triangles in homogeneous world coordinates: the
//! light-facing triangles (light cap), the back-facing ones sent to infinity (dark cap) and
//! the quads of the possible silhouette edges extruded to infinity with w = 0. The renderer
//! counts them in the stencil buffer under [`infinite_clip_from_view`], which never clips a
//! point at infinity. [`NearClipVolume`] tells which casters' volumes can reach the near
//! plane (z-fail) and which cannot (z-pass, without caps).

mod extrusion;
mod near_clip;
mod topology;

pub use extrusion::{
    VolumeCounts, VolumeParts, extrude_volume, infinite_clip_from_view,
    reversed_infinite_clip_from_view,
};
pub use near_clip::{NearClipFallback, NearClipVolume};
pub use topology::{MeshError, MeshTopology, OpenMeshPolicy};
