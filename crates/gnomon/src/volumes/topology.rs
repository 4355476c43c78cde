//! Welding and edge adjacency: what a mesh needs to bound shadow volumes.

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;

/// Why a mesh cannot bound shadow volumes.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    /// The index list's length is not a multiple of three.
    IndexCount {
        /// The length.
        count: usize,
    },
    /// A triangle names a vertex that does not exist.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The index.
        index: u32,
    },
    /// A vertex position is NaN or infinite.
    NonFinite {
        /// The vertex.
        vertex: usize,
    },
    /// An edge is used by one triangle only: the mesh has a hole or a border.
    OpenEdge {
        /// The edge's end points (welded positions).
        from: DVec3,
        /// See `from`.
        to: DVec3,
    },
    /// An edge is used twice in the same direction: more than two triangles meet there, or
    /// neighbouring triangles are wound inconsistently.
    NonManifoldEdge {
        /// The edge's end points (welded positions).
        from: DVec3,
        /// See `from`.
        to: DVec3,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::IndexCount { count } => {
                write!(f, "{count} indices is not a whole number of triangles")
            }
            MeshError::IndexOutOfRange { triangle, index } => {
                write!(
                    f,
                    "triangle {triangle} names vertex {index}, which does not exist"
                )
            }
            MeshError::NonFinite { vertex } => write!(f, "vertex {vertex} is not finite"),
            MeshError::OpenEdge { from, to } => write!(
                f,
                "the mesh is not closed: edge {from} -> {to} has one triangle (use the per-triangle option for open meshes)"
            ),
            MeshError::NonManifoldEdge { from, to } => write!(
                f,
                "edge {from} -> {to} is used twice in one direction: more than two triangles meet there or the winding is inconsistent"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

/// What to do with a mesh that is not a closed, consistently wound 2-manifold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OpenMeshPolicy {
    /// Refuse it with a [`MeshError`].
    #[default]
    Reject,
    /// Shadow it correctly anyway: every triangle gets a volume of its own (its three edges
    /// extruded, both caps), from whichever side the light sees it. Exact for any triangle
    /// soup, at the cost of three side quads per triangle instead of one per silhouette edge.
    PerTriangle,
}

/// A mesh's welded vertices, triangles and edge adjacency.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTopology {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// For each triangle and edge i (from vertex i to vertex i + 1), the triangle across it;
    /// `None` when the mesh is shadowed per triangle.
    neighbours: Option<Vec<[u32; 3]>>,
    degenerate: usize,
}

impl MeshTopology {
    /// Welds vertices closer than a millionth of the mesh's size, drops triangles that
    /// become degenerate, and builds the adjacency. A mesh that is not closed (an edge with
    /// one triangle) or not a consistently wound 2-manifold is refused, or with
    /// [`OpenMeshPolicy::PerTriangle`] kept for per-triangle volumes.
    pub fn new(
        positions: &[DVec3],
        indices: &[u32],
        policy: OpenMeshPolicy,
    ) -> Result<Self, MeshError> {
        if !indices.len().is_multiple_of(3) {
            return Err(MeshError::IndexCount {
                count: indices.len(),
            });
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { vertex });
        }
        let (welded, remap) = weld(positions);
        let mut triangles = Vec::with_capacity(indices.len() / 3);
        let mut degenerate = 0;
        for (t, tri) in indices.chunks_exact(3).enumerate() {
            let mut w = [0u32; 3];
            for (k, &i) in tri.iter().enumerate() {
                w[k] = *remap.get(i as usize).ok_or(MeshError::IndexOutOfRange {
                    triangle: t,
                    index: i,
                })?;
            }
            if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] {
                degenerate += 1;
            } else {
                triangles.push(w);
            }
        }
        let neighbours = match adjacency(&welded, &triangles) {
            Ok(n) => Some(n),
            Err(_) if policy == OpenMeshPolicy::PerTriangle => None,
            Err(e) => return Err(e),
        };
        Ok(Self {
            positions: welded,
            triangles,
            neighbours,
            degenerate,
        })
    }

    /// The welded positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The triangles (indices into [`MeshTopology::positions`]), degenerate ones dropped.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Whether the mesh is a closed, consistently wound 2-manifold (else it is shadowed per
    /// triangle).
    pub fn is_closed(&self) -> bool {
        self.neighbours.is_some()
    }

    /// For each triangle and edge i (vertex i to vertex i + 1), the triangle across it; `None`
    /// for a mesh shadowed per triangle.
    pub fn neighbours(&self) -> Option<&[[u32; 3]]> {
        self.neighbours.as_deref()
    }

    /// How many triangles welding made degenerate (dropped).
    pub fn degenerate_triangles(&self) -> usize {
        self.degenerate
    }

    /// The possible silhouette edges for a per-triangle facing (true: faces the light): the
    /// edges (from, to) of facing triangles whose neighbour does not face the light, in the
    /// facing triangle's winding. Empty for a mesh shadowed per triangle.
    pub fn silhouette_edges(&self, facing: &[bool]) -> Vec<(u32, u32)> {
        let Some(neighbours) = &self.neighbours else {
            return Vec::new();
        };
        let mut edges = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !facing[t] {
                continue;
            }
            for i in 0..3 {
                if !facing[neighbours[t][i] as usize] {
                    edges.push((tri[i], tri[(i + 1) % 3]));
                }
            }
        }
        edges
    }
}

