//! A procedural city of 10^4 buildings: the built-in scene with many casters, for setup and
//! rendering at the scale of real scenes. A 100 x 100 grid of blocks on a 12 m pitch (1.2 km
//! across), each 5 to 9 m wide and 4 to 64 m tall, with an avenue every tenth row and
//! column, on a ground slab. Every building casts and receives.

use glam::{DMat4, DVec3};

use crate::view::{NamedView, ViewLight};
use crate::{SceneLayout, SceneObject, Shape};

/// Buildings on a side of the city's grid.
pub const CITY_SIDE: u32 = 100;

/// The grid's pitch in metres.
const PITCH: f64 = 12.0;

/// A small deterministic hash (the same layout on every machine).
fn hash(i: u32) -> u32 {
    let mut x = i.wrapping_mul(0x2C1B_3C6D) ^ 0x297A_2D39;
    x ^= x >> 12;
    x = x.wrapping_mul(0x297A_2D39);
    x ^= x >> 15;
    x
}

/// The city.
pub fn city() -> SceneLayout {
    let half = 0.5 * PITCH * CITY_SIDE as f64;
    let mut objects = vec![SceneObject {
        name: "ground".into(),
        shape: Shape::Cuboid {
            half_extents: DVec3::new(half + 50.0, 0.5, half + 50.0),
        },
        world_from_object: DMat4::from_translation(DVec3::new(0.0, -0.5, 0.0)),
        casts: true,
        receives: true,
    }];
    for i in 0..CITY_SIDE {
        for j in 0..CITY_SIDE {
            let h = hash(i * CITY_SIDE + j);
            // An avenue every tenth row and column: lower buildings set back from it.
            let avenue = i % 10 == 0 || j % 10 == 0;
            let height = if avenue {
                4.0 + (h % 9) as f64
            } else {
                6.0 + (h % 59) as f64
            };
            let width = 5.0 + ((h >> 8) % 5) as f64;
            let depth = 5.0 + ((h >> 12) % 5) as f64;
            let centre = DVec3::new(
                -half + PITCH * (i as f64 + 0.5),
                0.5 * height,
                -half + PITCH * (j as f64 + 0.5),
            );
            objects.push(SceneObject {
                name: format!("building_{i}_{j}"),
                shape: Shape::Cuboid {
                    half_extents: DVec3::new(0.5 * width, 0.5 * height, 0.5 * depth),
                },
                world_from_object: DMat4::from_translation(centre),
                casts: true,
                receives: true,
            });
        }
    }
    SceneLayout {
        name: "city".into(),
        objects,
    }
}

/// The city's named views: over the whole city, down an avenue at eye height under a low
/// sun, and looking into the sun across the roofs.
pub fn city_views() -> Vec<NamedView> {
    let view = |name: &str, description: &str, eye: DVec3, target: DVec3, far: f64, sun: DVec3| {
        NamedView {
            name: name.into(),
            description: description.into(),
            eye,
            target,
            up: DVec3::Y,
            fov_y_degrees: 60.0,
            near: 1.0,
            far,
            light: ViewLight::Directional { direction: sun },
            more_lights: Vec::new(),
        }
    };
    // The street at x = 0 runs between grid columns 49 and 50 (centres at -6 and 6, at most
    // 4.5 m half wide): at least 3 m clear.
    vec![
        view(
            "overview",
            "the whole city from high up, the sun high to the side",
            DVec3::new(700.0, 550.0, 800.0),
            DVec3::ZERO,
            2500.0,
            DVec3::new(0.5, -1.0, -0.3),
        ),
        view(
            "avenue",
            "down an avenue at eye height under a low sun: thousands of casters in view",
            DVec3::new(0.0, 2.0, 590.0),
            DVec3::new(0.0, 5.0, 0.0),
            1500.0,
            DVec3::new(1.0, -0.25, -0.2),
        ),
        view(
            "dueling_frusta",
            "across the roofs, looking into a low sun",
            DVec3::new(-500.0, 90.0, -500.0),
            DVec3::new(0.0, 20.0, 0.0),
            2000.0,
            DVec3::new(-0.6, -0.4, -0.6),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_city_has_ten_thousand_buildings_in_its_square() {
        let city = city();
        assert_eq!(city.objects.len(), 1 + 10_000);
        let bounds = city.bounds().unwrap();
        let b = bounds.scene_box();
        assert!(b.max().y <= 64.0 && b.max().x <= 650.0 && b.min().x >= -650.0);
        for view in city_views() {
            view.camera_and_light(16.0 / 9.0).unwrap();
        }
    }
}
