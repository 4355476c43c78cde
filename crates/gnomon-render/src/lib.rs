//! gnomon's wgpu renderer: draws a scene with shadow setups from the core crate, on any wgpu
//! backend (Vulkan, GL/GLES, Metal, DX12, WebGPU).
//!
//! A frame: [`Renderer::prepare`] writes the records the shaders read (per light and per map,
//! relative to the camera, from f64) and picks each map's casters;
//! [`Renderer::encode_shadow_maps`] records a depth pass per map (Depth32Float layers of one
//! array texture; linear depth from `depth_from_world` plus constant and slope-scaled bias);
//! [`Renderer::encode_scene`] records the main pass (ambient plus Lambert per light, each
//! light's shadow factor from its maps: one tap, hardware 2x2 or 5x5 PCF, normal offset) into
//! the caller's target, reversed-Z float depth. Engines that keep their own main pass import
//! [`lookup_wgsl`] and bind [`Renderer::shadow_bind_group`]; [`CasterSet`] draws their own
//! casters into the maps. [`Renderer::render`] and [`Renderer::render_lights`] are the
//! headless wrapper (submit, read back: [`Frame`] with its direct-light mask, 255 lit, 0 not
//! lit, 128 no geometry). [`Renderer::render_volumes`] and [`Renderer::render_volumes_lit_by`]
//! draw exact shadows with stenciled shadow volumes (z-fail, z-pass, or chosen per caster).
//!
//! On a machine without a GPU, Mesa's software drivers do: lavapipe for Vulkan
//! (`apt-get install -y mesa-vulkan-drivers`) or llvmpipe for GL (`WGPU_BACKEND=gl`).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod atlas;
mod casters;
mod cutouts;
mod error;
mod frame;
mod gpu;
mod headless;
mod light_view;
mod measure;
mod passes;
mod pipelines;
mod probes;
mod readback;
mod records;
mod renderer;
mod resources;
mod samples;
mod scene;
mod settings;
mod soft;
mod timing;
mod uniforms;
mod volumes;

pub use error::{InvalidInput, RenderError};
pub use frame::{Frame, LightView, PixelMetrics, SKY};
pub use gpu::{Gpu, OPTIONAL_FEATURES};
pub use measure::{JUDGED_N_DOT_L, MaskErrors, Percentiles, PixelVerdict, SureErrors};
pub use passes::casters::{CasterBuffers, CasterDraw, CasterSet};
pub use passes::volumes::{StencilMode, VolumeFrame, VolumeStats};
pub use pipelines::COLOR_FORMAT;
pub use records::{MAX_LIGHTS, MAX_MAPS, ShadowedLight};
pub use renderer::Renderer;
pub use scene::{Instance, RenderScene};
pub use settings::{DepthBias, Filter, MapRead, RenderSettings, SceneTarget};
pub use soft::{PenumbraError, SoftFrame, penumbra_error};
pub use timing::{TimingSource, Timings};

/// The farthest far plane the renderer draws (metres, or the scene's units): it draws
/// relative to the camera in f32 with reversed-Z float depth, which the precision tests hold
/// to exact shadows out to about half this distance; farther views are refused.
pub const MAX_VIEW_DISTANCE: f64 = 1e6;

/// Mask value of a pixel lit by the light.
pub const MASK_LIT: u8 = 255;
/// Mask value of a pixel the light does not reach (facing away, outside the cone, shadowed).
pub const MASK_UNLIT: u8 = 0;
/// Mask value of a pixel with no geometry.
pub const MASK_EMPTY: u8 = 128;

/// The WGSL of gnomon's shadow lookup with its bindings in bind group `group`: the records
/// (`GnomonShadows`: lights, maps), the maps (a depth array bound for comparison and for raw
/// reads) and two samplers, and the functions `gnomon_shadow(light, p, n_geo, n_dot_l)`,
/// `gnomon_map_index`, `gnomon_lookup`, `gnomon_incidence`. Prepend it to your shader and bind
/// [`Renderer::shadow_bind_group`] at `group`. Positions are view-space (the camera's
/// `view_from_world`).
pub fn lookup_wgsl(group: u32) -> String {
    include_str!("wgsl/lookup.wgsl").replace("GNOMON_GROUP", &group.to_string())
}

#[cfg(test)]
mod tests {
    /// The value of `const NAME: f32 = ...;` in the lookup module.
    fn wgsl_constant(name: &str) -> f64 {
        let text = super::lookup_wgsl(0);
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("const {name}: f32 = ")))
            .unwrap_or_else(|| panic!("no {name}"));
        line.split('=')
            .nth(1)
            .unwrap()
            .trim()
            .trim_end_matches(';')
            .parse()
            .unwrap()
    }

    #[test]
    fn the_shader_s_paraboloid_matches_the_core_s() {
        let scale = wgsl_constant("GNOMON_PARABOLOID_SCALE");
        assert!((scale - gnomon::PARABOLOID_SCALE).abs() < 1e-9);
        let margin = gnomon::PARABOLOID_MARGIN_DEGREES.to_radians();
        assert!((wgsl_constant("GNOMON_PARABOLOID_RIM") + margin.sin()).abs() < 1e-9);
        assert!((1.0 / (0.5 * (90f64.to_radians() + margin)).tan() - scale).abs() < 1e-9);
    }

    #[test]
    fn the_shader_s_cascade_cover_matches_the_core_s() {
        let margin = wgsl_constant("GNOMON_COVER_MARGIN_TEXELS");
        assert_eq!(margin, gnomon::CascadeSlices::COVER_MARGIN_TEXELS as f64);
    }
}
