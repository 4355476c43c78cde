//! The headless wrapper for the CLI and the tests: renders a frame into the renderer's own
//! kept targets, submits, and reads the images back (in bands of rows, so that any size the
//! device takes works) as a [`Frame`].

use std::time::Instant;

use gnomon::{Camera, Light, ShadowSetup};

use crate::gpu::ErrorScopes;
use crate::light_view::{MAX_LIGHT_VIEW, draw_frustum};
use crate::pipelines::{
    CAMERA_DEPTH_FORMAT, COLOR_FORMAT, LIGHT_VIEW_FORMAT, LIT_FORMAT, METRICS_FORMAT,
};
use crate::records::ShadowedLight;
use crate::renderer::cleared_camera_depth;
use crate::timing::{Part, Timer, TimingSource};
use crate::{Gpu, MASK_EMPTY, MASK_LIT, MASK_UNLIT, RenderError, RenderSettings, Renderer};

/// Times of one frame's parts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    /// The shadow part (depth passes; for volumes, extrusion and stencil passes), ms.
    pub shadow_pass_ms: f64,
    /// The main pass(es), ms.
    pub main_pass_ms: f64,
    /// Reading the images back, ms (wall clock).
    pub readback_ms: f64,
    /// Where the pass times come from.
    pub source: TimingSource,
}

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
    /// ([`RenderSettings::metrics`]).
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
    fn side_by_side(views: &[(u32, Vec<u8>)]) -> Self {
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
}

impl PixelMetrics {
    /// From the metrics image (four 32-bit floats as their bits: undersampling, area, N.L,
    /// coverage).
    fn from_rgba(bytes: &[u8]) -> Self {
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

/// A colour attachment, cleared to `clear` or loaded; kept either way.
pub(crate) fn color_target(
    view: &wgpu::TextureView,
    clear: Option<wgpu::Color>,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// The headless frame's kept targets.
pub(crate) struct Targets {
    pub color: (wgpu::Texture, wgpu::TextureView),
    lit: (wgpu::Texture, wgpu::TextureView),
    depth: wgpu::TextureView,
    metrics: Option<(wgpu::Texture, wgpu::TextureView)>,
    light_view: Option<(wgpu::Texture, wgpu::TextureView)>,
}

/// A frame's encoder and its part times: with GPU timestamps one submission and the passes'
/// own times; without, a submission and a wait after each part, timed by the wall clock.
pub(crate) struct FrameClock {
    encoder: wgpu::CommandEncoder,
    gpu_timed: bool,
    part_start: Instant,
    cpu_shadow_ms: f64,
    wall: (f64, f64),
}

impl FrameClock {
    pub fn start(renderer: &mut Renderer) -> Self {
        let gpu_timed = renderer.timing_source() == TimingSource::GpuTimestamps;
        if let Some(timer) = &mut renderer.timer {
            timer.begin_frame();
        }
        Self {
            encoder: renderer
                .gpu
                .device
                .create_command_encoder(&Default::default()),
            gpu_timed,
            part_start: Instant::now(),
            cpu_shadow_ms: 0.0,
            wall: (0.0, 0.0),
        }
    }

    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        &mut self.encoder
    }

    /// The timestamp writes of the next pass, when timed on the GPU.
    pub fn timestamps<'t>(
        &self,
        timer: &'t mut Option<Timer>,
        part: Part,
    ) -> Option<wgpu::RenderPassTimestampWrites<'t>> {
        if self.gpu_timed {
            timer.as_mut()?.pass(part)
        } else {
            None
        }
    }

    /// Ends CPU work that belongs to the shadow part (volume extrusion).
    pub fn cpu_part(&mut self, part: Part) {
        let ms = self.part_start.elapsed().as_secs_f64() * 1e3;
        if part == Part::Shadow {
            self.cpu_shadow_ms += ms;
        }
        self.part_start = Instant::now();
    }

    /// Ends a part: on the wall clock, submits and waits.
    pub fn end_part(&mut self, gpu: &Gpu, part: Part) -> Result<(), RenderError> {
        if self.gpu_timed {
            return Ok(());
        }
        let encoder = std::mem::replace(
            &mut self.encoder,
            gpu.device.create_command_encoder(&Default::default()),
        );
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        let ms = self.part_start.elapsed().as_secs_f64() * 1e3;
        match part {
            Part::Shadow => self.wall.0 += ms,
            Part::Main => self.wall.1 += ms,
        }
        self.part_start = Instant::now();
        Ok(())
    }

    /// Submits what is left, waits, and gives the part times.
    pub fn finish(mut self, renderer: &Renderer) -> Result<Timings, RenderError> {
        if let (true, Some(timer)) = (self.gpu_timed, &renderer.timer) {
            timer.resolve(&mut self.encoder);
        }
        renderer.gpu.queue.submit([self.encoder.finish()]);
        renderer.gpu.wait()?;
        let (shadow, main, source) = match (self.gpu_timed, &renderer.timer) {
            (true, Some(timer)) => {
                let (s, m) = timer.read(&renderer.gpu)?;
                (s, m, TimingSource::GpuTimestamps)
            }
            _ => (self.wall.0, self.wall.1, TimingSource::WallClock),
        };
        Ok(Timings {
            shadow_pass_ms: shadow + self.cpu_shadow_ms,
            main_pass_ms: main,
            readback_ms: 0.0,
            source,
        })
    }
}

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
        let r = &self.resources;
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let make = |label, format, usage| r.target(label, (width, height), 1, format, usage);
        if self
            .headless
            .as_ref()
            .is_none_or(|t| (t.color.0.width(), t.color.0.height()) != (width, height))
        {
            self.headless = Some(Targets {
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
        let targets = self.headless.as_mut().expect("made above");
        if metrics && targets.metrics.is_none() {
            targets.metrics = Some(make("metrics", METRICS_FORMAT, attachment));
        }
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
        let mut clock = FrameClock::start(self);
        self.encode_shadow_maps_timed(clock.encoder(), true);
        clock.end_part(&self.gpu, Part::Shadow)?;
        {
            let targets = self.headless.as_ref().expect("made above");
            let timestamps = clock.timestamps(&mut self.timer, Part::Main);
            let mut attachments = vec![
                color_target(&targets.color.1, Some(SKY)),
                color_target(&targets.lit.1, Some(wgpu::Color::TRANSPARENT)),
            ];
            if settings.metrics {
                let view = &targets.metrics.as_ref().expect("made above").1;
                attachments.push(color_target(view, Some(wgpu::Color::TRANSPARENT)));
            }
            let mut pass = clock
                .encoder()
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("main (measured)"),
                    color_attachments: &attachments,
                    depth_stencil_attachment: Some(cleared_camera_depth(&targets.depth)),
                    timestamp_writes: timestamps,
                    ..Default::default()
                });
            pass.set_pipeline(
                self.pipelines
                    .measured_for(settings.metrics, self.main_spec)
                    .expect("made above"),
            );
            self.bind_frame(&mut pass);
            self.scene.bind(&mut pass);
            self.scene.draw_all(&mut pass, true);
        }
        clock.end_part(&self.gpu, Part::Main)?;
        let mut timings = clock.finish(self)?;
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
                let (size, offset) = (map.resolution.min(largest), self.slot(k));
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
                    pass.set_bind_group(0, &self.frame_group, &[offset]);
                    pass.set_bind_group(1, &self.atlas.bind_group, &[]);
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
