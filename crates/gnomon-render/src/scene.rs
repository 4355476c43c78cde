use std::ops::Range;

use glam::{DMat4, DVec3};
use gnomon::{Aabb, SceneBounds, SetupError};
use gnomon_scene::{Mesh, MeshPart, SceneFile, SceneLayout, Shape};

use crate::cutouts::GpuCutouts;
use crate::records::GpuInstance;
use crate::resources::Resources;
use crate::{InvalidInput, RenderError};

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

    /// A scene file's objects: its meshes (one per distinct file: instanced) and placed
    /// objects, coloured as the file says or from the palette by name.
    pub fn from_scene_file(file: &SceneFile) -> Self {
        Self {
            meshes: file.meshes.clone(),
            instances: file
                .objects
                .iter()
                .map(|object| Instance {
                    name: object.name.clone(),
                    mesh: object.mesh,
                    world_from_object: object.world_from_object,
                    casts: object.casts,
                    receives: object.receives,
                    color: object.color.unwrap_or_else(|| palette(&object.name)),
                })
                .collect(),
        }
    }

    /// A mesh standing on a ground slab: scaled uniformly to `height` (its y extent), its
    /// bounds centred over the origin, resting at y = 0 on a square slab ten times as wide as
    /// the mesh's largest side (the slab receives shadows, the mesh casts and receives).
    pub fn mesh_on_ground(name: &str, mesh: Mesh, height: f64) -> Result<Self, RenderError> {
        Self::parts_on_ground(name, vec![MeshPart::whole(mesh)], height)
    }

    /// A mesh file's parts ([`Mesh::load_parts`]) standing on a ground slab as
    /// [`RenderScene::mesh_on_ground`] places one mesh: each part one mesh, drawn as an
    /// instance (with its own box) at each of its placements, in its material's colour where
    /// it has one.
    pub fn parts_on_ground(
        name: &str,
        parts: Vec<MeshPart>,
        height: f64,
    ) -> Result<Self, RenderError> {
        // The slab is ten times as wide as the mesh: keep it within the core's range.
        if !(height.is_finite() && height > 0.0 && height <= 1e7) {
            return Err(InvalidInput::MeshHeight(height).into());
        }
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for part in &parts {
            for placement in &part.placements {
                for p in &part.mesh.positions {
                    let q = placement.transform_point3(*p);
                    (lo, hi) = (lo.min(q), hi.max(q));
                }
            }
        }
        let size = hi - lo;
        if !(size.y > 0.0 && size.is_finite()) {
            return Err(InvalidInput::FlatMesh {
                name: name.to_string(),
                bounds: format!("{lo} to {hi}"),
            }
            .into());
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
        let mut scene = Self {
            meshes: vec![ground],
            instances: vec![Instance {
                name: "ground".into(),
                mesh: 0,
                world_from_object: DMat4::from_translation(DVec3::new(0.0, -thickness, 0.0)),
                casts: false,
                receives: true,
                color: palette("ground"),
            }],
        };
        for part in parts {
            scene.meshes.push(part.mesh);
            let base = if part.name.is_empty() {
                name.to_string()
            } else {
                format!("{name} {}", part.name)
            };
            let instanced = part.placements.len() > 1;
            for (n, placement) in part.placements.iter().enumerate() {
                scene.instances.push(Instance {
                    name: if instanced {
                        format!("{base} [{n}]")
                    } else {
                        base.clone()
                    },
                    mesh: scene.meshes.len() - 1,
                    world_from_object: world_from_object * *placement,
                    casts: true,
                    receives: true,
                    color: part.color.unwrap_or([0.75, 0.62, 0.45]),
                });
            }
        }
        Ok(scene)
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

    /// How many triangles are drawn (every instance's mesh).
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.meshes[i.mesh].triangle_count())
            .sum()
    }

    /// The scene as a Wavefront OBJ text (world-space triangles, one object per instance).
    pub fn to_obj(&self, name: &str) -> String {
        gnomon_scene::obj_text(
            name,
            self.instances
                .iter()
                .map(|i| (i.name.as_str(), &self.meshes[i.mesh], i.world_from_object)),
        )
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

/// The vertex the GPU reads: object-space position and normal, and texture coordinates
/// (where its mesh has a cutout; else 0).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

/// Where one mesh's triangles are in the scene's index buffer (whose indices count from the
/// start of the vertex buffer, so that a pass that reads the buffers itself needs no base).
#[derive(Debug, Clone)]
pub(crate) struct MeshRange {
    pub indices: Range<u32>,
}

/// One instance as the renderer keeps it: its mesh, placement, world bounds and flags.
#[derive(Debug, Clone)]
pub(crate) struct SceneInstance {
    pub mesh: usize,
    pub world_from_object: DMat4,
    /// World bounds (none for a mesh without vertices).
    pub bounds: Option<Aabb>,
    pub casts: bool,
    pub receives: bool,
    pub color: [f32; 3],
}

impl SceneInstance {
    /// The colour the shaders read: w is 1 where shadows fall on the instance.
    fn shader_color(&self) -> [f32; 4] {
        let [r, g, b] = self.color;
        [r, g, b, if self.receives { 1.0 } else { 0.0 }]
    }
}

/// The scene on the GPU: every mesh once, in object space, in one vertex and one index
/// buffer; the instances' transforms (view from object, written every frame in f64 and
/// rounded last) in an instance buffer. Moving an instance rewrites its transform only.
pub(crate) struct GpuScene {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// Both buffers as group 3 of the exact paraboloid depth passes, which read a triangle's
    /// three corners themselves (where the device has storage buffers in vertex shaders).
    pub pulled: Option<wgpu::BindGroup>,
    pub meshes: Vec<MeshRange>,
    pub instances: Vec<SceneInstance>,
    pub instances_on_gpu: InstanceStream,
    /// Each mesh's object-space bounds (for moved instances).
    mesh_bounds: Vec<Option<Aabb>>,
    /// A hierarchy over the casting instances' boxes, for each map's culling.
    casters: CasterIndex,
    /// The meshes' holes (bind group 2 of the depth and main passes).
    pub cutouts: GpuCutouts,
}

/// The casting instances (with bounds) in a [`gnomon::BoxIndex`], refitted on the next query
/// after an instance moved.
#[derive(Default)]
struct CasterIndex {
    index: gnomon::BoxIndex,
    /// The instance of each box of the index.
    instances: Vec<u32>,
    /// Whether an instance moved since the index was made.
    moved: bool,
    /// The boxes found by the last query (kept to be reused without allocating).
    found: Vec<u32>,
}

impl CasterIndex {
    fn new(instances: &[SceneInstance]) -> Self {
        let (boxes, ids) = Self::casting(instances);
        Self {
            index: gnomon::BoxIndex::new(&boxes),
            instances: ids,
            moved: false,
            found: Vec::new(),
        }
    }

    fn casting(instances: &[SceneInstance]) -> (Vec<Aabb>, Vec<u32>) {
        instances
            .iter()
            .enumerate()
            .filter_map(|(k, i)| i.bounds.filter(|_| i.casts).map(|b| (b, k as u32)))
            .unzip()
    }
}

/// Instance buffer stride (`GpuInstance`).
pub(crate) const INSTANCE_STRIDE: u64 = std::mem::size_of::<GpuInstance>() as u64;

/// Per-instance transforms on the GPU (view from object, written every frame in f64 and
/// rounded last) and their CPU copy, kept so that frames allocate nothing.
pub(crate) struct InstanceStream {
    pub buffer: wgpu::Buffer,
    staged: Vec<GpuInstance>,
}

impl InstanceStream {
    /// Room for `count` instances.
    pub fn new(resources: &Resources, label: &str, count: usize) -> Self {
        Self {
            buffer: resources.buffer(
                label,
                INSTANCE_STRIDE * count.max(1) as u64,
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
            staged: Vec::with_capacity(count),
        }
    }

    /// Writes each instance's (world from object, colour) for the camera's view.
    pub fn write(
        &mut self,
        queue: &wgpu::Queue,
        view_from_world: DMat4,
        instances: impl Iterator<Item = (DMat4, [f32; 4])>,
    ) {
        self.staged.clear();
        self.staged
            .extend(instances.map(|(world_from_object, color)| {
                GpuInstance::new(view_from_world, world_from_object, color)
            }));
        if !self.staged.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(&self.staged));
        }
    }
}

