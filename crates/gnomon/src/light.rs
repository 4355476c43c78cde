//! Lights that cast the shadows: directional, spot and point.

use glam::{DVec3, DVec4};

use crate::error::{SetupError, check_direction, check_scalar, check_vec};
use crate::geometry::Plane;

/// The fraction of a spot or point light's range at which its frustums' near planes lie (a
/// point light's: each cube face's). Nearer points are not lit, and nearer casters are
/// clipped; [`crate::Diagnostics::casters_clipped_by_light_near`] counts the caster boxes
/// that reach that near.
///
/// A millionth: a lamp often hangs within a hand's breadth of a wall or inside a shade, and a
/// caster nearer than the near plane would cast no shadow, so the light would shine through
/// it. The depth compared in the maps is linear along the light, so a near plane this close
/// costs no depth precision. The maps' clip-space z runs from 0 at the near plane toward 1/2
/// only, so that a rasteriser's f32 roundings never carry a point far beyond the near plane
/// past the far end of the clip volume, as the usual perspective z (1 - near / d) would.
pub const SPOT_NEAR_FRACTION: f64 = 1e-6;

/// A light at infinity: parallel rays travelling along one direction (the sun).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    direction: DVec3,
}

impl DirectionalLight {
    /// A directional light whose rays travel along `direction` (need not be normalised).
    pub fn new(direction: DVec3) -> Result<Self, SetupError> {
        Ok(Self {
            direction: check_direction("light direction", direction)?,
        })
    }

    /// The unit direction the light travels.
    pub fn direction(&self) -> DVec3 {
        self.direction
    }
}

/// A spot light: a point light limited to a cone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotLight {
    position: DVec3,
    direction: DVec3,
    half_angle: f64,
    range: f64,
}

impl SpotLight {
    /// A spot light at `position` shining along `direction`, with the cone's half-angle in
    /// degrees (in (0, 89]) and its range (> 0).
    pub fn new(
        position: DVec3,
        direction: DVec3,
        half_angle_degrees: f64,
        range: f64,
    ) -> Result<Self, SetupError> {
        let position = check_vec("spot light position", position)?;
        let direction = check_direction("spot light direction", direction)?;
        if !half_angle_degrees.is_finite() {
            return Err(SetupError::NonFinite {
                what: "spot light half-angle",
            });
        }
        if !(half_angle_degrees > 0.0 && half_angle_degrees <= 89.0) {
            return Err(SetupError::InvalidSpotAngle {
                degrees: half_angle_degrees,
            });
        }
        check_scalar("spot light range", range)?;
        if range <= 0.0 {
            return Err(SetupError::InvalidRange { range });
        }
        Ok(Self {
            position,
            direction,
            half_angle: half_angle_degrees.to_radians(),
            range,
        })
    }

    /// Where the light is.
    pub fn position(&self) -> DVec3 {
        self.position
    }

    /// The unit direction of the cone's axis.
    pub fn direction(&self) -> DVec3 {
        self.direction
    }

    /// The cone's half-angle in radians.
    pub fn half_angle(&self) -> f64 {
        self.half_angle
    }

    /// How far the light reaches.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// The distance of the light frustum's near plane ([`SPOT_NEAR_FRACTION`] of the range).
    pub fn near(&self) -> f64 {
        self.range * SPOT_NEAR_FRACTION
    }

    /// The light frustum's planes, normals inward: a square pyramid around the cone (the cone
    /// is inscribed), from [`SpotLight::near`] to the range. `up` is the frustum's up axis
    /// (perpendicular to the direction).
    pub(crate) fn frustum_planes(&self, up: DVec3) -> [Plane; 6] {
        let d = self.direction;
        let right = d.cross(up).normalize();
        let up = right.cross(d);
        let t = self.half_angle.tan();
        let side = |axis: DVec3, sign: f64| {
            Plane::through_point(self.position, (t * d - sign * axis).normalize())
        };
        [
            Plane::through_point(self.position + self.near() * d, d),
            Plane::through_point(self.position + self.range * d, -d),
            side(right, -1.0),
            side(right, 1.0),
            side(up, -1.0),
            side(up, 1.0),
        ]
    }
}

