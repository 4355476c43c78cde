//! What a headless frame gives ([`Frame`], its light view and sampling metrics) and the kept
//! targets it is drawn into.

use crate::MASK_EMPTY;
use crate::pipelines::{CAMERA_DEPTH_FORMAT, COLOR_FORMAT, LIT_FORMAT, METRICS_FORMAT};
use crate::resources::Resources;
use crate::timing::Timings;

/// A rendered frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The image: RGBA, 8 bits per channel, sRGB-encoded, rows top to bottom.
    pub color: Vec<u8>,
    /// The direct-light mask, one byte per pixel: [`crate::MASK_LIT`] where some light
    /// reaches, [`crate::MASK_UNLIT`] where none does, [`crate::MASK_EMPTY`] with no geometry.
    pub mask: Vec<u8>,
    /// Each light's own mask, in the order of the lights (the same values).
    pub light_masks: Vec<Vec<u8>>,
    /// The first light's shadow factor per pixel as the main pass filters it (1 lit, 0
    /// shadowed; 1 where the surface receives no shadows, 0 where there is no geometry):
    /// shadow-map frames only (`None` for the volumes).
    pub shadow: Option<Vec<f32>>,
    /// The shadow map(s) as the light sees them, if asked for.
    pub light_view: Option<LightView>,
    /// The per-pixel sampling metrics of the first light, if asked for
    /// ([`crate::RenderSettings::metrics`]).
    pub metrics: Option<PixelMetrics>,
    /// Times of the passes.
    pub timings: Timings,
    /// How many of the scene's casters each shadow map drew (those whose box reaches its
    /// clip volume), in the order of the maps; empty for shadow volumes.
    pub casters_drawn: Vec<usize>,
}

/// The shadow maps as the light sees them (near = dark, far = light), with the camera's view
/// frustum in red; several maps side by side (the first on the left), in RGBA. Maps larger
/// than 2048 texels are shown at 2048.
#[derive(Debug, Clone, PartialEq)]
pub struct LightView {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA bytes, rows top to bottom.
    pub rgba: Vec<u8>,
}

impl LightView {
    /// Square views (size, RGBA) side by side, on a white background.
    pub(crate) fn side_by_side(views: &[(u32, Vec<u8>)]) -> Self {
        let width: u32 = views.iter().map(|v| v.0).sum();
        let height = views.iter().map(|v| v.0).max().unwrap_or(0);
        let mut rgba = vec![255u8; (width as usize) * (height as usize) * 4];
        let mut x0 = 0usize;
        for (size, view) in views {
            let size = *size as usize;
            for y in 0..size {
                let from = y * size * 4;
                let to = (y * width as usize + x0) * 4;
                rgba[to..to + size * 4].copy_from_slice(&view[from..from + size * 4]);
            }
            x0 += size;
        }
        Self {
            width,
            height,
            rgba,
        }
    }
}

/// Per pixel, how the shadow map samples what the pixel sees: J is the Jacobian of the
/// map's texel coordinates with respect to screen pixels (the map's exact gradient at the
/// point times the fragment's position derivatives, so it includes projection aliasing, the
/// surface's orientation, as well as perspective aliasing).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PixelMetrics {
    /// Pixels per texel along the worst direction, 1 / sigma_min(J): 1 = one texel per
    /// pixel, above 1 the map is undersampled (a texel spans several pixels). 0 where the
    /// pixel has no geometry, negative where the map does not see the point, at most 10^6
    /// (a surface edge-on to the light).
    pub undersampling: Vec<f32>,
    /// Pixels per texel in area, 1 / |det J| (the SPPSM paper's area measure, its eq. 3).
    pub area: Vec<f32>,
    /// N.L with the geometric normal turned toward the camera (0 where no geometry).
    pub n_dot_l: Vec<f32>,
    /// Whether the first light's one-tap lookup may be wrong: the texels around the point
    /// disagree, or one holds a depth within the bias's reach of the point's, or the point
    /// lies outside the map or near its border where the border holds a caster (false where
    /// no geometry).
    pub unsure: Vec<bool>,
}

impl PixelMetrics {
    /// From the metrics image (four 32-bit floats as their bits: undersampling, area, N.L,
    /// coverage: 1, or 2 where the lookup is unsure).
    pub(crate) fn from_rgba(bytes: &[u8]) -> Self {
        let mut m = Self::default();
        for texel in bytes.chunks_exact(16) {
            let f = |k: usize| {
                f32::from_le_bytes([
                    texel[4 * k],
                    texel[4 * k + 1],
                    texel[4 * k + 2],
                    texel[4 * k + 3],
                ])
            };
            let covered = f(3) > 0.5;
            m.undersampling.push(if covered { f(0) } else { 0.0 });
            m.area.push(if covered { f(1) } else { 0.0 });
            m.n_dot_l.push(if covered { f(2) } else { 0.0 });
            m.unsure.push(f(3) > 1.5);
        }
        m
    }

    /// Whether pixel `i` has geometry that the map sees.
    pub fn measured(&self, i: usize) -> bool {
        self.undersampling[i] > 0.0 && self.undersampling[i].is_finite()
    }

    /// Whether pixel `i` has geometry that the map sees and that faces the light
    /// (N.L > 0.1): where the shadow map's sampling shows (elsewhere the light does not
    /// reach, and surfaces edge-on to the light are not resolved by any map).
    pub fn lit_facing(&self, i: usize) -> bool {
        self.measured(i) && self.n_dot_l[i] > 0.1
    }
}

/// The colour image's background (a window's program clears its target of the main pass
/// with it to draw what `render` draws).
pub const SKY: wgpu::Color = wgpu::Color {
    r: 0.55,
    g: 0.7,
    b: 0.9,
    a: 1.0,
};

/// A mask image's background: no geometry.
pub(crate) const MASK_CLEAR: wgpu::Color = wgpu::Color {
    r: MASK_EMPTY as f64 / 255.0,
    g: 0.0,
    b: 0.0,
    a: 1.0,
};

/// The headless frame's kept targets.
pub(crate) struct Targets {
    pub color: (wgpu::Texture, wgpu::TextureView),
    pub lit: (wgpu::Texture, wgpu::TextureView),
    pub depth: wgpu::TextureView,
    pub metrics: Option<(wgpu::Texture, wgpu::TextureView)>,
    pub light_view: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl Targets {
    /// Makes (or keeps) the targets of a frame of `size` in `slot`, the metrics target too
    /// where asked.
    pub fn ensure(
        slot: &mut Option<Targets>,
        resources: &Resources,
        (width, height): (u32, u32),
        metrics: bool,
    ) {
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let make =
            |label, format, usage| resources.target(label, (width, height), 1, format, usage);
        if slot
            .as_ref()
            .is_none_or(|t| (t.color.0.width(), t.color.0.height()) != (width, height))
        {
            *slot = Some(Targets {
                color: make("color", COLOR_FORMAT, attachment),
                lit: make("lit lights", LIT_FORMAT, attachment),
                depth: make(
                    "camera depth",
                    CAMERA_DEPTH_FORMAT,
                    wgpu::TextureUsages::RENDER_ATTACHMENT,
                )
                .1,
                metrics: None,
                light_view: None,
            });
        }
        if let Some(targets) = slot.as_mut()
            && metrics
            && targets.metrics.is_none()
        {
            targets.metrics = Some(make("metrics", METRICS_FORMAT, attachment));
        }
    }
}