/// Every mesh once, in one vertex and one index list, and each mesh's range of indices.
type PackedMeshes = (Vec<Vertex>, Vec<u32>, Vec<MeshRange>);

/// The scene's meshes packed for the GPU.
fn packed_meshes(meshes: &[gnomon_scene::Mesh]) -> Result<PackedMeshes, RenderError> {
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    let mut ranges = Vec::new();
    for mesh in meshes {
        let first = indices.len() as u32;
        let base_vertex =
            u32::try_from(vertices.len()).map_err(|_| InvalidInput::TooManyVertices)?;
        let uv = |k: usize| mesh.uvs.get(k).map_or([0.0; 2], |t| t.as_vec2().to_array());
        vertices.extend(
            mesh.positions
                .iter()
                .zip(&mesh.normals)
                .enumerate()
                .map(|(k, (p, n))| Vertex {
                    position: p.as_vec3().to_array(),
                    normal: n.as_vec3().to_array(),
                    uv: uv(k),
                }),
        );
        indices.extend(mesh.indices.iter().map(|i| i + base_vertex));
        ranges.push(MeshRange {
            indices: first..indices.len() as u32,
        });
    }
    Ok((vertices, indices, ranges))
}

/// The scene's instances with their world boxes, each naming a mesh the scene has.
fn scene_instances(scene: &RenderScene) -> Result<Vec<SceneInstance>, RenderError> {
    let mut instances = Vec::new();
    for instance in &scene.instances {
        if instance.mesh >= scene.meshes.len() {
            return Err(InvalidInput::InstanceMesh {
                instance: instance.name.clone(),
                mesh: instance.mesh,
                count: scene.meshes.len(),
            }
            .into());
        }
        instances.push(SceneInstance {
            mesh: instance.mesh,
            world_from_object: instance.world_from_object,
            bounds: scene.instance_bounds(instance).ok(),
            casts: instance.casts,
            receives: instance.receives,
            color: instance.color,
        });
    }
    Ok(instances)
}

