//! Every pipeline, made once (or once per target format and sample count, on first use) and
//! kept. Group 0 is the frame and a per-pass slot (dynamic offset), group 1 the lookup
//! module's shadows (the records alone in depth passes), group 2 a mesh's holes, group 3 the
//! scene's triangles (the exact paraboloid depth passes).

use std::collections::HashMap;

use crate::atlas::{ID_FORMAT, MAP_FORMAT, lookup_layout};
use crate::cutouts::cutout_layout;
use crate::scene::{INSTANCE_STRIDE, Vertex};

/// The camera's depth in the main pass: reversed Z, 32-bit float.
pub(crate) const CAMERA_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The colour of headless frames (the measured main pass's first target), in which
/// [`crate::Renderer::frame_color`] keeps them.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The lit-light bits (and the geometry bit 31), and the first light's shadow factor as the
/// bits of an f32.
pub(crate) const LIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
/// Four f32 as their bits (Rgba32Float is not renderable on GL).
pub(crate) const METRICS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// A volume pass's per-light mask.
pub(crate) const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;
/// The light view's picture.
pub(crate) const LIGHT_VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The shader: the lookup module (group 1) and gnomon's passes.
pub(crate) fn shader_source() -> String {
    crate::lookup_wgsl(1) + include_str!("wgsl/passes.wgsl")
}

pub(crate) struct Pipelines {
    pub shader: wgpu::ShaderModule,
    /// Camera passes write their depth from the fragment shader: on GL, where wgpu maps clip
    /// z to [-1, 1] by z * 2 - w, which would cancel reversed Z's precision far away.
    pub fragment_depth: bool,
    pub frame_layout: wgpu::BindGroupLayout,
    pub lookup_layout: wgpu::BindGroupLayout,
    pub layout: wgpu::PipelineLayout,
    /// Group 2 of the main passes and of the depth passes that read holes.
    pub cutout_layout: wgpu::BindGroupLayout,
    /// The main passes' layout: groups 0 and 1, and the mesh's holes.
    main_layout: wgpu::PipelineLayout,
    /// The depth passes' group 1: the records alone (the maps are their targets).
    pub records_layout: wgpu::BindGroupLayout,
    depth_layout: wgpu::PipelineLayout,
    /// The depth passes' layout with the mesh's holes.
    depth_cut_layout: wgpu::PipelineLayout,
    /// Depth passes by the caster vertex stride, whether they write object IDs and whether
    /// they read holes.
    depth: HashMap<(u64, bool, bool), wgpu::RenderPipeline>,
    /// The exact paraboloid depth passes (see [`Paraboloids`]), where the device has storage
    /// buffers in vertex shaders.
    paraboloid: Option<Paraboloids>,
    /// The measured main pass, by metrics and specialisation.
    measured: HashMap<(bool, MainSpec), wgpu::RenderPipeline>,
    /// The main pass into a caller's target, by format, sample count and specialisation.
    color: HashMap<(wgpu::TextureFormat, u32, MainSpec), wgpu::RenderPipeline>,
    pub light_view: wgpu::RenderPipeline,
    /// The view samples pass (position and normal per pixel), on first use.
    samples: Option<wgpu::RenderPipeline>,
    fs_color: String,
    fs_measured: String,
}

/// What the main pass is specialised for (override constants): the number of lights (a loop
/// with a constant trip count costs far less than one bounded by a uniform on some devices:
/// 1.4x the main pass on lavapipe), and whether a light picks its map per pixel (cascades, a
/// point light's cube faces: the per-pixel choice of map makes every read of a map's record a
/// gather on a CPU rasteriser: 1.45x the main pass on lavapipe when compiled into frames that
/// have none), and how the maps are read (`MAP_READ`: by depth or by object ID).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub(crate) struct MainSpec {
    pub lights: u32,
    pub per_pixel: bool,
    /// `GNOMON_READ_*` of lookup.wgsl.
    pub read: u32,
    /// Whether the scene has holes (a discard, which costs early depth tests on GPUs, only
    /// where a mesh has them).
    pub cutout: bool,
}

impl MainSpec {
    fn constants(&self) -> [(&'static str, f64); 4] {
        [
            ("LIGHT_COUNT", self.lights as f64),
            ("PER_PIXEL", if self.per_pixel { 1.0 } else { 0.0 }),
            ("MAP_READ", self.read as f64),
            ("CUTOUT", if self.cutout { 1.0 } else { 0.0 }),
        ]
    }
}

/// The scene's vertex streams: positions, normals and texture coordinates, instances.
const SCENE_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];
const INSTANCE_ATTRIBUTES: [wgpu::VertexAttribute; 8] = wgpu::vertex_attr_array![
    3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4,
    7 => Float32x4, 8 => Float32x4, 9 => Float32x4, 10 => Float32x4
];

