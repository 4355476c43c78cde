//! Options shared by the subcommands that take a view and a light, and `gnomon setup`.

use std::path::PathBuf;

use clap::Args;
use glam::DVec3;
use gnomon::{
    Camera, DirectionalLight, Lens, Light, MapSettings, PointLight, SceneBounds, ShadowSetup,
    SpotLight, Technique, ViewSamples, compute_setup, compute_setup_with_samples,
};
use gnomon_render::RenderScene;
use gnomon_scene::{NamedView, ViewLight};

pub use gnomon_tools::params::{
    CascadeFitArg, CascadeSelectArg, CascadeSplitArg, SppsmWithArg, TechniqueParams,
    cascade_split_arg, options_read_by,
};

use crate::CliError;

/// Every command's default shadow-map size (texels on a side): one default for all.
pub const DEFAULT_SHADOW_MAP: u32 = 2048;

/// `--shadow-map`: a map size in texels within the core's range, named in the message.
pub fn parse_shadow_map(s: &str) -> Result<u32, String> {
    let range = gnomon::MIN_RESOLUTION..=gnomon::MAX_RESOLUTION;
    let out_of_range = || {
        format!(
            "'{s}' is not a shadow-map resolution: give {} to {} texels",
            range.start(),
            range.end()
        )
    };
    let size: i64 = s.trim().parse().map_err(|_| out_of_range())?;
    u32::try_from(size)
        .ok()
        .filter(|n| range.contains(n))
        .ok_or_else(out_of_range)
}

/// A camera, given by a named view of the command's scene and/or eye, target and up, and its
/// lens: explicit options override the named view's.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// A named view of the scene (the demo's, a scene file's `[[view]]`, or a mesh's:
    /// oblique, low_sun, dueling_frusta): its camera and light; the options below override
    /// them.
    #[arg(long)]
    pub view: Option<String>,
    /// Camera position, X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// The point the camera looks at, X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<DVec3>,
    /// The image's up direction, X,Y,Z (default: the named view's, else 0,1,0).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<DVec3>,
    /// Vertical field of view in degrees (default: the named view's, else 60).
    #[arg(long, allow_hyphen_values = true)]
    pub fov: Option<f64>,
    /// Near plane distance (default: the named view's, else 1).
    #[arg(long, allow_hyphen_values = true)]
    pub near: Option<f64>,
    /// Far plane distance (default: the named view's, else 400).
    #[arg(long, allow_hyphen_values = true)]
    pub far: Option<f64>,
    /// Width over height (default: the image's; 16:9 without an image).
    #[arg(long, allow_hyphen_values = true)]
    pub aspect: Option<f64>,
}

/// `name` among `views`, or a usage error listing them.
pub fn find_view<'a>(views: &'a [NamedView], name: &str) -> Result<&'a NamedView, CliError> {
    views.iter().find(|v| v.name == name.trim()).ok_or_else(|| {
        if views.is_empty() {
            CliError::usage(format!(
                "unknown view '{name}': the scene has no named views"
            ))
        } else {
            CliError::usage(format!(
                "unknown view '{name}' (known: {})",
                views
                    .iter()
                    .map(|v| v.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        }
    })
}

impl ViewArgs {
    /// The named view among the scene's `views`, if one is given.
    pub fn named<'a>(&self, views: &'a [NamedView]) -> Result<Option<&'a NamedView>, CliError> {
        self.view
            .as_deref()
            .map(|name| find_view(views, name))
            .transpose()
    }

    /// The validated camera, of aspect `default_aspect` unless `--aspect` says otherwise.
    pub fn camera_with_aspect(
        &self,
        views: &[NamedView],
        default_aspect: f64,
    ) -> Result<Camera, CliError> {
        let named = self.named(views)?;
        let (eye, target) = match (
            self.eye.or(named.map(|v| v.eye)),
            self.target.or(named.map(|v| v.target)),
        ) {
            (Some(eye), Some(target)) => (eye, target),
            _ => {
                return Err(CliError::usage(
                    "give --eye and --target, or a named --view",
                ));
            }
        };
        let defaults = Lens::default();
        let lens = Lens {
            fov_y_degrees: self
                .fov
                .or(named.map(|v| v.fov_y_degrees))
                .unwrap_or(defaults.fov_y_degrees),
            aspect: self.aspect.unwrap_or(default_aspect),
            near: self.near.or(named.map(|v| v.near)).unwrap_or(defaults.near),
            far: self.far.or(named.map(|v| v.far)).unwrap_or(400.0),
        };
        let up = self.up.or(named.map(|v| v.up)).unwrap_or(DVec3::Y);
        Ok(Camera::look_at(eye, target, up, lens)?)
    }

    /// The camera of an image of `size` (its aspect unless `--aspect` says otherwise), with a
    /// far plane the renderer draws precisely.
    pub fn drawn_camera(&self, views: &[NamedView], size: (u32, u32)) -> Result<Camera, CliError> {
        let camera = self.camera_with_aspect(views, size.0 as f64 / size.1 as f64)?;
        if camera.lens().far > gnomon_render::MAX_VIEW_DISTANCE {
            return Err(CliError::usage(format!(
                "--far {} is beyond what the renderer draws precisely (at most {})",
                camera.lens().far,
                gnomon_render::MAX_VIEW_DISTANCE
            )));
        }
        Ok(camera)
    }
}

