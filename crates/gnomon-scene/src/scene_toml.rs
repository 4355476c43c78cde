//! Reading a scene file's TOML ([`SceneFile::load`], [`SceneFile::parse`]): serde's raw
//! tables, each key checked where it is written so that an error names its line, then the
//! ground, the objects (their mesh files read once each) and the views.

use std::path::{Path, PathBuf};

use glam::{DMat4, DQuat, DVec3};
use serde::Deserialize;
use toml::Spanned;

use crate::view::{NamedView, ViewLight};
use crate::{FileObject, MAX_SCENE_FILE_BYTES, Mesh, SceneFile, SceneFileError, Shape};

/// The most lights a view may have (what the renderer draws in one frame).
const MAX_VIEW_LIGHTS: usize = 4;

/// The largest coordinate, scale or distance a scene file may give (the core's range).
const MAX_COORDINATE: f64 = 1e7;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    name: Option<String>,
    ground: Option<RawGround>,
    #[serde(default)]
    object: Vec<Spanned<RawObject>>,
    #[serde(default)]
    view: Vec<Spanned<RawView>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGround {
    size: Spanned<f64>,
    height: Option<Spanned<f64>>,
    color: Option<Spanned<[f64; 3]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    mesh: Spanned<String>,
    name: Option<String>,
    translate: Option<Spanned<[f64; 3]>>,
    scale: Option<Spanned<Scale>>,
    rotate_y_degrees: Option<Spanned<f64>>,
    casts: Option<bool>,
    receives: Option<bool>,
    color: Option<Spanned<[f64; 3]>>,
    split: Option<Spanned<String>>,
}

/// `scale = s` (uniform) or `scale = [sx, sy, sz]`.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum Scale {
    Uniform(f64),
    Axes([f64; 3]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawView {
    name: Spanned<String>,
    description: Option<String>,
    eye: Spanned<[f64; 3]>,
    target: Spanned<[f64; 3]>,
    up: Option<Spanned<[f64; 3]>>,
    fov: Option<Spanned<f64>>,
    near: Option<Spanned<f64>>,
    far: Option<Spanned<f64>>,
    light_dir: Option<Spanned<[f64; 3]>>,
    spot: Option<Spanned<[f64; 8]>>,
    point: Option<Spanned<[f64; 4]>>,
    light: Option<Vec<Spanned<RawLight>>>,
}

/// One of a view's `[[view.light]]` tables.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    light_dir: Option<Spanned<[f64; 3]>>,
    spot: Option<Spanned<[f64; 8]>>,
    point: Option<Spanned<[f64; 4]>>,
}

/// Errors at places in one file's text.
struct Located<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Located<'_> {
    fn line_of(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    fn at(&self, offset: usize, key: &str, message: impl Into<String>) -> SceneFileError {
        SceneFileError {
            path: self.path.to_path_buf(),
            line: Some(self.line_of(offset)),
            key: Some(key.into()),
            message: message.into(),
        }
    }

    /// A TOML or type error: its line, and the key written on that line where there is one.
    fn parse_error(&self, e: &toml::de::Error) -> SceneFileError {
        let (line, key) = match e.span() {
            Some(span) => {
                let start = self.text[..span.start.min(self.text.len())]
                    .rfind('\n')
                    .map_or(0, |i| i + 1);
                let line_text = self.text[start..].lines().next().unwrap_or_default();
                let key = line_text
                    .split_once('=')
                    .map(|(k, _)| k.trim().trim_matches('"').to_string())
                    .filter(|k| !k.is_empty() && !k.starts_with('#') && !k.starts_with('['));
                (Some(self.line_of(span.start)), key)
            }
            None => (None, None),
        };
        let message = e.message().trim();
        // serde's words for an untagged enum name a type the file's writer never sees.
        let message = if message.contains("untagged enum Scale") {
            "a scale is a positive number or three of them, [sx, sy, sz]"
        } else {
            message
        };
        SceneFileError {
            path: self.path.to_path_buf(),
            line,
            key,
            message: message.to_string(),
        }
    }

    /// A finite number in `range`, or an error naming `key`.
    fn number(
        &self,
        value: &Spanned<f64>,
        key: &str,
        ok: impl Fn(f64) -> bool,
        what: &str,
    ) -> Result<f64, SceneFileError> {
        let v = *value.get_ref();
        if v.is_finite() && ok(v) {
            Ok(v)
        } else {
            Err(self.at(value.span().start, key, format!("{v} is not {what}")))
        }
    }

    /// A vector of finite numbers within the core's range.
    fn vector<const N: usize>(
        &self,
        value: &Spanned<[f64; N]>,
        key: &str,
    ) -> Result<[f64; N], SceneFileError> {
        let v = *value.get_ref();
        match v
            .iter()
            .find(|x| !(x.is_finite() && x.abs() <= MAX_COORDINATE))
        {
            Some(bad) => Err(self.at(
                value.span().start,
                key,
                format!("{bad} is not a finite number up to {MAX_COORDINATE:e}"),
            )),
            None => Ok(v),
        }
    }

    fn vec3(&self, value: &Spanned<[f64; 3]>, key: &str) -> Result<DVec3, SceneFileError> {
        self.vector(value, key).map(DVec3::from_array)
    }

    fn color(&self, value: &Spanned<[f64; 3]>, key: &str) -> Result<[f32; 3], SceneFileError> {
        let v = *value.get_ref();
        if v.iter().all(|c| (0.0..=1.0).contains(c)) {
            Ok(v.map(|c| c as f32))
        } else {
            Err(self.at(
                value.span().start,
                key,
                "a colour is three numbers from 0 to 1 (linear RGB)",
            ))
        }
    }
}

