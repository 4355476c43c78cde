//! A point light's maps, one per cube face: the faces share the point light's frame, and each
//! face is set up as a spot light looking along its axis (see [`crate::Cube`]).

use crate::body::{focus_body, usable_body_extents};
use crate::diagnostics::{Diagnostics, Fallback};
use crate::error::SetupError;
use crate::focus::{FaceFrustum, FaceImages, unit_cube_clip, walk_casters};
use crate::frame::Frame;
use crate::geometry::ConvexPolyhedron;
use crate::light::{CubeFace, Light, PointLight, SpotLight, cube_face_tangent};
use crate::light_space::fixed_projector;
use crate::light_space::{AxisFrustum, Extents, build_map};
use crate::map::{CubeFaceMaps, MapSelection, ShadowSetup};
use crate::samples::ViewSamples;
use crate::technique::SetupInput;
use crate::techniques::ANGULAR_PADDING;
use crate::techniques::basis::{FocusBasis, Part};

/// The setup of technique `name` for a point light: its map of each face (see the module
/// documentation), `fit` making it on the face's basis (for the face's spot light). The
/// faces share the point light's frame: P and the receivers' classification against the
/// view are made once and cut by each face's frustum.
pub(crate) fn per_face(
    name: &'static str,
    input: &SetupInput<'_>,
    point: &PointLight,
    fit: impl Fn(&SetupInput<'_>, &FocusBasis<'_>) -> Result<ShadowSetup, SetupError>,
) -> Result<ShadowSetup, SetupError> {
    faces(name, input, point, false, fit)
}

/// [`per_face`], with each face's focused map made by [`focused_face`] where it can
/// (`quick`).
pub(crate) fn faces(
    name: &'static str,
    input: &SetupInput<'_>,
    point: &PointLight,
    quick: bool,
    fit: impl Fn(&SetupInput<'_>, &FocusBasis<'_>) -> Result<ShadowSetup, SetupError>,
) -> Result<ShadowSetup, SetupError> {
    input.map.validate()?;
    let view = Frame::new(input);
    let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
    let mut maps = Vec::new();
    let mut faces = CubeFaceMaps::new(point.position());
    // The face's setup, or `None` where it has nothing to shadow (or, unless `always`, where
    // its frustum does not meet the view).
    let face_setup = |face: CubeFace, always: bool| -> Result<Option<ShadowSetup>, SetupError> {
        let spot = point.face_light(face, input.map.resolution);
        let light = Light::Spot(spot);
        if quick
            && !always
            && let Some(setup) = focused_face(&view, input, &spot)
        {
            return Ok(setup);
        }
        // The face's share of the view samples (cast for the point light on first use),
        // which its warp limit judges on.
        let face_samples = face_share(view.samples(), point, face, input.map.resolution);
        let face_input = SetupInput {
            light: &light,
            samples: Some(&face_samples),
            ..*input
        };
        let frame = Frame::of_face(&view, &face_input);
        if frame.view_body.is_empty() && !always {
            return Ok(None);
        }
        let basis = FocusBasis::new(&frame, Part::Whole);
        let setup = fit(&face_input, &basis)?;
        if setup.maps.len() != 1 || setup.selection != MapSelection::Single {
            return Err(SetupError::PointLightUnsupported { technique: name });
        }
        Ok((always || !nothing_to_shadow(&setup)).then_some(setup))
    };
    for face in CubeFace::ALL {
        let Some(setup) = face_setup(face, false)? else {
            diagnostics.cube_faces_skipped += 1;
            continue;
        };
        add_face(&mut diagnostics, &setup.diagnostics);
        diagnostics.maps.push(setup.map_diagnostics(0));
        faces.push(face);
        maps.push(setup.maps[0]);
    }
    if maps.is_empty() {
        // Nothing visible can be shadowed: the first face keeps its (fallback) map, so that
        // a setup always has one.
        let face = CubeFace::ALL[0];
        let setup = face_setup(face, true)?.expect("made when asked always");
        diagnostics.cube_faces_skipped -= 1;
        add_face(&mut diagnostics, &setup.diagnostics);
        diagnostics.maps.push(setup.map_diagnostics(0));
        faces.push(face);
        maps.push(setup.maps[0]);
    }
    // Each receiver counts once, whichever faces see it.
    diagnostics.visible_receivers = view.visible().visible_receivers();
    Ok(ShadowSetup {
        technique: name,
        maps,
        selection: MapSelection::CubeFaces(faces),
        diagnostics,
    })
}

