//! The interface every technique implements, and the inputs it is given.

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::error::SetupError;
use crate::light::Light;
use crate::map::{MapSettings, ShadowSetup};
use crate::samples::ViewSamples;

/// Everything a technique needs: borrowed, so a setup per frame allocates little.
#[derive(Debug, Clone, Copy)]
pub struct SetupInput<'a> {
    /// The camera.
    pub camera: &'a Camera,
    /// The light.
    pub light: &'a Light,
    /// The scene's bounds.
    pub scene: &'a SceneBounds,
    /// The map size.
    pub map: MapSettings,
    /// What the pixels see of the lit receivers, when the caller has them for this frame
    /// (the warp limit compares maps on them); `None`: a technique that needs them casts
    /// them itself.
    pub samples: Option<&'a ViewSamples>,
}

/// A shadow-map technique: camera, light and scene bounds in, shadow maps out.
pub trait ShadowTechnique {
    /// The technique's name (`uniform`, `focused`, ...).
    fn name(&self) -> &'static str;

    /// Computes the shadow maps for one frame. A point light's are the technique's map of
    /// each cube face ([`crate::techniques::Cube`]'s module documentation); techniques with
    /// several maps per light (SPPSM, cascades) refuse point lights.
    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError>;
}
