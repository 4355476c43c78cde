//! Shadow-volume geometry for one light, and the camera projection that keeps it unclipped.

use glam::{DMat4, DVec3, DVec4};

use crate::camera::Lens;
use crate::light::Light;
use crate::volumes::MeshTopology;

/// How many triangles of each kind a volume got.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct VolumeCounts {
    /// Light-facing triangles, in place (the light cap).
    pub light_cap: usize,
    /// Back-facing triangles at infinity (the dark cap; none for a directional light, whose
    /// volume closes at one point at infinity).
    pub dark_cap: usize,
    /// Triangles of the silhouette quads extruded to infinity (one per edge for a directional
    /// light, where the quad's far edge is a single point).
    pub sides: usize,
}

/// Which parts of a volume to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VolumeParts {
    /// The closed volume: light cap, dark cap and sides (what z-fail counts).
    #[default]
    Closed,
    /// The sides only: enough for z-pass where the volume cannot reach the near plane (the
    /// light cap lies on the caster's own surface and the dark cap at infinity, so neither
    /// is ever in front of a visible surface).
    SidesOnly,
}

impl VolumeCounts {
    /// All triangles.
    pub fn total(&self) -> usize {
        self.light_cap + self.dark_cap + self.sides
    }
}

/// Appends to `out` the shadow volume of `mesh`, placed by `world_from_object` (any
/// invertible affine map), for `light` (a spot light shadows as the point light at its
/// position; its cone limits what it lights, not its volumes): three homogeneous world
/// vertices per triangle, each triangle counter-clockwise seen from outside the volume.
///
/// A point p goes to infinity away from the light as the direction (p - light, 0) (point
/// light) or (direction of travel, 0) (directional light). A closed mesh gives the light cap
/// (light-facing triangles), the dark cap (back-facing triangles at infinity) and one
/// extruded quad per possible silhouette edge (an edge between a light-facing and a
/// back-facing triangle). A mesh kept for per-triangle volumes
/// ([`crate::volumes::OpenMeshPolicy::PerTriangle`]) gives every triangle not edge-on to
/// the light a closed volume of its own, seen from the side the light sees. So does a closed
/// mesh that encloses a point light (a lamp inside a closed caster). No triangle faces the
/// light there, so the light cap, the silhouette and the closed volume's construction are
/// empty, while each triangle's own volume shadows what lies outside it. With
/// [`VolumeParts::SidesOnly`] the caps are left out.
pub fn extrude_volume(
    mesh: &MeshTopology,
    world_from_object: DMat4,
    light: &Light,
    parts: VolumeParts,
    out: &mut Vec<DVec4>,
) -> VolumeCounts {
    let caps = parts == VolumeParts::Closed;
    let world: Vec<DVec3> = mesh
        .positions()
        .iter()
        .map(|p| world_from_object.transform_point3(*p))
        .collect();
    // A mirroring placement turns the winding over.
    let mirrored = world_from_object.determinant() < 0.0;
    let (point, travel) = match light {
        Light::Directional(d) => (None, d.direction()),
        Light::Spot(s) => (Some(s.position()), DVec3::ZERO),
        Light::Point(p) => (Some(p.position()), DVec3::ZERO),
    };
    let to_infinity = |p: DVec3| match point {
        Some(c) => (p - c).extend(0.0),
        None => travel.extend(0.0),
    };
    // n . (direction toward the light), with the winding's normal n.
    let facing_amount = |[a, b, c]: [DVec3; 3]| {
        let n = (b - a).cross(c - a);
        let toward = match point {
            Some(position) => position - a,
            None => -travel,
        };
        let s = n.dot(toward);
        if mirrored { -s } else { s }
    };
    let mut emit = |tri: [DVec4; 3]| {
        if mirrored {
            out.extend([tri[0], tri[2], tri[1]]);
        } else {
            out.extend(tri);
        }
    };
    let mut counts = VolumeCounts::default();
    let side = |a: DVec3, b: DVec3, emit: &mut dyn FnMut([DVec4; 3])| {
        let (ea, eb) = (to_infinity(a), to_infinity(b));
        if point.is_some() {
            emit([a.extend(1.0), ea, eb]);
            emit([a.extend(1.0), eb, b.extend(1.0)]);
            2
        } else {
            emit([a.extend(1.0), ea, b.extend(1.0)]);
            1
        }
    };
    let corners = |tri: &[u32; 3]| tri.map(|k| world[k as usize]);

    let encloses_light = point.is_some_and(|c| mesh.is_closed() && encloses(mesh, &world, c));
    if mesh.is_closed() && !encloses_light {
        let facing: Vec<bool> = mesh
            .triangles()
            .iter()
            .map(|tri| facing_amount(corners(tri)) > 0.0)
            .collect();
        for (tri, &lit) in mesh.triangles().iter().zip(&facing).filter(|_| caps) {
            let p = corners(tri);
            if lit {
                emit(p.map(|q| q.extend(1.0)));
                counts.light_cap += 1;
            } else if point.is_some() {
                emit(p.map(to_infinity));
                counts.dark_cap += 1;
            }
        }
        for (a, b) in mesh.silhouette_edges(&facing) {
            counts.sides += side(world[a as usize], world[b as usize], &mut emit);
        }
    } else {
        for tri in mesh.triangles() {
            let p = corners(tri);
            let amount = facing_amount(p);
            if amount == 0.0 || amount.is_nan() {
                continue;
            }
            // Seen from the side the light sees: wound toward the light.
            let p = if amount > 0.0 { p } else { [p[0], p[2], p[1]] };
            if caps {
                emit(p.map(|q| q.extend(1.0)));
                counts.light_cap += 1;
            }
            if caps && point.is_some() {
                emit([to_infinity(p[0]), to_infinity(p[2]), to_infinity(p[1])]);
                counts.dark_cap += 1;
            }
            for i in 0..3 {
                counts.sides += side(p[i], p[(i + 1) % 3], &mut emit);
            }
        }
    }
    counts
}

