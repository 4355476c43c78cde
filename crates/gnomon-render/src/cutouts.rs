//! Alpha-masked meshes' holes ([`gnomon_scene::Cutout`]) on the GPU: bind group 2 of the
//! depth and main passes, one per mesh (its alpha as an R8 texture, a bilinear sampler with
//! its wrap modes, its cutoff), and one without holes (cutoff 0) for the other meshes. A
//! scene with a cutout draws its depth and main passes with the `CUTOUT` specialisation,
//! which discards where the alpha at the point's texture coordinates is below the cutoff;
//! other scenes draw without it, as before.

use crate::resources::Resources;
use crate::{InvalidInput, RenderError};
use gnomon_scene::{Mesh, Wrap};

/// Group 2: the alpha (binding 0), its sampler (1), the cutoff (2: x).
pub(crate) fn cutout_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("gnomon cutout"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    })
}

/// Each mesh's group 2.
pub(crate) struct GpuCutouts {
    /// The group of each mesh that has holes.
    groups: Vec<Option<wgpu::BindGroup>>,
    /// The group of the meshes without: one opaque texel, cutoff 0.
    solid: wgpu::BindGroup,
}

impl GpuCutouts {
    pub fn new(
        resources: &Resources,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
        meshes: &[Mesh],
    ) -> Result<Self, RenderError> {
        let limit = resources.device.limits().max_texture_dimension_2d;
        let group = |alpha: &[u8], (width, height): (u32, u32), wrap: [Wrap; 2], cutoff: f32| {
            let device = &resources.device;
            let texture = resources.texture_init(
                queue,
                "cutout alpha",
                (width, height),
                wgpu::TextureFormat::R8Unorm,
                alpha,
            );
            let address = |w: Wrap| match w {
                Wrap::Repeat => wgpu::AddressMode::Repeat,
                Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
                Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
            };
            let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("cutout"),
                address_mode_u: address(wrap[0]),
                address_mode_v: address(wrap[1]),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            });
            let cutoff = resources.buffer_init(
                "cutoff",
                bytemuck::cast_slice(&[cutoff, 0.0, 0.0, 0.0]),
                wgpu::BufferUsages::UNIFORM,
            );
            let view = texture.create_view(&Default::default());
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("cutout"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: cutoff.as_entire_binding(),
                    },
                ],
            })
        };
        let mut groups = Vec::with_capacity(meshes.len());
        for (k, mesh) in meshes.iter().enumerate() {
            let Some(cutout) = mesh.holes() else {
                groups.push(None);
                continue;
            };
            if cutout.width.max(cutout.height) > limit
                || cutout.alpha.len() != (cutout.width as usize) * (cutout.height as usize)
            {
                return Err(InvalidInput::AlphaMask {
                    mesh: k,
                    width: cutout.width,
                    height: cutout.height,
                    max: limit,
                }
                .into());
            }
            groups.push(Some(group(
                &cutout.alpha,
                (cutout.width, cutout.height),
                cutout.wrap,
                cutout.cutoff,
            )));
        }
        let solid = group(&[255], (1, 1), [Wrap::Repeat; 2], 0.0);
        Ok(Self { groups, solid })
    }

    /// Whether any mesh has holes.
    pub fn any(&self) -> bool {
        self.groups.iter().any(Option::is_some)
    }

    /// Mesh `mesh`'s group.
    pub fn group(&self, mesh: usize) -> &wgpu::BindGroup {
        self.groups
            .get(mesh)
            .and_then(Option::as_ref)
            .unwrap_or(&self.solid)
    }
}
