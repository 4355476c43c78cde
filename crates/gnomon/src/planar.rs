//! Planar projected shadows (the shadows lecture's first example, "Projection to a Plane"):
//! the casters flattened onto one receiver plane along the light's rays, drawn there as the
//! shadow. Exact on that plane, for what lies above it and below the light; nothing else
//! receives a shadow (the technique's limit).
//!
//! A point p at height h(p) = n . p + offset above the plane (normal n, the receiving side
//! h > 0) lands at
//! - for a directional light travelling along t (with n . t < 0): p + t h(p) / (-n . t);
//! - for a light at L, h(L) > 0: L + (p - L) h(L) / (h(L) - h(p)), for h(p) < h(L).
//!
//! In homogeneous form this is Blinn's matrix M = (pi . L) I - L pi^T (pi the plane's
//! coefficients, L the light as a point, w = 1, or as the direction toward it, w = 0):
//! [`flatten_matrix`]. A triangle is first clipped to the part that can cast (above the plane
//! and, for a light at a point, below the light's height: [`flatten_triangle`]), since a
//! vertex beyond the light would land on the far side of it (the "anti-shadow").

use glam::{DMat4, DVec3, DVec4};

use crate::boxes::Aabb;
use crate::geometry::Plane;
use crate::light::Light;

/// The receiver of planar shadows: a plane (the receiving side where its distance is
/// positive) and the convex polygon of it that receives (where the plane crosses a box: the
/// ground slab's top face, or the scene's box for a plane given by hand).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarReceiver {
    /// The plane, unit normal toward the receiving side.
    pub plane: Plane,
    /// The receiving polygon on it, in order around its centre (3 to 6 vertices).
    pub polygon: Vec<DVec3>,
}

impl PlanarReceiver {
    /// The part of `plane` inside `within` (a box, with `tolerance` for the faces the plane
    /// lies in); `None` where the plane misses it or the normal is not finite and non-zero.
    pub fn new(plane: Plane, within: &Aabb, tolerance: f64) -> Option<Self> {
        let length = plane.normal.length();
        if !(length.is_finite() && length > 0.0 && plane.offset.is_finite()) {
            return None;
        }
        let plane = Plane {
            normal: plane.normal / length,
            offset: plane.offset / length,
        };
        let corners = within.corners();
        let d = corners.map(|c| plane.distance(c));
        let mut points: Vec<DVec3> = Vec::new();
        for (c, dist) in corners.iter().zip(&d) {
            if dist.abs() <= tolerance {
                points.push(*c);
            }
        }
        for a in 0..8usize {
            for bit in [1usize, 2, 4] {
                if a & bit != 0 {
                    continue;
                }
                let b = a | bit;
                let (da, db) = (d[a], d[b]);
                if (da > tolerance && db < -tolerance) || (da < -tolerance && db > tolerance) {
                    points.push(corners[a] + (corners[b] - corners[a]) * (da / (da - db)));
                }
            }
        }
        if points.len() < 3 {
            return None;
        }
        // Around the centre, in the plane.
        let centre = points.iter().sum::<DVec3>() / points.len() as f64;
        let u = plane.normal.any_orthonormal_vector();
        let v = plane.normal.cross(u);
        points.sort_by(|p, q| {
            let angle = |x: &DVec3| (*x - centre).dot(v).atan2((*x - centre).dot(u));
            angle(p).total_cmp(&angle(q))
        });
        points.dedup_by(|a, b| a.distance(*b) <= tolerance);
        (points.len() >= 3).then_some(Self {
            plane,
            polygon: points,
        })
    }

    /// The polygon as a fan of triangles.
    pub fn triangles(&self) -> impl Iterator<Item = [DVec3; 3]> + '_ {
        (1..self.polygon.len() - 1).map(|k| [self.polygon[0], self.polygon[k], self.polygon[k + 1]])
    }
}

/// How far below the light's own height (as a fraction of it) a caster's part still casts:
/// the part above lands more than a thousand times the light's height away.
pub const LIGHT_HEIGHT_MARGIN: f64 = 1e-3;

/// Where a light stands for the plane: a position at a height above it, or a direction
/// coming from its receiving side; `None` where the light cannot reach the plane's receiving
/// side (a light below or in the plane, a directional light parallel to it or from below).
fn light_above(light: &Light, plane: &Plane) -> Option<DVec4> {
    match light {
        Light::Directional(d) => {
            let toward = -d.direction();
            (plane.normal.dot(toward) > 1e-9).then(|| toward.extend(0.0))
        }
        Light::Spot(s) => (plane.distance(s.position()) > 0.0).then(|| s.position().extend(1.0)),
        Light::Point(p) => (plane.distance(p.position()) > 0.0).then(|| p.position().extend(1.0)),
    }
}