impl Located<'_> {
    /// The light given by `light_dir`, `spot` or `point` (`None` for none; two is an error).
    fn light(
        &self,
        light_dir: &Option<Spanned<[f64; 3]>>,
        spot: &Option<Spanned<[f64; 8]>>,
        point: &Option<Spanned<[f64; 4]>>,
        view: &str,
    ) -> Result<Option<ViewLight>, SceneFileError> {
        if let Some(p) = point {
            if light_dir.is_some() || spot.is_some() {
                return Err(self.at(
                    p.span().start,
                    "point",
                    format!("a light of view '{view}' gives point and another light; give one"),
                ));
            }
            let p = self.vector(p, "point")?;
            return Ok(Some(ViewLight::Point {
                position: DVec3::new(p[0], p[1], p[2]),
                range: p[3],
            }));
        }
        Ok(match (light_dir, spot) {
            (Some(d), None) => Some(ViewLight::Directional {
                direction: self.vec3(d, "light_dir")?,
            }),
            (None, Some(s)) => {
                let s = self.vector(s, "spot")?;
                Some(ViewLight::Spot {
                    position: DVec3::new(s[0], s[1], s[2]),
                    direction: DVec3::new(s[3], s[4], s[5]),
                    half_angle_degrees: s[6],
                    range: s[7],
                })
            }
            (Some(_), Some(s)) => {
                return Err(self.at(
                    s.span().start,
                    "spot",
                    format!("a light of view '{view}' gives both light_dir and spot; give one"),
                ));
            }
            (None, None) => None,
        })
    }
}

/// One mesh a scene file's object places: its index in [`SceneFile::meshes`], its label
/// within the file (its material, its connected part, its instance), its material's colour
/// and where the file places it (a glTF node's transform).
#[derive(Debug, Clone)]
struct LoadedPart {
    mesh: usize,
    label: String,
    color: Option<[f32; 3]>,
    file_from_part: DMat4,
}

impl SceneFile {
    /// Reads the scene file at `path` and every mesh it names.
    pub fn load(path: &Path) -> Result<Self, SceneFileError> {
        let whole = |message: String| SceneFileError {
            path: path.to_path_buf(),
            line: None,
            key: None,
            message,
        };
        let meta = std::fs::metadata(path).map_err(|e| whole(e.to_string()))?;
        if !meta.is_file() {
            return Err(whole("not a regular file".into()));
        }
        if meta.len() > MAX_SCENE_FILE_BYTES {
            return Err(whole(format!(
                "larger than a scene file may be ({} MiB)",
                MAX_SCENE_FILE_BYTES >> 20
            )));
        }
        let text = std::fs::read_to_string(path).map_err(|e| whole(e.to_string()))?;
        Self::parse(path, &text)
    }

