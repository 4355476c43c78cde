//! The convex body B of the LiSPSM paper (section 3.3): every point that can matter for the
//! shadows seen by the camera.
//!
//! B is the part of the view frustum inside the scene box (call it P), extended toward the
//! light (to infinity for a directional light, to the light's position for a spot light),
//! and clipped again by the scene box (and, for a spot light, the light frustum).
//!
//! Construction. Extending P toward the light gives E: for a directional light the union of
//! the rays from P toward the light, for a spot light the convex hull of P and the light's
//! position. E is the intersection of two kinds of half-spaces:
//! - the planes of P's faces that face away from the light (the light is on their inner
//!   side): moving toward the light keeps a point inside them;
//! - the silhouette planes: for each edge of the 2D convex hull of P projected into the map
//!   plane (orthographically, or from the light's position), the plane of the light rays
//!   through that edge.
//!
//! So B = (scene box [and light frustum]) clipped by those planes: a handful of plane clips
//! of a box, with no 3D convex hull and no infinite geometry.

use glam::{DVec2, DVec3};

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::frame::Frame;
use crate::geometry::{ConvexPolyhedron, Plane, convex_hull_2d};
use crate::light::Light;
use crate::light_space::{Extents, Projector};
use crate::map::MapSettings;
use crate::technique::SetupInput;

/// The convex body B for a camera, a light and a scene (LiSPSM paper, section 3.3): the view
/// frustum inside the scene box, extended toward the light, clipped by the scene box and, for
/// a spot light, by the light frustum. Empty when the camera sees nothing of the scene (or
/// the spot light sees nothing of the view).
pub fn convex_body_b(camera: &Camera, light: &Light, scene: &SceneBounds) -> ConvexPolyhedron {
    let frame = Frame::new(&SetupInput {
        camera,
        light,
        scene,
        map: MapSettings::default(),
        samples: None,
    });
    focus_body(
        &frame.view_body,
        &frame.region,
        &frame.fixed,
        frame.tolerance,
    )
}

/// The convex body B: `region` (the scene box, or the scene box clipped by the light frustum)
/// clipped by the planes of P extended toward the light. `view_body` is P: the view frustum
/// clipped by the same region. Empty when P is.
pub(crate) fn focus_body(
    view_body: &ConvexPolyhedron,
    region: &ConvexPolyhedron,
    projector: &Projector,
    tolerance: f64,
) -> ConvexPolyhedron {
    if view_body.is_empty() {
        return ConvexPolyhedron::empty();
    }
    let planes = extension_planes(view_body, projector, tolerance);
    region.clip_all(&planes, tolerance)
}

/// The half-spaces whose intersection is P extended toward the light.
pub(crate) fn extension_planes(
    view_body: &ConvexPolyhedron,
    projector: &Projector,
    tolerance: f64,
) -> Vec<Plane> {
    let vertices = view_body.vertices(tolerance);
    let centroid = vertices.iter().copied().sum::<glam::DVec3>() / vertices.len().max(1) as f64;
    let mut planes: Vec<Plane> = view_body
        .bounding_planes(centroid, tolerance)
        .into_iter()
        .filter(|plane| match projector {
            // Inward normal m: moving toward the light (-forward) stays inside iff m . forward < 0.
            Projector::Parallel(frame) => plane.normal.dot(frame.forward) < -1e-12,
            // The light's position lies on the plane's inner side.
            Projector::Point { position, .. } => plane.distance(*position) > tolerance,
        })
        .collect();
    let projected: Vec<DVec2> = vertices
        .iter()
        .map(|p| projector.project(*p).truncate())
        .collect();
    let hull = convex_hull_2d(&projected);
    if hull.len() >= 3 {
        for (k, &i) in hull.iter().enumerate() {
            let (a, b) = (projected[i], projected[hull[(k + 1) % hull.len()]]);
            // An edge too short to have a direction bounds nothing that its neighbours do
            // not (leaving a silhouette plane out only enlarges B, which stays safe).
            if a.distance(b) <= tolerance {
                continue;
            }
            // Counter-clockwise hull: the inside is to the left of a -> b.
            let inward = (b - a).perp();
            if let Some(plane) = projector.plane_from_line(inward, -inward.dot(a)) {
                planes.push(plane);
            }
        }
    }
    planes
}

