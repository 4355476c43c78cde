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
    /// Bad input: an image size, a scene or a setup the renderer cannot draw.
    Invalid(InvalidInput),
}

/// Input the renderer cannot draw; each names the value at fault so that a caller can
/// report it or correct it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum InvalidInput {
    /// An image or target size outside 1 to the device's largest texture.
    ImageSize {
        /// What the size is of (an image, a target).
        what: &'static str,
        /// The width asked for, in pixels or texels.
        width: u32,
        /// The height asked for, in pixels or texels.
        height: u32,
        /// The largest allowed.
        max: u32,
    },
    /// A shadow map larger than the device's largest texture.
    MapTooLarge {
        /// The map's side in texels.
        resolution: u32,
        /// The largest allowed.
        max: u32,
    },
    /// A shadow map whose inset border leaves no texel inside.
    MapInsideInset {
        /// The map's side in texels.
        resolution: u32,
        /// The map's inset border in texels.
        inset: u32,
    },
    /// A far plane beyond the distance the renderer's view-relative floats hold precisely.
    FarPlane {
        /// The far plane distance given.
        far: f64,
        /// The largest allowed.
        max: f64,
    },
    /// More shadowed lights in one frame than the renderer's light table holds.
    TooManyLights {
        /// How many were given.
        count: usize,
        /// The largest allowed.
        max: usize,
    },
    /// More shadow maps in one frame than the atlas holds.
    TooManyMaps {
        /// How many were given.
        count: usize,
        /// The largest allowed.
        max: usize,
    },
    /// A setup whose map count does not fit the way its maps are selected.
    MapsForSelection {
        /// The setup's technique.
        technique: String,
        /// How many maps the setup has.
        maps: usize,
        /// How the maps are selected.
        selection: &'static str,
    },
    /// An instance index past the scene's instances.
    NoInstance {
        /// The index given.
        index: usize,
        /// How many were given.
        count: usize,
    },
    /// An instance that names a mesh the scene does not have.
    InstanceMesh {
        /// The instance's name.
        instance: String,
        /// The mesh index.
        mesh: usize,
        /// How many were given.
        count: usize,
    },
    /// A transform with a NaN or infinite entry (`what` names whose).
    NonFiniteTransform {
        /// What the size is of (an image, a target).
        what: &'static str,
    },
    /// A caster vertex stride that cannot hold a position.
    CasterStride {
        /// The stride given, in bytes.
        stride: u64,
    },
    /// Caster transforms written before any frame was prepared.
    FrameNotPrepared,
    /// Shadow volumes asked for without a light.
    NoLights,
    /// Soft-shadow light clusters of different sizes, or empty ones.
    UnevenClusters,
    /// An alpha mask larger than the device's largest texture, or with the wrong texel count.
    AlphaMask {
        /// The mesh index.
        mesh: usize,
        /// The width asked for, in pixels or texels.
        width: u32,
        /// The height asked for, in pixels or texels.
        height: u32,
        /// The largest allowed.
        max: u32,
    },
    /// A single mesh's display height that is not positive and finite up to 1e7.
    MeshHeight(f64),
    /// A mesh whose bounds have no height to scale.
    FlatMesh {
        /// The mesh's name.
        name: String,
        /// Its bounds, lowest to highest corner.
        bounds: String,
    },
    /// More vertices than 32-bit indices reach.
    TooManyVertices,
    /// A probe point that the probe pass did not draw (behind the camera, say).
    ProbeNotDrawn,
    /// A parameter the core refused (an area light's radius).
    Setup(gnomon::SetupError),
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

impl From<InvalidInput> for RenderError {
    fn from(e: InvalidInput) -> Self {
        RenderError::Invalid(e)
    }
}

impl fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use InvalidInput as I;
        match self {
            I::ImageSize {
                what,
                width,
                height,
                max,
            } => write!(
                f,
                "{what} size {width}x{height} is outside 1..={max} (this GPU's largest texture)"
            ),
            I::MapTooLarge { resolution, max } => {
                write!(f, "shadow map {resolution} exceeds the GPU's limit {max}")
            }
            I::MapInsideInset { resolution, inset } => {
                write!(
                    f,
                    "shadow map {resolution} has no texels inside its inset {inset}"
                )
            }
            I::FarPlane { far, max } => write!(
                f,
                "a far plane {far} away is beyond what the renderer draws precisely ({max})"
            ),
            I::TooManyLights { count, max } => {
                write!(f, "{count} shadowed lights in one frame; at most {max}")
            }
            I::TooManyMaps { count, max } => {
                write!(f, "{count} shadow maps in one frame; at most {max}")
            }
            I::MapsForSelection {
                technique,
                maps,
                selection,
            } => write!(
                f,
                "setup '{technique}' has {maps} maps for a {selection} selection"
            ),
            I::NoInstance { index, count } => write!(f, "instance {index} of {count}"),
            I::InstanceMesh {
                instance,
                mesh,
                count,
            } => write!(f, "instance '{instance}' names mesh {mesh} of {count}"),
            I::NonFiniteTransform { what } => write!(f, "{what} transform must be finite"),
            I::CasterStride { stride } => write!(
                f,
                "a caster vertex stride of {stride} bytes cannot hold a position (three f32, 4-byte aligned)"
            ),
            I::FrameNotPrepared => {
                write!(f, "prepare the frame before writing caster transforms")
            }
            I::NoLights => write!(f, "shadow volumes need at least one light"),
            I::UnevenClusters => write!(
                f,
                "soft shadows need clusters of one size, at least one sample each"
            ),
            I::AlphaMask {
                mesh,
                width,
                height,
                max,
            } => write!(
                f,
                "mesh {mesh}'s alpha mask is {width}x{height} texels: this device takes at most {max} a side"
            ),
            I::MeshHeight(height) => write!(
                f,
                "the mesh's height must be a positive number up to 1e7, got {height}"
            ),
            I::FlatMesh { name, bounds } => {
                write!(
                    f,
                    "mesh '{name}' has no height to scale (its bounds are {bounds})"
                )
            }
            I::TooManyVertices => write!(f, "the scene has more than 2^32 vertices"),
            I::ProbeNotDrawn => write!(f, "a probe point was not drawn"),
            I::Setup(e) => write!(f, "{e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_adapter_is_named_without_installation_advice() {
        let message = RenderError::NoAdapter("no Vulkan driver".into()).to_string();
        assert_eq!(message, "no graphics adapter found (no Vulkan driver)");
    }

    #[test]
    fn invalid_input_names_the_value_at_fault() {
        let e = RenderError::from(InvalidInput::TooManyMaps { count: 40, max: 32 });
        assert_eq!(e.to_string(), "40 shadow maps in one frame; at most 32");
        let e = RenderError::from(InvalidInput::NonFiniteTransform {
            what: "an instance",
        });
        assert_eq!(e.to_string(), "an instance transform must be finite");
    }
}