/// Welds positions closer than a millionth of the bounding box's diagonal: a grid of that
/// cell size, each point compared with the points in its 27 neighbouring cells.
fn weld(positions: &[DVec3]) -> (Vec<DVec3>, Vec<u32>) {
    let (min, max) = positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let size = if positions.is_empty() {
        0.0
    } else {
        (max - min).length()
    };
    let tolerance = (1e-6 * size).max(f64::MIN_POSITIVE);
    let cell = |p: DVec3| {
        let c = ((p - min) / tolerance).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
    let mut welded: Vec<DVec3> = Vec::new();
    let mut remap = Vec::with_capacity(positions.len());
    for p in positions {
        let (x, y, z) = cell(*p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = grid.get(&(x + dx, y + dy, z + dz)).and_then(|list| {
                        list.iter()
                            .find(|&&i| welded[i as usize].distance(*p) <= tolerance)
                    });
                    if let Some(&i) = near {
                        found = Some(i);
                        break 'search;
                    }
                }
            }
        }
        let index = found.unwrap_or_else(|| {
            welded.push(*p);
            let i = (welded.len() - 1) as u32;
            grid.entry((x, y, z)).or_default().push(i);
            i
        });
        remap.push(index);
    }
    (welded, remap)
}

/// Each triangle edge's neighbour, or the first edge that is open or non-manifold.
fn adjacency(positions: &[DVec3], triangles: &[[u32; 3]]) -> Result<Vec<[u32; 3]>, MeshError> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * triangles.len());
    let edge_error = |a: u32, b: u32, open: bool| {
        let (from, to) = (positions[a as usize], positions[b as usize]);
        if open {
            MeshError::OpenEdge { from, to }
        } else {
            MeshError::NonManifoldEdge { from, to }
        }
    };
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            if directed.insert((a, b), t as u32).is_some() {
                return Err(edge_error(a, b, false));
            }
        }
    }
    let mut neighbours = Vec::with_capacity(triangles.len());
    for tri in triangles {
        let mut n = [0u32; 3];
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            n[i] = *directed
                .get(&(b, a))
                .ok_or_else(|| edge_error(a, b, true))?;
        }
        neighbours.push(n);
    }
    Ok(neighbours)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube with split corners (24 vertices, as a renderer stores it: one set per face).
    fn split_cube() -> (Vec<DVec3>, Vec<u32>) {
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let n =
                    DVec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
                let u = DVec3::from_array(std::array::from_fn(|k| {
                    if k == (axis + 1) % 3 { 1.0 } else { 0.0 }
                }));
                let v = n.cross(u);
                let base = positions.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    positions.push(0.5 * (n + a * u + b * v));
                }
                indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            }
        }
        (positions, indices)
    }

    #[test]
    fn split_cube_welds_into_a_closed_manifold() {
        let (p, i) = split_cube();
        let t = MeshTopology::new(&p, &i, OpenMeshPolicy::Reject).unwrap();
        assert_eq!(t.positions().len(), 8);
        assert_eq!(t.triangles().len(), 12);
        assert!(t.is_closed());
        // Every neighbour relation is symmetric, and neighbours share the edge reversed.
        let n = t.neighbours().unwrap();
        for (a, tri) in t.triangles().iter().enumerate() {
            for e in 0..3 {
                let b = n[a][e] as usize;
                let (from, to) = (tri[e], tri[(e + 1) % 3]);
                let other = t.triangles()[b];
                assert!((0..3).any(|k| other[k] == to && other[(k + 1) % 3] == from));
                assert!(n[b].contains(&(a as u32)));
            }
        }
    }

    #[test]
    fn silhouette_of_a_cube_lit_from_above_is_the_top_square() {
        let (p, i) = split_cube();
        let t = MeshTopology::new(&p, &i, OpenMeshPolicy::Reject).unwrap();
        let light_travel = -DVec3::Y;
        let facing: Vec<bool> = t
            .triangles()
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|k| t.positions()[k as usize]);
                (b - a).cross(c - a).dot(-light_travel) > 0.0
            })
            .collect();
        let edges = t.silhouette_edges(&facing);
        assert_eq!(edges.len(), 4);
        for (a, b) in edges {
            let (pa, pb) = (t.positions()[a as usize], t.positions()[b as usize]);
            assert_eq!((pa.y, pb.y), (0.5, 0.5));
        }
    }

    #[test]
    fn open_and_inconsistent_meshes_are_refused_or_shadowed_per_triangle() {
        let (p, i) = split_cube();
        // Remove one triangle: a hole.
        let open = &i[..i.len() - 3];
        assert!(matches!(
            MeshTopology::new(&p, open, OpenMeshPolicy::Reject),
            Err(MeshError::OpenEdge { .. })
        ));
        let per_triangle = MeshTopology::new(&p, open, OpenMeshPolicy::PerTriangle).unwrap();
        assert!(!per_triangle.is_closed());
        assert!(per_triangle.silhouette_edges(&[true; 11]).is_empty());
        // Flip one triangle: inconsistent winding.
        let mut flipped = i.clone();
        flipped.swap(0, 1);
        assert!(matches!(
            MeshTopology::new(&p, &flipped, OpenMeshPolicy::Reject),
            Err(MeshError::NonManifoldEdge { .. })
        ));
        // Bad input.
        assert!(matches!(
            MeshTopology::new(&p, &i[..4], OpenMeshPolicy::Reject),
            Err(MeshError::IndexCount { count: 4 })
        ));
        assert!(matches!(
            MeshTopology::new(&p, &[0, 1, 99], OpenMeshPolicy::Reject),
            Err(MeshError::IndexOutOfRange { index: 99, .. })
        ));
        let mut nan = p.clone();
        nan[3].x = f64::NAN;
        assert!(matches!(
            MeshTopology::new(&nan, &i, OpenMeshPolicy::Reject),
            Err(MeshError::NonFinite { vertex: 3 })
        ));
    }
}
