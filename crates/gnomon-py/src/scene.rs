//! The scene: caster and receiver boxes for the setups, and what the renderer draws.

use std::path::PathBuf;
use std::sync::Arc;

use glam::DMat4;
use gnomon::{Aabb, Lens, SceneBounds};
use gnomon_render::{Instance, RenderScene};
use gnomon_scene::{NamedView, Shape};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::{boxes, boxes_array};
use crate::gnomon_error;
use crate::objects::{Camera, light_object};

/// What `render` draws of a scene.
#[derive(Clone)]
pub(crate) enum Drawn {
    /// Each box as a cuboid (a scene made from boxes).
    Boxes,
    /// The loaded meshes, whose boxes are the scene's.
    Meshes(Arc<RenderScene>),
    /// Loaded meshes whose boxes were moved: the meshes cannot follow.
    MovedMeshes,
}

/// A scene: boxes around the shadow casters and receivers (what a setup reads), and for
/// loaded scenes the meshes `render` draws and the named views.
///
/// `Scene(casters, receivers)` takes `(N, 2, 3)` arrays of minimum and maximum corners (or
/// `(N, 6)`: min x, y, z, max x, y, z); `Scene.load(path)` reads a mesh or scene file and
/// `Scene.demo()` is the command line's demo scene.
#[pyclass(frozen, module = "gnomon")]
pub struct Scene {
    pub(crate) bounds: Arc<SceneBounds>,
    pub(crate) drawn: Drawn,
    views: Vec<NamedView>,
    name: String,
    notes: Vec<String>,
}

#[pymethods]
impl Scene {
    #[new]
    fn new(
        py: Python<'_>,
        casters: &Bound<'_, PyAny>,
        receivers: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let (casters, receivers) = box_args(casters, receivers)?;
        let bounds = py
            .detach(|| SceneBounds::new(casters, receivers, None))
            .map_err(gnomon_error)?;
        Ok(Self {
            bounds: Arc::new(bounds),
            drawn: Drawn::Boxes,
            views: Vec::new(),
            name: "boxes".into(),
            notes: Vec::new(),
        })
    }

    /// The command line's demo scene (`gnomon ... --scene demo`) with its named views.
    #[staticmethod]
    fn demo(py: Python<'_>) -> PyResult<Self> {
        Self::builtin(py, "demo")
    }

    /// A built-in scene by name (`gnomon ... --scene NAME`) with its named views.
    #[staticmethod]
    fn builtin(py: Python<'_>, name: &str) -> PyResult<Self> {
        let layout = gnomon_scene::by_name(name).ok_or_else(|| {
            gnomon_error(format!(
                "unknown scene '{name}' (known: {})",
                gnomon_scene::SCENE_NAMES.join(", ")
            ))
        })?;
        let scene = RenderScene::from_layout(&layout);
        Self::from_meshes(
            py,
            layout.name.clone(),
            scene,
            gnomon_scene::views_by_name(name),
            Vec::new(),
        )
    }

    /// A scene file (`.toml`, as `--scene-file`) or a mesh file standing on a ground slab,
    /// scaled to `mesh_height` (as `--mesh` with `--mesh-height`). What the load left out
    /// is in `notes`.
    #[staticmethod]
    #[pyo3(signature = (path, mesh_height = 10.0))]
    fn load(py: Python<'_>, path: PathBuf, mesh_height: f64) -> PyResult<Self> {
        if path.extension().is_some_and(|x| x == "toml") {
            let file = py
                .detach(|| gnomon_scene::SceneFile::load(&path))
                .map_err(gnomon_error)?;
            let scene = RenderScene::from_scene_file(&file);
            return Self::from_meshes(py, file.name, scene, file.views, file.notes);
        }
        let (parts, notes) = py
            .detach(|| gnomon_scene::Mesh::load_parts(&path))
            .map_err(gnomon_error)?;
        let name = path
            .file_stem()
            .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
        let scene =
            RenderScene::parts_on_ground(&name, parts, mesh_height).map_err(gnomon_error)?;
        let views = gnomon_scene::mesh_views(mesh_height);
        Self::from_meshes(py, name, scene, views, notes)
    }

    /// The same scene with its boxes moved (an animated scene's next frame): as many boxes as
    /// before, in the same order. The box hierarchies are refitted, not rebuilt. A loaded
    /// scene's meshes do not follow: setups take the moved boxes, `render` refuses.
    fn moved(
        &self,
        py: Python<'_>,
        casters: &Bound<'_, PyAny>,
        receivers: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let (casters, receivers) = box_args(casters, receivers)?;
        let bounds = py
            .detach(|| self.bounds.with_boxes_moved(casters, receivers, None))
            .map_err(gnomon_error)?;
        Ok(Self {
            bounds: Arc::new(bounds),
            drawn: match self.drawn {
                Drawn::Boxes => Drawn::Boxes,
                _ => Drawn::MovedMeshes,
            },
            views: self.views.clone(),
            name: self.name.clone(),
            notes: self.notes.clone(),
        })
    }

