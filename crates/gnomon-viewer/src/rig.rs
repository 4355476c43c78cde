//! The viewer's camera and sun, moved by input: pure math, no window.
//!
//! Both keep the values they started from until input moves them (a camera's eye and target,
//! a sun's direction), so that an unmoved viewer draws exactly the named view it opened, and
//! the `gnomon render` command it prints reproduces the frame bit for bit.

use glam::{DQuat, DVec3};

/// Keys held down that move the camera, as a direction in the camera's own frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FlyKeys {
    /// W.
    pub forward: bool,
    /// S.
    pub back: bool,
    /// A.
    pub left: bool,
    /// D.
    pub right: bool,
    /// E.
    pub up: bool,
    /// Q.
    pub down: bool,
    /// Shift: four times the speed.
    pub fast: bool,
}

impl FlyKeys {
    /// Whether any key that moves is held.
    pub fn moving(&self) -> bool {
        self.forward || self.back || self.left || self.right || self.up || self.down
    }
}

/// How far the pitch may go from the horizon, in degrees: the view never turns over the pole,
/// where the camera's right axis (up x forward) vanishes.
pub const MAX_PITCH_DEGREES: f64 = 89.0;

/// A camera given by its eye, the point it looks at and the world's up direction: flown with
/// the keys, turned with the mouse, orbited around its target and zoomed toward it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRig {
    /// Camera position.
    pub eye: DVec3,
    /// The point looked at: the centre of orbits and zooms.
    pub target: DVec3,
    /// The world's up (the named view's up, as given: it is printed as given).
    pub up: DVec3,
    /// Fly speed in world units per second (before shift).
    pub speed: f64,
}

impl CameraRig {
    /// A rig at `eye` looking at `target` with `up` as the world's up; fly speed a tenth of
    /// the eye's distance to the target per second, at least 1.
    pub fn new(eye: DVec3, target: DVec3, up: DVec3) -> Self {
        Self {
            eye,
            target,
            up,
            speed: (eye.distance(target) * 0.5).max(1.0),
        }
    }

    /// The world's up, unit length.
    fn up_unit(&self) -> DVec3 {
        self.up.try_normalize().unwrap_or(DVec3::Y)
    }

    /// The unit direction the camera looks along.
    pub fn forward(&self) -> DVec3 {
        (self.target - self.eye)
            .try_normalize()
            .unwrap_or(-DVec3::Z)
    }

    /// The camera's unit right axis (forward x up; a fallback where they are parallel).
    pub fn right(&self) -> DVec3 {
        self.forward()
            .cross(self.up_unit())
            .try_normalize()
            .unwrap_or_else(|| self.up_unit().any_orthonormal_vector())
    }

    /// Moves eye and target together by the held keys for `dt` seconds.
    pub fn fly(&mut self, keys: FlyKeys, dt: f64) {
        if !keys.moving() {
            return;
        }
        let axis = |plus: bool, minus: bool| f64::from(u8::from(plus)) - f64::from(u8::from(minus));
        let step = self.speed * if keys.fast { 4.0 } else { 1.0 } * dt;
        let offset = self.forward() * axis(keys.forward, keys.back)
            + self.right() * axis(keys.right, keys.left)
            + self.up_unit() * axis(keys.up, keys.down);
        let offset = offset * step;
        self.eye += offset;
        self.target += offset;
    }

    /// Turns the view in place (mouse look): `yaw` degrees about the world's up (positive to
    /// the right), `pitch` degrees about the right axis (positive up), the pitch kept within
    /// [`MAX_PITCH_DEGREES`] of the horizon; the eye stays.
    pub fn look(&mut self, yaw: f64, pitch: f64) {
        let distance = self.eye.distance(self.target);
        let forward = self.turned(yaw, pitch);
        self.target = self.eye + forward * distance;
    }

    /// Turns the eye around the target (orbit): the same angles as [`CameraRig::look`], the
    /// eye moving on the sphere around the target, which stays.
    pub fn orbit(&mut self, yaw: f64, pitch: f64) {
        let distance = self.eye.distance(self.target);
        let forward = self.turned(yaw, pitch);
        self.eye = self.target - forward * distance;
    }

