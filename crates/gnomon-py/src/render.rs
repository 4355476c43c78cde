//! `render`: a frame of the scene with the technique's shadows (or the exact shadow
//! volumes), its shadow mask and its sampling error, as `gnomon render` draws it.

use std::sync::{Arc, Mutex, PoisonError};

use gnomon::{Camera as CoreCamera, Light, MapSettings, SceneBounds, ShadowSetup, Technique};
use gnomon_render::{Gpu, RenderScene, RenderSettings, Renderer, ShadowedLight, StencilMode};
use numpy::IntoPyArray;
use numpy::ndarray::{Array2, Array3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::gnomon_error;
use crate::objects::{Camera, light_arg};
use crate::scene::Scene;
use crate::setup::{Setup, resolution_arg};
use crate::values::technique;

/// The exact shadows' name among the techniques `render` takes.
const VOLUMES: &str = "volumes";

/// A rendered frame.
#[pyclass(frozen, module = "gnomon")]
pub struct Frame {
    frame: gnomon_render::Frame,
    setup: Option<Py<Setup>>,
    device: String,
}

#[pymethods]
impl Frame {
    /// The image, `(H, W, 3)` uint8, sRGB.
    #[getter]
    fn frame<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let rgb: Vec<u8> = self
            .frame
            .color
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let (w, h) = (self.frame.width as usize, self.frame.height as usize);
        Array3::from_shape_vec((h, w, 3), rgb)
            .expect("three bytes per pixel")
            .into_pyarray(py)
            .into_any()
    }

    /// The shadow mask, `(H, W)` uint8: 255 where the light reaches, 0 where it does not,
    /// 128 where there is no geometry (as `gnomon render --mask` writes it).
    #[getter]
    fn mask<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let (w, h) = (self.frame.width as usize, self.frame.height as usize);
        Array2::from_shape_vec((h, w), self.frame.mask.clone())
            .expect("one byte per pixel")
            .into_pyarray(py)
            .into_any()
    }

    /// Undersampling per pixel, `(H, W)` float32: pixels per texel along the worst
    /// direction (above 1 the map is coarser than the screen), 0 without geometry, negative
    /// where no map sees the point; `None` for the exact volumes, which have no map.
    #[getter]
    fn error_map<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyAny>> {
        let metrics = self.frame.metrics.as_ref()?;
        let (w, h) = (self.frame.width as usize, self.frame.height as usize);
        Some(
            Array2::from_shape_vec((h, w), metrics.undersampling.clone())
                .expect("one value per pixel")
                .into_pyarray(py)
                .into_any(),
        )
    }

    /// The setup drawn (with the renderer's view samples); `None` for the volumes.
    #[getter]
    fn setup(&self, py: Python<'_>) -> Option<Py<Setup>> {
        self.setup.as_ref().map(|s| s.clone_ref(py))
    }

    /// The GPU that drew it.
    #[getter]
    fn device(&self) -> &str {
        &self.device
    }

    /// Pass times in ms: `shadow_pass_ms`, `main_pass_ms`, `readback_ms`.
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.frame.timings;
        let dict = PyDict::new(py);
        dict.set_item("shadow_pass_ms", t.shadow_pass_ms)?;
        dict.set_item("main_pass_ms", t.main_pass_ms)?;
        dict.set_item("readback_ms", t.readback_ms)?;
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        format!(
            "Frame({}x{} on {})",
            self.frame.width, self.frame.height, self.device
        )
    }
}

/// What `render` draws: a map technique or the exact volumes.
enum Drawn {
    Maps(Technique),
    Volumes,
}

