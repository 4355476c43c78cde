//! Area lights as clusters of hard lights: the shadows lecture's "Stenciled Shadow Volumes
//! for Simulating Soft Shadows" (a cluster of point lights, each with exact shadows, their
//! light averaged). A spot or point light becomes a disc of point lights, a directional light
//! a cone of directions; the samples lie on a Vogel spiral (sample i at radius sqrt((i +
//! 1/2) / N) of the disc, turned by the golden angle), which covers the disc evenly for any N.

use glam::DVec3;

use crate::error::SetupError;
use crate::light::{DirectionalLight, Light, PointLight, SpotLight};

/// The most samples a cluster takes.
pub const MAX_AREA_SAMPLES: usize = 4096;

/// The largest angular radius of a directional area light, in degrees.
pub const MAX_ANGULAR_RADIUS_DEGREES: f64 = 45.0;

/// The golden angle, in radians.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// Offset `i` of `n` on the unit disc (Vogel's spiral), as (x, y).
pub fn vogel_disc(i: usize, n: usize) -> (f64, f64) {
    let r = ((i as f64 + 0.5) / n as f64).sqrt();
    let phi = i as f64 * GOLDEN_ANGLE;
    (r * phi.cos(), r * phi.sin())
}

/// Checks the radius of `light`'s area: finite, 0 or more, and for a directional light (an
/// angular radius in degrees) at most [`MAX_ANGULAR_RADIUS_DEGREES`].
pub fn check_radius(light: &Light, radius: f64) -> Result<(), SetupError> {
    let limit = match light {
        Light::Directional(_) => MAX_ANGULAR_RADIUS_DEGREES,
        _ => f64::MAX,
    };
    if !(radius.is_finite() && (0.0..=limit).contains(&radius)) {
        return Err(SetupError::InvalidParameter {
            name: "area light radius (0 or more; at most 45 degrees for a directional light)",
            value: radius,
        });
    }
    Ok(())
}

/// `light` as an area light sampled by `samples` hard lights: for a spot light, a disc of
/// `radius` world units centred on it and perpendicular to its direction; for a point light,
/// the same disc perpendicular to `facing` (where the scene lies from it); for a directional
/// light, directions within `radius` degrees of its own (the sun: 0.27). Each sample keeps the
/// light's other properties (cone, range). Radius 0 gives the light `samples` times.
pub fn area_light_samples(
    light: &Light,
    radius: f64,
    samples: usize,
    facing: DVec3,
) -> Result<Vec<Light>, SetupError> {
    if !(1..=MAX_AREA_SAMPLES).contains(&samples) {
        return Err(SetupError::InvalidParameter {
            name: "area light samples (1 to 4096)",
            value: samples as f64,
        });
    }
    check_radius(light, radius)?;
    let basis = |axis: DVec3| {
        let u = axis.any_orthonormal_vector();
        (u, axis.cross(u))
    };
    (0..samples)
        .map(|i| {
            let (x, y) = vogel_disc(i, samples);
            Ok(match light {
                Light::Directional(d) => {
                    let (u, v) = basis(d.direction());
                    let t = radius.to_radians().tan();
                    Light::Directional(DirectionalLight::new(d.direction() + (u * x + v * y) * t)?)
                }
                Light::Spot(s) => {
                    let (u, v) = basis(s.direction());
                    Light::Spot(SpotLight::new(
                        s.position() + (u * x + v * y) * radius,
                        s.direction(),
                        s.half_angle().to_degrees(),
                        s.range(),
                    )?)
                }
                Light::Point(p) => {
                    let axis = facing.try_normalize().unwrap_or(-DVec3::Y);
                    let (u, v) = basis(axis);
                    Light::Point(PointLight::new(
                        p.position() + (u * x + v * y) * radius,
                        p.range(),
                    )?)
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_disc_is_covered_evenly() {
        let n = 256;
        let points: Vec<(f64, f64)> = (0..n).map(|i| vogel_disc(i, n)).collect();
        assert!(points.iter().all(|(x, y)| x.hypot(*y) <= 1.0));
        // Half the samples within radius 1/sqrt(2) (half the area), the centroid near 0.
        let inner = points
            .iter()
            .filter(|(x, y)| x.hypot(*y) < 0.5f64.sqrt())
            .count();
        assert_eq!(inner, n / 2);
        let (sx, sy) = points
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        assert!((sx / n as f64).abs() < 0.02 && (sy / n as f64).abs() < 0.02);
    }

    #[test]
    fn samples_lie_on_the_disc_or_in_the_cone() {
        let spot = Light::Spot(
            SpotLight::new(
                DVec3::new(1.0, 10.0, 2.0),
                DVec3::new(0.0, -1.0, 0.2),
                40.0,
                60.0,
            )
            .unwrap(),
        );
        let cluster = area_light_samples(&spot, 2.0, 64, DVec3::ZERO).unwrap();
        assert_eq!(cluster.len(), 64);
        let Light::Spot(s) = spot else { unreachable!() };
        let mut farthest = 0.0f64;
        for l in &cluster {
            let Light::Spot(c) = l else { panic!() };
            let offset = c.position() - s.position();
            assert!(
                offset.dot(s.direction()).abs() < 1e-12,
                "in the disc's plane"
            );
            farthest = farthest.max(offset.length());
            assert!(c.direction().distance(s.direction()) < 1e-12);
            assert!((c.half_angle() - s.half_angle()).abs() < 1e-12);
            assert_eq!(c.range(), s.range());
        }
        assert!(farthest <= 2.0 && farthest > 1.9);
        let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.1)).unwrap());
        let Light::Directional(d) = sun else {
            unreachable!()
        };
        for l in area_light_samples(&sun, 0.27, 32, DVec3::ZERO).unwrap() {
            let Light::Directional(c) = l else { panic!() };
            let angle = c.direction().angle_between(d.direction()).to_degrees();
            assert!(angle <= 0.27 + 1e-9, "{angle}");
        }
        let lamp = Light::Point(PointLight::new(DVec3::new(0.0, 5.0, 0.0), 40.0).unwrap());
        for l in area_light_samples(&lamp, 0.5, 16, DVec3::new(0.0, -1.0, 0.0)).unwrap() {
            let Light::Point(c) = l else { panic!() };
            assert!((c.position().y - 5.0).abs() < 1e-12, "the disc faces down");
        }
    }

    #[test]
    fn bad_clusters_are_refused() {
        let sun = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
        for (radius, samples) in [(1.0, 0), (1.0, 5000), (-1.0, 4), (f64::NAN, 4), (60.0, 4)] {
            assert!(
                area_light_samples(&sun, radius, samples, DVec3::ZERO).is_err(),
                "{radius} {samples}"
            );
        }
        assert_eq!(
            area_light_samples(&sun, 0.0, 3, DVec3::ZERO).unwrap(),
            vec![sun; 3]
        );
    }
}