    /// A scene file's text, as read from `path` (mesh paths are relative to its folder).
    pub fn parse(path: &Path, text: &str) -> Result<Self, SceneFileError> {
        let at = Located { path, text };
        let raw: RawFile = toml::from_str(text).map_err(|e| at.parse_error(&e))?;
        let mut file = SceneFile {
            name: raw.name.clone().unwrap_or_else(|| {
                path.file_stem()
                    .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
            }),
            path: path.to_path_buf(),
            meshes: Vec::new(),
            objects: Vec::new(),
            views: Vec::new(),
            notes: Vec::new(),
        };
        if let Some(ground) = &raw.ground {
            at.place_ground(ground, &mut file)?;
        }
        let mut loaded = MeshFiles::default();
        for object in &raw.object {
            at.place_object(object.get_ref(), &mut loaded, &mut file)?;
        }
        for view in &raw.view {
            let named = at.view(view, &file.views)?;
            file.views.push(named);
        }
        if file.objects.is_empty() {
            return Err(SceneFileError {
                path: path.to_path_buf(),
                line: None,
                key: Some("object".into()),
                message: "the scene has no objects: give at least one [[object]] or a [ground]"
                    .into(),
            });
        }
        Ok(file)
    }
}

/// Where and how an object places its mesh file, as its keys give it.
struct Placement {
    translate: DVec3,
    scale: DVec3,
    angle_degrees: f64,
    color: Option<[f32; 3]>,
    split: bool,
}

/// The mesh files read so far, each (with its split) once: its parts' meshes in the scene.
#[derive(Default)]
struct MeshFiles(Vec<(PathBuf, bool, Vec<LoadedPart>)>);

impl Located<'_> {
    /// The `[ground]` table: a square slab whose top is at its height.
    fn place_ground(&self, ground: &RawGround, file: &mut SceneFile) -> Result<(), SceneFileError> {
        let size = self.number(
            &ground.size,
            "ground.size",
            |s| s > 0.0 && s <= MAX_COORDINATE,
            "a positive size up to 1e7",
        )?;
        let height = match &ground.height {
            Some(h) => self.number(
                h,
                "ground.height",
                |h| h.abs() <= MAX_COORDINATE,
                "a height within 1e7 of 0",
            )?,
            None => 0.0,
        };
        let color = match &ground.color {
            Some(c) => Some(self.color(c, "ground.color")?),
            None => None,
        };
        let half = 0.5 * size;
        let thickness = 0.025 * size;
        file.meshes.push(
            Shape::Cuboid {
                half_extents: DVec3::new(half, 0.5 * thickness, half),
            }
            .mesh(),
        );
        file.objects.push(FileObject {
            name: "ground".into(),
            mesh: file.meshes.len() - 1,
            world_from_object: DMat4::from_translation(DVec3::new(
                0.0,
                height - 0.5 * thickness,
                0.0,
            )),
            casts: false,
            receives: true,
            color,
        });
        Ok(())
    }

    /// One `[[object]]`: its keys checked (cheap) before its mesh file is read, then one
    /// placed object per part of the file.
    fn place_object(
        &self,
        object: &RawObject,
        loaded: &mut MeshFiles,
        file: &mut SceneFile,
    ) -> Result<(), SceneFileError> {
        let mesh_start = object.mesh.span().start;
        let relative = object.mesh.get_ref();
        if relative.trim().is_empty() {
            return Err(self.at(mesh_start, "mesh", "names no file"));
        }
        let placement = self.placement(object)?;
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let parts = loaded
            .parts(&folder.join(relative), placement.split, file)
            .map_err(|e| self.at(mesh_start, "mesh", e.to_string()))?;
        let name = object.name.clone().unwrap_or_else(|| {
            Path::new(relative)
                .file_stem()
                .map_or("mesh".into(), |s| s.to_string_lossy().into_owned())
        });
        let world_from_object = DMat4::from_scale_rotation_translation(
            placement.scale,
            DQuat::from_rotation_y(placement.angle_degrees.to_radians()),
            placement.translate,
        );
        for part in &parts {
            file.objects.push(FileObject {
                name: if part.label.is_empty() {
                    name.clone()
                } else {
                    format!("{name} {}", part.label)
                },
                mesh: part.mesh,
                world_from_object: world_from_object * part.file_from_part,
                casts: object.casts.unwrap_or(true),
                receives: object.receives.unwrap_or(true),
                color: placement.color.or(part.color),
            });
        }
        Ok(())
    }

    /// An object's translation, scale, rotation, colour and split, checked.
    fn placement(&self, object: &RawObject) -> Result<Placement, SceneFileError> {
        let translate = match &object.translate {
            Some(t) => self.vec3(t, "translate")?,
            None => DVec3::ZERO,
        };
        let scale = match &object.scale {
            Some(s) => self.scale(s)?,
            None => DVec3::ONE,
        };
        let angle_degrees = match &object.rotate_y_degrees {
            Some(a) => self.number(a, "rotate_y_degrees", |_| true, "a finite angle")?,
            None => 0.0,
        };
        let color = match &object.color {
            Some(c) => Some(self.color(c, "color")?),
            None => None,
        };
        let split = match &object.split {
            None => false,
            Some(v) => match v.get_ref().as_str() {
                "none" => false,
                "components" => true,
                other => {
                    return Err(self.at(
                        v.span().start,
                        "split",
                        format!("'{other}' is not none or components"),
                    ));
                }
            },
        };
        Ok(Placement {
            translate,
            scale,
            angle_degrees,
            color,
            split,
        })
    }

    /// `scale = s` or `[sx, sy, sz]`, each positive and within the core's range.
    fn scale(&self, s: &Spanned<Scale>) -> Result<DVec3, SceneFileError> {
        let axes = match *s.get_ref() {
            Scale::Uniform(v) => [v; 3],
            Scale::Axes(v) => v,
        };
        match axes
            .iter()
            .find(|v| !(v.is_finite() && **v > 0.0 && **v <= MAX_COORDINATE))
        {
            Some(bad) => Err(self.at(
                s.span().start,
                "scale",
                format!("{bad} is not a positive scale up to 1e7"),
            )),
            None => Ok(DVec3::from_array(axes)),
        }
    }
}

