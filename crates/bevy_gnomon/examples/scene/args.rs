//! The example's options, checked before any window or GPU: a bad one exits 2 with one line.

use std::path::PathBuf;

use bevy::math::Vec3;
use clap::{Parser, ValueEnum};
use gnomon::Technique;
use gnomon_scene::{NamedView, ViewLight};
use gnomon_tools::TechniqueParams;

/// Whose cascades the light draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Shadows {
    /// Bevy's own cascades (bevy_light's spheres, its default configuration).
    Bevy,
    /// gnomon's fits through the plugin.
    Gnomon,
}

/// The demo scene (or a scene file) in Bevy, its sun's cascades Bevy's or gnomon's.
#[derive(Debug, Parser)]
#[command(name = "scene", about)]
pub struct Cli {
    /// A scene file (TOML: meshes, a ground slab, named views); default: gnomon's demo.
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    /// A named view of the scene (default: its first).
    #[arg(long, conflicts_with_all = ["eye", "target", "light_dir"])]
    pub view: Option<String>,
    /// The camera's position X,Y,Z (with --target and --light-dir instead of --view).
    #[arg(long, value_parser = vec3, allow_hyphen_values = true, requires_all = ["target", "light_dir"])]
    pub eye: Option<Vec3>,
    /// The point the camera looks at X,Y,Z.
    #[arg(long, value_parser = vec3, allow_hyphen_values = true, requires = "eye")]
    pub target: Option<Vec3>,
    /// The direction the sunlight travels X,Y,Z.
    #[arg(long, value_parser = vec3, allow_hyphen_values = true, requires = "eye")]
    pub light_dir: Option<Vec3>,
    /// Vertical field of view in degrees (default: the view's, else 60).
    #[arg(long)]
    pub fov: Option<f32>,
    /// Near plane (default: the view's, else 1).
    #[arg(long)]
    pub near: Option<f32>,
    /// Far plane, also the shadow distance of both Bevy's cascades and gnomon's (default:
    /// the view's, else 400).
    #[arg(long)]
    pub far: Option<f32>,
    /// Whose cascades to draw first (the G key switches in the window).
    #[arg(long, value_enum, default_value = "gnomon")]
    pub shadows: Shadows,
    /// gnomon's technique (cascades, focused, lispsm, xpsm, uniform); its parameters are the
    /// gnomon command line's.
    #[arg(long, default_value = "cascades")]
    pub technique: String,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// The sun's depth bias, world units along the light (Bevy's `shadow_depth_bias`).
    #[arg(long, default_value_t = 0.02)]
    pub depth_bias: f32,
    /// The sun's normal bias, in texels of the cascade read (Bevy's `shadow_normal_bias`).
    #[arg(long, default_value_t = 1.8)]
    pub normal_bias: f32,
    /// Bevy's shadow map size, a power of two (each cascade's map).
    #[arg(long, default_value_t = 2048)]
    pub shadow_map: u32,
    /// Image or window size WxH.
    #[arg(long, value_parser = size, default_value = "1280x720")]
    pub size: (u32, u32),
    /// Run headless for this many frames, then write --screenshot and --mask and exit.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Where the headless run writes its last frame (PNG).
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Where the headless run writes the shadow mask (PNG: 255 lit, 0 shadowed, 128 not
    /// judged: no geometry, facing away from the sun or too dim, or a geometry edge).
    #[arg(long, requires = "frames")]
    pub mask: Option<PathBuf>,
}

/// What the example runs: one camera, one sun, whose shadows.
#[derive(Debug, Clone)]
pub struct Options {
    pub eye: Vec3,
    pub target: Vec3,
    pub light_dir: Vec3,
    pub fov_degrees: f32,
    pub near: f32,
    pub far: f32,
    pub shadows: Shadows,
    pub technique: Technique,
    pub shadow_map: u32,
    pub depth_bias: f32,
    pub normal_bias: f32,
    pub size: (u32, u32),
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    pub mask: Option<PathBuf>,
}

/// The options for `cli` over the scene's named views: one line on error.
pub fn options(cli: Cli, views: &[NamedView]) -> Result<Options, String> {
    let technique = gnomon_tools::map_technique(&cli.technique, &cli.params)
        .map_err(|e| format!("--technique: {e}"))?;
    bevy_gnomon::Drawable::check(&technique).map_err(|e| format!("--technique: {e}"))?;
    if !cli.shadow_map.is_power_of_two() || !(256..=8192).contains(&cli.shadow_map) {
        return Err(format!(
            "--shadow-map {}: a power of two from 256 to 8192",
            cli.shadow_map
        ));
    }
    for (name, bias) in [
        ("--depth-bias", cli.depth_bias),
        ("--normal-bias", cli.normal_bias),
    ] {
        if !(bias.is_finite() && bias >= 0.0) {
            return Err(format!("{name} {bias}: a finite number, at least 0"));
        }
    }
    if cli.frames == Some(0) {
        return Err("--frames 0: at least 1".into());
    }
    if cli.frames.is_some() && cli.screenshot.is_none() && cli.mask.is_none() {
        return Err("--frames needs --screenshot or --mask (what to write)".into());
    }
    for path in [&cli.screenshot, &cli.mask].into_iter().flatten() {
        check_output(path)?;
    }
    let (eye, target, light_dir, fov, near, far) = match (cli.eye, cli.target, cli.light_dir) {
        (Some(eye), Some(target), Some(dir)) => (eye, target, dir, 60.0, 1.0, 400.0),
        _ => named(views, cli.view.as_deref())?,
    };
    let options = Options {
        eye,
        target,
        light_dir,
        fov_degrees: cli.fov.unwrap_or(fov),
        near: cli.near.unwrap_or(near),
        far: cli.far.unwrap_or(far),
        shadows: cli.shadows,
        technique,
        shadow_map: cli.shadow_map,
        depth_bias: cli.depth_bias,
        normal_bias: cli.normal_bias,
        size: cli.size,
        frames: cli.frames,
        screenshot: cli.screenshot,
        mask: cli.mask,
    };
    check_camera(&options)?;
    Ok(options)
}

type ViewParts = (Vec3, Vec3, Vec3, f32, f32, f32);

/// `base` moved to a named view (its camera, lens and sun); `None` for a view whose light
/// is not the sun.
pub fn for_view(base: &Options, view: &NamedView) -> Option<Options> {
    let (eye, target, light_dir, fov_degrees, near, far) =
        named(std::slice::from_ref(view), None).ok()?;
    Some(Options {
        eye,
        target,
        light_dir,
        fov_degrees,
        near,
        far,
        ..base.clone()
    })
}

fn named(views: &[NamedView], name: Option<&str>) -> Result<ViewParts, String> {
    let names = || {
        views
            .iter()
            .map(|v| v.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let view = match name {
        Some(n) => views
            .iter()
            .find(|v| v.name == n)
            .ok_or_else(|| format!("--view {n}: the scene's views are {}", names()))?,
        None => views
            .first()
            .ok_or("the scene has no named view: give --eye, --target and --light-dir")?,
    };
    let ViewLight::Directional { direction } = view.light else {
        return Err(format!(
            "view {}: its light is not the sun; the plugin fits directional lights (spot and point lights stay Bevy's)",
            view.name
        ));
    };
    let f = |v: glam::DVec3| Vec3::new(v.x as f32, v.y as f32, v.z as f32);
    Ok((
        f(view.eye),
        f(view.target),
        f(direction),
        view.fov_y_degrees as f32,
        view.near as f32,
        view.far as f32,
    ))
}

fn check_camera(o: &Options) -> Result<(), String> {
    let finite = [o.eye, o.target, o.light_dir].iter().all(|v| v.is_finite());
    if !finite || (o.eye - o.target).length() < 1e-6 || o.light_dir.length() < 1e-9 {
        return Err("--eye, --target, --light-dir: finite, eye apart from target, a non-zero light direction".into());
    }
    if !(o.fov_degrees > 0.0 && o.fov_degrees < 180.0) {
        return Err(format!("--fov {}: in (0, 180) degrees", o.fov_degrees));
    }
    if !(o.near > 0.0 && o.far > o.near && o.far.is_finite()) {
        return Err(format!("--near {} --far {}: 0 < near < far", o.near, o.far));
    }
    Ok(())
}

/// An output's folder must exist and the name must be a PNG, before any work.
fn check_output(path: &std::path::Path) -> Result<(), String> {
    if path.extension().and_then(|e| e.to_str()) != Some("png") {
        return Err(format!("{}: the output is a PNG (.png)", path.display()));
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(d) = dir
        && !d.is_dir()
    {
        return Err(format!("{}: no such folder", d.display()));
    }
    Ok(())
}

fn vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}': three numbers X,Y,Z"))?;
    match parts[..] {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("'{s}': three finite numbers X,Y,Z")),
    }
}

fn size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("'{s}': WxH, e.g. 640x360"))?;
    let (w, h) = (w.trim().parse::<u32>(), h.trim().parse::<u32>());
    match (w, h) {
        (Ok(w), Ok(h)) if (16..=8192).contains(&w) && (16..=8192).contains(&h) => Ok((w, h)),
        _ => Err(format!("'{s}': WxH with each from 16 to 8192")),
    }
}
