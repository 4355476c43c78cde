//! Loading triangle meshes from files: OFF (through `off-rs`), Wavefront OBJ (`tobj`), PLY,
//! ASCII or binary (`ply-rs-bw`), glTF 2.0, `.gltf` with its buffers or `.glb` (`gltf`), and
//! STL, ASCII or binary (`stl_io`), and Terragen heightfields (`.ter`, [`crate::terragen`]).
//! Polygons are split into fans of triangles; vertex normals are the angle-weighted average
//! of the triangles around each vertex that meet it at less than a crease angle (files' own
//! normals are not read).
//!
//! glTF: the default scene (else the first, else every root node) is flattened into one mesh
//! in its world frame: each node's transform composed down the hierarchy, every triangle
//! primitive of every mesh a node instances, the winding flipped under a mirroring transform
//! (negative determinant) so that faces stay counter-clockwise from outside. Primitives of
//! other modes (points, lines, strips and fans) are skipped and named in the load's notes; a
//! file that requires an extension gnomon does not read (`KHR_draco_mesh_compression`, ...)
//! is refused. [`Mesh::load_parts`] keeps one part per material (glTF: its base colour
//! factor; OBJ: its `Kd`); colour textures are not read, but an alpha-masked glTF material's
//! texture gives its part's holes ([`crate::Cutout`], with the texture coordinates).

use std::path::{Path, PathBuf};

use std::sync::Arc;

use glam::{DMat4, DVec2, DVec3};

use crate::Mesh;
use crate::format::{LoadError, MAX_MESH_BYTES, MeshFormat, Polygons, RawPart};
use crate::mesh::Cutout;

/// One part of a mesh file: the triangles of one material (OBJ), of one material of one
/// glTF mesh, or the whole file; placed once or more in the file's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPart {
    /// The material's name (empty for a file without materials).
    pub name: String,
    /// Its triangles, in its own frame (a glTF mesh's).
    pub mesh: Mesh,
    /// The material's colour (linear RGB), where the file gives one.
    pub color: Option<[f32; 3]>,
    /// Where the file places it: file from part, one per instance (a glTF mesh that several
    /// nodes use is read once and placed at each; a mirroring placement has a negative
    /// determinant). The identity alone for the other formats.
    pub placements: Vec<DMat4>,
}

impl MeshPart {
    /// A whole mesh as one part, placed once where it is.
    pub fn whole(mesh: Mesh) -> Self {
        Self {
            name: String::new(),
            mesh,
            color: None,
            placements: vec![DMat4::IDENTITY],
        }
    }

    /// The part's triangles at every placement, in the file's frame (mirrored placements
    /// rewound, so that triangles stay counter-clockwise from outside).
    pub fn flattened(&self) -> Mesh {
        if self.placements == [DMat4::IDENTITY] {
            return self.mesh.clone();
        }
        let placed: Vec<Mesh> = self
            .placements
            .iter()
            .map(|m| self.mesh.transformed(*m))
            .collect();
        Mesh::merged(&placed)
    }
}

/// A mesh file's bytes (a regular file, at most [`MAX_MESH_BYTES`]), its format and folder.
fn read_mesh_file(path: &Path) -> Result<(Vec<u8>, MeshFormat, Option<&Path>), LoadError> {
    let format = MeshFormat::from_path(path).ok_or_else(|| LoadError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let io = |source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    };
    // A regular file, read up to the limit (a link to /dev/zero reports size 0 and never
    // ends; a size check alone would pass it).
    if !std::fs::metadata(path).map_err(io)?.is_file() {
        return Err(LoadError::NotAFile {
            path: path.to_path_buf(),
        });
    }
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(std::fs::File::open(path).map_err(io)?, MAX_MESH_BYTES + 1),
        &mut bytes,
    )
    .map_err(io)?;
    if bytes.len() as u64 > MAX_MESH_BYTES {
        return Err(LoadError::TooLarge {
            path: path.to_path_buf(),
        });
    }
    let base = path.parent().filter(|p| !p.as_os_str().is_empty());
    Ok((bytes, format, base))
}

impl Mesh {
    /// Loads a mesh file, its format chosen by the extension (see [`MeshFormat`]).
    pub fn load(path: &Path) -> Result<Mesh, LoadError> {
        Self::load_with_notes(path).map(|(mesh, _)| mesh)
    }

    /// [`Mesh::load`], and what the load left out (a glTF's primitives that are not
    /// triangles), one line each, for the caller to show as warnings.
    pub fn load_with_notes(path: &Path) -> Result<(Mesh, Vec<String>), LoadError> {
        let (bytes, format, base) = read_mesh_file(path)?;
        Self::parse_in(&bytes, format, Some(base.unwrap_or(Path::new(".")))).map_err(|e| e.at(path))
    }

