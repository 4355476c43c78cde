//! The headless run: frames rendered to an image, then the shadow mask from three frames of
//! the same view (with shadows, without, and each object's id).

use std::sync::{Arc, Mutex};

use bevy::asset::RenderAssetUsages;
use bevy::camera::RenderTarget;
use bevy::image::Image;
use bevy::light::cascade::{CascadeShadowConfig, Cascades};
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::render_resource::TextureFormat;
use bevy::render::renderer::RenderDevice;
use bevy::render::settings::WgpuFeatures;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use bevy_gnomon::GnomonShadowsStatus;

use crate::args::Options;
use crate::world::{HeldCascades, Loaded};

/// Mask values, as gnomon's own masks write them.
const MASK_LIT: u8 = 255;
const MASK_SHADOWED: u8 = 0;
const MASK_NOT_JUDGED: u8 = 128;

/// Below this linear brightness without shadows a pixel is too dim to judge: the sun's N.L
/// under about 0.1 (a white surface facing the sun reads 0.8).
const DIMMEST_JUDGED: f32 = 0.08;

/// A Bevy app drawing into an image, updated by hand.
pub struct Headless {
    app: App,
    target: Handle<Image>,
    size: (u32, u32),
    /// The last mask's frames without shadows and of object ids, kept for `mask_again`.
    judging: Option<(Vec<u8>, Vec<u8>)>,
}

impl Headless {
    /// The app for `options`' first view, its pipelines not yet built.
    pub fn new(options: &Options, loaded: Loaded) -> Self {
        let (w, h) = options.size;
        let mut app = App::new();
        app.add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    ..default()
                })
                .set(RenderPlugin {
                    // Every pipeline ready on the frame that needs it: no frame lacks a mesh.
                    synchronous_pipeline_compilation: true,
                    ..default()
                })
                .disable::<WinitPlugin>()
                .disable::<LogPlugin>(),
        );
        crate::world::configure(&mut app, options, loaded);
        let mut image = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
        image.asset_usage = RenderAssetUsages::RENDER_WORLD | RenderAssetUsages::MAIN_WORLD;
        let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
        app.insert_resource(crate::world::Target(Some(RenderTarget::Image(
            target.clone().into(),
        ))));
        app.finish();
        app.cleanup();
        Self {
            app,
            target,
            size: (w, h),
            judging: None,
        }
    }

    /// Whether the device clips depth as asked (`DEPTH_CLIP_CONTROL`): without it Bevy
    /// emulates unclipped depth in a way that is wrong for warped maps.
    #[allow(dead_code)]
    pub fn depth_clip_control(&self) -> bool {
        self.app
            .world()
            .resource::<RenderDevice>()
            .features()
            .contains(WgpuFeatures::DEPTH_CLIP_CONTROL)
    }

    /// Why the plugin left Bevy's cascades on the last frame, if it did.
    pub fn refused(&mut self) -> Option<String> {
        let world = self.app.world_mut();
        let mut statuses = world.query::<&GnomonShadowsStatus>();
        statuses.iter(world).find_map(|s| s.error.clone())
    }

    /// Runs `n` frames.
    pub fn frames(&mut self, n: u32) {
        for _ in 0..n {
            self.app.update();
        }
    }

    /// Switches to `options`' view, sun and shadows (the mask test goes through the views).
    #[allow(dead_code)]
    pub fn set_view(&mut self, options: &Options) {
        crate::world::set_view(self.app.world_mut(), options);
    }

    /// The next frame (sRGB RGBA bytes) and its shadow mask (one byte a pixel).
    pub fn frame_and_mask(&mut self) -> Result<(Vec<u8>, Vec<u8>), String> {
        let shadowed = self.settled()?;
        set_shadows(&mut self.app, false);
        let unshadowed = self.settled();
        set_shadows(&mut self.app, true);
        crate::world::show_ids(self.app.world_mut(), true);
        let ids = self.settled();
        crate::world::show_ids(self.app.world_mut(), false);
        self.judging = Some((unshadowed?, ids?));
        Ok((shadowed.clone(), self.mask_of(&shadowed)))
    }

    /// The mask of the next frame, judged as the last `frame_and_mask` was (for a frame that
    /// differs from it only in its shadows).
    #[allow(dead_code)]
    pub fn mask_again(&mut self) -> Result<Vec<u8>, String> {
        let shadowed = self.settled()?;
        Ok(self.mask_of(&shadowed))
    }

    fn mask_of(&self, shadowed: &[u8]) -> Vec<u8> {
        let (w, h) = self.size;
        let (unshadowed, ids) = self.judging.as_ref().expect("frame_and_mask first");
        mask(w as usize, h as usize, shadowed, unshadowed, ids)
    }

    /// The sun's cascade configuration and cascades as last built.
    #[allow(dead_code)]
    pub fn cascades(&mut self) -> HeldCascades {
        let world = self.app.world_mut();
        let mut suns = world.query::<(&CascadeShadowConfig, &Cascades)>();
        let (config, cascades) = suns.iter(world).next().expect("a sun");
        HeldCascades(Some((config.clone(), cascades.clone())))
    }

    /// Draws `held` cascades instead of those built each frame (`HeldCascades(None)`: the
    /// built ones again).
    #[allow(dead_code)]
    pub fn hold(&mut self, held: HeldCascades) {
        self.app.insert_resource(held);
    }

    /// Moves only the camera to `options`' eye and target.
    #[allow(dead_code)]
    pub fn move_camera(&mut self, options: &Options) {
        crate::world::move_camera(self.app.world_mut(), options);
    }

    /// The next frame, as sRGB bytes (RGBA).
    pub fn capture(&mut self) -> Result<Vec<u8>, String> {
        capture(&mut self.app, &self.target)
    }

    /// The first frame that the next one repeats: a change (a new view, shadows off, other
    /// materials) can take a few frames to reach the image (meshes and maps uploaded,
    /// cascades built from the last frame's transforms).
    pub fn settled(&mut self) -> Result<Vec<u8>, String> {
        let mut last = self.capture()?;
        for _ in 0..10 {
            let next = self.capture()?;
            if next == last {
                return Ok(next);
            }
            last = next;
        }
        Err("the frame did not settle in 10 frames".into())
    }
}

