//! A caller's casters for the depth passes: an engine keeps its own main pass and meshes,
//! and gives gnomon the vertex and index buffers it already has plus a transform per draw.

use std::ops::Range;

use glam::DMat4;
use gnomon::Aabb;

use crate::passes::reaches_all;
use crate::scene::{InstanceStream, transformed_bounds};

/// One caster: a range of the index buffer drawn with a base vertex and a placement.
#[derive(Debug, Clone, PartialEq)]
pub struct CasterDraw {
    /// Indices into the index buffer.
    pub indices: Range<u32>,
    /// Added to each index.
    pub base_vertex: i32,
    /// World from object.
    pub world_from_object: DMat4,
    /// Object-space bounds of what it draws: with them a map draws only the casters that reach
    /// it; without, every map draws it.
    pub object_bounds: Option<Aabb>,
}

/// A caller's vertex buffer (positions as three f32 at `offset`, every `stride` bytes), index
/// buffer and draws, with the per-draw transforms gnomon writes relative to the camera.
pub struct CasterSet {
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) vertex_offset: u64,
    pub(crate) vertex_stride: u64,
    pub(crate) indices: wgpu::Buffer,
    pub(crate) index_format: wgpu::IndexFormat,
    pub(crate) draws: Vec<CasterDraw>,
    pub(crate) world_bounds: Vec<Option<Aabb>>,
    pub(crate) instances: InstanceStream,
}

/// The caller's buffers for [`CasterSet::new`].
#[derive(Debug, Clone)]
pub struct CasterBuffers {
    /// Vertices (VERTEX usage); positions are three f32.
    pub vertices: wgpu::Buffer,
    /// Byte offset of the first position.
    pub vertex_offset: u64,
    /// Bytes from one position to the next.
    pub vertex_stride: u64,
    /// Indices (INDEX usage).
    pub indices: wgpu::Buffer,
    /// Their format.
    pub index_format: wgpu::IndexFormat,
}

impl CasterSet {
    /// Moves draw `k`.
    pub fn set_transform(&mut self, k: usize, world_from_object: DMat4) {
        let draw = &mut self.draws[k];
        draw.world_from_object = world_from_object;
        self.world_bounds[k] = draw
            .object_bounds
            .and_then(|b| transformed_bounds(&b, world_from_object));
    }

    /// The casters' world boxes (those with bounds), for the core's scene bounds.
    pub fn world_bounds(&self) -> impl Iterator<Item = Aabb> + '_ {
        self.world_bounds.iter().flatten().copied()
    }

    /// Draws the casters that reach every plane.
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, planes: &[glam::DVec4]) {
        pass.set_vertex_buffer(0, self.vertices.slice(self.vertex_offset..));
        pass.set_vertex_buffer(1, self.instances.buffer.slice(..));
        pass.set_index_buffer(self.indices.slice(..), self.index_format);
        for (k, draw) in self.draws.iter().enumerate() {
            if self.world_bounds[k].is_none_or(|b| reaches_all(&b, planes)) {
                pass.draw_indexed(
                    draw.indices.clone(),
                    draw.base_vertex,
                    k as u32..k as u32 + 1,
                );
            }
        }
    }
}
