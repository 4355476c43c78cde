//! A caller's casters for the depth passes: an engine keeps its own main pass and meshes,
//! and gives gnomon the vertex and index buffers it already has plus a transform per draw.

use std::ops::Range;

use glam::DMat4;
use gnomon::Aabb;

use crate::renderer::reaches_all;
use crate::scene::{InstanceStream, transformed_bounds};
use crate::{InvalidInput, RenderError, Renderer};

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
    vertices: wgpu::Buffer,
    vertex_offset: u64,
    pub(crate) vertex_stride: u64,
    indices: wgpu::Buffer,
    index_format: wgpu::IndexFormat,
    draws: Vec<CasterDraw>,
    world_bounds: Vec<Option<Aabb>>,
    instances: InstanceStream,
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
    /// Casters drawn from the caller's buffers.
    pub fn new(
        renderer: &Renderer,
        buffers: CasterBuffers,
        draws: Vec<CasterDraw>,
    ) -> Result<Self, RenderError> {
        if buffers.vertex_stride < 12 || !buffers.vertex_stride.is_multiple_of(4) {
            return Err(InvalidInput::CasterStride {
                stride: buffers.vertex_stride,
            }
            .into());
        }
        if draws.iter().any(|d| !d.world_from_object.is_finite()) {
            return Err(InvalidInput::NonFiniteTransform { what: "a caster" }.into());
        }
        let world_bounds = draws
            .iter()
            .map(|d| {
                d.object_bounds
                    .and_then(|b| transformed_bounds(&b, d.world_from_object))
            })
            .collect();
        let instances = InstanceStream::new(&renderer.resources, "caster instances", draws.len());
        Ok(Self {
            vertices: buffers.vertices,
            vertex_offset: buffers.vertex_offset,
            vertex_stride: buffers.vertex_stride,
            indices: buffers.indices,
            index_format: buffers.index_format,
            draws,
            world_bounds,
            instances,
        })
    }

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

    /// Writes the transforms for the camera of the renderer's prepared frame.
    pub fn write_transforms(&mut self, renderer: &Renderer) -> Result<(), RenderError> {
        let camera = renderer
            .prepared_camera
            .ok_or(InvalidInput::FrameNotPrepared)?;
        let placements = self.draws.iter().map(|d| (d.world_from_object, [1.0; 4]));
        self.instances
            .write(&renderer.gpu.queue, camera.view_from_world(), placements);
        Ok(())
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
