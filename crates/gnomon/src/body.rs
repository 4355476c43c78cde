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

use glam::DVec2;

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::focus::VisibleScene;
use crate::geometry::{ConvexPolyhedron, Plane, convex_hull_2d};
use crate::light::Light;
use crate::light_space::Projector;
use crate::techniques::{fixed_projector, tolerance};

/// The convex body B for a camera, a light and a scene (LiSPSM paper, section 3.3): the view
/// frustum inside the scene box, extended toward the light, clipped by the scene box and, for
/// a spot light, by the light frustum. Empty when the camera sees nothing of the scene (or
/// the spot light sees nothing of the view).
pub fn convex_body_b(camera: &Camera, light: &Light, scene: &SceneBounds) -> ConvexPolyhedron {
    let tolerance = tolerance(scene, Some(camera), light);
    let projector = fixed_projector(light);
    let light_planes = match light {
        Light::Directional(_) => None,
        Light::Spot(spot) => Some(spot.frustum_planes(projector.frame().up)),
    };
    let visible = VisibleScene::new(camera, scene, light_planes.as_ref(), tolerance);
    let region = ConvexPolyhedron::from_box(&scene.scene_box()).clip_all(light_planes.iter().flatten(), tolerance);
    focus_body(&visible.view_body, &region, &projector, tolerance)
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
pub(crate) fn extension_planes(view_body: &ConvexPolyhedron, projector: &Projector, tolerance: f64) -> Vec<Plane> {
    let mut planes: Vec<Plane> = view_body
        .bounding_planes(tolerance)
        .into_iter()
        .filter(|plane| match projector {
            // Inward normal m: moving toward the light (-forward) stays inside iff m . forward < 0.
            Projector::Parallel(frame) => plane.normal.dot(frame.forward) < -1e-12,
            // The light's position lies on the plane's inner side.
            Projector::Point { position, .. } => plane.distance(*position) > tolerance,
        })
        .collect();
    let vertices = view_body.vertices(tolerance);
    let projected: Vec<DVec2> = vertices.iter().map(|p| projector.project(*p).truncate()).collect();
    let hull = convex_hull_2d(&projected);
    if hull.len() >= 3 {
        for (k, &i) in hull.iter().enumerate() {
            let (a, b) = (projected[i], projected[hull[(k + 1) % hull.len()]]);
            // Counter-clockwise hull: the inside is to the left of a -> b.
            let inward = (b - a).perp();
            if let Some(plane) = projector.plane_from_line(inward, -inward.dot(a)) {
                planes.push(plane);
            }
        }
    }
    planes
}
