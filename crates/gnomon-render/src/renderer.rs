//! [`Renderer`]: the kept resources and one frame's flow, from the core's setups to encoded
//! passes. `prepare` writes the frame's records (lights, maps, instance transforms) and picks
//! each map's casters; `encode_shadow_maps` records the depth passes and `encode_scene` the
//! main pass into the caller's encoder and target. `headless.rs` wraps them for the CLI and
//! the tests (submit, read back).

use glam::DMat4;
use gnomon::{Camera, MapSelection};

use crate::atlas::{AtlasBindings, ShadowAtlas};
use crate::gpu::ErrorScopes;
use crate::passes::FrameBindings;
use crate::passes::casters::CasterSet;
use crate::passes::main::{MainTargets, begin_main_pass};
use crate::passes::maps::{PreparedMap, SceneDepth, begin_depth_pass};
use crate::passes::stencil::VolumePass;
use crate::passes::volumes::{VolumeCasters, VolumePipelines};
use crate::pipelines::Pipelines;
use crate::readback::Readback;
use crate::records::{
    GpuFrame, MAX_LIGHTS, MAX_MAPS, MapSlot, ShadowedLight, filter_code, light_record, map_record,
    mat, reversed_clip_from_view,
};
use crate::resources::Resources;
use crate::scene::{GpuScene, RenderScene};
use crate::settings::{DepthBias, MapRead, PROJECTIVE_DEPTH_BIAS, RenderSettings, SceneTarget};
use crate::timing::{FrameClock, Part, Timer, TimingSource, Timings};
use crate::uniforms::FrameUniforms;
use crate::{Gpu, InvalidInput, RenderError};

/// Draws shadowed scenes. It keeps the pipelines, samplers, uniform buffers, the shadow maps
/// and the targets, and remakes a texture only when a frame needs a larger one; the scene's
/// meshes stay on the GPU in object space with one transform per instance.
pub struct Renderer {
    pub(crate) gpu: Gpu,
    pub(crate) resources: Resources,
    pub(crate) scene: GpuScene,
    pub(crate) pipelines: Pipelines,
    pub(crate) uniforms: FrameUniforms,
    pub(crate) atlas: ShadowAtlas,
    /// The main pass's kept depth buffer.
    main: MainTargets,
    pub(crate) maps: Vec<PreparedMap>,
    pub(crate) prepared_camera: Option<Camera>,
    /// What the prepared frame's main pass is specialised for (its lights, a per-pixel choice of map).
    pub(crate) main_spec: crate::pipelines::MainSpec,
    pub(crate) volumes: VolumePass,
    pub(crate) readback: Readback,
    pub(crate) timer: Option<Timer>,
    /// Time headless frames by the wall clock even where timestamps exist.
    pub(crate) wall_clock: bool,
    pub(crate) headless: Option<crate::frame::Targets>,
    /// The view samples pass's targets (made on first use).
    pub(crate) sample_targets: Option<crate::passes::samples::SampleTargets>,
    /// The probe pass (made on first use).
    pub(crate) probes: Option<crate::passes::probes::Probes>,
    /// The diagonal of the scene's box when the renderer was made (or
    /// [`DepthBias::FULL_SIZE_DIAGONAL`] without bounds): the scale of the default depth bias
    /// in small scenes.
    scene_diagonal: f64,
}

