//! The shadow volumes' kept pipelines, targets and caster meshes, and the extrusion of
//! each frame's volumes (the passes are encoded in `volumes.rs`).

use std::ops::Range;

use glam::DVec3;
use glam::DVec4;
use gnomon::planar::PlanarReceiver;
use gnomon::volumes::{
    MeshTopology, NearClipFallback, NearClipVolume, OpenMeshPolicy, VolumeParts, extrude_volume,
};
use gnomon::{Aabb, Camera, Light};

use crate::pipelines::{COLOR_FORMAT, MASK_FORMAT, PipelineSpec, Pipelines, build, scene_buffers};
use crate::scene::SceneInstance;
use crate::{Frame, Gpu, RenderScene};

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
    /// What was drawn.
    pub stats: VolumeStats,
}

/// How far the volumes' caps are pushed behind the faces they lie on (and the planar
/// receiver pulled in front of its face), in units of the f32's last place of the depth: the
/// shader's `DEPTH_PUSH_ULPS` (see [`VolumePipelines::new`]).
pub(crate) const PUSH_ULPS: f64 = 16.0;

/// What fills the stencil of a light: its shadow volumes, or planar shadows.
#[derive(Clone, Copy)]
pub(crate) enum Stenciled<'a> {
    Volumes(StencilMode),
    Planar(&'a PlanarReceiver),
}

/// The casters' meshes, ready for extrusion (their placements are the scene's instances).
pub(crate) struct VolumeCasters {
    /// Per mesh of the scene, its topology (open meshes kept for per-triangle volumes).
    pub topologies: Vec<Option<MeshTopology>>,
    /// The last extrusion (kept so that frames reuse its memory).
    pub out: Vec<DVec4>,
}

/// The volumes of every light of a frame: view-space homogeneous vertices, three per
/// triangle; per light, its z-fail volumes (closed) and its z-pass ones (sides only).
pub(crate) struct ExtrudedVolumes {
    pub vertices: Vec<[f32; 4]>,
    pub ranges: Vec<(Range<u32>, Range<u32>)>,
    pub stats: VolumeStats,
}

impl VolumeCasters {
    pub fn new(scene: &RenderScene) -> Self {
        let mut topologies: Vec<Option<MeshTopology>> = vec![None; scene.meshes.len()];
        for instance in &scene.instances {
            if instance.casts && instance.mesh < scene.meshes.len() {
                let slot = &mut topologies[instance.mesh];
                if slot.is_none() {
                    let mesh = &scene.meshes[instance.mesh];
                    // Per-triangle volumes keep any mesh correct; bad indices were caught when
                    // the mesh was made, so an error here leaves the mesh without a volume.
                    *slot = MeshTopology::new(
                        &mesh.positions,
                        &mesh.indices,
                        OpenMeshPolicy::PerTriangle,
                    )
                    .ok();
                }
            }
        }
        Self {
            topologies,
            out: Vec::new(),
        }
    }

    /// Every casting instance's volume for each light, counted as `mode` says (`camera`
    /// decides which casters can reach its near plane under [`StencilMode::PerCaster`]; an
    /// instance without bounds always counts as reaching it), in view space.
    pub fn extrude(
        &mut self,
        instances: &[SceneInstance],
        camera: &Camera,
        lights: &[Light],
        mode: StencilMode,
        into: &mut ExtrudedVolumes,
    ) {
        into.vertices.clear();
        into.ranges.clear();
        into.stats = VolumeStats::default();
        let view_from_world = camera.view_from_world();
        for light in lights {
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
            into.stats.near_clip_fallback = into
                .stats
                .near_clip_fallback
                .or(near_clip.as_ref().and_then(NearClipVolume::fallback));
            let start = into.vertices.len() as u32;
            let mut z_fail_end = start;
            for counted_z_fail in [true, false] {
                let parts = if counted_z_fail {
                    VolumeParts::Closed
                } else {
                    VolumeParts::SidesOnly
                };
                for instance in instances.iter().filter(|i| i.casts) {
                    let Some(topology) = &self.topologies[instance.mesh] else {
                        continue;
                    };
                    if z_fail(&instance.bounds) != counted_z_fail {
                        continue;
                    }
                    self.out.clear();
                    let counts = extrude_volume(
                        topology,
                        instance.world_from_object,
                        light,
                        parts,
                        &mut self.out,
                    );
                    into.stats.triangles += counts.total();
                    if counted_z_fail {
                        into.stats.z_fail_casters += 1;
                    } else {
                        into.stats.z_pass_casters += 1;
                    }
                    // To view space in f64 (directions at infinity stay directions).
                    into.vertices.extend(
                        self.out
                            .iter()
                            .map(|v| (view_from_world * *v).as_vec4().to_array()),
                    );
                }
                if counted_z_fail {
                    z_fail_end = into.vertices.len() as u32;
                }
            }
            into.ranges
                .push((start..z_fail_end, z_fail_end..into.vertices.len() as u32));
        }
    }
}

