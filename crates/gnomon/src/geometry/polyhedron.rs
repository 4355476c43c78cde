use glam::DVec3;

use super::Plane;
use crate::bounds::Aabb;

/// A convex polyhedron stored as its faces (polygons of world-space points).
///
/// Built from a box or a frustum's eight corners and then clipped by planes; the vertices are
/// what the shadow setups use (extents in light space). Face winding is not relied on: face
/// planes are oriented with the polyhedron's centroid. All comparisons use a tolerance given
/// by the caller in world units, so that a point on a clipping plane is kept exactly once.
///
/// Storage is flat (all face points in one buffer, faces as end offsets) so that a clip
/// allocates two buffers, not one per face.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConvexPolyhedron {
    points: Vec<DVec3>,
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
        const FACES: [[usize; 4]; 6] = [
            [0, 1, 2, 3],
            [4, 7, 6, 5],
            [0, 4, 5, 1],
            [1, 5, 6, 2],
            [2, 6, 7, 3],
            [3, 7, 4, 0],
        ];
        let points = FACES.iter().flatten().map(|&i| c[i]).collect();
        Self {
            points,
            face_ends: vec![4, 8, 12, 16, 20, 24],
        }
    }

    /// Whether nothing is left.
    pub fn is_empty(&self) -> bool {
        self.face_ends.is_empty()
    }

    /// The faces, each a polygon.
    pub fn faces(&self) -> impl Iterator<Item = &[DVec3]> + '_ {
        let mut start = 0;
        self.face_ends.iter().map(move |&end| {
            let face = &self.points[start..end];
            start = end;
            face
        })
    }

    /// The distinct vertices (points closer than `tolerance` are merged).
    pub fn vertices(&self, tolerance: f64) -> Vec<DVec3> {
        let mut out: Vec<DVec3> = Vec::with_capacity(self.points.len() / 2);
        for p in &self.points {
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
        for face in self.faces() {
            // Newell's method: robust for nearly degenerate polygons.
            let mut normal = DVec3::ZERO;
            for (i, a) in face.iter().enumerate() {
                let b = face[(i + 1) % face.len()];
                normal += DVec3::new(
                    (a.y - b.y) * (a.z + b.z),
                    (a.z - b.z) * (a.x + b.x),
                    (a.x - b.x) * (a.y + b.y),
                );
            }
            // |normal| is twice the area; skip faces thinner than the tolerance.
            let area2 = normal.length();
            let extent = face.iter().map(|p| p.distance(face[0])).fold(0.0, f64::max);
            if area2 <= 2.0 * tolerance * extent.max(tolerance) {
                continue;
            }
            let mut normal = normal / area2;
            let face_center = face.iter().copied().sum::<DVec3>() / face.len() as f64;
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
        let mut out = self.clone();
        out.clip_in_place(plane, tolerance, &mut Scratch::new());
        out
    }

    /// Clips by every plane in turn.
    pub fn clip_all<'a>(
        &self,
        planes: impl IntoIterator<Item = &'a Plane>,
        tolerance: f64,
    ) -> ConvexPolyhedron {
        let mut out = self.clone();
        let mut scratch = Scratch::new();
        for plane in planes {
            if out.is_empty() {
                break;
            }
            out.clip_in_place(plane, tolerance, &mut scratch);
        }
        out
    }

    fn clip_in_place(&mut self, plane: &Plane, tolerance: f64, scratch: &mut Scratch) {
        let mut max_d = f64::NEG_INFINITY;
        let mut min_d = f64::INFINITY;
        scratch.distances.clear();
        scratch.distances.reserve(self.points.len());
        for p in &self.points {
            let d = plane.distance(*p);
            max_d = max_d.max(d);
            min_d = min_d.min(d);
            scratch.distances.push(d);
        }
        if self.is_empty() || max_d <= tolerance {
            *self = Self::empty();
            return;
        }
        if min_d >= -tolerance {
            return;
        }
        scratch.points.clear();
        scratch.face_ends.clear();
        scratch.cap.clear();
        // The buffers swapped in from the last clip may be only as large as its polyhedron.
        scratch.points.reserve(self.points.len() + 16);
        scratch.face_ends.reserve(self.face_ends.len() + 2);
        scratch.cap.reserve(16);
        let mut face_start = 0;
        for (face, &face_end) in self.faces().zip(&self.face_ends) {
            let distances = &scratch.distances[face_start..face_end];
            face_start = face_end;
            let start = scratch.points.len();
            clip_polygon(
                face,
                distances,
                tolerance,
                &mut scratch.points,
                &mut scratch.cap,
            );
            if scratch.points.len() - start >= 3 {
                scratch.face_ends.push(scratch.points.len());
            } else {
                scratch.points.truncate(start);
            }
        }
        if order_cap(&mut scratch.cap, plane, tolerance) {
            scratch.points.extend_from_slice(&scratch.cap);
            scratch.face_ends.push(scratch.points.len());
        }
        std::mem::swap(&mut self.points, &mut scratch.points);
        std::mem::swap(&mut self.face_ends, &mut scratch.face_ends);
        if self.face_ends.len() < 2 {
            *self = Self::empty();
        }
    }
}

