//! The built-in demo scene: about 400 m across, with a ground slab, city blocks of different
//! heights, a long avenue lined with thin poles, and free-standing spheres, tori and torus
//! knots in a park. Everything casts and receives shadows.

use glam::{DMat4, DQuat, DVec3};
use gnomon::{Camera, Lens, Light, SetupError};

use crate::view::{NamedView, ViewLight};
use crate::{SceneLayout, SceneObject, Shape};

/// Half the ground's size: the scene spans [-200, 200] m in x and z.
pub const GROUND_HALF_SIZE: f64 = 200.0;

/// A named camera and sun for the demo scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemoView {
    /// The view's name.
    pub name: &'static str,
    /// Where the camera is.
    pub eye: [f64; 3],
    /// What it looks at.
    pub target: [f64; 3],
    /// The direction the sunlight travels.
    pub light: DemoLight,
    /// The camera's far plane distance (near is 1 m, the vertical field of view 60 degrees).
    pub far: f64,
    /// What the view shows.
    pub description: &'static str,
}

impl DemoView {
    /// The view's camera, for an image of width / height `aspect`, and its light. Errors only
    /// for a bad `aspect` (the views themselves are valid).
    pub fn camera_and_light(&self, aspect: f64) -> Result<(Camera, Light), SetupError> {
        let lens = Lens {
            far: self.far,
            aspect,
            ..Lens::default()
        };
        let camera = Camera::look_at(
            DVec3::from_array(self.eye),
            DVec3::from_array(self.target),
            DVec3::Y,
            lens,
        )?;
        Ok((camera, self.light.view_light().light()?))
    }
}

/// The light of a demo view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DemoLight {
    /// The sun: the direction its light travels.
    Sun([f64; 3]),
    /// A lamp: a point light at `position` reaching `range` metres.
    Lamp {
        /// Where it is.
        position: [f64; 3],
        /// How far it reaches.
        range: f64,
    },
}

impl DemoLight {
    /// The light as a named view's.
    pub fn view_light(&self) -> ViewLight {
        match *self {
            DemoLight::Sun(d) => ViewLight::Directional {
                direction: DVec3::from_array(d),
            },
            DemoLight::Lamp { position, range } => ViewLight::Point {
                position: DVec3::from_array(position),
                range,
            },
        }
    }
}

/// The demo's named views, from easy to hard for shadow maps.
pub const DEMO_VIEWS: &[DemoView] = &[
    DemoView {
        name: "overview",
        far: 800.0,
        eye: [260.0, 190.0, 260.0],
        target: [0.0, 0.0, 0.0],
        light: DemoLight::Sun([-0.4, -1.0, -0.25]),
        description: "the whole scene from high up, sun high behind the viewer",
    },
    DemoView {
        name: "overhead_sun",
        far: 400.0,
        eye: [-150.0, 60.0, 150.0],
        target: [0.0, 0.0, 0.0],
        light: DemoLight::Sun([0.05, -1.0, 0.08]),
        description: "the city at noon: the sun straight overhead, short shadows",
    },
    DemoView {
        name: "street",
        far: 400.0,
        eye: [-185.0, 2.0, 58.0],
        target: [185.0, 2.0, 58.0],
        light: DemoLight::Sun([0.35, -0.6, 1.0]),
        description: "down the long avenue at eye height, low sun from the side",
    },
    DemoView {
        name: "low_sun",
        far: 400.0,
        eye: [120.0, 25.0, 190.0],
        target: [0.0, 5.0, 0.0],
        light: DemoLight::Sun([1.0, -0.18, 0.3]),
        description: "the city under a low sun: long shadows",
    },
    DemoView {
        name: "dueling_frusta",
        far: 400.0,
        eye: [150.0, 8.0, 150.0],
        target: [0.0, 20.0, 0.0],
        light: DemoLight::Sun([0.6, -0.45, 0.6]),
        description: "looking into the sun",
    },
    DemoView {
        name: "miners_lamp",
        far: 400.0,
        eye: [100.0, 120.0, 100.0],
        target: [0.0, 0.0, 0.0],
        light: DemoLight::Sun([-0.55, -0.65, -0.55]),
        description: "looking along the light",
    },
    DemoView {
        name: "light_behind",
        far: 400.0,
        eye: [-190.0, 14.0, 58.0],
        target: [0.0, 4.0, 10.0],
        light: DemoLight::Sun([0.85, -0.4, -0.15]),
        description: "a low sun behind the viewer, shadows falling away from the camera",
    },
    DemoView {
        name: "street_lamp",
        far: 300.0,
        eye: [-98.0, 7.0, 80.0],
        target: [-60.0, 1.0, 52.0],
        light: DemoLight::Lamp {
            position: [-60.0, 8.6, 58.0],
            range: 120.0,
        },
        description: "a lamp over the avenue at night: the poles' and blocks' shadows fan out from it",
    },
    DemoView {
        name: "courtyard_lamp",
        far: 300.0,
        eye: [-128.0, 95.0, -104.0],
        target: [-138.0, 0.0, -140.0],
        light: DemoLight::Lamp {
            position: [-141.0, 3.0, -135.0],
            range: 150.0,
        },
        description: "a lamp at a crossing between four blocks: each face of its cube sees a street",
    },
    DemoView {
        name: "lamp_by_wall",
        far: 300.0,
        eye: [-50.0, 14.0, -48.0],
        target: [-78.0, 0.0, -62.0],
        light: DemoLight::Lamp {
            position: [-63.5, 4.0, -77.0],
            range: 100.0,
        },
        description: "a lamp 2.5 m from a block's wall: the wall, the street and the ground fall in different faces",
    },
];

