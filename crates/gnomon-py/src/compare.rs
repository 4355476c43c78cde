//! `compare`: techniques drawn on one view and judged against the exact shadow volumes, as
//! a row of `gnomon compare --json` each.

use gnomon::Technique;
use gnomon_render::{MaskErrors, Percentiles, PixelMetrics, SureErrors};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::{Value, json};

use crate::gnomon_error;
use crate::objects::Camera;
use crate::render::Shot;
use crate::scene::Scene;
use crate::values::{json_to_py, params};

/// The techniques `compare` draws unless told: the single maps a user weighs and the cascades.
const DEFAULT_TECHNIQUES: [&str; 4] = ["focused", "lispsm", "sppsm", "cascades"];

/// Draws `scene` from `camera` lit by `light` with each of `techniques` and with the exact
/// shadow volumes, and judges each technique's shadow mask against the exact one on the
/// pixels that face the light: one dict per technique with the keys of
/// `gnomon compare --json`'s rows (`technique`, `shadow_map`, `maps`, `fallback`,
/// `wrong_percent`, `false_shadow_percent`, `missed_shadow_percent`, `compared_pixels`,
/// `unsure_percent`, `sure_wrong_percent`, `undersampling` and `area_undersampling`
/// percentiles, `setup_us`, `frame_ms`). Keyword
/// arguments are technique parameters, each read by at least one of the techniques.
#[pyfunction]
#[pyo3(signature = (scene, camera, light, techniques = None, size = (640, 360), resolution = 2048, **params))]
#[allow(clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    scene: PyRef<'py, Scene>,
    camera: PyRef<'py, Camera>,
    light: &Bound<'py, PyAny>,
    techniques: Option<Vec<String>>,
    size: (i64, i64),
    resolution: i64,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let names =
        techniques.unwrap_or_else(|| DEFAULT_TECHNIQUES.iter().map(|t| t.to_string()).collect());
    let techniques = named_techniques(&names, params)?;
    let shot = Shot::new(&scene, &camera, light, size, resolution)?;
    let rows = py
        .detach(|| {
            let mut renderer = shot.open_renderer()?;
            let exact = shot.draw_volumes(&mut renderer)?;
            techniques
                .iter()
                .zip(&names)
                .map(|(technique, name)| {
                    let (frame, setup, setup_us) = shot.draw_maps(&mut renderer, technique)?;
                    Ok(row(
                        name,
                        &frame,
                        &exact.mask,
                        &setup,
                        setup_us,
                        shot.resolution,
                    ))
                })
                .collect::<Result<Vec<Value>, String>>()
        })
        .map_err(gnomon_error)?;
    rows.iter().map(|r| json_to_py(py, r)).collect()
}

/// The techniques by name, each with the parameters, which must each be read by one of them.
fn named_techniques(
    names: &[String],
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Vec<Technique>> {
    if names.is_empty() {
        return Err(gnomon_error("techniques: give at least one"));
    }
    let params = params(kwargs)?;
    let techniques = names
        .iter()
        .map(|name| {
            let technique = name.trim().parse::<Technique>().map_err(gnomon_error)?;
            Ok(params.apply(technique))
        })
        .collect::<PyResult<Vec<_>>>()?;
    params.check_used_by(&techniques).map_err(gnomon_error)?;
    Ok(techniques)
}

fn row(
    name: &str,
    frame: &gnomon_render::Frame,
    exact_mask: &[u8],
    setup: &gnomon::ShadowSetup,
    setup_us: f64,
    resolution: u32,
) -> Value {
    let metrics = frame.metrics.as_ref().expect("metrics asked for");
    let errors = MaskErrors::of(&frame.mask, exact_mask, &metrics.n_dot_l);
    let sure = SureErrors::of(&frame.mask, exact_mask, &metrics.n_dot_l, &metrics.unsure);
    let t = frame.timings;
    json!({
        "technique": name,
        "shadow_map": resolution,
        "maps": setup.maps.len(),
        "fallback": setup.fallback().map(|f| f.name()),
        "wrong_percent": errors.wrong_percent(),
        "false_shadow_percent": errors.false_shadow_percent(),
        "missed_shadow_percent": errors.missed_shadow_percent(),
        "compared_pixels": errors.compared,
        "unsure_percent": sure.unsure_percent(),
        "sure_wrong_percent": sure.sure_wrong_percent(),
        "undersampling": percentiles(metrics, &metrics.undersampling),
        "area_undersampling": percentiles(metrics, &metrics.area),
        "setup_us": setup_us,
        "frame_ms": setup_us / 1e3 + t.shadow_pass_ms + t.main_pass_ms,
    })
}

fn percentiles(metrics: &PixelMetrics, values: &[f32]) -> Value {
    metrics
        .percentiles(values)
        .map_or(Value::Null, |p: Percentiles| {
            json!({"p50": p.p50, "p95": p.p95, "p99": p.p99, "max": p.max, "pixels": p.pixels})
        })
}
