//! The perspective camera whose view the shadows are for.
//!
//! Conventions: right-handed world, +Y up; the camera looks down its view-space -Z; clip-space
//! depth is in [0, 1] as in wgpu (near plane at 0, far plane at 1).

use glam::{DMat3, DMat4, DVec3, DVec4};

use crate::error::{SetupError, check_direction, check_scalar, check_vec};
use crate::geometry::Plane;

/// The camera's projection: vertical field of view, aspect ratio and clip planes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lens {
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_degrees: f64,
    /// Width over height of the image, > 0.
    pub aspect: f64,
    /// Distance of the near plane, > 0.
    pub near: f64,
    /// Distance of the far plane, > near.
    pub far: f64,
}

impl Default for Lens {
    /// 60 degrees, 16:9, near 1, far 400 (the LiSPSM paper's set-up, widened to 16:9).
    fn default() -> Self {
        Self {
            fov_y_degrees: 60.0,
            aspect: 16.0 / 9.0,
            near: 1.0,
            far: 400.0,
        }
    }
}

impl Lens {
    fn validate(&self) -> Result<(), SetupError> {
        let fov = self.fov_y_degrees;
        if !fov.is_finite() {
            return Err(SetupError::NonFinite {
                what: "field of view",
            });
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(SetupError::InvalidFieldOfView { degrees: fov });
        }
        if !self.aspect.is_finite() {
            return Err(SetupError::NonFinite {
                what: "aspect ratio",
            });
        }
        if !(1e-6..=1e6).contains(&self.aspect) {
            return Err(SetupError::InvalidAspect {
                aspect: self.aspect,
            });
        }
        check_scalar("near plane", self.near)?;
        check_scalar("far plane", self.far)?;
        if !(self.near > 0.0 && self.near < self.far) {
            return Err(SetupError::InvalidNearFar {
                near: self.near,
                far: self.far,
            });
        }
        Ok(())
    }
}

/// A validated perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    view_from_world: DMat4,
    eye: DVec3,
    /// Unit view direction (world space).
    forward: DVec3,
    /// Unit up vector of the image (world space), perpendicular to `forward`.
    up: DVec3,
    /// Unit right vector of the image (world space).
    right: DVec3,
    lens: Lens,
}

impl Camera {
    /// A camera at `eye` looking at `target`, with `up` giving the image's up direction.
    ///
    /// Errors: non-finite input, `eye == target`, `up` parallel to the view direction, or a
    /// bad lens (see [`Lens`]).
    pub fn look_at(eye: DVec3, target: DVec3, up: DVec3, lens: Lens) -> Result<Self, SetupError> {
        check_vec("camera eye", eye)?;
        check_vec("camera target", target)?;
        let up = check_direction("camera up", up)?;
        lens.validate()?;
        let forward = check_direction("camera view direction", target - eye)
            .map_err(|_| SetupError::DegenerateView)?;
        let right = forward.cross(up);
        if right.length() < 1e-9 {
            return Err(SetupError::DegenerateView);
        }
        let right = right.normalize();
        let up = right.cross(forward);
        Ok(Self::from_basis(eye, forward, up, right, lens))
    }

    /// A camera from a rigid `view_from_world` matrix (the camera looks down its -Z).
    ///
    /// Errors: non-finite entries, a matrix that is not a rotation plus translation
    /// ([`SetupError::NotRigid`]), or a bad lens.
    pub fn from_view_from_world(view_from_world: DMat4, lens: Lens) -> Result<Self, SetupError> {
        if !view_from_world.is_finite() {
            return Err(SetupError::NonFinite {
                what: "view_from_world",
            });
        }
        lens.validate()?;
        let rotation = DMat3::from_mat4(view_from_world);
        let should_be_identity = rotation.transpose() * rotation;
        let orthonormal = (should_be_identity - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() < 1e-6);
        let last_row = view_from_world.row(3);
        if !orthonormal || rotation.determinant() < 0.0 || last_row != DVec4::W {
            return Err(SetupError::NotRigid);
        }
        let world_from_view = view_from_world.inverse();
        let eye = check_vec("camera eye", world_from_view.w_axis.truncate())?;
        let right = world_from_view.x_axis.truncate().normalize();
        let up = world_from_view.y_axis.truncate().normalize();
        let forward = -world_from_view.z_axis.truncate().normalize();
        Ok(Self::from_basis(eye, forward, up, right, lens))
    }

    fn from_basis(eye: DVec3, forward: DVec3, up: DVec3, right: DVec3, lens: Lens) -> Self {
        // Rows: right, up, -forward (the camera looks down its -Z), with the eye at the origin.
        let view_from_world = DMat4::from_cols(
            right.extend(-right.dot(eye)),
            up.extend(-up.dot(eye)),
            (-forward).extend(forward.dot(eye)),
            DVec4::W,
        )
        .transpose();
        Self {
            view_from_world,
            eye,
            forward,
            up,
            right,
            lens,
        }
    }

    /// World to view space (right-handed, looking down -Z).
    pub fn view_from_world(&self) -> DMat4 {
        self.view_from_world
    }

    /// View to clip space, depth in [0, 1].
    pub fn clip_from_view(&self) -> DMat4 {
        let Lens {
            fov_y_degrees,
            aspect,
            near,
            far,
        } = self.lens;
        let cot = 1.0 / (0.5 * fov_y_degrees.to_radians()).tan();
        // z_clip = far (z_view + near) / (near - far), w = -z_view: 0 at the near plane, 1 at
        // the far plane.
        let a = far / (near - far);
        DMat4::from_cols(
            DVec4::new(cot / aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, cot, 0.0, 0.0),
            DVec4::new(0.0, 0.0, a, -1.0),
            DVec4::new(0.0, 0.0, a * near, 0.0),
        )
    }

