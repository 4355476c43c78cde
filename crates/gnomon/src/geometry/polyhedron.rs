use std::cell::RefCell;

use glam::DVec3;

use super::Plane;
use crate::boxes::Aabb;

/// A convex polyhedron: its distinct vertices and its faces (polygons of vertex indices).
///
/// Built from a box or a frustum's eight corners and then clipped by planes; the vertices are
/// what the shadow setups use (extents in light space). Face winding is not relied on: face
/// planes are oriented with the polyhedron's centroid. All comparisons use a tolerance given
/// by the caller in world units, so that a point on a clipping plane is kept exactly once.
///
/// Faces index one vertex list, so that a clip measures each vertex's distance once and
/// makes each crossing edge's point once (the two faces that share the edge read the same
/// point). Storage is flat (faces as end offsets into one index buffer), so that a clip
/// allocates nothing once its scratch buffers have grown.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConvexPolyhedron {
    vertices: Vec<DVec3>,
    indices: Vec<u32>,
    face_ends: Vec<usize>,
}

impl ConvexPolyhedron {
    /// The empty polyhedron.
    pub fn empty() -> Self {
        Self::default()
    }

    /// The polyhedron of a box.
    pub fn from_box(aabb: &Aabb) -> Self {
        Self::from_hexahedron(&aabb.corners_as_hexahedron())
    }

    /// A hexahedron from eight corners: the first four and the last four each a quad (in the
    /// same rotational order), as [`crate::Camera::frustum_corners`] returns them.
    pub fn from_hexahedron(c: &[DVec3; 8]) -> Self {
        const FACES: [[u32; 4]; 6] = [
            [0, 1, 2, 3],
            [4, 7, 6, 5],
            [0, 4, 5, 1],
            [1, 5, 6, 2],
            [2, 6, 7, 3],
            [3, 7, 4, 0],
        ];
        Self {
            vertices: c.to_vec(),
            indices: FACES.iter().flatten().copied().collect(),
            face_ends: vec![4, 8, 12, 16, 20, 24],
        }
    }

    /// Whether nothing is left.
    pub fn is_empty(&self) -> bool {
        self.face_ends.is_empty()
    }

    /// The corner points: every vertex, each once (points that a clip made closer than its
    /// tolerance may both be there; [`Self::vertices`] merges them).
    pub fn points(&self) -> &[DVec3] {
        if self.is_empty() { &[] } else { &self.vertices }
    }

