//! How an engine makes its [`CasterSet`] from a [`Renderer`] and writes its transforms for the
//! prepared frame.

use crate::passes::casters::{CasterBuffers, CasterDraw, CasterSet};
use crate::scene::{InstanceStream, transformed_bounds};
use crate::{InvalidInput, RenderError, Renderer};

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
}
