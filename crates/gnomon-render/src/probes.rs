//! Probes: a frame's shadow state at given surface points, as its main pass reads it (the
//! map its selection picks, the normal offset, one tap; lit beyond a cascade's shadow
//! distance), for measurements on fixed world points (`gnomon flicker`).

use glam::DVec3;
use gnomon::Camera;

use crate::error::{InvalidInput, RenderError};
use crate::headless::color_target;
use crate::pipelines::scene_buffers;

/// The probes' target: one u32 of state bits per point.
const PROBE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
use crate::records::ShadowedLight;
use crate::renderer::{RenderSettings, Renderer};
use crate::scene::Vertex;

/// Points per batch: one per texel of a square target of this side (`PROBE_SIZE` in the
/// WGSL).
const PROBE_SIZE: u32 = 256;

/// The probe pass's kept resources (made on first use).
pub(crate) struct Probes {
    pipeline: wgpu::RenderPipeline,
    target: (wgpu::Texture, wgpu::TextureView),
    points: wgpu::Buffer,
}

impl Renderer {
    /// Whether light 0 of `lights` reaches each surface point (world position, unit normal)
    /// according to its shadow maps, one tap, as the main pass's mask reads it: true where
    /// the map says lit (or beyond a cascade's shadow distance), false where shadowed. Facing
    /// the light is not judged here. Prepares the frame (as [`Renderer::prepare`]) and draws
    /// its maps.
    pub fn lit_at_points(
        &mut self,
        camera: &Camera,
        lights: &[ShadowedLight<'_>],
        settings: &RenderSettings,
        points: &[(DVec3, DVec3)],
    ) -> Result<Vec<bool>, RenderError> {
        self.prepare(camera, lights, settings)?;
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.encode_shadow_maps(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        if self.probes.is_none() {
            self.probes = Some(self.make_probes());
        }
        let view_from_world = camera.view_from_world();
        let batch = (PROBE_SIZE * PROBE_SIZE) as usize;
        let mut lit = Vec::with_capacity(points.len());
        for chunk in points.chunks(batch) {
            let vertices: Vec<Vertex> = chunk
                .iter()
                .map(|(p, n)| Vertex {
                    position: view_from_world.transform_point3(*p).as_vec3().to_array(),
                    normal: view_from_world.transform_vector3(*n).as_vec3().to_array(),
                    uv: [0.0; 2],
                })
                .collect();
            let probes = self.probes.as_ref().expect("made above");
            self.gpu
                .queue
                .write_buffer(&probes.points, 0, bytemuck::cast_slice(&vertices));
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("probes"),
                    color_attachments: &[color_target(
                        &probes.target.1,
                        Some(wgpu::Color::TRANSPARENT),
                    )],
                    ..Default::default()
                });
                pass.set_pipeline(&probes.pipeline);
                self.bind_frame(&mut pass);
                pass.set_vertex_buffer(0, probes.points.slice(..));
                pass.draw(0..chunk.len() as u32, 0..1);
            }
            self.gpu.queue.submit([encoder.finish()]);
            let bits = self.readback.read(
                &self.gpu,
                &self.resources,
                &self.probes.as_ref().expect("made above").target.0,
                4,
                0,
            )?;
            for texel in bits.chunks_exact(4).take(chunk.len()) {
                let b = u32::from_le_bytes([texel[0], texel[1], texel[2], texel[3]]);
                if b & 2 == 0 {
                    return Err(InvalidInput::ProbeNotDrawn.into());
                }
                lit.push(b & 1 != 0);
            }
        }
        Ok(lit)
    }

    fn make_probes(&self) -> Probes {
        let device = &self.gpu.device;
        let shader = &self.pipelines.shader;
        let [vertex_buffer, _] = scene_buffers();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("probes"),
            layout: Some(&self.pipelines.layout),
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
        Probes {
            pipeline,
            target: self.resources.target(
                "probes",
                (PROBE_SIZE, PROBE_SIZE),
                1,
                PROBE_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            ),
            points: self.resources.buffer(
                "probe points",
                batch * std::mem::size_of::<Vertex>() as u64,
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
        }
    }
}
