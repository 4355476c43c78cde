//! Probes: a frame's shadow state at given surface points, as its main pass reads it (the
//! map its selection picks, the normal offset, one tap; lit beyond a cascade's shadow
//! distance), for measurements on fixed world points (`gnomon flicker`).

use glam::DVec3;
use gnomon::Camera;

use crate::Renderer;
use crate::error::{InvalidInput, RenderError};
use crate::passes::FrameBindings;
use crate::passes::probes::{PROBE_SIZE, Probes};
use crate::records::ShadowedLight;
use crate::scene::Vertex;
use crate::settings::RenderSettings;

impl Renderer {
    /// Whether light 0 of `lights` reaches each surface point (world position, unit normal)
    /// according to its shadow maps, one tap, as the main pass's mask reads it: true where
    /// the map says lit (or beyond a cascade's shadow distance), false where shadowed. Facing
    /// the light is not judged here. Prepares the frame (as [`Renderer::prepare`]) and draws
    /// its maps.
    pub fn lit_at_points(
        &mut self,
        camera: &Camera,
        lights: &[ShadowedLight<'_>],
        settings: &RenderSettings,
        points: &[(DVec3, DVec3)],
    ) -> Result<Vec<bool>, RenderError> {
        self.prepare(camera, lights, settings)?;
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.encode_shadow_maps(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        if self.probes.is_none() {
            self.probes = Some(Probes::new(
                &self.gpu.device,
                &self.resources,
                &self.pipelines,
            ));
        }
        let view_from_world = camera.view_from_world();
        let batch = (PROBE_SIZE * PROBE_SIZE) as usize;
        let mut lit = Vec::with_capacity(points.len());
        for chunk in points.chunks(batch) {
            let vertices: Vec<Vertex> = chunk
                .iter()
                .map(|(p, n)| Vertex {
                    position: view_from_world.transform_point3(*p).as_vec3().to_array(),
                    normal: view_from_world.transform_vector3(*n).as_vec3().to_array(),
                    uv: [0.0; 2],
                })
                .collect();
            let probes = self.probes.as_ref().expect("made above");
            self.gpu
                .queue
                .write_buffer(&probes.points, 0, bytemuck::cast_slice(&vertices));
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            let bindings = FrameBindings::of(&self.uniforms, &self.atlas);
            probes.encode(&mut encoder, bindings, chunk.len() as u32);
            self.gpu.queue.submit([encoder.finish()]);
            let bits = self.readback.read(
                &self.gpu,
                &self.resources,
                &self.probes.as_ref().expect("made above").target.0,
                4,
                0,
            )?;
            for texel in bits.chunks_exact(4).take(chunk.len()) {
                let b = u32::from_le_bytes([texel[0], texel[1], texel[2], texel[3]]);
                if b & 2 == 0 {
                    return Err(InvalidInput::ProbeNotDrawn.into());
                }
                lit.push(b & 1 != 0);
            }
        }
        Ok(lit)
    }
}
