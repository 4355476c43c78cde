//! # gnomon
//!
//! The GPU-free core of gnomon: a camera, a light and the scene's bounds in, shadow-map
//! matrices out. No GPU, no I/O; math in `f64` with [glam].
//!
//! ```
//! use gnomon::{Aabb, Camera, DirectionalLight, Focused, Lens, Light, MapSettings, SceneBounds, compute_setup};
//! use glam::DVec3;
//!
//! let camera = Camera::look_at(DVec3::new(0.0, 2.0, 10.0), DVec3::ZERO, DVec3::Y, Lens::default())?;
//! let light = Light::Directional(DirectionalLight::new(DVec3::new(-1.0, -2.0, -0.5))?);
//! let ground = Aabb::new(DVec3::new(-50.0, -0.1, -50.0), DVec3::new(50.0, 0.0, 50.0))?;
//! let crate_box = Aabb::new(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 2.0, 1.0))?;
//! let scene = SceneBounds::new(vec![crate_box], vec![ground, crate_box], None)?;
//! let setup = compute_setup(&Focused, &camera, &light, &scene, MapSettings::default())?;
//! let map = &setup.maps[0];
//! // The crate's top lands in the map, inside the one-texel border.
//! let p = map.project(DVec3::new(0.0, 2.0, 0.0)).unwrap();
//! assert!(p.x.abs() <= map.inset_ndc() && p.y.abs() <= map.inset_ndc());
//! # Ok::<(), gnomon::SetupError>(())
//! ```
//!
//! Conventions: right-handed world, +Y up; cameras look down their view-space -Z; clip-space
//! depth in [0, 1] as in wgpu; matrices are named `a_from_b` (`clip_from_world` takes world
//! points to clip space).
//!
//! Techniques (each cites its paper): [`Uniform`] (SSM), [`Focused`] (FSM with unit cube
//! clipping), [`Lispsm`] (LiSPSM), [`Tsm`] (TSM), [`Xpsm`] (XPSM), [`Psm`] (PSM), [`Sppsm`]
//! (two maps and a separating plane), [`Cascades`] (a map per slice of the view, each fitted by
//! a single-map technique, or stable cascades), [`Cube`] (a point light's six faces, each
//! focused; the single-map techniques take point lights per face too), [`DualParaboloid`] (a
//! point light's two hemispheres). The warps are limited so that they sample the
//! frame's [`ViewSamples`] no more coarsely than the focused map. Every technique implements
//! [`ShadowTechnique`];
//! [`Technique`] names them all. [`analysis`] measures aliasing from the matrices;
//! [`volumes`] builds exact shadow volumes.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod analysis;
pub mod area_light;
mod body;
mod bounds;
mod bvh;
mod camera;
mod error;
mod focus;
mod frame;
pub mod geometry;
mod light;
mod light_space;
mod parallel;
pub mod planar;
mod put_off;
mod samples;
mod setup;
pub mod techniques;
pub mod volumes;

pub use body::convex_body_b;
pub use bounds::{Aabb, SceneBounds};
pub use bvh::BoxIndex;
pub use camera::{Camera, Lens};
pub use error::SetupError;
pub use light::{
    CUBE_FACE_BORDER_TEXELS, CubeFace, DirectionalLight, Light, PointLight, SPOT_NEAR_FRACTION,
    SpotLight, cube_face_tangent,
};
pub use samples::{ViewSample, ViewSamples, undersampling};
pub use setup::{
    CascadeSlices, CastersBySide, CubeFaceMaps, Diagnostics, Fallback, LightFrameKind,
    MAX_CASCADES, MAX_RESOLUTION, MIN_RESOLUTION, MapProjection, MapSelection, MapSettings,
    PARABOLOID_MARGIN_DEGREES, PARABOLOID_SCALE, SetupInput, ShadowMap, ShadowSetup,
    ShadowTechnique, Technique, UnknownTechnique, compute_setup, compute_setup_with_samples,
};
pub use techniques::{
    ADAPTIVE_HYSTERESIS, CascadeFit, CascadeSelect, CascadeSplit, Cascades, Cube, DualParaboloid,
    Focused, Lispsm, PerspectiveMap, Psm, Sppsm, Tsm, Uniform, Xpsm,
};

/// Largest magnitude accepted for positions and distances (world units). Beyond it `f32`
/// GPU matrices lose all precision; inputs above it are rejected with
/// [`SetupError::OutOfRange`].
pub const MAX_COORDINATE: f64 = 1e9;
