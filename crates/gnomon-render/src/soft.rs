//! Soft shadows as the shadows lecture simulates them with stenciled shadow volumes: an area
//! light sampled by a cluster of hard lights ([`gnomon::area_light`]), each drawn with exact
//! volumes, their frames averaged in linear light. The reference for soft shadows.

use gnomon::{Camera, Light};

use crate::{
    Frame, InvalidInput, MASK_EMPTY, MASK_LIT, RenderError, RenderSettings, Renderer, StencilMode,
    Timings,
};

/// A soft-shadowed frame: the cluster's frames averaged.
#[derive(Debug, Clone)]
pub struct SoftFrame {
    /// The averaged frame: colour in sRGB, `mask` the main light's shadow factor as
    /// `255 x factor` (0 where there is no geometry), timings summed.
    pub frame: Frame,
    /// The main light's shadow factor per pixel: the share of its samples that reach it
    /// (`None` where there is no geometry).
    pub factor: Vec<Option<f32>>,
    /// Volume triangles drawn over all the samples.
    pub triangles: usize,
}

/// sRGB byte to linear light.
fn to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to an sRGB byte.
fn to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

impl Renderer {
    /// Renders `camera` lit by area lights, each given as its cluster of samples
    /// (`clusters[l]`: light l's samples, all clusters of one size N): frame j draws sample j
    /// of every light with exact volumes counted as `mode` says, and the N frames are
    /// averaged (each light's direct light is the mean of its samples'). The factor and mask
    /// are the first light's.
    pub fn render_soft_volumes(
        &mut self,
        camera: &Camera,
        clusters: &[Vec<Light>],
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<SoftFrame, RenderError> {
        let n = clusters.first().map_or(0, Vec::len);
        if n == 0 || clusters.iter().any(|c| c.len() != n) {
            return Err(InvalidInput::UnevenClusters.into());
        }
        let pixels = (settings.width * settings.height) as usize;
        let mut color = vec![0.0f32; pixels * 3];
        let mut lit = vec![0u32; pixels];
        let mut geometry = vec![false; pixels];
        let mut timings = Timings::default();
        let mut triangles = 0;
        let lut: Vec<f32> = (0..=255u8).map(to_linear).collect();
        for j in 0..n {
            let lights: Vec<Light> = clusters.iter().map(|c| c[j]).collect();
            let drawn = self.render_volumes_lit_by(camera, &lights, settings, mode)?;
            let f = &drawn.frame;
            for (i, rgba) in f.color.chunks_exact(4).enumerate() {
                for c in 0..3 {
                    color[i * 3 + c] += lut[rgba[c] as usize];
                }
            }
            for (i, m) in f.light_masks[0].iter().enumerate() {
                geometry[i] |= *m != MASK_EMPTY;
                lit[i] += u32::from(*m == MASK_LIT);
            }
            timings.shadow_pass_ms += f.timings.shadow_pass_ms;
            timings.main_pass_ms += f.timings.main_pass_ms;
            timings.readback_ms += f.timings.readback_ms;
            timings.source = f.timings.source;
            triangles += drawn.stats.triangles;
        }
        let scale = 1.0 / n as f32;
        let rgba: Vec<u8> = color
            .chunks_exact(3)
            .flat_map(|c| {
                [
                    to_srgb(c[0] * scale),
                    to_srgb(c[1] * scale),
                    to_srgb(c[2] * scale),
                    255,
                ]
            })
            .collect();
        let factor: Vec<Option<f32>> = lit
            .iter()
            .zip(&geometry)
            .map(|(l, g)| g.then_some(*l as f32 * scale))
            .collect();
        let mask = factor
            .iter()
            .map(|f| f.map_or(0, |f| (f * 255.0).round() as u8))
            .collect::<Vec<u8>>();
        Ok(SoftFrame {
            frame: Frame {
                shadow: None,
                width: settings.width,
                height: settings.height,
                color: rgba,
                light_masks: vec![mask.clone()],
                mask,
                light_view: None,
                metrics: None,
                timings,
                casters_drawn: Vec::new(),
            },
            factor,
            triangles,
        })
    }
}

/// How far a soft shadow factor lies from a reference's over their penumbrae.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PenumbraError {
    /// The mean absolute difference of the factors over the pixels judged.
    pub mean: f64,
    /// The pixels judged: those (facing the light, N.L > 0.1) where either factor lies
    /// strictly between lit and shadowed (0.02 to 0.98): the union of both penumbrae.
    pub pixels: usize,
}

/// The penumbra error of `factor` (one per pixel: a frame's [`Frame::shadow`]) against
/// `reference` (a [`SoftFrame::factor`] of the same view), over the pixels whose N.L
/// (`n_dot_l`) is above 0.1.
pub fn penumbra_error(reference: &[Option<f32>], factor: &[f32], n_dot_l: &[f32]) -> PenumbraError {
    let inside = |f: f32| f > 0.02 && f < 0.98;
    let (mut sum, mut pixels) = (0.0, 0usize);
    for ((r, f), n) in reference.iter().zip(factor).zip(n_dot_l) {
        let Some(r) = *r else { continue };
        if *n > 0.1 && (inside(r) || inside(*f)) {
            sum += (r - f).abs() as f64;
            pixels += 1;
        }
    }
    PenumbraError {
        mean: sum / pixels.max(1) as f64,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for c in 0..=255u8 {
            assert_eq!(to_srgb(to_linear(c)), c);
        }
    }
}
