//! The camera and the lights: Python classes over the core's, checked where they are made.

use glam::DVec3;
use gnomon::{DirectionalLight, Lens, Light, PointLight, SpotLight};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::{tuple3, vec3};
use crate::gnomon_error;

/// A perspective camera looking from `eye` at `target`: a vertical field of view `fov` in
/// degrees, `aspect` = width / height, near and far plane distances (the command line's
/// defaults: 60 degrees, 16:9, 1 and 400).
#[pyclass(frozen, module = "gnomon")]
pub struct Camera {
    pub(crate) camera: gnomon::Camera,
    eye: DVec3,
    target: DVec3,
    up: DVec3,
}

#[pymethods]
impl Camera {
    #[new]
    #[pyo3(signature = (eye, target, up = None, fov = 60.0, aspect = 16.0 / 9.0, near = 1.0, far = 400.0))]
    fn new(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        fov: f64,
        aspect: f64,
        near: f64,
        far: f64,
    ) -> PyResult<Self> {
        let (eye, target) = (vec3("eye", eye)?, vec3("target", target)?);
        let up = up.map_or(Ok(DVec3::Y), |u| vec3("up", u))?;
        let lens = Lens {
            fov_y_degrees: fov,
            aspect,
            near,
            far,
        };
        Self::from_parts(eye, target, up, lens)
    }

    /// Where the camera is.
    #[getter]
    fn eye<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        tuple3(py, self.eye)
    }

    /// What it looks at.
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        tuple3(py, self.target)
    }

    /// The image's up direction.
    #[getter]
    fn up<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        tuple3(py, self.up)
    }

    /// Vertical field of view, degrees.
    #[getter]
    fn fov(&self) -> f64 {
        self.camera.lens().fov_y_degrees
    }

    /// Width / height.
    #[getter]
    fn aspect(&self) -> f64 {
        self.camera.lens().aspect
    }

    /// Near plane distance.
    #[getter]
    fn near(&self) -> f64 {
        self.camera.lens().near
    }

    /// Far plane distance.
    #[getter]
    fn far(&self) -> f64 {
        self.camera.lens().far
    }

    fn __repr__(&self) -> String {
        let l = self.camera.lens();
        format!(
            "Camera(eye={:?}, target={:?}, up={:?}, fov={}, aspect={}, near={}, far={})",
            self.eye.to_array(),
            self.target.to_array(),
            self.up.to_array(),
            l.fov_y_degrees,
            l.aspect,
            l.near,
            l.far
        )
    }
}

impl Camera {
    /// The camera of these parts, refused as the core refuses it.
    pub(crate) fn from_parts(eye: DVec3, target: DVec3, up: DVec3, lens: Lens) -> PyResult<Self> {
        let camera = gnomon::Camera::look_at(eye, target, up, lens).map_err(gnomon_error)?;
        Ok(Self {
            camera,
            eye,
            target,
            up,
        })
    }
}

/// A directional light (the sun): `direction` is the way its light travels.
#[pyclass(frozen, module = "gnomon")]
pub struct Sun {
    light: DirectionalLight,
}

#[pymethods]
impl Sun {
    #[new]
    fn new(direction: &Bound<'_, PyAny>) -> PyResult<Self> {
        let light = DirectionalLight::new(vec3("direction", direction)?).map_err(gnomon_error)?;
        Ok(Self { light })
    }

    /// The unit direction the light travels.
    #[getter]
    fn direction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        tuple3(py, self.light.direction())
    }

    fn __repr__(&self) -> String {
        format!("Sun(direction={:?})", self.light.direction().to_array())
    }
}

/// A spot light at `position` shining along `direction`, its cone `half_angle` degrees wide
/// on each side, reaching `range` world units.
#[pyclass(frozen, module = "gnomon")]
pub struct Spot {
    light: SpotLight,
}

#[pymethods]
impl Spot {
    #[new]
    fn new(
        position: &Bound<'_, PyAny>,
        direction: &Bound<'_, PyAny>,
        half_angle: f64,
        range: f64,
    ) -> PyResult<Self> {
        let light = SpotLight::new(
            vec3("position", position)?,
            vec3("direction", direction)?,
            half_angle,
            range,
        )
        .map_err(gnomon_error)?;
        Ok(Self { light })
    }

    fn __repr__(&self) -> String {
        format!("Spot({:?})", self.light)
    }
}

/// A point light at `position` reaching `range` world units (shadowed by six cube faces or
/// two paraboloid maps).
#[pyclass(frozen, module = "gnomon")]
pub struct Point {
    light: PointLight,
}

#[pymethods]
impl Point {
    #[new]
    fn new(position: &Bound<'_, PyAny>, range: f64) -> PyResult<Self> {
        let light = PointLight::new(vec3("position", position)?, range).map_err(gnomon_error)?;
        Ok(Self { light })
    }

    fn __repr__(&self) -> String {
        format!("Point({:?})", self.light)
    }
}

/// The light object `obj` (a `Sun`, `Spot` or `Point`) as the core's light.
pub(crate) fn light_arg(obj: &Bound<'_, PyAny>) -> PyResult<Light> {
    if let Ok(sun) = obj.cast::<Sun>() {
        return Ok(Light::Directional(sun.get().light));
    }
    if let Ok(spot) = obj.cast::<Spot>() {
        return Ok(Light::Spot(spot.get().light));
    }
    if let Ok(point) = obj.cast::<Point>() {
        return Ok(Light::Point(point.get().light));
    }
    Err(gnomon_error(
        "light: expected a gnomon.Sun, gnomon.Spot or gnomon.Point",
    ))
}

/// The core's light as a Python light object.
pub(crate) fn light_object(py: Python<'_>, light: Light) -> PyResult<Bound<'_, PyAny>> {
    Ok(match light {
        Light::Directional(light) => Bound::new(py, Sun { light })?.into_any(),
        Light::Spot(light) => Bound::new(py, Spot { light })?.into_any(),
        Light::Point(light) => Bound::new(py, Point { light })?.into_any(),
    })
}