    /// Moves the eye toward the target (positive `steps`) or away, 10% of the distance per
    /// step; the eye stays at least a hundredth of a unit away.
    pub fn zoom(&mut self, steps: f64) {
        let distance = self.eye.distance(self.target);
        let new = (distance * 0.9f64.powf(steps)).max(0.01);
        self.eye = self.target - self.forward() * new;
    }

    /// The forward direction turned by `yaw` and `pitch` degrees, the pitch clamped.
    fn turned(&self, yaw: f64, pitch: f64) -> DVec3 {
        let forward = self.forward();
        let elevation = forward
            .dot(self.up_unit())
            .clamp(-1.0, 1.0)
            .asin()
            .to_degrees();
        let limit = MAX_PITCH_DEGREES;
        let new_elevation = (elevation + pitch).clamp(-limit, limit);
        let pitch = new_elevation - elevation;
        let yawed = DQuat::from_axis_angle(self.up_unit(), -yaw.to_radians()) * forward;
        let right = yawed
            .cross(self.up_unit())
            .try_normalize()
            .unwrap_or_else(|| self.right());
        (DQuat::from_axis_angle(right, pitch.to_radians()) * yawed).normalize()
    }
}

/// A directional light's travel direction, turned by input: azimuth about the world's up and
/// elevation of the sun (the direction toward the light) above the horizon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunRig {
    /// The direction the light travels (from the sun toward the scene), as given until the
    /// sun is turned (then unit length).
    pub direction: DVec3,
    /// The world's up, unit length.
    pub up: DVec3,
}

impl SunRig {
    /// The sun whose light travels along `direction`.
    pub fn new(direction: DVec3, up: DVec3) -> Self {
        Self {
            direction,
            up: up.try_normalize().unwrap_or(DVec3::Y),
        }
    }

    /// The sun's elevation above the horizon in degrees (negative: below it).
    pub fn elevation_degrees(&self) -> f64 {
        (-self.unit())
            .dot(self.up)
            .clamp(-1.0, 1.0)
            .asin()
            .to_degrees()
    }

    /// The sun's azimuth in degrees about the world's up, from an axis perpendicular to up.
    pub fn azimuth_degrees(&self) -> f64 {
        let (x, z) = self.horizontal_axes();
        let to_sun = -self.unit();
        to_sun.dot(z).atan2(to_sun.dot(x)).to_degrees()
    }

    /// The light's unit direction.
    fn unit(&self) -> DVec3 {
        self.direction.try_normalize().unwrap_or(-DVec3::Y)
    }

    /// The sun at `azimuth` and `elevation` degrees (elevation clamped to within 89.9 degrees
    /// of the horizon's poles).
    pub fn set(&mut self, azimuth: f64, elevation: f64) {
        let (x, z) = self.horizontal_axes();
        let (az, el) = (
            azimuth.to_radians(),
            elevation.clamp(-89.9, 89.9).to_radians(),
        );
        let to_sun = (x * az.cos() + z * az.sin()) * el.cos() + self.up * el.sin();
        self.direction = -to_sun.normalize();
    }

    /// Turns the sun by `azimuth` and `elevation` degrees.
    pub fn turn(&mut self, azimuth: f64, elevation: f64) {
        if azimuth == 0.0 && elevation == 0.0 {
            return;
        }
        let (az, el) = (self.azimuth_degrees(), self.elevation_degrees());
        self.set(az + azimuth, el + elevation);
    }

