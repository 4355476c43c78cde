use std::time::Instant;

use glam::{DMat4, DVec3, DVec4};
use gnomon::{Camera, Light, MapSelection, ShadowMap, ShadowSetup};

use crate::scene::{GpuScene, RenderScene, Vertex};
use crate::volumes::{VolumeCasters, VolumePipelines};
use crate::{Gpu, MASK_EMPTY, RenderError, light_view, readback};

/// How the main pass filters shadow-map lookups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// One tap: a texel is in or out.
    None,
    /// The hardware's 2x2 bilinear comparison.
    #[default]
    Hardware2x2,
    /// 5x5 taps, averaged (percentage closer filtering).
    Pcf5x5,
}

/// Depth bias against shadow acne.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthBias {
    /// Constant bias in world units along the light.
    pub constant_world: f64,
    /// Slope-scaled bias: this many texels' worth of the surface's depth slope.
    pub slope_texels: f64,
    /// Upper limit of the slope-scaled bias, in world units.
    pub max_slope_world: f64,
    /// Normal offset: the lookup moves this many texels along the geometric normal (scaled
    /// by 1 - N.L, so surfaces facing the light move little).
    pub normal_offset_texels: f64,
}

impl Default for DepthBias {
    /// 2 cm constant, 2 texels of slope (at most 1 m), a 1-texel normal offset.
    fn default() -> Self {
        Self {
            constant_world: 0.02,
            slope_texels: 2.0,
            max_slope_world: 1.0,
            normal_offset_texels: 1.0,
        }
    }
}

/// What to render and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Shadow-map filtering.
    pub filter: Filter,
    /// Depth bias.
    pub bias: DepthBias,
    /// Ambient light, 0 to 1.
    pub ambient: f64,
    /// Also return the shadow map as the light sees it, with the view frustum drawn over it.
    pub light_view: bool,
    /// Also return the per-pixel sampling metrics ([`Frame::metrics`]).
    pub metrics: bool,
    /// Two-map setups: tint each pixel by the map it reads (red: the second, perspective
    /// map; blue: the first, focused map), as in the SPPSM paper's figures.
    pub tint: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            filter: Filter::default(),
            bias: DepthBias::default(),
            ambient: 0.25,
            light_view: false,
            metrics: false,
            tint: false,
        }
    }
}

/// Wall-clock times of one frame's parts (the GPU waited for after each).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    /// The shadow-map depth pass(es), milliseconds.
    pub shadow_pass_ms: f64,
    /// The main pass, milliseconds.
    pub main_pass_ms: f64,
    /// Reading the images back, milliseconds.
    pub readback_ms: f64,
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
    /// The direct-light mask, one byte per pixel: [`crate::MASK_LIT`], [`crate::MASK_UNLIT`] or
    /// [`crate::MASK_EMPTY`].
    pub mask: Vec<u8>,
    /// The shadow map(s) as the light sees them, if asked for.
    pub light_view: Option<LightView>,
    /// The per-pixel sampling metrics, if asked for ([`RenderSettings::metrics`]).
    pub metrics: Option<PixelMetrics>,
    /// Times of the passes.
    pub timings: Timings,
}

