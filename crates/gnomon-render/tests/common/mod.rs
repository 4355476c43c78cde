//! Shared by the GPU tests: an exact-shadow oracle (a CPU ray caster on parry3d-f64), mask
//! comparison, and a renderer that refuses to run without an adapter (no silent skips).

#![allow(dead_code)]

use glam::{DVec3, DVec4};
use gnomon::{Camera, Light, MapSettings, ShadowSetup, ShadowTechnique, compute_setup};
use gnomon_render::{
    Frame, Gpu, MASK_EMPTY, MASK_LIT, MASK_UNLIT, RenderScene, RenderSettings, Renderer,
};
use parry3d_f64::math::Vector;
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;

/// A renderer on whatever adapter there is; panics (fails the test) without one.
pub fn renderer(scene: &RenderScene) -> Renderer {
    Renderer::new(gpu(), scene).expect("renderer")
}

/// The test process's one device, opened by the first test that asks and never closed.
///
/// Why one: NVIDIA's Linux Vulkan driver (580, H200) crashes the process when a device is
/// destroyed on one thread while another thread's device lives on (the driver's own
/// threads return into code it has unloaded; gfx-rs/wgpu#8365). Tests that each opened and
/// dropped their own device crashed object_id's binary with two threads. Error scopes are
/// per thread, so tests sharing the device still see only their own errors.
pub fn gpu() -> Gpu {
    static GPU: std::sync::OnceLock<Gpu> = std::sync::OnceLock::new();
    GPU.get_or_init(|| Gpu::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}")))
        .clone()
}

/// The default settings of a `size` x `size` frame.
pub fn square_settings(size: u32) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        ..RenderSettings::default()
    }
}

/// A square camera with a 60 degree field of view, up +Y.
pub fn square_camera(eye: DVec3, target: DVec3, near: f64, far: f64) -> Camera {
    square_camera_up(eye, target, DVec3::Y, near, far)
}

/// A square 60 degree camera with its own up (one looking straight up or down needs one).
pub fn square_camera_up(eye: DVec3, target: DVec3, up: DVec3, near: f64, far: f64) -> Camera {
    let lens = gnomon::Lens {
        fov_y_degrees: 60.0,
        aspect: 1.0,
        near,
        far,
    };
    Camera::look_at(eye, target, up, lens).expect("a valid camera")
}

