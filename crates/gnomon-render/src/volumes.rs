//! Stenciled shadow volumes: the exact shadows gnomon measures every map against (the
//! shadows lecture, `shared/papers/shadows-lecture-volumes-and-maps.md`).
//!
//! Per frame: the casters' volumes are extruded on the CPU by the core crate
//! ([`gnomon::volumes`]); the scene's depth is laid down through the camera's projection
//! with the far plane at infinity (so volume geometry at infinity, w = 0, is never clipped);
//! the volumes are drawn into the stencil buffer with two-sided stencil and wrapping
//! increments in one pass - z-fail (Carmack's reverse: back faces behind the surface +1,
//! front faces behind it -1; right even when the camera is inside a volume) or z-pass (front
//! faces in front of the surface +1, back faces -1; wrong when a volume reaches the near
//! plane); then the scene is shaded twice under the stencil test: lit where the count is 0,
//! shadowed elsewhere. The mask is written as for shadow maps.

use std::time::Instant;

use glam::{DMat4, DVec4};
use gnomon::volumes::{MeshTopology, OpenMeshPolicy, extrude_volume, infinite_clip_from_view};
use gnomon::{Camera, Light, MapProjection, ShadowMap};

use crate::renderer::{ShadowOverride, globals, main_targets, texture};
use crate::{Frame, RenderError, RenderScene, RenderSettings, Renderer, Timings};

/// Depth and stencil of the volume passes.
pub(crate) const DEPTH_STENCIL_FORMAT: wgpu::TextureFormat =
    wgpu::TextureFormat::Depth24PlusStencil8;

/// Epsilon of the infinite projection: points at infinity land at depth 1 - epsilon.
const INFINITY_EPSILON: f64 = 1e-6;

/// How the stencil counts volume faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StencilMode {
    /// Count the faces behind the visible surface (Carmack's reverse): exact wherever the
    /// camera is, with both caps.
    #[default]
    ZFail,
    /// Count the faces in front of the visible surface: cheaper in fill on some hardware,
    /// wrong where a volume reaches the camera's near plane.
    ZPass,
}

/// The casters' meshes, ready for extrusion.
pub(crate) struct VolumeCasters {
    /// Per mesh of the scene, its topology (open meshes kept for per-triangle volumes).
    topologies: Vec<Option<MeshTopology>>,
    /// The casting instances: mesh index and placement.
    instances: Vec<(usize, DMat4)>,
}

impl VolumeCasters {
    pub fn new(scene: &RenderScene) -> Self {
        let mut topologies: Vec<Option<MeshTopology>> = vec![None; scene.meshes.len()];
        let mut instances = Vec::new();
        for instance in scene.instances.iter().filter(|i| i.casts) {
            let slot = &mut topologies[instance.mesh];
            if slot.is_none() {
                let mesh = &scene.meshes[instance.mesh];
                // Per-triangle volumes keep any mesh correct; bad indices were caught when
                // the mesh was made, so an error here leaves the mesh without a volume.
                *slot =
                    MeshTopology::new(&mesh.positions, &mesh.indices, OpenMeshPolicy::PerTriangle)
                        .ok();
            }
            instances.push((instance.mesh, instance.world_from_object));
        }
        Self {
            topologies,
            instances,
        }
    }

    /// Every caster's volume, homogeneous world vertices, three per triangle.
    pub fn extrude(&self, light: &Light) -> Vec<[f32; 4]> {
        let mut out: Vec<DVec4> = Vec::new();
        for (mesh, world_from_object) in &self.instances {
            if let Some(topology) = &self.topologies[*mesh] {
                extrude_volume(topology, *world_from_object, light, &mut out);
            }
        }
        out.iter().map(|v| v.as_vec4().to_array()).collect()
    }
}

/// The pipelines of the volume passes.
pub(crate) struct VolumePipelines {
    depth: wgpu::RenderPipeline,
    z_fail: wgpu::RenderPipeline,
    z_pass: wgpu::RenderPipeline,
    lit: wgpu::RenderPipeline,
    shadowed: wgpu::RenderPipeline,
}