pub(crate) fn scene_buffers() -> [wgpu::VertexBufferLayout<'static>; 2] {
    [
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &SCENE_ATTRIBUTES,
        },
        wgpu::VertexBufferLayout {
            array_stride: INSTANCE_STRIDE,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &INSTANCE_ATTRIBUTES,
        },
    ]
}

/// The exact paraboloid depth passes: the vertex shader reads its triangle's three corners
/// from the scene's buffers (group 3) and draws a triangle around the hemisphere's image of
/// the whole triangle; the fragment shader casts its texel's ray at the triangle and keeps
/// the distance where it hits (so the triangle's edges are the curves they are in the map,
/// not straight lines between the corners' places).
pub(crate) struct Paraboloids {
    /// Group 3: the scene's vertices and indices, read-only.
    layout: wgpu::BindGroupLayout,
    /// Groups 0, 1 and 3, and with the mesh's holes in group 2.
    plain: wgpu::PipelineLayout,
    cut: wgpu::PipelineLayout,
    /// By whether they write object IDs and whether they read holes.
    pipelines: HashMap<(bool, bool), wgpu::RenderPipeline>,
}

/// A pipeline's parts that vary.
pub(crate) struct PipelineSpec<'a> {
    pub label: &'a str,
    pub vertex: &'a str,
    pub buffers: &'a [wgpu::VertexBufferLayout<'a>],
    pub fragment: Option<&'a str>,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub constants: &'a [(&'a str, f64)],
    pub depth: Option<wgpu::DepthStencilState>,
    pub samples: u32,
}

impl Pipelines {
    /// The fragment entry point `name`, or its `_frag_depth` twin where camera passes write
    /// their depth.
    pub fn fragment(&self, name: &str) -> String {
        fragment_entry(name, self.fragment_depth)
    }

    pub fn new(device: &wgpu::Device, backend: wgpu::Backend) -> Self {
        let fragment_depth = backend == wgpu::Backend::Gl;
        let (fs_measured, fs_color) = (
            fragment_entry("fs_measured", fragment_depth),
            fragment_entry("fs_color", fragment_depth),
        );
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("gnomon passes"),
            source: wgpu::ShaderSource::Wgsl(shader_source().into()),
        });
        let uniform = |binding, dynamic| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: dynamic,
                min_binding_size: None,
            },
            count: None,
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gnomon frame"),
            entries: &[uniform(0, false), uniform(1, true)],
        });
        let lookup_layout = lookup_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gnomon"),
            bind_group_layouts: &[Some(&frame_layout), Some(&lookup_layout)],
            immediate_size: 0,
        });
        let records_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gnomon records"),
            entries: &[uniform(0, false)],
        });
        let depth_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gnomon depth"),
            bind_group_layouts: &[Some(&frame_layout), Some(&records_layout)],
            immediate_size: 0,
        });
        let cutout_layout = cutout_layout(device);
        let main_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gnomon main"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&lookup_layout),
                Some(&cutout_layout),
            ],
            immediate_size: 0,
        });
        let depth_cut_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gnomon depth with holes"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&records_layout),
                Some(&cutout_layout),
            ],
            immediate_size: 0,
        });
        let mut pipelines = Self {
            measured: HashMap::new(),
            light_view: build(
                device,
                &shader,
                &layout,
                &PipelineSpec {
                    label: "light view",
                    vertex: "vs_fullscreen",
                    buffers: &[],
                    fragment: Some("fs_light_view"),
                    targets: &[Some(LIGHT_VIEW_FORMAT.into())],
                    constants: &[],
                    depth: None,
                    samples: 1,
                },
            ),
            shader,
            fragment_depth,
            fs_color,
            fs_measured,
            frame_layout,
            lookup_layout,
            layout,
            cutout_layout,
            main_layout,
            records_layout,
            depth_layout,
            depth_cut_layout,
            depth: HashMap::new(),
            paraboloid: None,
            color: HashMap::new(),
            samples: None,
        };
        pipelines.depth(device, std::mem::size_of::<Vertex>() as u64, false, false);
        pipelines.paraboloid = pipelines.exact_paraboloids(device);
        pipelines
    }

    /// The exact paraboloid passes with their first pipeline made, or `None` where the device
    /// refuses them (no storage buffers in vertex shaders: WebGL2, some GLES drivers).
    fn exact_paraboloids(&self, device: &wgpu::Device) -> Option<Paraboloids> {
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gnomon scene triangles"),
            entries: &[storage(0), storage(1)],
        });
        let pipeline_layout = |label, cut: Option<&wgpu::BindGroupLayout>| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[
                    Some(&self.frame_layout),
                    Some(&self.records_layout),
                    cut,
                    Some(&layout),
                ],
                immediate_size: 0,
            })
        };
        let mut paraboloids = Paraboloids {
            plain: pipeline_layout("gnomon paraboloid depth", None),
            cut: pipeline_layout(
                "gnomon paraboloid depth with holes",
                Some(&self.cutout_layout),
            ),
            layout,
            pipelines: HashMap::new(),
        };
        paraboloids.make(device, &self.shader, false, false);
        let internal = pollster::block_on(internal.pop());
        let validation = pollster::block_on(validation.pop());
        (internal.is_none() && validation.is_none()).then_some(paraboloids)
    }

    /// Group 3's layout of the exact paraboloid passes, where the device has them.
    pub fn pulled_layout(&self) -> Option<&wgpu::BindGroupLayout> {
        self.paraboloid.as_ref().map(|p| &p.layout)
    }

    /// Makes the exact paraboloid depth pass for `ids` and `cut` (see [`Pipelines::depth`]),
    /// where the device has them.
    pub fn paraboloid(&mut self, device: &wgpu::Device, ids: bool, cut: bool) {
        if let Some(p) = &mut self.paraboloid {
            p.make(device, &self.shader, ids, cut);
        }
    }

    /// The exact paraboloid depth pass already made for `ids` and `cut`.
    pub fn paraboloid_for(&self, ids: bool, cut: bool) -> Option<&wgpu::RenderPipeline> {
        self.paraboloid.as_ref()?.pipelines.get(&(ids, cut))
    }

    /// The depth pass for casters whose positions (three f32) repeat every `stride` bytes;
    /// with `ids`, it also writes each caster's object ID into an [`ID_FORMAT`] target; with
    /// `cut`, it reads texture coordinates (two f32 after the position and normal: the
    /// scene's [`Vertex`]) and discards the mesh's holes (group 2).
    pub fn depth(
        &mut self,
        device: &wgpu::Device,
        stride: u64,
        ids: bool,
        cut: bool,
    ) -> &wgpu::RenderPipeline {
        let shader = &self.shader;
        let layout = if cut {
            &self.depth_cut_layout
        } else {
            &self.depth_layout
        };
        self.depth.entry((stride, ids, cut)).or_insert_with(|| {
            let attributes = [
                wgpu::VertexAttribute {
                    format: wgpu::VertexFormat::Float32x3,
                    offset: 0,
                    shader_location: 0,
                },
                wgpu::VertexAttribute {
                    format: wgpu::VertexFormat::Float32x2,
                    offset: std::mem::offset_of!(Vertex, uv) as u64,
                    shader_location: 2,
                },
            ];
            let transform = &INSTANCE_ATTRIBUTES[..4];
            let id_target = [Some(ID_FORMAT.into())];
            let fragment = match (ids, cut) {
                (false, false) => "fs_depth",
                (true, false) => "fs_depth_id",
                (false, true) => "fs_depth_cut",
                (true, true) => "fs_depth_id_cut",
            };
            build(
                device,
                shader,
                layout,
                &PipelineSpec {
                    label: "shadow depth",
                    vertex: if cut { "vs_depth_cut" } else { "vs_depth" },
                    buffers: &[
                        wgpu::VertexBufferLayout {
                            array_stride: stride,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &attributes[..if cut { 2 } else { 1 }],
                        },
                        wgpu::VertexBufferLayout {
                            array_stride: INSTANCE_STRIDE,
                            step_mode: wgpu::VertexStepMode::Instance,
                            attributes: transform,
                        },
                    ],
                    fragment: Some(fragment),
                    targets: if ids { &id_target } else { &[] },
                    constants: &[],
                    depth: Some(map_depth()),
                    samples: 1,
                },
            )
        })
    }

    /// The depth pass already made for `stride`, `ids` and `cut`.
    pub fn depth_for(&self, stride: u64, ids: bool, cut: bool) -> Option<&wgpu::RenderPipeline> {
        self.depth.get(&(stride, ids, cut))
    }

    /// The measured main pass already made.
    pub fn measured_for(&self, metrics: bool, spec: MainSpec) -> Option<&wgpu::RenderPipeline> {
        self.measured.get(&(metrics, spec))
    }

    /// The measured main pass (colour, lit-light bits, and with `metrics` the sampling
    /// metrics) for `spec`.
    pub fn measured(
        &mut self,
        device: &wgpu::Device,
        metrics: bool,
        spec: MainSpec,
    ) -> &wgpu::RenderPipeline {
        let (shader, layout, fragment) = (&self.shader, &self.main_layout, &self.fs_measured);
        self.measured.entry((metrics, spec)).or_insert_with(|| {
            let mut targets = vec![Some(COLOR_FORMAT.into()), Some(LIT_FORMAT.into())];
            if metrics {
                targets.push(Some(METRICS_FORMAT.into()));
            }
            build(
                device,
                shader,
                layout,
                &PipelineSpec {
                    label: "main (measured)",
                    vertex: "vs_main",
                    buffers: &scene_buffers(),
                    fragment: Some(fragment),
                    targets: &targets,
                    constants: &[("METRICS", if metrics { 1.0 } else { 0.0 })]
                        .into_iter()
                        .chain(spec.constants())
                        .collect::<Vec<_>>(),
                    depth: Some(camera_depth()),
                    samples: 1,
                },
            )
        })
    }

    /// The view samples pass: position and geometric normal per pixel, two targets of
    /// [`METRICS_FORMAT`].
    pub fn samples(&mut self, device: &wgpu::Device) -> &wgpu::RenderPipeline {
        let (shader, layout) = (&self.shader, &self.layout);
        let fragment = fragment_entry("fs_samples", self.fragment_depth);
        self.samples.get_or_insert_with(|| {
            build(
                device,
                shader,
                layout,
                &PipelineSpec {
                    label: "view samples",
                    vertex: "vs_main",
                    buffers: &scene_buffers(),
                    fragment: Some(&fragment),
                    targets: &[Some(METRICS_FORMAT.into()), Some(METRICS_FORMAT.into())],
                    constants: &[],
                    depth: Some(camera_depth()),
                    samples: 1,
                },
            )
        })
    }

    /// The main pass into a target of `format` with `samples` samples, for `spec`.
    pub fn color(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
        spec: MainSpec,
    ) -> &wgpu::RenderPipeline {
        let (shader, layout, fragment) = (&self.shader, &self.main_layout, &self.fs_color);
        self.color
            .entry((format, samples, spec))
            .or_insert_with(|| {
                build(
                    device,
                    shader,
                    layout,
                    &PipelineSpec {
                        label: "main",
                        vertex: "vs_main",
                        buffers: &scene_buffers(),
                        fragment: Some(fragment),
                        targets: &[Some(format.into())],
                        constants: &spec.constants(),
                        depth: Some(camera_depth()),
                        samples,
                    },
                )
            })
    }
}