/// A point light: rays from a point in every direction, up to a range (a lamp, a torch).
///
/// Shadow-map techniques see it as six spot lights, one per cube face
/// ([`PointLight::face_light`]); the exact volumes extrude from its position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    position: DVec3,
    range: f64,
}

impl PointLight {
    /// A point light at `position` reaching `range` (> 0) world units.
    pub fn new(position: DVec3, range: f64) -> Result<Self, SetupError> {
        let position = check_vec("point light position", position)?;
        check_scalar("point light range", range)?;
        if range <= 0.0 {
            return Err(SetupError::InvalidRange { range });
        }
        Ok(Self { position, range })
    }

    /// Where the light is.
    pub fn position(&self) -> DVec3 {
        self.position
    }

    /// How far the light reaches.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// The distance of each face frustum's near plane ([`SPOT_NEAR_FRACTION`] of the range).
    pub fn near(&self) -> f64 {
        self.range * SPOT_NEAR_FRACTION
    }

    /// The cube face that the direction `d` (from the light) falls in: its major axis, the
    /// first of x, y, z on a tie.
    pub fn face_of(d: DVec3) -> CubeFace {
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            if d.x >= 0.0 {
                CubeFace::PosX
            } else {
                CubeFace::NegX
            }
        } else if a.y >= a.z {
            if d.y >= 0.0 {
                CubeFace::PosY
            } else {
                CubeFace::NegY
            }
        } else if d.z >= 0.0 {
            CubeFace::PosZ
        } else {
            CubeFace::NegZ
        }
    }

    /// The spot light that one cube face's map is fitted for: the light's position, the
    /// face's axis, and a square frustum a little wider than the face's 90 degrees, by
    /// [`CUBE_FACE_BORDER_TEXELS`] texels of a `resolution`-texel map on each side. A lookup
    /// filtered near a face's edge then reads texels that hold the casters. The frustum's
    /// sides lie along the cube's edges: the spot's fixed frame has a world axis as its up.
    pub fn face_light(&self, face: CubeFace, resolution: u32) -> SpotLight {
        let t = cube_face_tangent(resolution);
        SpotLight {
            position: self.position,
            direction: face.axis(),
            half_angle: t.atan(),
            range: self.range,
        }
    }
}

/// Texels of border that each cube face's map keeps beyond the face's 90 degrees, on each
/// side: more than the 5x5 filter's reach of two texels.
pub const CUBE_FACE_BORDER_TEXELS: u32 = 3;

/// The tangent of a cube face frustum's half-angle for `resolution`-texel maps: 1 (45
/// degrees) widened so that [`CUBE_FACE_BORDER_TEXELS`] of its texels lie beyond it.
pub fn cube_face_tangent(resolution: u32) -> f64 {
    let border = f64::from(CUBE_FACE_BORDER_TEXELS);
    let r = f64::from(resolution.max(4 * CUBE_FACE_BORDER_TEXELS));
    1.0 / (1.0 - 2.0 * border / r)
}

/// One face of a point light's cube, named by its axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CubeFace {
    /// +x.
    PosX,
    /// -x.
    NegX,
    /// +y.
    PosY,
    /// -y.
    NegY,
    /// +z.
    PosZ,
    /// -z.
    NegZ,
}

impl CubeFace {
    /// The six faces, in the order of their maps.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    /// The face's axis (a unit world axis).
    pub fn axis(&self) -> DVec3 {
        match self {
            CubeFace::PosX => DVec3::X,
            CubeFace::NegX => DVec3::NEG_X,
            CubeFace::PosY => DVec3::Y,
            CubeFace::NegY => DVec3::NEG_Y,
            CubeFace::PosZ => DVec3::Z,
            CubeFace::NegZ => DVec3::NEG_Z,
        }
    }

    /// The face's index in [`CubeFace::ALL`].
    pub fn index(&self) -> usize {
        *self as usize
    }

