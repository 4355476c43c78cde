//! numpy in and out: arrays of numbers read as f64 with their shape checked (each refusal
//! names the argument), and the core's vectors and matrices written as numpy arrays.

use glam::{DMat4, DVec3};
use gnomon::Aabb;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::gnomon_error;

/// Reads `obj` as numbers and hands its shape and values (row-major) to `read`: a float64 or
/// float32 numpy array, or anything `numpy.asarray` makes floats of (lists, tuples); arrays
/// of other dtypes are refused rather than converted. A contiguous float64 array is read in
/// place, without a copy.
pub(crate) fn with_numbers<T>(
    arg: &str,
    obj: &Bound<'_, PyAny>,
    read: impl FnOnce(&[usize], &[f64]) -> PyResult<T>,
) -> PyResult<T> {
    if let Ok(array) = obj.cast::<PyArrayDyn<f64>>() {
        let array = array.readonly();
        return match array.as_slice() {
            Ok(slice) => read(array.shape(), slice),
            Err(_) => {
                let values: Vec<f64> = array.as_array().iter().copied().collect();
                read(array.shape(), &values)
            }
        };
    }
    if let Ok(array) = obj.cast::<PyArrayDyn<f32>>() {
        let array = array.readonly();
        let values: Vec<f64> = array.as_array().iter().map(|&v| f64::from(v)).collect();
        return read(array.shape(), &values);
    }
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        return Err(gnomon_error(format!(
            "{arg}: expected float64 or float32 values, got dtype {}",
            array.dtype()
        )));
    }
    let numpy = obj.py().import("numpy")?;
    let converted = numpy
        .call_method1("asarray", (obj, numpy.getattr("float64")?))
        .map_err(|_| {
            gnomon_error(format!(
                "{arg}: expected an array of numbers, got {}",
                type_name(obj)
            ))
        })?;
    with_numbers(arg, &converted, read)
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "an object".to_string(), |n| n.to_string())
}

fn shape_text(shape: &[usize]) -> String {
    let parts: Vec<String> = shape.iter().map(usize::to_string).collect();
    if parts.len() == 1 {
        format!("({},)", parts[0])
    } else {
        format!("({})", parts.join(", "))
    }
}

/// A 3-vector: a sequence or array of three numbers.
pub(crate) fn vec3(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<DVec3> {
    with_numbers(arg, obj, |shape, values| {
        if shape != [3] {
            return Err(gnomon_error(format!(
                "{arg}: expected 3 numbers (x, y, z), got shape {}",
                shape_text(shape)
            )));
        }
        Ok(DVec3::new(values[0], values[1], values[2]))
    })
}

/// Refuses a points argument of another shape than `(N, 3)`.
fn check_points_shape(arg: &str, shape: &[usize]) -> PyResult<()> {
    if shape.len() != 2 || shape[1] != 3 {
        return Err(gnomon_error(format!(
            "{arg}: expected shape (N, 3), got {}",
            shape_text(shape)
        )));
    }
    Ok(())
}

/// Points: an `(N, 3)` array.
pub(crate) fn points(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<DVec3>> {
    with_numbers(arg, obj, |shape, values| {
        check_points_shape(arg, shape)?;
        Ok(values
            .chunks_exact(3)
            .map(|p| DVec3::new(p[0], p[1], p[2]))
            .collect())
    })
}

/// Boxes: `(N, 2, 3)` (minimum and maximum corners) or `(N, 6)` (min x, y, z, max x, y, z).
pub(crate) fn boxes(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<Aabb>> {
    with_numbers(arg, obj, |shape, values| {
        // An empty list is no boxes.
        if !matches!(shape, [_, 2, 3] | [_, 6] | [0]) {
            return Err(gnomon_error(format!(
                "{arg}: expected shape (N, 2, 3) or (N, 6) (minimum and maximum corners), got {}",
                shape_text(shape)
            )));
        }
        // Sized once: collecting into a Result grows the vector by doubling.
        let mut out = Vec::with_capacity(values.len() / 6);
        for (i, b) in values.chunks_exact(6).enumerate() {
            let (min, max) = (DVec3::new(b[0], b[1], b[2]), DVec3::new(b[3], b[4], b[5]));
            out.push(Aabb::new(min, max).map_err(|e| gnomon_error(format!("{arg}[{i}]: {e}")))?);
        }
        Ok(out)
    })
}

/// Boxes as an `(N, 2, 3)` array.
pub(crate) fn boxes_array<'py>(py: Python<'py>, boxes: &[Aabb]) -> Bound<'py, PyAny> {
    let values: Vec<f64> = boxes
        .iter()
        .flat_map(|b| b.min().to_array().into_iter().chain(b.max().to_array()))
        .collect();
    Array3::from_shape_vec((boxes.len(), 2, 3), values)
        .expect("six values per box")
        .into_pyarray(py)
        .into_any()
}

/// A matrix as a `(4, 4)` array indexed `[row, column]`, so that `m @ p` transforms a
/// column vector `p`.
pub(crate) fn matrix<'py>(py: Python<'py>, m: &DMat4) -> Bound<'py, PyAny> {
    let rows = m.transpose().to_cols_array();
    Array2::from_shape_vec((4, 4), rows.to_vec())
        .expect("16 values")
        .into_pyarray(py)
        .into_any()
}

/// A vector of f64 as a 1-D array.
pub(crate) fn vector<'py>(py: Python<'py>, values: Vec<f64>) -> Bound<'py, PyAny> {
    Array1::from_vec(values).into_pyarray(py).into_any()
}

/// Points `(N, 3)` mapped point by point (`f` gives `None` where a point has no image): an
/// `(N, 3)` array, a row of NaN for each `None`.
pub(crate) fn map_points<'py>(
    arg: &str,
    obj: &Bound<'py, PyAny>,
    f: impl Fn(DVec3) -> Option<DVec3>,
) -> PyResult<Bound<'py, PyAny>> {
    let values = with_numbers(arg, obj, |shape, values| {
        check_points_shape(arg, shape)?;
        Ok(values
            .chunks_exact(3)
            .flat_map(|p| f(DVec3::new(p[0], p[1], p[2])).map_or([f64::NAN; 3], |q| q.to_array()))
            .collect::<Vec<f64>>())
    })?;
    Ok(Array2::from_shape_vec((values.len() / 3, 3), values)
        .expect("three values per point")
        .into_pyarray(obj.py())
        .into_any())
}

/// A 3-vector as a tuple.
pub(crate) fn tuple3<'py>(py: Python<'py>, v: DVec3) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, v.to_array())
}
