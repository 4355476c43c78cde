//! Typed errors for bad input.

use std::fmt;

use glam::DVec3;

/// Why a shadow setup could not be computed from the given input.
///
/// Every public constructor and [`crate::compute_setup`] reports bad input through this type;
/// no input makes the library panic or return a non-finite matrix.
#[derive(Debug, Clone, PartialEq)]
pub enum SetupError {
    /// A number was NaN or infinite.
    NonFinite {
        /// Which input held it.
        what: &'static str,
    },
    /// A number's magnitude was beyond what gnomon supports
    /// ([`crate::MAX_COORDINATE`] for positions and distances).
    OutOfRange {
        /// Which input held it.
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A direction had zero length (or was too short to normalise).
    ZeroDirection {
        /// Which direction.
        what: &'static str,
    },
    /// The camera's near and far planes do not satisfy `0 < near < far`.
    InvalidNearFar {
        /// The near plane distance given.
        near: f64,
        /// The far plane distance given.
        far: f64,
    },
    /// The vertical field of view was outside the open interval (0, 180) degrees.
    InvalidFieldOfView {
        /// The value given, in degrees.
        degrees: f64,
    },
    /// The aspect ratio was not a positive number.
    InvalidAspect {
        /// The value given.
        aspect: f64,
    },
    /// A camera `view_from_world` matrix was not a rigid transform (rotation plus translation).
    NotRigid,
    /// The camera's up vector was parallel to its view direction (or eye equals target).
    DegenerateView,
    /// A box had `min > max` along some axis.
    InvertedBox {
        /// The box's minimum corner.
        min: DVec3,
        /// The box's maximum corner.
        max: DVec3,
    },
    /// A box had zero size along every axis (a point).
    EmptyBox {
        /// Where the point lies.
        at: DVec3,
    },
    /// No scene box was given and there was no caster or receiver box to derive one from.
    EmptyScene,
    /// [`crate::SceneBounds::with_boxes_moved`] was given a different number of boxes.
    BoxCountChanged {
        /// Casters before and given.
        casters: (usize, usize),
        /// Receivers before and given.
        receivers: (usize, usize),
    },
    /// A spot light's cone half-angle was outside (0, 89] degrees.
    InvalidSpotAngle {
        /// The value given, in degrees.
        degrees: f64,
    },
    /// A spot light's range was not a positive number.
    InvalidRange {
        /// The value given.
        range: f64,
    },
    /// The shadow-map resolution or viewport inset was unusable.
    InvalidResolution {
        /// The resolution given, in texels.
        resolution: u32,
        /// The viewport inset given, in texels.
        viewport_inset: u32,
    },
    /// A technique parameter was outside its documented range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The computation produced a non-finite matrix. This is a bug in gnomon; the error is
    /// returned instead of a NaN matrix so that callers never draw with one.
    NumericalFailure {
        /// The technique that failed.
        technique: &'static str,
    },
    /// The technique makes several maps per light (SPPSM, cascades), which a point light's
    /// cube faces cannot hold.
    PointLightUnsupported {
        /// The technique.
        technique: &'static str,
    },
    /// Cascades picked by coverage that are not stable: a fitted cascade's map holds only its
    /// slice's depths and casters.
    CoverageNeedsStable,
    /// The technique is for point lights only (`cube`).
    NeedsPointLight {
        /// The technique.
        technique: &'static str,
    },
    /// A measurement ([`crate::analysis`]) cannot be taken from the given map.
    Unmeasurable {
        /// Why.
        what: &'static str,
    },
}

impl fmt::Display for SetupError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SetupError::NonFinite { what } => write!(f, "{what} is not a finite number"),
            SetupError::OutOfRange { what, value } => write!(
                f,
                "{what} = {value} is out of range (magnitudes up to {:e} are supported)",
                crate::MAX_COORDINATE
            ),
            SetupError::ZeroDirection { what } => write!(f, "{what} has zero length"),
            SetupError::InvalidNearFar { near, far } => {
                write!(
                    f,
                    "near and far must satisfy 0 < near < far (got near = {near}, far = {far})"
                )
            }
            SetupError::InvalidFieldOfView { degrees } => {
                write!(
                    f,
                    "field of view must be in (0, 180) degrees (got {degrees})"
                )
            }
            SetupError::InvalidAspect { aspect } => {
                write!(f, "aspect ratio must be from 1e-6 to 1e6 (got {aspect})")
            }
            SetupError::NotRigid => {
                write!(
                    f,
                    "view_from_world must be a rigid transform (rotation and translation)"
                )
            }
            SetupError::DegenerateView => write!(
                f,
                "camera view is degenerate: eye equals target or up is parallel to the view direction"
            ),
            SetupError::InvertedBox { min, max } => write!(
                f,
                "box is inverted: min ({}, {}, {}) exceeds max ({}, {}, {}) along some axis",
                min.x, min.y, min.z, max.x, max.y, max.z
            ),
            SetupError::EmptyBox { at } => {
                write!(
                    f,
                    "box is empty: zero size at ({}, {}, {})",
                    at.x, at.y, at.z
                )
            }
            SetupError::EmptyScene => {
                write!(
                    f,
                    "scene is empty: no scene box and no caster or receiver box"
                )
            }
            SetupError::BoxCountChanged { casters, receivers } => {
                write!(
                    f,
                    "moved boxes must keep their number: {} casters and {} receivers before, {} and {} given",
                    casters.0, receivers.0, casters.1, receivers.1
                )
            }
            SetupError::InvalidSpotAngle { degrees } => {
                write!(
                    f,
                    "spot light half-angle must be in (0, 89] degrees (got {degrees})"
                )
            }
            SetupError::InvalidRange { range } => {
                write!(f, "light range must be positive (got {range})")
            }
            SetupError::InvalidResolution {
                resolution,
                viewport_inset,
            } => {
                let range = crate::MIN_RESOLUTION..=crate::MAX_RESOLUTION;
                if range.contains(resolution) {
                    write!(
                        f,
                        "a viewport inset of {viewport_inset} texels is unusable on a \
                         {resolution}-texel shadow map (it must be below a quarter of the map)"
                    )
                } else {
                    write!(
                        f,
                        "shadow map resolution {resolution} is out of range (must be {} to {} \
                         texels)",
                        range.start(),
                        range.end()
                    )
                }
            }
            SetupError::InvalidParameter { name, value } => {
                write!(f, "parameter {name} = {value} is out of range")
            }
            SetupError::NumericalFailure { technique } => write!(
                f,
                "technique {technique} produced a non-finite matrix (a bug in gnomon; please report it)"
            ),
            SetupError::Unmeasurable { what } => write!(f, "cannot measure: {what}"),
            SetupError::PointLightUnsupported { technique } => write!(
                f,
                "technique {technique} has several maps per light and does not take point lights (use cube, focused, lispsm, psm, tsm, xpsm or uniform)"
            ),
            SetupError::CoverageNeedsStable => write!(
                f,
                "cascades pick a map by coverage only when they are stable (a fitted cascade's map holds only its slice)"
            ),
            SetupError::NeedsPointLight { technique } => {
                write!(f, "technique {technique} needs a point light")
            }
        }
    }
}

impl std::error::Error for SetupError {}

/// Checks that a scalar is finite and within [`crate::MAX_COORDINATE`].
pub(crate) fn check_scalar(what: &'static str, value: f64) -> Result<f64, SetupError> {
    if !value.is_finite() {
        return Err(SetupError::NonFinite { what });
    }
    if value.abs() > crate::MAX_COORDINATE {
        return Err(SetupError::OutOfRange { what, value });
    }
    Ok(value)
}

/// Checks that every component of a vector is finite and within [`crate::MAX_COORDINATE`].
pub(crate) fn check_vec(what: &'static str, v: DVec3) -> Result<DVec3, SetupError> {
    for c in v.to_array() {
        check_scalar(what, c)?;
    }
    Ok(v)
}

/// Checks a direction and returns it normalised.
pub(crate) fn check_direction(what: &'static str, v: DVec3) -> Result<DVec3, SetupError> {
    check_vec(what, v)?;
    let len = v.length();
    if len < 1e-12 * v.abs().max_element().max(1.0) || len == 0.0 {
        return Err(SetupError::ZeroDirection { what });
    }
    Ok(v / len)
}
