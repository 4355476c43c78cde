//! Area lights as clusters of hard lights: the shadows lecture's "Stenciled Shadow Volumes
//! for Simulating Soft Shadows" (a cluster of point lights, each with exact shadows, their
//! light averaged). A spot or point light becomes a disc of point lights, a directional light
//! a cone of directions; the samples lie on a Vogel spiral (sample i at radius sqrt((i +
//! 1/2) / N) of the disc, turned by the golden angle), which covers the disc evenly for any N.
//!
//! Clusters are progressive: one of more than [`BASE_AREA_SAMPLES`] samples is the base
//! cluster of [`BASE_AREA_SAMPLES`] plus a second spiral of the rest, so that a larger cluster
//! refines the default one instead of replacing it. Why: the error of N points on a disc cut by
//! a shadow's straight edge falls like N^(-3/4) at best (Beck's bound for half-planes), so two
//! unrelated spirals of 64 and 256 points differ by more than the nested ones do, for almost
//! the same error of the larger one. An engine can also accumulate the base cluster first and
//! the rest later.

use glam::DVec3;

use crate::error::SetupError;
use crate::light::{DirectionalLight, Light, PointLight, SpotLight};

/// The most samples a cluster takes.
pub const MAX_AREA_SAMPLES: usize = 4096;

/// The largest angular radius of a directional area light, in degrees.
pub const MAX_ANGULAR_RADIUS_DEGREES: f64 = 45.0;

/// The size of the base cluster that every larger cluster contains (the CLI's default
/// `--area-samples`).
pub const BASE_AREA_SAMPLES: usize = 64;

/// The golden angle, in radians.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// How far the refining spiral is turned against the base one, in radians (30 degrees), so
/// that their first points do not coincide.
const REFINEMENT_TURN: f64 = std::f64::consts::FRAC_PI_6;

/// Offset `i` of `n` on the unit disc (Vogel's spiral), as (x, y).
pub fn vogel_disc(i: usize, n: usize) -> (f64, f64) {
    turned_vogel_disc(i, n, 0.0)
}

fn turned_vogel_disc(i: usize, n: usize, turn: f64) -> (f64, f64) {
    let r = ((i as f64 + 0.5) / n as f64).sqrt();
    let phi = i as f64 * GOLDEN_ANGLE + turn;
    (r * phi.cos(), r * phi.sin())
}

/// Offset `i` of a cluster of `n` on the unit disc, as (x, y): Vogel's spiral of `n` up to
/// [`BASE_AREA_SAMPLES`]; above, the base spiral's points first, then a spiral of the other
/// `n - BASE_AREA_SAMPLES` turned by 30 degrees (the module's note says why).
pub fn cluster_disc(i: usize, n: usize) -> (f64, f64) {
    if n <= BASE_AREA_SAMPLES {
        vogel_disc(i, n)
    } else if i < BASE_AREA_SAMPLES {
        vogel_disc(i, BASE_AREA_SAMPLES)
    } else {
        turned_vogel_disc(
            i - BASE_AREA_SAMPLES,
            n - BASE_AREA_SAMPLES,
            REFINEMENT_TURN,
        )
    }
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

/// `light` as an area light sampled by `samples` hard lights. For a spot light it is a disc of
/// `radius` world units centred on it and perpendicular to its direction. For a point light
/// it is the same disc perpendicular to `facing` (where the scene lies from it). For a
/// directional light it is the directions within `radius` degrees of its own (the sun:
/// 0.27). Each sample keeps the light's other properties (cone, range). Radius 0 gives the
/// light `samples` times.
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
            let (x, y) = cluster_disc(i, samples);
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
        let points: Vec<(f64, f64)> = (0..n).map(|i| cluster_disc(i, n)).collect();
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

    /// The share of `points` on the lit side of the line x cos(a) + y sin(a) = d.
    fn lit_share(points: &[(f64, f64)], a: f64, d: f64) -> f64 {
        let lit = points
            .iter()
            .filter(|(x, y)| x * a.cos() + y * a.sin() < d)
            .count();
        lit as f64 / points.len() as f64
    }

    #[test]
    fn larger_clusters_refine_the_base_one() {
        let cluster = |n: usize| (0..n).map(|i| cluster_disc(i, n)).collect::<Vec<_>>();
        let (base, fine) = (cluster(BASE_AREA_SAMPLES), cluster(256));
        assert_eq!(&fine[..BASE_AREA_SAMPLES], &base[..]);
        assert_eq!(
            cluster(48),
            (0..48).map(|i| vogel_disc(i, 48)).collect::<Vec<_>>()
        );
        // A shadow's straight edge at every angle, crossing the disc at offsets d spread evenly
        // over (-1, 1): over the penumbra of 256 samples, 64 differ from them by less than 1%
        // of the shadow factor at every angle (the soft-shadow issue's bound), and both stay
        // near the disc's true share (the circular segment's area over pi).
        let (mut worst, mut worst_error) = (0.0f64, [0.0f64; 2]);
        for k in 0..36 {
            let a = (k as f64 + 0.5) * std::f64::consts::PI / 18.0;
            let (mut sum, mut count, mut errors) = (0.0, 0, [0.0; 2]);
            for j in 0..400 {
                let d = -1.0 + (j as f64 + 0.5) / 200.0;
                let truth = (std::f64::consts::PI - d.acos() + d * (1.0 - d * d).sqrt())
                    / std::f64::consts::PI;
                let (c, f) = (lit_share(&base, a, d), lit_share(&fine, a, d));
                errors[0] += (c - truth).abs() / 400.0;
                errors[1] += (f - truth).abs() / 400.0;
                if f > 0.0 && f < 1.0 {
                    sum += (c - f).abs();
                    count += 1;
                }
            }
            worst = worst.max(sum / count as f64);
            worst_error = [worst_error[0].max(errors[0]), worst_error[1].max(errors[1])];
        }
        assert!(worst < 0.01, "64 against 256: {worst}");
        assert!(
            worst_error[0] < 0.015 && worst_error[1] < 0.006,
            "{worst_error:?}"
        );
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
