//! A point light's cube faces have no seam. In a closed room lit by a lamp off its centre, a
//! rotated cage of bars around the lamp throws shadows across each of the twelve cube-face
//! edges (every wall shows the four borders of the face that sees it). Six cameras, one per
//! wall, judge the 5x5 PCF shadow factor (not only the one-tap mask) on the pixels within 2
//! pixels of a face border and at least 3 pixels from the exact shadow's boundary: there the
//! filter's taps must read the face's own casters, so the factor must be 1 where the oracle
//! says lit and 0 where it says shadowed. A face map without its border of texels beyond 90
//! degrees (gnomon::CUBE_FACE_BORDER_TEXELS) reads cleared texels there and fails.

mod common;

use glam::{DMat4, DQuat, DVec3};
use gnomon::{Cube, CubeFace, Light, MapSelection, PointLight};
use gnomon_render::{Filter, MASK_EMPTY, MASK_LIT, RenderScene, RenderSettings, StencilMode};
use gnomon_scene::{SceneLayout, SceneObject, Shape};

const SIZE: u32 = 256;
const LAMP: DVec3 = DVec3::new(0.7, 0.4, -0.3);

fn room() -> SceneLayout {
    let mut objects = Vec::new();
    // Six walls, 12 m across, 0.5 m thick, receiving only.
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut half = DVec3::splat(6.5);
            half[axis] = 0.25;
            let mut at = DVec3::ZERO;
            at[axis] = sign * 6.25;
            objects.push(SceneObject {
                name: format!("wall_{axis}_{sign}"),
                shape: Shape::Cuboid { half_extents: half },
                world_from_object: DMat4::from_translation(at),
                casts: false,
                receives: true,
            });
        }
    }
    // The cage: the twelve edges of a cube of half-size 2.2 around the lamp, turned so that
    // the bars' shadows cross the face borders (unturned, they would lie along them).
    let turn =
        DQuat::from_rotation_y(0.21) * DQuat::from_rotation_x(0.14) * DQuat::from_rotation_z(0.1);
    for axis in 0..3 {
        for (u, v) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let mut half = DVec3::splat(0.12);
            half[axis] = 2.3;
            let mut at = DVec3::ZERO;
            at[(axis + 1) % 3] = 2.2 * u;
            at[(axis + 2) % 3] = 2.2 * v;
            objects.push(SceneObject {
                name: format!("bar_{axis}_{u}_{v}"),
                shape: Shape::Cuboid { half_extents: half },
                world_from_object: DMat4::from_translation(LAMP)
                    * DMat4::from_quat(turn)
                    * DMat4::from_translation(at),
                casts: true,
                receives: true,
            });
        }
    }
    SceneLayout {
        name: "cage".into(),
        objects,
    }
}

#[test]
fn pcf_has_no_seam_at_cube_face_borders() {
    let layout = room();
    let scene = RenderScene::from_layout(&layout);
    let bounds = layout.bounds().unwrap();
    let mut renderer = common::renderer(&scene);
    let light = Light::Point(PointLight::new(LAMP, 40.0).unwrap());
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        filter: Filter::Pcf5x5,
        ambient: 0.0,
        ..RenderSettings::default()
    };
    let srgb = |c: u8| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let mut totals = (0usize, 0usize, 0usize);
    let mut borders_seen = std::collections::BTreeSet::new();
    for face in CubeFace::ALL {
        // From the lamp's side of the room, 3.5 m off the lamp, looking at the wall the face
        // sees.
        let axis = face.axis();
        let side = axis.any_orthonormal_vector();
        let eye = LAMP - 1.5 * axis + 3.2 * side + 0.9 * axis.cross(side);
        let target = LAMP + 5.5 * axis;
        let up = if axis.y.abs() > 0.5 {
            DVec3::Z
        } else {
            DVec3::Y
        };
        let lens = gnomon::Lens {
            fov_y_degrees: 100.0,
            aspect: 1.0,
            near: 0.05,
            far: 40.0,
        };
        let camera = gnomon::Camera::look_at(eye, target, up, lens).unwrap();
        let setup = gnomon::compute_setup(
            &Cube,
            &camera,
            &light,
            &bounds,
            gnomon::MapSettings::with_resolution(1024),
        )
        .unwrap();
        let MapSelection::CubeFaces(faces) = setup.selection else {
            panic!("{:?}", setup.selection);
        };
        let frame = renderer.render(&camera, &light, &setup, &settings).unwrap();
        let exact = renderer
            .render_volumes(&camera, &light, &settings, StencilMode::ZFail)
            .unwrap()
            .frame;
        let oracle = common::oracle(&scene, &camera, &light, SIZE, SIZE);
        let w = SIZE as i64;
        let at = |x: i64, y: i64| (y * w + x) as usize;
        let face_of = |i: usize| oracle.points[i].map(|p| PointLight::face_of(p - LAMP));
        let (mut judged, mut wrong, mut shadowed) = (0usize, 0usize, 0usize);
        for y in 3..w - 3 {
            for x in 3..w - 3 {
                let i = at(x, y);
                let Some(own) = face_of(i) else { continue };
                if oracle.n_dot_l[i] < 0.2 || oracle.mask[i] == MASK_EMPTY {
                    continue;
                }
                // Within 2 pixels of a face border, 3 from the exact shadow's boundary.
                let mut near_border = None;
                let mut near_edge = false;
                for dy in -3..=3i64 {
                    for dx in -3..=3i64 {
                        let j = at(x + dx, y + dy);
                        if oracle.mask[j] != oracle.mask[i] {
                            near_edge = true;
                        }
                        if dx.abs() <= 2
                            && dy.abs() <= 2
                            && let Some(other) = face_of(j)
                            && other != own
                        {
                            near_border = Some(if own.index() < other.index() {
                                (own, other)
                            } else {
                                (other, own)
                            });
                        }
                    }
                }
                let (Some(border), false) = (near_border, near_edge) else {
                    continue;
                };
                let lit = oracle.mask[i] == MASK_LIT;
                let pcf = srgb(frame.color[4 * i + 1]);
                let reference = srgb(exact.color[4 * i + 1]);
                // Ambient 0: the exact frame's colour is the lit colour where lit, and a
                // shadowed pixel's is black (a factor of 0.1 would leave at least 0.01).
                if lit && reference <= 0.02 {
                    continue;
                }
                let factor_ok = if lit {
                    pcf >= 0.9 * reference
                } else {
                    pcf <= 0.01
                };
                judged += 1;
                shadowed += usize::from(!lit);
                if !factor_ok {
                    wrong += 1;
                }
                if !lit {
                    borders_seen.insert(border);
                }
            }
        }
        println!(
            "wall {}: {judged} border pixels judged ({shadowed} shadowed), {wrong} wrong; maps {:?}",
            face.name(),
            faces.faces()
        );
        totals.0 += judged;
        totals.1 += wrong;
        totals.2 += shadowed;
    }
    let (judged, wrong, shadowed) = totals;
    println!(
        "{judged} pixels judged, {shadowed} shadowed, {wrong} wrong; shadowed borders {}",
        borders_seen.len()
    );
    assert!(judged > 2000 && shadowed > 300, "too few pixels judged");
    assert_eq!(
        borders_seen.len(),
        12,
        "shadows cross every cube edge: {borders_seen:?}"
    );
    assert!(
        (wrong as f64) <= 0.005 * judged as f64,
        "{wrong} of {judged} border pixels have the wrong PCF factor"
    );
}
