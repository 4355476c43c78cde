//! The depth passes' per-map state: where each map lies in the array and which casters it
//! draws; the pass that clears and scissors its layer, and the scene's casters drawn into it.

use glam::DVec4;
use gnomon::ShadowMap;

use crate::atlas::ShadowAtlas;
use crate::passes::{FrameBindings, clip_side_planes};
use crate::pipelines::Pipelines;
use crate::scene::GpuScene;

/// One map of the prepared frame: where it is and which instances it draws.
#[derive(Default)]
pub(crate) struct PreparedMap {
    pub layer: u32,
    pub resolution: u32,
    pub inset: u32,
    /// World planes (a, b, c, d) a caster's box must reach (positive side) to be drawn: the
    /// map's clip volume's sides and, for a plane selection, the map's side of the plane.
    pub planes: Vec<DVec4>,
    /// The scene's instances drawn into it.
    pub casters: Vec<u32>,
    /// Whether it is a paraboloid hemisphere (drawn by the exact paraboloid pass where the
    /// device has it).
    pub paraboloid: bool,
}

impl PreparedMap {
    /// Fills the record of `map` in `layer`: the planes a caster's box must reach (the map's
    /// clip volume's sides, the map's `side` of a plane selection, a hemisphere's rim) and
    /// the scene's casters that reach them.
    pub fn fill(&mut self, layer: u32, map: &ShadowMap, side: Option<DVec4>, scene: &mut GpuScene) {
        self.layer = layer;
        self.resolution = map.resolution;
        self.inset = map.viewport_inset;
        self.planes.clear();
        self.planes.extend(clip_side_planes(map.clip_from_world));
        self.planes.extend(side);
        self.paraboloid = map.projection == gnomon::MapProjection::Paraboloid;
        if self.paraboloid {
            // A hemisphere holds what lies on its side of the light, to its rim
            // (q.z >= -sin(margin) |q|, and |q| <= 1 within the range).
            let rim = gnomon::PARABOLOID_MARGIN_DEGREES.to_radians().sin();
            self.planes
                .push(map.clip_from_world.row(2) + DVec4::new(0.0, 0.0, 0.0, rim));
        }
        scene.casters_reaching(&self.planes, &mut self.casters);
    }
}

/// The depth pass of one map: its layer cleared to the far depth, drawn inside the inset
/// square (the border stays at the far depth: lookups outside the focus region read as lit);
/// with `ids`, its object-ID layer too, cleared to 0 (no caster).
pub(crate) fn begin_depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    atlas: &ShadowAtlas,
    map: &PreparedMap,
    ids: bool,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    let id_target = ids.then(|| wgpu::RenderPassColorAttachment {
        view: &atlas.id_layer_views[map.layer as usize],
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    });
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("shadow depth"),
        color_attachments: if ids {
            std::slice::from_ref(&id_target)
        } else {
            &[]
        },
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &atlas.layer_views[map.layer as usize],
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timestamps,
        ..Default::default()
    });
    let r = map.resolution;
    pass.set_viewport(0.0, 0.0, r as f32, r as f32, 0.0, 1.0);
    pass.set_scissor_rect(map.inset, map.inset, r - 2 * map.inset, r - 2 * map.inset);
    pass
}

/// What the depth passes of the scene's casters read of the frame.
pub(crate) struct SceneDepth<'a> {
    pub atlas: &'a ShadowAtlas,
    pub scene: &'a GpuScene,
    /// Made for `ids` and `cut` (and the scene's vertex stride) by the caller.
    pub pipelines: &'a Pipelines,
    pub bindings: FrameBindings<'a>,
    /// Whether the maps hold object IDs beside depth.
    pub ids: bool,
    /// Whether alpha-masked instances cut holes.
    pub cut: bool,
}

impl SceneDepth<'_> {
    /// Records map `k`'s depth pass: the exact paraboloid pass where the map is a hemisphere
    /// and the device has it, else the rasterised casters.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        k: u32,
        map: &PreparedMap,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let (ids, cut) = (self.ids, self.cut);
        let mut pass = begin_depth_pass(encoder, self.atlas, map, ids, timestamps);
        self.bindings.bind(&mut pass, k);
        let exact = self.pipelines.paraboloid_for(ids, cut);
        if let Some(pipeline) = exact.filter(|_| map.paraboloid) {
            pass.set_pipeline(pipeline);
            if self.scene.bind_pulled(&mut pass) {
                self.scene
                    .draw_pulled(&mut pass, map.casters.iter().copied(), cut);
                return;
            }
        }
        let stride = std::mem::size_of::<crate::scene::Vertex>() as u64;
        pass.set_pipeline(
            self.pipelines
                .depth_for(stride, ids, cut)
                .expect("made by the caller"),
        );
        self.scene.bind(&mut pass);
        self.scene
            .draw_instances(&mut pass, map.casters.iter().copied(), cut);
    }
}