/// A small deterministic hash, so that the layout is the same on every machine.
fn hash(i: u32) -> u32 {
    let mut x = i.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 15;
    x = x.wrapping_mul(0x2C1B_3C6D);
    x ^= x >> 12;
    x
}

fn object(name: String, shape: Shape, world_from_object: DMat4) -> SceneObject {
    SceneObject {
        name,
        shape,
        world_from_object,
        casts: true,
        receives: true,
    }
}

/// The demo scene.
pub fn demo() -> SceneLayout {
    let mut objects = Vec::new();
    objects.push(object(
        "ground".into(),
        Shape::Cuboid {
            half_extents: DVec3::new(GROUND_HALF_SIZE, 0.5, GROUND_HALF_SIZE),
        },
        DMat4::from_translation(DVec3::new(0.0, -0.5, 0.0)),
    ));
    // City blocks: a 5 x 5 grid, 24 m blocks on a 40 m pitch, 8 to 60 m tall.
    for i in 0..5u32 {
        for j in 0..5u32 {
            let h = 8.0 + (hash(i * 5 + j) % 53) as f64;
            let center = DVec3::new(
                -170.0 + 12.0 + 40.0 * i as f64,
                0.5 * h,
                -170.0 + 12.0 + 40.0 * j as f64,
            );
            objects.push(object(
                format!("block_{i}_{j}"),
                Shape::Cuboid {
                    half_extents: DVec3::new(12.0, 0.5 * h, 12.0),
                },
                DMat4::from_translation(center),
            ));
        }
    }
    // The avenue (z from 48 to 68, across the whole ground) lined with poles every 20 m.
    for k in 0..19 {
        let x = -180.0 + 20.0 * k as f64;
        for z in [48.0, 68.0] {
            objects.push(object(
                format!("pole_{k}_{}", z as i32),
                Shape::Pole {
                    radius: 0.15,
                    height: 8.0,
                },
                DMat4::from_translation(DVec3::new(x, 0.0, z)),
            ));
        }
    }
    // The park: spheres, tori and knots.
    let spheres = [
        (110.0, 5.0, 110.0, 5.0),
        (150.0, 8.0, 140.0, 8.0),
        (95.0, 14.0, 160.0, 3.0),
        (130.0, 3.0, -60.0, 3.0),
    ];
    for (n, (x, y, z, r)) in spheres.into_iter().enumerate() {
        objects.push(object(
            format!("sphere_{n}"),
            Shape::Sphere { radius: r },
            DMat4::from_translation(DVec3::new(x, y, z)),
        ));
    }
    let tori = [
        (
            120.0,
            10.0,
            170.0,
            DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
        ),
        (170.0, 2.0, 100.0, DQuat::IDENTITY),
        (
            100.0,
            9.0,
            -120.0,
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        ),
    ];
    for (n, (x, y, z, rotation)) in tori.into_iter().enumerate() {
        objects.push(object(
            format!("torus_{n}"),
            Shape::Torus {
                major_radius: 7.0,
                minor_radius: 2.0,
            },
            DMat4::from_rotation_translation(rotation, DVec3::new(x, y, z)),
        ));
    }
    let knots = [(160.0, 12.0, -20.0), (80.0, 12.0, 130.0)];
    for (n, (x, y, z)) in knots.into_iter().enumerate() {
        objects.push(object(
            format!("knot_{n}"),
            Shape::TorusKnot {
                p: 2,
                q: 3,
                major_radius: 6.0,
                minor_radius: 3.0,
                tube_radius: 1.2,
            },
            DMat4::from_rotation_translation(DQuat::from_rotation_x(0.4), DVec3::new(x, y, z)),
        ));
    }
    SceneLayout {
        name: "demo".into(),
        objects,
    }
}