/// Blinn's projection of world space onto `plane` along `light`'s rays, M = (pi . L) I -
/// L pi^T (a world-to-world homogeneous matrix: divide by w), scaled so that w > 0 for the
/// points that cast; `None` where the light cannot reach the plane's receiving side.
pub fn flatten_matrix(light: &Light, plane: &Plane) -> Option<DMat4> {
    let l = light_above(light, plane)?;
    let pi = plane.normal.extend(plane.offset);
    // M = (pi . L) I - L pi^T: column j of L pi^T is L pi_j.
    let d = pi.dot(l);
    let m = DMat4::from_diagonal(DVec4::splat(d))
        - DMat4::from_cols(l * pi.x, l * pi.y, l * pi.z, l * pi.w);
    // w = pi . L - pi . p for a light at a point (positive below it); for a direction,
    // w = pi . L > 0.
    Some(m)
}

/// The part of triangle `t` that can cast onto `plane` (above it and, for a light at a
/// point, below [`LIGHT_HEIGHT_MARGIN`] of the light's height), flattened onto the plane
/// along the light's rays: a convex polygon of 0 to 5 vertices, fanned into triangles
/// appended to `out`. Returns how many triangles were added.
pub fn flatten_triangle(
    light: &Light,
    plane: &Plane,
    t: [DVec3; 3],
    out: &mut Vec<[DVec3; 3]>,
) -> usize {
    let Some(l) = light_above(light, plane) else {
        return 0;
    };
    // Clip: h(p) >= 0, and h(p) <= (1 - margin) h(L) for a light at a point.
    let mut polygon: Vec<DVec3> = t.to_vec();
    polygon = clip(&polygon, |p| plane.distance(p));
    if l.w != 0.0 {
        let ceiling = plane.distance(l.truncate()) * (1.0 - LIGHT_HEIGHT_MARGIN);
        polygon = clip(&polygon, |p| ceiling - plane.distance(p));
    }
    // A part lying in the plane (the receiver's own face, a caster's base on it) is its own
    // shadow: it adds nothing.
    let scale = 1.0 + t.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
    if polygon.len() < 3 || polygon.iter().all(|p| plane.distance(*p) <= 1e-9 * scale) {
        return 0;
    }
    let project = |p: DVec3| -> DVec3 {
        let h = plane.distance(p);
        if l.w == 0.0 {
            let toward = l.truncate();
            p - toward * (h / plane.normal.dot(toward))
        } else {
            let light = l.truncate();
            let hl = plane.distance(light);
            light + (p - light) * (hl / (hl - h))
        }
    };
    let flat: Vec<DVec3> = polygon.iter().map(|p| project(*p)).collect();
    for k in 1..flat.len() - 1 {
        out.push([flat[0], flat[k], flat[k + 1]]);
    }
    flat.len() - 2
}

