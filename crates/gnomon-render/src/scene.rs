use glam::{DMat3, DMat4, DVec3};
use gnomon::{Aabb, SceneBounds, SetupError};
use gnomon_scene::{Mesh, SceneLayout, Shape};

use crate::RenderError;

/// One placed mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// A name for listings.
    pub name: String,
    /// Index into [`RenderScene::meshes`].
    pub mesh: usize,
    /// Object to world (rotation and translation).
    pub world_from_object: DMat4,
    /// Whether it is drawn into shadow maps.
    pub casts: bool,
    /// Whether shadows fall on it.
    pub receives: bool,
    /// Its colour (linear RGB).
    pub color: [f32; 3],
}

/// Meshes and their instances: what the renderer draws.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RenderScene {
    /// The meshes, in object space.
    pub meshes: Vec<Mesh>,
    /// The placed meshes.
    pub instances: Vec<Instance>,
}

impl RenderScene {
    /// A scene from a layout: one mesh per object, generated from its shape.
    pub fn from_layout(layout: &SceneLayout) -> Self {
        let mut scene = Self::default();
        for (k, object) in layout.objects.iter().enumerate() {
            scene.meshes.push(object.shape.mesh());
            scene.instances.push(Instance {
                name: object.name.clone(),
                mesh: k,
                world_from_object: object.world_from_object,
                casts: object.casts,
                receives: object.receives,
                color: palette(&object.name),
            });
        }
        scene
    }

    /// A mesh standing on a ground slab: scaled uniformly to `height` (its y extent), its
    /// bounds centred over the origin, resting at y = 0 on a square slab ten times as wide as
    /// the mesh's largest side (the slab receives shadows, the mesh casts and receives).
    pub fn mesh_on_ground(name: &str, mesh: Mesh, height: f64) -> Result<Self, RenderError> {
        if !(height.is_finite() && height > 0.0) {
            return Err(RenderError::Invalid(format!(
                "the mesh's height must be a positive number, got {height}"
            )));
        }
        let (lo, hi) = mesh.bounds();
        let size = hi - lo;
        if !(size.y > 0.0 && size.is_finite()) {
            return Err(RenderError::Invalid(format!(
                "mesh '{name}' has no height to scale (its bounds are {lo} to {hi})"
            )));
        }
        let scale = height / size.y;
        let centre = 0.5 * (lo + hi);
        let world_from_object = DMat4::from_scale(DVec3::splat(scale))
            * DMat4::from_translation(DVec3::new(-centre.x, -lo.y, -centre.z));
        let half = 5.0 * scale * size.max_element();
        let thickness = 0.05 * half;
        let ground = Shape::Cuboid {
            half_extents: DVec3::new(half, thickness, half),
        }
        .mesh();
        Ok(Self {
            meshes: vec![ground, mesh],
            instances: vec![
                Instance {
                    name: "ground".into(),
                    mesh: 0,
                    world_from_object: DMat4::from_translation(DVec3::new(0.0, -thickness, 0.0)),
                    casts: false,
                    receives: true,
                    color: palette("ground"),
                },
                Instance {
                    name: name.into(),
                    mesh: 1,
                    world_from_object,
                    casts: true,
                    receives: true,
                    color: [0.75, 0.62, 0.45],
                },
            ],
        })
    }

    /// The world bounds of an instance (its mesh's vertices transformed).
    pub fn instance_bounds(&self, instance: &Instance) -> Result<Aabb, SetupError> {
        let mesh = &self.meshes[instance.mesh];
        let mut min = DVec3::INFINITY;
        let mut max = DVec3::NEG_INFINITY;
        for p in &mesh.positions {
            let w = instance.world_from_object.transform_point3(*p);
            min = min.min(w);
            max = max.max(w);
        }
        Aabb::new(min, max)
    }

    /// The bounds the core's setup needs: caster and receiver boxes, and their union.
    pub fn bounds(&self) -> Result<SceneBounds, SetupError> {
        let mut casters = Vec::new();
        let mut receivers = Vec::new();
        for instance in &self.instances {
            let b = self.instance_bounds(instance)?;
            if instance.casts {
                casters.push(b);
            }
            if instance.receives {
                receivers.push(b);
            }
        }
        SceneBounds::new(casters, receivers, None)
    }

