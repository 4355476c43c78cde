//! Named views: a camera and a light under a name, from the demo's table, a scene file, or
//! made to fit a mesh on its ground slab. Every command that takes `--view NAME` looks the
//! name up in its scene's list of these.

use glam::DVec3;
use gnomon::{Camera, DirectionalLight, Lens, Light, PointLight, SetupError, SpotLight};

/// The light of a named view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ViewLight {
    /// A directional light travelling along `direction`.
    Directional {
        /// The direction the light travels.
        direction: DVec3,
    },
    /// A spot light.
    Spot {
        /// Where it is.
        position: DVec3,
        /// Where it points.
        direction: DVec3,
        /// The cone's half angle in degrees.
        half_angle_degrees: f64,
        /// How far it reaches.
        range: f64,
    },
    /// A point light.
    Point {
        /// Where it is.
        position: DVec3,
        /// How far it reaches.
        range: f64,
    },
}

impl ViewLight {
    /// The validated light.
    pub fn light(&self) -> Result<Light, SetupError> {
        Ok(match *self {
            ViewLight::Directional { direction } => {
                Light::Directional(DirectionalLight::new(direction)?)
            }
            ViewLight::Spot {
                position,
                direction,
                half_angle_degrees,
                range,
            } => Light::Spot(SpotLight::new(
                position,
                direction,
                half_angle_degrees,
                range,
            )?),
            ViewLight::Point { position, range } => Light::Point(PointLight::new(position, range)?),
        })
    }
}

/// A camera and a light under a name.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedView {
    /// The view's name (what `--view` takes).
    pub name: String,
    /// What the view shows (may be empty).
    pub description: String,
    /// Where the camera is.
    pub eye: DVec3,
    /// What it looks at.
    pub target: DVec3,
    /// The image's up direction.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f64,
    /// Near plane distance.
    pub near: f64,
    /// Far plane distance.
    pub far: f64,
    /// The light (the view's main light: the one a command that takes one light uses).
    pub light: ViewLight,
    /// More lights, drawn with the first where a command draws several.
    pub more_lights: Vec<ViewLight>,
}

impl NamedView {
    /// The view's camera for an image of width / height `aspect`.
    pub fn camera(&self, aspect: f64) -> Result<Camera, SetupError> {
        let lens = Lens {
            fov_y_degrees: self.fov_y_degrees,
            aspect,
            near: self.near,
            far: self.far,
        };
        Camera::look_at(self.eye, self.target, self.up, lens)
    }

    /// The view's camera (for `aspect`) and its (main) light.
    pub fn camera_and_light(&self, aspect: f64) -> Result<(Camera, Light), SetupError> {
        Ok((self.camera(aspect)?, self.light.light()?))
    }

    /// Every light of the view, validated: the main light, then the others.
    pub fn lights(&self) -> Result<Vec<Light>, SetupError> {
        std::iter::once(&self.light)
            .chain(&self.more_lights)
            .map(ViewLight::light)
            .collect()
    }
}

/// Views of a mesh `height` tall standing on the origin (the mesh on its ground slab): an
/// oblique view under a high sun, the same camera under a low sun, and the camera looking
/// into a low sun. Near and far scale with the height.
pub fn mesh_views(height: f64) -> Vec<NamedView> {
    let h = height;
    let view = |name: &str, description: &str, eye: DVec3, target: DVec3, light: DVec3| NamedView {
        name: name.into(),
        description: description.into(),
        eye: eye * h,
        target: target * h,
        up: DVec3::Y,
        fov_y_degrees: Lens::default().fov_y_degrees,
        near: 0.05 * h,
        far: 20.0 * h,
        light: ViewLight::Directional { direction: light },
        more_lights: Vec::new(),
    };
    let (eye, target) = (DVec3::new(1.4, 1.2, 2.0), DVec3::new(0.0, 0.3, 0.0));
    vec![
        view(
            "oblique",
            "the mesh from above and to the side, sun high",
            eye,
            target,
            DVec3::new(0.5, -1.0, -0.3),
        ),
        view(
            "low_sun",
            "the same camera under a low sun: long shadows over the ground",
            eye,
            target,
            DVec3::new(-1.0, -0.2, 0.35),
        ),
        view(
            "dueling_frusta",
            "looking into a low sun",
            DVec3::new(1.6, 0.4, 1.6),
            DVec3::new(0.0, 0.4, 0.0),
            DVec3::new(0.6, -0.45, 0.6),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_views_keep_their_camera_and_sun() {
        for (named, demo) in crate::demo_views().iter().zip(crate::DEMO_VIEWS) {
            let (a, la) = named.camera_and_light(1.5).unwrap();
            let (b, lb) = demo.camera_and_light(1.5).unwrap();
            assert_eq!(a.view_from_world(), b.view_from_world());
            assert_eq!(a.lens(), b.lens());
            assert_eq!(la, lb);
        }
    }

    #[test]
    fn mesh_views_are_valid_and_scale_with_the_mesh() {
        for h in [0.01, 1.0, 1e4] {
            for v in mesh_views(h) {
                let (camera, _) = v.camera_and_light(16.0 / 9.0).unwrap();
                assert!((camera.lens().far - 20.0 * h).abs() < 1e-9 * h);
                // The mesh (its box, about h wide) lies in front of the camera.
                assert!(camera.forward().dot(-camera.eye()) > 0.0);
            }
        }
    }
}
