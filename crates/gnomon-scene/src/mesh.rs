//! Triangle meshes for the layouts' shapes: positions, normals and indices, counter-clockwise
//! seen from outside. Every mesh is closed.

use std::f64::consts::{PI, TAU};

use std::sync::Arc;

use glam::{DMat4, DVec2, DVec3};

use crate::{SceneLayout, Shape};

/// A triangle mesh in object space.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Unit vertex normals (for shading).
    pub normals: Vec<DVec3>,
    /// Triangles, three indices each, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// Texture coordinates, one per vertex where the mesh has a [`Cutout`] (else empty).
    pub uvs: Vec<DVec2>,
    /// Where its surface has holes: an alpha-masked material's alpha (glTF's `MASK` mode).
    pub cutout: Option<Arc<Cutout>>,
}

/// An alpha-masked material's holes (glTF's `MASK` alpha mode): where its alpha, read at a
/// point's texture coordinates (bilinear, wrapping as the sampler says), is below `cutoff`,
/// the surface is not there: it casts no shadow (the depth pass discards it) and the camera
/// sees through it. Shadow volumes and planar shadows draw the surface whole.
#[derive(Debug, Clone, PartialEq)]
pub struct Cutout {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Alpha per texel (0 to 255, the material's alpha factor applied), row by row from
    /// texture coordinate v = 0.
    pub alpha: Vec<u8>,
    /// Alpha below this (0 to 1) is a hole.
    pub cutoff: f32,
    /// How u and v continue outside 0 to 1.
    pub wrap: [Wrap; 2],
}

/// How a texture coordinate continues outside 0 to 1 (glTF's sampler wrap modes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// The texture repeats (glTF's default).
    #[default]
    Repeat,
    /// The texture repeats, every other copy mirrored.
    MirroredRepeat,
    /// The edge texel continues.
    ClampToEdge,
}

impl Cutout {
    /// Whether any texel is a hole (a cutout without one cuts nothing).
    pub fn has_holes(&self) -> bool {
        let cut = self.cutoff * 255.0;
        self.alpha.iter().any(|&a| f32::from(a) < cut)
    }

    /// The alpha (0 to 1) at texture coordinates `uv`, bilinear between texel centres with
    /// the wrap modes, as the GPU's sampler reads it.
    pub fn alpha_at(&self, uv: DVec2) -> f64 {
        let texel = |i: i64, j: i64| {
            let wrap = |k: i64, n: u32, mode: Wrap| -> usize {
                let n = i64::from(n);
                (match mode {
                    Wrap::Repeat => k.rem_euclid(n),
                    Wrap::ClampToEdge => k.clamp(0, n - 1),
                    Wrap::MirroredRepeat => {
                        let m = k.rem_euclid(2 * n);
                        if m < n { m } else { 2 * n - 1 - m }
                    }
                }) as usize
            };
            let (x, y) = (
                wrap(i, self.width, self.wrap[0]),
                wrap(j, self.height, self.wrap[1]),
            );
            f64::from(self.alpha[y * self.width as usize + x]) / 255.0
        };
        let (x, y) = (
            uv.x * f64::from(self.width) - 0.5,
            uv.y * f64::from(self.height) - 0.5,
        );
        let (i, j) = (x.floor(), y.floor());
        let (fx, fy) = (x - i, y - j);
        let (i, j) = (i as i64, j as i64);
        let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
        let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// Whether the surface is there at `uv` (its alpha at least the cutoff).
    pub fn solid_at(&self, uv: DVec2) -> bool {
        self.alpha_at(uv) >= f64::from(self.cutoff)
    }
}

impl Mesh {
    fn vertex(&mut self, p: DVec3, n: DVec3) -> u32 {
        self.positions.push(p);
        self.normals.push(n.normalize_or_zero());
        (self.positions.len() - 1) as u32
    }

    fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.indices.extend_from_slice(&[a, b, c]);
    }

    fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.triangle(a, b, c);
        self.triangle(a, c, d);
    }

    /// The mesh moved by `placement`: positions transformed, normals by its inverse
    /// transpose; a mirroring placement (negative determinant) rewinds the triangles, so
    /// that they stay counter-clockwise from outside.
    pub fn transformed(&self, placement: DMat4) -> Mesh {
        let normal_from_object = glam::DMat3::from_mat4(placement).inverse().transpose();
        let mut indices = self.indices.clone();
        if placement.determinant() < 0.0 {
            for t in indices.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        Mesh {
            positions: self
                .positions
                .iter()
                .map(|p| placement.transform_point3(*p))
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|n| (normal_from_object * *n).normalize_or_zero())
                .collect(),
            indices,
            uvs: self.uvs.clone(),
            cutout: self.cutout.clone(),
        }
    }

    /// Its holes: the cutout, where every vertex has texture coordinates to read it at.
    pub fn holes(&self) -> Option<&Cutout> {
        self.cutout
            .as_deref()
            .filter(|_| self.uvs.len() == self.positions.len())
    }

    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The mesh's connected parts: triangles that share a vertex position (vertices split at
    /// creases count as one) belong to one part. Each part keeps its vertices, normals,
    /// texture coordinates, cutout and winding, in the order of its first triangle; parts are in the order of their first
    /// triangles.
    pub fn components(&self) -> Vec<Mesh> {
        // One id per distinct position, then union-find over the triangles' positions.
        let mut id_of = std::collections::HashMap::with_capacity(self.positions.len());
        let position_id: Vec<usize> = self
            .positions
            .iter()
            .map(|p| {
                let key = p.to_array().map(f64::to_bits);
                let next = id_of.len();
                *id_of.entry(key).or_insert(next)
            })
            .collect();
        let mut parent: Vec<usize> = (0..id_of.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for t in self.indices.chunks_exact(3) {
            let a = root(&mut parent, position_id[t[0] as usize]);
            for &v in &t[1..] {
                let b = root(&mut parent, position_id[v as usize]);
                parent[b] = a;
            }
        }
        let mut part_of_root: std::collections::HashMap<usize, usize> = Default::default();
        let mut parts: Vec<Mesh> = Vec::new();
        let mut remap: Vec<(usize, u32)> = vec![(usize::MAX, 0); self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let r = root(&mut parent, position_id[t[0] as usize]);
            let next = parts.len();
            let part = *part_of_root.entry(r).or_insert(next);
            if part == parts.len() {
                parts.push(Mesh {
                    cutout: self.cutout.clone(),
                    ..Mesh::default()
                });
            }
            let mesh = &mut parts[part];
            for &v in t {
                let v = v as usize;
                if remap[v].0 != part {
                    mesh.positions.push(self.positions[v]);
                    mesh.normals.push(self.normals[v]);
                    if let Some(uv) = self.uvs.get(v) {
                        mesh.uvs.push(*uv);
                    }
                    remap[v] = (part, (mesh.positions.len() - 1) as u32);
                }
                mesh.indices.push(remap[v].1);
            }
        }
        parts
    }

    /// A grid of `rows x cols` quads from a parametric surface, wrapping in both directions
    /// when asked (the seam shares vertices, so the mesh stays closed).
    fn parametric(
        &mut self,
        rows: u32,
        cols: u32,
        wrap_rows: bool,
        surface: impl Fn(f64, f64) -> (DVec3, DVec3),
    ) {
        let base = self.positions.len() as u32;
        let row_count = if wrap_rows { rows } else { rows + 1 };
        for i in 0..row_count {
            for j in 0..cols {
                let (p, n) = surface(i as f64 / rows as f64, j as f64 / cols as f64);
                self.vertex(p, n);
            }
        }
        let index = |i: u32, j: u32| base + (i % row_count) * cols + (j % cols);
        let first_index = self.indices.len();
        for i in 0..rows {
            for j in 0..cols {
                self.quad(
                    index(i, j),
                    index(i, j + 1),
                    index(i + 1, j + 1),
                    index(i + 1, j),
                );
            }
        }
        // Wind outward whatever the parametrisation's orientation: the signed volume of a
        // closed surface is positive when its triangles face out.
        let volume: f64 = self.indices[first_index..]
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| self.positions[i as usize]);
                a.dot(b.cross(c))
            })
            .sum();
        if volume < 0.0 {
            for t in self.indices[first_index..].chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
    }
}

/// Tessellation of curved shapes: segments around a full turn.
const SEGMENTS: u32 = 24;

impl Shape {
    /// The shape's triangle mesh in object space.
    pub fn mesh(&self) -> Mesh {
        let mut m = Mesh::default();
        match *self {
            Shape::Cuboid { half_extents } => cuboid(&mut m, half_extents),
            Shape::Sphere { radius } => sphere(&mut m, radius),
            Shape::Torus {
                major_radius,
                minor_radius,
            } => {
                m.parametric(SEGMENTS * 2, SEGMENTS / 2, true, |u, v| {
                    let (phi, theta) = (TAU * u, TAU * v);
                    let ring = DVec3::new(phi.cos(), 0.0, -phi.sin());
                    let n = ring * theta.cos() + DVec3::Y * theta.sin();
                    (ring * major_radius + n * minor_radius, n)
                });
            }
            Shape::TorusKnot {
                p,
                q,
                major_radius,
                minor_radius,
                tube_radius,
            } => torus_knot(&mut m, (p, q), (major_radius, minor_radius), tube_radius),
            Shape::Pole { radius, height } => pole(&mut m, radius, height),
        }
        m
    }
}