impl Paraboloids {
    fn make(&mut self, device: &wgpu::Device, shader: &wgpu::ShaderModule, ids: bool, cut: bool) {
        let layout = if cut { &self.cut } else { &self.plain };
        self.pipelines.entry((ids, cut)).or_insert_with(|| {
            let fragment = match (ids, cut) {
                (false, false) => "fs_paraboloid",
                (true, false) => "fs_paraboloid_id",
                (false, true) => "fs_paraboloid_cut",
                (true, true) => "fs_paraboloid_id_cut",
            };
            let id_target = [Some(ID_FORMAT.into())];
            build(
                device,
                shader,
                layout,
                &PipelineSpec {
                    label: "paraboloid depth",
                    vertex: "vs_paraboloid",
                    buffers: &[wgpu::VertexBufferLayout {
                        array_stride: INSTANCE_STRIDE,
                        step_mode: wgpu::VertexStepMode::Instance,
                        attributes: &INSTANCE_ATTRIBUTES[..4],
                    }],
                    fragment: Some(fragment),
                    targets: if ids { &id_target } else { &[] },
                    constants: &[],
                    depth: Some(map_depth()),
                    samples: 1,
                },
            )
        });
    }
}

/// The shadow map's depth test: nearer is less.
fn map_depth() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: MAP_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::LessEqual),
        stencil: wgpu::StencilState::default(),
        bias: wgpu::DepthBiasState::default(),
    }
}

/// A fragment entry point, or its `_frag_depth` twin when camera passes write their depth.
fn fragment_entry(name: &str, fragment_depth: bool) -> String {
    if fragment_depth {
        format!("{name}_frag_depth")
    } else {
        name.to_string()
    }
}

/// The camera's depth test: reversed Z, nearer is greater.
fn camera_depth() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: CAMERA_DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Greater),
        stencil: wgpu::StencilState::default(),
        bias: wgpu::DepthBiasState::default(),
    }
}

/// A render pipeline of gnomon's shader. Both faces are drawn: thin and open geometry casts
/// too, the depth is biased anyway, and the shading normal is turned toward the camera.
pub(crate) fn build(
    device: &wgpu::Device,
    shader: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    spec: &PipelineSpec<'_>,
) -> wgpu::RenderPipeline {
    let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> =
        spec.buffers.iter().cloned().map(Some).collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some(spec.vertex),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
            buffers: &buffers,
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: spec.depth.clone(),
        multisample: wgpu::MultisampleState {
            count: spec.samples,
            ..Default::default()
        },
        fragment: spec.fragment.map(|entry| wgpu::FragmentState {
            module: shader,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
            targets: spec.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
