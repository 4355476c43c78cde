//! The main pass: the scene, shaded and shadowed, into the caller's target, with a depth
//! buffer it keeps; or, headless, into the renderer's own targets with the lit-light bits and
//! the pixel metrics beside the colour.

use crate::frame::{SKY, Targets};
use crate::passes::{FrameBindings, cleared_camera_depth, color_target};
use crate::pipelines::CAMERA_DEPTH_FORMAT;
use crate::resources::Resources;
use crate::scene::GpuScene;
use crate::settings::SceneTarget;

/// The main pass's kept depth buffer (its size and samples are the last target's).
#[derive(Default)]
pub(crate) struct MainTargets {
    camera_depth: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl MainTargets {
    /// The depth buffer of a target of `w` x `h` pixels and `samples` samples, made anew
    /// only when those change.
    pub fn depth(
        &mut self,
        resources: &Resources,
        (w, h, samples): (u32, u32, u32),
    ) -> &wgpu::TextureView {
        if self
            .camera_depth
            .as_ref()
            .is_none_or(|(t, _)| (t.width(), t.height(), t.sample_count()) != (w, h, samples))
        {
            self.camera_depth = Some(resources.target(
                "camera depth",
                (w, h),
                samples,
                CAMERA_DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            ));
        }
        &self.camera_depth.as_ref().expect("made above").1
    }
}

/// Begins the main pass into the caller's target (cleared where it asks), depth cleared.
pub(crate) fn begin_main_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    target: &SceneTarget<'_>,
    depth: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("main"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target.view,
            depth_slice: None,
            resolve_target: target.resolve_target,
            ops: wgpu::Operations {
                load: target.clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(cleared_camera_depth(depth)),
        ..Default::default()
    })
}

/// Records the headless main pass into `targets`: the colour, the lit-light bits and, where
/// `targets` holds them (`metrics`), the pixel metrics, drawn by the measured `pipeline`.
pub(crate) fn encode_measured(
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
    metrics: bool,
    (pipeline, bindings, scene): (&wgpu::RenderPipeline, FrameBindings<'_>, &GpuScene),
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut attachments = vec![
        color_target(&targets.color.1, Some(SKY)),
        color_target(&targets.lit.1, Some(wgpu::Color::TRANSPARENT)),
    ];
    if metrics {
        let view = &targets.metrics.as_ref().expect("made with the targets").1;
        attachments.push(color_target(view, Some(wgpu::Color::TRANSPARENT)));
    }
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("main (measured)"),
        color_attachments: &attachments,
        depth_stencil_attachment: Some(cleared_camera_depth(&targets.depth)),
        timestamp_writes: timestamps,
        ..Default::default()
    });
    pass.set_pipeline(pipeline);
    bindings.bind(&mut pass, 0);
    scene.bind(&mut pass);
    scene.draw_all(&mut pass, true);
}
