//! What every gnomon front end shares (the command line, the Python and the C bindings), so
//! that each gives the same answer for the same input: techniques by name with their
//! parameters ([`params`]), a setup as JSON ([`setup_json`]) and `analyze`'s aliasing curves
//! ([`analysis`]).

#![forbid(unsafe_code)]

pub mod analysis;
pub mod params;
mod setup_json;

pub use params::TechniqueParams;
pub use setup_json::setup_json;

use gnomon::Technique;

/// Bad input from a front end's caller: one line that names what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsageError(pub String);

impl UsageError {
    /// An error with this message.
    pub fn new(message: impl Into<String>) -> Self {
        UsageError(message.into())
    }
}

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// The shadow-map technique named `name` (one of [`Technique::NAMES`]) with `params`
/// applied, refused where it reads none of the parameters given.
pub fn map_technique(name: &str, params: &TechniqueParams) -> Result<Technique, UsageError> {
    // The core's error names the known techniques.
    let technique = name
        .trim()
        .parse::<Technique>()
        .map_err(|e| UsageError::new(e.to_string()))?;
    let technique = params.apply(technique);
    params.check_used_by(&[technique])?;
    Ok(technique)
}