fn vector(p: DVec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn dvec(v: Vector) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// The exact direct-light mask and N.L of every pixel.
pub struct OracleMask {
    pub width: u32,
    pub height: u32,
    /// 255 lit, 0 not lit, 128 no geometry.
    pub mask: Vec<u8>,
    /// N.L with the geometric normal turned toward the camera (0 where no geometry).
    pub n_dot_l: Vec<f64>,
    /// The surface point each pixel sees (`None`: no geometry).
    pub points: Vec<Option<DVec3>>,
    /// The scene's instance each pixel sees (`None`: no geometry).
    pub objects: Vec<Option<usize>>,
    /// Whether the light reaches each pixel's point but for shadows (inside a spot's cone and
    /// a light's range; false where no geometry).
    pub in_light: Vec<bool>,
}

/// Ray casts the mask the renderer's `--mask` draws: primary rays through pixel centres,
/// then a shadow ray from 1e-5 x the scene diagonal off the surface along the normal.
pub fn oracle(
    scene: &RenderScene,
    camera: &Camera,
    light: &Light,
    width: u32,
    height: u32,
) -> OracleMask {
    let holes = Holes::new(scene);
    let triangles = &holes.triangles;
    let mut all_vertices = Vec::new();
    let mut all_indices = Vec::new();
    let mut caster_vertices = Vec::new();
    let mut caster_indices = Vec::new();
    // Each caster triangle's index among all triangles.
    let mut caster_triangles = Vec::new();
    for (g, (t, k)) in triangles.iter().enumerate() {
        let base = all_vertices.len() as u32;
        all_vertices.extend(t.iter().map(|p| vector(*p)));
        all_indices.push([base, base + 1, base + 2]);
        if scene.instances[*k].casts {
            let base = caster_vertices.len() as u32;
            caster_vertices.extend(t.iter().map(|p| vector(*p)));
            caster_indices.push([base, base + 1, base + 2]);
            caster_triangles.push(g);
        }
    }
    let everything = TriMesh::new(all_vertices, all_indices).expect("scene mesh");
    let casters = TriMesh::new(caster_vertices, caster_indices).expect("caster mesh");
    let bounds = scene.bounds().expect("bounds").scene_box();
    let diagonal = bounds.diagonal();
    let world_from_clip = camera.clip_from_world().inverse();
    let unproject = |x: f64, y: f64, z: f64| {
        let p: DVec4 = world_from_clip * DVec4::new(x, y, z, 1.0);
        p.truncate() / p.w
    };
    let n = (width * height) as usize;
    let mut mask = vec![MASK_EMPTY; n];
    let mut n_dot_l = vec![0.0; n];
    let mut points = vec![None; n];
    let mut objects = vec![None; n];
    let mut reached = vec![false; n];
    for py in 0..height {
        for px in 0..width {
            let x = (px as f64 + 0.5) / width as f64 * 2.0 - 1.0;
            let y = 1.0 - (py as f64 + 0.5) / height as f64 * 2.0;
            let near = unproject(x, y, 0.0);
            let far = unproject(x, y, 1.0);
            let Some(hit) = holes.first_hit(&everything, near, far - near, 1.0, |s| s as usize)
            else {
                continue;
            };
            let i = (py * width + px) as usize;
            let p = near + (far - near) * hit.time_of_impact;
            points[i] = Some(p);
            objects[i] = Some(triangles[hit.subshape].1);
            let mut normal = hit.normal.normalize();
            if normal.dot(near - p) < 0.0 {
                normal = -normal;
            }
            let (to_light, max_distance, in_light) = match light {
                Light::Directional(d) => (-d.direction(), 4.0 * diagonal + 1e6, true),
                Light::Spot(s) => {
                    let d = s.position() - p;
                    let along = (-d).dot(s.direction());
                    let inside = along >= s.near()
                        && along <= s.range()
                        && (-d).normalize().dot(s.direction()) >= s.half_angle().cos();
                    (d.normalize(), d.length(), inside)
                }
                Light::Point(l) => {
                    let d = l.position() - p;
                    let inside = d.length() >= l.near() && d.length() <= l.range();
                    (d.normalize(), d.length(), inside)
                }
            };
            let ndl = normal.dot(to_light);
            n_dot_l[i] = ndl;
            reached[i] = in_light;
            if ndl <= 0.0 || !in_light {
                mask[i] = MASK_UNLIT;
                continue;
            }
            let origin = p + normal * 1e-5 * diagonal;
            let blocked = holes
                .first_hit(&casters, origin, to_light, max_distance, |s| {
                    caster_triangles[s as usize]
                })
                .is_some();
            mask[i] = if blocked { MASK_UNLIT } else { MASK_LIT };
        }
    }
    OracleMask {
        width,
        height,
        mask,
        n_dot_l,
        points,
        objects,
        in_light: reached,
    }
}

/// The holes of a scene's alpha-masked meshes ([`gnomon_scene::Cutout`]), per triangle of
/// [`RenderScene::world_triangles`]: rays pass through a triangle where its mesh's alpha, at
/// the texture coordinates interpolated to the hit, is below the cutoff.
pub struct Holes<'a> {
    scene: &'a RenderScene,
    /// [`RenderScene::world_triangles`].
    pub triangles: Vec<([DVec3; 3], usize)>,
}

impl<'a> Holes<'a> {
    pub fn new(scene: &'a RenderScene) -> Self {
        Self {
            scene,
            triangles: scene.world_triangles(),
        }
    }

