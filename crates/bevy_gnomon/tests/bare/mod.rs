//! A Bevy app with what the plugin reads (assets, meshes, transforms, cameras, lights) and no
//! renderer: for the plugin's tests and its bench.

use bevy::asset::AssetPlugin;
use bevy::camera::CameraPlugin;
use bevy::light::LightPlugin;
use bevy::mesh::MeshPlugin;
use bevy::prelude::*;
use bevy::transform::TransformPlugin;
use bevy_gnomon::GnomonShadowsPlugin;

/// The app, with the plugin or without (Bevy's own cascades alone).
pub fn app(with_plugin: bool) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin::default(),
        bevy::window::WindowPlugin {
            primary_window: None,
            ..default()
        },
        bevy::image::ImagePlugin::default(),
        MeshPlugin,
        TransformPlugin,
        CameraPlugin,
        LightPlugin,
    ));
    if with_plugin {
        app.add_plugins(GnomonShadowsPlugin);
    }
    app
}