impl From<&DemoView> for NamedView {
    fn from(v: &DemoView) -> Self {
        let lens = Lens::default();
        Self {
            name: v.name.into(),
            description: v.description.into(),
            eye: DVec3::from_array(v.eye),
            target: DVec3::from_array(v.target),
            up: DVec3::Y,
            fov_y_degrees: lens.fov_y_degrees,
            near: lens.near,
            far: v.far,
            light: v.light.view_light(),
            more_lights: Vec::new(),
        }
    }
}

/// The demo's named views ([`crate::DEMO_VIEWS`]) as [`NamedView`]s.
pub fn demo_views() -> Vec<NamedView> {
    DEMO_VIEWS.iter().map(NamedView::from).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_layout_is_about_400_m_and_everything_casts_and_receives() {
        let scene = demo();
        let bounds = scene.bounds().unwrap();
        let s = bounds.scene_box();
        assert!((s.max().x - s.min().x - 400.0).abs() < 1.0);
        assert!((s.max().z - s.min().z - 400.0).abs() < 1.0);
        assert_eq!(bounds.casters().len(), scene.objects.len());
        assert_eq!(bounds.receivers().len(), scene.objects.len());
        let kinds: std::collections::BTreeSet<_> =
            scene.objects.iter().map(|o| o.shape.kind()).collect();
        assert_eq!(kinds.len(), 5, "every kind of shape appears: {kinds:?}");
        // Blocks of different heights.
        let heights: std::collections::BTreeSet<_> = bounds
            .casters()
            .iter()
            .filter(|b| b.max().y > 7.0)
            .map(|b| (b.max().y * 10.0) as i64)
            .collect();
        assert!(heights.len() > 10);
    }

    #[test]
    fn every_view_has_a_camera_and_its_light_and_bad_aspects_are_errors() {
        let mut lamps = 0;
        for view in DEMO_VIEWS {
            let (camera, light) = view.camera_and_light(16.0 / 9.0).unwrap();
            assert!((camera.eye() - DVec3::from_array(view.eye)).length() < 1e-9);
            match (light, view.light) {
                (Light::Directional(sun), DemoLight::Sun(d)) => {
                    let d = DVec3::from_array(d).normalize();
                    assert!((sun.direction() - d).length() < 1e-9, "{}", view.name);
                }
                (Light::Point(lamp), DemoLight::Lamp { position, range }) => {
                    assert_eq!(lamp.position(), DVec3::from_array(position));
                    assert_eq!(lamp.range(), range);
                    // The lamp lies in the open, not inside an object.
                    let inside = demo().objects.iter().any(|o| {
                        let b = o.world_bounds().unwrap();
                        (b.min().cmplt(lamp.position()) & lamp.position().cmplt(b.max())).all()
                    });
                    assert!(!inside, "{} is inside an object", view.name);
                    lamps += 1;
                }
                other => panic!("{}: {other:?}", view.name),
            }
            for aspect in [0.0, -1.0, f64::NAN] {
                assert!(view.camera_and_light(aspect).is_err(), "{aspect}");
            }
        }
        assert_eq!(lamps, 3, "the point-light views");
    }

    #[test]
    fn objects_do_not_overlap_the_avenue_or_each_other_much() {
        let scene = demo();
        for o in &scene.objects {
            let b = o.world_bounds().unwrap();
            if o.name.starts_with("block") {
                assert!(b.max().z < 48.0, "{} reaches into the avenue", o.name);
            }
            assert!(b.min().y >= -1.0 - 1e-9);
        }
    }
}