    /// Two unit axes perpendicular to up: the azimuth is measured from the first toward the
    /// second.
    fn horizontal_axes(&self) -> (DVec3, DVec3) {
        let reference = if self.up.x.abs() < 0.9 {
            DVec3::X
        } else {
            DVec3::Z
        };
        let x = (reference - self.up * reference.dot(self.up)).normalize();
        (x, self.up.cross(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        a.distance(b) < 1e-9
    }

    #[test]
    fn an_unmoved_rig_keeps_its_eye_and_target_exactly() {
        let (eye, target) = (DVec3::new(0.1, 7.3, -3.7), DVec3::new(2.9, 0.3, 11.1));
        let mut rig = CameraRig::new(eye, target, DVec3::Y);
        rig.fly(FlyKeys::default(), 1.0);
        assert_eq!((rig.eye, rig.target), (eye, target));
        let sun = SunRig::new(DVec3::new(-0.3, -0.8, 0.2).normalize(), DVec3::Y);
        let mut turned = sun;
        turned.turn(0.0, 0.0);
        assert_eq!(turned, sun);
    }

    #[test]
    fn flying_forward_moves_along_the_view_and_keeps_the_direction() {
        let mut rig = CameraRig::new(DVec3::ZERO, DVec3::new(0.0, 0.0, -10.0), DVec3::Y);
        rig.speed = 2.0;
        let keys = FlyKeys {
            forward: true,
            ..FlyKeys::default()
        };
        rig.fly(keys, 0.5);
        assert!(close(rig.eye, DVec3::new(0.0, 0.0, -1.0)));
        assert!(close(rig.forward(), -DVec3::Z));
        let keys = FlyKeys {
            right: true,
            fast: true,
            ..FlyKeys::default()
        };
        rig.fly(keys, 0.25);
        assert!(close(rig.eye, DVec3::new(2.0, 0.0, -1.0)), "{}", rig.eye);
    }

    #[test]
    fn look_turns_about_up_and_clamps_the_pitch() {
        let mut rig = CameraRig::new(DVec3::ZERO, DVec3::new(0.0, 0.0, -10.0), DVec3::Y);
        rig.look(90.0, 0.0);
        // Turning right from -z faces +x.
        assert!(close(rig.forward(), DVec3::X), "{}", rig.forward());
        assert!(close(rig.eye, DVec3::ZERO));
        assert!((rig.target.length() - 10.0).abs() < 1e-9);
        rig.look(0.0, 200.0);
        let elevation = rig.forward().y.asin().to_degrees();
        assert!((elevation - MAX_PITCH_DEGREES).abs() < 1e-9, "{elevation}");
    }

    #[test]
    fn orbit_keeps_the_target_and_the_distance() {
        let target = DVec3::new(1.0, 2.0, 3.0);
        let mut rig = CameraRig::new(DVec3::new(1.0, 2.0, 13.0), target, DVec3::Y);
        for (yaw, pitch) in [(30.0, 10.0), (-75.0, 40.0), (400.0, -95.0)] {
            rig.orbit(yaw, pitch);
            assert_eq!(rig.target, target);
            assert!((rig.eye.distance(target) - 10.0).abs() < 1e-9);
            assert!(
                rig.forward().dot(DVec3::Y).abs() <= MAX_PITCH_DEGREES.to_radians().sin() + 1e-12
            );
        }
        rig.zoom(1.0);
        assert!((rig.eye.distance(target) - 9.0).abs() < 1e-9);
        rig.zoom(-2.0);
        assert!((rig.eye.distance(target) - 9.0 / 0.81).abs() < 1e-9);
    }

    #[test]
    fn the_sun_turns_by_azimuth_and_elevation() {
        let mut sun = SunRig::new(DVec3::new(-1.0, -1.0, 0.0), DVec3::Y);
        assert!((sun.elevation_degrees() - 45.0).abs() < 1e-9);
        let az = sun.azimuth_degrees();
        sun.turn(90.0, -15.0);
        assert!((sun.elevation_degrees() - 30.0).abs() < 1e-9);
        let turned = (sun.azimuth_degrees() - az).rem_euclid(360.0);
        assert!((turned - 90.0).abs() < 1e-9, "{turned}");
        sun.turn(0.0, 200.0);
        assert!(sun.elevation_degrees() <= 89.9 + 1e-9);
        assert!((sun.direction.length() - 1.0).abs() < 1e-12);
    }
}
