//! The view samples pass: what the camera's pixels see of the real surfaces, for the core's
//! warp limit ([`gnomon::ViewSamples`], which from boxes alone can only estimate it).

use glam::DVec3;
use gnomon::{Camera, Light, ViewSamples};

use crate::Renderer;
use crate::error::RenderError;
use crate::passes::FrameBindings;
use crate::passes::samples::SampleTargets;
use crate::settings::RenderSettings;

impl Renderer {
    /// What `camera`'s pixels see of the scene, lit by `light`, as the core's samples: the
    /// scene drawn once into a grid of [`ViewSamples::grid`] pixels (about
    /// [`ViewSamples::RAYS`]), each pixel's surface point and geometric normal read back (one
    /// wait on the GPU). Give them to [`gnomon::compute_setup_with_samples`] for the same
    /// camera and light, so that the warp limit compares maps on the real surfaces. It
    /// writes the frame's records for `camera`: call it before [`Renderer::prepare`]. (An
    /// engine would take them from its last frame's depth and normals instead.)
    pub fn view_samples(
        &mut self,
        camera: &Camera,
        light: &Light,
    ) -> Result<ViewSamples, RenderError> {
        let points = self.surface_points(camera, ViewSamples::grid(camera.lens().aspect))?;
        Ok(ViewSamples::from_surface_points(
            camera,
            light,
            points.into_iter().flatten(),
        ))
    }

    /// What each pixel of a `cols` x `rows` image of `camera` sees: its surface point and
    /// geometric normal (turned toward the camera), world space, row by row from the top;
    /// `None` where there is no geometry. (It writes the frame's records for `camera`.)
    pub fn surface_points(
        &mut self,
        camera: &Camera,
        (cols, rows): (u32, u32),
    ) -> Result<Vec<Option<(DVec3, DVec3)>>, RenderError> {
        self.gpu.check_size("surface points", cols, rows)?;
        self.prepare_lights(camera, &[], &RenderSettings::default())?;
        SampleTargets::ensure(&mut self.sample_targets, &self.resources, (cols, rows));
        self.pipelines.samples(&self.gpu.device);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.sample_targets.as_ref().expect("made above").encode(
            &mut encoder,
            self.pipelines.samples(&self.gpu.device),
            FrameBindings::of(&self.uniforms, &self.atlas),
            &self.scene,
        );
        self.gpu.queue.submit([encoder.finish()]);
        let targets = self.sample_targets.as_ref().expect("made above");
        let positions =
            self.readback
                .read(&self.gpu, &self.resources, &targets.position.0, 16, 0)?;
        let normals = self
            .readback
            .read(&self.gpu, &self.resources, &targets.normal.0, 16, 0)?;
        // Camera-relative view space back to the world, in f64.
        let world_from_view = camera.view_from_world().inverse();
        let floats = |texel: &[u8]| {
            let f = |k: usize| {
                f32::from_le_bytes([texel[k], texel[k + 1], texel[k + 2], texel[k + 3]]) as f64
            };
            (DVec3::new(f(0), f(4), f(8)), f(12))
        };
        Ok(positions
            .chunks_exact(16)
            .zip(normals.chunks_exact(16))
            .map(|(p, n)| {
                let ((p, geometry), (n, _)) = (floats(p), floats(n));
                (geometry > 0.5).then(|| {
                    (
                        world_from_view.transform_point3(p),
                        world_from_view.transform_vector3(n).normalize_or_zero(),
                    )
                })
            })
            .collect())
    }
}