/// Runs `options.frames` frames headless and writes the screenshot and the mask.
pub fn run(options: &Options, loaded: Loaded) -> Result<(), String> {
    let (w, h) = options.size;
    let mut headless = Headless::new(options, loaded);
    // Three frames to build the pipelines and upload the meshes, then the timed ones.
    headless.frames(3);
    let frames = options.frames.unwrap_or(1);
    let started = std::time::Instant::now();
    headless.frames(frames);
    let seconds = started.elapsed().as_secs_f64();
    eprintln!(
        "{frames} frames in {seconds:.2} s: {:.2} ms a frame",
        1e3 * seconds / f64::from(frames)
    );
    // A refused fit leaves Bevy's cascades: say so rather than write Bevy's picture.
    if let Some(error) = headless.refused() {
        return Err(format!("gnomon's fit was not used: {error}"));
    }
    let (frame, mask) = match &options.mask {
        Some(_) => headless.frame_and_mask()?,
        None => (headless.settled()?, Vec::new()),
    };
    if let Some(path) = &options.screenshot {
        save(path, w, h, &frame, 4)?;
    }
    if let Some(path) = &options.mask {
        save(path, w, h, &mask, 1)?;
    }
    Ok(())
}

/// The next frame of `target`, as sRGB bytes (RGBA).
fn capture(app: &mut App, target: &Handle<Image>) -> Result<Vec<u8>, String> {
    let slot: Arc<Mutex<Option<Vec<u8>>>> = Arc::default();
    let into = slot.clone();
    app.world_mut()
        .spawn(Screenshot::image(target.clone()))
        .observe(move |captured: On<ScreenshotCaptured>| {
            *into.lock().unwrap() = captured.image.data.clone();
        });
    for _ in 0..60 {
        app.update();
        if let Some(bytes) = slot.lock().unwrap().take() {
            return Ok(bytes);
        }
    }
    Err("the frame did not come back from the GPU".into())
}

/// Turns the sun's shadows on or off.
fn set_shadows(app: &mut App, on: bool) {
    let world = app.world_mut();
    let mut lights = world.query::<&mut DirectionalLight>();
    for mut light in lights.iter_mut(world) {
        light.shadow_maps_enabled = on;
    }
}

/// The shadow mask: shadowed where the frame is under half as bright as without shadows;
/// not judged where there is no geometry, at an object's edge (a neighbour shows another
/// object) or where the surface is too dim without shadows.
fn mask(w: usize, h: usize, shadowed: &[u8], unshadowed: &[u8], ids: &[u8]) -> Vec<u8> {
    let id = |x: usize, y: usize| {
        let i = 4 * (y * w + x);
        [ids[i], ids[i + 1], ids[i + 2]]
    };
    let linear = |bytes: &[u8], i: usize| srgb_to_linear(bytes[4 * i + 1]);
    let mut out = vec![MASK_NOT_JUDGED; w * h];
    for y in 0..h {
        for x in 0..w {
            let here = id(x, y);
            let background = here == [0, 0, 0];
            let edge = [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)]
                .iter()
                .any(|(dx, dy)| {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    nx >= 0
                        && ny >= 0
                        && (nx as usize) < w
                        && (ny as usize) < h
                        && id(nx as usize, ny as usize) != here
                });
            let i = y * w + x;
            let (lit, seen) = (linear(unshadowed, i), linear(shadowed, i));
            if background || edge || lit < DIMMEST_JUDGED {
                continue;
            }
            out[i] = if seen < 0.5 * lit {
                MASK_SHADOWED
            } else {
                MASK_LIT
            };
        }
    }
    out
}

fn srgb_to_linear(v: u8) -> f32 {
    let c = f32::from(v) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Writes RGBA (channels 4) or grey (1) bytes as a PNG.
fn save(path: &std::path::Path, w: u32, h: u32, bytes: &[u8], channels: u8) -> Result<(), String> {
    let colour = if channels == 4 {
        image::ExtendedColorType::Rgba8
    } else {
        image::ExtendedColorType::L8
    };
    image::save_buffer(path, bytes, w, h, colour).map_err(|e| format!("{}: {e}", path.display()))
}
