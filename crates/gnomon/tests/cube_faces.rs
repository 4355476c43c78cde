//! A point light's cube faces keep a border beyond their 90 degrees: a lookup filtered at a
//! pixel beside a face's edge reads a texel or two past it, which must still hold the scene.
//! Where a face's map reaches one of its edges (a ground point just inside it lands in the
//! map), the ground point as far just past that edge lands in the map too (a face cut to
//! exactly 90 degrees puts it outside). Elsewhere the map is cut to what its casters can
//! shadow, and past the edge is outside it as the rest is.

use glam::DVec3;
use gnomon::{
    Aabb, Camera, Cube, CubeFace, Lens, Light, Lispsm, MapSelection, MapSettings, PointLight,
    SceneBounds, ShadowTechnique, compute_setup,
};

const LAMP: DVec3 = DVec3::new(0.0, 4.0, 0.0);

/// A ground slab and pillars around a lamp: tall ones beside it, whose shadows cross the
/// edges of the face below, and shorter ones farther out, along the axes and diagonals.
fn yard() -> SceneBounds {
    let ground = Aabb::new(DVec3::new(-60.0, -1.0, -60.0), DVec3::new(60.0, 0.0, 60.0)).unwrap();
    let pillars = [
        (1.0, 0.2, 3.5),
        (-1.6, -0.3, 3.5),
        (0.2, 1.2, 3.5),
        (-0.4, -1.7, 3.5),
        (7.0, 1.0, 3.0),
        (-8.0, -2.0, 3.0),
        (1.5, 9.0, 3.0),
        (-2.0, -7.0, 3.0),
        (6.0, 6.0, 3.0),
        (-6.0, 7.0, 3.0),
        (6.5, -6.0, 3.0),
        (-7.0, -6.5, 3.0),
    ];
    let mut casters = Vec::new();
    for (x, z, height) in pillars {
        let min = DVec3::new(x, 0.0, z);
        casters.push(Aabb::new(min, min + DVec3::new(0.6, height, 0.6)).unwrap());
    }
    let mut receivers = casters.clone();
    receivers.push(ground);
    SceneBounds::new(casters, receivers, None).unwrap()
}

/// The face's two other axes.
fn across(face: CubeFace) -> [DVec3; 2] {
    let a = face.axis().abs();
    if a.x > 0.5 {
        [DVec3::Y, DVec3::Z]
    } else if a.y > 0.5 {
        [DVec3::X, DVec3::Z]
    } else {
        [DVec3::X, DVec3::Y]
    }
}

/// Pairs of ground points (y = 0, within 20 m of the lamp) whose directions from the lamp lie
/// `texels` texels of a `resolution` map inside and past one of `face`'s edges.
fn across_the_edges(face: CubeFace, resolution: u32, texels: f64) -> Vec<[DVec3; 2]> {
    let offset = texels * 2.0 / f64::from(resolution);
    let [e1, e2] = across(face);
    let ground = |d: DVec3| {
        (d.y < -1e-3)
            .then(|| LAMP + d * (LAMP.y / -d.y))
            .filter(|p| (*p - LAMP).length() < 20.0)
    };
    let mut points = Vec::new();
    for (edge, along) in [(e1, e2), (e2, e1)] {
        for sign in [-1.0, 1.0] {
            for i in 0..=80 {
                let s = -0.95 + 1.9 * f64::from(i) / 80.0;
                let d = |t: f64| face.axis() + sign * t * edge + s * along;
                if let (Some(inside), Some(past)) =
                    (ground(d(1.0 - offset)), ground(d(1.0 + offset)))
                {
                    points.push([inside, past]);
                }
            }
        }
    }
    points
}

#[test]
fn points_just_past_a_faces_edge_land_inside_its_map() {
    let lens = Lens {
        fov_y_degrees: 90.0,
        aspect: 1.0,
        near: 1.0,
        far: 200.0,
    };
    let camera = Camera::look_at(DVec3::new(0.5, 40.0, 0.3), LAMP, DVec3::Z, lens).unwrap();
    let lamp = Light::Point(PointLight::new(LAMP, 100.0).unwrap());
    let techniques: [&dyn ShadowTechnique; 2] = [&Cube, &Lispsm::default()];
    for technique in techniques {
        for resolution in [256, 1024] {
            let map = MapSettings::with_resolution(resolution);
            let setup = compute_setup(technique, &camera, &lamp, &yard(), map).unwrap();
            let MapSelection::CubeFaces(faces) = setup.selection else {
                panic!("{:?}", setup.selection);
            };
            assert!(faces.faces().len() >= 5, "{:?}", faces.faces());
            let in_map = |q: Option<DVec3>| q.is_some_and(|q| q.x.abs() <= 1.0 && q.y.abs() <= 1.0);
            let mut checked = 0;
            for &face in faces.faces() {
                let map = &setup.maps[faces.map_of(face).unwrap()];
                for texels in [0.5, 1.5] {
                    for [inside, past] in across_the_edges(face, resolution, texels) {
                        assert_eq!(PointLight::face_of(inside - LAMP), face);
                        assert_ne!(PointLight::face_of(past - LAMP), face);
                        if !in_map(map.project(inside)) {
                            continue;
                        }
                        assert!(
                            in_map(map.project(past)),
                            "{} {resolution}: face {}, {past}, {texels} texels past: {:?}",
                            technique.name(),
                            face.name(),
                            map.project(past),
                        );
                        checked += 1;
                    }
                }
            }
            println!(
                "{} {resolution}: {checked} points past an edge",
                technique.name()
            );
            assert!(checked > 100, "{checked}");
        }
    }
}
