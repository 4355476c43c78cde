//! The volumes' passes as a frame draws them: the kept targets, the upload of the extruded
//! vertices, and the encoding (the scene's depth and ambient term, then per light the stencil
//! count and the light's direct term where the count is 0).

use crate::frame::{MASK_CLEAR, SKY};
use crate::passes::volumes::{ExtrudedVolumes, VolumeCasters, VolumePipelines, VolumeStats};
use crate::passes::{FrameBindings, color_target};
use crate::pipelines::MASK_FORMAT;
use crate::resources::Resources;
use crate::scene::GpuScene;
use crate::timing::{FrameClock, Part, Timer};
use crate::{Gpu, RenderError};

/// The shadow volumes' kept state: their pipelines, the casters' meshes, and the targets
/// (made on first use).
pub(crate) struct VolumePass {
    pub pipelines: VolumePipelines,
    pub casters: VolumeCasters,
    pub targets: Option<VolumeTargets>,
}

/// The volume passes' kept targets and buffers.
pub(crate) struct VolumeTargets {
    pub size: (u32, u32),
    pub depth_view: wgpu::TextureView,
    pub masks: Vec<(wgpu::Texture, wgpu::TextureView)>,
    pub vertices: Option<wgpu::Buffer>,
    pub extruded: ExtrudedVolumes,
}

impl VolumeTargets {
    /// `kept` where it is of `size` with a mask for each of `lights`; else new targets, which
    /// keep the vertex buffer and the extrusion's storage of `kept`.
    pub fn fitting(
        kept: Option<Self>,
        resources: &Resources,
        format: wgpu::TextureFormat,
        size: (u32, u32),
        lights: usize,
    ) -> Self {
        if let Some(t) = kept.as_ref()
            && t.size == size
            && t.masks.len() >= lights
        {
            return kept.expect("checked above");
        }
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let (_, depth_view) = resources.target("volumes depth and stencil", size, 1, format, usage);
        let masks = (0..lights)
            .map(|_| {
                let usage = usage | wgpu::TextureUsages::COPY_SRC;
                resources.target("light mask", size, 1, MASK_FORMAT, usage)
            })
            .collect();
        let (vertices, extruded) = match kept {
            Some(k) => (k.vertices, k.extruded),
            None => (
                None,
                ExtrudedVolumes {
                    vertices: Vec::new(),
                    ranges: Vec::new(),
                    stats: VolumeStats::default(),
                },
            ),
        };
        Self {
            size,
            depth_view,
            masks,
            vertices,
            extruded,
        }
    }

    /// Writes the extruded vertices to the GPU, the buffer grown to a power of two where they
    /// no longer fit (so that a growing scene remakes it rarely).
    pub fn upload(&mut self, resources: &Resources, queue: &wgpu::Queue) {
        let bytes = (self.extruded.vertices.len() * 16) as u64;
        if bytes == 0 {
            return;
        }
        if self.vertices.as_ref().is_none_or(|b| b.size() < bytes) {
            let size = bytes.next_power_of_two().max(1 << 16);
            let usage = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST;
            self.vertices = Some(resources.buffer("shadow volumes", size, usage));
        }
        let buffer = self.vertices.as_ref().expect("made above");
        queue.write_buffer(buffer, 0, bytemuck::cast_slice(&self.extruded.vertices));
    }
}

/// What the volume passes read of the renderer's frame.
pub(crate) struct StencilFrame<'a> {
    pub gpu: &'a Gpu,
    pub pipelines: &'a VolumePipelines,
    pub targets: &'a VolumeTargets,
    pub bindings: FrameBindings<'a>,
    pub scene: &'a GpuScene,
    /// The image the frame's colour goes to.
    pub color_view: &'a wgpu::TextureView,
    /// Whether the volumes are flattened onto a plane (planar shadows) rather than extruded.
    pub planar: bool,
}

