//! Uniform shadow map (SSM): the light's projection covers the whole scene box.
//!
//! Williams, "Casting curved shadows on curved surfaces" (SIGGRAPH 1978), the original
//! shadow map; the LiSPSM paper (Wimmer et al. 2004, section 4) analyses its error as the
//! n -> infinity end of its family. The map does not depend on the camera, so it never swims,
//! and spends most of its texels on what the camera does not see.

use crate::bounds::SceneBounds;
use crate::diagnostics::{Diagnostics, Fallback};
use crate::error::SetupError;
use crate::frame::tolerance;
use crate::geometry::ConvexPolyhedron;
use crate::light::{CubeFace, Light, SpotLight};
use crate::light_space::{Extents, build_map, fixed_projector};
use crate::map::{MapSelection, MapSettings, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::ANGULAR_PADDING;

use glam::DVec3;

/// Uniform shadow map (SSM): an orthographic projection (directional light) or the spot
/// light's own perspective, fitted to the whole scene box. Independent of the camera.
///
/// Light frame: fixed by the light direction alone (world +Y made perpendicular, or +Z for a
/// nearly vertical light). Degenerate cases: a spot light whose frustum misses the scene box
/// gets a map of its whole cone ([`Fallback::SpotLightMissesScene`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Uniform;

impl ShadowTechnique for Uniform {
    fn name(&self) -> &'static str {
        "uniform"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let Light::Point(point) = input.light {
            return crate::techniques::per_face(self.name(), input, point, |input, _| {
                self.setup(input)
            });
        }
        input.map.validate()?;
        let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
        let map = uniform_map(input.light, input.scene, input.map, &mut diagnostics);
        Ok(ShadowSetup {
            technique: self.name(),
            maps: vec![map],
            selection: MapSelection::Single,
            diagnostics,
        })
    }
}

/// The uniform map (also the fallback of the camera-dependent techniques): the same map
/// whatever the camera.
pub(crate) fn uniform_map(
    light: &Light,
    scene: &SceneBounds,
    settings: MapSettings,
    diagnostics: &mut Diagnostics,
) -> ShadowMap {
    let tolerance = tolerance(scene, None, light);
    let projector = fixed_projector(light);
    let scene_box = scene.scene_box();
    match light {
        Light::Directional(_) => {
            let region = projector.box_extents(&scene_box);
            build_map(&projector, &region, settings, tolerance, tolerance)
        }
        Light::Point(point) => {
            // Techniques see a point light's faces as spot lights; a point light itself gets
            // the map of its downward face.
            let face = Light::Spot(point.face_light(CubeFace::NegY, settings.resolution));
            uniform_map(&face, scene, settings, diagnostics)
        }
        Light::Spot(spot) => {
            let planes = spot.frustum_planes(projector.frame().up);
            let lit = ConvexPolyhedron::from_box(&scene_box).clip_all(&planes, tolerance);
            let region = if lit.is_empty() {
                diagnostics.fallbacks.push(Fallback::SpotLightMissesScene);
                whole_cone(spot)
            } else {
                let mut ext = Extents::EMPTY;
                for p in lit.vertices(tolerance) {
                    ext.add(projector.project(p));
                }
                within_cone(ext, spot)
            };
            build_map(&projector, &region, settings, ANGULAR_PADDING, tolerance)
        }
    }
}

/// `ext` (a spot light's projector's) cut to the light's square in x and y. The clips keep
/// points up to the tolerance outside the frustum's sides, which project outside it by the
/// tolerance over their depth: near the light (a lamp inside a box) up to a thousandth of the
/// square (see [`crate::frame::tolerance`]). `ext` itself where the cut leaves nothing.
pub(crate) fn within_cone(ext: Extents, spot: &SpotLight) -> Extents {
    let cut = ext.within_square(spot.half_angle().tan());
    if cut.is_empty() { ext } else { cut }
}

/// The extents of a spot light's whole frustum (tangent units, depth from near to range).
fn whole_cone(spot: &SpotLight) -> Extents {
    let t = spot.half_angle().tan();
    Extents {
        min: DVec3::new(-t, -t, spot.near()),
        max: DVec3::new(t, t, spot.range()),
    }
}
