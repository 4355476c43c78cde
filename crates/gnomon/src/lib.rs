//! # gnomon
//!
//! The GPU-free core of gnomon: a camera, a light and the scene's bounds in, shadow-map
//! matrices out. No GPU, no I/O; math in `f64` with [glam](https://docs.rs/glam).
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
//! ## Cascades
//!
//! Four LiSPSM cascades: each map carries the view depths it serves, and its own diagnostics
//! say whether it fell back. A point outside a map reads as lit, so most of the frame lies
//! outside any one cascade's map; [`ShadowSetup::map_for`] picks the map a point reads.
//!
//! ```
//! use gnomon::{Aabb, Camera, Cascades, DirectionalLight, Lens, Light, MapSettings, SceneBounds, compute_setup};
//! use glam::DVec3;
//!
//! let lens = Lens { near: 0.5, far: 300.0, ..Lens::default() };
//! let camera = Camera::look_at(DVec3::new(0.0, 1.7, 0.0), DVec3::new(0.0, 1.0, -100.0), DVec3::Y, lens)?;
//! let light = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -0.6, -0.4))?);
//! let ground = Aabb::new(DVec3::new(-500.0, -1.0, -500.0), DVec3::new(500.0, 0.0, 500.0))?;
//! let towers: Vec<Aabb> = (0..20)
//!     .map(|i| {
//!         let min = DVec3::new(-40.0 + 4.0 * i as f64, 0.0, -10.0 - 15.0 * i as f64);
//!         Aabb::new(min, min + DVec3::new(3.0, 12.0, 3.0))
//!     })
//!     .collect::<Result<_, _>>()?;
//! let mut receivers = towers.clone();
//! receivers.push(ground);
//! let scene = SceneBounds::new(towers, receivers, None)?;
//!
//! let setup = compute_setup(&Cascades::default(), &camera, &light, &scene, MapSettings::with_resolution(2048))?;
//! assert_eq!(setup.maps.len(), 4);
//! for (i, map) in setup.maps.iter().enumerate() {
//!     let [near, far] = map.view_depth_range.expect("a cascade serves a range of view depths");
//!     let fell_back = &setup.map_diagnostics(i).fallbacks;
//!     println!("cascade {i}: view depths {near:.1} to {far:.1}, fallbacks {fell_back:?}");
//! }
//! // A point 20 m ahead reads the first cascade.
//! assert_eq!(setup.map_for(DVec3::new(0.0, 0.0, -20.0)), Some(0));
//! # Ok::<(), gnomon::SetupError>(())
//! ```
//!
//! ## Your own view samples
//!
//! The warp limit judges a warp on what the frame's pixels see of the lit receivers. Without
//! samples, the core casts rays at the receiver boxes; an engine that has a depth and normal
//! buffer can hand in its own surface points instead ([`ViewSamples::from_surface_points`]),
//! which follow the real surfaces rather than their boxes.
//!
//! ```
//! use gnomon::{Aabb, Camera, DirectionalLight, Lens, Light, Lispsm, MapSettings, SceneBounds, ViewSamples, compute_setup_with_samples};
//! use glam::DVec3;
//!
//! let camera = Camera::look_at(DVec3::new(0.0, 3.0, 20.0), DVec3::ZERO, DVec3::Y, Lens::default())?;
//! let light = Light::Directional(DirectionalLight::new(DVec3::new(-0.5, -1.0, -0.3))?);
//! let ground = Aabb::new(DVec3::new(-50.0, -0.1, -50.0), DVec3::new(50.0, 0.0, 50.0))?;
//! let pillar = Aabb::new(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 6.0, 1.0))?;
//! let scene = SceneBounds::new(vec![pillar], vec![ground, pillar], None)?;
//!
//! // (position, normal) of what the pixels see: here a grid on the ground, as a depth
//! // buffer's readback would give.
//! let points = (0..32).flat_map(|i| (0..16).map(move |j| {
//!     (DVec3::new(-16.0 + i as f64, 0.0, -10.0 + j as f64), DVec3::Y)
//! }));
//! let samples = ViewSamples::from_surface_points(&camera, &light, points);
//! assert!(!samples.is_empty());
//! let setup = compute_setup_with_samples(&Lispsm::default(), &camera, &light, &scene, MapSettings::default(), &samples)?;
//! // The limit ran on these samples: the warp kept some strength, or the focused map was used.
//! assert!(setup.diagnostics.warp_strength.is_some());
//! # Ok::<(), gnomon::SetupError>(())
//! ```
//!
//! Conventions: right-handed world, +Y up; cameras look down their view-space -Z; clip-space
//! depth in [0, 1] as in wgpu; matrices are named `a_from_b` (`clip_from_world` takes world
//! points to clip space); a point outside a map reads as lit ([`ShadowMap`]).
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
mod boxes;
mod bvh;
mod camera;
mod diagnostics;
mod error;
mod focus;
mod frame;
pub mod geometry;
mod light;
mod light_space;
mod map;
mod parallel;
pub mod planar;
mod put_off;
mod samples;
mod setup;
mod technique;
pub mod techniques;
pub mod volumes;

pub use body::convex_body_b;
pub use bounds::SceneBounds;
pub use boxes::Aabb;
pub use bvh::BoxIndex;
pub use camera::{Camera, Lens};
pub use diagnostics::{CastersBySide, Diagnostics, Fallback, LightFrameKind, MapDiagnostics};
pub use error::SetupError;
pub use light::{
    CUBE_FACE_BORDER_TEXELS, CubeFace, DirectionalLight, Light, PointLight, SPOT_NEAR_FRACTION,
    SpotLight, cube_face_tangent,
};
pub use map::{
    CascadeSlices, CubeFaceMaps, MAX_CASCADES, MapProjection, MapSelection, MapSettings,
    PARABOLOID_MARGIN_DEGREES, PARABOLOID_SCALE, ShadowMap, ShadowSetup,
};
pub use samples::{ViewSample, ViewSamples, undersampling};
pub use setup::{Technique, UnknownTechnique, compute_setup, compute_setup_with_samples};
pub use technique::{SetupInput, ShadowTechnique};
pub use techniques::{
    ADAPTIVE_HYSTERESIS, CascadeFit, CascadeSelect, CascadeSplit, Cascades, Cube, DualParaboloid,
    Focused, Lispsm, PerspectiveMap, Psm, Sppsm, Tsm, Uniform, Xpsm,
};

/// Largest magnitude accepted for positions and distances (world units). Beyond it `f32`
/// GPU matrices lose all precision; inputs above it are rejected with
/// [`SetupError::OutOfRange`].
pub const MAX_COORDINATE: f64 = 1e9;

/// Smallest supported shadow-map resolution, in texels.
pub const MIN_RESOLUTION: u32 = 8;
/// Largest supported shadow-map resolution, in texels.
pub const MAX_RESOLUTION: u32 = 32768;
