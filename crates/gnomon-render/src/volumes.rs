//! Stenciled shadow volumes: the exact shadows gnomon measures every map against (the
//! shadows lecture, `shared/papers/shadows-lecture-volumes-and-maps.md`).
//!
//! Per frame: the scene's depth is laid down through the camera's projection with the far
//! plane at infinity (so volume geometry at infinity, w = 0, is never clipped) and the
//! ambient term drawn. Then per light: the casters' volumes are extruded on the CPU by the
//! core crate ([`gnomon::volumes`]) and drawn into the cleared stencil buffer with two-sided
//! stencil and wrapping increments in one pass - z-fail (Carmack's reverse: back faces
//! behind the surface +1, front faces behind it -1; right even when the camera is inside a
//! volume), z-pass (front faces in front of the surface +1, back faces -1; wrong when a
//! volume reaches the near plane) or per caster (z-pass without caps where the caster's
//! volume cannot reach the near plane, z-fail elsewhere); then the light's direct term is
//! added where the count is 0 and its mask written (lit where the count is 0, shadowed
//! elsewhere, as for shadow maps).

use std::ops::Range;
use std::time::Instant;

use glam::{DMat4, DVec4};
use gnomon::volumes::{
    MeshTopology, NearClipFallback, NearClipVolume, OpenMeshPolicy, VolumeParts, extrude_volume,
    infinite_clip_from_view,
};
use gnomon::{Aabb, Camera, Light, MapProjection, ShadowMap};

use crate::renderer::{MASK_CLEAR, SKY, ShadowOverride, color_target, globals, texture};
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
    /// Per caster (a speed option, exact like z-fail): z-pass without caps for the casters
    /// whose volume cannot reach the near plane (their bounds lie outside the near clip
    /// volume, [`gnomon::volumes::NearClipVolume`]), z-fail for the others. Both count into
    /// the same stencil: each closed volume adds one where it covers a pixel's surface
    /// either way.
    PerCaster,
}

/// What the volume passes drew, over all lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct VolumeStats {
    /// Volume triangles drawn into the stencil.
    pub triangles: usize,
    /// Caster volumes counted with z-fail (with caps).
    pub z_fail_casters: usize,
    /// Caster volumes counted with z-pass (sides only).
    pub z_pass_casters: usize,
    /// Set when [`StencilMode::PerCaster`] sent every caster to z-fail because the near clip
    /// volume was flat for some light.
    pub near_clip_fallback: Option<NearClipFallback>,
}

/// A frame drawn with shadow volumes, lit by one or more lights.
#[derive(Debug, Clone, PartialEq)]
pub struct VolumeFrame {
    /// The image; its mask says where at least one light reaches (for one light, that
    /// light's mask).
    pub frame: Frame,
    /// Each light's own direct-light mask, in the order of the lights.
    pub light_masks: Vec<Vec<u8>>,
    /// What was drawn.
    pub stats: VolumeStats,
}

/// The casters' meshes, ready for extrusion.
pub(crate) struct VolumeCasters {
    /// Per mesh of the scene, its topology (open meshes kept for per-triangle volumes).
    topologies: Vec<Option<MeshTopology>>,
    /// The casting instances: mesh index, placement and world bounds (none for a flat or
    /// empty mesh: it then always counts as reaching the near plane).
    instances: Vec<(usize, DMat4, Option<Aabb>)>,
}

