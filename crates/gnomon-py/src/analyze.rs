//! `analyze`: every technique's perspective aliasing dp/ds along the view axis in the
//! LiSPSM paper's ideal configuration, as `gnomon analyze --json` gives it, with the curves
//! as numpy arrays.

use gnomon::analysis::IdealConfiguration;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::vector;
use crate::gnomon_error;
use crate::setup::resolution_arg;
use crate::values::{json_to_py, params};

/// The curves of `analyze`: one entry per technique.
#[pyclass(frozen, module = "gnomon")]
pub struct Analysis {
    analysis: gnomon_tools::analysis::Analysis,
}

#[pymethods]
impl Analysis {
    /// Near plane distance z_n.
    #[getter]
    fn z_n(&self) -> f64 {
        self.analysis.config.z_near
    }

    /// Far plane distance z_f.
    #[getter]
    fn z_f(&self) -> f64 {
        self.analysis.config.z_far
    }

    /// Angle gamma between the view direction and the light's, degrees.
    #[getter]
    fn gamma(&self) -> f64 {
        self.analysis.config.gamma_degrees
    }

    /// The map's texels on a side.
    #[getter]
    fn resolution(&self) -> u32 {
        self.analysis.shadow_map
    }

    /// The logarithmic limit's constant dp/ds, z_n ln(z_f / z_n) (texels of a map one unit
    /// wide): the least maximum any single map can reach.
    #[getter]
    fn logarithmic_ideal(&self) -> f64 {
        self.analysis.config.logarithmic_ideal()
    }

    /// The analysed techniques' names (`psm-paper` is PSM as the papers draw it).
    #[getter]
    fn techniques(&self) -> Vec<String> {
        self.analysis.rows.iter().map(|r| r.label.clone()).collect()
    }

    /// One technique's curve: `(z, dp_ds)`, two 1-D arrays (z spaced geometrically from z_n
    /// to z_f; dp/ds in texels).
    fn curve<'py>(
        &self,
        py: Python<'py>,
        technique: &str,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let row = self
            .analysis
            .rows
            .iter()
            .find(|r| r.label == technique)
            .ok_or_else(|| {
                gnomon_error(format!(
                    "unknown technique '{technique}' (analysed: {})",
                    self.techniques().join(", ")
                ))
            })?;
        let curve = row
            .curve
            .as_ref()
            .map_err(|e| gnomon_error(format!("{technique}: {e}")))?;
        Ok((vector(py, curve.z.clone()), vector(py, curve.dp_ds.clone())))
    }

    /// The summary of every technique as dicts (`technique`, `fallback`, `max`, `z_of_max`,
    /// `at_z_n`, `at_z_f`, `min`, `z_of_min`, and `z`, `dp_ds` arrays; `error` where a
    /// curve cannot be measured).
    #[getter]
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        let json = self.analysis.to_json();
        let rows = json["techniques"].as_array().cloned().unwrap_or_default();
        rows.iter()
            .zip(&self.analysis.rows)
            .map(|(value, row)| {
                let mut value = value.clone();
                if let Some(map) = value.as_object_mut() {
                    map.remove("curve");
                }
                let dict = json_to_py(py, &value)?;
                if let Ok(curve) = &row.curve {
                    dict.set_item("z", vector(py, curve.z.clone()))?;
                    dict.set_item("dp_ds", vector(py, curve.dp_ds.clone()))?;
                }
                Ok(dict)
            })
            .collect()
    }

    /// Exactly what `gnomon analyze --json` prints for the same arguments.
    fn to_json(&self) -> String {
        serde_json::to_string_pretty(&self.analysis.to_json()).expect("JSON of plain values")
    }

    fn __repr__(&self) -> String {
        format!(
            "Analysis(z_n={}, z_f={}, gamma={}, {} techniques)",
            self.z_n(),
            self.z_f(),
            self.gamma(),
            self.analysis.rows.len()
        )
    }
}

/// Perspective aliasing dp/ds along the view axis of every technique, measured from its
/// actual matrices in the LiSPSM paper's ideal configuration (view and light at `gamma`
/// degrees, near plane `zn`, far plane `zf`), at `samples` distances, in the texels of a
/// `resolution` map; as `gnomon analyze`. Keyword arguments are technique parameters, as in
/// `setup`. The paper's Figure 6 plots `uniform`, `psm-paper` and `lispsm` with the
/// logarithmic limit.
#[pyfunction]
#[pyo3(signature = (zn = 1.0, zf = 100.0, gamma = 90.0, samples = 200, resolution = 2048, **params))]
pub fn analyze(
    py: Python<'_>,
    zn: f64,
    zf: f64,
    gamma: f64,
    samples: usize,
    resolution: i64,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Analysis> {
    let technique_params = self::params(params)?;
    let resolution = resolution_arg(resolution)?;
    if samples < 2 {
        return Err(gnomon_error("samples: give at least 2"));
    }
    let config = IdealConfiguration::new(zn, zf, gamma).map_err(gnomon_error)?;
    let analysis = py
        .detach(|| gnomon_tools::analysis::analyze(config, &technique_params, samples, resolution))
        .map_err(gnomon_error)?;
    Ok(Analysis { analysis })
}
