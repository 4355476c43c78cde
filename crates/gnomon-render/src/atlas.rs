//! The shadow maps: layers of one Depth32Float array texture, each map in its layer's top-left
//! corner (maps may differ in size; the layers have the largest map's size), and beside them
//! an R32Uint array of the same layers for object-ID maps (the ID of the caster nearest the
//! light per texel; one texel a layer until a frame reads IDs). The textures and their bind
//! group (the lookup module's group) are kept and grown only when a frame needs more layers,
//! larger ones or IDs.

use crate::resources::Resources;

/// The shadow maps' depth format.
pub(crate) const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The object-ID maps' format: 0 where no caster was drawn, else the caster's ID.
pub(crate) const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// The fewest layers the array has.
const MIN_LAYERS: u32 = 2;

pub(crate) struct ShadowAtlas {
    /// Kept with its views.
    _texture: wgpu::Texture,
    pub layer_size: u32,
    pub layers: u32,
    /// One view per layer, for the depth passes.
    pub layer_views: Vec<wgpu::TextureView>,
    /// The object-ID array (kept with its views), with one view per layer where it holds
    /// maps of the layers' size (empty while no frame has read IDs).
    _ids: wgpu::Texture,
    pub id_layer_views: Vec<wgpu::TextureView>,
    /// The lookup module's bind group: records, the array twice, two samplers.
    pub bind_group: wgpu::BindGroup,
}

/// What the lookup group binds besides the texture.
pub(crate) struct AtlasBindings<'a> {
    pub layout: &'a wgpu::BindGroupLayout,
    pub shadows: &'a wgpu::Buffer,
    pub compare: &'a wgpu::Sampler,
    pub nearest: &'a wgpu::Sampler,
}

impl ShadowAtlas {
    /// Maps of side `size` in `layers` layers, with object-ID layers of that size too where
    /// `ids`.
    pub fn new(
        resources: &Resources,
        bindings: &AtlasBindings<'_>,
        size: u32,
        layers: u32,
        ids: bool,
    ) -> Self {
        // At least two layers: wgpu's GL backend makes a one-layer texture a plain 2D texture,
        // which an array view then reads as zeros. Nor a multiple of six: it makes a square
        // texture of 6k layers a cube map (a point light's six faces hit that), which an
        // array view reads wrongly too.
        let mut layers = layers.max(MIN_LAYERS);
        if layers.is_multiple_of(6) {
            layers += 1;
        }
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let texture = resources.texture("shadow maps", size, size, layers, 1, MAP_FORMAT, usage);
        let id_size = if ids { size } else { 1 };
        let id_texture = resources.texture(
            "object-ID maps",
            id_size,
            id_size,
            layers,
            1,
            ID_FORMAT,
            usage,
        );
        let layer_views = per_layer(&texture, layers);
        let id_layer_views = if ids {
            per_layer(&id_texture, layers)
        } else {
            Vec::new()
        };
        let array = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let id_array = id_texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let bind_group = resources
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("gnomon shadows"),
                layout: bindings.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: bindings.shadows.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&array),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(bindings.compare),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&array),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(bindings.nearest),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::TextureView(&id_array),
                    },
                ],
            });
        Self {
            _texture: texture,
            layer_size: size,
            layers,
            layer_views,
            _ids: id_texture,
            id_layer_views,
            bind_group,
        }
    }

    /// Whether maps of side `size` in `layers` layers fit, with their object-ID layers where
    /// `ids`.
    pub fn holds(&self, size: u32, layers: u32, ids: bool) -> bool {
        size <= self.layer_size && layers <= self.layers && (!ids || self.has_ids())
    }

    /// Whether the object-ID layers hold maps (a frame has read IDs).
    pub fn has_ids(&self) -> bool {
        !self.id_layer_views.is_empty()
    }
}

/// One 2D view per layer of an array texture (a pass's target).
fn per_layer(texture: &wgpu::Texture, layers: u32) -> Vec<wgpu::TextureView> {
    (0..layers)
        .map(|layer| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect()
}

/// The lookup group's layout (`wgsl/lookup.wgsl`).
pub(crate) fn lookup_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let texture = |sample_type| wgpu::BindingType::Texture {
        sample_type,
        view_dimension: wgpu::TextureViewDimension::D2Array,
        multisampled: false,
    };
    let entry = |binding, visibility, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("gnomon shadows"),
        entries: &[
            entry(
                0,
                wgpu::ShaderStages::VERTEX | fragment,
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
            ),
            entry(1, fragment, texture(wgpu::TextureSampleType::Depth)),
            entry(
                2,
                fragment,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            ),
            entry(
                3,
                fragment,
                texture(wgpu::TextureSampleType::Float { filterable: false }),
            ),
            entry(
                4,
                fragment,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
            ),
            entry(5, fragment, texture(wgpu::TextureSampleType::Uint)),
        ],
    })
}