/// A box of half extents `h`: four vertices per face so that each face has its own normal.
fn cuboid(m: &mut Mesh, h: DVec3) {
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = DVec3::ZERO;
            n[axis] = sign;
            let u = DVec3::from_array(std::array::from_fn(|k| {
                if k == (axis + 1) % 3 { 1.0 } else { 0.0 }
            }));
            let v = n.cross(u);
            let c = n * h;
            let (hu, hv) = (u * h, v * h);
            let a = m.vertex(c - hu - hv, n);
            let b = m.vertex(c + hu - hv, n);
            let cc = m.vertex(c + hu + hv, n);
            let d = m.vertex(c - hu + hv, n);
            m.quad(a, b, cc, d);
        }
    }
}

/// Latitude rings between the poles; the poles are single vertices.
fn sphere(m: &mut Mesh, radius: f64) {
    let rings = SEGMENTS / 2;
    let top = m.vertex(DVec3::Y * radius, DVec3::Y);
    let bottom = m.vertex(-DVec3::Y * radius, -DVec3::Y);
    let first = m.positions.len() as u32;
    for i in 1..rings {
        let theta = PI * i as f64 / rings as f64;
        for j in 0..SEGMENTS {
            let phi = TAU * j as f64 / SEGMENTS as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            m.vertex(n * radius, n);
        }
    }
    let at = |i: u32, j: u32| first + (i - 1) * SEGMENTS + j % SEGMENTS;
    for j in 0..SEGMENTS {
        m.triangle(top, at(1, j), at(1, j + 1));
        m.triangle(bottom, at(rings - 1, j + 1), at(rings - 1, j));
    }
    for i in 1..rings - 1 {
        for j in 0..SEGMENTS {
            m.quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
}

/// A (p, q) torus knot's tube.
fn torus_knot(
    m: &mut Mesh,
    (p, q): (u32, u32),
    (major_radius, minor_radius): (f64, f64),
    tube_radius: f64,
) {
    let curve = |t: f64| {
        let r = major_radius + minor_radius * (q as f64 * t).cos();
        DVec3::new(
            r * (p as f64 * t).cos(),
            minor_radius * (q as f64 * t).sin(),
            -r * (p as f64 * t).sin(),
        )
    };
    let steps = SEGMENTS * 8;
    m.parametric(steps, SEGMENTS / 2, true, |u, v| {
        let t = TAU * u;
        let dt = 1e-4;
        let c = curve(t);
        let tangent = (curve(t + dt) - curve(t - dt)).normalize();
        // A frame around the tangent from the direction away from the axis.
        let outward = DVec3::new(c.x, 0.0, c.z).normalize();
        let normal = (outward - tangent * tangent.dot(outward)).normalize();
        let binormal = tangent.cross(normal);
        let theta = TAU * v;
        let n = normal * theta.cos() + binormal * theta.sin();
        (c + n * tube_radius, n)
    });
}

/// A capped cylinder standing on the origin.
fn pole(m: &mut Mesh, radius: f64, height: f64) {
    let bottom_center = m.vertex(DVec3::ZERO, -DVec3::Y);
    let top_center = m.vertex(DVec3::Y * height, DVec3::Y);
    let n_sides = SEGMENTS / 2;
    let mut ring = Vec::new();
    for j in 0..n_sides {
        let phi = TAU * j as f64 / n_sides as f64;
        let dir = DVec3::new(phi.cos(), 0.0, -phi.sin());
        ring.push([
            m.vertex(dir * radius, dir),
            m.vertex(dir * radius + DVec3::Y * height, dir),
            m.vertex(dir * radius, -DVec3::Y),
            m.vertex(dir * radius + DVec3::Y * height, DVec3::Y),
        ]);
    }
    for j in 0..n_sides as usize {
        let (a, b) = (ring[j], ring[(j + 1) % n_sides as usize]);
        m.quad(a[0], b[0], b[1], a[1]);
        m.triangle(top_center, a[3], b[3]);
        m.triangle(bottom_center, b[2], a[2]);
    }
}

impl SceneLayout {
    /// Every triangle of the scene in world space, with the index of its object.
    pub fn world_triangles(&self) -> Vec<([DVec3; 3], usize)> {
        let mut out = Vec::new();
        for (k, object) in self.objects.iter().enumerate() {
            let mesh = object.shape.mesh();
            let m: DMat4 = object.world_from_object;
            for t in mesh.indices.chunks_exact(3) {
                let p = |i: u32| m.transform_point3(mesh.positions[i as usize]);
                out.push(([p(t[0]), p(t[1]), p(t[2])], k));
            }
        }
        out
    }

    /// The scene as a Wavefront OBJ text (world-space triangles, one group per object).
    pub fn to_obj(&self) -> String {
        let meshes: Vec<Mesh> = self.objects.iter().map(|o| o.shape.mesh()).collect();
        obj_text(
            &self.name,
            self.objects
                .iter()
                .zip(&meshes)
                .map(|(o, m)| (o.name.as_str(), m, o.world_from_object)),
        )
    }
}

/// Placed meshes as a Wavefront OBJ text: world-space triangles, one object (`o`) per part,
/// under a comment naming the scene. A part whose transform mirrors (negative determinant)
/// is rewound, so that every face stays outward.
pub fn obj_text<'a>(
    scene: &str,
    parts: impl IntoIterator<Item = (&'a str, &'a Mesh, DMat4)>,
) -> String {
    use std::fmt::Write;
    let mut s = format!("# gnomon scene '{scene}': world-space triangles\n");
    let mut base = 1;
    for (name, mesh, world_from_object) in parts {
        let _ = writeln!(s, "o {name}");
        for p in &mesh.positions {
            let w = world_from_object.transform_point3(*p);
            let _ = writeln!(s, "v {} {} {}", w.x, w.y, w.z);
        }
        let mirrored = world_from_object.determinant() < 0.0;
        for t in mesh.indices.chunks_exact(3) {
            let (b, c) = if mirrored { (t[2], t[1]) } else { (t[1], t[2]) };
            let _ = writeln!(s, "f {} {} {}", base + t[0], base + b, base + c);
        }
        base += mesh.positions.len() as u32;
    }
    s
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;

    /// Closed and consistently wound: every edge (by position) is used once in each
    /// direction; and outward: the signed volume is positive.
    fn assert_closed_outward(shape: Shape) {
        let m = shape.mesh();
        let key = |i: u32| {
            let p = m.positions[i as usize];
            (
                (p.x * 1e6).round() as i64,
                (p.y * 1e6).round() as i64,
                (p.z * 1e6).round() as i64,
            )
        };
        let mut edges: HashMap<_, i32> = HashMap::new();
        let mut volume = 0.0;
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
                *edges.entry((a, b)).or_default() += 1;
                *edges.entry((b, a)).or_default() -= 1;
            }
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
            volume += a.dot(b.cross(c)) / 6.0;
        }
        assert!(
            edges.values().all(|&v| v == 0),
            "{shape:?} is not closed and consistently wound"
        );
        assert!(volume > 0.0, "{shape:?} winds inward (volume {volume})");
        let (lo, hi) = shape.local_bounds();
        for p in &m.positions {
            assert!(
                p.cmpge(lo - 1e-9).all() && p.cmple(hi + 1e-9).all(),
                "{shape:?}: {p} outside its bounds"
            );
        }
    }

    #[test]
    fn every_shape_is_closed_outward_and_inside_its_bounds() {
        assert_closed_outward(Shape::Cuboid {
            half_extents: DVec3::new(1.0, 2.0, 3.0),
        });
        assert_closed_outward(Shape::Sphere { radius: 2.0 });
        assert_closed_outward(Shape::Torus {
            major_radius: 3.0,
            minor_radius: 1.0,
        });
        assert_closed_outward(Shape::TorusKnot {
            p: 2,
            q: 3,
            major_radius: 6.0,
            minor_radius: 3.0,
            tube_radius: 1.2,
        });
        assert_closed_outward(Shape::Pole {
            radius: 0.2,
            height: 8.0,
        });
    }

    #[test]
    fn components_are_the_parts_that_share_no_vertex() {
        let cube = Shape::Cuboid {
            half_extents: DVec3::ONE,
        }
        .mesh();
        let ball = Shape::Sphere { radius: 1.0 }.mesh();
        // Two cubes (each face its own vertices in the shape's mesh: welded by position) and a
        // ball, in one mesh.
        let mut both = Mesh::default();
        for (mesh, offset) in [(&cube, 0.0), (&ball, 5.0), (&cube, 10.0)] {
            let base = both.positions.len() as u32;
            both.positions
                .extend(mesh.positions.iter().map(|p| *p + DVec3::X * offset));
            both.normals.extend(&mesh.normals);
            both.indices.extend(mesh.indices.iter().map(|i| i + base));
        }
        let parts = both.components();
        assert_eq!(parts.len(), 3);
        assert_eq!(parts[0].triangle_count(), cube.triangle_count());
        assert_eq!(parts[1].triangle_count(), ball.triangle_count());
        assert_eq!(parts[1].positions.len(), ball.positions.len());
        assert!((parts[2].bounds().0 - DVec3::new(9.0, -1.0, -1.0)).length() < 1e-12);
        assert_eq!(parts[0].components().len(), 1);
    }

    #[test]
    fn obj_export_has_every_triangle() {
        let scene = crate::demo();
        let obj = scene.to_obj();
        let faces = obj.lines().filter(|l| l.starts_with("f ")).count();
        assert_eq!(faces, scene.world_triangles().len());
    }
}