/// The light: directional, spot or point, at most one (without any, the named view's).
#[derive(Debug, Clone, Args)]
#[group(required = false, multiple = false)]
pub struct LightArgs {
    /// A directional light: the direction the light travels, X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light_dir: Option<DVec3>,
    /// A spot light: PX,PY,PZ,DX,DY,DZ,HALF_ANGLE_DEG,RANGE (position, direction, cone
    /// half-angle in degrees, range).
    #[arg(long, value_parser = parse_spot, allow_hyphen_values = true)]
    pub spot: Option<[f64; 8]>,
    /// A point light: X,Y,Z,RANGE (position and range); its shadow maps are cube faces
    /// (techniques `cube`, or any single-map technique per face).
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub point: Option<[f64; 4]>,
}

impl LightArgs {
    /// The validated light: the one given, else the named view's among `views`.
    pub fn light(&self, view: &ViewArgs, views: &[NamedView]) -> Result<Light, CliError> {
        match (self.light_dir, self.spot, self.point, view.named(views)?) {
            (Some(d), None, None, _) => Ok(Light::Directional(DirectionalLight::new(d)?)),
            (None, Some(s), None, _) => Ok(Light::Spot(SpotLight::new(
                DVec3::new(s[0], s[1], s[2]),
                DVec3::new(s[3], s[4], s[5]),
                s[6],
                s[7],
            )?)),
            (None, None, Some(p), _) => Ok(Light::Point(PointLight::new(
                DVec3::new(p[0], p[1], p[2]),
                p[3],
            )?)),
            (None, None, None, Some(named)) => Ok(named.light.light()?),
            _ => Err(CliError::usage(
                "give one of --light-dir, --spot and --point, or a named --view",
            )),
        }
    }

    /// Every light: the one given, else all of the named view's (a scene file's view may
    /// have several).
    pub fn lights(&self, view: &ViewArgs, views: &[NamedView]) -> Result<Vec<Light>, CliError> {
        match (self.light_dir, self.spot, self.point, view.named(views)?) {
            (None, None, None, Some(named)) => Ok(named.lights()?),
            _ => Ok(vec![self.light(view, views)?]),
        }
    }

    /// The light of a command that draws one: [`LightArgs::light`], with a warning where the
    /// named view has more lights than the one used.
    pub fn main_light(
        &self,
        view: &ViewArgs,
        views: &[NamedView],
        command: &str,
    ) -> Result<Light, CliError> {
        if let (None, None, None, Some(named)) =
            (self.light_dir, self.spot, self.point, view.named(views)?)
            && !named.more_lights.is_empty()
        {
            eprintln!(
                "warning: view '{}' has {} lights; {command} uses the first",
                named.name,
                1 + named.more_lights.len()
            );
        }
        self.light(view, views)
    }
}

/// A suite: every scene file of a folder, for the commands that go over many scenes.
#[derive(Debug, Clone, Args)]
pub struct SuiteArgs {
    /// Go over every scene file (`*.toml`) in this folder and all its views instead of one
    /// scene (scripts/fetch-suite.sh fetches assets/suite's models).
    #[arg(long, conflicts_with_all = ["scene_file", "mesh"])]
    pub suite: Option<PathBuf>,
}

/// Which of the scene's named views a command goes over.
#[derive(Debug, Clone, Args)]
pub struct ViewListArgs {
    /// The views: `all` or names, comma-separated.
    #[arg(
        long,
        visible_alias = "view",
        value_delimiter = ',',
        default_value = "all"
    )]
    pub views: Vec<String>,
}

