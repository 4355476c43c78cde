//! `setup` and what it returns (a setup and its maps), and `project`.

use std::sync::{Arc, OnceLock};

use gnomon::{MapSettings, ShadowMap, ShadowSetup, ViewSamples};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde_json::Value;

use crate::arrays::{map_points, matrix, points, vector};
use crate::gnomon_error;
use crate::objects::{Camera, light_arg};
use crate::scene::Scene;
use crate::values::{json_to_py, technique};

/// A shadow-map setup: the maps, how a point picks among them, and what the setup did.
#[pyclass(frozen, module = "gnomon")]
pub struct Setup {
    pub(crate) setup: Arc<ShadowSetup>,
    /// The JSON form, made on first use: a frame loop that reads only the matrices never
    /// pays for it.
    json: OnceLock<Value>,
}

impl Setup {
    pub(crate) fn new(setup: ShadowSetup) -> Self {
        Self {
            setup: Arc::new(setup),
            json: OnceLock::new(),
        }
    }

    fn json(&self) -> &Value {
        self.json
            .get_or_init(|| gnomon_tools::setup_json(&self.setup))
    }
}

#[pymethods]
impl Setup {
    /// The technique's name.
    #[getter]
    fn technique(&self) -> &str {
        self.setup.technique
    }

    /// The fallback the setup took, by name (`None` if it took none; `diagnostics` says why).
    #[getter]
    fn fallback(&self) -> Option<&'static str> {
        self.setup.fallback().map(|f| f.name())
    }

    /// The shadow maps, one or more (cascades, SPPSM's pair, a point light's faces).
    #[getter]
    fn maps(&self) -> Vec<Map> {
        self.setup
            .maps
            .iter()
            .zip(self.json()["maps"].as_array().into_iter().flatten())
            .map(|(map, json)| Map {
                map: *map,
                json: json.clone(),
            })
            .collect()
    }

    /// How a point picks its map: a dict with `kind` (`single`, `plane`, `cascades`,
    /// `dual_paraboloid`, `cube_faces`) and that kind's data, as in `to_json()`.
    #[getter]
    fn selection<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.json()["selection"])
    }

    /// What the setup did (fallbacks with their reasons, the light frame, gamma, caster
    /// counts, ...), as a dict; each map has its own fallbacks and warp strength.
    #[getter]
    fn diagnostics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.json()["diagnostics"])
    }

    /// The setup as JSON text: exactly what `gnomon setup --json` prints for the same
    /// inputs (matrices column-major).
    fn to_json(&self) -> String {
        serde_json::to_string_pretty(self.json()).expect("JSON of plain values")
    }

    fn __len__(&self) -> usize {
        self.setup.maps.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Setup('{}', {} map(s){})",
            self.setup.technique,
            self.setup.maps.len(),
            self.fallback()
                .map(|f| format!(", fallback {f}"))
                .unwrap_or_default()
        )
    }
}

/// One shadow map of a setup.
#[pyclass(frozen, module = "gnomon")]
pub struct Map {
    map: ShadowMap,
    json: Value,
}

#[pymethods]
impl Map {
    /// World to the map's clip space, a `(4, 4)` array indexed `[row, column]`
    /// (`clip = clip_from_world @ [x, y, z, 1]`; x and y over w in [-1, 1] across the map).
    #[getter]
    fn clip_from_world<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.map.clip_from_world)
    }

    /// The depth the map stores, as a row: `depth = depth_from_world @ [x, y, z, 1]`, a
    /// `(4,)` array (TSM and PSM carry their depth here, not in clip z).
    #[getter]
    fn depth_from_world<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, self.map.depth_from_world.to_array().to_vec())
    }

    /// Texels on a side.
    #[getter]
    fn resolution(&self) -> u32 {
        self.map.resolution
    }

    /// Texels left empty at the map's border.
    #[getter]
    fn viewport_inset(&self) -> Option<u32> {
        self.json["viewport_inset"]
            .as_u64()
            .and_then(|v| u32::try_from(v).ok())
    }

    /// `orthographic`, `perspective` or `paraboloid`.
    #[getter]
    fn projection(&self) -> String {
        self.json["projection"]
            .as_str()
            .unwrap_or_default()
            .to_string()
    }

    /// The view depths `(near, far)` this map covers (cascades), else `None`.
    #[getter]
    fn view_depth_range<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.json["view_depth_range"])
    }

    /// This map's own fallbacks, by name.
    #[getter]
    fn fallbacks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.json["fallbacks"])
    }

    /// The warp's strength where the warp limit weakened it (else `None`).
    #[getter]
    fn warp_strength<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.json["warp_strength"])
    }

    /// Where world points land: see `gnomon.project`.
    fn project<'py>(&self, points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        project_points(&self.map, points)
    }

    fn __repr__(&self) -> String {
        format!(
            "Map({}, {} texels{})",
            self.projection(),
            self.map.resolution,
            self.map
                .view_depth_range
                .map(|[a, b]| format!(", view depths {a}..{b}"))
                .unwrap_or_default()
        )
    }
}