impl Renderer {
    /// Uploads the scene and builds the pipelines.
    pub fn new(gpu: Gpu, scene: &RenderScene) -> Result<Self, RenderError> {
        let device = gpu.device.clone();
        let scopes = ErrorScopes::push(&gpu);
        let resources = Resources::new(device.clone());
        let pipelines = Pipelines::new(&device, gpu.adapter_info.backend);
        let uniforms = FrameUniforms::new(&device, &resources, &pipelines);
        let atlas = ShadowAtlas::new(
            &resources,
            &AtlasBindings {
                layout: &pipelines.lookup_layout,
                shadows: &uniforms.shadows_buffer,
                compare: &uniforms.compare_sampler,
                nearest: &uniforms.nearest_sampler,
            },
            1,
            1,
            false,
        );
        let volumes = VolumePass {
            pipelines: VolumePipelines::new(&gpu, &pipelines),
            casters: VolumeCasters::new(scene),
            targets: None,
        };
        let gpu_scene = GpuScene::new(
            &resources,
            &gpu.queue,
            &pipelines.cutout_layout,
            pipelines.pulled_layout(),
            scene,
        )?;
        let timer = Timer::new(&gpu, &resources);
        let mut renderer = Self {
            scene: gpu_scene,
            pipelines,
            uniforms,
            atlas,
            main: MainTargets::default(),
            maps: Vec::new(),
            prepared_camera: None,
            main_spec: Default::default(),
            volumes,
            readback: Readback::new(),
            timer,
            wall_clock: false,
            headless: None,
            sample_targets: None,
            probes: None,
            scene_diagonal: DepthBias::FULL_SIZE_DIAGONAL,
            resources,
            gpu,
        };
        // The union of the casters' and receivers' boxes (the scene box `scene_bounds` would
        // give), without building its hierarchies.
        let corners = (renderer.scene.instances.iter())
            .filter(|i| i.casts || i.receives)
            .filter_map(|i| i.bounds);
        renderer.scene_diagonal = corners
            .map(|b| (b.min(), b.max()))
            .reduce(|(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
            .map_or(DepthBias::FULL_SIZE_DIAGONAL, |(lo, hi)| (hi - lo).length());
        scopes.pop()?;
        Ok(renderer)
    }

    /// The GPU this renderer draws on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Where headless frames' pass times come from: GPU timestamps where the device has
    /// TIMESTAMP_QUERY, else the wall clock.
    pub fn timing_source(&self) -> crate::TimingSource {
        if self.timer.is_some() && !self.wall_clock {
            crate::TimingSource::GpuTimestamps
        } else {
            crate::TimingSource::WallClock
        }
    }

    /// Times headless frames by the wall clock (each part submitted and waited for) even
    /// where GPU timestamps exist: to compare with wall-clock figures.
    pub fn use_wall_clock(&mut self, wall_clock: bool) {
        self.wall_clock = wall_clock;
    }

    /// Reads images back in bands of at most `bytes` (default 16 MiB; at least one row):
    /// for tests of the banding.
    #[doc(hidden)]
    pub fn set_readback_band_bytes(&mut self, bytes: u64) {
        self.readback.band_bytes = bytes.max(1);
    }

    /// Buffers and textures this renderer has made since it was created: steady-state frames
    /// add none.
    pub fn resources_created(&self) -> u64 {
        self.resources.created()
    }

    /// Whether the shadow volumes' depth is 32-bit float (DEPTH32FLOAT_STENCIL8); without the
    /// feature it is Depth24PlusStencil8 (reversed Z then gains nothing far away).
    pub fn volumes_have_float_depth(&self) -> bool {
        self.volumes.pipelines.float_depth
    }

    /// Whether instance `index` of the scene casts shadows from the next frame on (its maps
    /// pick their casters among those that do).
    pub fn set_instance_casts(&mut self, index: usize, casts: bool) -> Result<(), RenderError> {
        let count = self.scene.instances.len();
        if index >= count {
            return Err(InvalidInput::NoInstance { index, count }.into());
        }
        self.scene.set_casts(index, casts);
        Ok(())
    }

    /// Moves instance `index` of the scene (world from object); the next frame draws it there.
    pub fn set_instance_transform(
        &mut self,
        index: usize,
        world_from_object: DMat4,
    ) -> Result<(), RenderError> {
        if index >= self.scene.instances.len() {
            return Err(InvalidInput::NoInstance {
                index,
                count: self.scene.instances.len(),
            }
            .into());
        }
        if !world_from_object.is_finite() {
            return Err(InvalidInput::NonFiniteTransform {
                what: "an instance",
            }
            .into());
        }
        self.scene.set_transform(index, world_from_object);
        Ok(())
    }

    /// The scene's world bounds as the core's setup needs them (casters, receivers), from the
    /// instances' current placements.
    pub fn scene_bounds(&self) -> Result<gnomon::SceneBounds, gnomon::SetupError> {
        let mut casters = Vec::new();
        let mut receivers = Vec::new();
        for i in &self.scene.instances {
            if let Some(b) = i.bounds {
                if i.casts {
                    casters.push(b);
                }
                if i.receives {
                    receivers.push(b);
                }
            }
        }
        gnomon::SceneBounds::new(casters, receivers, None)
    }

    /// The lookup module's bind group (`lookup_wgsl`): the frame's records and the shadow
    /// maps. It is remade when the maps grow: take it after [`Renderer::prepare`].
    pub fn shadow_bind_group(&self) -> &wgpu::BindGroup {
        &self.atlas.bind_group
    }

    /// The lookup module's bind group layout.
    pub fn shadow_bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.pipelines.lookup_layout
    }

    /// Writes one frame's records: the camera, each light with its shadow setup (from the core
    /// for the same camera and light), the instance transforms, and picks the casters of each
    /// map. Grows the shadow maps when a setup needs more or larger ones.
    pub fn prepare(
        &mut self,
        camera: &Camera,
        lights: &[ShadowedLight<'_>],
        settings: &RenderSettings,
    ) -> Result<(), RenderError> {
        let lights: Vec<(&gnomon::Light, Option<&gnomon::ShadowSetup>)> =
            lights.iter().map(|l| (l.light, Some(l.setup))).collect();
        self.prepare_records(camera, &lights, settings)
    }

    /// [`Renderer::prepare`] for lights without maps (shadow volumes).
    pub(crate) fn prepare_lights(
        &mut self,
        camera: &Camera,
        lights: &[gnomon::Light],
        settings: &RenderSettings,
    ) -> Result<(), RenderError> {
        let lights: Vec<(&gnomon::Light, Option<&gnomon::ShadowSetup>)> =
            lights.iter().map(|l| (l, None)).collect();
        self.prepare_records(camera, &lights, settings)
    }

    fn prepare_records(
        &mut self,
        camera: &Camera,
        lights: &[(&gnomon::Light, Option<&gnomon::ShadowSetup>)],
        settings: &RenderSettings,
    ) -> Result<(), RenderError> {
        let (map_count, largest) = check_frame(camera, lights, self.gpu.max_texture_size())?;
        self.ensure_atlas(map_count, largest, settings.read.reads_ids());
        let view_from_world = camera.view_from_world();
        let world_from_camera = view_from_world.inverse();
        let shadows = &mut *self.uniforms.shadows;
        shadows.lights = [bytemuck::Zeroable::zeroed(); MAX_LIGHTS];
        // The maps' records are refilled in place (their lists keep their memory).
        self.maps.resize_with(map_count, PreparedMap::default);
        let mut layer = 0usize;
        for (k, (light, setup)) in lights.iter().enumerate() {
            shadows.lights[k] =
                light_record(light, *setup, view_from_world, world_from_camera, layer)?;
            shadows.lights[k].range[2] = area_size(light, settings.area_light_radius)?;
            let Some(setup) = setup else { continue };
            for (i, map) in setup.maps.iter().enumerate() {
                let slot = MapSlot {
                    layer: layer as u32,
                    layer_size: self.atlas.layer_size,
                };
                shadows.maps[layer] = map_record(
                    map,
                    world_from_camera,
                    slot,
                    &settings.bias,
                    self.scene_diagonal,
                );
                if settings.read == MapRead::Coverage {
                    // Every point at depth 1/2 and every caster written at 0 (the bias): a
                    // covered texel shadows whatever reads it, nearer than the casters or not,
                    // and an empty one (1) nothing.
                    shadows.maps[layer].depth_from_camera = [0.0, 0.0, 0.0, 0.5];
                    shadows.maps[layer].bias[0] = PROJECTIVE_DEPTH_BIAS as f32;
                    shadows.maps[layer].bias[1] = 0.0;
                }
                let side = match setup.selection {
                    // The first map reads the negative side, the second the positive.
                    MapSelection::Plane { plane_world } => {
                        Some(if i == 0 { -plane_world } else { plane_world })
                    }
                    _ => None,
                };
                self.maps[layer].fill(layer as u32, map, side, &mut self.scene);
                layer += 1;
            }
        }
        shadows.info = [lights.len() as u32, filter_code(settings.filter), 0, 0];
        self.write_frame(camera, lights, settings);
        Ok(())
    }

    /// Makes the map array anew where this frame needs more or larger layers (or object IDs).
    fn ensure_atlas(&mut self, map_count: usize, largest: u32, reads_ids: bool) {
        let ids = reads_ids || self.atlas.has_ids();
        if self.atlas.holds(largest, map_count.max(1) as u32, ids) {
            return;
        }
        self.atlas = ShadowAtlas::new(
            &self.resources,
            &AtlasBindings {
                layout: &self.pipelines.lookup_layout,
                shadows: &self.uniforms.shadows_buffer,
                compare: &self.uniforms.compare_sampler,
                nearest: &self.uniforms.nearest_sampler,
            },
            largest.max(self.atlas.layer_size),
            (map_count as u32).max(self.atlas.layers),
            ids,
        );
    }

    /// Writes the frame's uniforms, records and instance transforms, and what its main pass
    /// is specialised for.
    fn write_frame(
        &mut self,
        camera: &Camera,
        lights: &[(&gnomon::Light, Option<&gnomon::ShadowSetup>)],
        settings: &RenderSettings,
    ) {
        let frame = GpuFrame {
            clip_from_camera: mat(reversed_clip_from_view(camera)),
            infinite_clip_from_camera: mat(gnomon::volumes::reversed_infinite_clip_from_view(
                &camera.lens(),
            )),
            shading: [
                settings.ambient as f32,
                if settings.tint { 1.0 } else { 0.0 },
                0.0,
                0.0,
            ],
        };
        let queue = &self.gpu.queue;
        queue.write_buffer(&self.uniforms.frame_buffer, 0, bytemuck::bytes_of(&frame));
        queue.write_buffer(
            &self.uniforms.shadows_buffer,
            0,
            bytemuck::bytes_of(&*self.uniforms.shadows),
        );
        let coverage = settings.read == MapRead::Coverage;
        self.scene
            .write_transforms(queue, camera.view_from_world(), coverage);
        self.prepared_camera = Some(*camera);
        self.main_spec = crate::pipelines::MainSpec {
            lights: lights.len() as u32,
            read: settings.read.code(),
            per_pixel: lights.iter().flat_map(|l| l.1).any(|s| {
                matches!(
                    s.selection,
                    MapSelection::Cascades(_) | MapSelection::CubeFaces(_)
                )
            }),
            cutout: self.scene.cutouts.any(),
        };
    }

    /// Whether paraboloid maps are drawn exactly (each texel's ray cast at each triangle: see
    /// the depth pass in passes.wgsl), which needs storage buffers in vertex shaders; where the
    /// device lacks them, and for a caller's casters ([`Renderer::encode_shadow_maps_of`]),
    /// the triangles' edges are straight in the map between their corners' places.
    pub fn exact_paraboloids(&self) -> bool {
        // The scene's triangles are bound only where the pipelines were made.
        self.scene.pulled.is_some()
    }

    /// How many of the scene's casters each map of the prepared frame draws (those whose
    /// world box reaches the map's clip volume), in the order of the maps.
    pub fn casters_drawn(&self) -> Vec<usize> {
        self.maps.iter().map(|m| m.casters.len()).collect()
    }

    /// Records the prepared frame's depth passes (the scene's casters) into `encoder`.
    pub fn encode_shadow_maps(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.encode_shadow_maps_timed(encoder, false);
    }

    pub(crate) fn encode_shadow_maps_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timed: bool,
    ) {
        let stride = std::mem::size_of::<crate::scene::Vertex>() as u64;
        let (ids, cut) = (self.main_spec.read != 0, self.main_spec.cutout);
        self.pipelines.depth(&self.gpu.device, stride, ids, cut);
        self.pipelines.paraboloid(&self.gpu.device, ids, cut);
        let depth = SceneDepth {
            atlas: &self.atlas,
            scene: &self.scene,
            pipelines: &self.pipelines,
            bindings: FrameBindings::for_depth(&self.uniforms),
            ids,
            cut,
        };
        for (k, map) in self.maps.iter().enumerate() {
            let timestamps = if timed {
                self.timer.as_mut().and_then(|t| t.pass(Part::Shadow))
            } else {
                None
            };
            depth.encode(encoder, k as u32, map, timestamps);
        }
    }

    /// Records the prepared frame's depth passes with a caller's casters (its vertex and index
    /// buffers and transforms) instead of the scene's. Call [`CasterSet::write_transforms`]
    /// after [`Renderer::prepare`] first. Where the frame reads object IDs, a caster's ID is
    /// its draw's index + 1. The caller's casters are drawn whole (no alpha-masked holes).
    pub fn encode_shadow_maps_of(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &CasterSet,
    ) {
        let ids = self.main_spec.read != 0;
        self.pipelines
            .depth(&self.gpu.device, casters.vertex_stride, ids, false);
        let bindings = FrameBindings::for_depth(&self.uniforms);
        for (k, map) in self.maps.iter().enumerate() {
            let mut pass = begin_depth_pass(encoder, &self.atlas, map, ids, None);
            pass.set_pipeline(
                self.pipelines
                    .depth_for(casters.vertex_stride, ids, false)
                    .expect("made above"),
            );
            bindings.bind(&mut pass, k as u32);
            casters.draw(&mut pass, &map.planes);
        }
    }

    /// Records the main pass: the scene, shaded and shadowed, into the caller's target (its
    /// format and sample count), with a depth buffer the renderer keeps.
    pub fn encode_scene(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        target: &SceneTarget<'_>,
    ) -> Result<(), RenderError> {
        let (w, h, samples) = (target.width, target.height, target.sample_count);
        self.gpu.check_size("target", w, h)?;
        let depth = self.main.depth(&self.resources, (w, h, samples));
        let pipeline =
            self.pipelines
                .color(&self.gpu.device, target.format, samples, self.main_spec);
        let mut pass = begin_main_pass(encoder, target, depth);
        pass.set_pipeline(pipeline);
        self.frame_bindings().bind(&mut pass, 0);
        self.scene.bind(&mut pass);
        self.scene.draw_all(&mut pass, true);
        Ok(())
    }

    /// A frame's clock, on the GPU's timestamps where the renderer has them.
    pub(crate) fn start_clock(&mut self) -> FrameClock {
        let gpu_timed = self.timing_source() == TimingSource::GpuTimestamps;
        FrameClock::start(&self.gpu, &mut self.timer, gpu_timed)
    }

    /// Submits the frame's last work, waits and reads its part times.
    pub(crate) fn finish_clock(&self, clock: FrameClock) -> Result<Timings, RenderError> {
        clock.finish(&self.gpu, &self.timer)
    }

    /// The frame's bind groups as the passes that shade bind them.
    fn frame_bindings(&self) -> FrameBindings<'_> {
        FrameBindings::of(&self.uniforms, &self.atlas)
    }
}

