//! Stenciled shadow volumes: the exact shadows gnomon measures every map against (the
//! shadows lecture's "Shadow Volumes" slides; Everitt and Kilgard 2002).
//!
//! Per frame: the scene's depth is laid down through the camera's reversed infinite projection
//! (depth = near / distance: volume geometry at infinity, w = 0, lands at exactly 0 and is
//! never clipped; Depth32FloatStencil8 where the device has it) and the
//! ambient term drawn. Then per light: the casters' volumes are extruded on the CPU by the
//! core crate ([`gnomon::volumes`]) and drawn into the cleared stencil buffer with two-sided
//! stencil and wrapping increments in one pass - z-fail (Carmack's reverse: back faces
//! behind the surface +1, front faces behind it -1; right even when the camera is inside a
//! volume), z-pass (front faces in front of the surface +1, back faces -1; wrong when a
//! volume reaches the near plane) or per caster (z-pass without caps where the caster's
//! volume cannot reach the near plane, z-fail elsewhere); then the light's direct term is
//! added where the count is 0 and its mask written (lit where the count is 0, shadowed
//! elsewhere, as for shadow maps).

use gnomon::planar::PlanarReceiver;
use gnomon::{Camera, Light};

use crate::passes::FrameBindings;
use crate::passes::stencil::{StencilFrame, VolumeTargets};
use crate::passes::volumes::{StencilMode, Stenciled, VolumeFrame, VolumeStats};
use crate::timing::Part;
use crate::{Frame, InvalidInput, RenderError, RenderSettings, Renderer};