    /// Whether triangle `g` has a hole at `p` (a point on it).
    pub fn hole(&self, g: usize, p: DVec3) -> bool {
        let (corners, k) = self.triangles[g];
        let mesh = &self.scene.meshes[self.scene.instances[k].mesh];
        let Some(cutout) = mesh.holes() else {
            return false;
        };
        // The triangle's place in its mesh: instances' triangles follow each other.
        let instance_start = self.triangles.partition_point(|t| t.1 < k);
        let first = 3 * (g - instance_start);
        // Barycentric coordinates of p.
        let [a, b, c] = corners;
        let (e1, e2, d) = (b - a, c - a, p - a);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (d.dot(e1), d.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let v = (d22 * d1 - d12 * d2) / det;
        let w = (d11 * d2 - d12 * d1) / det;
        let uv = |k: usize| mesh.uvs[mesh.indices[first + k] as usize];
        !cutout.solid_at(uv(0) * (1.0 - v - w) + uv(1) * v + uv(2) * w)
    }

    /// The first hit of the ray `origin + t direction` (t up to `max`) on `mesh` that is not
    /// in a hole, with its time along the ray and its triangle among all (`global` maps
    /// the mesh's triangle to it).
    pub fn first_hit(
        &self,
        mesh: &TriMesh,
        origin: DVec3,
        direction: DVec3,
        max: f64,
        global: impl Fn(u32) -> usize,
    ) -> Option<Hit> {
        let mut start = 0.0;
        // Past a hole: a step of a millionth of the ray's reach.
        let step = 1e-6 * max;
        loop {
            let ray = Ray::new(vector(origin + direction * start), vector(direction));
            let hit = mesh.cast_local_ray_and_get_normal(&ray, max - start, false)?;
            let time = start + hit.time_of_impact;
            let g = global(hit.subshape);
            if !self.hole(g, origin + direction * time) {
                return Some(Hit {
                    time_of_impact: time,
                    subshape: g,
                    normal: dvec(hit.normal),
                });
            }
            start = time + step;
        }
    }
}

/// A ray's first solid hit: its time along the ray, its triangle among all, its normal.
pub struct Hit {
    pub time_of_impact: f64,
    pub subshape: usize,
    pub normal: DVec3,
}

/// Where the light meets the scene's casters, per pixel of an oracle's mask (the object-ID
/// oracle): which casting instance the light reaches first on its ray through the pixel's
/// point, and whether that changes within a few texels of a map around the point, across the
/// light's rays (the point lies near an outline of what the light sees, where an object-ID
/// map aliases).
pub struct LightFirst {
    /// The casting instance the light's ray through the point meets first (at the point
    /// itself where nothing is nearer the light and its object casts; `None` where nothing
    /// casts on the ray or the pixel has no geometry).
    pub objects: Vec<Option<usize>>,
    /// Whether a ray of the light through a point within the radius around the pixel's
    /// point (across the rays) meets another first.
    pub near_outline: Vec<bool>,
}

/// [`LightFirst`] of `oracle`'s pixels, the outlines within `radius_texels` of `map`'s
/// texels (their largest side at the point, across the light's rays).
pub fn light_first(
    scene: &RenderScene,
    light: &Light,
    oracle: &OracleMask,
    map: &gnomon::ShadowMap,
    radius_texels: f64,
) -> LightFirst {
    let triangles = scene.world_triangles();
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut owners = Vec::new();
    for (t, k) in &triangles {
        if scene.instances[*k].casts {
            let base = vertices.len() as u32;
            vertices.extend(t.iter().map(|p| vector(*p)));
            indices.push([base, base + 1, base + 2]);
            owners.push(*k);
        }
    }
    let casters = TriMesh::new(vertices, indices).expect("caster mesh");
    let far = 4.0 * scene.bounds().expect("bounds").scene_box().diagonal() + 1.0;
    // The direction of the light's ray through q, and the first caster on it (through q
    // and beyond).
    let along = |q: DVec3| match light {
        Light::Directional(d) => d.direction(),
        Light::Spot(s) => (q - s.position()).normalize(),
        Light::Point(l) => (q - l.position()).normalize(),
    };
    let first = |q: DVec3| {
        let origin = match light {
            Light::Directional(d) => q - d.direction() * far,
            Light::Spot(s) => s.position(),
            Light::Point(l) => l.position(),
        };
        let ray = Ray::new(vector(origin), vector(along(q)));
        casters
            .cast_local_ray_and_get_normal(&ray, f64::MAX, false)
            .map(|hit| owners[hit.subshape as usize])
    };
    let ndc = |q: DVec3| {
        let c = map.clip_from_world * q.extend(1.0);
        glam::DVec2::new(c.x, c.y) / c.w
    };
    let mut objects = vec![None; oracle.points.len()];
    let mut near_outline = vec![false; oracle.points.len()];
    for (i, p) in oracle.points.iter().enumerate() {
        let Some(p) = *p else { continue };
        let centre = first(p);
        objects[i] = centre;
        let a = along(p);
        let u = a.any_orthonormal_vector();
        let v = a.cross(u);
        // The map's texel across the rays at p, its larger side (2 / resolution in ndc).
        let step = 1e-5 * (1.0 + p.abs().max_element());
        let rate = |d: DVec3| ((ndc(p + step * d) - ndc(p)) / step).length();
        let texel = 2.0 / map.resolution as f64 / rate(u).min(rate(v)).max(1e-300);
        let r = radius_texels * texel;
        near_outline[i] = (0..8).any(|k| {
            let angle = k as f64 * std::f64::consts::FRAC_PI_4;
            first(p + r * (angle.cos() * u + angle.sin() * v)) != centre
        });
    }
    LightFirst {
        objects,
        near_outline,
    }
}

/// How a rendered mask compares with the oracle.
#[derive(Debug, Clone, Copy)]
pub struct Agreement {
    /// Pixels compared: N.L > 0.1 (or all with geometry when the threshold is None), away
    /// from lit/shadow and geometry boundaries.
    pub compared: usize,
    /// Of those, how many agree.
    pub agreeing: usize,
    /// Oracle pixels compared that are in shadow (so that a test is not all lit).
    pub shadowed: usize,
    /// Of those, how many the mask has in shadow too.
    pub shadowed_agreeing: usize,
}

impl Agreement {
    pub fn fraction(&self) -> f64 {
        self.agreeing as f64 / self.compared.max(1) as f64
    }

