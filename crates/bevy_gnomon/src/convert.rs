//! gnomon's maps as Bevy's cascades: glam 0.34 in f64 to Bevy's glam in f32, Bevy's
//! reversed depth, a world frame for the shadow view, and one texel size per map.

use bevy_light::cascade::Cascade;
use bevy_math::{Mat4, Quat};
use glam::{DMat4, DVec3, DVec4};
use gnomon::{Camera, ShadowMap};

/// Bevy's cascade for a gnomon map.
///
/// `world_from_light` is the light's rotation (Bevy's shadow view is oriented by it);
/// `read_at` is the world point where the texel size is measured (see [`texel_size`]).
pub(crate) fn cascade(map: &ShadowMap, world_from_light: Quat, read_at: DVec3) -> Cascade {
    let clip_from_world = reversed_depth(map.clip_from_world);
    // The shadow view's origin: the centre of the map's near plane (Bevy puts its own
    // there), found through the inverse so that it holds for warped maps too.
    let near_centre = clip_from_world.inverse() * DVec4::new(0.0, 0.0, 1.0, 1.0);
    let origin = if near_centre.w.abs() > f64::EPSILON {
        near_centre.truncate() / near_centre.w
    } else {
        DVec3::ZERO
    };
    let rotation = DMat4::from_quat(glam::DQuat::from_array(
        world_from_light.to_array().map(f64::from),
    ));
    let world_from_cascade = DMat4::from_translation(origin) * rotation;
    let clip_from_cascade = clip_from_world * world_from_cascade;
    Cascade {
        world_from_cascade: to_bevy(world_from_cascade),
        clip_from_cascade: to_bevy(clip_from_cascade),
        clip_from_world: to_bevy(clip_from_world),
        texel_size: texel_size(map, read_at) as f32,
    }
}

/// Bevy's depth is reversed (1 at the near plane, 0 at the far, compared with
/// `GreaterEqual`): z' = w - z, so that z'/w = 1 - z/w for orthographic and warped maps
/// alike.
pub(crate) fn reversed_depth(clip_from_world: DMat4) -> DMat4 {
    let rows = [0, 1, 2, 3].map(|i| clip_from_world.row(i));
    DMat4::from_cols(rows[0], rows[1], rows[3] - rows[2], rows[3]).transpose()
}

/// The world size of one texel at `p`, across the light: the square root of the world area
/// a texel covers there, from the derivatives of the map's x/w and y/w along two directions
/// perpendicular to the light. Constant over an orthographic map; a warped map's texels
/// grow with distance from the camera, so the size holds where `p` is.
pub(crate) fn texel_size(map: &ShadowMap, p: DVec3) -> f64 {
    let c = map.clip_from_world;
    let clip = c * p.extend(1.0);
    // The light's direction is the map's depth axis: the world direction its depth row
    // grows along.
    let along = map.depth_from_world.truncate().normalize_or(DVec3::NEG_Y);
    let e1 = along.any_orthonormal_vector();
    let e2 = along.cross(e1);
    let ndc_derivative = |e: DVec3| {
        let de = c * e.extend(0.0);
        (de.truncate().truncate() * clip.w - clip.truncate().truncate() * de.w) / (clip.w * clip.w)
    };
    let (d1, d2) = (ndc_derivative(e1), ndc_derivative(e2));
    let ndc_area = (d1.x * d2.y - d1.y * d2.x).abs();
    let texel_ndc = 2.0 / map.resolution as f64;
    if ndc_area > 0.0 && ndc_area.is_finite() && clip.w > 0.0 {
        texel_ndc / ndc_area.sqrt()
    } else {
        texel_ndc / (c.row(0).truncate().length() * c.row(1).truncate().length()).sqrt()
    }
}

/// Where a cascade is read, for its texel size: on the camera's axis, halfway in log depth
/// through the view depths the map serves (a slice's pixels spread over its depths about
/// evenly in log depth, as the practical split's slices do).
pub(crate) fn read_point(camera: &Camera, depths: [f64; 2]) -> DVec3 {
    let halfway = (depths[0].max(f64::MIN_POSITIVE) * depths[1]).sqrt();
    camera.eye() + camera.forward() * halfway
}

/// A gnomon matrix in Bevy's glam.
pub(crate) fn to_bevy(m: DMat4) -> Mat4 {
    Mat4::from_cols_array(&m.as_mat4().to_cols_array())
}

/// A Bevy vector in gnomon's glam.
pub(crate) fn from_bevy(v: bevy_math::Vec3) -> DVec3 {
    DVec3::new(v.x.into(), v.y.into(), v.z.into())
}