/// The focused map with unit cube clipping of one face (`spot`, its spot light), fitted
/// straight from the point light's frame `view` rather than from a frame of the face: the
/// view's visible receiver parts and the casters are taken under the face's projector. The
/// image of a box's part inside the face's frustum is a closed form ([`AxisFrustum`]: the
/// face's frame has world axes), so no box is cut; a receiver part that several view planes
/// cut is cut by the frustum's planes where its image would add to the extents.
/// `Some(None)` when the face has nothing to shadow (no visible receiver, or no caster for
/// them); `None` where the face needs its own frame (below).
///
/// B is built only where the light stands outside the scene box: inside it (the corners of
/// the face's near plane inside the box) B reaches the face's near plane (the segments from
/// the light to P run in it), so it cannot raise the map's near plane above the casters'.
/// Outside, B is the face's own frame's (the scene box in the face's frustum cut by the
/// face's P extended toward the light). `None` only where the face's frame does not have
/// world axes.
fn focused_face(
    view: &Frame<'_>,
    input: &SetupInput<'_>,
    spot: &SpotLight,
) -> Option<Option<ShadowSetup>> {
    let light = Light::Spot(*spot);
    let projector = fixed_projector(&light);
    let up = projector.frame().up;
    let (tolerance, scene) = (view.tolerance, input.scene);
    let (d, t) = (spot.direction(), spot.half_angle().tan());
    let right = d.cross(up).normalize();
    let up = right.cross(d);
    let center = spot.position() + spot.near() * d;
    let scene_box = scene.scene_box();
    let near_inside = [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
        .iter()
        .all(|(a, b)| {
            let corner = center + spot.near() * t * (a * right + b * up);
            scene_box.contains_point(corner, -tolerance)
        });
    let axis = AxisFrustum::new(
        projector.frame(),
        spot.position(),
        t,
        spot.near(),
        spot.range(),
    )?;
    let frustum = FaceFrustum {
        planes: spot.frustum_planes(projector.frame().up),
        axis,
    };
    let mut diagnostics = Diagnostics::new(input.camera, &light, scene);
    let receivers = if view.view_body.is_empty() {
        Extents::EMPTY
    } else {
        view.visible()
            .extents_in_frustum(scene, &view.receiver_planes, &frustum, &projector)
    };
    if receivers.is_empty() {
        return Some(None);
    }
    let body = (!near_inside).then(|| {
        let view_body = view.view_body.clip_all(&frustum.planes, tolerance);
        let region = ConvexPolyhedron::from_box(&scene_box).clip_all(&frustum.planes, tolerance);
        focus_body(&view_body, &region, &projector, tolerance).vertices(tolerance)
    });
    let body_extents = body.map(|body| {
        diagnostics.focus_body_vertices = body.len();
        let extents = usable_body_extents(&body, &projector, &receivers, tolerance);
        if extents.is_none() {
            diagnostics.fallbacks.push(Fallback::DegenerateFocusBody);
        }
        extents
    });
    let images = FaceImages {
        scene,
        projector: &projector,
        frustum: &frustum,
    };
    // The images are of the casters' parts inside the frustum: the walk cuts by the near
    // plane alone, to count the casters it clips.
    let walked = walk_casters(
        scene,
        &images,
        &receivers,
        &frustum.planes[..1],
        true,
        tolerance,
    );
    walked.count_into(scene, &mut diagnostics);
    let Some(region) = unit_cube_clip(&receivers, &walked.extents, body_extents.flatten().as_ref())
    else {
        return Some(None);
    };
    Some(Some(ShadowSetup {
        technique: "cube",
        maps: vec![build_map(
            &projector,
            &region,
            input.map,
            ANGULAR_PADDING,
            tolerance,
        )],
        selection: MapSelection::Single,
        diagnostics,
    }))
}

/// Whether a face's setup has nothing to shadow (no visible receiver, or no caster for
/// them): the face is skipped.
fn nothing_to_shadow(setup: &ShadowSetup) -> bool {
    setup.diagnostics.fallbacks.iter().any(|f| {
        matches!(
            f,
            Fallback::NoVisibleReceiver
                | Fallback::SpotLightMissesView
                | Fallback::NoCasterForReceivers
        )
    })
}

/// The samples inside the frustum of `face` (for `resolution`-texel maps): its share of the
/// view, which its warp limit judges on.
fn face_share(
    samples: &ViewSamples,
    point: &PointLight,
    face: CubeFace,
    resolution: u32,
) -> ViewSamples {
    let (axis, t) = (face.axis(), cube_face_tangent(resolution));
    samples.filtered(|s| {
        let d = s.position - point.position();
        let along = d.dot(axis);
        along > 0.0 && (d - along * axis).abs().max_element() <= t * along
    })
}

/// The point light of `input` for a technique that takes point lights only.
pub(crate) fn point_light_only<'a>(
    input: &SetupInput<'a>,
    technique: &'static str,
) -> Result<&'a PointLight, SetupError> {
    input.map.validate()?;
    match input.light {
        Light::Point(point) => Ok(point),
        _ => Err(SetupError::NeedsPointLight { technique }),
    }
}