impl MeshFiles {
    /// The parts of the mesh file at `mesh_path` (split into connected pieces with `split`),
    /// read and added to the scene's meshes the first time, shared after.
    fn parts(
        &mut self,
        mesh_path: &Path,
        split: bool,
        file: &mut SceneFile,
    ) -> Result<Vec<LoadedPart>, crate::LoadError> {
        if let Some((_, _, parts)) = self
            .0
            .iter()
            .find(|(p, s, _)| p == mesh_path && *s == split)
        {
            return Ok(parts.clone());
        }
        let (parts, notes) = Mesh::load_parts(mesh_path)?;
        file.notes.extend(
            notes
                .into_iter()
                .map(|n| format!("{}: {n}", mesh_path.display())),
        );
        let several = parts.len() > 1;
        let mut loaded = Vec::new();
        for part in parts {
            let label = if several {
                part.name.clone()
            } else {
                String::new()
            };
            let pieces = if split {
                part.mesh.components()
            } else {
                vec![part.mesh]
            };
            let instanced = part.placements.len() > 1;
            for (j, piece) in pieces.into_iter().enumerate() {
                file.meshes.push(piece);
                let label = match (label.is_empty(), split) {
                    (true, true) => format!("#{j}"),
                    (false, true) => format!("{label} #{j}"),
                    (_, false) => label.clone(),
                };
                // A mesh the file places several times is one mesh, drawn as an instance at
                // each place.
                for (n, placement) in part.placements.iter().enumerate() {
                    loaded.push(LoadedPart {
                        mesh: file.meshes.len() - 1,
                        label: match (instanced, label.is_empty()) {
                            (false, _) => label.clone(),
                            (true, true) => format!("[{n}]"),
                            (true, false) => format!("{label} [{n}]"),
                        },
                        color: part.color,
                        file_from_part: *placement,
                    });
                }
            }
        }
        self.0
            .push((mesh_path.to_path_buf(), split, loaded.clone()));
        Ok(loaded)
    }
}