/// The polygon's part where `f >= 0` (Sutherland-Hodgman against one plane).
fn clip(polygon: &[DVec3], f: impl Fn(DVec3) -> f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        let (fa, fb) = (f(a), f(b));
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            out.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::light::{DirectionalLight, PointLight, SpotLight};

    fn ground() -> Plane {
        Plane::through_point(DVec3::new(0.0, 2.0, 0.0), DVec3::Y)
    }

    /// The point of the plane on the ray from the light (or along its travel) through `p`,
    /// found by intersecting the ray: what a flattened point must be.
    fn ray_hit(light: &Light, plane: &Plane, p: DVec3) -> DVec3 {
        let (origin, dir) = match light {
            Light::Directional(d) => (p, d.direction()),
            Light::Spot(s) => (s.position(), p - s.position()),
            Light::Point(q) => (q.position(), p - q.position()),
        };
        let s = -plane.distance(origin) / plane.normal.dot(dir);
        origin + dir * s
    }

    fn lights() -> Vec<Light> {
        vec![
            Light::Directional(DirectionalLight::new(DVec3::new(0.4, -1.0, 0.3)).unwrap()),
            Light::Point(PointLight::new(DVec3::new(1.0, 12.0, -2.0), 100.0).unwrap()),
            Light::Spot(
                SpotLight::new(
                    DVec3::new(-3.0, 9.0, 1.0),
                    DVec3::new(0.2, -1.0, 0.0),
                    50.0,
                    80.0,
                )
                .unwrap(),
            ),
        ]
    }

    proptest! {
        /// Every flattened vertex lies on the plane, on the light's ray through a point of
        /// the caster's part above the plane (and below the light).
        #[test]
        fn flattened_points_lie_on_the_plane_along_the_light(
            a in prop::array::uniform3(-10.0f64..10.0),
            b in prop::array::uniform3(-10.0f64..10.0),
            c in prop::array::uniform3(-10.0f64..10.0),
            k in 0usize..3,
        ) {
            let light = lights()[k];
            let plane = ground();
            let t = [DVec3::from_array(a), DVec3::from_array(b), DVec3::from_array(c)];
            let mut out = Vec::new();
            flatten_triangle(&light, &plane, t, &mut out);
            let m = flatten_matrix(&light, &plane).unwrap();
            for p in out.iter().flatten() {
                prop_assert!(plane.distance(*p).abs() < 1e-6 * (1.0 + p.length()), "{p}");
            }
            // The matrix and the direct projection agree on the triangle's casting vertices.
            for v in t {
                let h = plane.distance(v);
                let below_light = match light {
                    Light::Directional(_) => true,
                    Light::Point(q) => h < plane.distance(q.position()) * (1.0 - LIGHT_HEIGHT_MARGIN),
                    Light::Spot(s) => h < plane.distance(s.position()) * (1.0 - LIGHT_HEIGHT_MARGIN),
                };
                if h >= 0.0 && below_light {
                    let q = m * v.extend(1.0);
                    prop_assert!(q.w > 0.0);
                    let q = q.truncate() / q.w;
                    let hit = ray_hit(&light, &plane, v);
                    prop_assert!(q.distance(hit) < 1e-6 * (1.0 + hit.length()), "{q} vs {hit}");
                }
            }
        }
    }

    #[test]
    fn parts_below_the_plane_or_above_the_light_cast_nothing() {
        let plane = ground();
        let lamp = Light::Point(PointLight::new(DVec3::new(0.0, 12.0, 0.0), 100.0).unwrap());
        let mut out = Vec::new();
        // Wholly below the plane.
        let below = [
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.5, 1.0),
        ];
        assert_eq!(flatten_triangle(&lamp, &plane, below, &mut out), 0);
        // Wholly above the lamp.
        let above = below.map(|p| p + DVec3::new(0.0, 20.0, 0.0));
        assert_eq!(flatten_triangle(&lamp, &plane, above, &mut out), 0);
        // Half below the plane: the part above lands on the plane, inside the shadow of the
        // whole triangle.
        let half = [
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 3.0, 0.0),
        ];
        assert_eq!(flatten_triangle(&lamp, &plane, half, &mut out), 1);
        for p in &out[0] {
            assert!(p.y == 2.0 || (p.y - 2.0).abs() < 1e-12);
        }
        // A light below the plane, or a sun from below, reaches none of its receiving side.
        let under = Light::Point(PointLight::new(DVec3::new(0.0, -5.0, 0.0), 100.0).unwrap());
        assert!(flatten_matrix(&under, &plane).is_none());
        let sun_below = Light::Directional(DirectionalLight::new(DVec3::Y).unwrap());
        assert!(flatten_matrix(&sun_below, &plane).is_none());
        assert_eq!(flatten_triangle(&sun_below, &plane, half, &mut out), 0);
    }

    #[test]
    fn the_receiver_is_the_plane_inside_the_box() {
        let slab = Aabb::new(DVec3::new(-5.0, -1.0, -4.0), DVec3::new(5.0, 2.0, 4.0)).unwrap();
        // The slab's top face.
        let top = PlanarReceiver::new(ground(), &slab, 1e-9).unwrap();
        assert_eq!(top.polygon.len(), 4);
        assert!(top.polygon.iter().all(|p| p.y == 2.0));
        assert_eq!(top.triangles().count(), 2);
        // A tilted plane through the box's centre: a polygon of 3 to 6 vertices on it, each
        // on the box's surface.
        let tilted = Plane::through_point(slab.center(), DVec3::new(1.0, 2.0, 0.5));
        let cut = PlanarReceiver::new(tilted, &slab, 1e-9).unwrap();
        assert!((3..=6).contains(&cut.polygon.len()), "{:?}", cut.polygon);
        for p in &cut.polygon {
            assert!(cut.plane.distance(*p).abs() < 1e-9);
            assert!(slab.contains_point(*p, 1e-9));
        }
        // A plane that misses the box, and one with no normal.
        let above = Plane::through_point(DVec3::new(0.0, 9.0, 0.0), DVec3::Y);
        assert!(PlanarReceiver::new(above, &slab, 1e-9).is_none());
        let none = Plane {
            normal: DVec3::ZERO,
            offset: 1.0,
        };
        assert!(PlanarReceiver::new(none, &slab, 1e-9).is_none());
    }

    #[test]
    fn a_face_in_the_plane_casts_nothing() {
        let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.0)).unwrap());
        let mut out = Vec::new();
        let on = [
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(0.0, 2.0, 1.0),
        ];
        assert_eq!(flatten_triangle(&sun, &ground(), on, &mut out), 0);
    }

    #[test]
    fn a_sun_straight_above_flattens_straight_down() {
        let plane = ground();
        let sun = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
        let mut out = Vec::new();
        let t = [
            DVec3::new(1.0, 5.0, 2.0),
            DVec3::new(3.0, 7.0, 2.0),
            DVec3::new(1.0, 9.0, 4.0),
        ];
        assert_eq!(flatten_triangle(&sun, &plane, t, &mut out), 1);
        assert_eq!(out[0], t.map(|p| p.with_y(2.0)));
    }
}
