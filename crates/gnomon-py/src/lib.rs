//! gnomon's Python module, `gnomon._gnomon` (the `gnomon` package re-exports it): cameras,
//! lights and scenes in; shadow-map setups, projections, aliasing curves and renders out, as
//! numpy arrays. Every front end's shared parts (technique names and parameters, the setup's
//! JSON, the curves) come from `gnomon-tools`, so that Python gives what `gnomon` prints.

mod analyze;
mod arrays;
mod compare;
mod objects;
mod render;
mod scene;
mod setup;
mod values;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The module's own allocator: it keeps freed memory for the next call, where the system's
/// returns large blocks to the kernel and a scene's next build faults them in again.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

create_exception!(
    gnomon,
    GnomonError,
    PyValueError,
    "Bad input to gnomon: the message names what is wrong, in one line."
);

/// A `GnomonError` with `error`'s one-line message.
pub(crate) fn gnomon_error(error: impl std::fmt::Display) -> PyErr {
    GnomonError::new_err(error.to_string())
}

#[pymodule]
fn _gnomon(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GnomonError", m.py().get_type::<GnomonError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("TECHNIQUES", gnomon::Technique::NAMES.to_vec())?;
    m.add_class::<objects::Camera>()?;
    m.add_class::<objects::Sun>()?;
    m.add_class::<objects::Spot>()?;
    m.add_class::<objects::Point>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<setup::Setup>()?;
    m.add_class::<setup::Map>()?;
    m.add_class::<analyze::Analysis>()?;
    m.add_class::<render::Frame>()?;
    m.add_function(wrap_pyfunction!(setup::setup, m)?)?;
    m.add_function(wrap_pyfunction!(setup::project, m)?)?;
    m.add_function(wrap_pyfunction!(analyze::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    Ok(())
}