    /// Parses a mesh from a file's contents (a glTF's buffers must be inside it: a `.glb`
    /// or data URIs).
    pub fn parse(bytes: &[u8], format: MeshFormat) -> Result<Mesh, LoadError> {
        Self::parse_in(bytes, format, None).map(|(mesh, _)| mesh)
    }

    /// [`Mesh::parse`] with the folder a glTF's buffer files (and an OBJ's material
    /// libraries) are relative to, and the notes: the file's parts, merged.
    fn parse_in(
        bytes: &[u8],
        format: MeshFormat,
        base: Option<&Path>,
    ) -> Result<(Mesh, Vec<String>), LoadError> {
        let (parts, notes) = Self::parse_parts(bytes, format, base)?;
        let meshes: Vec<Mesh> = parts.iter().map(MeshPart::flattened).collect();
        Ok((Mesh::merged(&meshes), notes))
    }

    /// A file's contents as its parts (see [`Mesh::load_parts`]).
    // Only the OBJ and glTF readers take the folder and the notes.
    #[cfg_attr(
        not(any(feature = "obj", feature = "gltf")),
        allow(unused_mut, unused_variables)
    )]
    pub(crate) fn parse_parts(
        bytes: &[u8],
        format: MeshFormat,
        base: Option<&Path>,
    ) -> Result<(Vec<MeshPart>, Vec<String>), LoadError> {
        let parse_error = |message: String| LoadError::Parse {
            path: PathBuf::new(),
            format,
            message,
        };
        let mut notes = Vec::new();
        let one = |polygons: Polygons| vec![RawPart::whole(polygons)];
        let raw = match format {
            #[cfg(feature = "off")]
            MeshFormat::Off => one(crate::readers::parse_off(bytes).map_err(parse_error)?),
            #[cfg(feature = "obj")]
            MeshFormat::Obj => {
                crate::readers::parse_obj(bytes, base, &mut notes).map_err(parse_error)?
            }
            #[cfg(feature = "ply")]
            MeshFormat::Ply => one(crate::readers::parse_ply(bytes).map_err(parse_error)?),
            #[cfg(feature = "gltf")]
            MeshFormat::Gltf => crate::gltf::parts(bytes, base, &mut notes)?,
            #[cfg(feature = "stl")]
            MeshFormat::Stl => one(crate::readers::parse_stl(bytes).map_err(parse_error)?),
            MeshFormat::Ter => one(crate::terragen::parse_ter(bytes).map_err(parse_error)?),
            // The formats whose features this build leaves out.
            #[allow(unreachable_patterns)]
            _ => {
                return Err(LoadError::LeftOut {
                    path: PathBuf::new(),
                    format,
                });
            }
        };
        let mut parts = Vec::new();
        for part in raw {
            match Self::from_polygons_with(part.positions, &part.polygons, part.uvs, part.cutout) {
                Ok(mesh) => parts.push(MeshPart {
                    name: part.name,
                    mesh,
                    color: part.color,
                    placements: part.placements,
                }),
                // A part without triangles (an OBJ group of points) is left out; a file
                // without any is refused below.
                Err(LoadError::NoTriangles { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        if parts.is_empty() {
            return Err(LoadError::NoTriangles {
                path: PathBuf::new(),
            });
        }
        Ok((parts, notes))
    }

    /// One mesh of several: their vertices and triangles one after another.
    ///
    /// The merged mesh keeps a cutout (and the texture coordinates) only where every mesh
    /// has the same one; otherwise it is drawn whole.
    pub fn merged(meshes: &[Mesh]) -> Mesh {
        let cutout = meshes.first().and_then(|m| m.cutout.clone());
        let shared = meshes.iter().all(|m| m.cutout == cutout);
        let mut out = Mesh {
            cutout: cutout.filter(|_| shared),
            ..Mesh::default()
        };
        for m in meshes {
            let base = out.positions.len() as u32;
            out.positions.extend_from_slice(&m.positions);
            out.normals.extend_from_slice(&m.normals);
            out.indices.extend(m.indices.iter().map(|i| i + base));
            if out.cutout.is_some() {
                out.uvs.extend_from_slice(&m.uvs);
            }
        }
        out
    }

    /// Loads a mesh file as its parts: one per material of an OBJ (with its `Kd` colour from
    /// the material library beside it) or of a glTF (with its base colour factor), one for
    /// the other formats. [`Mesh::load`] is these parts merged.
    pub fn load_parts(path: &Path) -> Result<(Vec<MeshPart>, Vec<String>), LoadError> {
        let (bytes, format, base) = read_mesh_file(path)?;
        Self::parse_parts(&bytes, format, Some(base.unwrap_or(Path::new("."))))
            .map_err(|e| e.at(path))
    }

    /// A mesh from positions and polygons (vertex indices, counter-clockwise seen from
    /// outside), each polygon split into a fan of triangles; normals smooth across edges
    /// where the faces meet at less than [`CREASE_DEGREES`], and a vertex split where they
    /// meet at more (a box keeps flat faces, a scanned surface stays smooth).
    pub fn from_polygons(positions: Vec<DVec3>, polygons: &[Vec<i64>]) -> Result<Mesh, LoadError> {
        Self::from_polygons_with(positions, polygons, Vec::new(), None)
    }

    /// [`Mesh::from_polygons`] with texture coordinates (one per position) and a cutout
    /// that reads them (both kept only together).
    pub(crate) fn from_polygons_with(
        positions: Vec<DVec3>,
        polygons: &[Vec<i64>],
        uvs: Vec<DVec2>,
        cutout: Option<Arc<Cutout>>,
    ) -> Result<Mesh, LoadError> {
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(LoadError::NonFinite {
                path: PathBuf::new(),
                vertex,
            });
        }
        let mut indices = Vec::new();
        for polygon in polygons {
            for &index in polygon {
                if index < 0 || index as usize >= positions.len() || index > u32::MAX as i64 {
                    return Err(LoadError::IndexOutOfRange {
                        path: PathBuf::new(),
                        index,
                        vertex_count: positions.len(),
                    });
                }
            }
            for k in 1..polygon.len().saturating_sub(1) {
                indices.extend([polygon[0], polygon[k], polygon[k + 1]].map(|i| i as u32));
            }
        }
        if indices.is_empty() {
            return Err(LoadError::NoTriangles {
                path: PathBuf::new(),
            });
        }
        let Creased { mut mesh, origins } = creased(&positions, &indices);
        if let Some(cutout) = cutout.filter(|_| uvs.len() == positions.len()) {
            mesh.uvs = origins.iter().map(|&v| uvs[v as usize]).collect();
            mesh.cutout = Some(cutout);
        }
        Ok(mesh)
    }

    /// The smallest box around the vertices: (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            })
    }
}

/// Faces meeting at an edge at more than this angle (between their normals) keep a crease:
/// their shared vertices are split, each side with its own normal.
pub const CREASE_DEGREES: f64 = 60.0;

/// The mesh of `positions` and triangles `indices` with angle-weighted normals per corner
/// (each triangle's unit normal weighted by its angle at the vertex, so that how a polygon
/// was split does not matter), over the triangles around the vertex whose normal is within
/// [`CREASE_DEGREES`] of the corner's triangle; corners of a vertex with the same normal
/// share one vertex. Unit normals; zero where a vertex touches only degenerate triangles.
fn creased(positions: &[DVec3], indices: &[u32]) -> Creased {
    let cos_crease = CREASE_DEGREES.to_radians().cos();
    let triangles = indices.len() / 3;
    let corner = |t: usize, k: usize| indices[3 * t + k] as usize;
    let face: Vec<DVec3> = (0..triangles)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| positions[corner(t, k)]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let angle = |t: usize, k: usize| {
        let p = positions[corner(t, k)];
        let e1 = positions[corner(t, (k + 1) % 3)] - p;
        let e2 = positions[corner(t, (k + 2) % 3)] - p;
        let a = e1.angle_between(e2);
        if a.is_finite() { a } else { 0.0 }
    };
    // The corners (triangle, k) around each vertex, in one array.
    let mut start = vec![0usize; positions.len() + 1];
    for &i in indices {
        start[i as usize + 1] += 1;
    }
    for v in 0..positions.len() {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut around = vec![(0usize, 0usize); indices.len()];
    for t in 0..triangles {
        for k in 0..3 {
            let v = corner(t, k);
            around[fill[v]] = (t, k);
            fill[v] += 1;
        }
    }
    let mut mesh = Mesh {
        positions: Vec::with_capacity(positions.len()),
        normals: Vec::with_capacity(positions.len()),
        indices: vec![0; indices.len()],
        ..Mesh::default()
    };
    let mut origins = Vec::with_capacity(positions.len());
    for v in 0..positions.len() {
        let corners = &around[start[v]..start[v + 1]];
        let first = mesh.positions.len();
        for &(t, k) in corners {
            let n = corners
                .iter()
                .filter(|&&(u, _)| face[t] == DVec3::ZERO || face[u].dot(face[t]) >= cos_crease)
                .map(|&(u, j)| face[u] * angle(u, j))
                .sum::<DVec3>()
                .normalize_or_zero();
            let index = match mesh.normals[first..].iter().position(|m| *m == n) {
                Some(j) => first + j,
                None => {
                    mesh.positions.push(positions[v]);
                    mesh.normals.push(n);
                    origins.push(v as u32);
                    mesh.normals.len() - 1
                }
            };
            mesh.indices[3 * t + k] = index as u32;
        }
    }
    Creased { mesh, origins }
}

/// A mesh with split vertices and, for each of its vertices, the input vertex it came from.
struct Creased {
    mesh: Mesh,
    origins: Vec<u32>,
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A unit cube as quads, counter-clockwise from outside.
    pub(crate) const CUBE_OFF: &str = "OFF\n# a cube\n8 6 12\n\
        0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
        4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n";

    fn cube_obj() -> String {
        "# a cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n"
            .to_string()
    }

    fn cube_ply_ascii() -> String {
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n\
         property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
         4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n"
            .to_string()
    }

    /// A binary little-endian PLY of the same cube, double coordinates and uint indices.
    fn cube_ply_binary() -> Vec<u8> {
        let mut out = b"ply\nformat binary_little_endian 1.0\nelement vertex 8\n\
            property double x\nproperty double y\nproperty double z\nelement face 6\n\
            property list uchar uint vertex_indices\nend_header\n"
            .to_vec();
        let corners = [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [1, 1, 1],
            [0, 1, 1],
        ];
        for c in corners {
            for x in c {
                out.extend_from_slice(&(x as f64).to_le_bytes());
            }
        }
        let faces = [
            [0u32, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [1, 2, 6, 5],
            [0, 4, 7, 3],
        ];
        for f in faces {
            out.push(4);
            for i in f {
                out.extend_from_slice(&i.to_le_bytes());
            }
        }
        out
    }

    /// The cube as ASCII STL: each quad of [`CUBE_OFF`] as two facets.
    fn cube_stl() -> String {
        let cube = Mesh::parse(CUBE_OFF.as_bytes(), MeshFormat::Off).unwrap();
        let mut out = String::from("solid cube\n");
        for t in cube.indices.chunks_exact(3) {
            out.push_str("facet normal 0 0 0\nouter loop\n");
            for &i in t {
                let p = cube.positions[i as usize];
                out.push_str(&format!("vertex {} {} {}\n", p.x, p.y, p.z));
            }
            out.push_str("endloop\nendfacet\n");
        }
        out + "endsolid cube\n"
    }

    /// A mesh's triangles as text (each corner's position and normal), each triangle started
    /// at its smallest corner, sorted: equal for meshes that differ only in vertex order.
    pub(crate) fn sorted_triangles(m: &Mesh) -> Vec<String> {
        let mut all: Vec<String> = m
            .indices
            .chunks_exact(3)
            .map(|t| {
                let corners: Vec<String> = t
                    .iter()
                    .map(|&i| format!("{} {}", m.positions[i as usize], m.normals[i as usize]))
                    .collect();
                let first = (0..3).min_by_key(|&k| &corners[k]).unwrap();
                (0..3)
                    .map(|k| corners[(first + k) % 3].clone())
                    .collect::<Vec<_>>()
                    .join(" | ")
            })
            .collect();
        all.sort();
        all
    }

    /// Signed volume: 1 for the unit cube wound outward.
    pub(crate) fn volume(m: &Mesh) -> f64 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn every_format_reads_the_same_cube() {
        let meshes = [
            Mesh::parse(CUBE_OFF.as_bytes(), MeshFormat::Off).unwrap(),
            Mesh::parse(cube_obj().as_bytes(), MeshFormat::Obj).unwrap(),
            Mesh::parse(cube_ply_ascii().as_bytes(), MeshFormat::Ply).unwrap(),
            Mesh::parse(&cube_ply_binary(), MeshFormat::Ply).unwrap(),
            Mesh::parse(cube_stl().as_bytes(), MeshFormat::Stl).unwrap(),
        ];
        for m in &meshes {
            // Each corner split in three by the creases: one vertex per face and corner.
            assert_eq!(m.positions.len(), 24);
            assert_eq!(m.triangle_count(), 12);
            assert!((volume(m) - 1.0).abs() < 1e-12, "volume {}", volume(m));
            assert_eq!(m.bounds(), (DVec3::ZERO, DVec3::ONE));
            // Flat faces: every corner's normal is its triangle's.
            for t in m.indices.chunks_exact(3) {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                let face = (b - a).cross(c - a).normalize();
                for &i in t {
                    assert!((m.normals[i as usize] - face).length() < 1e-12);
                }
            }
        }
        // The same triangles with the same normals (the formats order vertices differently).
        for m in &meshes[1..] {
            assert_eq!(sorted_triangles(m), sorted_triangles(&meshes[0]));
        }
    }

    #[test]
    fn obj_materials_make_parts_with_their_colour() {
        let dir = std::env::temp_dir().join(format!("gnomon-obj-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("two.mtl"),
            "newmtl red\nKd 0.8 0.1 0.1\nnewmtl grey\nKd 0.5 0.5 0.5\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("two.obj"),
            "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
             usemtl red\nf 1 2 3\nusemtl grey\nf 4 5 6\nusemtl red\nf 1 3 2\n",
        )
        .unwrap();
        let (parts, notes) = Mesh::load_parts(&dir.join("two.obj")).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["red", "grey"]);
        assert_eq!(parts[0].color, Some([0.8, 0.1, 0.1]));
        assert_eq!(parts[0].mesh.triangle_count(), 2);
        assert_eq!(parts[1].mesh.triangle_count(), 1);
        // Merged, as Mesh::load gives it: every triangle.
        assert_eq!(
            Mesh::load(&dir.join("two.obj")).unwrap().triangle_count(),
            3
        );
        // Without its library: one part per material still, no colours, and a note.
        std::fs::remove_file(dir.join("two.mtl")).unwrap();
        let (parts, notes) = Mesh::load_parts(&dir.join("two.obj")).unwrap();
        assert!(parts.iter().all(|p| p.color.is_none()));
        assert!(notes[0].contains("two.mtl not found"), "{notes:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn normals_are_smooth_below_the_crease_angle() {
        // A ring of 16 quads (22.5 degrees apart): one normal per vertex, pointing outward.
        let n = 16;
        let mut positions = Vec::new();
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            positions.push(DVec3::new(a.cos(), 0.0, -a.sin()));
            positions.push(DVec3::new(a.cos(), 1.0, -a.sin()));
        }
        let quads: Vec<Vec<i64>> = (0..n as i64)
            .map(|k| {
                let j = (k + 1) % n as i64;
                vec![2 * k, 2 * j, 2 * j + 1, 2 * k + 1]
            })
            .collect();
        let m = Mesh::from_polygons(positions, &quads).unwrap();
        assert_eq!(m.positions.len(), 2 * n);
        for (p, normal) in m.positions.iter().zip(&m.normals) {
            let out = DVec3::new(p.x, 0.0, p.z).normalize();
            assert!((*normal - out).length() < 1e-9, "{p}: {normal}");
        }
    }

    #[test]
    fn bad_files_give_clear_errors() {
        let parse = |text: &str, format| Mesh::parse(text.as_bytes(), format).unwrap_err();
        assert!(matches!(
            parse(
                "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                MeshFormat::Off
            ),
            LoadError::IndexOutOfRange {
                index: 7,
                vertex_count: 3,
                ..
            }
        ));
        assert!(matches!(
            parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", MeshFormat::Obj),
            LoadError::Parse {
                format: MeshFormat::Obj,
                ..
            }
        ));
        assert!(matches!(
            parse("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", MeshFormat::Off),
            LoadError::NoTriangles { .. }
        ));
        assert!(matches!(
            parse("not a mesh at all", MeshFormat::Off),
            LoadError::Parse { .. }
        ));
        assert!(matches!(
            parse("ply\nformat ascii 1.0\nend_header\n", MeshFormat::Ply),
            LoadError::Parse { .. }
        ));
        assert!(matches!(
            parse(
                "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n",
                MeshFormat::Off
            ),
            LoadError::NonFinite { vertex: 1, .. }
        ));
        assert!(matches!(
            parse("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj),
            LoadError::NonFinite { vertex: 1, .. }
        ));
        let e = Mesh::load(Path::new("/nonexistent/bunny.off")).unwrap_err();
        assert!(matches!(e, LoadError::Io { .. }));
        assert!(e.to_string().contains("/nonexistent/bunny.off"), "{e}");
        let e = Mesh::load(Path::new("bunny.3ds")).unwrap_err();
        assert!(matches!(e, LoadError::UnknownFormat { .. }), "{e}");
    }
}