impl VolumeCasters {
    /// Planar shadows of every light on `receiver`, in view space: per light, the receiver
    /// polygon's triangles, then every casting instance's triangles flattened onto its plane
    /// (the ranges take the places of the z-fail and z-pass volumes).
    pub fn flatten(
        &mut self,
        scene: &[SceneInstance],
        camera: &Camera,
        lights: &[Light],
        receiver: &PlanarReceiver,
        into: &mut ExtrudedVolumes,
    ) {
        into.vertices.clear();
        into.ranges.clear();
        into.stats = VolumeStats::default();
        let view_from_world = camera.view_from_world();
        let to_view = |p: DVec3| (view_from_world * p.extend(1.0)).as_vec4().to_array();
        let mut flat = Vec::new();
        for light in lights {
            let start = into.vertices.len() as u32;
            into.vertices
                .extend(receiver.triangles().flatten().map(to_view));
            let mid = into.vertices.len() as u32;
            for instance in scene.iter().filter(|i| i.casts) {
                let Some(topology) = &self.topologies[instance.mesh] else {
                    continue;
                };
                into.stats.z_fail_casters += 1;
                let (m, positions) = (instance.world_from_object, topology.positions());
                for t in topology.triangles() {
                    let corner = |k: usize| m.transform_point3(positions[t[k] as usize]);
                    flat.clear();
                    gnomon::planar::flatten_triangle(
                        light,
                        &receiver.plane,
                        [corner(0), corner(1), corner(2)],
                        &mut flat,
                    );
                    into.stats.triangles += flat.len();
                    into.vertices
                        .extend(flat.iter().flatten().map(|p| to_view(*p)));
                }
            }
            into.ranges
                .push((start..mid, mid..into.vertices.len() as u32));
        }
    }
}

/// The pipelines of the volume passes.
pub(crate) struct VolumePipelines {
    /// Whether the depth is Depth32FloatStencil8 (else Depth24PlusStencil8).
    pub float_depth: bool,
    pub format: wgpu::TextureFormat,
    /// The scene's depth, the ambient term and the first light's mask as if shadowed.
    pub depth_and_ambient: wgpu::RenderPipeline,
    pub z_fail: wgpu::RenderPipeline,
    pub z_pass: wgpu::RenderPipeline,
    /// One light's direct light added where its stencil count is 0, and its mask.
    pub lit: wgpu::RenderPipeline,
    /// Its mask where the count is not 0, and the direct light of instances that receive no
    /// shadows (skipped for the first light when every instance receives: the ambient pass
    /// wrote its mask).
    pub shadowed: wgpu::RenderPipeline,
    /// Planar shadows: the receiver polygon's visible pixels marked 1 (pulled in front of the
    /// face it lies on), the flattened casters raising a marked pixel to 2 once, the marks
    /// that stayed 1 cleared: the stencil is then non-zero exactly where a caster's shadow
    /// falls on the visible receiver.
    pub planar_mark: wgpu::RenderPipeline,
    pub planar_flat: wgpu::RenderPipeline,
    pub planar_unmark: wgpu::RenderPipeline,
}

