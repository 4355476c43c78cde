//! gnomon's wgpu renderer: draws a scene with a shadow setup from the core crate.
//!
//! Headless: it renders into textures and reads them back. Any adapter works; on a machine
//! without a GPU, Mesa's software Vulkan driver (lavapipe) does
//! (`apt-get install -y mesa-vulkan-drivers`).
//!
//! Passes, per frame: a depth pass into each shadow map (Depth32Float; the map's resolution and
//! viewport inset from the setup; linear depth from `depth_from_world` plus constant and
//! slope-scaled bias), then the main pass: ambient plus Lambert, the shadow factor from a
//! comparison sampler (one tap, hardware 2x2 or 5x5 PCF, optional normal offset), and the
//! direct-light mask (255 lit, 0 not lit, 128 no geometry). [`Renderer::render_volumes`]
//! and [`Renderer::render_volumes_lit_by`] (several lights) draw exact shadows with
//! stenciled shadow volumes instead (z-fail, z-pass, or chosen per caster).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod error;
mod gpu;
mod light_view;
mod readback;
mod renderer;
mod scene;
mod volumes;

pub use error::RenderError;
pub use gpu::Gpu;
pub use renderer::{
    DepthBias, Filter, Frame, LightView, PixelMetrics, RenderSettings, Renderer, Timings,
};
pub use scene::{Instance, RenderScene};
pub use volumes::{StencilMode, VolumeFrame, VolumeStats};

/// Mask value of a pixel lit by the light.
pub const MASK_LIT: u8 = 255;
/// Mask value of a pixel the light does not reach (facing away, outside the cone, shadowed).
pub const MASK_UNLIT: u8 = 0;
/// Mask value of a pixel with no geometry.
pub const MASK_EMPTY: u8 = 128;