impl StencilFrame<'_> {
    /// Records the volume passes of `lights` lights into `clock`'s encoder, each timed as the
    /// part it belongs to.
    pub fn encode(
        &self,
        lights: usize,
        clock: &mut FrameClock,
        timer: &mut Option<Timer>,
    ) -> Result<(), RenderError> {
        self.depth_and_ambient(clock, timer);
        clock.end_part(self.gpu, Part::Main)?;
        for k in 0..lights {
            self.stencil(k, clock, timer);
            clock.end_part(self.gpu, Part::Shadow)?;
            self.light(k, clock, timer);
            clock.end_part(self.gpu, Part::Main)?;
        }
        Ok(())
    }

    /// The scene's depth and its ambient term; the first light's mask is cleared here.
    fn depth_and_ambient(&self, clock: &mut FrameClock, timer: &mut Option<Timer>) {
        let shading = Shading {
            label: "volumes: depth and ambient",
            clears: (Some(SKY), Some(MASK_CLEAR)),
            clear_depth_stencil: true,
        };
        let mut pass = self.begin_shading(shading, &self.targets.masks[0].1, clock, timer);
        pass.set_pipeline(&self.pipelines.depth_and_ambient);
        self.bindings.bind(&mut pass, 0);
        self.scene.bind(&mut pass);
        self.scene.draw_all(&mut pass, false);
    }

    /// Light `k`'s volumes counted into the cleared stencil.
    fn stencil(&self, k: usize, clock: &mut FrameClock, timer: &mut Option<Timer>) {
        let (z_fail, z_pass) = self.targets.extruded.ranges[k].clone();
        let timestamps = clock.timestamps(timer, Part::Shadow);
        let mut pass = clock
            .encoder()
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("volumes: stencil"),
                color_attachments: &[],
                depth_stencil_attachment: Some(depth_stencil(
                    &self.targets.depth_view,
                    false,
                    true,
                )),
                timestamp_writes: timestamps,
                ..Default::default()
            });
        self.bindings.bind(&mut pass, k as u32);
        if let Some(buffer) = &self.targets.vertices {
            pass.set_vertex_buffer(0, buffer.slice(..));
            self.pipelines
                .draw_stencil(&mut pass, (z_fail, z_pass), self.planar);
        }
    }

    /// Light `k`'s direct term where its count is 0, and its mask.
    fn light(&self, k: usize, clock: &mut FrameClock, timer: &mut Option<Timer>) {
        // The first light's mask was started by the ambient pass; the others' start empty and
        // get their shadowed pixels here. (Instances that receive no shadows get their direct
        // light in the shadowed draw too, so the first light skips it only when every
        // instance receives.)
        let first = k == 0;
        let skip_shadowed = first && self.scene.all_receive();
        let shading = Shading {
            label: "volumes: one light",
            clears: (None, (!first).then_some(MASK_CLEAR)),
            clear_depth_stencil: false,
        };
        let mut pass = self.begin_shading(shading, &self.targets.masks[k].1, clock, timer);
        pass.set_stencil_reference(0);
        self.bindings.bind(&mut pass, k as u32);
        self.scene.bind(&mut pass);
        let draws = [&self.pipelines.lit, &self.pipelines.shadowed];
        for pipeline in draws.iter().take(if skip_shadowed { 1 } else { 2 }) {
            pass.set_pipeline(pipeline);
            self.scene.draw_all(&mut pass, false);
        }
    }

    /// Begins a pass that shades into the frame's colour and a light's `mask`, timed as the
    /// main part.
    fn begin_shading<'e>(
        &self,
        shading: Shading,
        mask: &wgpu::TextureView,
        clock: &'e mut FrameClock,
        timer: &mut Option<Timer>,
    ) -> wgpu::RenderPass<'e> {
        let timestamps = clock.timestamps(timer, Part::Main);
        let clear = shading.clear_depth_stencil;
        clock
            .encoder()
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(shading.label),
                color_attachments: &[
                    color_target(self.color_view, shading.clears.0),
                    color_target(mask, shading.clears.1),
                ],
                depth_stencil_attachment: Some(depth_stencil(
                    &self.targets.depth_view,
                    clear,
                    clear,
                )),
                timestamp_writes: timestamps,
                ..Default::default()
            })
    }
}

/// How a shading pass of the volumes begins: its label, the clears of the colour and the mask
/// (or loads), and whether depth and stencil are cleared.
struct Shading {
    label: &'static str,
    clears: (Option<wgpu::Color>, Option<wgpu::Color>),
    clear_depth_stencil: bool,
}

/// The depth-stencil attachment of the volume passes: depth cleared to 0 (reversed Z: the
/// far plane) or loaded, stencil cleared to 0 or loaded; both kept.
pub(crate) fn depth_stencil(
    view: &wgpu::TextureView,
    clear_depth: bool,
    clear_stencil: bool,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    fn ops<T>(clear: Option<T>) -> wgpu::Operations<T> {
        wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        }
    }
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(ops(clear_depth.then_some(0.0))),
        stencil_ops: Some(ops(clear_stencil.then_some(0))),
    }
}