/// Shadow-map matrices for `technique` (one of `gnomon.TECHNIQUES`), seen by `camera`, lit
/// by `light` (a `Sun`, `Spot` or `Point`), over `scene`'s boxes.
///
/// `resolution` is the map's texels on a side. `samples=(positions, normals)`, two `(N, 3)`
/// arrays of the surface points the pixels see (world space), lets the warp limit judge the
/// maps on the real surfaces instead of the boxes. Further keyword arguments are the
/// technique's parameters by the command line's names with `_` for `-` (`cascades=4`,
/// `cascade_split="log"`, `stable=True`, `lispsm_n=5.0`); one the technique does not read
/// is refused. The GIL is released while the setup runs.
///
/// Raises `GnomonError` on bad input, with the core's one-line message.
#[pyfunction]
#[pyo3(signature = (technique, camera, light, scene, resolution = 2048, samples = None, **params))]
// The Python signature's arguments, each a keyword argument there.
#[allow(clippy::too_many_arguments)]
pub fn setup(
    py: Python<'_>,
    technique: &str,
    camera: PyRef<'_, Camera>,
    light: &Bound<'_, PyAny>,
    scene: PyRef<'_, Scene>,
    resolution: i64,
    samples: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Setup> {
    let technique = self::technique(technique, params)?;
    let light = light_arg(light)?;
    let map = MapSettings::with_resolution(resolution_arg(resolution)?);
    let camera = camera.camera;
    let samples = samples
        .map(|s| view_samples(s, &camera, &light))
        .transpose()?;
    let bounds = scene.bounds.clone();
    let computed = py.detach(|| match &samples {
        Some(samples) => {
            gnomon::compute_setup_with_samples(&technique, &camera, &light, &bounds, map, samples)
        }
        None => gnomon::compute_setup(&technique, &camera, &light, &bounds, map),
    });
    Ok(Setup::new(computed.map_err(gnomon_error)?))
}

/// A shadow-map resolution argument, refused outside the core's range.
pub(crate) fn resolution_arg(resolution: i64) -> PyResult<u32> {
    u32::try_from(resolution)
        .ok()
        .filter(|r| (gnomon::MIN_RESOLUTION..=gnomon::MAX_RESOLUTION).contains(r))
        .ok_or_else(|| {
            gnomon_error(format!(
                "resolution: {resolution} is not a shadow-map resolution: give {} to {} texels",
                gnomon::MIN_RESOLUTION,
                gnomon::MAX_RESOLUTION
            ))
        })
}

/// The caller's view samples: `(positions, normals)`, two `(N, 3)` arrays.
fn view_samples(
    samples: &Bound<'_, PyAny>,
    camera: &gnomon::Camera,
    light: &gnomon::Light,
) -> PyResult<ViewSamples> {
    let pair = samples
        .cast::<PyTuple>()
        .ok()
        .filter(|t| t.len() == 2)
        .ok_or_else(|| {
            gnomon_error("samples: expected a tuple (positions, normals) of two (N, 3) arrays")
        })?;
    let positions = points("samples[0] (positions)", &pair.get_item(0)?)?;
    let normals = points("samples[1] (normals)", &pair.get_item(1)?)?;
    if positions.len() != normals.len() {
        return Err(gnomon_error(format!(
            "samples: {} positions but {} normals",
            positions.len(),
            normals.len()
        )));
    }
    Ok(ViewSamples::from_surface_points(
        camera,
        light,
        positions.into_iter().zip(normals),
    ))
}

/// Where world `points` (an `(N, 3)` array) land in `map`: an `(N, 3)` array of normalised
/// device coordinates (x and y in [-1, 1] across the map, z its clip depth); a row of NaN
/// where a point has none (behind a perspective map's centre, beyond a paraboloid's rim).
#[pyfunction]
pub fn project<'py>(
    map: PyRef<'py, Map>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    project_points(&map.map, points)
}

fn project_points<'py>(map: &ShadowMap, points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    map_points("points", points, |p| map.project(p))
}