/// One light's volumes: homogeneous world vertices, three per triangle; the z-fail volumes
/// (closed) first, then the z-pass ones (sides only).
pub(crate) struct ExtrudedVolumes {
    vertices: Vec<[f32; 4]>,
    z_fail: Range<u32>,
    z_pass: Range<u32>,
    stats: VolumeStats,
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
            let bounds = scene.instance_bounds(instance).ok();
            instances.push((instance.mesh, instance.world_from_object, bounds));
        }
        Self {
            topologies,
            instances,
        }
    }

    /// Every caster's volume for `light`, counted as `mode` says (`camera` decides which
    /// casters can reach its near plane under [`StencilMode::PerCaster`]).
    pub fn extrude(&self, camera: &Camera, light: &Light, mode: StencilMode) -> ExtrudedVolumes {
        let near_clip =
            (mode == StencilMode::PerCaster).then(|| NearClipVolume::new(camera, light));
        let z_fail = |bounds: &Option<Aabb>| match mode {
            StencilMode::ZFail => true,
            StencilMode::ZPass => false,
            StencilMode::PerCaster => match (&near_clip, bounds) {
                (Some(volume), Some(b)) => volume.may_reach(b),
                _ => true,
            },
        };
        let mut out: Vec<DVec4> = Vec::new();
        let mut stats = VolumeStats {
            near_clip_fallback: near_clip.as_ref().and_then(NearClipVolume::fallback),
            ..VolumeStats::default()
        };
        let mut z_fail_end = 0;
        for counted_z_fail in [true, false] {
            let parts = if counted_z_fail {
                VolumeParts::Closed
            } else {
                VolumeParts::SidesOnly
            };
            for (mesh, world_from_object, bounds) in &self.instances {
                let Some(topology) = &self.topologies[*mesh] else {
                    continue;
                };
                if z_fail(bounds) != counted_z_fail {
                    continue;
                }
                let counts = extrude_volume(topology, *world_from_object, light, parts, &mut out);
                stats.triangles += counts.total();
                if counted_z_fail {
                    stats.z_fail_casters += 1;
                } else {
                    stats.z_pass_casters += 1;
                }
            }
            if counted_z_fail {
                z_fail_end = out.len() as u32;
            }
        }
        ExtrudedVolumes {
            vertices: out.iter().map(|v| v.as_vec4().to_array()).collect(),
            z_fail: 0..z_fail_end,
            z_pass: z_fail_end..out.len() as u32,
            stats,
        }
    }
}

/// The pipelines of the volume passes.
pub(crate) struct VolumePipelines {
    /// The scene's depth, the ambient term and the first light's mask as if shadowed.
    depth_and_ambient: wgpu::RenderPipeline,
    z_fail: wgpu::RenderPipeline,
    z_pass: wgpu::RenderPipeline,
    /// One light's direct light added where its stencil count is 0, and its mask.
    lit: wgpu::RenderPipeline,
    /// Its mask where the count is not 0, and the direct light of instances that receive no
    /// shadows (skipped for the first light when every instance receives: the ambient pass
    /// wrote its mask).
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
        // Lights: colour added (linear, before sRGB encoding), mask written.
        let additive_targets = [
            targets[0].clone().map(|t| wgpu::ColorTargetState {
                blend: Some(wgpu::BlendState {
                    color: wgpu::BlendComponent {
                        src_factor: wgpu::BlendFactor::One,
                        dst_factor: wgpu::BlendFactor::One,
                        operation: wgpu::BlendOperation::Add,
                    },
                    alpha: wgpu::BlendComponent::REPLACE,
                }),
                ..t
            }),
            targets[1].clone(),
        ];
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
        // The volumes: stencil only, two-sided, no depth writes; front and back faces count
        // as `front` and `back` say.
        let volumes = |label, front, back| {
            pipeline(
                label,
                globals_layout,
                "vs_volume",
                &volume_vertices,
                None,
                false,
                C::Less,
                stencil(front, back, 0xff, 0xff),
            )
        };
        // One light's shading: the scene where the stencil count compares to 0 as `compare`
        // says, colour added.
        let light_pass = |label, compare| {
            pipeline(
                label,
                main_layout,
                "vs_main",
                scene_vertices,
                Some(("fs_main", &additive_targets)),
                false,
                C::LessEqual,
                stencil(test(compare), test(compare), 0xff, 0),
            )
        };
        Self {
            z_fail: volumes(
                "volumes: z-fail",
                face(S::DecrementWrap, S::Keep),
                face(S::IncrementWrap, S::Keep),
            ),
            z_pass: volumes(
                "volumes: z-pass",
                face(S::Keep, S::IncrementWrap),
                face(S::Keep, S::DecrementWrap),
            ),
            depth_and_ambient: pipeline(
                "volumes: depth and ambient",
                main_layout,
                "vs_main",
                scene_vertices,
                Some(("fs_main", targets)),
                true,
                C::Less,
                no_stencil.clone(),
            ),
            lit: light_pass("volumes: lit", C::Equal),
            shadowed: light_pass("volumes: shadowed", C::NotEqual),
        }
    }
}

