//! What a mesh file is and what reading one gives or fails with, shared by the format readers
//! (`gltf.rs`, `terragen.rs`) and the loader over them (`load.rs`).

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec2, DVec3};

use crate::mesh::Cutout;

/// The mesh file formats [`crate::Mesh::load`] reads, chosen by the file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// Object File Format (`.off`).
    Off,
    /// Wavefront OBJ (`.obj`); materials are ignored.
    Obj,
    /// Polygon File Format (`.ply`), ASCII or binary; the `vertex` element's x, y, z and the
    /// `face` element's `vertex_indices` (or `vertex_index`) list.
    Ply,
    /// glTF 2.0: `.gltf` (JSON, buffers beside it or embedded) or `.glb` (binary); see the
    /// module documentation.
    Gltf,
    /// STL (`.stl`), ASCII or binary; facet normals are not read (the vertex order gives the
    /// winding).
    Stl,
    /// A Terragen heightfield (`.ter`): the grid as triangles, y up, in metres.
    Ter,
}

impl MeshFormat {
    /// The format of a path, from its extension (any case).
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "off" => Some(Self::Off),
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            "gltf" | "glb" => Some(Self::Gltf),
            "stl" => Some(Self::Stl),
            "ter" => Some(Self::Ter),
            _ => None,
        }
    }

    /// The format's usual extension.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::Obj => "obj",
            Self::Ply => "ply",
            Self::Gltf => "gltf",
            Self::Stl => "stl",
            Self::Ter => "ter",
        }
    }
}

/// The largest mesh file read: 1 GiB.
pub const MAX_MESH_BYTES: u64 = 1 << 30;

/// Why a mesh file could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The path is not a regular file (a folder, a device such as /dev/zero, a pipe).
    NotAFile {
        /// The path.
        path: PathBuf,
    },
    /// The file is larger than [`MAX_MESH_BYTES`].
    TooLarge {
        /// The file.
        path: PathBuf,
    },
    /// The file could not be read.
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The extension is none of `.off`, `.obj`, `.ply`, `.gltf`, `.glb`, `.stl`.
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file is not valid in its format.
    Parse {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: MeshFormat,
        /// What the parser said.
        message: String,
    },
    /// A face refers to a vertex that does not exist.
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// The index.
        index: i64,
        /// How many vertices there are.
        vertex_count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    NonFinite {
        /// The file.
        path: PathBuf,
        /// The vertex's index.
        vertex: usize,
    },
    /// The file holds no triangle (faces with fewer than three vertices do not count).
    NoTriangles {
        /// The file.
        path: PathBuf,
    },
    /// The file's format is one this build of gnomon-scene leaves out (its feature is off).
    LeftOut {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: MeshFormat,
    },
    /// A glTF file requires an extension gnomon does not read.
    UnsupportedExtension {
        /// The file.
        path: PathBuf,
        /// The extension's name.
        extension: String,
    },
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotAFile { path } => {
                write!(f, "{} is not a regular file", path.display())
            }
            Self::TooLarge { path } => write!(
                f,
                "{} is larger than {} MiB, the most a mesh file may hold",
                path.display(),
                MAX_MESH_BYTES >> 20
            ),
            Self::Io { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            Self::UnknownFormat { path } => write!(
                f,
                "{}: unknown mesh format (known extensions: .off, .obj, .ply, .gltf, .glb, .stl, .ter)",
                path.display()
            ),
            Self::Parse {
                path,
                format,
                message,
            } => write!(
                f,
                "{}: not a valid .{} file: {message}",
                path.display(),
                format.extension()
            ),
            Self::IndexOutOfRange {
                path,
                index,
                vertex_count,
            } => write!(
                f,
                "{}: a face uses vertex {index}, but there are {vertex_count} vertices",
                path.display()
            ),
            Self::NonFinite { path, vertex } => write!(
                f,
                "{}: vertex {vertex} has a coordinate that is not a finite number",
                path.display()
            ),
            Self::NoTriangles { path } => write!(f, "{}: no triangles", path.display()),
            Self::LeftOut { path, format } => write!(
                f,
                // Each reader's feature is named by its format's extension.
                "{}: this build reads no .{ext} files (gnomon-scene's feature '{ext}' is off)",
                path.display(),
                ext = format.extension()
            ),
            Self::UnsupportedExtension { path, extension } => write!(
                f,
                "{}: requires the glTF extension {extension}, which gnomon does not read",
                path.display()
            ),
        }
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl LoadError {
    /// The error with its file's path filled in.
    pub(crate) fn at(mut self, file: &Path) -> Self {
        match &mut self {
            Self::Io { path, .. }
            | Self::NotAFile { path }
            | Self::TooLarge { path }
            | Self::UnknownFormat { path }
            | Self::Parse { path, .. }
            | Self::IndexOutOfRange { path, .. }
            | Self::NonFinite { path, .. }
            | Self::NoTriangles { path }
            | Self::LeftOut { path, .. }
            | Self::UnsupportedExtension { path, .. } => *path = file.to_path_buf(),
        }
        self
    }
}

/// Positions and polygons (vertex indices).
pub(crate) type Polygons = (Vec<DVec3>, Vec<Vec<i64>>);

/// A part as parsed, before its normals.
pub(crate) struct RawPart {
    pub name: String,
    pub positions: Vec<DVec3>,
    pub polygons: Vec<Vec<i64>>,
    pub color: Option<[f32; 3]>,
    pub placements: Vec<DMat4>,
    /// Texture coordinates, one per position, where the part has a cutout.
    pub uvs: Vec<DVec2>,
    pub cutout: Option<Arc<Cutout>>,
}

impl RawPart {
    pub(crate) fn whole((positions, polygons): Polygons) -> Self {
        Self {
            name: String::new(),
            positions,
            polygons,
            color: None,
            placements: vec![DMat4::IDENTITY],
            uvs: Vec::new(),
            cutout: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_format_left_out_names_its_feature() {
        let e = LoadError::LeftOut {
            path: PathBuf::new(),
            format: MeshFormat::Gltf,
        }
        .at(Path::new("a.glb"));
        assert_eq!(
            e.to_string(),
            "a.glb: this build reads no .gltf files (gnomon-scene's feature 'gltf' is off)"
        );
    }
}