impl Located<'_> {
    /// One `[[view]]`: its name (unique among `earlier`), its camera and its lights, checked
    /// as the core checks them.
    fn view(
        &self,
        view: &Spanned<RawView>,
        earlier: &[NamedView],
    ) -> Result<NamedView, SceneFileError> {
        let start = view.span().start;
        let view = view.get_ref();
        let name = view.name.get_ref().trim().to_string();
        if name.is_empty() {
            return Err(self.at(view.name.span().start, "name", "a view needs a name"));
        }
        if earlier.iter().any(|v| v.name == name) {
            return Err(self.at(
                view.name.span().start,
                "name",
                format!("a second view named '{name}'"),
            ));
        }
        let defaults = gnomon::Lens::default();
        let distance = |v: &Option<Spanned<f64>>, key: &str, default: f64| match v {
            Some(v) => self.number(
                v,
                key,
                |d| d > 0.0 && d <= MAX_COORDINATE,
                "a positive distance up to 1e7",
            ),
            None => Ok(default),
        };
        let mut lights = self.view_lights(view, start, &name)?;
        let light = lights.remove(0);
        let named = NamedView {
            name: name.clone(),
            description: view.description.clone().unwrap_or_default(),
            eye: self.vec3(&view.eye, "eye")?,
            target: self.vec3(&view.target, "target")?,
            up: match &view.up {
                Some(u) => self.vec3(u, "up")?,
                None => DVec3::Y,
            },
            fov_y_degrees: match &view.fov {
                Some(f) => self.number(
                    f,
                    "fov",
                    |f| f > 0.0 && f < 180.0,
                    "a field of view in (0, 180) degrees",
                )?,
                None => defaults.fov_y_degrees,
            },
            near: distance(&view.near, "near", defaults.near)?,
            far: distance(&view.far, "far", 400.0)?,
            light,
            more_lights: lights,
        };
        // The camera and lights as the core checks them (eye at the target, up along the
        // view, near beyond far, a bad spot), at this view's line.
        named
            .camera(16.0 / 9.0)
            .and_then(|_| named.lights())
            .map_err(|e| self.at(start, "view", format!("view '{name}': {e}")))?;
        Ok(named)
    }

    /// A view's lights, its own first, then its `[[view.light]]` tables: one to
    /// [`MAX_VIEW_LIGHTS`].
    fn view_lights(
        &self,
        view: &RawView,
        start: usize,
        name: &str,
    ) -> Result<Vec<ViewLight>, SceneFileError> {
        let mut lights = Vec::new();
        lights.extend(self.light(&view.light_dir, &view.spot, &view.point, name)?);
        for table in view.light.iter().flatten() {
            let light = table.get_ref();
            match self.light(&light.light_dir, &light.spot, &light.point, name)? {
                Some(l) => lights.push(l),
                None => {
                    return Err(self.at(
                        table.span().start,
                        "view.light",
                        format!("a light of view '{name}' needs light_dir, spot or point"),
                    ));
                }
            }
        }
        if lights.is_empty() {
            return Err(self.at(
                start,
                "view",
                format!("view '{name}' needs a light: light_dir, spot, point or [[view.light]]"),
            ));
        }
        if lights.len() > MAX_VIEW_LIGHTS {
            return Err(self.at(
                start,
                "view",
                format!(
                    "view '{name}' has {} lights; the renderer draws at most {MAX_VIEW_LIGHTS}",
                    lights.len()
                ),
            ));
        }
        Ok(lights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SceneFile, SceneFileError> {
        SceneFile::parse(Path::new("/nonexistent/scene.toml"), text)
    }

    #[test]
    fn a_ground_and_views_without_meshes() {
        let file = parse(
            "[ground]\nsize = 100\nheight = 2\n\n[[view]]\nname = \"a\"\neye = [0, 10, 30]\n\
             target = [0, 0, 0]\nlight_dir = [0.3, -1, 0.2]\n\n[[view]]\nname = \"b\"\n\
             eye = [5, 5, 5]\ntarget = [0, 0, 0]\nfov = 40\nnear = 0.5\nfar = 90\n\
             spot = [0, 20, 0, 0, -1, 0, 30, 50]\n",
        )
        .unwrap();
        assert_eq!(file.name, "scene");
        assert_eq!(file.objects.len(), 1);
        let ground = &file.objects[0];
        assert!(!ground.casts && ground.receives);
        // The slab's top is at the height.
        let top = file.meshes[0]
            .positions
            .iter()
            .map(|p| ground.world_from_object.transform_point3(*p).y)
            .fold(f64::MIN, f64::max);
        assert!((top - 2.0).abs() < 1e-12);
        assert_eq!(file.views.len(), 2);
        assert_eq!(file.views[1].fov_y_degrees, 40.0);
        assert_eq!(file.views[1].far, 90.0);
        assert!(matches!(
            file.views[1].light,
            ViewLight::Spot { range: 50.0, .. }
        ));
        assert_eq!(file.views[0].far, 400.0);
        // Lights as [[view.light]] tables, after or instead of the view's own.
        let file = parse(
            "[ground]\nsize = 100\n[[view]]\nname = \"a\"\neye = [0, 10, 30]\ntarget = [0, 0, 0]\n\
             [[view.light]]\nlight_dir = [0, -1, 0]\n[[view.light]]\n\
             spot = [0, 20, 0, 0, -1, 0, 30, 50]\n[[view.light]]\npoint = [1, 3, -2, 40]\n",
        )
        .unwrap();
        let view = &file.views[0];
        assert!(matches!(view.light, ViewLight::Directional { .. }));
        assert_eq!(view.more_lights.len(), 2);
        assert_eq!(
            view.more_lights[1],
            ViewLight::Point {
                position: DVec3::new(1.0, 3.0, -2.0),
                range: 40.0
            }
        );
        assert_eq!(view.lights().unwrap().len(), 3);
    }

    /// Each broken file: the line and key named, one line of text.
    #[test]
    fn errors_name_the_line_and_key() {
        let cases: &[(&str, usize, Option<&str>, &str)] = &[
            (
                "[ground]\nsize = 10\ncolour = [1, 1, 1]\n",
                3,
                None,
                "unknown field",
            ),
            (
                "[ground]\nsize = \"big\"\n",
                2,
                Some("size"),
                "invalid type",
            ),
            (
                "[ground]\nsize = -3\n",
                2,
                Some("ground.size"),
                "is not a positive size",
            ),
            ("[ground]\nsize = nan\n", 2, Some("ground.size"), "is not"),
            (
                "[[object]]\nmesh = \"missing.off\"\n",
                2,
                Some("mesh"),
                "missing.off",
            ),
            ("[[object]]\nscale = 2\n", 1, None, "missing field `mesh`"),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\n",
                3,
                Some("view"),
                "needs a light",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\n\
                 light_dir = [0, -1, 0]\npoint = [0, 5, 0, 20]\n",
                8,
                Some("point"),
                "gives point and another light",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\n\
                 point = [0, 5, 0, -20]\n",
                3,
                Some("view"),
                "range",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1]\n",
                5,
                Some("eye"),
                "",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 0, 0]\ntarget = [0, 0, 0]\nlight_dir = [0, -1, 0]\n",
                3,
                Some("view"),
                "view 'v'",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\nlight_dir = [0, -1, 0]\nfov = 200\n",
                8,
                Some("fov"),
                "field of view",
            ),
            (
                "[ground]\nsize = 10\ncolor = [2, 0, 0]\n",
                3,
                Some("ground.color"),
                "colour",
            ),
            ("name = \"x\"\n", 0, Some("object"), "no objects"),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\n[[view.light]]\nlight_dir = [0, 0, 0]\n",
                3,
                Some("view"),
                "zero",
            ),
            (
                "[ground]\nsize = 10\n[[view]]\nname = \"v\"\neye = [0, 1, 2]\ntarget = [0, 0, 0]\n[[view.light]]\nfov = 3\n",
                8,
                Some("fov"),
                "unknown field",
            ),
            ("[ground\nsize = 1\n", 1, None, ""),
            (
                "[[object]]\nmesh = \"a.off\"\nscale = [1, 0, 1]\n",
                3,
                Some("scale"),
                "0 is not a positive scale",
            ),
            (
                "[[object]]\nmesh = \"a.off\"\nscale = \"big\"\n",
                3,
                Some("scale"),
                "a scale is a positive number",
            ),
        ];
        for &(text, line, key, words) in cases {
            let e = parse(text).expect_err(text);
            if line > 0 {
                assert_eq!(e.line, Some(line), "{text}: {e}");
            }
            if key.is_some() {
                assert_eq!(e.key.as_deref(), key, "{text}: {e}");
            }
            let shown = e.to_string();
            assert!(shown.contains(words), "{text}: {shown}");
            assert!(!shown.contains('\n'), "{shown}");
            assert!(shown.starts_with("/nonexistent/scene.toml"), "{shown}");
        }
    }

    #[test]
    fn objects_share_a_mesh_file_and_place_it() {
        let dir = std::env::temp_dir().join(format!("gnomon-scene-file-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("m")).unwrap();
        std::fs::write(
            dir.join("m/tri.off"),
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        )
        .unwrap();
        let text = "[[object]]\nmesh = \"m/tri.off\"\n\n[[object]]\nmesh = \"m/tri.off\"\n\
                    name = \"second\"\ntranslate = [10, 0, 0]\nscale = 2\nrotate_y_degrees = 90\n\
                    casts = false\ncolor = [1, 0, 0]\n";
        let file = SceneFile::parse(&dir.join("s.toml"), text).unwrap();
        assert_eq!(file.meshes.len(), 1);
        assert_eq!(file.objects.len(), 2);
        assert_eq!(file.objects[0].name, "tri");
        let second = &file.objects[1];
        assert_eq!(second.name, "second");
        assert!(!second.casts && second.receives);
        assert_eq!(second.color, Some([1.0, 0.0, 0.0]));
        // (1, 0, 0) scaled by 2, turned 90 degrees about y (x goes to -z), moved by 10 in x.
        let p = second
            .world_from_object
            .transform_point3(DVec3::new(1.0, 0.0, 0.0));
        assert!((p - DVec3::new(10.0, 0.0, -2.0)).length() < 1e-12, "{p}");
        // Two triangles apart in one file, split: two objects with their own meshes.
        std::fs::write(
            dir.join("m/two.off"),
            "OFF\n6 2 0\n0 0 0\n1 0 0\n0 1 0\n5 0 0\n6 0 0\n5 1 0\n3 0 1 2\n3 3 4 5\n",
        )
        .unwrap();
        let text = "[[object]]\nmesh = \"m/two.off\"\nsplit = \"components\"\n\n[[object]]\n\
                    mesh = \"m/two.off\"\n";
        let file = SceneFile::parse(&dir.join("s.toml"), text).unwrap();
        assert_eq!(file.meshes.len(), 3);
        let names: Vec<&str> = file.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["two #0", "two #1", "two"]);
        assert_eq!(file.meshes[1].bounds().0, DVec3::new(5.0, 0.0, 0.0));
        let e = SceneFile::parse(
            &dir.join("s.toml"),
            "[[object]]\nmesh = \"m/two.off\"\nsplit = \"parts\"\n",
        )
        .unwrap_err();
        assert!(e.to_string().contains(":3: key 'split'"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A valid scene file, damaged at random (bytes deleted, replaced or inserted, lines
    /// cut): parsing never panics, and a refusal is one line naming the file.
    mod damaged {
        use proptest::prelude::*;

        use super::*;

        const VALID: &str = "name = \"s\"\n[ground]\nsize = 100\nheight = 2\n\n[[view]]\n\
            name = \"a\"\neye = [0, 10, 30]\ntarget = [0, 0, 0]\nfov = 50\nnear = 0.5\nfar = 90\n\
            light_dir = [0.3, -1, 0.2]\n\n[[view]]\nname = \"b\"\neye = [5, 5, 5]\ntarget = [0, 1, 0]\n\
            spot = [0, 20, 0, 0, -1, 0, 30, 50]\n[[view.light]]\nlight_dir = [1, -1, 0]\n";

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(2000))]
            #[test]
            fn never_panics_and_refuses_in_one_line(
                edits in proptest::collection::vec((0usize..400, 0u8..4, any::<u8>()), 1..6)
            ) {
                let mut bytes = VALID.as_bytes().to_vec();
                for (at, kind, byte) in edits {
                    let at = at % (bytes.len() + 1);
                    match kind {
                        0 if at < bytes.len() => { bytes.remove(at); }
                        1 if at < bytes.len() => bytes[at] = byte,
                        2 => bytes.insert(at, byte),
                        _ => {
                            // Cut the text from a line's start to the next line's.
                            let start = bytes[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                            let end = bytes[at..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| at + i + 1);
                            bytes.drain(start..end);
                        }
                    }
                }
                let text = String::from_utf8_lossy(&bytes);
                match parse(&text) {
                    Ok(file) => {
                        for view in &file.views {
                            prop_assert!(view.camera(16.0 / 9.0).is_ok() && view.lights().is_ok());
                        }
                    }
                    Err(e) => {
                        let shown = e.to_string();
                        prop_assert!(!shown.contains('\n'), "{}", shown);
                        prop_assert!(shown.starts_with("/nonexistent/scene.toml"), "{}", shown);
                    }
                }
            }
        }
    }
}
