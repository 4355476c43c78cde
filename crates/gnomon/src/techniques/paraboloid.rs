//! Dual paraboloid shadow maps for point lights: two maps, one per hemisphere around the
//! light, each the image of its hemisphere in a paraboloid mirror.
//!
//! Heidrich and Seidel, "View-independent environment maps" (1998), the paraboloid
//! parameterisation; Brabec, Annen and Seidel, "Shadow mapping for hemispherical and
//! omnidirectional light sources" (2002), its use for shadows. A direction at angle theta
//! from the hemisphere's axis lands at radius tan(theta / 2): the whole hemisphere in one
//! disc, sampled within a factor of two everywhere, with two maps instead of the cube's six.
//! The mapping is not projective: a straight edge between two vertices maps to a curve (an arc
//! of a circle), which a rasteriser drawing between the mapped vertices draws straight, so
//! that large triangles cover the wrong texels; gnomon-render's depth pass casts each texel's
//! ray at the triangle instead where the device allows (`compare` measures both). Each hemisphere reaches
//! [`crate::PARABOLOID_MARGIN_DEGREES`] past 90 degrees, so that filtering near the rim reads the
//! casters. The maps are not focused: they hold the whole sphere of directions.

use glam::{DMat4, DVec3, DVec4};

use crate::diagnostics::Diagnostics;
use crate::error::SetupError;
use crate::light_space::LightFrame;
use crate::map::{MapProjection, MapSelection, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::faces::point_light_only;

/// Dual paraboloid maps for a point light: `maps[0]` the hemisphere below the light (around
/// -y, where a lamp's receivers mostly are), `maps[1]` the one above
/// ([`MapSelection::DualParaboloid`], [`MapProjection::Paraboloid`]). Directional and spot
/// lights are refused ([`SetupError::NeedsPointLight`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DualParaboloid;

impl ShadowTechnique for DualParaboloid {
    fn name(&self) -> &'static str {
        "paraboloid"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        let point = point_light_only(input, self.name())?;
        let position = point.position();
        let scale = 1.0 / point.range();
        let map = |axis: DVec3| {
            let f = LightFrame::fixed(axis);
            // q = (right, up, axis) . (p - position) / range.
            let row = |v: DVec3| (v * scale).extend(-v.dot(position) * scale);
            let (x, y, z) = (row(f.right), row(f.up), row(f.forward));
            ShadowMap {
                clip_from_world: DMat4::from_cols(x, y, z, DVec4::W).transpose(),
                depth_from_world: z,
                resolution: input.map.resolution,
                viewport_inset: input.map.viewport_inset,
                projection: MapProjection::Paraboloid,
                view_depth_range: None,
            }
        };
        let axis = DVec3::NEG_Y;
        Ok(ShadowSetup {
            technique: self.name(),
            maps: vec![map(axis), map(-axis)],
            selection: MapSelection::DualParaboloid { position, axis },
            diagnostics: Diagnostics::new(input.camera, input.light, input.scene),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounds::SceneBounds;
    use crate::boxes::Aabb;
    use crate::camera::{Camera, Lens};
    use crate::light::{Light, PointLight};
    use crate::map::MapSettings;
    use crate::setup::compute_setup;

    #[test]
    fn every_direction_lands_inside_its_hemisphere_s_disc() {
        let ground =
            Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
        let scene = SceneBounds::new(vec![ground], vec![ground], None).unwrap();
        let camera = Camera::look_at(
            DVec3::new(0.0, 10.0, 20.0),
            DVec3::ZERO,
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let lamp = PointLight::new(DVec3::new(1.0, 4.0, -2.0), 30.0).unwrap();
        let setup = compute_setup(
            &DualParaboloid,
            &camera,
            &Light::Point(lamp),
            &scene,
            MapSettings::with_resolution(512),
        )
        .unwrap();
        assert_eq!(setup.maps.len(), 2);
        let s = setup.maps[0].inset_ndc();
        for k in 0..2000 {
            // Directions spread over the sphere (a spiral), at distances up to the range.
            let t = (k as f64 + 0.5) / 2000.0;
            let (z, phi) = (1.0 - 2.0 * t, k as f64 * 2.399_963);
            let r = (1.0 - z * z).sqrt();
            let d = DVec3::new(r * phi.cos(), z, r * phi.sin());
            let p = lamp.position() + d * (1.0 + 29.0 * t);
            let map = &setup.maps[setup.map_for(p).unwrap()];
            let ndc = map.project(p).expect("in its hemisphere");
            assert!(ndc.x.abs() <= s && ndc.y.abs() <= s, "{p}: {ndc}");
            assert!(ndc.truncate().length() <= s * crate::map::PARABOLOID_SCALE + 1e-12);
            let depth = map.linear_depth(p);
            assert!((depth - (p - lamp.position()).length() / 30.0).abs() < 1e-12);
        }
        // The margin: just past 90 degrees the first map still holds the point.
        let p = lamp.position() + DVec3::new(1.0, 0.03, 0.0);
        assert_eq!(setup.map_for(p), Some(1));
        assert!(setup.maps[0].project(p).is_some());
    }
}