    /// `+x`, `-x`, ... (JSON and logs).
    pub fn name(&self) -> &'static str {
        match self {
            CubeFace::PosX => "+x",
            CubeFace::NegX => "-x",
            CubeFace::PosY => "+y",
            CubeFace::NegY => "-y",
            CubeFace::PosZ => "+z",
            CubeFace::NegZ => "-z",
        }
    }
}

/// The light whose shadows are computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A light at infinity.
    Directional(DirectionalLight),
    /// A spot light.
    Spot(SpotLight),
    /// A point light.
    Point(PointLight),
}

impl Light {
    /// The light's main direction: the direction of travel for a directional light, the
    /// cone's axis for a spot light, straight down (-y) for a point light, which has none.
    pub fn direction(&self) -> DVec3 {
        match self {
            Light::Directional(l) => l.direction(),
            Light::Spot(s) => s.direction(),
            Light::Point(_) => DVec3::NEG_Y,
        }
    }

    /// Where the light is (`None` for a directional light).
    pub fn position(&self) -> Option<DVec3> {
        match self {
            Light::Directional(_) => None,
            Light::Spot(s) => Some(s.position()),
            Light::Point(p) => Some(p.position()),
        }
    }

    /// Where the light's rays come from, in homogeneous coordinates: the point at infinity
    /// against the direction of travel (directional) or the light's position (spot).
    pub(crate) fn homogeneous_source(&self) -> DVec4 {
        match self {
            Light::Directional(l) => (-l.direction()).extend(0.0),
            Light::Spot(s) => s.position().extend(1.0),
            Light::Point(p) => p.position().extend(1.0),
        }
    }

    /// The row of the linear depth along the light (world units): `row . (p, 1)` is the
    /// distance along the direction of travel. It is measured from the plane through the
    /// origin for a directional light and from the light's plane for a spot light; for a
    /// point light it runs along -y from its height.
    pub(crate) fn linear_depth_row(&self) -> DVec4 {
        match self {
            Light::Directional(l) => l.direction().extend(0.0),
            Light::Spot(s) => s.direction().extend(-s.direction().dot(s.position())),
            // No single axis: along its nominal direction (techniques see a point light's
            // faces as spot lights, never the point light itself).
            Light::Point(p) => DVec3::NEG_Y.extend(p.position().y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_lights() {
        assert!(matches!(
            DirectionalLight::new(DVec3::ZERO),
            Err(SetupError::ZeroDirection { .. })
        ));
        assert!(matches!(
            DirectionalLight::new(DVec3::new(f64::NAN, 1.0, 0.0)),
            Err(SetupError::NonFinite { .. })
        ));
        let p = DVec3::ZERO;
        let d = -DVec3::Y;
        assert!(SpotLight::new(p, d, 30.0, 10.0).is_ok());
        assert!(matches!(
            SpotLight::new(p, d, 0.0, 10.0),
            Err(SetupError::InvalidSpotAngle { .. })
        ));
        assert!(matches!(
            SpotLight::new(p, d, 90.0, 10.0),
            Err(SetupError::InvalidSpotAngle { .. })
        ));
        assert!(matches!(
            SpotLight::new(p, d, 30.0, 0.0),
            Err(SetupError::InvalidRange { .. })
        ));
        assert!(matches!(
            SpotLight::new(p, DVec3::ZERO, 30.0, 1.0),
            Err(SetupError::ZeroDirection { .. })
        ));
    }

    #[test]
    fn spot_frustum_contains_its_cone() {
        let s = SpotLight::new(
            DVec3::new(1.0, 5.0, 2.0),
            DVec3::new(0.2, -1.0, 0.1),
            40.0,
            20.0,
        )
        .unwrap();
        let up = s.direction().any_orthonormal_vector();
        let planes = s.frustum_planes(up);
        let a = s.direction().any_orthonormal_pair();
        for k in 0..32 {
            let phi = k as f64 / 32.0 * std::f64::consts::TAU;
            let ray =
                s.direction() + 0.999 * s.half_angle().tan() * (phi.cos() * a.0 + phi.sin() * a.1);
            let p = s.position() + 10.0 * ray;
            assert!(planes.iter().all(|pl| pl.distance(p) >= 0.0));
        }
        assert!(planes[0].distance(s.position()) < 0.0);
    }
}