/// Buffers reused across the clips of one [`ConvexPolyhedron::clip_all`].
struct Scratch {
    distances: Vec<f64>,
    points: Vec<DVec3>,
    face_ends: Vec<usize>,
    cap: Vec<DVec3>,
}

impl Scratch {
    /// Room for the polyhedra of the setups (a box or frustum clipped by a few planes: up
    /// to about 12 faces of 3 to 6 vertices), so that clipping does not grow them piecewise.
    fn new() -> Self {
        Self {
            distances: Vec::with_capacity(64),
            points: Vec::with_capacity(64),
            face_ends: Vec::with_capacity(16),
            cap: Vec::with_capacity(16),
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

/// Sutherland-Hodgman against one plane, given each point's signed distance to it; the kept
/// polygon is appended to `out`, points on the plane (and new intersection points) to `cap`.
fn clip_polygon(
    face: &[DVec3],
    distances: &[f64],
    tolerance: f64,
    out: &mut Vec<DVec3>,
    cap: &mut Vec<DVec3>,
) {
    let n = face.len();
    for i in 0..n {
        let a = face[i];
        let b = face[(i + 1) % n];
        let da = distances[i];
        let db = distances[(i + 1) % n];
        if da >= -tolerance {
            out.push(a);
            if da <= tolerance {
                cap.push(a);
            }
        }
        if (da < -tolerance && db > tolerance) || (da > tolerance && db < -tolerance) {
            // Compute from a canonical endpoint order so that the two faces sharing this edge
            // produce the identical point.
            let (p, q, dp, dq) = if (a.x, a.y, a.z) < (b.x, b.y, b.z) {
                (a, b, da, db)
            } else {
                (b, a, db, da)
            };
            let t = dp / (dp - dq);
            let x = p + (q - p) * t;
            out.push(x);
            cap.push(x);
        }
    }
}

/// Orders the points where the polyhedron meets the clipping plane into a polygon, in place;
/// `false` when fewer than three distinct points remain.
fn order_cap(points: &mut Vec<DVec3>, plane: &Plane, tolerance: f64) -> bool {
    let mut n = 0;
    for i in 0..points.len() {
        let p = points[i];
        if !points[..n]
            .iter()
            .any(|q| q.distance_squared(p) <= tolerance * tolerance)
        {
            points[n] = p;
            n += 1;
        }
    }
    points.truncate(n);
    if n < 3 {
        return false;
    }
    let center = points.iter().copied().sum::<DVec3>() / n as f64;
    let (u, v) = plane.normal.any_orthonormal_pair();
    // A pseudo-angle: monotone in the angle around the centre, cheaper than atan2.
    let pseudo_angle = |x: f64, y: f64| {
        let t = x / (x.abs() + y.abs()).max(f64::MIN_POSITIVE);
        if y >= 0.0 { 1.0 - t } else { 3.0 + t }
    };
    let mut keyed: Vec<(f64, DVec3)> = points
        .iter()
        .map(|p| {
            let d = *p - center;
            (pseudo_angle(d.dot(u), d.dot(v)), *p)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.clear();
    points.extend(keyed.into_iter().map(|(_, p)| p));
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
        assert!(cut.faces().any(|f| f.len() == 6));
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
