//! Which casters' volumes can reach the camera's near plane: those need z-fail; the others
//! can use z-pass without caps (Everitt and Kilgard 2002, section 4; Ogre's per-caster
//! choice).
//!
//! A caster's shadow volume holds a point r of the near-plane rectangle R exactly when the
//! segment from r toward the light meets the caster. The union of those segments over R is
//! the *near clip volume*: for a point light at P the pyramid conv(R, P); for a directional
//! light travelling along d the half-infinite prism R + t (-d), t >= 0. A caster whose
//! bounds lie wholly outside one of its planes cannot shadow any point of R, so its volume
//! cannot be cut by the near plane, and z-pass counts it right.

use glam::DVec3;

use crate::boxes::Aabb;
use crate::camera::Camera;
use crate::light::Light;

/// How much the near rectangle is grown on each side (a fraction of its size) so that
/// round-off at its edges never lets a volume through.
const RECTANGLE_MARGIN: f64 = 0.01;

/// Why every caster is treated as reaching the near plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NearClipFallback {
    /// The light lies (nearly) in the near plane, or a directional light travels (nearly)
    /// parallel to it: the near clip volume is flat, and the test is not trusted.
    LightInNearPlane,
}

/// The near clip volume of a camera and a light (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct NearClipVolume {
    /// Planes (n, offset) with the volume where n . x + offset <= 0.
    planes: Vec<(DVec3, f64)>,
    /// Set when the volume is flat: every caster reaches the near plane.
    fallback: Option<NearClipFallback>,
}

impl NearClipVolume {
    /// The near clip volume of `camera`'s near-plane rectangle (grown by 1% on each side)
    /// toward `light` (a spot light counts as the point light at its position).
    pub fn new(camera: &Camera, light: &Light) -> Self {
        let c = camera.frustum_corners();
        let centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
        let rect: [DVec3; 4] =
            [c[0], c[1], c[2], c[3]].map(|p| p + (p - centre) * (2.0 * RECTANGLE_MARGIN));
        let forward = camera.forward();
        let size = (rect[2] - rect[0]).length();
        // The direction from the rectangle toward the light, and the apex (point lights).
        let (toward_light, apex) = match light {
            Light::Directional(d) => (-d.direction(), None),
            Light::Spot(s) => (s.position() - centre, Some(s.position())),
            Light::Point(p) => (p.position() - centre, Some(p.position())),
        };
        // The light's side of the near plane, relative to the rectangle's size: a light in
        // the plane (or travelling along it) makes the volume flat.
        let height = forward.dot(toward_light);
        let flat = match apex {
            Some(_) => height.abs() <= 1e-6 * size,
            None => height.abs() <= 1e-6,
        };
        if flat || !height.is_finite() {
            return Self {
                planes: Vec::new(),
                fallback: Some(NearClipFallback::LightInNearPlane),
            };
        }
        let mut planes = Vec::with_capacity(5);
        // The near plane itself: the volume lies on the light's side.
        let base = if height > 0.0 { -forward } else { forward };
        planes.push((base, -base.dot(centre)));
        // An interior point, to orient the side planes.
        let inside = match apex {
            Some(p) => 0.8 * centre + 0.2 * p,
            None => centre + toward_light.normalize() * size,
        };
        for k in 0..4 {
            let (a, b) = (rect[k], rect[(k + 1) % 4]);
            // The side through edge ab and the light: containing the light's position, or the
            // direction toward a directional light.
            let along = match apex {
                Some(p) => p - a,
                None => toward_light,
            };
            let n = (b - a).cross(along).normalize_or_zero();
            if n == DVec3::ZERO {
                continue; // Edge-on: the other planes still bound the volume.
            }
            let n = if n.dot(inside - a) > 0.0 { -n } else { n };
            planes.push((n, -n.dot(a)));
        }
        // A point light: nothing beyond the light casts on R. The plane through the light
        // facing away from R bounds conv(R, P) where every corner of R lies behind it.
        if let Some(p) = apex {
            let n = (p - centre).normalize_or_zero();
            if n != DVec3::ZERO && rect.iter().all(|r| n.dot(*r - p) <= 0.0) {
                planes.push((n, -n.dot(p)));
            }
        }
        Self {
            planes,
            fallback: None,
        }
    }

    /// Whether the volume of a caster inside `bounds` may reach the near plane: false only
    /// when a plane of the near clip volume has the whole box outside (conservative: boxes
    /// near an edge of the volume count as reaching it).
    pub fn may_reach(&self, bounds: &Aabb) -> bool {
        if self.fallback.is_some() {
            return true;
        }
        let (centre, half) = (bounds.center(), bounds.half_extents());
        self.planes.iter().all(|(n, offset)| {
            // The box's corner deepest inside the plane: centre - |n| . half.
            n.dot(centre) + offset - n.abs().dot(half) <= 0.0
        })
    }