    /// The faces, each the indices of its vertices in [`Self::points`] in order.
    fn face_indices(&self) -> impl Iterator<Item = &[u32]> + '_ {
        let mut start = 0;
        self.face_ends.iter().map(move |&end| {
            let face = &self.indices[start..end];
            start = end;
            face
        })
    }

    /// The distinct vertices (points closer than `tolerance` are merged).
    pub fn vertices(&self, tolerance: f64) -> Vec<DVec3> {
        let mut out: Vec<DVec3> = Vec::with_capacity(self.points().len());
        for p in self.points() {
            if !out
                .iter()
                .any(|q| q.distance_squared(*p) <= tolerance * tolerance)
            {
                out.push(*p);
            }
        }
        out
    }

    /// The planes of the faces of non-negligible area, normals pointing inward: the
    /// polyhedron is the intersection of their insides. `centroid`: a point inside.
    pub fn bounding_planes(&self, centroid: DVec3, tolerance: f64) -> Vec<Plane> {
        let mut planes = Vec::with_capacity(self.face_ends.len());
        let v = &self.vertices;
        for face in self.face_indices() {
            // Newell's method: robust for nearly degenerate polygons.
            let mut normal = DVec3::ZERO;
            for (i, &a) in face.iter().enumerate() {
                let (a, b) = (v[a as usize], v[face[(i + 1) % face.len()] as usize]);
                normal += DVec3::new(
                    (a.y - b.y) * (a.z + b.z),
                    (a.z - b.z) * (a.x + b.x),
                    (a.x - b.x) * (a.y + b.y),
                );
            }
            // |normal| is twice the area; skip faces thinner than the tolerance.
            let area2 = normal.length();
            let first = v[face[0] as usize];
            let extent = face
                .iter()
                .map(|&i| v[i as usize].distance(first))
                .fold(0.0, f64::max);
            if area2 <= 2.0 * tolerance * extent.max(tolerance) {
                continue;
            }
            let mut normal = normal / area2;
            let face_center =
                face.iter().map(|&i| v[i as usize]).sum::<DVec3>() / face.len() as f64;
            if normal.dot(face_center - centroid) < 0.0 {
                normal = -normal;
            }
            planes.push(Plane::through_point(face_center, -normal));
        }
        planes
    }

    /// The part of the polyhedron on the inside of `plane` (signed distance >= -tolerance).
    /// A polyhedron that only touches the plane comes back empty.
    pub fn clip(&self, plane: &Plane, tolerance: f64) -> ConvexPolyhedron {
        let mut out = self.with_room();
        Scratch::with(|scratch| out.clip_in_place(plane, tolerance, scratch));
        out
    }

    /// Clips by every plane in turn.
    pub fn clip_all<'a>(
        &self,
        planes: impl IntoIterator<Item = &'a Plane>,
        tolerance: f64,
    ) -> ConvexPolyhedron {
        let mut out = self.with_room();
        Scratch::with(|scratch| {
            for plane in planes {
                if out.is_empty() {
                    break;
                }
                out.clip_in_place(plane, tolerance, scratch);
            }
        });
        out
    }

    /// A copy with the room a [`Scratch`] has: a clip swaps its buffers with the scratch's,
    /// so that an exact-size copy would make the next clip grow them piece by piece.
    fn with_room(&self) -> Self {
        fn copy<T: Copy>(v: &[T], room: usize) -> Vec<T> {
            let mut out = Vec::with_capacity(room.max(v.len()));
            out.extend_from_slice(v);
            out
        }
        Self {
            vertices: copy(&self.vertices, Scratch::VERTICES),
            indices: copy(&self.indices, Scratch::INDICES),
            face_ends: copy(&self.face_ends, Scratch::FACES),
        }
    }

    fn clip_in_place(&mut self, plane: &Plane, tolerance: f64, scratch: &mut Scratch) {
        if self.is_empty() {
            return;
        }
        let mut max_d = f64::NEG_INFINITY;
        let mut min_d = f64::INFINITY;
        let distances = &mut scratch.distances;
        distances.clear();
        for p in &self.vertices {
            let d = plane.distance(*p);
            max_d = max_d.max(d);
            min_d = min_d.min(d);
            distances.push(d);
        }
        if max_d <= tolerance {
            *self = Self::empty();
            return;
        }
        if min_d >= -tolerance {
            return;
        }
        // The kept vertices, renumbered; those on the plane start the cap.
        let (vertices, remap, cap) = (&mut scratch.vertices, &mut scratch.remap, &mut scratch.cap);
        vertices.clear();
        remap.clear();
        cap.clear();
        for (p, &d) in self.vertices.iter().zip(distances.iter()) {
            if d >= -tolerance {
                if d <= tolerance {
                    cap.push(vertices.len() as u32);
                }
                remap.push(vertices.len() as u32);
                vertices.push(*p);
            } else {
                remap.push(u32::MAX);
            }
        }
        // Each crossing edge's point, made once: (lower index, higher index, point's index).
        let crossings = &mut scratch.crossings;
        crossings.clear();
        let (indices, face_ends) = (&mut scratch.indices, &mut scratch.face_ends);
        indices.clear();
        face_ends.clear();
        let mut face_start = 0;
        for &face_end in &self.face_ends {
            let face = &self.indices[face_start..face_end];
            face_start = face_end;
            let start = indices.len();
            let Some(&last) = face.last() else {
                continue;
            };
            // Each edge (a, b) of the face in order, the closing one first.
            let mut a = last as usize;
            for &b in face {
                let b = b as usize;
                let (da, db) = (distances[a], distances[b]);
                if da >= -tolerance {
                    indices.push(remap[a]);
                }
                if (da < -tolerance && db > tolerance) || (da > tolerance && db < -tolerance) {
                    let key = (a.min(b) as u32, a.max(b) as u32);
                    let index = match crossings.iter().find(|c| (c.0, c.1) == key) {
                        Some(c) => c.2,
                        None => {
                            let (p, q) = (key.0 as usize, key.1 as usize);
                            let (dp, dq) = (distances[p], distances[q]);
                            let t = dp / (dp - dq);
                            let (vp, vq) = (self.vertices[p], self.vertices[q]);
                            let index = vertices.len() as u32;
                            vertices.push(vp + (vq - vp) * t);
                            crossings.push((key.0, key.1, index));
                            cap.push(index);
                            index
                        }
                    };
                    indices.push(index);
                }
                a = b;
            }
            if indices.len() - start >= 3 {
                face_ends.push(indices.len());
            } else {
                indices.truncate(start);
            }
        }
        if order_cap(cap, vertices, plane, tolerance, &mut scratch.keyed) {
            indices.extend_from_slice(cap);
            face_ends.push(indices.len());
        }
        std::mem::swap(&mut self.vertices, vertices);
        std::mem::swap(&mut self.indices, indices);
        std::mem::swap(&mut self.face_ends, face_ends);
        if self.face_ends.len() < 2 {
            *self = Self::empty();
        }
    }
}

/// Buffers a clip works in: one set per thread, reused by every clip ([`Scratch::with`]).
struct Scratch {
    distances: Vec<f64>,
    remap: Vec<u32>,
    vertices: Vec<DVec3>,
    indices: Vec<u32>,
    face_ends: Vec<usize>,
    crossings: Vec<(u32, u32, u32)>,
    cap: Vec<u32>,
    keyed: Vec<(f64, u32)>,
}

impl Scratch {
    /// Room for the polyhedra of the setups (a box or frustum clipped by a few planes: up
    /// to about 12 faces of 3 to 6 vertices), so that clipping does not grow them piecewise.
    const VERTICES: usize = 32;
    const INDICES: usize = 64;
    const FACES: usize = 16;