impl VolumePipelines {
    pub fn new(
        device: &wgpu::Device,
        shader: &wgpu::ShaderModule,
        main_layout: &wgpu::PipelineLayout,
        globals_layout: &wgpu::PipelineLayout,
        scene_vertices: &wgpu::VertexBufferLayout<'_>,
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> Self {
        let volume_attributes = wgpu::vertex_attr_array![0 => Float32x4];
        let volume_vertices = wgpu::VertexBufferLayout {
            array_stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &volume_attributes,
        };
        let face = |depth_fail_op, pass_op| wgpu::StencilFaceState {
            compare: wgpu::CompareFunction::Always,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op,
            pass_op,
        };
        let stencil = |front, back, read_mask, write_mask| wgpu::StencilState {
            front,
            back,
            read_mask,
            write_mask,
        };
        let test = |compare| wgpu::StencilFaceState {
            compare,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Keep,
            pass_op: wgpu::StencilOperation::Keep,
        };
        let pipeline = |label,
                        layout,
                        vertex_entry,
                        buffer: &wgpu::VertexBufferLayout<'_>,
                        fragment: Option<(&str, &[Option<wgpu::ColorTargetState>])>,
                        depth_write,
                        depth_compare,
                        stencil: wgpu::StencilState| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: shader,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers: &[Some(buffer.clone())],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_STENCIL_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(depth_compare),
                    stencil,
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: fragment.map(|(entry, targets)| wgpu::FragmentState {
                    module: shader,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        use wgpu::CompareFunction as C;
        use wgpu::StencilOperation as S;
        let no_stencil = wgpu::StencilState::default();
        Self {
            depth: pipeline(
                "volumes: scene depth",
                globals_layout,
                "vs_main",
                scene_vertices,
                None,
                true,
                C::Less,
                no_stencil.clone(),
            ),
            z_fail: pipeline(
                "volumes: z-fail",
                globals_layout,
                "vs_volume",
                &volume_vertices,
                None,
                false,
                C::Less,
                stencil(
                    face(S::DecrementWrap, S::Keep),
                    face(S::IncrementWrap, S::Keep),
                    0xff,
                    0xff,
                ),
            ),
            z_pass: pipeline(
                "volumes: z-pass",
                globals_layout,
                "vs_volume",
                &volume_vertices,
                None,
                false,
                C::Less,
                stencil(
                    face(S::Keep, S::IncrementWrap),
                    face(S::Keep, S::DecrementWrap),
                    0xff,
                    0xff,
                ),
            ),
            lit: pipeline(
                "volumes: lit",
                main_layout,
                "vs_main",
                scene_vertices,
                Some(("fs_main", targets)),
                false,
                C::LessEqual,
                stencil(test(C::Equal), test(C::Equal), 0xff, 0),
            ),
            shadowed: pipeline(
                "volumes: shadowed",
                main_layout,
                "vs_main",
                scene_vertices,
                Some(("fs_main", targets)),
                false,
                C::LessEqual,
                stencil(test(C::NotEqual), test(C::NotEqual), 0xff, 0),
            ),
        }
    }
}

/// The depth-stencil attachment of the volume passes: cleared to depth 1 and stencil 0, or
/// loaded; kept either way.
fn depth_stencil(
    view: &wgpu::TextureView,
    clear: bool,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    fn ops<T>(clear: Option<T>) -> wgpu::Operations<T> {
        wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        }
    }
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(ops(clear.then_some(1.0))),
        stencil_ops: Some(ops(clear.then_some(0))),
    }
}

impl Renderer {
    /// Renders one frame of `camera` lit by `light` with exact shadows from stenciled shadow
    /// volumes (see the module documentation). `settings`' filter and bias do not apply.
    pub fn render_volumes(
        &self,
        camera: &Camera,
        light: &Light,
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<Frame, RenderError> {
        let (width, height) = self.image_size(settings)?;
        let device = &self.gpu.device;
        let error_scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let start = Instant::now();
        let volume = self.volume_casters.extrude(light);
        let clip_from_world =
            infinite_clip_from_view(&camera.lens(), INFINITY_EPSILON) * camera.view_from_world();
        // No map: the stencil decides (the map's fields are unused).
        let no_map = ShadowMap {
            clip_from_world: DMat4::IDENTITY,
            depth_from_world: DVec4::ZERO,
            resolution: 1,
            viewport_inset: 0,
            projection: MapProjection::Orthographic,
        };
        use wgpu::util::DeviceExt;
        let uniform = |shadow_override| {
            let g = globals(
                camera,
                clip_from_world,
                light,
                &no_map,
                settings,
                shadow_override,
            );
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("globals"),
                contents: bytemuck::bytes_of(&g),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let (lit_uniform, shadowed_uniform) = (
            uniform(ShadowOverride::Lit),
            uniform(ShadowOverride::Shadowed),
        );
        let volume_buffer = (!volume.is_empty()).then(|| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("shadow volumes"),
                contents: bytemuck::cast_slice(&volume),
                usage: wgpu::BufferUsages::VERTEX,
            })
        });
        let (color, mask) = self.main_images(width, height);
        let depth = texture(
            device,
            "depth and stencil",
            width,
            height,
            DEPTH_STENCIL_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let dummy_map = texture(
            device,
            "no shadow map",
            1,
            1,
            crate::renderer::DEPTH_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let (color_view, mask_view, depth_view, dummy_view) = (
            color.create_view(&Default::default()),
            mask.create_view(&Default::default()),
            depth.create_view(&Default::default()),
            dummy_map.create_view(&Default::default()),
        );
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &self.volumes.depth.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: lit_uniform.as_entire_binding(),
            }],
        });
        let main_group = |uniform: &wgpu::Buffer| self.main_bind_group(uniform, &dummy_view);
        let (lit_group, shadowed_group) = (main_group(&lit_uniform), main_group(&shadowed_uniform));
        let setup_ms = start.elapsed().as_secs_f64() * 1e3;

        let start = Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("volumes: depth and stencil"),
                color_attachments: &[],
                depth_stencil_attachment: Some(depth_stencil(&depth_view, true)),
                ..Default::default()
            });
            pass.set_bind_group(0, &globals_group, &[]);
            pass.set_pipeline(&self.volumes.depth);
            self.scene.draw(&mut pass, self.scene.all_indices.clone());
            if let Some(buffer) = &volume_buffer {
                pass.set_pipeline(match mode {
                    StencilMode::ZFail => &self.volumes.z_fail,
                    StencilMode::ZPass => &self.volumes.z_pass,
                });
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..volume.len() as u32, 0..1);
            }
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        let stencil_ms = start.elapsed().as_secs_f64() * 1e3;

        let start = Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("volumes: shading"),
                color_attachments: &main_targets(&color_view, &mask_view),
                depth_stencil_attachment: Some(depth_stencil(&depth_view, false)),
                ..Default::default()
            });
            pass.set_stencil_reference(0);
            for (pipeline, group) in [
                (&self.volumes.lit, &lit_group),
                (&self.volumes.shadowed, &shadowed_group),
            ] {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                self.scene.draw(&mut pass, self.scene.all_indices.clone());
            }
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        let main_pass_ms = start.elapsed().as_secs_f64() * 1e3;
        if let Some(error) = pollster::block_on(error_scope.pop()) {
            return Err(RenderError::Gpu(error.to_string()));
        }
        let start = Instant::now();
        let (color_bytes, mask_bytes) = self.read_main_images(&color, &mask)?;
        let readback_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(Frame {
            width,
            height,
            color: color_bytes,
            mask: mask_bytes,
            light_view: None,
            timings: Timings {
                shadow_pass_ms: setup_ms + stencil_ms,
                main_pass_ms,
                readback_ms,
            },
        })
    }
}