/// Renders `scene` from `camera` lit by `light` with `technique`'s shadows (one of
/// `gnomon.TECHNIQUES`, or `"volumes"` for the exact stenciled shadow volumes, the ground
/// truth) into an image of `size = (width, height)` pixels; `resolution` and the keyword
/// arguments are the maps' as in `setup`. The setup takes the renderer's view samples, as
/// `gnomon render` does, so the masks agree with the command line's.
///
/// The camera's aspect must be the image's. One GPU device serves the whole process,
/// opened on the first call; the GIL is released while it draws.
#[pyfunction]
#[pyo3(signature = (scene, camera, light, technique = "focused", size = (640, 360), resolution = 2048, **params))]
// The Python signature's arguments, each a keyword argument there.
#[allow(clippy::too_many_arguments)]
pub fn render(
    py: Python<'_>,
    scene: PyRef<'_, Scene>,
    camera: PyRef<'_, Camera>,
    light: &Bound<'_, PyAny>,
    technique: &str,
    size: (i64, i64),
    resolution: i64,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Frame> {
    let drawn = if technique.trim() == VOLUMES {
        if params.is_some_and(|p| !p.is_empty()) {
            return Err(gnomon_error("volumes take no technique parameters"));
        }
        Drawn::Volumes
    } else {
        Drawn::Maps(self::technique(technique, params)?)
    };
    let shot = Shot::new(&scene, &camera, light, size, resolution)?;
    if let Drawn::Maps(technique) = &drawn {
        // Bad parameters for this view are refused before the GPU opens.
        let map = MapSettings::with_resolution(shot.resolution);
        gnomon::compute_setup(technique, &shot.camera, &shot.light, &shot.bounds, map)
            .map_err(gnomon_error)?;
    }
    let (frame, setup, device) = py
        .detach(|| {
            let mut renderer = shot.open_renderer()?;
            let device = renderer.gpu().describe();
            let (frame, setup) = match drawn {
                Drawn::Volumes => (shot.draw_volumes(&mut renderer)?, None),
                Drawn::Maps(t) => {
                    let (frame, setup, _) = shot.draw_maps(&mut renderer, &t)?;
                    (frame, Some(setup))
                }
            };
            Ok::<_, String>((frame, setup, device))
        })
        .map_err(gnomon_error)?;
    let setup = setup.map(|s| Py::new(py, Setup::new(s))).transpose()?;
    Ok(Frame {
        frame,
        setup,
        device,
    })
}

/// One view to draw, checked before any work: the scene's meshes and boxes, the camera (its
/// aspect the image's), the light, the image's size and the maps' resolution.
pub(crate) struct Shot {
    pub scene: Arc<RenderScene>,
    pub bounds: Arc<SceneBounds>,
    pub camera: CoreCamera,
    pub light: Light,
    pub size: (u32, u32),
    pub resolution: u32,
}

impl Shot {
    pub(crate) fn new(
        scene: &Scene,
        camera: &Camera,
        light: &Bound<'_, PyAny>,
        size: (i64, i64),
        resolution: i64,
    ) -> PyResult<Self> {
        let size = image_size(size)?;
        Ok(Self {
            scene: scene.render_scene()?,
            bounds: scene.bounds.clone(),
            camera: checked_camera(camera.camera, size)?,
            light: light_arg(light)?,
            size,
            resolution: resolution_arg(resolution)?,
        })
    }

    /// A renderer of the scene, refusing an image or map larger than the GPU's largest
    /// texture.
    pub(crate) fn open_renderer(&self) -> Result<Renderer, String> {
        let gpu = process_gpu()?;
        let (max, (w, h), r) = (gpu.max_texture_size(), self.size, self.resolution);
        if w > max || h > max || r > max {
            return Err(format!(
                "the image ({w}x{h}) or the map ({r}) exceeds this GPU's largest texture, \
                 {max} on a side ({})",
                gpu.describe()
            ));
        }
        Renderer::new(gpu, &self.scene).map_err(|e| e.to_string())
    }

    /// A map technique's frame (with metrics) and its setup, which takes the renderer's view
    /// samples, and how long the setup took in microseconds.
    pub(crate) fn draw_maps(
        &self,
        renderer: &mut Renderer,
        technique: &Technique,
    ) -> Result<(gnomon_render::Frame, ShadowSetup, f64), String> {
        let (camera, light) = (&self.camera, self.light);
        let samples = renderer
            .view_samples(camera, &light)
            .map_err(|e| e.to_string())?;
        let map = MapSettings::with_resolution(self.resolution);
        let started = std::time::Instant::now();
        let setup = gnomon::compute_setup_with_samples(
            technique,
            camera,
            &light,
            &self.bounds,
            map,
            &samples,
        )
        .map_err(|e| e.to_string())?;
        let setup_us = started.elapsed().as_secs_f64() * 1e6;
        let settings = RenderSettings {
            width: self.size.0,
            height: self.size.1,
            metrics: true,
            ..RenderSettings::default()
        };
        let (lights, setups) = ([light], [setup]);
        let frame = renderer
            .render_lights(camera, &ShadowedLight::pairs(&lights, &setups), &settings)
            .map_err(|e| e.to_string())?;
        let [setup] = setups;
        Ok((frame, setup, setup_us))
    }

    /// The exact shadow volumes' frame (z-fail counting).
    pub(crate) fn draw_volumes(
        &self,
        renderer: &mut Renderer,
    ) -> Result<gnomon_render::Frame, String> {
        let settings = RenderSettings {
            width: self.size.0,
            height: self.size.1,
            ..RenderSettings::default()
        };
        renderer
            .render_volumes_lit_by(&self.camera, &[self.light], &settings, StencilMode::ZFail)
            .map(|drawn| drawn.frame)
            .map_err(|e| e.to_string())
    }
}

fn image_size((w, h): (i64, i64)) -> PyResult<(u32, u32)> {
    let side = |v: i64| u32::try_from(v).ok().filter(|v| (1..=16384).contains(v));
    match (side(w), side(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(gnomon_error(format!(
            "size: ({w}, {h}) is not an image size: give (width, height), each 1 to 16384"
        ))),
    }
}

/// The camera, refused where its aspect is not the image's (the picture would be
/// stretched) or it sees farther than the renderer draws precisely.
fn checked_camera(camera: CoreCamera, (w, h): (u32, u32)) -> PyResult<CoreCamera> {
    let (lens, image_aspect) = (camera.lens(), f64::from(w) / f64::from(h));
    if (lens.aspect / image_aspect - 1.0).abs() > 1e-3 {
        return Err(gnomon_error(format!(
            "the camera's aspect {:.4} is not the image's {w}x{h} ({image_aspect:.4}): make the \
             camera with aspect={w}/{h}",
            lens.aspect
        )));
    }
    if lens.far > gnomon_render::MAX_VIEW_DISTANCE {
        return Err(gnomon_error(format!(
            "the camera's far plane {} is beyond what the renderer draws precisely (at most {})",
            lens.far,
            gnomon_render::MAX_VIEW_DISTANCE
        )));
    }
    Ok(camera)
}

/// The process's GPU, opened on first use: the renderer wants one device per process.
fn process_gpu() -> Result<Gpu, String> {
    static GPU: Mutex<Option<Gpu>> = Mutex::new(None);
    let mut kept = GPU.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(gpu) = kept.as_ref() {
        return Ok(gpu.clone());
    }
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    *kept = Some(gpu.clone());
    Ok(gpu)
}
