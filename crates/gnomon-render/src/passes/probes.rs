//! The probe pass: its kept resources (a pipeline that draws points, a square target of state
//! bits, one per point, and the points' buffer) and a batch of points drawn into them.

use crate::passes::{FrameBindings, color_target};
use crate::pipelines::{Pipelines, scene_buffers};
use crate::resources::Resources;
use crate::scene::Vertex;

/// The probes' target: one u32 of state bits per point.
const PROBE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// Points per batch: one per texel of a square target of this side (`PROBE_SIZE` in the
/// WGSL).
pub(crate) const PROBE_SIZE: u32 = 256;

/// The probe pass's kept resources (made on first use).
pub(crate) struct Probes {
    pub pipeline: wgpu::RenderPipeline,
    pub target: (wgpu::Texture, wgpu::TextureView),
    pub points: wgpu::Buffer,
}

impl Probes {
    /// The pass's pipeline, target and point buffer.
    pub fn new(device: &wgpu::Device, resources: &Resources, pipelines: &Pipelines) -> Self {
        let shader = &pipelines.shader;
        let [vertex_buffer, _] = scene_buffers();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("probes"),
            layout: Some(&pipelines.layout),
            vertex: wgpu::VertexState {
                module: shader,
                entry_point: Some("vs_probe"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_buffer)],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::PointList,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: shader,
                entry_point: Some("fs_probe"),
                compilation_options: Default::default(),
                targets: &[Some(PROBE_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let batch = (PROBE_SIZE * PROBE_SIZE) as u64;
        Self {
            pipeline,
            target: resources.target(
                "probes",
                (PROBE_SIZE, PROBE_SIZE),
                1,
                PROBE_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            ),
            points: resources.buffer(
                "probe points",
                batch * std::mem::size_of::<Vertex>() as u64,
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
        }
    }

    /// Records the first `count` points of the buffer drawn into the target (cleared).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bindings: FrameBindings<'_>,
        count: u32,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("probes"),
            color_attachments: &[color_target(&self.target.1, Some(wgpu::Color::TRANSPARENT))],
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        bindings.bind(&mut pass, 0);
        pass.set_vertex_buffer(0, self.points.slice(..));
        pass.draw(0..count, 0..1);
    }
}