/// Which lighting terms a draw adds.
#[derive(Clone, Copy)]
enum Terms {
    AmbientOnly,
    DirectOnly,
}

/// The depth-stencil attachment of the volume passes: depth cleared to 1 or loaded, stencil
/// cleared to 0 or loaded; both kept.
fn depth_stencil(
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
        depth_ops: Some(ops(clear_depth.then_some(1.0))),
        stencil_ops: Some(ops(clear_stencil.then_some(0))),
    }
}

impl Renderer {
    /// Renders one frame of `camera` lit by `light` with exact shadows from stenciled shadow
    /// volumes; see [`Renderer::render_volumes_lit_by`].
    pub fn render_volumes(
        &self,
        camera: &Camera,
        light: &Light,
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<VolumeFrame, RenderError> {
        self.render_volumes_lit_by(camera, std::slice::from_ref(light), settings, mode)
    }

    /// Renders one frame of `camera` lit by `lights` with exact shadows from stenciled
    /// shadow volumes (see the module documentation): the scene's depth and the ambient term
    /// once, then per light its volumes into a cleared stencil and its direct light added
    /// where the count is 0. `settings`' filter and bias do not apply. Timings: the shadow
    /// pass is extrusion plus stencil passes, the main pass the depth, ambient and lighting
    /// passes, summed over the lights.
    pub fn render_volumes_lit_by(
        &self,
        camera: &Camera,
        lights: &[Light],
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<VolumeFrame, RenderError> {
        if lights.is_empty() {
            return Err(RenderError::Invalid(
                "shadow volumes need at least one light".into(),
            ));
        }
        let (width, height) = self.image_size(settings)?;
        let device = &self.gpu.device;
        let error_scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
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
        let uniform = |light: &Light, shadow_override, terms: Terms| {
            let g = globals(
                camera,
                clip_from_world,
                light,
                &no_map,
                settings,
                shadow_override,
            );
            let g = match terms {
                Terms::AmbientOnly => g.ambient_only(),
                Terms::DirectOnly => g.direct_light_only(),
            };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("globals"),
                contents: bytemuck::bytes_of(&g),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let color = self.color_image(width, height);
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
        let (color_view, depth_view, dummy_view) = (
            color.create_view(&Default::default()),
            depth.create_view(&Default::default()),
            dummy_map.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
        );
        // The ambient term alone; the mask of the first light as if all were shadowed (the
        // light's pass then writes where it reaches).
        let ambient_uniform = uniform(&lights[0], ShadowOverride::Shadowed, Terms::AmbientOnly);
        let ambient_group = self.main_bind_group(&ambient_uniform, &dummy_view);
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &self.volumes.z_fail.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: ambient_uniform.as_entire_binding(),
            }],
        });
        let masks: Vec<wgpu::Texture> = lights
            .iter()
            .map(|_| self.mask_image(width, height))
            .collect();
        let mask_views: Vec<wgpu::TextureView> = masks
            .iter()
            .map(|m| m.create_view(&Default::default()))
            .collect();
        let mut timings = Timings::default();
        let start = Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("volumes: depth and ambient"),
                color_attachments: &[
                    color_target(&color_view, Some(SKY)),
                    color_target(&mask_views[0], Some(MASK_CLEAR)),
                ],
                depth_stencil_attachment: Some(depth_stencil(&depth_view, true, true)),
                ..Default::default()
            });
            pass.set_bind_group(0, &ambient_group, &[]);
            pass.set_pipeline(&self.volumes.depth_and_ambient);
            self.scene.draw(&mut pass, self.scene.all_indices.clone());
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        timings.main_pass_ms += start.elapsed().as_secs_f64() * 1e3;

        let mut stats = VolumeStats::default();
        for (k, light) in lights.iter().enumerate() {
            let start = Instant::now();
            let volumes = self.volume_casters.extrude(camera, light, mode);
            stats.triangles += volumes.stats.triangles;
            stats.z_fail_casters += volumes.stats.z_fail_casters;
            stats.z_pass_casters += volumes.stats.z_pass_casters;
            stats.near_clip_fallback = stats
                .near_clip_fallback
                .or(volumes.stats.near_clip_fallback);
            let volume_buffer = (!volumes.vertices.is_empty()).then(|| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("shadow volumes"),
                    contents: bytemuck::cast_slice(&volumes.vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                })
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("volumes: stencil"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(depth_stencil(&depth_view, false, true)),
                    ..Default::default()
                });
                pass.set_bind_group(0, &globals_group, &[]);
                if let Some(buffer) = &volume_buffer {
                    pass.set_vertex_buffer(0, buffer.slice(..));
                    for (pipeline, range) in [
                        (&self.volumes.z_fail, volumes.z_fail.clone()),
                        (&self.volumes.z_pass, volumes.z_pass.clone()),
                    ] {
                        if !range.is_empty() {
                            pass.set_pipeline(pipeline);
                            pass.draw(range, 0..1);
                        }
                    }
                }
            }
            self.gpu.queue.submit([encoder.finish()]);
            self.gpu.wait()?;
            timings.shadow_pass_ms += start.elapsed().as_secs_f64() * 1e3;

            let start = Instant::now();
            let (lit_uniform, shadowed_uniform) = (
                uniform(light, ShadowOverride::Lit, Terms::DirectOnly),
                uniform(light, ShadowOverride::Shadowed, Terms::DirectOnly),
            );
            let (lit_group, shadowed_group) = (
                self.main_bind_group(&lit_uniform, &dummy_view),
                self.main_bind_group(&shadowed_uniform, &dummy_view),
            );
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                // The first light's mask was started by the ambient pass; the others' start
                // empty and get their shadowed pixels here. (Instances that receive no
                // shadows get their direct light in the shadowed draw too, so the first light
                // skips it only when every instance receives.)
                let first = k == 0;
                let skip_shadowed = first && self.scene.all_receive;
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("volumes: one light"),
                    color_attachments: &[
                        color_target(&color_view, None),
                        color_target(&mask_views[k], (!first).then_some(MASK_CLEAR)),
                    ],
                    depth_stencil_attachment: Some(depth_stencil(&depth_view, false, false)),
                    ..Default::default()
                });
                pass.set_stencil_reference(0);
                let draws = [
                    (&self.volumes.lit, &lit_group),
                    (&self.volumes.shadowed, &shadowed_group),
                ];
                for (pipeline, group) in draws.iter().take(if skip_shadowed { 1 } else { 2 }) {
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, *group, &[]);
                    self.scene.draw(&mut pass, self.scene.all_indices.clone());
                }
            }
            self.gpu.queue.submit([encoder.finish()]);
            self.gpu.wait()?;
            timings.main_pass_ms += start.elapsed().as_secs_f64() * 1e3;
        }
        if let Some(error) = pollster::block_on(error_scope.pop()) {
            return Err(RenderError::Gpu(error.to_string()));
        }
        let start = Instant::now();
        let color_bytes = self.read_color(&color)?;
        let light_masks = masks
            .iter()
            .map(|m| self.read_mask(m))
            .collect::<Result<Vec<_>, _>>()?;
        timings.readback_ms = start.elapsed().as_secs_f64() * 1e3;
        // Lit by any light: 255 beats 0; empty pixels are empty for every light.
        let mut mask = light_masks[0].clone();
        for other in &light_masks[1..] {
            for (m, o) in mask.iter_mut().zip(other) {
                *m = (*m).max(*o);
            }
        }
        Ok(VolumeFrame {
            frame: Frame {
                width,
                height,
                color: color_bytes,
                mask,
                light_view: None,
                metrics: None,
                timings,
            },
            light_masks,
            stats,
        })
    }
}