impl VolumePipelines {
    pub fn new(gpu: &Gpu, pipelines: &Pipelines) -> Self {
        let float_depth = gpu
            .device
            .features()
            .contains(wgpu::Features::DEPTH32FLOAT_STENCIL8);
        let b = VolumeBuilder {
            device: &gpu.device,
            pipelines,
            format: if float_depth {
                wgpu::TextureFormat::Depth32FloatStencil8
            } else {
                wgpu::TextureFormat::Depth24PlusStencil8
            },
            // A float depth's constant bias unit is each implementation's own: the push in
            // the shader does its work there. A 24-bit depth's unit is fixed and far coarser.
            constant: if float_depth { 0 } else { 16 },
        };
        use wgpu::CompareFunction as C;
        use wgpu::StencilOperation as S;
        let face = |depth_fail_op, pass_op| wgpu::StencilFaceState {
            compare: C::Always,
            fail_op: S::Keep,
            depth_fail_op,
            pass_op,
        };
        let stencil_only = |compare, pass_op| wgpu::StencilFaceState {
            compare,
            fail_op: S::Keep,
            depth_fail_op: S::Keep,
            pass_op,
        };
        let fs_planar = pipelines.fragment_depth.then_some("fs_planar_frag_depth");
        Self {
            float_depth,
            format: b.format,
            planar_mark: b.planar(
                "planar: receiver",
                (C::GreaterEqual, fs_planar),
                stencil_only(C::Always, S::Replace),
                true,
            ),
            planar_flat: b.planar(
                "planar: flattened casters",
                (C::Always, None),
                stencil_only(C::Equal, S::IncrementClamp),
                false,
            ),
            planar_unmark: b.planar(
                "planar: unshadowed receiver",
                (C::Always, None),
                stencil_only(C::Equal, S::Zero),
                false,
            ),
            z_fail: b.volumes(
                "volumes: z-fail",
                face(S::DecrementWrap, S::Keep),
                face(S::IncrementWrap, S::Keep),
            ),
            z_pass: b.volumes(
                "volumes: z-pass",
                face(S::Keep, S::IncrementWrap),
                face(S::Keep, S::DecrementWrap),
            ),
            depth_and_ambient: b.depth_and_ambient(),
            lit: b.light_pass("volumes: lit", "fs_volume_lit", C::Equal),
            shadowed: b.light_pass("volumes: shadowed", "fs_volume_shadowed", C::NotEqual),
        }
    }
}

impl VolumePipelines {
    /// One light's stencil, its vertices bound: its volumes, z-fail then z-pass (`ranges`), or
    /// with `planar` the receiver's visible pixels marked (the first range), raised once
    /// under the flattened casters (the second), the unshadowed marks cleared.
    pub fn draw_stencil(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        (z_fail, z_pass): (Range<u32>, Range<u32>),
        planar: bool,
    ) {
        let (planar_draws, volume_draws);
        let draws: &[(&wgpu::RenderPipeline, Range<u32>)] = if planar {
            pass.set_stencil_reference(1);
            planar_draws = [
                (&self.planar_mark, z_fail.clone()),
                (&self.planar_flat, z_pass),
                (&self.planar_unmark, z_fail),
            ];
            &planar_draws
        } else {
            volume_draws = [(&self.z_fail, z_fail), (&self.z_pass, z_pass)];
            &volume_draws
        };
        for (pipeline, range) in draws {
            if !range.is_empty() {
                pass.set_pipeline(pipeline);
                pass.draw(range.clone(), 0..1);
            }
        }
    }
}

/// What the volume passes' pipelines share: the device, the scene's shader and layout, the
/// depth-stencil format and the constant part of the caps' push.
struct VolumeBuilder<'a> {
    device: &'a wgpu::Device,
    pipelines: &'a Pipelines,
    format: wgpu::TextureFormat,
    constant: i32,
}

/// The volumes' vertices: view-space homogeneous positions.
const VOLUME_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x4];