    /// Set when every caster counts as reaching the near plane, and why.
    pub fn fallback(&self) -> Option<NearClipFallback> {
        self.fallback
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Lens;
    use crate::light::{DirectionalLight, SpotLight};
    use proptest::prelude::*;

    fn camera(eye: DVec3, target: DVec3, near: f64) -> Camera {
        let lens = Lens {
            fov_y_degrees: 60.0,
            aspect: 1.5,
            near,
            far: 500.0,
        };
        Camera::look_at(eye, target, DVec3::Y, lens).unwrap()
    }

    fn unit(v: [f64; 3]) -> DVec3 {
        DVec3::from_array(v)
    }

    /// Whether a segment from `r` toward the light (to the light's position, or 1e4 along
    /// the direction toward a directional light) meets the box, by sampling it densely.
    fn segment_hits(r: DVec3, light: &Light, b: &Aabb) -> bool {
        let end = match light {
            Light::Directional(d) => r - d.direction() * 1e4,
            Light::Spot(s) => s.position(),
            Light::Point(p) => p.position(),
        };
        // Clip the segment to the slab of each axis (exact segment-box test).
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let d = end - r;
        for axis in 0..3 {
            let (lo, hi, o, v) = (b.min()[axis], b.max()[axis], r[axis], d[axis]);
            if v.abs() < 1e-300 {
                if o < lo || o > hi {
                    return false;
                }
            } else {
                let (a, c) = ((lo - o) / v, (hi - o) / v);
                t0 = t0.max(a.min(c));
                t1 = t1.min(a.max(c));
            }
        }
        t0 <= t1
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Soundness: a box the test lets go (z-pass) is hit by no segment from the near
        /// rectangle toward the light.
        #[test]
        fn boxes_let_go_cast_no_shadow_on_the_near_plane(
            eye in prop::array::uniform3(-20.0..20.0f64),
            look in prop::array::uniform3(-1.0..1.0f64),
            near in 0.1..3.0f64,
            spot in any::<bool>(),
            light_at in prop::array::uniform3(-30.0..30.0f64),
            light_dir in prop::array::uniform3(-1.0..1.0f64),
            box_at in prop::array::uniform3(-30.0..30.0f64),
            box_half in prop::array::uniform3(0.1..6.0f64),
            samples in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64), 64),
        ) {
            let eye = unit(eye);
            prop_assume!(unit(look).length() > 0.1 && unit(light_dir).length() > 0.1);
            prop_assume!(unit(look).normalize().cross(DVec3::Y).length() > 0.05);
            let camera = camera(eye, eye + unit(look), near);
            let light = if spot {
                match SpotLight::new(unit(light_at), unit(light_dir), 60.0, 100.0) {
                    Ok(s) => Light::Spot(s),
                    Err(_) => return Ok(()),
                }
            } else {
                Light::Directional(DirectionalLight::new(unit(light_dir)).unwrap())
            };
            let b = Aabb::from_center_half_extents(unit(box_at), unit(box_half)).unwrap();
            let volume = NearClipVolume::new(&camera, &light);
            if !volume.may_reach(&b) {
                let c = camera.frustum_corners();
                for (u, v) in samples.iter().copied().chain([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]) {
                    let r = c[0] + (c[1] - c[0]) * u + (c[3] - c[0]) * v;
                    prop_assert!(!segment_hits(r, &light, &b), "box {b:?} let go but shadows {r}");
                }
            }
        }
    }

    #[test]
    fn casters_far_from_the_near_plane_may_use_z_pass() {
        // Looking down -z from 10 m up, sun from above and behind.
        let camera = camera(DVec3::new(0.0, 10.0, 20.0), DVec3::ZERO, 1.0);
        let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.0, -1.0, -0.5)).unwrap());
        let volume = NearClipVolume::new(&camera, &sun);
        assert_eq!(volume.fallback(), None);
        let cube = |x: f64, y: f64, z: f64| {
            Aabb::from_center_half_extents(DVec3::new(x, y, z), DVec3::ONE).unwrap()
        };
        // On the ground in front of the camera: its shadow falls away from the camera.
        assert!(!volume.may_reach(&cube(0.0, 1.0, 0.0)));
        // Far off to the side.
        assert!(!volume.may_reach(&cube(60.0, 1.0, 20.0)));
        // Between the camera and the sun (above and behind it): shadows the near plane.
        assert!(volume.may_reach(&cube(0.0, 30.0, 30.0)));
        // Around the camera.
        assert!(volume.may_reach(&cube(0.0, 10.0, 20.0)));
        // A spot light right above the camera: a box between them reaches it.
        let spot = Light::Spot(
            SpotLight::new(DVec3::new(0.0, 30.0, 20.0), -DVec3::Y, 60.0, 100.0).unwrap(),
        );
        let volume = NearClipVolume::new(&camera, &spot);
        assert!(volume.may_reach(&cube(0.0, 20.0, 19.0)));
        assert!(!volume.may_reach(&cube(0.0, 1.0, 0.0)));
        // Beyond the light, a box casts nothing on the near plane.
        assert!(!volume.may_reach(&cube(0.0, 40.0, 20.0)));
    }

    #[test]
    fn a_light_in_the_near_plane_sends_every_caster_to_z_fail() {
        let camera = camera(DVec3::ZERO, -DVec3::Z, 1.0);
        let sun = Light::Directional(DirectionalLight::new(DVec3::X).unwrap());
        let volume = NearClipVolume::new(&camera, &sun);
        assert_eq!(volume.fallback(), Some(NearClipFallback::LightInNearPlane));
        let far_away = Aabb::from_center_half_extents(DVec3::splat(1e3), DVec3::ONE).unwrap();
        assert!(volume.may_reach(&far_away));
    }
}
