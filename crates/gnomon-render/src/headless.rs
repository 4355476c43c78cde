//! The headless wrapper for the CLI and the tests: renders a frame into the renderer's own
//! kept targets, submits, and reads the images back (in bands of rows, so that any size the
//! device takes works) as a [`Frame`].

use std::time::Instant;

use gnomon::{Camera, Light, ShadowSetup};

use crate::frame::{Frame, LightView, PixelMetrics, Targets};
use crate::gpu::ErrorScopes;
use crate::light_view::{MAX_LIGHT_VIEW, draw_frustum};
use crate::passes::main::encode_measured;
use crate::passes::{FrameBindings, color_target};
use crate::pipelines::LIGHT_VIEW_FORMAT;
use crate::records::ShadowedLight;
use crate::timing::Part;
use crate::{MASK_EMPTY, MASK_LIT, MASK_UNLIT, RenderError, RenderSettings, Renderer};

impl Renderer {
    /// The colour image (Rgba8UnormSrgb: [`crate::COLOR_FORMAT`]) of the last headless frame
    /// ([`Renderer::render_lights`], [`Renderer::draw_volumes_lit_by`]), kept on the GPU;
    /// `None` before the first.
    pub fn frame_color(&self) -> Option<&wgpu::Texture> {
        self.headless.as_ref().map(|t| &t.color.0)
    }

    /// Copies a 2D texture (layer 0) to the CPU: `bytes_per_texel` bytes per texel, rows
    /// tightly packed, top to bottom (through the renderer's kept staging buffer; waits).
    pub fn read_texture(
        &mut self,
        texture: &wgpu::Texture,
        bytes_per_texel: u32,
    ) -> Result<Vec<u8>, RenderError> {
        self.readback
            .read(&self.gpu, &self.resources, texture, bytes_per_texel, 0)
    }

    /// The image size of `settings`, checked against the GPU's limit.
    pub(crate) fn image_size(&self, settings: &RenderSettings) -> Result<(u32, u32), RenderError> {
        self.gpu
            .check_size("image", settings.width, settings.height)?;
        Ok((settings.width, settings.height))
    }

    /// Makes (or keeps) the headless targets for a `width` x `height` frame.
    pub(crate) fn ensure_headless(&mut self, width: u32, height: u32, metrics: bool) {
        Targets::ensure(
            &mut self.headless,
            &self.resources,
            (width, height),
            metrics,
        );
    }

    /// Renders one frame of `camera` lit by `light`, with the shadow maps of `setup` (computed
    /// by the core crate for the same camera, light and scene): one map, or two maps and the
    /// plane that picks one per pixel (SPPSM; each caster drawn into the maps of the sides its
    /// bounds reach).
    pub fn render(
        &mut self,
        camera: &Camera,
        light: &Light,
        setup: &ShadowSetup,
        settings: &RenderSettings,
    ) -> Result<Frame, RenderError> {
        self.render_lights(camera, &[ShadowedLight { light, setup }], settings)
    }