/// The shadow maps as the light sees them (near = dark, far = light), with the camera's view
/// frustum in red; two maps side by side (the first on the left), in RGBA.
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
        let mut rgba = vec![255u8; (width * height * 4) as usize];
        let mut x0 = 0;
        for (size, view) in views {
            for y in 0..*size {
                let from = (y * size * 4) as usize;
                let to = ((y * width + x0) * 4) as usize;
                rgba[to..to + (size * 4) as usize]
                    .copy_from_slice(&view[from..from + (size * 4) as usize]);
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
/// map's texel coordinates with respect to screen pixels, from the fragment shader's
/// derivatives of the shadow coordinate (so it includes projection aliasing, the surface's
/// orientation, as well as perspective aliasing).
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
    /// From the metrics image (RGBA 32-bit floats: undersampling, area, N.L, coverage).
    fn from_rgba(bytes: &[u8]) -> Self {
        let mut m = Self::default();
        for texel in bytes.chunks_exact(16) {
            let f = |k: usize| f32::from_le_bytes(texel[4 * k..4 * k + 4].try_into().unwrap());
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

/// Where the main pass's shadow factor comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ShadowOverride {
    /// The shadow map.
    Map = 0,
    /// Lit (the stencil said so).
    Lit = 1,
    /// Shadowed (the stencil said so).
    Shadowed = 2,
}

/// The uniform block of `shadow.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Globals {
    camera_clip_from_world: [[f32; 4]; 4],
    light_clip_from_world: [[f32; 4]; 4],
    depth_from_world: [f32; 4],
    eye: [f32; 4],
    light: [f32; 4],
    spot: [f32; 4],
    bias: [f32; 4],
    map: [f32; 4],
    extra: [f32; 4],
    light_clip_from_world_b: [[f32; 4]; 4],
    depth_from_world_b: [f32; 4],
    plane: [f32; 4],
    selection: [f32; 4],
}

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;
const METRICS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Draws a scene with shadow setups. Holds the GPU, the pipelines and the scene's buffers.
pub struct Renderer {
    pub(crate) gpu: Gpu,
    pub(crate) scene: GpuScene,
    layout: wgpu::BindGroupLayout,
    depth_pipeline: wgpu::RenderPipeline,
    /// The main pass, [two maps][sampling metrics].
    main_pipelines: [[wgpu::RenderPipeline; 2]; 2],
    linear_sampler: wgpu::Sampler,
    nearest_sampler: wgpu::Sampler,
    pub(crate) volumes: VolumePipelines,
    pub(crate) volume_casters: VolumeCasters,
}

impl Renderer {
    /// Uploads the scene and builds the pipelines.
    pub fn new(gpu: Gpu, scene: &RenderScene) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shadow.wgsl").into()),
        });
        // The uniform block, binding 0 of both layouts.
        let globals_entry = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals and shadow map"),
            entries: &[
                globals_entry,
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[globals_entry],
        });
        let main_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("main"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let depth_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("depth"),
                bind_group_layouts: &[Some(&depth_layout)],
                immediate_size: 0,
            });
        let vertex_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &vertex_attributes,
        };
        // Both pipelines draw both faces: thin and open geometry casts too, the depth is
        // biased anyway, and the mask's normal is turned toward the camera.
        let pipeline = |label,
                        layout,
                        vertex_entry,
                        fragment_entry,
                        targets: &[Option<wgpu::ColorTargetState>],
                        constants: &[(&str, f64)]| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout.clone())],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fragment_entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants,
                        ..Default::default()
                    },
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let depth_pipeline = pipeline(
            "shadow depth",
            &depth_pipeline_layout,
            "vs_depth",
            "fs_depth",
            &[],
            &[],
        );
        // The main pass specialised (pipeline-overridable constants) for one or two maps,
        // without and with the sampling metrics target: [two maps][metrics].
        let main_pipelines = [false, true].map(|two_maps| {
            [false, true].map(|metrics| {
                let mut targets = vec![Some(COLOR_FORMAT.into()), Some(MASK_FORMAT.into())];
                if metrics {
                    targets.push(Some(METRICS_FORMAT.into()));
                }
                let flag = |on: bool| if on { 1.0 } else { 0.0 };
                pipeline(
                    "main",
                    &main_pipeline_layout,
                    "vs_main",
                    "fs_main",
                    &targets,
                    &[("TWO_MAPS", flag(two_maps)), ("METRICS", flag(metrics))],
                )
            })
        });
        let volumes = VolumePipelines::new(
            device,
            &shader,
            &main_pipeline_layout,
            &depth_pipeline_layout,
            &vertex_layout,
            &[Some(COLOR_FORMAT.into()), Some(MASK_FORMAT.into())],
        );
        let sampler = |filter: wgpu::FilterMode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison"),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: filter,
                min_filter: filter,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            })
        };
        let linear_sampler = sampler(wgpu::FilterMode::Linear);
        let nearest_sampler = sampler(wgpu::FilterMode::Nearest);
        let volume_casters = VolumeCasters::new(scene);
        let scene = GpuScene::new(device, scene);
        Ok(Self {
            volumes,
            volume_casters,
            gpu,
            scene,
            layout,
            depth_pipeline,
            main_pipelines,
            linear_sampler,
            nearest_sampler,
        })
    }

    /// The main pass's bind group: the globals and the shadow maps (an array view, one layer
    /// per map).
    pub(crate) fn main_bind_group(
        &self,
        uniform: &wgpu::Buffer,
        shadow_view: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("globals and shadow map"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: uniform.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(shadow_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&self.linear_sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Sampler(&self.nearest_sampler),
                    },
                ],
            })
    }

    /// The image size of `settings`, checked against the GPU's limit.
    pub(crate) fn image_size(&self, settings: &RenderSettings) -> Result<(u32, u32), RenderError> {
        let (width, height) = (settings.width, settings.height);
        let max = self.gpu.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::Invalid(format!(
                "image size {width}x{height} is outside 1..={max}"
            )));
        }
        Ok((width, height))
    }

    /// The main pass's colour and mask images (see [`color_target`]).
    pub(crate) fn main_images(&self, width: u32, height: u32) -> (wgpu::Texture, wgpu::Texture) {
        (
            self.color_image(width, height),
            self.mask_image(width, height),
        )
    }

    /// A colour image (see [`color_target`]).
    pub(crate) fn color_image(&self, width: u32, height: u32) -> wgpu::Texture {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        texture(
            &self.gpu.device,
            "color",
            width,
            height,
            COLOR_FORMAT,
            usage,
        )
    }

    /// Reads a colour image back (RGBA).
    pub(crate) fn read_color(&self, color: &wgpu::Texture) -> Result<Vec<u8>, RenderError> {
        readback::read_texture(&self.gpu, color, wgpu::TextureAspect::All, 4)
    }

    /// A mask image (see [`color_target`]).
    pub(crate) fn mask_image(&self, width: u32, height: u32) -> wgpu::Texture {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        texture(&self.gpu.device, "mask", width, height, MASK_FORMAT, usage)
    }

    /// Reads a mask image back (one byte per pixel).
    pub(crate) fn read_mask(&self, mask: &wgpu::Texture) -> Result<Vec<u8>, RenderError> {
        readback::read_texture(&self.gpu, mask, wgpu::TextureAspect::All, 1)
    }

    /// Reads the colour and mask images back (RGBA and one byte per pixel).
    pub(crate) fn read_main_images(
        &self,
        color: &wgpu::Texture,
        mask: &wgpu::Texture,
    ) -> Result<(Vec<u8>, Vec<u8>), RenderError> {
        Ok((self.read_color(color)?, self.read_mask(mask)?))
    }

    /// The GPU this renderer draws on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Renders one frame of `camera` lit by `light`, with the shadow maps of `setup` (computed
    /// by the core crate for the same camera, light and scene): one map, or two maps and the
    /// plane that picks one per pixel (SPPSM; each caster drawn into the maps of the sides
    /// its bounds reach).
    pub fn render(
        &self,
        camera: &Camera,
        light: &Light,
        setup: &ShadowSetup,
        settings: &RenderSettings,
    ) -> Result<Frame, RenderError> {
        let (width, height) = self.image_size(settings)?;
        let max = self.gpu.device.limits().max_texture_dimension_2d;
        // The maps, each with the side of the plane whose casters it draws (None: all).
        let maps: Vec<(ShadowMap, Option<(DVec4, f64)>)> =
            match (setup.selection, setup.maps.as_slice()) {
                (MapSelection::Single, [map]) => vec![(*map, None)],
                (MapSelection::Plane { plane_world }, [first, second]) => vec![
                    (*first, Some((plane_world, -1.0))),
                    (*second, Some((plane_world, 1.0))),
                ],
                _ => {
                    return Err(RenderError::Invalid(format!(
                        "setup '{}' has {} maps for a {} selection",
                        setup.technique,
                        setup.maps.len(),
                        setup.selection.kind()
                    )));
                }
            };
        for (map, _) in &maps {
            if map.resolution > max {
                return Err(RenderError::Invalid(format!(
                    "shadow map {} exceeds the GPU's limit {max}",
                    map.resolution
                )));
            }
        }
        // The maps are layers of one texture: one size.
        let resolution = maps[0].0.resolution;
        if maps.iter().any(|(m, _)| m.resolution != resolution) {
            return Err(RenderError::Invalid(format!(
                "setup '{}' has maps of different sizes",
                setup.technique
            )));
        }
        let device = &self.gpu.device;
        let error_scope = self
            .gpu
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let uniform_buffer = |g: &Globals| {
            use wgpu::util::DeviceExt;
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("globals"),
                contents: bytemuck::bytes_of(g),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        // Each map's own globals (its depth pass reads the first map's slots), and the main
        // pass's with both maps.
        let map_globals = |map: &ShadowMap| {
            globals(
                camera,
                camera.clip_from_world(),
                light,
                map,
                settings,
                ShadowOverride::Map,
            )
        };
        let main_globals = match (setup.selection, maps.get(1)) {
            (MapSelection::Plane { plane_world }, Some((second, _))) => {
                map_globals(&maps[0].0).with_second_map(second, plane_world, settings.tint)
            }
            _ => map_globals(&maps[0].0),
        };
        let texture = |label, w, h, format, usage| texture(device, label, w, h, format, usage);
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;

        // Depth passes, one layer each.
        let start = Instant::now();
        let shadow_texture = texture_layers(
            device,
            "shadow maps",
            resolution,
            maps.len() as u32,
            DEPTH_FORMAT,
            attachment | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        for (layer, (map, side)) in maps.iter().enumerate() {
            let shadow_view = shadow_texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer as u32,
                array_layer_count: Some(1),
                ..Default::default()
            });
            let uniform = uniform_buffer(&map_globals(map));
            let depth_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("globals"),
                layout: &self.depth_pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                }],
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("shadow depth"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(cleared_depth(&shadow_view)),
                    ..Default::default()
                });
                // The border texels stay cleared to the far depth: lookups outside the focus
                // region read as lit.
                let inset = map.viewport_inset;
                let inner = map.resolution - 2 * inset;
                pass.set_scissor_rect(inset, inset, inner, inner);
                pass.set_pipeline(&self.depth_pipeline);
                pass.set_bind_group(0, &depth_bind_group, &[]);
                match side {
                    None => self
                        .scene
                        .draw(&mut pass, self.scene.caster_indices.clone()),
                    Some((plane, sign)) => {
                        self.scene.draw_casters_on_side(&mut pass, *plane, *sign)
                    }
                }
            }
            self.gpu.queue.submit([encoder.finish()]);
        }
        self.gpu.wait()?;
        let shadow_pass_ms = start.elapsed().as_secs_f64() * 1e3;

        // Main pass.
        let start = Instant::now();
        let (color, mask) = self.main_images(width, height);
        let metrics = settings
            .metrics
            .then(|| texture("metrics", width, height, METRICS_FORMAT, attachment));
        let depth = texture(
            "depth",
            width,
            height,
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let (color_view, mask_view, depth_view) = (
            color.create_view(&Default::default()),
            mask.create_view(&Default::default()),
            depth.create_view(&Default::default()),
        );
        let metrics_view = metrics.as_ref().map(|m| m.create_view(&Default::default()));
        let uniform = uniform_buffer(&main_globals);
        let shadow_array = shadow_texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let bind_group = self.main_bind_group(&uniform, &shadow_array);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut targets = vec![
                color_target(&color_view, Some(SKY)),
                color_target(&mask_view, Some(MASK_CLEAR)),
            ];
            if let Some(view) = &metrics_view {
                targets.push(color_target(view, Some(wgpu::Color::TRANSPARENT)));
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("main"),
                color_attachments: &targets,
                depth_stencil_attachment: Some(cleared_depth(&depth_view)),
                ..Default::default()
            });
            pass.set_pipeline(
                &self.main_pipelines[usize::from(maps.len() == 2)][usize::from(settings.metrics)],
            );
            pass.set_bind_group(0, &bind_group, &[]);
            self.scene.draw(&mut pass, self.scene.all_indices.clone());
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        let main_pass_ms = start.elapsed().as_secs_f64() * 1e3;
        if let Some(error) = pollster::block_on(error_scope.pop()) {
            return Err(RenderError::Gpu(error.to_string()));
        }

        let start = Instant::now();
        let (color_bytes, mask_bytes) = self.read_main_images(&color, &mask)?;
        let light_view = if settings.light_view {
            // The maps side by side, as the light sees them.
            let mut views = Vec::new();
            for (layer, (map, _)) in maps.iter().enumerate() {
                let depth = readback::read_texture_layer(
                    &self.gpu,
                    &shadow_texture,
                    wgpu::TextureAspect::DepthOnly,
                    4,
                    layer as u32,
                )?;
                views.push((
                    map.resolution,
                    light_view::draw(&depth, map.resolution, camera, map),
                ));
            }
            Some(LightView::side_by_side(&views))
        } else {
            None
        };
        let metrics = match &metrics {
            Some(texture) => {
                let bytes =
                    readback::read_texture(&self.gpu, texture, wgpu::TextureAspect::All, 16)?;
                Some(PixelMetrics::from_rgba(&bytes))
            }
            None => None,
        };
        let readback_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(Frame {
            width,
            height,
            color: color_bytes,
            mask: mask_bytes,
            light_view,
            metrics,
            timings: Timings {
                shadow_pass_ms,
                main_pass_ms,
                readback_ms,
            },
        })
    }
}