/// Whether the closed mesh (vertices `world`) encloses `p`: its winding number about `p`, the
/// sum of the triangles' signed solid angles over 4 pi (Van Oosterom and Strackee's formula),
/// is 1 inside and 0 outside, whatever the winding's sense. Points outside the mesh's bounds
/// are rejected first.
fn encloses(mesh: &MeshTopology, world: &[DVec3], p: DVec3) -> bool {
    let (lo, hi) = world
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), q| {
            (lo.min(*q), hi.max(*q))
        });
    if p.cmplt(lo).any() || p.cmpgt(hi).any() {
        return false;
    }
    let total: f64 = mesh
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| world[k as usize] - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total.abs() > 2.0 * std::f64::consts::PI
}

/// View to clip space with the far plane at infinity (depth in [0, 1], as wgpu wants):
/// z_clip = (1 - epsilon) (-z_view - near), w = -z_view. Depth is 0 at the near plane and
/// tends to 1 - epsilon at infinity, so points at infinity (w = 0 in world space) land
/// inside the depth range and are never clipped (Everitt and Kilgard's P_inf with their
/// epsilon against round-off). The rest as [`crate::Camera::clip_from_view`].
pub fn infinite_clip_from_view(lens: &Lens, epsilon: f64) -> DMat4 {
    let cot = 1.0 / (0.5 * lens.fov_y_degrees.to_radians()).tan();
    let a = 1.0 - epsilon;
    DMat4::from_cols(
        DVec4::new(cot / lens.aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, cot, 0.0, 0.0),
        DVec4::new(0.0, 0.0, -a, -1.0),
        DVec4::new(0.0, 0.0, -a * lens.near, 0.0),
    )
}

