//! gnomon inside a plain wgpu program that owns its device, queue, camera and target (a
//! Bgra8 texture, as surfaces often are). Two ways to embed, both in one encoder of ours:
//!
//! A. gnomon draws its scene, shaded and shadowed, into our target.
//! B. We keep our own main pass and meshes: gnomon draws our casters (our vertex and index
//!    buffers) into its maps, and our shader reads them through the WGSL lookup gnomon ships.
//!
//! Both are checked against `Renderer::render` of the same view (the headless wrapper the CLI
//! uses). Run: `cargo run --release -p gnomon-render --example embed` (also run by
//! `tests/embed.rs`). The lines marked `gnomon:` are all the gnomon-specific code.

use glam::{DMat4, DVec3};
use gnomon::{Camera, DirectionalLight, Lens, Light, Lispsm, MapSettings, compute_setup};
use gnomon_render::{
    CasterBuffers, CasterDraw, CasterSet, Gpu, RenderScene, RenderSettings, Renderer, SceneTarget,
    ShadowedLight, lookup_wgsl,
};
use wgpu::util::DeviceExt;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 200;
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Bgra8UnormSrgb;
const SKY: wgpu::Color = wgpu::Color {
    r: 0.55,
    g: 0.7,
    b: 0.9,
    a: 1.0,
};

/// Our own main pass for way B: world-space vertices, our matrices, gnomon's lookup.
const OUR_SHADER: &str = r#"
struct Ours { clip_from_view: mat4x4<f32>, view_from_world: mat4x4<f32>, to_light: vec4<f32> };
@group(0) @binding(0) var<uniform> ours: Ours;
struct Out { @builtin(position) clip: vec4<f32>, @location(0) view: vec3<f32>,
             @location(1) normal: vec3<f32>, @location(2) color: vec3<f32> };
@vertex fn vs(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) c: vec3<f32>) -> Out {
    let view = ours.view_from_world * vec4<f32>(p, 1.0);
    return Out(ours.clip_from_view * view, view.xyz, (ours.view_from_world * vec4<f32>(n, 0.0)).xyz, c);
}
@fragment fn fs(in: Out) -> @location(0) vec4<f32> {
    var n_geo = normalize(cross(dpdx(in.view), dpdy(in.view)));
    if (dot(n_geo, -in.view) < 0.0) { n_geo = -n_geo; }
    var n = normalize(in.normal);
    if (dot(n, -in.view) < 0.0) { n = -n; }
    let l = ours.to_light.xyz;
    let shadow = gnomon_shadow(0u, in.view, n_geo, dot(n_geo, l));   // gnomon: the lookup
    let ambient = 0.25;
    return vec4<f32>(in.color * (ambient + (1.0 - ambient) * max(dot(n, l), 0.0) * shadow), 1.0);
}
"#;

/// The three images (RGBA) and how many pixels of A and B match the reference.
pub struct Report {
    pub gnomon_draws: Vec<u8>,
    pub own_pass: Vec<u8>,
    pub reference: Vec<u8>,
    /// The reference's direct-light mask.
    pub mask: Vec<u8>,
    pub agreement_a: f64,
    pub agreement_b: f64,
}