/// A 2D texture of one mip level.
pub(crate) fn texture(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    texture_2d(device, label, width, height, 1, format, usage)
}

/// A square 2D array texture of `layers` layers (one mip level).
pub(crate) fn texture_layers(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    texture_2d(device, label, size, size, layers, format, usage)
}

fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    layers: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The colour image's background.
pub(crate) const SKY: wgpu::Color = wgpu::Color {
    r: 0.55,
    g: 0.7,
    b: 0.9,
    a: 1.0,
};

/// The mask image's background: no geometry.
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

/// A depth attachment cleared to the far depth (1) and kept.
fn cleared_depth(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

fn mat(m: DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}

fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

/// The uniform block for one frame.
impl Globals {
    /// The same, drawing the direct light only (no ambient term): for the passes that add
    /// one light each.
    pub(crate) fn direct_light_only(mut self) -> Self {
        self.extra[2] = 1.0;
        self
    }

    /// The same, drawing the ambient term only (the mask as usual).
    pub(crate) fn ambient_only(mut self) -> Self {
        self.extra[2] = 2.0;
        self
    }

    /// The same with a second map, read on the positive side of `plane_world`; `tint`
    /// colours pixels by the map they read.
    pub(crate) fn with_second_map(
        mut self,
        map: &ShadowMap,
        plane_world: DVec4,
        tint: bool,
    ) -> Self {
        self.light_clip_from_world_b = mat(map.clip_from_world);
        self.depth_from_world_b = map.depth_from_world.as_vec4().to_array();
        self.plane = plane_world.as_vec4().to_array();
        self.selection = [
            2.0,
            if tint { 1.0 } else { 0.0 },
            map.resolution as f32,
            0.0,
        ];
        self
    }
}

pub(crate) fn globals(
    camera: &Camera,
    camera_clip_from_world: DMat4,
    light: &Light,
    map: &ShadowMap,
    settings: &RenderSettings,
    shadow_override: ShadowOverride,
) -> Globals {
    let depth_per_world = map.depth_from_world.truncate().length();
    let (light_vector, spot, extra) = match light {
        Light::Directional(d) => (vec4(d.direction(), 0.0), [0.0; 4], [0.0; 4]),
        Light::Spot(s) => (
            vec4(s.position(), 1.0),
            vec4(s.direction(), s.half_angle().cos()),
            [s.range() as f32, s.near() as f32, 0.0, 0.0],
        ),
    };
    let bias = settings.bias;
    let filter = match settings.filter {
        Filter::None => 0.0,
        Filter::Hardware2x2 => 1.0,
        Filter::Pcf5x5 => 2.0,
    };
    Globals {
        camera_clip_from_world: mat(camera_clip_from_world),
        light_clip_from_world: mat(map.clip_from_world),
        depth_from_world: map.depth_from_world.as_vec4().to_array(),
        eye: vec4(camera.eye(), 1.0),
        light: light_vector,
        spot,
        bias: [
            (bias.constant_world * depth_per_world) as f32,
            bias.slope_texels as f32,
            (bias.max_slope_world * depth_per_world) as f32,
            bias.normal_offset_texels as f32,
        ],
        map: [
            map.resolution as f32,
            shadow_override as u32 as f32,
            filter,
            settings.ambient as f32,
        ],
        extra,
        // One map: the second slot repeats the first and is never read.
        light_clip_from_world_b: mat(map.clip_from_world),
        depth_from_world_b: map.depth_from_world.as_vec4().to_array(),
        plane: [0.0; 4],
        selection: [1.0, 0.0, map.resolution as f32, 0.0],
    }
}
