//! gnomon's demo scene (or a scene file) in Bevy, its sun's shadows from Bevy's cascades or
//! gnomon's fits: G switches between them, the title shows the fit's setup time and the
//! frame time, V goes to the next named view. With `--frames N` it runs headless and writes a screenshot and the shadow
//! mask.
//!
//! ```text
//! cargo run --release -p bevy_gnomon --example scene -- --view street
//! cargo run --release -p bevy_gnomon --example scene -- --view street --size 640x360 \
//!     --frames 3 --screenshot street.png --mask street-mask.png
//! ```

mod args;
mod headless;
mod world;

use std::process::ExitCode;

use bevy::prelude::*;
use bevy::window::WindowResolution;
use bevy_gnomon::{GnomonShadows, GnomonShadowsStatus};
use clap::Parser;

use crate::args::{Options, Shadows};
use crate::world::{Loaded, Settings};

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let prepared = world::load(cli.scene_file.as_deref())
        .and_then(|loaded| args::options(cli, &loaded.views).map(|o| (o, loaded)));
    let (options, loaded) = match prepared {
        Ok(p) => p,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    // Bevy panics where it finds no GPU: say so in one line.
    std::panic::set_hook(Box::new(|info| {
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "Bevy stopped".into());
        let line = message.lines().next().unwrap_or_default().to_string();
        eprintln!("error: {line} (a Vulkan driver: Mesa's lavapipe on a machine without a GPU)");
    }));
    if options.frames.is_some() {
        return match headless::run(&options, loaded) {
            Ok(()) => ExitCode::SUCCESS,
            Err(message) => {
                eprintln!("error: {message}");
                ExitCode::FAILURE
            }
        };
    }
    windowed(options, loaded);
    ExitCode::SUCCESS
}

/// The scene in a window, until it is closed.
fn windowed(options: Options, loaded: Loaded) {
    let (w, h) = options.size;
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "gnomon in Bevy".into(),
            resolution: WindowResolution::new(w, h),
            ..default()
        }),
        ..default()
    }));
    world::configure(&mut app, &options, loaded);
    app.insert_resource(world::Target(None))
        .add_systems(Update, (switch_shadows, next_view, show_times));
    app.run();
}

/// G switches the sun between Bevy's cascades and gnomon's.
fn switch_shadows(
    keys: Res<ButtonInput<KeyCode>>,
    settings: Res<Settings>,
    mut commands: Commands,
    suns: Query<(Entity, Has<GnomonShadows>), With<DirectionalLight>>,
) {
    if !keys.just_pressed(KeyCode::KeyG) {
        return;
    }
    for (sun, gnomon) in &suns {
        if gnomon {
            commands.entity(sun).remove::<GnomonShadows>();
        } else {
            commands
                .entity(sun)
                .insert(world::gnomon_shadows(&settings.0));
        }
    }
}

/// V moves the camera and the sun to the scene's next named view with a sun.
fn next_view(world: &mut World, mut index: Local<usize>) {
    if !world
        .resource::<ButtonInput<KeyCode>>()
        .just_pressed(KeyCode::KeyV)
    {
        return;
    }
    let views = world.resource::<world::Views>().0.clone();
    let mut settings = world.resource::<Settings>().0.clone();
    let gnomon = world
        .query_filtered::<(), (With<DirectionalLight>, With<GnomonShadows>)>()
        .iter(world)
        .next()
        .is_some();
    settings.shadows = if gnomon {
        Shadows::Gnomon
    } else {
        Shadows::Bevy
    };
    for _ in 0..views.len() {
        *index = (*index + 1) % views.len();
        if let Some(options) = args::for_view(&settings, &views[*index]) {
            world::set_view(world, &options);
            return;
        }
    }
}

/// The window's title: whose shadows, gnomon's setup time, the frame time.
fn show_times(
    time: Res<Time>,
    mut windows: Query<&mut Window>,
    suns: Query<Option<&GnomonShadowsStatus>, (With<DirectionalLight>, With<GnomonShadows>)>,
    mut smoothed: Local<f64>,
) {
    let frame = time.delta_secs_f64();
    *smoothed = if *smoothed == 0.0 {
        frame
    } else {
        0.95 * *smoothed + 0.05 * frame
    };
    let shadows = match suns.iter().next() {
        Some(Some(status)) => match &status.error {
            Some(e) => format!("gnomon refused ({e}), Bevy's cascades"),
            None => format!("gnomon's fit, setup {:.0} us", status.setup_seconds * 1e6),
        },
        _ => "Bevy's cascades".to_string(),
    };
    for mut window in &mut windows {
        window.title = format!(
            "gnomon in Bevy: {shadows}, frame {:.1} ms (G: whose shadows, V: next view)",
            *smoothed * 1e3
        );
    }
}