    /// Every triangle in world space, with its instance's index.
    pub fn world_triangles(&self) -> Vec<([DVec3; 3], usize)> {
        let mut out = Vec::new();
        for (k, instance) in self.instances.iter().enumerate() {
            let mesh = &self.meshes[instance.mesh];
            for t in mesh.indices.chunks_exact(3) {
                let p = |i: u32| {
                    instance
                        .world_from_object
                        .transform_point3(mesh.positions[i as usize])
                };
                out.push(([p(t[0]), p(t[1]), p(t[2])], k));
            }
        }
        out
    }
}

/// A muted colour from a name, so that objects are told apart.
fn palette(name: &str) -> [f32; 3] {
    if name == "ground" {
        return [0.55, 0.55, 0.5];
    }
    let h = name
        .bytes()
        .fold(2166136261u32, |h, b| (h ^ b as u32).wrapping_mul(16777619));
    let c = |shift: u32| 0.45 + 0.4 * ((h >> shift) & 0xff) as f32 / 255.0;
    [c(0), c(8), c(16)]
}

/// The vertex the GPU reads: world position, normal, colour (alpha: receives shadows).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub color: [f32; 4],
}

/// The scene baked into world space on the GPU: one vertex and one index buffer; casters
/// first so that the depth pass draws one range.
pub(crate) struct GpuScene {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// Indices of the casters (the depth pass draws these).
    pub caster_indices: std::ops::Range<u32>,
    /// Each caster's indices and world bounds (min, max), for setups with two maps: a caster
    /// is drawn into the maps of the sides of the plane its bounds reach.
    pub casters: Vec<(std::ops::Range<u32>, DVec3, DVec3)>,
    /// All indices (the main pass draws these).
    pub all_indices: std::ops::Range<u32>,
    /// Whether every instance receives shadows.
    pub all_receive: bool,
}

impl GpuScene {
    /// Binds the buffers and draws the casters whose bounds reach the side `sign` (1 or -1)
    /// of `plane` (world).
    pub fn draw_casters_on_side(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        plane: glam::DVec4,
        sign: f64,
    ) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        let n = plane.truncate();
        for (range, lo, hi) in &self.casters {
            let (c, h) = (0.5 * (*lo + *hi), 0.5 * (*hi - *lo));
            let reach = sign * (n.dot(c) + plane.w) + n.abs().dot(h);
            if reach >= 0.0 {
                pass.draw_indexed(range.clone(), 0, 0..1);
            }
        }
    }

    /// Binds the buffers and draws the triangles of `indices`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, indices: std::ops::Range<u32>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(indices, 0, 0..1);
    }

    pub fn new(device: &wgpu::Device, scene: &RenderScene) -> Self {
        use wgpu::util::DeviceExt;
        let mut vertices: Vec<Vertex> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut order: Vec<&Instance> = scene.instances.iter().filter(|i| i.casts).collect();
        let caster_count = order.len();
        order.extend(scene.instances.iter().filter(|i| !i.casts));
        let mut caster_index_count = 0;
        let mut casters = Vec::new();
        for (k, instance) in order.iter().enumerate() {
            let mesh = &scene.meshes[instance.mesh];
            let first_index = indices.len() as u32;
            let m = instance.world_from_object;
            let normal_matrix = DMat3::from_mat4(m).inverse().transpose();
            let base = vertices.len() as u32;
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                let w = m.transform_point3(*p);
                (lo, hi) = (lo.min(w), hi.max(w));
                let wn = (normal_matrix * *n).normalize_or_zero();
                let [r, g, b] = instance.color;
                vertices.push(Vertex {
                    position: w.as_vec3().to_array(),
                    normal: wn.as_vec3().to_array(),
                    color: [r, g, b, if instance.receives { 1.0 } else { 0.0 }],
                });
            }
            indices.extend(mesh.indices.iter().map(|i| base + i));
            if k < caster_count {
                casters.push((first_index..indices.len() as u32, lo, hi));
            }
            if k + 1 == caster_count {
                caster_index_count = indices.len() as u32;
            }
        }
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Self {
            vertices: vertex_buffer,
            indices: index_buffer,
            caster_indices: 0..caster_index_count,
            casters,
            all_indices: 0..indices.len() as u32,
            all_receive: scene.instances.iter().all(|i| i.receives),
        }
    }
}