    /// The share of the oracle's shadowed pixels that the mask has in shadow.
    pub fn shadow_recall(&self) -> f64 {
        self.shadowed_agreeing as f64 / self.shadowed.max(1) as f64
    }
}

/// Compares on the pixels with N.L > `min_n_dot_l` whose 3x3 oracle neighbourhood has one
/// value (not next to a lit/shadow or geometry boundary).
pub fn agreement(frame: &Frame, oracle: &OracleMask, min_n_dot_l: f64) -> Agreement {
    assert_eq!((frame.width, frame.height), (oracle.width, oracle.height));
    mask_agreement(&frame.mask, oracle, min_n_dot_l)
}

/// [`agreement`] for a mask of the oracle's size.
pub fn mask_agreement(mask: &[u8], oracle: &OracleMask, min_n_dot_l: f64) -> Agreement {
    assert_eq!(mask.len(), oracle.mask.len());
    let (w, h) = (oracle.width as i64, oracle.height as i64);
    let mut result = Agreement {
        compared: 0,
        agreeing: 0,
        shadowed: 0,
        shadowed_agreeing: 0,
    };
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = (y * w + x) as usize;
            let value = oracle.mask[i];
            if value == MASK_EMPTY || oracle.n_dot_l[i] <= min_n_dot_l {
                continue;
            }
            let uniform = (-1..=1).all(|dy| {
                (-1..=1).all(|dx| oracle.mask[((y + dy) * w + x + dx) as usize] == value)
            });
            if !uniform {
                continue;
            }
            result.compared += 1;
            result.shadowed += usize::from(value == MASK_UNLIT);
            result.agreeing += usize::from(mask[i] == value);
            result.shadowed_agreeing += usize::from(value == MASK_UNLIT && mask[i] == value);
        }
    }
    result
}

/// Computes the setup and renders the frame.
pub fn render(
    renderer: &mut Renderer,
    scene: &RenderScene,
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    resolution: u32,
    settings: &RenderSettings,
) -> (ShadowSetup, Frame) {
    let bounds = scene.bounds().unwrap();
    let setup = compute_setup(
        technique,
        camera,
        light,
        &bounds,
        MapSettings::with_resolution(resolution),
    )
    .unwrap();
    let frame = renderer.render(camera, light, &setup, settings).unwrap();
    (setup, frame)
}

/// A cuboid mesh of half extents `half`.
pub fn cuboid(half: DVec3) -> gnomon_scene::Mesh {
    gnomon_scene::Shape::Cuboid { half_extents: half }.mesh()
}

/// An instance of mesh `mesh` placed at `at` (receives shadows; casts as `casts` says).
pub fn placed(name: &str, mesh: usize, at: DVec3, casts: bool) -> gnomon_render::Instance {
    gnomon_render::Instance {
        name: name.into(),
        mesh,
        world_from_object: glam::DMat4::from_translation(at),
        casts,
        receives: true,
        color: [0.6, 0.6, 0.6],
    }
}

/// A square ground slab (half size `ground_half`, top at y = 0; receives, does not cast) and
/// one box named `name` with half extents `half` standing on it with its base centred at
/// `base` (casts and receives).
pub fn box_on_ground(ground_half: f64, name: &str, half: DVec3, base: DVec3) -> RenderScene {
    RenderScene {
        meshes: vec![
            cuboid(DVec3::new(ground_half, 0.5, ground_half)),
            cuboid(half),
        ],
        instances: vec![
            placed("ground", 0, DVec3::new(0.0, -0.5, 0.0), false),
            placed(name, 1, base + DVec3::Y * half.y, true),
        ],
    }
}

/// Whether pixel `i`'s 3x3 neighbourhood in the oracle has one value and sees surfaces at
/// height `y` (the interior of a region of one surface, away from shadow and geometry
/// edges).
pub fn interior_at_height(o: &OracleMask, i: usize, y: f64) -> bool {
    let (w, h) = (o.width as usize, o.height as usize);
    let (px, py) = (i % w, i / w);
    if px == 0 || py == 0 || px + 1 >= w || py + 1 >= h {
        return false;
    }
    let value = o.mask[i];
    (0..3).all(|dy| {
        (0..3).all(|dx| {
            let j = (py + dy - 1) * w + px + dx - 1;
            o.mask[j] == value && o.points[j].is_some_and(|p| (p.y - y).abs() < 1e-6)
        })
    })
}