impl VolumeBuilder<'_> {
    fn make(&self, spec: PipelineSpec<'_>) -> wgpu::RenderPipeline {
        build(
            self.device,
            &self.pipelines.shader,
            &self.pipelines.layout,
            &spec,
        )
    }

    fn volume_vertices() -> [wgpu::VertexBufferLayout<'static>; 1] {
        [wgpu::VertexBufferLayout {
            array_stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VOLUME_ATTRIBUTES,
        }]
    }

    /// Depth compared (and written where `write`), stencil faces as given.
    fn depth_stencil(
        &self,
        (write, compare): (bool, wgpu::CompareFunction),
        (front, back): (wgpu::StencilFaceState, wgpu::StencilFaceState),
        (read_mask, write_mask): (u32, u32),
        bias: wgpu::DepthBiasState,
    ) -> Option<wgpu::DepthStencilState> {
        Some(wgpu::DepthStencilState {
            format: self.format,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState {
                front,
                back,
                read_mask,
                write_mask,
            },
            bias,
        })
    }

    /// The caps' push behind the faces they lie on (`sign` -1), or the planar receiver's pull
    /// in front of its face (+1). The volumes' vertices are formed in f64 on the CPU, the
    /// scene's on the GPU from object space: a light cap would z-fight with its caster's lit
    /// faces. Pushed a little behind (reversed Z: smaller), a cap always counts as behind
    /// the face it lies on, as z-fail needs; the push is far below a pixel. The shader pushes
    /// by `DEPTH_PUSH_ULPS` units of the f32's last place of each fragment's depth (the same
    /// relative push on every device); the pipeline adds 0.05 of the depth's slope per pixel,
    /// for faces seen edge-on.
    fn push(&self, sign: i32) -> wgpu::DepthBiasState {
        wgpu::DepthBiasState {
            constant: sign * self.constant,
            slope_scale: sign as f32 * 0.05,
            clamp: 0.0,
        }
    }

    /// The volumes: stencil only, two-sided, no depth writes; front and back faces count as
    /// `front` and `back` say. Reversed Z: a face in front of the surface passes (Greater),
    /// one behind it fails the depth test.
    fn volumes(
        &self,
        label: &str,
        front: wgpu::StencilFaceState,
        back: wgpu::StencilFaceState,
    ) -> wgpu::RenderPipeline {
        let faces = (front, back);
        let depth = (false, wgpu::CompareFunction::Greater);
        self.make(PipelineSpec {
            label,
            vertex: "vs_volume",
            buffers: &Self::volume_vertices(),
            fragment: self
                .pipelines
                .fragment_depth
                .then_some("fs_volume_frag_depth"),
            targets: &[],
            constants: &[("DEPTH_PUSH_ULPS", PUSH_ULPS)],
            depth: self.depth_stencil(depth, faces, (0xff, 0xff), self.push(-1)),
            samples: 1,
        })
    }

    /// One light's shading: the scene where the stencil count compares to 0 as `compare`
    /// says, colour added (linear, before sRGB encoding), mask written.
    fn light_pass(
        &self,
        label: &str,
        fragment: &str,
        compare: wgpu::CompareFunction,
    ) -> wgpu::RenderPipeline {
        let additive = [
            Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: Some(wgpu::BlendState {
                    color: wgpu::BlendComponent {
                        src_factor: wgpu::BlendFactor::One,
                        dst_factor: wgpu::BlendFactor::One,
                        operation: wgpu::BlendOperation::Add,
                    },
                    alpha: wgpu::BlendComponent::REPLACE,
                }),
                write_mask: wgpu::ColorWrites::ALL,
            }),
            Some(MASK_FORMAT.into()),
        ];
        let test = wgpu::StencilFaceState {
            compare,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Keep,
            pass_op: wgpu::StencilOperation::Keep,
        };
        let depth = (false, wgpu::CompareFunction::GreaterEqual);
        let no_bias = wgpu::DepthBiasState::default();
        self.make(PipelineSpec {
            label,
            vertex: "vs_main_infinite",
            buffers: &scene_buffers(),
            fragment: Some(&self.pipelines.fragment(fragment)),
            targets: &additive,
            constants: &[],
            depth: self.depth_stencil(depth, (test, test), (0xff, 0), no_bias),
            samples: 1,
        })
    }

    /// A planar shadows' stencil pass; `pulled` pulls the receiver's polygon in front of the
    /// face it lies on, as the caps are pushed behind.
    fn planar(
        &self,
        label: &str,
        (depth_compare, fragment): (wgpu::CompareFunction, Option<&str>),
        face: wgpu::StencilFaceState,
        pulled: bool,
    ) -> wgpu::RenderPipeline {
        let (bias, constants) = if pulled {
            (self.push(1), &[("DEPTH_PUSH_ULPS", -PUSH_ULPS)][..])
        } else {
            (wgpu::DepthBiasState::default(), &[][..])
        };
        let depth = self.depth_stencil((false, depth_compare), (face, face), (0xff, 0xff), bias);
        self.make(PipelineSpec {
            label,
            vertex: "vs_volume",
            buffers: &Self::volume_vertices(),
            fragment,
            targets: &[],
            constants,
            depth,
            samples: 1,
        })
    }

    /// The scene's depth and its ambient term, the mask cleared to lit.
    fn depth_and_ambient(&self) -> wgpu::RenderPipeline {
        let ignore = wgpu::StencilFaceState::IGNORE;
        let depth = (true, wgpu::CompareFunction::Greater);
        self.make(PipelineSpec {
            label: "volumes: depth and ambient",
            vertex: "vs_main_infinite",
            buffers: &scene_buffers(),
            fragment: Some(&self.pipelines.fragment("fs_ambient")),
            targets: &[Some(COLOR_FORMAT.into()), Some(MASK_FORMAT.into())],
            constants: &[],
            depth: self.depth_stencil(
                depth,
                (ignore, ignore),
                (0, 0),
                wgpu::DepthBiasState::default(),
            ),
            samples: 1,
        })
    }
}
