use std::fmt;

/// Why rendering failed.
#[derive(Debug)]
pub enum RenderError {
    /// No graphics adapter: no GPU driver and no software driver.
    NoAdapter(String),
    /// The adapter refused to create a device.
    Device(String),
    /// The GPU reported an error (validation, out of memory).
    Gpu(String),
    /// Bad input: image size, a setup the renderer cannot draw.
    Invalid(String),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::NoAdapter(detail) => write!(f, "no graphics adapter found ({detail})"),
            RenderError::Device(e) => write!(f, "cannot create a GPU device: {e}"),
            RenderError::Gpu(e) => write!(f, "GPU error: {e}"),
            RenderError::Invalid(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RenderError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_adapter_is_named_without_installation_advice() {
        let message = RenderError::NoAdapter("no Vulkan driver".into()).to_string();
        assert_eq!(message, "no graphics adapter found (no Vulkan driver)");
    }
}