impl ViewListArgs {
    /// The views named, in the order given (`all`: every view of the scene, in its order).
    pub fn select<'a>(&self, views: &'a [NamedView]) -> Result<Vec<&'a NamedView>, CliError> {
        let chosen: Vec<&NamedView> = if self.views.iter().any(|v| v.trim() == "all") {
            views.iter().collect()
        } else {
            self.views
                .iter()
                .map(|name| find_view(views, name))
                .collect::<Result<_, _>>()?
        };
        if chosen.is_empty() {
            return Err(CliError::usage(
                "the scene has no named views (a scene file gives them as [[view]] tables)",
            ));
        }
        Ok(chosen)
    }
}

/// The `gnomon render` command that draws named view `view` of the scene given by
/// `scene_options` ([`LoadedScene::options`]) as a report's cell: `technique.1` names it
/// (`--technique`), `technique.0` the map technique whose map size and those of `params` it
/// reads (`None` for what draws no map: the volumes, planar shadows), the rest as the report
/// drew it. Every figure can be reproduced from its report.
pub fn render_command(
    scene_options: &str,
    view: &NamedView,
    (technique, name): (Option<&Technique>, &str),
    params: &TechniqueParams,
    shadow_map: u32,
    size: (u32, u32),
    extra: &str,
) -> String {
    let mut command = "gnomon render".to_string();
    if !scene_options.is_empty() {
        command += &format!(" {scene_options}");
    }
    // Several lights come only from the view itself: name it.
    if !view.more_lights.is_empty() {
        command += &format!(" --view {}", shell_word(&view.name));
    } else {
        command += &view_options(view);
    }
    command += &format!(" --technique {name}");
    if let Some(technique) = technique {
        command += &format!(" --shadow-map {shadow_map}");
        let read = options_read_by(technique);
        for (option, flag) in params.flags() {
            if read.contains(&option) {
                command += &format!(" {flag}");
            }
        }
    }
    command += &format!(" --size {}x{}{extra}", size.0, size.1);
    command
}

/// The options that give a named view's camera and its (one) light explicitly.
fn view_options(view: &NamedView) -> String {
    let v = |a: DVec3| format!("{},{},{}", a.x, a.y, a.z);
    let mut options = format!(" --eye={} --target={}", v(view.eye), v(view.target));
    let defaults = Lens::default();
    if view.up != DVec3::Y {
        options += &format!(" --up={}", v(view.up));
    }
    if view.fov_y_degrees != defaults.fov_y_degrees {
        options += &format!(" --fov {}", view.fov_y_degrees);
    }
    if view.near != defaults.near {
        options += &format!(" --near {}", view.near);
    }
    options += &format!(" --far {}", view.far);
    match view.light {
        ViewLight::Directional { direction } => {
            options += &format!(" --light-dir={}", v(direction));
        }
        ViewLight::Spot {
            position,
            direction,
            half_angle_degrees,
            range,
        } => {
            options += &format!(
                " --spot={},{},{half_angle_degrees},{range}",
                v(position),
                v(direction)
            );
        }
        ViewLight::Point { position, range } => {
            options += &format!(" --point={},{range}", v(position));
        }
    }
    options
}

/// The option that gives `light`: `--light-dir=...`, `--spot=...` or `--point=...`.
pub fn light_option(light: &Light) -> String {
    let v = |a: DVec3| format!("{},{},{}", a.x, a.y, a.z);
    match light {
        Light::Directional(d) => format!("--light-dir={}", v(d.direction())),
        Light::Spot(s) => format!(
            "--spot={},{},{},{}",
            v(s.position()),
            v(s.direction()),
            s.half_angle().to_degrees(),
            s.range()
        ),
        Light::Point(p) => format!("--point={},{}", v(p.position()), p.range()),
    }
}

/// `gnomon setup`.
#[derive(Debug, Clone, Args)]
pub struct SetupArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub light: LightArgs,
    /// The shadow-map technique (the names of [`crate::names`]).
    #[arg(long, default_value = "focused", value_parser = crate::names::map_arg)]
    pub technique: Technique,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Shadow-map resolution in texels (square).
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Print JSON instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// A built-in scene's layout by name.
pub fn scene_layout(name: &str) -> Result<gnomon_scene::SceneLayout, CliError> {
    gnomon_scene::by_name(name).ok_or_else(|| {
        CliError::usage(format!(
            "unknown scene '{name}' (known: {})",
            gnomon_scene::SCENE_NAMES.join(", ")
        ))
    })
}