impl Renderer {
    /// Renders one frame of `camera` lit by `light` with exact shadows from stenciled shadow
    /// volumes; see [`Renderer::render_volumes_lit_by`].
    pub fn render_volumes(
        &mut self,
        camera: &Camera,
        light: &Light,
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<VolumeFrame, RenderError> {
        self.render_volumes_lit_by(camera, std::slice::from_ref(light), settings, mode)
    }

    /// Renders one frame of `camera` lit by `lights` with exact shadows from stenciled
    /// shadow volumes (see the module documentation): the scene's depth and the ambient term
    /// once, then per light its volumes into a cleared stencil and its direct light added
    /// where the count is 0. `settings`' filter and bias do not apply. Timings: the shadow
    /// part is extrusion plus stencil passes, the main part the depth, ambient and lighting
    /// passes, summed over the lights.
    pub fn render_volumes_lit_by(
        &mut self,
        camera: &Camera,
        lights: &[Light],
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<VolumeFrame, RenderError> {
        let (timings, stats) = self.draw_volumes_lit_by(camera, lights, settings, mode)?;
        self.read_stenciled(timings, stats, lights.len(), settings)
    }

    /// Reads back a stenciled frame: its colour and each light's mask.
    fn read_stenciled(
        &mut self,
        timings: crate::Timings,
        stats: VolumeStats,
        light_count: usize,
        settings: &RenderSettings,
    ) -> Result<VolumeFrame, RenderError> {
        let (width, height) = (settings.width, settings.height);
        let start = std::time::Instant::now();
        let headless = self.headless.as_ref().expect("made by the draw");
        let color = self
            .readback
            .read(&self.gpu, &self.resources, &headless.color.0, 4, 0)?;
        let targets = self.volumes.targets.as_ref().expect("kept by the draw");
        let mut light_masks = Vec::with_capacity(light_count);
        for (texture, _) in targets.masks.iter().take(light_count) {
            light_masks.push(
                self.readback
                    .read(&self.gpu, &self.resources, texture, 1, 0)?,
            );
        }
        let mut timings = timings;
        timings.readback_ms = start.elapsed().as_secs_f64() * 1e3;
        // Lit by any light: 255 beats 0; empty pixels are empty for every light.
        let mut mask = light_masks[0].clone();
        for other in &light_masks[1..] {
            for (m, o) in mask.iter_mut().zip(other) {
                *m = (*m).max(*o);
            }
        }
        Ok(VolumeFrame {
            frame: Frame {
                width,
                height,
                color,
                mask,
                light_masks,
                shadow: None,
                light_view: None,
                metrics: None,
                timings,
                casters_drawn: Vec::new(),
            },
            stats,
        })
    }

    /// [`Renderer::render_volumes_lit_by`] without reading the frame back: the image stays in
    /// [`Renderer::frame_color`] (a window's program copies it to its own target); waits for
    /// the GPU to time the parts.
    pub fn draw_volumes_lit_by(
        &mut self,
        camera: &Camera,
        lights: &[Light],
        settings: &RenderSettings,
        mode: StencilMode,
    ) -> Result<(crate::Timings, VolumeStats), RenderError> {
        self.draw_stenciled(camera, lights, settings, Stenciled::Volumes(mode))
    }

    /// Renders one frame of `camera` lit by `lights` with planar projected shadows on
    /// `receiver` (the shadows lecture's "projection to a plane", [`gnomon::planar`]): the
    /// casters flattened onto its plane mark, through the stencil, the visible pixels of its
    /// polygon they cover (once however many overlap); every other surface is lit (the
    /// technique's limit). The passes are the volumes' with that stencil; the stats count
    /// the flattened triangles and the casters.
    pub fn render_planar_lit_by(
        &mut self,
        camera: &Camera,
        lights: &[Light],
        receiver: &PlanarReceiver,
        settings: &RenderSettings,
    ) -> Result<VolumeFrame, RenderError> {
        let (timings, stats) =
            self.draw_stenciled(camera, lights, settings, Stenciled::Planar(receiver))?;
        self.read_stenciled(timings, stats, lights.len(), settings)
    }

    /// [`Renderer::render_planar_lit_by`] without reading the frame back (see
    /// [`Renderer::draw_volumes_lit_by`]).
    pub fn draw_planar_lit_by(
        &mut self,
        camera: &Camera,
        lights: &[Light],
        receiver: &PlanarReceiver,
        settings: &RenderSettings,
    ) -> Result<(crate::Timings, VolumeStats), RenderError> {
        self.draw_stenciled(camera, lights, settings, Stenciled::Planar(receiver))
    }

    fn draw_stenciled(
        &mut self,
        camera: &Camera,
        lights: &[Light],
        settings: &RenderSettings,
        stenciled: Stenciled<'_>,
    ) -> Result<(crate::Timings, VolumeStats), RenderError> {
        if lights.is_empty() {
            return Err(InvalidInput::NoLights.into());
        }
        let (width, height) = self.image_size(settings)?;
        let scopes = crate::gpu::ErrorScopes::push(&self.gpu);
        self.prepare_lights(camera, lights, settings)?;
        self.ensure_headless(width, height, false);
        let mut targets = VolumeTargets::fitting(
            self.volumes.targets.take(),
            &self.resources,
            self.volumes.pipelines.format,
            (width, height),
            lights.len(),
        );
        let mut clock = self.start_clock();
        // Extrusion (or flattening) on the CPU counts as the shadow part.
        match stenciled {
            Stenciled::Volumes(mode) => self.volumes.casters.extrude(
                &self.scene.instances,
                camera,
                lights,
                mode,
                &mut targets.extruded,
            ),
            Stenciled::Planar(receiver) => self.volumes.casters.flatten(
                &self.scene.instances,
                camera,
                lights,
                receiver,
                &mut targets.extruded,
            ),
        }
        targets.upload(&self.resources, &self.gpu.queue);
        clock.cpu_part(Part::Shadow);
        let frame = StencilFrame {
            gpu: &self.gpu,
            pipelines: &self.volumes.pipelines,
            targets: &targets,
            bindings: FrameBindings::of(&self.uniforms, &self.atlas),
            scene: &self.scene,
            color_view: &self.headless.as_ref().expect("made above").color.1,
            planar: matches!(stenciled, Stenciled::Planar(_)),
        };
        let result = frame.encode(lights.len(), &mut clock, &mut self.timer);
        let stats = targets.extruded.stats;
        self.volumes.targets = Some(targets);
        result?;
        let timings = self.finish_clock(clock)?;
        scopes.pop()?;
        Ok((timings, stats))
    }
}