/// A frame's camera, lights and maps checked against what the renderer draws: its map
/// count and largest map.
fn check_frame(
    camera: &Camera,
    lights: &[(&gnomon::Light, Option<&gnomon::ShadowSetup>)],
    max: u32,
) -> Result<(usize, u32), RenderError> {
    if camera.lens().far > crate::MAX_VIEW_DISTANCE {
        return Err(InvalidInput::FarPlane {
            far: camera.lens().far,
            max: crate::MAX_VIEW_DISTANCE,
        }
        .into());
    }
    if lights.len() > MAX_LIGHTS {
        return Err(InvalidInput::TooManyLights {
            count: lights.len(),
            max: MAX_LIGHTS,
        }
        .into());
    }
    let map_count: usize = lights.iter().flat_map(|l| l.1).map(|s| s.maps.len()).sum();
    if map_count > MAX_MAPS {
        return Err(InvalidInput::TooManyMaps {
            count: map_count,
            max: MAX_MAPS,
        }
        .into());
    }
    let mut largest = 1;
    for map in lights.iter().flat_map(|l| l.1).flat_map(|s| &s.maps) {
        if map.resolution > max {
            return Err(InvalidInput::MapTooLarge {
                resolution: map.resolution,
                max,
            }
            .into());
        }
        if map.resolution <= 2 * map.viewport_inset {
            return Err(InvalidInput::MapInsideInset {
                resolution: map.resolution,
                inset: map.viewport_inset,
            }
            .into());
        }
        largest = largest.max(map.resolution);
    }
    Ok((map_count, largest))
}

/// A light's area for PCSS as the lookup reads it (`GnomonLight.range.z`): a directional
/// light's tangent of its angular radius, a spot or point light's radius.
fn area_size(light: &gnomon::Light, radius: f64) -> Result<f32, RenderError> {
    gnomon::area_light::check_radius(light, radius).map_err(InvalidInput::Setup)?;
    Ok(match light {
        gnomon::Light::Directional(_) => radius.to_radians().tan(),
        _ => radius,
    } as f32)
}
