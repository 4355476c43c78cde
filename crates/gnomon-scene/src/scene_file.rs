//! Scene files (TOML): objects made of mesh files, an optional ground slab and named views.
//!
//! ```toml
//! [ground]                 # optional: a square slab centred on the origin
//! size = 200.0             # its edge
//! height = 0.0             # the y of its top (default 0)
//!
//! [[object]]
//! mesh = "models/bunny.off"   # .off .obj .ply .stl .gltf .glb .ter, relative to this file
//! name = "bunny"              # optional (default: the file's stem)
//! translate = [0, 0, 0]       # optional
//! scale = 10.0                # optional, > 0: uniform, or [sx, sy, sz] along the mesh's axes
//! rotate_y_degrees = 30       # optional
//! casts = true                # optional
//! receives = true             # optional
//! color = [0.8, 0.6, 0.4]     # optional, linear RGB in [0, 1]
//! split = "components"        # optional: each connected part its own object (and box)
//!
//! [[view]]
//! name = "front"
//! eye = [0, 5, 30]
//! target = [0, 3, 0]
//! up = [0, 1, 0]              # optional (default +y)
//! fov = 60                    # optional, vertical, degrees (default 60)
//! near = 1                    # optional (default 1)
//! far = 400                   # optional (default 400)
//! light_dir = [0.3, -1, 0.2]  # or spot = [px, py, pz, dx, dy, dz, half_angle, range],
//!                             # or point = [px, py, pz, range]
//! description = "..."         # optional
//!
//! [[view.light]]              # optional: more lights of the view above (up to 4 in all),
//! spot = [0, 20, 0, 0, -1, 0, 30, 50]   # each with light_dir, spot or point
//! ```
//!
//! An object is `world_from_object = translate * rotate_y * scale`. A mesh file used by
//! several objects is read once and shared (instanced). Every error is one line naming the
//! file, the line and the key ([`SceneFileError`]). Reading the TOML (`scene_toml.rs`) is
//! behind the default-on feature `scene-file`; the loaded scene's types here are always built.

use std::fmt;
use std::path::PathBuf;

use glam::DMat4;

use crate::Mesh;
use crate::view::NamedView;

/// The largest scene file read (the meshes it names have their own limit).
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;

/// A scene file, loaded: its meshes read, its objects placed, its views checked.
#[derive(Debug, Clone)]
pub struct SceneFile {
    /// The scene's name (the `name` key, else the file's stem).
    pub name: String,
    /// The file.
    pub path: PathBuf,
    /// The meshes in object space: one per distinct file, and the ground's slab.
    pub meshes: Vec<Mesh>,
    /// The placed objects (the ground first where there is one).
    pub objects: Vec<FileObject>,
    /// The named views, in the file's order.
    pub views: Vec<NamedView>,
    /// What the mesh loads left out (one line each), for the caller to show as warnings.
    pub notes: Vec<String>,
}

/// One placed mesh of a scene file.
#[derive(Debug, Clone, PartialEq)]
pub struct FileObject {
    /// Its name.
    pub name: String,
    /// Index into [`SceneFile::meshes`].
    pub mesh: usize,
    /// Object to world.
    pub world_from_object: DMat4,
    /// Whether it casts shadows.
    pub casts: bool,
    /// Whether it receives shadows.
    pub receives: bool,
    /// Its colour (linear RGB), if the file gives one.
    pub color: Option<[f32; 3]>,
}

/// A scene file that cannot be used: one line, `FILE:LINE: key 'KEY': what is wrong`.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFileError {
    /// The file.
    pub path: PathBuf,
    /// The line (from 1), where the error has one.
    pub line: Option<usize>,
    /// The key, where the error has one.
    pub key: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if let Some(key) = &self.key {
            write!(f, "key '{key}': ")?;
        }
        write!(f, "{}", self.message.replace('\n', " "))
    }
}

impl std::error::Error for SceneFileError {}