/// Adds one face's counts and fallbacks to the point light's diagnostics.
fn add_face(total: &mut Diagnostics, face: &Diagnostics) {
    for f in &face.fallbacks {
        if !total.fallbacks.contains(f) {
            total.fallbacks.push(*f);
        }
    }
    total.relevant_casters += face.relevant_casters;
    total.culled_casters += face.culled_casters;
    total.casters_clipped_by_light_near += face.casters_clipped_by_light_near;
    total.focus_body_vertices += face.focus_body_vertices;
    total.light_frame = face.light_frame;
    total.warp_strength = match (total.warp_strength, face.warp_strength) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
}

#[cfg(test)]
mod shared_frame_tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::*;
    use crate::bvh::test_scenes;
    use crate::map::MapSettings;
    use crate::setup::compute_setup_with_samples;
    use crate::technique::ShadowTechnique;
    use crate::techniques::{Focused, Lispsm};

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

        /// The faces refined from the point light's shared frame (or, for the focused map,
        /// fitted from it) get the maps that a frame of each face's own spot light gives.
        #[test]
        fn shared_faces_match_faces_set_up_alone(
            boxes in prop::collection::vec((prop::array::uniform3(-40.0f64..40.0), prop::array::uniform3(0.5f64..15.0), 0u8..3), 1..30),
            eye in prop::array::uniform3(-60.0f64..60.0),
            target in prop::array::uniform3(-20.0f64..20.0),
            lamp in prop::array::uniform3(-30.0f64..30.0),
            range in 10.0f64..200.0,
            warp in any::<bool>(),
            above_scene in any::<bool>(),
        ) {
            let scene = test_scenes::mixed(&boxes);
            let camera = test_scenes::camera(eye, target);
            prop_assume!(camera.is_some());
            let camera = camera.unwrap();
            // Inside the scene box or above it: the focused faces are fitted from the point
            // light's frame, with B where it stands outside the box.
            let high = if above_scene { 60.0 } else { 0.0 };
            let position = DVec3::from_array(lamp).with_y(lamp[1].abs() * 0.3 + 0.5 + high);
            let point = PointLight::new(position, range).unwrap();
            let technique: &dyn ShadowTechnique = if warp { &Lispsm::default() as &dyn ShadowTechnique } else { &Focused };
            faces_match_faces_set_up_alone(technique, &camera, &point, &scene)?;
        }

        /// A lamp over the scene box (beside it too) and a narrow view of part of the scene:
        /// B, which the focused faces build from the point light's frame there, raises some
        /// faces' near planes above the nearest caster in their receivers' columns, and every
        /// face gets the map (or is skipped as) its own spot light's frame gives.
        #[test]
        fn faces_of_a_lamp_over_the_scene_match_faces_set_up_alone(
            boxes in prop::collection::vec((prop::array::uniform3(0.0f64..1.0), prop::array::uniform3(0.3f64..6.3)), 3..23),
            lamp in prop::array::uniform3(0.0f64..1.0),
            eye in prop::array::uniform3(0.0f64..1.0),
            target in prop::array::uniform2(-30.0f64..30.0),
            fov in 5.0f64..35.0,
            far in 20.0f64..80.0,
        ) {
            use crate::bounds::SceneBounds;
            use crate::boxes::Aabb;
            use crate::camera::{Camera, Lens};
            let casters: Vec<Aabb> = boxes
                .iter()
                .map(|(lo, size)| {
                    let lo = DVec3::new(lo[0] * 60.0 - 30.0, lo[1] * 15.0, lo[2] * 60.0 - 30.0);
                    Aabb::new(lo, lo + DVec3::from_array(*size)).unwrap()
                })
                .collect();
            let mut receivers = casters.clone();
            receivers.push(Aabb::new(DVec3::new(-40.0, -1.0, -40.0), DVec3::new(40.0, 0.0, 40.0)).unwrap());
            let scene = SceneBounds::new(casters, receivers, None).unwrap();
            let top = scene.scene_box().max().y;
            let position = DVec3::new(lamp[0] * 100.0 - 50.0, top + 0.5 + lamp[1] * 10.0, lamp[2] * 100.0 - 50.0);
            let eye = DVec3::new(eye[0] * 80.0 - 40.0, 1.0 + eye[1] * 20.0, eye[2] * 80.0 - 40.0);
            let target = DVec3::new(target[0], 0.0, target[1]);
            prop_assume!(eye.distance(target) > 2.0);
            let lens = Lens { fov_y_degrees: fov, aspect: 1.5, near: 0.5, far };
            let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
            let point = PointLight::new(position, 200.0).unwrap();
            faces_match_faces_set_up_alone(&Focused, &camera, &point, &scene)?;
        }
    }

    /// Checks that `technique`'s faces for `point` are those that each face's own spot light
    /// gives: the same maps, and a face skipped exactly where its own setup has nothing to
    /// shadow (unless every face is, when the first keeps a map).
    fn faces_match_faces_set_up_alone(
        technique: &dyn ShadowTechnique,
        camera: &crate::camera::Camera,
        point: &PointLight,
        scene: &crate::bounds::SceneBounds,
    ) -> Result<(), TestCaseError> {
        let light = Light::Point(*point);
        let map = MapSettings::with_resolution(1024);
        let samples = ViewSamples::new(camera, &light, scene);
        let shared =
            compute_setup_with_samples(technique, camera, &light, scene, map, &samples).unwrap();
        let MapSelection::CubeFaces(faces) = &shared.selection else {
            panic!()
        };
        let mut drawn = Vec::new();
        for face in CubeFace::ALL {
            let spot = Light::Spot(point.face_light(face, map.resolution));
            let own = face_share(&samples, point, face, map.resolution);
            let alone =
                compute_setup_with_samples(technique, camera, &spot, scene, map, &own).unwrap();
            if !nothing_to_shadow(&alone) {
                drawn.push(face);
            }
            let Some(k) = faces.faces().iter().position(|f| *f == face) else {
                continue;
            };
            let (a, b) = (
                shared.maps[k].clip_from_world,
                alone.maps[0].clip_from_world,
            );
            let scale = b.abs().to_cols_array().iter().copied().fold(0.0, f64::max);
            let diff = (a - b)
                .abs()
                .to_cols_array()
                .iter()
                .copied()
                .fold(0.0, f64::max);
            prop_assert!(diff <= 1e-9 * scale, "face {face:?}: {a} vs {b}");
        }
        if !drawn.is_empty() {
            prop_assert_eq!(faces.faces(), &drawn[..]);
        }
        Ok(())
    }
}