    /// World to clip space.
    pub fn clip_from_world(&self) -> DMat4 {
        self.clip_from_view() * self.view_from_world
    }

    /// The eye position.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The unit view direction.
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// The unit image-up direction.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The unit image-right direction.
    pub fn right(&self) -> DVec3 {
        self.right
    }

    /// The lens.
    pub fn lens(&self) -> Lens {
        self.lens
    }

    /// The eight corners of the view frustum in world space: the near plane's
    /// (bottom-left, bottom-right, top-right, top-left), then the far plane's in the same order.
    pub fn frustum_corners(&self) -> [DVec3; 8] {
        let tan_y = (0.5 * self.lens.fov_y_degrees.to_radians()).tan();
        let tan_x = tan_y * self.lens.aspect;
        let corner = |distance: f64, sx: f64, sy: f64| {
            self.eye + distance * (self.forward + sx * tan_x * self.right + sy * tan_y * self.up)
        };
        let (n, f) = (self.lens.near, self.lens.far);
        [
            corner(n, -1.0, -1.0),
            corner(n, 1.0, -1.0),
            corner(n, 1.0, 1.0),
            corner(n, -1.0, 1.0),
            corner(f, -1.0, -1.0),
            corner(f, 1.0, -1.0),
            corner(f, 1.0, 1.0),
            corner(f, -1.0, 1.0),
        ]
    }

    /// The six planes of the view frustum, normals pointing inward (near, far, left, right,
    /// bottom, top).
    pub fn frustum_planes(&self) -> [Plane; 6] {
        let half_y = 0.5 * self.lens.fov_y_degrees.to_radians();
        let tan_y = half_y.tan();
        let tan_x = tan_y * self.lens.aspect;
        let (f, r, u, e) = (self.forward, self.right, self.up, self.eye);
        // A side plane through the eye containing the edge direction forward + t * side has
        // inward normal proportional to (t * forward - side) (for the +side plane).
        let side = |axis: DVec3, tan: f64, sign: f64| {
            Plane::through_point(e, (tan * f - sign * axis).normalize())
        };
        [
            Plane::through_point(e + self.lens.near * f, f),
            Plane::through_point(e + self.lens.far * f, -f),
            side(r, tan_x, -1.0),
            side(r, tan_x, 1.0),
            side(u, tan_y, -1.0),
            side(u, tan_y, 1.0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens() -> Lens {
        Lens {
            fov_y_degrees: 90.0,
            aspect: 1.0,
            near: 1.0,
            far: 10.0,
        }
    }

    #[test]
    fn look_at_matches_view_matrix() {
        let cam = Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(4.0, 0.0, -1.0),
            DVec3::Y,
            lens(),
        )
        .unwrap();
        let again = Camera::from_view_from_world(cam.view_from_world(), lens()).unwrap();
        assert!((again.eye() - cam.eye()).length() < 1e-12);
        assert!((again.forward() - cam.forward()).length() < 1e-12);
        // The frustum's far corners project to the clip-space corners at depth 1.
        let clip = cam.clip_from_world();
        for (i, c) in cam.frustum_corners().iter().enumerate() {
            let p = clip.project_point3(*c);
            assert!((p.x.abs() - 1.0).abs() < 1e-9 && (p.y.abs() - 1.0).abs() < 1e-9);
            assert!((p.z - if i < 4 { 0.0 } else { 1.0 }).abs() < 1e-9);
            for plane in cam.frustum_planes() {
                assert!(plane.distance(*c) > -1e-9);
            }
        }
    }

    #[test]
    fn rejects_bad_input() {
        let l = lens();
        let e = DVec3::ZERO;
        assert_eq!(
            Camera::look_at(e, e, DVec3::Y, l),
            Err(SetupError::DegenerateView)
        );
        assert_eq!(
            Camera::look_at(e, DVec3::Y, DVec3::Y, l),
            Err(SetupError::DegenerateView)
        );
        assert!(matches!(
            Camera::look_at(e, -DVec3::Z, DVec3::ZERO, l),
            Err(SetupError::ZeroDirection { .. })
        ));
        let bad = |lens: Lens| Camera::look_at(e, -DVec3::Z, DVec3::Y, lens);
        assert!(matches!(
            bad(Lens { near: 0.0, ..l }),
            Err(SetupError::InvalidNearFar { .. })
        ));
        assert!(matches!(
            bad(Lens { near: 10.0, ..l }),
            Err(SetupError::InvalidNearFar { .. })
        ));
        assert!(matches!(
            bad(Lens {
                fov_y_degrees: 180.0,
                ..l
            }),
            Err(SetupError::InvalidFieldOfView { .. })
        ));
        assert!(matches!(
            bad(Lens {
                fov_y_degrees: 0.0,
                ..l
            }),
            Err(SetupError::InvalidFieldOfView { .. })
        ));
        assert!(matches!(
            bad(Lens { aspect: -1.0, ..l }),
            Err(SetupError::InvalidAspect { .. })
        ));
        assert!(matches!(
            bad(Lens { far: f64::NAN, ..l }),
            Err(SetupError::NonFinite { .. })
        ));
        let mut skewed = DMat4::IDENTITY;
        skewed.x_axis.y = 0.5;
        assert_eq!(
            Camera::from_view_from_world(skewed, l),
            Err(SetupError::NotRigid)
        );
    }
}