/// B's extents under `projector`, or `None` when B is empty or does not hold the visible
/// receivers (a flat or numerically broken body: it is then not used).
pub(crate) fn usable_body_extents(
    body: &[DVec3],
    projector: &Projector,
    receivers: &Extents,
    tolerance: f64,
) -> Option<Extents> {
    if body.is_empty() {
        return None;
    }
    let ext = projector.points_extents(body);
    let slack = 1e-6 * (receivers.max.z - receivers.min.z) + tolerance;
    (ext.min.z <= receivers.min.z + slack).then_some(ext)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::boxes::Aabb;
    use crate::camera::Lens;
    use crate::light::{DirectionalLight, SpotLight};

    /// Camera at the origin looking down -Z, 90 degrees, square, near 1, far 10: the frustum's
    /// cross-section at depth d is [-d, d]^2.
    fn camera() -> Camera {
        let lens = Lens {
            fov_y_degrees: 90.0,
            aspect: 1.0,
            near: 1.0,
            far: 10.0,
        };
        Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, lens).unwrap()
    }

    fn scene(half: f64) -> SceneBounds {
        SceneBounds::new(
            vec![],
            vec![],
            Some(Aabb::new(DVec3::splat(-half), DVec3::splat(half)).unwrap()),
        )
        .unwrap()
    }

    fn directional(x: f64, y: f64, z: f64) -> Light {
        Light::Directional(DirectionalLight::new(DVec3::new(x, y, z)).unwrap())
    }

    /// Asserts that the vertex sets are equal (within 1e-6).
    fn assert_vertices(body: &ConvexPolyhedron, expected: &[DVec3]) {
        let got = body.vertices(1e-9);
        let missing: Vec<_> = expected
            .iter()
            .filter(|e| !got.iter().any(|g| g.distance(**e) < 1e-6))
            .collect();
        let extra: Vec<_> = got
            .iter()
            .filter(|g| !expected.iter().any(|e| g.distance(*e) < 1e-6))
            .collect();
        assert!(
            missing.is_empty() && extra.is_empty(),
            "missing {missing:?}, extra {extra:?}, got {got:?}"
        );
    }

    /// The corners (+-x, +-y, z).
    fn quad(x: f64, y: f64, z: f64) -> Vec<DVec3> {
        let mut v = Vec::new();
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                v.push(DVec3::new(sx * x, sy * y, z));
            }
        }
        v
    }

    #[test]
    fn frustum_inside_box_light_straight_down() {
        // B = the frustum swept up to the box's top: its bottom face (y = z) and the
        // trapezoid of its footprint at y = 100.
        let body = convex_body_b(&camera(), &directional(0.0, -1.0, 0.0), &scene(100.0));
        let mut expected = Vec::new();
        for (d, y) in [(1.0, -1.0), (10.0, -10.0)] {
            for sx in [-1.0, 1.0] {
                expected.push(DVec3::new(sx * d, y, -d));
                expected.push(DVec3::new(sx * d, 100.0, -d));
            }
        }
        assert_vertices(&body, &expected);
    }

    #[test]
    fn box_inside_frustum_is_its_own_body() {
        let lens = Lens {
            fov_y_degrees: 90.0,
            aspect: 1.0,
            near: 0.1,
            far: 100.0,
        };
        let cam = Camera::look_at(DVec3::new(0.0, 0.0, 10.0), DVec3::ZERO, DVec3::Y, lens).unwrap();
        for light in [
            directional(1.0, -2.0, 0.5),
            directional(0.0, 0.0, 1.0),
            directional(0.0, -1.0, 0.0),
        ] {
            let body = convex_body_b(&cam, &light, &scene(1.0));
            assert_vertices(
                &body,
                &Aabb::new(DVec3::splat(-1.0), DVec3::ONE).unwrap().corners(),
            );
        }
    }

    #[test]
    fn light_along_the_view_axis() {
        // Light travelling with the view (from behind the camera): the far face swept back
        // toward the light to the box's face at z = 100.
        let body = convex_body_b(&camera(), &directional(0.0, 0.0, -1.0), &scene(100.0));
        let mut expected = quad(10.0, 10.0, -10.0);
        expected.extend(quad(10.0, 10.0, 100.0));
        assert_vertices(&body, &expected);
        // Light shining into the camera: the frustum stays and its far face is swept away
        // from the camera to the box's face at z = -100 (the far corners stay vertices: the
        // frustum's sides bend into the prism's there).
        let body = convex_body_b(&camera(), &directional(0.0, 0.0, 1.0), &scene(100.0));
        let mut expected = quad(1.0, 1.0, -1.0);
        expected.extend(quad(10.0, 10.0, -10.0));
        expected.extend(quad(10.0, 10.0, -100.0));
        assert_vertices(&body, &expected);
    }

    #[test]
    fn box_cuts_the_extension() {
        // A box whose top is at y = 4 cuts both the frustum and the sweep: B is the part of
        // the frustum below y = 4 (inside |x| <= 100) swept up to y = 4.
        let scene = SceneBounds::new(
            vec![],
            vec![],
            Some(
                Aabb::new(
                    DVec3::new(-100.0, -100.0, -100.0),
                    DVec3::new(100.0, 4.0, 100.0),
                )
                .unwrap(),
            ),
        )
        .unwrap();
        let body = convex_body_b(&camera(), &directional(0.0, -1.0, 0.0), &scene);
        let mut expected = Vec::new();
        for (d, y) in [(1.0, -1.0), (10.0, -10.0)] {
            for sx in [-1.0, 1.0] {
                expected.push(DVec3::new(sx * d, y, -d));
                expected.push(DVec3::new(sx * d, 4.0, -d));
            }
        }
        assert_vertices(&body, &expected);
    }

    #[test]
    fn spot_light_that_sees_part_of_the_frustum() {
        // A narrow spot above the frustum pointing down: its pyramid is |x| <= 0.1 d,
        // |z + 5| <= 0.1 d with d = 20 - y. Inside the view frustum (|x|, |y| <= -z) the lowest
        // point is y = z = -70/9; the largest z is -30/11 (on the bottom plane y = z); the
        // widest x is 0.1 (20 + 70/9) = 25/9; the top is the light's near plane.
        let spot = SpotLight::new(
            DVec3::new(0.0, 20.0, -5.0),
            -DVec3::Y,
            0.1f64.atan().to_degrees(),
            40.0,
        )
        .unwrap();
        let light = Light::Spot(spot);
        let body = convex_body_b(&camera(), &light, &scene(100.0));
        assert!(!body.is_empty());
        let v = body.vertices(1e-9);
        let min = v.iter().copied().reduce(DVec3::min).unwrap();
        let max = v.iter().copied().reduce(DVec3::max).unwrap();
        let expected_min = DVec3::new(-25.0 / 9.0, -70.0 / 9.0, -70.0 / 9.0);
        let expected_max = DVec3::new(25.0 / 9.0, 20.0 - spot.near(), -30.0 / 11.0);
        assert!(
            (min - expected_min).abs().max_element() < 1e-6,
            "min {min}, expected {expected_min}"
        );
        assert!(
            (max - expected_max).abs().max_element() < 1e-6,
            "max {max}, expected {expected_max}"
        );
        // Every vertex is inside the spot light's frustum.
        let up = crate::light_space::fixed_projector(&light).frame().up;
        for p in &v {
            assert!(
                spot.frustum_planes(up)
                    .iter()
                    .all(|pl| pl.distance(*p) > -1e-9)
            );
        }
    }

    #[test]
    fn camera_looking_away_from_the_scene_gives_empty_body() {
        let cam = Camera::look_at(
            DVec3::new(0.0, 0.0, 50.0),
            DVec3::new(0.0, 0.0, 100.0),
            DVec3::Y,
            camera().lens(),
        )
        .unwrap();
        let body = convex_body_b(&cam, &directional(0.0, -1.0, 0.0), &scene(10.0));
        assert!(body.is_empty());
    }
}
