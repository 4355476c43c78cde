//! The shadow-map techniques, one file each, all behind [`crate::ShadowTechnique`].

pub(crate) mod basis;
mod cascades;
mod cube;
mod focused;
mod lispsm;
mod paraboloid;
mod psm;
mod sppsm;
mod tsm;
mod uniform;
mod view_warp;
mod warp_limit;
mod xpsm;

pub use cascades::{ADAPTIVE_HYSTERESIS, CascadeFit, CascadeSelect, CascadeSplit, Cascades};
pub use cube::Cube;
pub(crate) use cube::{focused_per_face, per_face};
pub use focused::Focused;
pub use lispsm::Lispsm;
pub use paraboloid::DualParaboloid;
pub use psm::Psm;
pub use sppsm::{PerspectiveMap, Sppsm, ray_area_density, separating_plane};
pub use tsm::Tsm;
pub use uniform::Uniform;
pub(crate) use uniform::fixed_projector;
pub use xpsm::Xpsm;

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::light::Light;

/// The world-space tolerance of one setup: a billionth of the distances involved (the scene
/// box's diagonal plus how far the camera and light are from it), and for a spot or point
/// light at most a thousandth of its near plane's distance (with the near plane at
/// [`crate::SPOT_NEAR_FRACTION`] of the range, a billionth of the range): the clips keep
/// points up to the tolerance outside the near plane, and the light's projection divides by
/// their depth (a lamp of 0.1 m range in a 500 m scene has its near plane 1e-7 from it,
/// under the 5e-7 the scene alone gives).
pub(crate) fn tolerance(scene: &SceneBounds, camera: Option<&Camera>, light: &Light) -> f64 {
    let scene_box = scene.scene_box();
    let center = scene_box.center();
    let mut scale = scene_box.diagonal();
    if let Some(camera) = camera {
        scale += (camera.eye() - center).length();
    }
    let near = match light {
        Light::Directional(_) => f64::INFINITY,
        Light::Spot(spot) => {
            scale += (spot.position() - center).length() + spot.range();
            spot.near()
        }
        Light::Point(point) => {
            scale += (point.position() - center).length() + point.range();
            point.near()
        }
    };
    (1e-9 * scale).min(1e-3 * near)
}

/// `f` on the basis of all of `input`'s frame (a technique's setup of one whole view).
pub(crate) fn on_whole_frame<R>(
    input: &crate::technique::SetupInput<'_>,
    f: impl FnOnce(&basis::FocusBasis) -> R,
) -> R {
    let frame = crate::frame::Frame::new(input);
    f(&basis::FocusBasis::new(&frame, basis::Part::Whole))
}

/// Padding of a perspective map's xy extents (tangent units).
pub(crate) const ANGULAR_PADDING: f64 = 1e-9;

/// A setup (usually the focused map a warp falls back to) under another technique's name,
/// with `fallback` named first among its fallbacks.
pub(crate) fn with_fallback(
    mut setup: crate::map::ShadowSetup,
    technique: &'static str,
    fallback: crate::diagnostics::Fallback,
) -> crate::map::ShadowSetup {
    setup.technique = technique;
    setup.diagnostics.fallbacks.retain(|f| *f != fallback);
    setup.diagnostics.fallbacks.insert(0, fallback);
    setup
}
