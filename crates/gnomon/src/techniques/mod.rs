//! The shadow-map techniques, one file each, all behind [`crate::ShadowTechnique`].

pub(crate) mod basis;
mod cascades;
mod cube;
mod faces;
mod focused;
mod lispsm;
mod paraboloid;
mod psm;
mod sppsm;
mod tsm;
mod uniform;
mod view_warp;
mod warp_limit;
mod warp_space;
mod xpsm;

pub use cascades::{ADAPTIVE_HYSTERESIS, CascadeFit, CascadeSelect, CascadeSplit, Cascades};
pub use cube::Cube;
pub(crate) use faces::per_face;
pub use focused::Focused;
pub(crate) use focused::focused_per_face;
pub use lispsm::Lispsm;
pub use paraboloid::DualParaboloid;
pub use psm::Psm;
pub use sppsm::{PerspectiveMap, Sppsm, ray_area_density, separating_plane};
pub use tsm::Tsm;
pub use uniform::Uniform;
pub use xpsm::Xpsm;

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