/// Computes a setup and how long it took, in microseconds: with the renderer's view samples
/// of the same camera and light where there are some (the warp limit then compares maps on
/// the real surfaces), else with the core's own from the boxes.
pub fn timed_setup(
    technique: &Technique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    resolution: u32,
    samples: Option<&ViewSamples>,
) -> Result<(ShadowSetup, f64), CliError> {
    let start = std::time::Instant::now();
    let map = MapSettings::with_resolution(resolution);
    let setup = match samples {
        Some(samples) => compute_setup_with_samples(technique, camera, light, scene, map, samples)?,
        None => compute_setup(technique, camera, light, scene, map)?,
    };
    Ok((setup, start.elapsed().as_secs_f64() * 1e6))
}

/// A mesh file to use instead of a built-in scene.
#[derive(Debug, Clone, Args)]
pub struct MeshArgs {
    /// This mesh (.off, .obj, .ply, .stl, .gltf, .glb or a .ter heightfield) standing on a ground slab instead of
    /// a built-in scene (scripts/fetch-meshes.sh fetches the bunny and a knot into
    /// assets/meshes/); its named views: oblique, low_sun, dueling_frusta.
    #[arg(long, conflicts_with = "scene")]
    pub mesh: Option<PathBuf>,
    /// The mesh's height in world units once placed (it is scaled uniformly).
    #[arg(long, default_value_t = 10.0, requires = "mesh")]
    pub mesh_height: f64,
}

/// Where a command's scene comes from: a built-in scene, a mesh file on a ground slab, or a
/// scene file. One definition for every command.
#[derive(Debug, Clone, Args)]
pub struct SceneArgs {
    /// The scene: a built-in scene's name.
    #[arg(long, default_value = "demo")]
    pub scene: String,
    #[command(flatten)]
    pub mesh: MeshArgs,
    /// A scene file (TOML: mesh files placed as objects, a ground slab, named views; the
    /// format is in the README) instead of a built-in scene.
    #[arg(long, conflicts_with_all = ["scene", "mesh"])]
    pub scene_file: Option<PathBuf>,
}

/// A command's scene, loaded.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// Its name, for reports.
    pub name: String,
    /// What is drawn. Its bounds (`RenderScene::bounds`, the drawn vertices' boxes) are what
    /// every command hands the core, so that `setup` prints the matrices `render` draws with.
    pub scene: RenderScene,
    /// Its named views (what `--view` takes).
    pub views: Vec<NamedView>,
    /// The options that give this scene on the command line (empty for the demo), for the
    /// commands that reproduce a figure.
    pub options: String,
}

