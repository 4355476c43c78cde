use glam::DVec3;

use super::Plane;
use crate::bounds::Aabb;

/// A convex polyhedron stored as its faces (polygons of world-space points).
///
/// Built from a box or a frustum's eight corners and then clipped by planes; the vertices are
/// what the shadow setups use (extents in light space). Face winding is not relied on: face
/// planes are oriented with the polyhedron's centroid. All comparisons use a tolerance given
/// by the caller in world units, so that a point on a clipping plane is kept exactly once.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConvexPolyhedron {
    faces: Vec<Vec<DVec3>>,
}

impl ConvexPolyhedron {
    /// The empty polyhedron.
    pub fn empty() -> Self {
        Self { faces: Vec::new() }
    }

    /// The polyhedron of a box.
    pub fn from_box(aabb: &Aabb) -> Self {
        Self::from_hexahedron(&aabb.corners_as_hexahedron())
    }

    /// A hexahedron from eight corners: the first four and the last four each a quad (in the
    /// same rotational order), as [`crate::Camera::frustum_corners`] returns them.
    pub fn from_hexahedron(c: &[DVec3; 8]) -> Self {
        let faces = vec![
            vec![c[0], c[1], c[2], c[3]],
            vec![c[4], c[7], c[6], c[5]],
            vec![c[0], c[4], c[5], c[1]],
            vec![c[1], c[5], c[6], c[2]],
            vec![c[2], c[6], c[7], c[3]],
            vec![c[3], c[7], c[4], c[0]],
        ];
        Self { faces }
    }

    /// Whether nothing is left.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// The faces.
    pub fn faces(&self) -> &[Vec<DVec3>] {
        &self.faces
    }

    /// The distinct vertices (points closer than `tolerance` are merged).
    pub fn vertices(&self, tolerance: f64) -> Vec<DVec3> {
        let mut out: Vec<DVec3> = Vec::new();
        for p in self.faces.iter().flatten() {
            if !out.iter().any(|q| q.distance_squared(*p) <= tolerance * tolerance) {
                out.push(*p);
            }
        }
        out
    }

    /// The mean of the vertices (a point inside a non-empty polyhedron).
    pub fn centroid(&self, tolerance: f64) -> DVec3 {
        let v = self.vertices(tolerance);
        v.iter().copied().sum::<DVec3>() / v.len().max(1) as f64
    }

    /// The planes of the faces of non-negligible area, normals pointing inward: the
    /// polyhedron is the intersection of their insides.
    pub fn bounding_planes(&self, tolerance: f64) -> Vec<Plane> {
        let centroid = self.centroid(tolerance);
        let mut planes = Vec::with_capacity(self.faces.len());
        for face in &self.faces {
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
        let mut max_d = f64::NEG_INFINITY;
        let mut min_d = f64::INFINITY;
        for p in self.faces.iter().flatten() {
            let d = plane.distance(*p);
            max_d = max_d.max(d);
            min_d = min_d.min(d);
        }
        if self.faces.is_empty() || max_d <= tolerance {
            return Self::empty();
        }
        if min_d >= -tolerance {
            return self.clone();
        }
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        let mut cap: Vec<DVec3> = Vec::new();
        for face in &self.faces {
            let clipped = clip_polygon(face, plane, tolerance, &mut cap);
            if clipped.len() >= 3 {
                faces.push(clipped);
            }
        }
        if let Some(cap_face) = order_cap(cap, plane, tolerance) {
            faces.push(cap_face);
        }
        if faces.len() < 2 {
            return Self::empty();
        }
        Self { faces }
    }

    /// Clips by every plane in turn.
    pub fn clip_all<'a>(&self, planes: impl IntoIterator<Item = &'a Plane>, tolerance: f64) -> ConvexPolyhedron {
        let mut out = self.clone();
        for plane in planes {
            if out.is_empty() {
                break;
            }
            out = out.clip(plane, tolerance);
        }
        out
    }
}

impl Aabb {
    /// The corners in the order [`ConvexPolyhedron::from_hexahedron`] takes.
    pub(crate) fn corners_as_hexahedron(&self) -> [DVec3; 8] {
        let c = self.corners();
        [c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]]
    }
}

/// Sutherland-Hodgman against one plane; points on the plane (and new intersection points)
/// are appended to `cap`.
fn clip_polygon(face: &[DVec3], plane: &Plane, tolerance: f64, cap: &mut Vec<DVec3>) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(face.len() + 2);
    let n = face.len();
    for i in 0..n {
        let a = face[i];
        let b = face[(i + 1) % n];
        let da = plane.distance(a);
        let db = plane.distance(b);
        if da >= -tolerance {
            out.push(a);
            if da <= tolerance {
                cap.push(a);
            }
        }
        if (da < -tolerance && db > tolerance) || (da > tolerance && db < -tolerance) {
            // Compute from a canonical endpoint order so that the two faces sharing this edge
            // produce the identical point.
            let (p, q, dp, dq) = if (a.x, a.y, a.z) < (b.x, b.y, b.z) { (a, b, da, db) } else { (b, a, db, da) };
            let t = dp / (dp - dq);
            let x = p + (q - p) * t;
            out.push(x);
            cap.push(x);
        }
    }
    out
}

/// Orders the points where the polyhedron meets the clipping plane into a polygon.
fn order_cap(mut points: Vec<DVec3>, plane: &Plane, tolerance: f64) -> Option<Vec<DVec3>> {
    let mut unique: Vec<DVec3> = Vec::with_capacity(points.len());
    for p in points.drain(..) {
        if !unique.iter().any(|q| q.distance_squared(p) <= tolerance * tolerance) {
            unique.push(p);
        }
    }
    if unique.len() < 3 {
        return None;
    }
    let center = unique.iter().copied().sum::<DVec3>() / unique.len() as f64;
    let (u, v) = plane.normal.any_orthonormal_pair();
    let mut keyed: Vec<(f64, DVec3)> = unique
        .into_iter()
        .map(|p| {
            let d = p - center;
            (d.dot(v).atan2(d.dot(u)), p)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    Some(keyed.into_iter().map(|(_, p)| p).collect())
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
        let planes = cube.bounding_planes(1e-9);
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
        assert!(cut.faces().iter().any(|f| f.len() == 6));
    }

    #[test]
    fn clip_outside_and_touching_give_empty() {
        let cube = unit_cube();
        assert!(cube.clip(&Plane::through_point(DVec3::splat(2.0), DVec3::X), 1e-9).is_empty());
        assert!(cube.clip(&Plane::through_point(DVec3::ONE, DVec3::X), 1e-9).is_empty());
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
        assert!(v.iter().all(|p| (p.y - 0.25).abs() < 1e-12 || (p.y - 0.75).abs() < 1e-12));
    }
}
