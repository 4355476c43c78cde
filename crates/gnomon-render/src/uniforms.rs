//! The frame's uniforms, made once: the frame record (projections, shading), every light's
//! and map's records, the slots by which a pass picks its map or light, the shadow samplers,
//! and their bind groups.

use crate::pipelines::Pipelines;
use crate::records::{GpuFrame, GpuShadows, GpuSlot, MAX_LIGHTS, MAX_MAPS};
use crate::resources::Resources;

/// The frame's uniform buffers, samplers and bind groups.
pub(crate) struct FrameUniforms {
    pub compare_sampler: wgpu::Sampler,
    pub nearest_sampler: wgpu::Sampler,
    pub frame_buffer: wgpu::Buffer,
    pub shadows_buffer: wgpu::Buffer,
    _slot_buffer: wgpu::Buffer,
    pub slot_stride: u32,
    pub frame_group: wgpu::BindGroup,
    /// The records alone, for the depth passes.
    pub records_group: wgpu::BindGroup,
    /// The prepared frame's records (kept to be rewritten without allocating).
    pub shadows: Box<GpuShadows>,
}

impl FrameUniforms {
    pub fn new(device: &wgpu::Device, resources: &Resources, pipelines: &Pipelines) -> Self {
        let sampler = |label, filter, compare| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: filter,
                min_filter: filter,
                compare,
                ..Default::default()
            })
        };
        let compare_sampler = sampler(
            "shadow comparison (2x2)",
            wgpu::FilterMode::Linear,
            Some(wgpu::CompareFunction::LessEqual),
        );
        let nearest_sampler = sampler("shadow raw depth", wgpu::FilterMode::Nearest, None);
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let frame_buffer =
            resources.buffer("frame", std::mem::size_of::<GpuFrame>() as u64, uniform);
        let shadows_buffer =
            resources.buffer("shadows", std::mem::size_of::<GpuShadows>() as u64, uniform);
        // One slot per map (depth passes, light views) and per light (volume passes).
        let slot_stride = device.limits().min_uniform_buffer_offset_alignment.max(16);
        let slots: Vec<u8> = (0..MAX_MAPS.max(MAX_LIGHTS) as u32)
            .flat_map(|k| {
                let mut bytes = bytemuck::bytes_of(&GpuSlot {
                    map: k,
                    light: k,
                    unused: [0; 2],
                })
                .to_vec();
                bytes.resize(slot_stride as usize, 0);
                bytes
            })
            .collect();
        let slot_buffer = resources.buffer_init("slots", &slots, wgpu::BufferUsages::UNIFORM);
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gnomon frame"),
            layout: &pipelines.frame_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &slot_buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<GpuSlot>() as u64),
                    }),
                },
            ],
        });
        let records_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gnomon records"),
            layout: &pipelines.records_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: shadows_buffer.as_entire_binding(),
            }],
        });
        Self {
            compare_sampler,
            nearest_sampler,
            frame_buffer,
            shadows_buffer,
            _slot_buffer: slot_buffer,
            slot_stride,
            frame_group,
            records_group,
            shadows: Box::new(bytemuck::Zeroable::zeroed()),
        }
    }
}