/// `text` as one shell word.
fn shell_word(text: &str) -> String {
    let text = text.to_string();
    if !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+,:=@".contains(c))
    {
        text
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

impl LoadedScene {
    /// The scene file at `path` (warnings for what its mesh loads left out).
    pub fn from_scene_file(path: &std::path::Path) -> Result<Self, CliError> {
        let file =
            gnomon_scene::SceneFile::load(path).map_err(|e| CliError::usage(e.to_string()))?;
        for note in &file.notes {
            eprintln!("warning: {note}");
        }
        Ok(LoadedScene {
            name: file.name.clone(),
            scene: RenderScene::from_scene_file(&file),
            views: file.views,
            options: format!("--scene-file {}", shell_word(&path.display().to_string())),
        })
    }
}

/// Every scene file (`*.toml`) in `folder`, by name, loaded (each file's stem and scene);
/// a scene without named views, or a folder without scene files, is a usage error.
pub fn suite_scenes(folder: &std::path::Path) -> Result<Vec<(String, LoadedScene)>, CliError> {
    let entries = std::fs::read_dir(folder)
        .map_err(|e| CliError::usage(format!("--suite {}: {e}", folder.display())))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml") && p.is_file())
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(CliError::usage(format!(
            "--suite {}: no scene files (*.toml) there",
            folder.display()
        )));
    }
    paths
        .iter()
        .map(|path| {
            let loaded = LoadedScene::from_scene_file(path).map_err(|e| {
                if e.message.contains("cannot read") {
                    CliError::usage(format!(
                        "{} (scripts/fetch-suite.sh fetches the suite's models)",
                        e.message
                    ))
                } else {
                    e
                }
            })?;
            if loaded.views.is_empty() {
                return Err(CliError::usage(format!(
                    "{}: a suite's scene needs named views ([[view]])",
                    path.display()
                )));
            }
            let stem = path
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
            Ok((stem, loaded))
        })
        .collect()
}

impl SceneArgs {
    /// Loads the scene: reads the mesh or scene file (warnings for what a load left out).
    pub fn load(&self) -> Result<LoadedScene, CliError> {
        if let Some(path) = &self.scene_file {
            return LoadedScene::from_scene_file(path);
        }
        let Some(path) = &self.mesh.mesh else {
            let layout = scene_layout(&self.scene)?;
            return Ok(LoadedScene {
                name: layout.name.clone(),
                scene: RenderScene::from_layout(&layout),
                views: gnomon_scene::views_by_name(&self.scene),
                options: if self.scene == "demo" {
                    String::new()
                } else {
                    format!("--scene {}", self.scene)
                },
            });
        };
        let (parts, notes) =
            gnomon_scene::Mesh::load_parts(path).map_err(|e| CliError::usage(e.to_string()))?;
        for note in notes {
            eprintln!("warning: {}: {note}", path.display());
        }
        let name = path
            .file_stem()
            .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
        Ok(LoadedScene {
            scene: RenderScene::parts_on_ground(&name, parts, self.mesh.mesh_height)?,
            name,
            views: gnomon_scene::mesh_views(self.mesh.mesh_height),
            options: format!(
                "--mesh {} --mesh-height {}",
                shell_word(&path.display().to_string()),
                self.mesh.mesh_height
            ),
        })
    }
}

/// Runs `gnomon setup`.
pub fn run_setup(args: &SetupArgs) -> Result<(), CliError> {
    let loaded = args.scene.load()?;
    let scene = loaded.scene.bounds()?;
    let camera = args.view.camera_with_aspect(&loaded.views, 16.0 / 9.0)?;
    let light = args.light.main_light(&args.view, &loaded.views, "setup")?;
    let technique = args.params.apply(args.technique);
    args.params.check_used_by(&[technique])?;
    let setup = compute_setup(
        &technique,
        &camera,
        &light,
        &scene,
        MapSettings::with_resolution(args.shadow_map),
    )?;
    if args.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&gnomon_tools::setup_json(&setup))
                .expect("JSON of plain values")
        );
    } else {
        crate::output::print(&crate::report::setup_text(&setup));
    }
    Ok(())
}

fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {what} as {N} comma-separated numbers, got '{s}'"
        ));
    }
    let mut out = [0.0f64; N];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p.parse().map_err(|_| format!("'{p}' is not a number"))?;
        if !o.is_finite() {
            return Err(format!("'{p}' is not a finite number"));
        }
    }
    Ok(out)
}

/// Parses `X,Y,Z`.
pub fn parse_vec3(s: &str) -> Result<DVec3, String> {
    parse_numbers::<3>(s, "X,Y,Z").map(DVec3::from_array)
}

fn parse_spot(s: &str) -> Result<[f64; 8], String> {
    parse_numbers::<8>(s, "PX,PY,PZ,DX,DY,DZ,HALF_ANGLE_DEG,RANGE")
}

fn parse_point(s: &str) -> Result<[f64; 4], String> {
    parse_numbers::<4>(s, "X,Y,Z,RANGE")
}

/// A plane A,B,C,D (A x + B y + C z + D = 0, the receiving side where it is positive), with
/// a non-zero normal (A, B, C).
pub fn parse_plane(s: &str) -> Result<[f64; 4], String> {
    let p = parse_numbers::<4>(s, "A,B,C,D")?;
    if DVec3::new(p[0], p[1], p[2]).length() < 1e-12 {
        return Err(format!("the plane '{s}' has no normal (A, B, C are 0)"));
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_vectors() {
        assert_eq!(parse_vec3("1, -2,3.5").unwrap(), DVec3::new(1.0, -2.0, 3.5));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,x").is_err());
        assert!(parse_vec3("1,2,nan").is_err());
        assert!(parse_vec3("1,2,inf").is_err());
        assert_eq!(parse_spot("0,10,0,0,-1,0,30,50").unwrap()[6], 30.0);
        assert_eq!(parse_point("0,10,-2,50").unwrap(), [0.0, 10.0, -2.0, 50.0]);
        assert!(parse_point("0,10,50").is_err());
    }
}
