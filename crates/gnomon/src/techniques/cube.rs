//! Point lights: a map per cube face, each fitted like a spot light's map (`cube`: the focused map
//! with unit cube clipping per face), and any single-map technique run per face.
//!
//! The shadows lecture ("Shadows", volumes and maps) covers point lights with six 90-degree maps;
//! the unit cube clipping blog post fits each frustum to what it must hold. Each face here is a
//! spot light at the point light's position looking along the face's axis
//! ([`crate::PointLight::face_light`]): a square frustum a few texels wider than the face, whose
//! sides lie along the cube's edges. The face's map is that spot's map from the chosen technique
//! (focused for `cube`; LiSPSM or PSM warp after the face's own perspective, as they do for a spot
//! light, an extension of ours; TSM and XPSM use the focused map there) on the view samples inside
//! the face. A face that sees no visible receiver, or none that a caster can shadow, gets no map
//! ([`crate::Diagnostics::cube_faces_skipped`]): its points read as lit.
//!
//! A point reads the map of the face its direction from the light falls in (its major axis,
//! [`crate::PointLight::face_of`]); [`crate::MapSelection::CubeFaces`] lists the faces that have
//! maps.

use crate::error::SetupError;
use crate::map::ShadowSetup;
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::faces::point_light_only;
use crate::techniques::focused::focused_per_face;

/// Cube shadow maps for a point light: six faces, each the focused map with unit cube
/// clipping of the visible receivers in that face's frustum and the casters that can shadow
/// them; a face with nothing to shadow is skipped. For a directional or spot light it is
/// refused ([`SetupError::NeedsPointLight`]); other techniques take point lights too (per
/// face; `focused` then gives the same maps under its own name).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Cube;

impl ShadowTechnique for Cube {
    fn name(&self) -> &'static str {
        "cube"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        let point = point_light_only(input, self.name())?;
        focused_per_face(self.name(), input, point)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::bounds::SceneBounds;
    use crate::boxes::Aabb;
    use crate::camera::{Camera, Lens};
    use crate::light::{CubeFace, DirectionalLight, Light, PointLight};
    use crate::map::{MapSelection, MapSettings};
    use crate::setup::compute_setup;
    use crate::techniques::Focused;

    fn street() -> SceneBounds {
        let ground =
            Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
        let block = Aabb::new(DVec3::new(4.0, 0.0, -6.0), DVec3::new(12.0, 20.0, 6.0)).unwrap();
        SceneBounds::new(vec![block], vec![ground, block], None).unwrap()
    }

    #[test]
    fn cube_is_focused_per_face_and_refuses_other_lights() {
        let scene = street();
        let camera = Camera::look_at(
            DVec3::new(-20.0, 15.0, 25.0),
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let lamp = Light::Point(PointLight::new(DVec3::new(0.0, 5.0, 0.0), 80.0).unwrap());
        let map = MapSettings::with_resolution(1024);
        let cube = compute_setup(&Cube, &camera, &lamp, &scene, map).unwrap();
        let focused = compute_setup(&Focused, &camera, &lamp, &scene, map).unwrap();
        assert_eq!(cube.technique, "cube");
        assert_eq!(focused.technique, "focused");
        assert_eq!(cube.maps, focused.maps);
        let MapSelection::CubeFaces(faces) = cube.selection else {
            panic!("{:?}", cube.selection);
        };
        // The ground the -x face sees has no caster that can shadow it (the block stands on
        // the +x side): that face is skipped; the ground below and the block's wall have
        // maps.
        assert!(
            !faces.faces().contains(&CubeFace::NegX),
            "{:?}",
            faces.faces()
        );
        assert!(faces.faces().contains(&CubeFace::PosX));
        assert!(faces.faces().contains(&CubeFace::NegY));
        assert_eq!(cube.maps.len() + cube.diagnostics.cube_faces_skipped, 6);
        // A point of the block's wall facing the lamp reads the +x face's map.
        let k = cube.map_for(DVec3::new(4.0, 3.0, 1.0)).unwrap();
        assert_eq!(faces.faces()[k], CubeFace::PosX);
        let sun = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
        assert!(matches!(
            compute_setup(&Cube, &camera, &sun, &scene, map),
            Err(SetupError::NeedsPointLight { .. })
        ));
    }

    #[test]
    fn a_lamp_that_shadows_nothing_visible_keeps_one_map() {
        let scene = street();
        // The camera looks away from everything.
        let camera = Camera::look_at(
            DVec3::new(0.0, 30.0, 0.0),
            DVec3::new(0.0, 60.0, 1.0),
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let lamp = Light::Point(PointLight::new(DVec3::new(0.0, 5.0, 0.0), 80.0).unwrap());
        let setup = compute_setup(&Cube, &camera, &lamp, &scene, MapSettings::default()).unwrap();
        assert_eq!(setup.maps.len(), 1);
        assert_eq!(setup.diagnostics.cube_faces_skipped, 5);
        assert!(setup.maps.iter().all(|m| m.is_finite()));
    }
}