/// View to clip space with the far plane at infinity and reversed depth: z_clip = near w,
/// w_clip = -z_view, so depth = near / distance: 1 at the near plane and exactly 0 for points
/// at infinity (w = 0), with no epsilon. Compare with `Greater` and clear depth to 0; a float
/// depth buffer then keeps its relative precision at every distance. The rest as
/// [`crate::Camera::clip_from_view`].
pub fn reversed_infinite_clip_from_view(lens: &Lens) -> DMat4 {
    let cot = 1.0 / (0.5 * lens.fov_y_degrees.to_radians()).tan();
    DMat4::from_cols(
        DVec4::new(cot / lens.aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, cot, 0.0, 0.0),
        DVec4::new(0.0, 0.0, 0.0, -1.0),
        DVec4::new(0.0, 0.0, lens.near, 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{DirectionalLight, SpotLight};
    use crate::volumes::OpenMeshPolicy;

    #[test]
    fn reversed_infinite_projection_puts_infinity_at_zero_and_the_near_plane_at_one() {
        let lens = Lens {
            fov_y_degrees: 60.0,
            aspect: 1.5,
            near: 0.25,
            far: 100.0,
        };
        let p = reversed_infinite_clip_from_view(&lens);
        let depth = |v: DVec4| {
            let c = p * v;
            c.z / c.w
        };
        assert_eq!(depth(DVec4::new(0.0, 0.0, -0.25, 1.0)), 1.0);
        assert!((depth(DVec4::new(0.3, -0.2, -2.5, 1.0)) - 0.1).abs() < 1e-15);
        // A direction (w = 0): exactly 0, whatever its length.
        let c = p * DVec4::new(0.1, 0.2, -1.0, 0.0);
        assert_eq!(c.z, 0.0);
        assert!(c.w > 0.0);
        // x and y as the finite projection.
        let finite = infinite_clip_from_view(&lens, 0.0);
        let v = DVec4::new(1.0, -2.0, -7.0, 1.0);
        assert_eq!(
            (p * v).truncate().truncate(),
            (finite * v).truncate().truncate()
        );
    }

    #[test]
    fn a_point_light_inside_a_closed_mesh_gets_one_volume_per_triangle() {
        let mesh = tetrahedron();
        let inside = Light::Spot(
            SpotLight::new(DVec3::new(0.2, 0.2, -0.2), DVec3::NEG_Y, 60.0, 10.0).unwrap(),
        );
        let outside = Light::Spot(
            SpotLight::new(DVec3::new(0.2, 3.0, -0.2), DVec3::NEG_Y, 60.0, 10.0).unwrap(),
        );
        let mut out = Vec::new();
        // Inside: every triangle its own closed volume (cap, dark cap, three quads).
        let counts = extrude_volume(
            &mesh,
            DMat4::IDENTITY,
            &inside,
            VolumeParts::Closed,
            &mut out,
        );
        assert_eq!(
            (counts.light_cap, counts.dark_cap, counts.sides),
            (4, 4, 24),
            "{counts:?}"
        );
        // Moved by a placement (mirrored too), the same.
        let mirror = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let moved = Light::Spot(
            SpotLight::new(DVec3::new(-0.2, 0.2, -0.2), DVec3::NEG_Y, 60.0, 10.0).unwrap(),
        );
        let counts = extrude_volume(&mesh, mirror, &moved, VolumeParts::Closed, &mut out);
        assert_eq!(counts.light_cap, 4, "{counts:?}");
        // Outside: the one closed volume (light cap and dark cap split the four faces).
        let counts = extrude_volume(
            &mesh,
            DMat4::IDENTITY,
            &outside,
            VolumeParts::Closed,
            &mut out,
        );
        assert_eq!(counts.light_cap + counts.dark_cap, 4, "{counts:?}");
        assert!(counts.sides < 24, "{counts:?}");
        // The winding number: inside, outside, outside the bounds.
        let world = mesh.positions().to_vec();
        assert!(encloses(&mesh, &world, DVec3::new(0.2, 0.2, -0.2)));
        assert!(!encloses(&mesh, &world, DVec3::new(0.6, 0.6, -0.6)));
        assert!(!encloses(&mesh, &world, DVec3::new(0.2, 3.0, -0.2)));
    }

    /// A tetrahedron, counter-clockwise from outside.
    fn tetrahedron() -> MeshTopology {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let i = [0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3];
        MeshTopology::new(&p, &i, OpenMeshPolicy::Reject).unwrap()
    }

    /// Signed volume of the triangles' cone from a point: positive when they bound the
    /// point's region outward (finite triangles only).
    fn winding_number_times_volume(tris: &[DVec4], from: DVec3, far: f64) -> f64 {
        // Replace points at infinity by points far along their direction.
        let finite = |v: DVec4| {
            if v.w == 0.0 {
                v.truncate().normalize() * far
            } else {
                v.truncate() / v.w
            }
        };
        tris.chunks(3)
            .map(|t| {
                let [a, b, c] = [
                    finite(t[0]) - from,
                    finite(t[1]) - from,
                    finite(t[2]) - from,
                ];
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn volumes_are_closed_and_outward() {
        let mesh = tetrahedron();
        let lights = [
            Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.2)).unwrap()),
            Light::Spot(SpotLight::new(DVec3::new(0.4, 5.0, -0.3), -DVec3::Y, 60.0, 50.0).unwrap()),
        ];
        for light in &lights {
            for policy in [OpenMeshPolicy::Reject, OpenMeshPolicy::PerTriangle] {
                let mut tris = Vec::new();
                let counts = if policy == OpenMeshPolicy::Reject {
                    extrude_volume(
                        &mesh,
                        DMat4::IDENTITY,
                        light,
                        VolumeParts::Closed,
                        &mut tris,
                    )
                } else {
                    // Per-triangle volumes of the same (closed) mesh, forced.
                    let p: Vec<DVec3> = mesh.positions().to_vec();
                    let open: Vec<u32> = mesh.triangles()[..3].iter().flatten().copied().collect();
                    let m = MeshTopology::new(&p, &open, OpenMeshPolicy::PerTriangle).unwrap();
                    assert!(!m.is_closed());
                    extrude_volume(&m, DMat4::IDENTITY, light, VolumeParts::Closed, &mut tris)
                };
                assert_eq!(tris.len(), 3 * counts.total());
                // Every edge of the volume is used once in each direction (closed, consistent).
                let key = |v: DVec4| {
                    let v = if v.w == 0.0 {
                        v.truncate().normalize().extend(0.0)
                    } else {
                        v
                    };
                    v.to_array().map(|x| (x * 1e9).round() as i64)
                };
                let mut edges = std::collections::HashMap::new();
                for t in tris.chunks(3) {
                    for i in 0..3 {
                        let (a, b) = (key(t[i]), key(t[(i + 1) % 3]));
                        if a != b {
                            *edges.entry((a, b)).or_insert(0i32) += 1;
                            *edges.entry((b, a)).or_insert(0i32) -= 1;
                        }
                    }
                }
                assert!(
                    edges.values().all(|&n| n == 0),
                    "{light:?} {policy:?}: open volume"
                );
                // Outward: the signed volume seen from a point inside the shadow is positive.
                let below = DVec3::new(0.2, -3.0, -0.2);
                let v = winding_number_times_volume(&tris, below, 1e3);
                assert!(v > 0.0, "{light:?} {policy:?}: volume {v}");
            }
        }
    }

    #[test]
    fn sides_only_leaves_out_both_caps() {
        let mesh = tetrahedron();
        let spot =
            Light::Spot(SpotLight::new(DVec3::new(0.4, 5.0, -0.3), -DVec3::Y, 60.0, 50.0).unwrap());
        let (mut closed, mut sides) = (Vec::new(), Vec::new());
        let all = extrude_volume(
            &mesh,
            DMat4::IDENTITY,
            &spot,
            VolumeParts::Closed,
            &mut closed,
        );
        let only = extrude_volume(
            &mesh,
            DMat4::IDENTITY,
            &spot,
            VolumeParts::SidesOnly,
            &mut sides,
        );
        assert!(
            all.light_cap > 0 && all.dark_cap > 0 && all.sides > 0,
            "{all:?}"
        );
        assert_eq!(
            only,
            VolumeCounts {
                light_cap: 0,
                dark_cap: 0,
                sides: all.sides
            }
        );
        // The same side triangles, in the same order.
        assert_eq!(&closed[closed.len() - sides.len()..], &sides[..]);
    }

    #[test]
    fn mirrored_placement_keeps_volumes_outward() {
        let mesh = tetrahedron();
        let light = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
        let mirror = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let mut tris = Vec::new();
        let counts = extrude_volume(&mesh, mirror, &light, VolumeParts::Closed, &mut tris);
        assert_eq!(counts.light_cap, 1, "only the slanted face looks up");
        let v = winding_number_times_volume(&tris, DVec3::new(-0.2, -3.0, -0.2), 1e3);
        assert!(v > 0.0, "{v}");
    }

    #[test]
    fn infinite_projection_keeps_infinity_inside_the_depth_range() {
        let lens = Lens::default();
        let m = infinite_clip_from_view(&lens, 1e-6);
        let near = m * DVec4::new(0.0, 0.0, -lens.near, 1.0);
        assert!((near.z / near.w).abs() < 1e-12);
        let at_infinity = m * DVec4::new(0.1, 0.2, -1.0, 0.0);
        let z = at_infinity.z / at_infinity.w;
        assert!(z < 1.0 && z > 1.0 - 1e-5, "{z}");
        let far = m * DVec4::new(0.0, 0.0, -1e6, 1.0);
        assert!(far.z / far.w < z);
    }
}
