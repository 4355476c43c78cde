//! What several passes share: the frame's bindings, their attachments and the culling of
//! casters by a map's planes.

pub(crate) mod casters;
pub(crate) mod main;
pub(crate) mod maps;
pub(crate) mod probes;
pub(crate) mod samples;
pub(crate) mod stencil;
pub(crate) mod volumes;

use glam::{DMat4, DVec4};
use gnomon::Aabb;

use crate::atlas::ShadowAtlas;
use crate::uniforms::FrameUniforms;

/// The frame's bind groups as a pass binds them: group 0 (the frame's records, at a slot's
/// dynamic offset) and group 1 (for the passes that shade, the maps and the samplers that read
/// them; for the depth passes, the records alone).
#[derive(Clone, Copy)]
pub(crate) struct FrameBindings<'a> {
    pub frame_group: &'a wgpu::BindGroup,
    pub second_group: &'a wgpu::BindGroup,
    /// The bytes between two slots of group 0.
    pub slot_stride: u32,
}

impl<'a> FrameBindings<'a> {
    /// The groups of the passes that shade: the frame's records and the atlas's lookup.
    pub fn of(uniforms: &'a FrameUniforms, atlas: &'a ShadowAtlas) -> Self {
        Self {
            frame_group: &uniforms.frame_group,
            second_group: &atlas.bind_group,
            slot_stride: uniforms.slot_stride,
        }
    }

    /// The groups of the depth passes, which read the records but no map.
    pub fn for_depth(uniforms: &'a FrameUniforms) -> Self {
        Self {
            frame_group: &uniforms.frame_group,
            second_group: &uniforms.records_group,
            slot_stride: uniforms.slot_stride,
        }
    }

    /// Binds both groups, group 0 at `slot` (map k for the depth passes, light k for the
    /// volume passes).
    pub fn bind(&self, pass: &mut wgpu::RenderPass<'_>, slot: u32) {
        pass.set_bind_group(0, self.frame_group, &[slot * self.slot_stride]);
        pass.set_bind_group(1, self.second_group, &[]);
    }
}

/// A depth attachment cleared to 0 (reversed Z: the far plane) and kept.
pub(crate) fn cleared_camera_depth(
    view: &wgpu::TextureView,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(0.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// The four side planes of a map's clip volume as world planes (x <= w, -x <= w, y <= w,
/// -y <= w): a box outside one of them lands outside the map.
pub(crate) fn clip_side_planes(clip_from_world: DMat4) -> [DVec4; 4] {
    let rows = clip_from_world.transpose();
    [
        rows.w_axis - rows.x_axis,
        rows.w_axis + rows.x_axis,
        rows.w_axis - rows.y_axis,
        rows.w_axis + rows.y_axis,
    ]
}

/// Whether a box reaches the positive side of every plane (some corner on it).
pub(crate) fn reaches_all(b: &Aabb, planes: &[DVec4]) -> bool {
    let (c, h) = (b.center(), b.half_extents());
    planes.iter().all(|p| {
        let n = p.truncate();
        n.dot(c) + p.w + n.abs().dot(h) >= 0.0
    })
}

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
