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
            RenderError::NoAdapter(detail) => write!(
                f,
                "no graphics adapter found ({detail}); on a machine without a GPU driver install \
                 Mesa's software Vulkan driver (apt-get install -y mesa-vulkan-drivers) or its \
                 GL driver (apt-get install -y libegl-mesa0 libgl1-mesa-dri, WGPU_BACKEND=gl)"
            ),
            RenderError::Device(e) => write!(f, "cannot create a GPU device: {e}"),
            RenderError::Gpu(e) => write!(f, "GPU error: {e}"),
            RenderError::Invalid(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RenderError {}
