//! The view samples pass: its kept targets (position and normal per pixel, and depth) and the
//! scene drawn into them.

use crate::passes::{FrameBindings, cleared_camera_depth, color_target};
use crate::pipelines::{CAMERA_DEPTH_FORMAT, METRICS_FORMAT};
use crate::resources::Resources;
use crate::scene::GpuScene;

/// The kept targets of the samples pass: position and normal per pixel, and depth.
pub(crate) struct SampleTargets {
    pub position: (wgpu::Texture, wgpu::TextureView),
    pub normal: (wgpu::Texture, wgpu::TextureView),
    pub depth: wgpu::TextureView,
}

impl SampleTargets {
    /// Makes (or keeps) the targets of a `cols` x `rows` grid in `slot`.
    pub fn ensure(slot: &mut Option<SampleTargets>, r: &Resources, (cols, rows): (u32, u32)) {
        if slot
            .as_ref()
            .is_some_and(|t| (t.position.0.width(), t.position.0.height()) == (cols, rows))
        {
            return;
        }
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        *slot = Some(SampleTargets {
            position: r.target("sample positions", (cols, rows), 1, METRICS_FORMAT, usage),
            normal: r.target("sample normals", (cols, rows), 1, METRICS_FORMAT, usage),
            depth: r
                .target(
                    "sample depth",
                    (cols, rows),
                    1,
                    CAMERA_DEPTH_FORMAT,
                    wgpu::TextureUsages::RENDER_ATTACHMENT,
                )
                .1,
        });
    }

    /// Records the scene drawn by the samples `pipeline` into the targets (cleared).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::RenderPipeline,
        bindings: FrameBindings<'_>,
        scene: &GpuScene,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("view samples"),
            color_attachments: &[
                color_target(&self.position.1, Some(wgpu::Color::TRANSPARENT)),
                color_target(&self.normal.1, Some(wgpu::Color::TRANSPARENT)),
            ],
            depth_stencil_attachment: Some(cleared_camera_depth(&self.depth)),
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        bindings.bind(&mut pass, 0);
        scene.bind(&mut pass);
        scene.draw_all(&mut pass, false);
    }
}
