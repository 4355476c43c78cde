//! Every buffer and texture the renderer makes goes through [`Resources`], which counts them,
//! so that a test can check that steady-state frames make none.

use std::sync::atomic::{AtomicU64, Ordering};

use wgpu::util::DeviceExt;

/// The device and a count of the buffers and textures made on it.
pub(crate) struct Resources {
    pub device: wgpu::Device,
    created: AtomicU64,
}

impl Resources {
    pub fn new(device: wgpu::Device) -> Self {
        Self {
            device,
            created: AtomicU64::new(0),
        }
    }

    /// Buffers and textures made so far.
    pub fn created(&self) -> u64 {
        self.created.load(Ordering::Relaxed)
    }

    fn count(&self) {
        self.created.fetch_add(1, Ordering::Relaxed);
    }

    pub fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.count();
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(16),
            usage,
            mapped_at_creation: false,
        })
    }

    pub fn buffer_init(
        &self,
        label: &str,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        self.count();
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
    }

    /// A 2D texture (`layers` array layers, one mip level).
    #[allow(clippy::too_many_arguments)]
    pub fn texture(
        &self,
        label: &str,
        width: u32,
        height: u32,
        layers: u32,
        sample_count: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        self.count();
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    /// A 2D texture to sample (one layer, one mip level) holding `data`, row by row.
    pub fn texture_init(
        &self,
        queue: &wgpu::Queue,
        label: &str,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
        data: &[u8],
    ) -> wgpu::Texture {
        self.count();
        self.device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            data,
        )
    }

    /// A one-layer render target and its view.
    pub fn target(
        &self,
        label: &str,
        (width, height): (u32, u32),
        sample_count: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> (wgpu::Texture, wgpu::TextureView) {
        let texture = self.texture(label, width, height, 1, sample_count, format, usage);
        let view = texture.create_view(&Default::default());
        (texture, view)
    }
}
