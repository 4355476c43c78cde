//! Texture to CPU copies in bands of rows through one kept staging buffer, so that any image
//! the device can render can be read back (a buffer is limited to 256 MiB) and steady-state
//! frames make no buffer.

use crate::resources::Resources;
use crate::{Gpu, RenderError};

/// The largest band copied at once.
pub(crate) const BAND_BYTES: u64 = 16 << 20;

pub(crate) struct Readback {
    staging: Option<wgpu::Buffer>,
    pub band_bytes: u64,
}

impl Readback {
    pub fn new() -> Self {
        Self {
            staging: None,
            band_bytes: BAND_BYTES,
        }
    }

    /// Copies layer `layer` of a 2D texture to the CPU: `bytes_per_texel` bytes per texel,
    /// rows tightly packed, top to bottom.
    pub fn read(
        &mut self,
        gpu: &Gpu,
        resources: &Resources,
        texture: &wgpu::Texture,
        bytes_per_texel: u32,
        layer: u32,
    ) -> Result<Vec<u8>, RenderError> {
        let (width, height) = (texture.width(), texture.height());
        let unpadded = width as u64 * bytes_per_texel as u64;
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
        let padded = unpadded.div_ceil(align) * align;
        let rows_per_band = (self.band_bytes / padded).clamp(1, height as u64) as u32;
        let needed = padded * rows_per_band as u64;
        if self.staging.as_ref().is_none_or(|b| b.size() < needed) {
            let size = needed.max(self.staging.as_ref().map_or(0, |b| b.size()));
            self.staging = Some(resources.buffer(
                "readback",
                size,
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ));
        }
        let staging = self.staging.as_ref().expect("made above");
        let mut out = Vec::with_capacity((unpadded * height as u64) as usize);
        let mut y = 0;
        while y < height {
            let rows = rows_per_band.min(height - y);
            let mut encoder = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("readback"),
                });
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: 0, y, z: layer },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded as u32),
                        rows_per_image: Some(rows),
                    },
                },
                wgpu::Extent3d {
                    width,
                    height: rows,
                    depth_or_array_layers: 1,
                },
            );
            gpu.queue.submit([encoder.finish()]);
            let slice = staging.slice(..padded * rows as u64);
            map_for_reading(gpu, &slice)?;
            {
                let data = slice
                    .get_mapped_range()
                    .map_err(|e| RenderError::Gpu(e.to_string()))?;
                for row in data.chunks_exact(padded as usize) {
                    out.extend_from_slice(&row[..unpadded as usize]);
                }
            }
            staging.unmap();
            y += rows;
        }
        Ok(out)
    }
}

/// Maps `slice` for reading and waits until it is mapped (after the work that fills it was
/// submitted).
pub(crate) fn map_for_reading(gpu: &Gpu, slice: &wgpu::BufferSlice<'_>) -> Result<(), RenderError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    gpu.wait()?;
    receiver
        .recv()
        .map_err(|e| RenderError::Gpu(e.to_string()))?
        .map_err(|e| RenderError::Gpu(e.to_string()))
}