    /// Runs `f` with this thread's scratch buffers, kept between clips so that a clip
    /// allocates only its result (a fresh set where they are in use).
    fn with<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
        thread_local! {
            static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::new());
        }
        let mut f = Some(f);
        let reused = SCRATCH.with(|cell| {
            cell.try_borrow_mut()
                .ok()
                .map(|mut scratch| (f.take().expect("called once"))(&mut scratch))
        });
        match reused {
            Some(r) => r,
            None => (f.take().expect("called once"))(&mut Scratch::new()),
        }
    }

    fn new() -> Self {
        Self {
            distances: Vec::with_capacity(Self::VERTICES),
            remap: Vec::with_capacity(Self::VERTICES),
            vertices: Vec::with_capacity(Self::VERTICES),
            indices: Vec::with_capacity(Self::INDICES),
            face_ends: Vec::with_capacity(Self::FACES),
            crossings: Vec::with_capacity(16),
            cap: Vec::with_capacity(16),
            keyed: Vec::with_capacity(16),
        }
    }
}

impl Aabb {
    /// The corners in the order [`ConvexPolyhedron::from_hexahedron`] takes.
    pub(crate) fn corners_as_hexahedron(&self) -> [DVec3; 8] {
        let c = self.corners();
        [c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]]
    }
}

/// Orders the cap's vertices (indices into `vertices`, on the clipping plane) into a
/// polygon, in place, leaving out any closer than `tolerance` to one kept before it; `false`
/// when fewer than three remain.
fn order_cap(
    cap: &mut Vec<u32>,
    vertices: &[DVec3],
    plane: &Plane,
    tolerance: f64,
    keyed: &mut Vec<(f64, u32)>,
) -> bool {
    let mut n = 0;
    for i in 0..cap.len() {
        let p = vertices[cap[i] as usize];
        if !cap[..n]
            .iter()
            .any(|&q| vertices[q as usize].distance_squared(p) <= tolerance * tolerance)
        {
            cap[n] = cap[i];
            n += 1;
        }
    }
    cap.truncate(n);
    if n < 3 {
        return false;
    }
    let center = cap.iter().map(|&i| vertices[i as usize]).sum::<DVec3>() / n as f64;
    let (u, v) = plane.normal.any_orthonormal_pair();
    // A pseudo-angle: monotone in the angle around the centre, cheaper than atan2.
    let pseudo_angle = |x: f64, y: f64| {
        let t = x / (x.abs() + y.abs()).max(f64::MIN_POSITIVE);
        if y >= 0.0 { 1.0 - t } else { 3.0 + t }
    };
    keyed.clear();
    keyed.extend(cap.iter().map(|&i| {
        let d = vertices[i as usize] - center;
        (pseudo_angle(d.dot(u), d.dot(v)), i)
    }));
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    cap.clear();
    cap.extend(keyed.iter().map(|&(_, i)| i));
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> ConvexPolyhedron {
        ConvexPolyhedron::from_box(&Aabb::new(DVec3::ZERO, DVec3::ONE).unwrap())
    }

    #[test]
    fn box_has_eight_vertices_and_inward_planes() {
        let cube = unit_cube();
        assert_eq!(cube.vertices(1e-9).len(), 8);
        let planes = cube.bounding_planes(DVec3::splat(0.5), 1e-9);
        assert_eq!(planes.len(), 6);
        for plane in planes {
            assert!((plane.distance(DVec3::splat(0.5)) - 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn diagonal_cut_of_a_cube() {
        // x + y + z <= 1.5 cuts the cube through six edge midpoints: a hexagonal cap.
        let n = DVec3::ONE.normalize();
        let plane = Plane::through_point(DVec3::splat(0.5), -n);
        let cut = unit_cube().clip(&plane, 1e-9);
        let vertices = cut.vertices(1e-9);
        // Four corners below the plane plus six edge midpoints.
        assert_eq!(vertices.len(), 4 + 6);
        assert!(vertices.iter().all(|p| p.element_sum() <= 1.5 + 1e-12));
        assert!(cut.face_indices().any(|f| f.len() == 6));
    }

    #[test]
    fn clip_outside_and_touching_give_empty() {
        let cube = unit_cube();
        assert!(
            cube.clip(&Plane::through_point(DVec3::splat(2.0), DVec3::X), 1e-9)
                .is_empty()
        );
        assert!(
            cube.clip(&Plane::through_point(DVec3::ONE, DVec3::X), 1e-9)
                .is_empty()
        );
        let same = cube.clip(&Plane::through_point(DVec3::ZERO, DVec3::X), 1e-9);
        assert_eq!(same, cube);
    }

    #[test]
    fn clip_to_slab() {
        let slab = unit_cube()
            .clip(&Plane::through_point(DVec3::splat(0.25), DVec3::Y), 1e-9)
            .clip(&Plane::through_point(DVec3::splat(0.75), -DVec3::Y), 1e-9);
        let v = slab.vertices(1e-9);
        assert_eq!(v.len(), 8);
        assert!(
            v.iter()
                .all(|p| (p.y - 0.25).abs() < 1e-12 || (p.y - 0.75).abs() < 1e-12)
        );
    }
}
