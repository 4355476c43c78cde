//! gnomon's shadow fits inside Bevy: put [`GnomonShadows`] on a `DirectionalLight` and its
//! cascades are fitted by gnomon (focused, LiSPSM or XPSM maps per slice, stable or not)
//! instead of Bevy's spheres, drawn by Bevy's own renderer.
//!
//! ```no_run
//! use bevy_app::App;
//! use bevy_gnomon::{GnomonShadows, GnomonShadowsPlugin};
//! # fn spawn(app: &mut App) {
//! app.add_plugins(GnomonShadowsPlugin);
//! app.world_mut().spawn((bevy_light::DirectionalLight::default(), GnomonShadows::default()));
//! # }
//! ```
//!
//! Each frame, after Bevy has built its cascades and before it derives the light's frusta
//! from them, the plugin runs gnomon's setup for each active camera and writes the light's
//! `Cascades` (one list per camera) and the bounds and overlap of its
//! `CascadeShadowConfig`, which Bevy's shader picks a cascade by. The scene's boxes come
//! from the meshes' `Aabb` and `GlobalTransform` (`NotShadowCaster` and `NotShadowReceiver`
//! honoured), kept between frames and refitted when they move.
//!
//! Bevy draws a map as gnomon means it when its clip z carries depth and a point picks its
//! map by view depth: uniform, focused, LiSPSM and XPSM fits, single or as cascades. TSM,
//! PSM and SPPSM are refused ([`Drawable`]). Warped fits need the device's
//! `DEPTH_CLIP_CONTROL`: without it Bevy emulates unclipped depth by clamping clip z before
//! the divide by w, which is right only for orthographic maps; an app on such a device
//! inserts [`DepthClipControl`]`(false)` and warped fits are refused.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod convert;
mod fit;
mod scene;
mod settings;

use bevy_app::{App, Plugin, PostUpdate};
use bevy_camera::visibility::VisibilitySystems;
use bevy_ecs::schedule::{IntoScheduleConfigs, SystemSet};
use bevy_light::SimulationLightSystems;
use bevy_transform::TransformSystems;

pub use fit::fit_cascades;
pub use scene::{GnomonScene, track_scene};
pub use settings::{
    BevyCascadeConfig, DepthClipControl, Drawable, GnomonShadows, GnomonShadowsStatus,
    MAX_BEVY_CASCADES, NotDrawable, keep_bevy_config,
};

/// Re-exported so that an app names techniques without depending on gnomon itself.
pub use gnomon;

/// The plugin's systems, in `PostUpdate`.
#[derive(Debug, Hash, PartialEq, Eq, Clone, SystemSet)]
pub enum GnomonShadowSystems {
    /// A light's own cascade configuration is saved when gnomon takes it over and given
    /// back when it stops (before Bevy builds its cascades).
    KeepBevyConfig,
    /// The scene's boxes follow the meshes (after transforms and bounds are up to date).
    TrackScene,
    /// The fits replace Bevy's cascades (after Bevy builds them, before it derives the
    /// light frusta that cull the shadow casters).
    FitCascades,
}

/// Adds the systems that fit every [`GnomonShadows`] light's cascades with gnomon.
#[derive(Default)]
pub struct GnomonShadowsPlugin;

impl Plugin for GnomonShadowsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<GnomonScene>()
            .init_resource::<DepthClipControl>()
            .configure_sets(
                PostUpdate,
                (
                    GnomonShadowSystems::KeepBevyConfig
                        .before(SimulationLightSystems::UpdateDirectionalLightCascades),
                    GnomonShadowSystems::TrackScene
                        .after(VisibilitySystems::CalculateBounds)
                        .after(TransformSystems::Propagate),
                    GnomonShadowSystems::FitCascades
                        .after(GnomonShadowSystems::TrackScene)
                        .after(SimulationLightSystems::UpdateDirectionalLightCascades)
                        .before(SimulationLightSystems::UpdateLightFrusta),
                ),
            )
            .add_systems(
                PostUpdate,
                (
                    keep_bevy_config.in_set(GnomonShadowSystems::KeepBevyConfig),
                    track_scene.in_set(GnomonShadowSystems::TrackScene),
                    fit_cascades.in_set(GnomonShadowSystems::FitCascades),
                ),
            );
    }
}