    /// Renders one frame lit by several lights, each with its own shadow maps (at most
    /// [`crate::MAX_LIGHTS`] lights and [`crate::MAX_MAPS`] maps in all).
    pub fn render_lights(
        &mut self,
        camera: &Camera,
        lights: &[ShadowedLight<'_>],
        settings: &RenderSettings,
    ) -> Result<Frame, RenderError> {
        let (width, height) = self.image_size(settings)?;
        let scopes = ErrorScopes::push(&self.gpu);
        self.prepare(camera, lights, settings)?;
        self.ensure_headless(width, height, settings.metrics);
        // Made on first use, then kept.
        self.pipelines
            .measured(&self.gpu.device, settings.metrics, self.main_spec);
        let mut clock = self.start_clock();
        self.encode_shadow_maps_timed(clock.encoder(), true);
        clock.end_part(&self.gpu, Part::Shadow)?;
        let timestamps = clock.timestamps(&mut self.timer, Part::Main);
        let pipeline = self
            .pipelines
            .measured_for(settings.metrics, self.main_spec);
        encode_measured(
            clock.encoder(),
            self.headless.as_ref().expect("made above"),
            settings.metrics,
            (
                pipeline.expect("made above"),
                FrameBindings::of(&self.uniforms, &self.atlas),
                &self.scene,
            ),
            timestamps,
        );
        clock.end_part(&self.gpu, Part::Main)?;
        let mut timings = self.finish_clock(clock)?;
        scopes.pop()?;

        let start = Instant::now();
        let targets = self.headless.as_ref().expect("made above");
        let color = self
            .readback
            .read(&self.gpu, &self.resources, &targets.color.0, 4, 0)?;
        let lit = self
            .readback
            .read(&self.gpu, &self.resources, &targets.lit.0, 8, 0)?;
        let metrics = match &targets.metrics {
            Some((texture, _)) if settings.metrics => Some(PixelMetrics::from_rgba(
                &self
                    .readback
                    .read(&self.gpu, &self.resources, texture, 16, 0)?,
            )),
            _ => None,
        };
        let (mask, light_masks) = masks_from_bits(&lit, lights.len());
        let shadow = lit
            .chunks_exact(8)
            .map(|texel| f32::from_le_bytes([texel[4], texel[5], texel[6], texel[7]]))
            .collect();
        let light_view = if settings.light_view {
            Some(self.light_view(camera, lights, settings.light_view_size)?)
        } else {
            None
        };
        timings.readback_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(Frame {
            width,
            height,
            color,
            mask,
            light_masks,
            shadow: Some(shadow),
            light_view,
            metrics,
            timings,
            casters_drawn: self.casters_drawn(),
        })
    }

    /// The prepared frame's maps as the light sees them, side by side.
    fn light_view(
        &mut self,
        camera: &Camera,
        lights: &[ShadowedLight<'_>],
        largest: u32,
    ) -> Result<LightView, RenderError> {
        let largest = largest.clamp(64, MAX_LIGHT_VIEW);
        let mut views = Vec::new();
        let mut k = 0u32;
        for l in lights {
            for (i, map) in l.setup.maps.iter().enumerate() {
                let size = map.resolution.min(largest);
                let targets = self.headless.as_mut().expect("made by render");
                if targets
                    .light_view
                    .as_ref()
                    .is_none_or(|t| t.0.width() != size)
                {
                    targets.light_view = Some(self.resources.target(
                        "light view",
                        (size, size),
                        1,
                        LIGHT_VIEW_FORMAT,
                        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                    ));
                }
                let (texture, view) = targets.light_view.as_ref().expect("made above");
                let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("light view"),
                        color_attachments: &[color_target(view, Some(wgpu::Color::WHITE))],
                        ..Default::default()
                    });
                    pass.set_pipeline(&self.pipelines.light_view);
                    FrameBindings::of(&self.uniforms, &self.atlas).bind(&mut pass, k);
                    pass.draw(0..3, 0..1);
                }
                self.gpu.queue.submit([encoder.finish()]);
                let mut rgba = self
                    .readback
                    .read(&self.gpu, &self.resources, texture, 4, 0)?;
                // A cascade's map shows its slice of the view.
                let slice = match l.setup.selection {
                    gnomon::MapSelection::Cascades(c) => Camera::from_view_from_world(
                        camera.view_from_world(),
                        gnomon::Lens {
                            near: c.view_depths[i],
                            far: c.view_depths[i + 1],
                            ..camera.lens()
                        },
                    )
                    .ok(),
                    _ => None,
                };
                draw_frustum(&mut rgba, size, slice.as_ref().unwrap_or(camera), map);
                views.push((size, rgba));
                k += 1;
            }
        }
        Ok(LightView::side_by_side(&views))
    }
}

/// The combined mask and each light's mask from the lit-light bits (bit 31: geometry), the
/// first four bytes of each texel of eight.
fn masks_from_bits(bits: &[u8], lights: usize) -> (Vec<u8>, Vec<Vec<u8>>) {
    let n = bits.len() / 8;
    let mut mask = Vec::with_capacity(n);
    let mut per_light = vec![Vec::with_capacity(n); lights];
    for texel in bits.chunks_exact(8) {
        let b = u32::from_le_bytes([texel[0], texel[1], texel[2], texel[3]]);
        let geometry = b & 0x8000_0000 != 0;
        let value = |lit: bool| match (geometry, lit) {
            (false, _) => MASK_EMPTY,
            (true, true) => MASK_LIT,
            (true, false) => MASK_UNLIT,
        };
        mask.push(value(b & 0x7fff_ffff != 0));
        for (k, m) in per_light.iter_mut().enumerate() {
            m.push(value(b & (1 << k) != 0));
        }
    }
    (mask, per_light)
}