impl GpuScene {
    pub fn new(
        resources: &Resources,
        queue: &wgpu::Queue,
        cutout_layout: &wgpu::BindGroupLayout,
        pulled_layout: Option<&wgpu::BindGroupLayout>,
        scene: &RenderScene,
    ) -> Result<Self, RenderError> {
        let (vertices, indices, meshes) = packed_meshes(&scene.meshes)?;
        let instances = scene_instances(scene)?;
        // Buffers are never empty (a scene without geometry still binds them).
        let pad = |mut bytes: Vec<u8>| {
            bytes.resize(bytes.len().max(16).next_multiple_of(4), 0);
            bytes
        };
        // The exact paraboloid pass binds both buffers whole: where one is larger than a
        // storage binding may be, the straight-edged pass draws the scene.
        let vertex_bytes = (std::mem::size_of_val(vertices.as_slice()) as u64).max(16);
        let index_bytes = (std::mem::size_of_val(indices.as_slice()) as u64).max(16);
        let largest = resources.device.limits().max_storage_buffer_binding_size;
        let pulled_layout = pulled_layout.filter(|_| vertex_bytes.max(index_bytes) <= largest);
        let storage = if pulled_layout.is_some() {
            wgpu::BufferUsages::STORAGE
        } else {
            wgpu::BufferUsages::empty()
        };
        let vertex_buffer = resources.buffer_init(
            "scene vertices",
            &pad(bytemuck::cast_slice(&vertices).to_vec()),
            wgpu::BufferUsages::VERTEX | storage,
        );
        let index_buffer = resources.buffer_init(
            "scene indices",
            &pad(bytemuck::cast_slice(&indices).to_vec()),
            wgpu::BufferUsages::INDEX | storage,
        );
        let pulled = pulled_layout.map(|layout| {
            resources
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("scene triangles"),
                    layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: vertex_buffer.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: index_buffer.as_entire_binding(),
                        },
                    ],
                })
        });
        let instances_on_gpu = InstanceStream::new(resources, "scene instances", instances.len());
        Ok(Self {
            vertices: vertex_buffer,
            indices: index_buffer,
            pulled,
            meshes,
            mesh_bounds: scene
                .meshes
                .iter()
                .map(|m| {
                    let (lo, hi) = m.bounds();
                    Aabb::new(lo, hi).ok()
                })
                .collect(),
            casters: CasterIndex::new(&instances),
            cutouts: GpuCutouts::new(resources, queue, cutout_layout, &scene.meshes)?,
            instances,
            instances_on_gpu,
        })
    }

    /// Replaces `out` with the casting instances whose world box reaches the positive side
    /// of every plane `(a, b, c, d)`, in increasing order, through the casters' hierarchy
    /// (refitted first if an instance moved: the same casters, or built anew if the set of
    /// casting instances with a box changed).
    pub fn casters_reaching(&mut self, planes: &[glam::DVec4], out: &mut Vec<u32>) {
        let index = &mut self.casters;
        if index.moved {
            let (boxes, ids) = CasterIndex::casting(&self.instances);
            if ids == index.instances {
                index.index.refit(&boxes);
            } else {
                index.index = gnomon::BoxIndex::new(&boxes);
                index.instances = ids;
            }
            index.moved = false;
        }
        index.found.clear();
        index.index.reaching(planes, &mut index.found);
        out.clear();
        out.extend(index.found.iter().map(|&k| index.instances[k as usize]));
    }

    /// Moves instance `index`: its transform and world bounds; the GPU copy follows with the
    /// next frame's transforms.
    pub fn set_transform(&mut self, index: usize, world_from_object: DMat4) {
        let instance = &mut self.instances[index];
        instance.world_from_object = world_from_object;
        instance.bounds =
            self.mesh_bounds[instance.mesh].and_then(|b| transformed_bounds(&b, world_from_object));
        self.casters.moved = true;
    }

    /// Whether instance `index` casts (its maps' casters are picked again).
    pub fn set_casts(&mut self, index: usize, casts: bool) {
        let instance = &mut self.instances[index];
        if instance.casts != casts {
            instance.casts = casts;
            self.casters.moved = true;
        }
    }

    /// Whether every instance receives shadows.
    pub fn all_receive(&self) -> bool {
        self.instances.iter().all(|i| i.receives)
    }

    /// Writes every instance's view-from-object transform for the camera's view.
    pub fn write_transforms(
        &mut self,
        queue: &wgpu::Queue,
        view_from_world: DMat4,
        casters_lit: bool,
    ) {
        let placements = self.instances.iter().map(|i| {
            let mut color = i.shader_color();
            // Casters fully lit (projective shadows): they receive none.
            if casters_lit && i.casts {
                color[3] = 0.0;
            }
            (i.world_from_object, color)
        });
        self.instances_on_gpu
            .write(queue, view_from_world, placements);
    }

    /// Binds the buffers for the main pass (positions and normals, instances).
    pub fn bind(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_vertex_buffer(1, self.instances_on_gpu.buffer.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
    }

    /// Draws every instance (after [`GpuScene::bind`]); see [`GpuScene::draw_instances`].
    pub fn draw_all(&self, pass: &mut wgpu::RenderPass<'_>, with_holes: bool) {
        self.draw_instances(pass, 0..self.instances.len() as u32, with_holes);
    }

    /// Draws the instances of `indices` (after [`GpuScene::bind`]); `with_holes`, for a
    /// pipeline that reads them: each with its mesh's holes as group 2.
    pub fn draw_instances(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        indices: impl IntoIterator<Item = u32>,
        with_holes: bool,
    ) {
        self.for_each_draw(pass, indices, with_holes, |pass, mesh, k| {
            pass.draw_indexed(mesh.indices.clone(), 0, k..k + 1);
        });
    }

    /// Draws the instances of `indices` for the exact paraboloid depth pass (after
    /// [`GpuScene::bind_pulled`]), as [`GpuScene::draw_instances`] does: one vertex per
    /// index, which the vertex shader reads with its triangle's other corners from group 3.
    pub fn draw_pulled(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        indices: impl IntoIterator<Item = u32>,
        with_holes: bool,
    ) {
        self.for_each_draw(pass, indices, with_holes, |pass, mesh, k| {
            pass.draw(mesh.indices.clone(), k..k + 1);
        });
    }

    /// Calls `draw` with each instance of `indices` and its mesh, its mesh's holes bound as
    /// group 2 first where `with_holes` (once per run of instances sharing them).
    fn for_each_draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        indices: impl IntoIterator<Item = u32>,
        with_holes: bool,
        draw: impl Fn(&mut wgpu::RenderPass<'_>, &MeshRange, u32),
    ) {
        let mut bound: Option<&wgpu::BindGroup> = None;
        for k in indices {
            let m = self.instances[k as usize].mesh;
            if with_holes {
                let group = self.cutouts.group(m);
                if !bound.is_some_and(|b| std::ptr::eq(b, group)) {
                    pass.set_bind_group(2, group, &[]);
                    bound = Some(group);
                }
            }
            draw(pass, &self.meshes[m], k);
        }
    }

    /// Binds the instances and the triangles (group 3) for [`GpuScene::draw_pulled`]; false
    /// where the scene has no triangles to read (the device lacks storage buffers in vertex
    /// shaders).
    pub fn bind_pulled(&self, pass: &mut wgpu::RenderPass<'_>) -> bool {
        let Some(pulled) = &self.pulled else {
            return false;
        };
        pass.set_vertex_buffer(0, self.instances_on_gpu.buffer.slice(..));
        pass.set_bind_group(3, pulled, &[]);
        true
    }
}

/// The world box of an object-space box under a transform (its eight corners).
pub(crate) fn transformed_bounds(b: &Aabb, world_from_object: DMat4) -> Option<Aabb> {
    let mut min = DVec3::INFINITY;
    let mut max = DVec3::NEG_INFINITY;
    for c in b.corners() {
        let w = world_from_object.transform_point3(c);
        min = min.min(w);
        max = max.max(w);
    }
    Aabb::new(min, max).ok()
}
