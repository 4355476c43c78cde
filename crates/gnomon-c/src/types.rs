//! The plain structs of the C interface and their conversion to the core's types (every
//! value checked by the core's constructors).

use glam::DVec3;
use gnomon::{Aabb, DirectionalLight, Lens, Light, PointLight, SpotLight};

/// The most maps one setup has (cascades: up to 8; a point light: 6 cube faces).
pub const GNOMON_MAX_MAPS: usize = 8;

/// A directional light (the sun): `direction` only.
pub const GNOMON_LIGHT_SUN: u32 = 0;
/// A spot light: `position`, `direction`, `half_angle_degrees`, `range`.
pub const GNOMON_LIGHT_SPOT: u32 = 1;
/// A point light: `position`, `range`.
pub const GNOMON_LIGHT_POINT: u32 = 2;

/// An axis-aligned box, world space: its minimum and maximum corners.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonBox {
    /// The minimum corner (x, y, z).
    pub min: [f64; 3],
    /// The maximum corner; every coordinate at least the minimum's.
    pub max: [f64; 3],
}

/// A perspective camera looking from `eye` at `target`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonCamera {
    /// Where the camera is.
    pub eye: [f64; 3],
    /// What it looks at.
    pub target: [f64; 3],
    /// The image's up direction (usually 0, 1, 0).
    pub up: [f64; 3],
    /// Vertical field of view, degrees (the command line's default: 60).
    pub fov_y_degrees: f64,
    /// Width / height of the image (default 16 / 9).
    pub aspect: f64,
    /// Near plane distance, > 0 (default 1).
    pub near_plane: f64,
    /// Far plane distance, > near (default 400).
    pub far_plane: f64,
}

/// A light: `kind` is one of GNOMON_LIGHT_SUN, GNOMON_LIGHT_SPOT and GNOMON_LIGHT_POINT;
/// the fields that kind does not read are ignored.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct GnomonLight {
    /// GNOMON_LIGHT_SUN, GNOMON_LIGHT_SPOT or GNOMON_LIGHT_POINT.
    pub kind: u32,
    /// Spot and point lights: where the light is.
    pub position: [f64; 3],
    /// Sun and spot lights: the direction the light travels.
    pub direction: [f64; 3],
    /// Spot lights: the cone's half-angle, degrees.
    pub half_angle_degrees: f64,
    /// Spot and point lights: how far the light reaches.
    pub range: f64,
}

impl GnomonBox {
    pub(crate) fn aabb(&self) -> Result<Aabb, gnomon::SetupError> {
        Aabb::new(DVec3::from_array(self.min), DVec3::from_array(self.max))
    }
}

impl GnomonCamera {
    pub(crate) fn camera(&self) -> Result<gnomon::Camera, gnomon::SetupError> {
        let lens = Lens {
            fov_y_degrees: self.fov_y_degrees,
            aspect: self.aspect,
            near: self.near_plane,
            far: self.far_plane,
        };
        gnomon::Camera::look_at(
            DVec3::from_array(self.eye),
            DVec3::from_array(self.target),
            DVec3::from_array(self.up),
            lens,
        )
    }
}

impl GnomonLight {
    pub(crate) fn light(&self) -> Result<Light, String> {
        let (position, direction) = (
            DVec3::from_array(self.position),
            DVec3::from_array(self.direction),
        );
        let light = match self.kind {
            GNOMON_LIGHT_SUN => DirectionalLight::new(direction).map(Light::Directional),
            GNOMON_LIGHT_SPOT => {
                SpotLight::new(position, direction, self.half_angle_degrees, self.range)
                    .map(Light::Spot)
            }
            GNOMON_LIGHT_POINT => PointLight::new(position, self.range).map(Light::Point),
            other => {
                return Err(format!(
                    "light kind {other} is not GNOMON_LIGHT_SUN (0), GNOMON_LIGHT_SPOT (1) or \
                     GNOMON_LIGHT_POINT (2)"
                ));
            }
        };
        light.map_err(|e| e.to_string())
    }
}