    /// The caster boxes, `(N, 2, 3)`: minimum and maximum corners.
    #[getter]
    fn casters<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        boxes_array(py, self.bounds.casters())
    }

    /// The receiver boxes, `(N, 2, 3)`.
    #[getter]
    fn receivers<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        boxes_array(py, self.bounds.receivers())
    }

    /// The box around everything, `(2, 3)`.
    #[getter]
    fn scene_box<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        boxes_array(py, &[self.bounds.scene_box()]).get_item(0)
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// What loading left out, one line each.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// The names of the named views (`--view NAME` on the command line).
    #[getter]
    fn views(&self) -> Vec<String> {
        self.views.iter().map(|v| v.name.clone()).collect()
    }

    /// The named view's camera (for images of width / height `aspect`) and main light, as
    /// `gnomon setup --view NAME` takes them.
    #[pyo3(signature = (name, aspect = 16.0 / 9.0))]
    fn view<'py>(&self, py: Python<'py>, name: &str, aspect: f64) -> PyResult<Bound<'py, PyTuple>> {
        let view = self.views.iter().find(|v| v.name == name).ok_or_else(|| {
            gnomon_error(format!(
                "unknown view '{name}' (known: {})",
                self.views().join(", ")
            ))
        })?;
        let lens = Lens {
            fov_y_degrees: view.fov_y_degrees,
            aspect,
            near: view.near,
            far: view.far,
        };
        let camera = Camera::from_parts(view.eye, view.target, view.up, lens)?;
        let light = view.light.light().map_err(gnomon_error)?;
        PyTuple::new(
            py,
            [Bound::new(py, camera)?.into_any(), light_object(py, light)?],
        )
    }

    fn __len__(&self) -> usize {
        self.bounds.casters().len() + self.bounds.receivers().len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene('{}', {} casters, {} receivers, views: {})",
            self.name,
            self.bounds.casters().len(),
            self.bounds.receivers().len(),
            self.views().join(", ")
        )
    }
}

impl Scene {
    fn from_meshes(
        py: Python<'_>,
        name: String,
        scene: RenderScene,
        views: Vec<NamedView>,
        notes: Vec<String>,
    ) -> PyResult<Self> {
        let bounds = py.detach(|| scene.bounds()).map_err(gnomon_error)?;
        Ok(Self {
            bounds: Arc::new(bounds),
            drawn: Drawn::Meshes(Arc::new(scene)),
            views,
            name,
            notes,
        })
    }

    /// What the renderer draws: the loaded meshes, or a cuboid per box (casters cast and
    /// receive, receivers only receive).
    pub(crate) fn render_scene(&self) -> PyResult<Arc<RenderScene>> {
        match &self.drawn {
            Drawn::Meshes(scene) => Ok(scene.clone()),
            Drawn::Boxes => Ok(Arc::new(cuboids(&self.bounds))),
            Drawn::MovedMeshes => Err(gnomon_error(
                "this loaded scene's boxes were moved and its meshes cannot follow: render it \
                 as loaded, or make the scene from boxes",
            )),
        }
    }
}

/// The `casters` and `receivers` arguments as boxes.
fn box_args(
    casters: &Bound<'_, PyAny>,
    receivers: &Bound<'_, PyAny>,
) -> PyResult<(Vec<Aabb>, Vec<Aabb>)> {
    Ok((boxes("casters", casters)?, boxes("receivers", receivers)?))
}

fn cuboids(bounds: &SceneBounds) -> RenderScene {
    let mut scene = RenderScene::default();
    let placed = |b: &Aabb, casts: bool| (b.half_extents(), b.center(), casts);
    let all = bounds
        .casters()
        .iter()
        .map(|b| placed(b, true))
        .chain(bounds.receivers().iter().map(|b| placed(b, false)));
    for (k, (half_extents, center, casts)) in all.enumerate() {
        scene.meshes.push(Shape::Cuboid { half_extents }.mesh());
        scene.instances.push(Instance {
            name: if casts { "caster" } else { "receiver" }.to_string(),
            mesh: k,
            world_from_object: DMat4::from_translation(center),
            casts,
            receives: true,
            color: if casts {
                [0.75, 0.72, 0.68]
            } else {
                [0.55, 0.6, 0.5]
            },
        });
    }
    scene
}