pub fn run() -> Result<Report, Box<dyn std::error::Error>> {
    // Our program: device, target, camera, light, meshes.
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        required_features: adapter.features() & gnomon_render::OPTIONAL_FEATURES,
        ..Default::default()
    }))?;
    let texture = |label, format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: WIDTH,
                height: HEIGHT,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let target = texture(
        "our target",
        FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let target_view = target.create_view(&Default::default());
    let lens = Lens {
        aspect: WIDTH as f64 / HEIGHT as f64,
        far: 800.0,
        ..Lens::default()
    };
    let camera = Camera::look_at(DVec3::new(230.0, 200.0, 230.0), DVec3::ZERO, DVec3::Y, lens)?;
    let light = Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.3))?);
    let scene = RenderScene::from_layout(&gnomon_scene::demo());

    // gnomon: a renderer on our device, the setup for our camera and light, the frame's records.
    let gpu = Gpu::from_device(device.clone(), queue.clone(), adapter.get_info());
    let mut renderer = Renderer::new(gpu, &scene)?;
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        ..RenderSettings::default()
    };
    let setup = compute_setup(
        &Lispsm::default(),
        &camera,
        &light,
        &renderer.scene_bounds()?,
        MapSettings::with_resolution(2048),
    )?;
    let lights = [ShadowedLight {
        light: &light,
        setup: &setup,
    }];
    renderer.prepare(&camera, &lights, &settings)?;

    // A: gnomon draws its scene into our target, in our encoder.
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.encode_shadow_maps(&mut encoder); // gnomon
    renderer.encode_scene(
        &mut encoder,
        &SceneTarget {
            view: &target_view,
            format: FORMAT,
            width: WIDTH,
            height: HEIGHT,
            sample_count: 1,
            resolve_target: None,
            clear: Some(SKY),
        },
    )?; // gnomon
    queue.submit([encoder.finish()]);
    let gnomon_draws = read_bgra(&device, &queue, &target);

    // B: our own meshes (world-space vertices: position, normal, colour), casters first.
    let mut vertices: Vec<[f32; 9]> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    let mut caster_indices = 0;
    for casts in [true, false] {
        for instance in scene.instances.iter().filter(|i| i.casts == casts) {
            let mesh = &scene.meshes[instance.mesh];
            let m = instance.world_from_object;
            let base = vertices.len() as u32;
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                let (p, n) = (m.transform_point3(*p), m.transform_vector3(*n).normalize());
                let c = instance.color;
                vertices.push([
                    p.x as f32, p.y as f32, p.z as f32, n.x as f32, n.y as f32, n.z as f32, c[0],
                    c[1], c[2],
                ]);
            }
            indices.extend(mesh.indices.iter().map(|i| base + i));
        }
        if casts {
            caster_indices = indices.len() as u32;
        }
    }
    let buffer = |contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents,
            usage,
        })
    };
    let vertex_buffer = buffer(bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
    let index_buffer = buffer(bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
    // gnomon: our casters, drawn from our buffers into its maps.
    let mut casters = CasterSet::new(
        &renderer,
        CasterBuffers {
            vertices: vertex_buffer.clone(),
            vertex_offset: 0,
            vertex_stride: 36,
            indices: index_buffer.clone(),
            index_format: wgpu::IndexFormat::Uint32,
        },
        vec![CasterDraw {
            indices: 0..caster_indices,
            base_vertex: 0,
            world_from_object: DMat4::IDENTITY,
            object_bounds: None,
        }],
    )?;
    casters.write_transforms(&renderer)?; // gnomon
    // Our pipeline: gnomon's lookup in bind group 1 of our shader.
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("ours"),
        source: wgpu::ShaderSource::Wgsl((lookup_wgsl(1) + OUR_SHADER).into()), // gnomon
    });
    let our_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&our_layout), Some(renderer.shadow_bind_group_layout())], // gnomon
        immediate_size: 0,
    });
    let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3];
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("our main pass"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &shader,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: 36,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &shader,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(FORMAT.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let to_light = -camera
        .view_from_world()
        .transform_vector3(DVec3::new(0.5, -1.0, 0.3).normalize());
    let mut uniform: Vec<f32> = Vec::new();
    uniform.extend(camera.clip_from_view().as_mat4().to_cols_array());
    uniform.extend(camera.view_from_world().as_mat4().to_cols_array());
    uniform.extend([to_light.x as f32, to_light.y as f32, to_light.z as f32, 0.0]);
    let uniform = buffer(bytemuck::cast_slice(&uniform), wgpu::BufferUsages::UNIFORM);
    let our_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &our_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: uniform.as_entire_binding(),
        }],
    });
    let depth = texture(
        "our depth",
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let depth_view = depth.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.encode_shadow_maps_of(&mut encoder, &casters); // gnomon
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("our main pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(SKY),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &our_group, &[]);
        pass.set_bind_group(1, renderer.shadow_bind_group(), &[]); // gnomon
        pass.set_vertex_buffer(0, vertex_buffer.slice(..));
        pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..indices.len() as u32, 0, 0..1);
    }
    queue.submit([encoder.finish()]);
    let own_pass = read_bgra(&device, &queue, &target);

    // The reference: gnomon's headless render of the same view.
    let frame = renderer.render(&camera, &light, &setup, &settings)?;
    let (reference, mask) = (frame.color, frame.mask);
    Ok(Report {
        mask,
        agreement_a: agreement(&gnomon_draws, &reference),
        agreement_b: agreement(&own_pass, &reference),
        gnomon_draws,
        own_pass,
        reference,
    })
}

/// The share of pixels whose channels are all within 3 of the reference's.
fn agreement(image: &[u8], reference: &[u8]) -> f64 {
    let close = image
        .chunks_exact(4)
        .zip(reference.chunks_exact(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).all(|(x, y)| x.abs_diff(*y) <= 3))
        .count();
    close as f64 / (image.len() / 4) as f64
}

/// Reads our target back as RGBA (our code, not gnomon's: a plain wgpu copy).
fn read_bgra(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Vec<u8> {
    let row = (WIDTH * 4).div_ceil(256) * 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (row * HEIGHT) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
        },
        wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    buffer.map_async(wgpu::MapMode::Read, .., |_| {});
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let data = buffer.get_mapped_range(..).expect("mapped");
    let mut rgba = Vec::with_capacity((WIDTH * HEIGHT * 4) as usize);
    for line in data.chunks_exact(row as usize) {
        for bgra in line[..(WIDTH * 4) as usize].chunks_exact(4) {
            rgba.extend_from_slice(&[bgra[2], bgra[1], bgra[0], bgra[3]]);
        }
    }
    rgba
}

fn main() {
    match run() {
        Ok(report) => {
            println!(
                "A (gnomon draws into our target): {:.2}% of pixels match gnomon render; \
                 B (our own main pass): {:.2}%",
                100.0 * report.agreement_a,
                100.0 * report.agreement_b
            );
            if report.agreement_a < 0.99 || report.agreement_b < 0.99 {
                std::process::exit(1);
            }
        }
        Err(e) => {
            eprintln!("embed: {e}");
            std::process::exit(1);
        }
    }
}
