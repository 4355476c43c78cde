//! Perspective aliasing measured from a technique's actual matrices, as in the LiSPSM paper
//! (Wimmer, Scherzer and Purgathofer, "Light Space Perspective Shadow Maps", 2004, section 4
//! and Figure 6) and
//! the SPPSM paper's Figure 1.
//!
//! The paper's *ideal configuration*: a camera at the origin looking down -Z with near plane
//! z_n and far plane z_f, a directional light perpendicular to the view (tilt gamma = 90
//! degrees; other tilts are allowed), and a scene that is exactly the view frustum's box
//! (casters and receivers). For a point at distance z along the view axis, the aliasing error
//! with the projection term set to 1 is the paper's equation (1),
//!
//! ```text
//! dp/ds = (z_n / z) dz/ds
//! ```
//!
//! where s is the map coordinate, normalised to [0, 1] across the whole map, of the point's
//! image. [`view_axis_aliasing`] measures it by central differences of the map's
//! `clip_from_world`. Uniform maps give (z_f - z_n) z_n / z (99 at z_n for z_n = 1,
//! z_f = 100), perspective shadow maps (the paper's n = z_n) z (z_f - z_n) / z_f (99 at z_f),
//! LiSPSM with n_opt the same value at both ends (9.9); no single-map parameterisation beats
//! the logarithmic one's constant z_n ln(z_f / z_n) (4.61) everywhere.

use glam::DVec3;

use crate::bounds::SceneBounds;
use crate::boxes::Aabb;
use crate::camera::{Camera, Lens};
use crate::error::{SetupError, check_scalar};
use crate::light::{DirectionalLight, Light};
use crate::map::{MapSelection, ShadowMap, ShadowSetup};

/// The LiSPSM paper's ideal configuration, with the tilt gamma between the view direction
/// and the light's direction of travel free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdealConfiguration {
    /// Near plane distance z_n.
    pub z_near: f64,
    /// Far plane distance z_f.
    pub z_far: f64,
    /// Angle between the view direction and the direction the light travels, degrees, in
    /// (0, 180); 90 is the paper's ideal case.
    pub gamma_degrees: f64,
}

impl IdealConfiguration {
    /// Vertical field of view of the camera (square image), degrees.
    pub const FOV_Y_DEGREES: f64 = 60.0;

    /// Checks the numbers: 0 < z_n < z_f, gamma in (0, 180) degrees.
    pub fn new(z_near: f64, z_far: f64, gamma_degrees: f64) -> Result<Self, SetupError> {
        let z_near = check_scalar("z_n", z_near)?;
        let z_far = check_scalar("z_f", z_far)?;
        let gamma_degrees = check_scalar("gamma", gamma_degrees)?;
        if !(z_near > 0.0 && z_near < z_far) {
            return Err(SetupError::InvalidNearFar {
                near: z_near,
                far: z_far,
            });
        }
        if !(gamma_degrees > 0.0 && gamma_degrees < 180.0) {
            return Err(SetupError::InvalidParameter {
                name: "gamma (degrees, in (0, 180))",
                value: gamma_degrees,
            });
        }
        Ok(Self {
            z_near,
            z_far,
            gamma_degrees,
        })
    }

    /// The camera: at the origin, looking down -Z, up +Y, square image.
    pub fn camera(&self) -> Result<Camera, SetupError> {
        let lens = Lens {
            fov_y_degrees: Self::FOV_Y_DEGREES,
            aspect: 1.0,
            near: self.z_near,
            far: self.z_far,
        };
        Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, lens)
    }

    /// The light: travelling at gamma from the view direction, downward (for gamma = 90,
    /// straight down).
    pub fn light(&self) -> Result<Light, SetupError> {
        let gamma = self.gamma_degrees.to_radians();
        let direction = DVec3::new(0.0, -gamma.sin(), -gamma.cos());
        Ok(Light::Directional(DirectionalLight::new(direction)?))
    }

    /// The scene: the view frustum's box, as the only caster, the only receiver and the
    /// scene box.
    pub fn scene(&self) -> Result<SceneBounds, SetupError> {
        let corners = self.camera()?.frustum_corners();
        let (min, max) = corners
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let frustum_box = Aabb::new(min, max)?;
        SceneBounds::new(vec![frustum_box], vec![frustum_box], Some(frustum_box))
    }

    /// The logarithmic parameterisation's constant error, z_n ln(z_f / z_n): the least
    /// maximum dp/ds of any parameterisation along the view axis.
    pub fn logarithmic_ideal(&self) -> f64 {
        self.z_near * (self.z_far / self.z_near).ln()
    }
}

/// dp/ds along the view axis for z in [z_n, z_f], and its summary.
#[derive(Debug, Clone, PartialEq)]
pub struct AliasingCurve {
    /// The sampled distances (geometrically spaced from z_n to z_f).
    pub z: Vec<f64>,
    /// dp/ds at each.
    pub dp_ds: Vec<f64>,
    /// The largest dp/ds.
    pub max: f64,
    /// Where it is largest.
    pub z_of_max: f64,
    /// The smallest dp/ds.
    pub min: f64,
    /// Where it is smallest.
    pub z_of_min: f64,
    /// dp/ds at z_n.
    pub at_near: f64,
    /// dp/ds at z_f.
    pub at_far: f64,
}

/// The normalised map coordinate of a world point: ([0, 1]^2 over the whole map), or None
/// behind the map's projection.
fn map_coordinates(map: &ShadowMap, p: DVec3) -> Option<glam::DVec2> {
    map.project(p).map(|ndc| 0.5 * (ndc.truncate() + 1.0))
}

/// dp/ds = (z_n / z) dz/ds at distance `z` (clamped to [z_n, z_f]) along the view axis of
/// `config`, from `map`: central differences with a step of 1e-5 z (one-sided at the ends).
pub fn view_axis_dp_ds(
    map: &ShadowMap,
    config: &IdealConfiguration,
    z: f64,
) -> Result<f64, SetupError> {
    view_axis_dp_ds_of(&[*map], MapSelection::Single, config, z, None)
}

/// [`view_axis_dp_ds`] for a setup: at each point, the map its selection picks (SPPSM: the
/// side of the plane).
pub fn setup_view_axis_dp_ds(
    setup: &ShadowSetup,
    config: &IdealConfiguration,
    z: f64,
) -> Result<f64, SetupError> {
    view_axis_dp_ds_of(&setup.maps, setup.selection, config, z, None)
}

/// [`setup_view_axis_dp_ds`] in the texels of one map of `reference_resolution`: the value
/// of the map read times `reference_resolution` over its resolution, so that K cascades of
/// resolution R / sqrt(K) (the texels of one map of R) compare with one map of R.
pub fn setup_view_axis_dp_ds_in_texels(
    setup: &ShadowSetup,
    config: &IdealConfiguration,
    z: f64,
    reference_resolution: u32,
) -> Result<f64, SetupError> {
    view_axis_dp_ds_of(
        &setup.maps,
        setup.selection,
        config,
        z,
        Some(reference_resolution),
    )
}

/// [`setup_view_axis_aliasing`] in the texels of one map of `reference_resolution` (see
/// [`setup_view_axis_dp_ds_in_texels`]).
pub fn setup_view_axis_aliasing_in_texels(
    setup: &ShadowSetup,
    config: &IdealConfiguration,
    samples: usize,
    reference_resolution: u32,
) -> Result<AliasingCurve, SetupError> {
    aliasing_curve(config, samples, |z| {
        setup_view_axis_dp_ds_in_texels(setup, config, z, reference_resolution)
    })
}

/// dp/ds at `z` from the map `selection` picks there; with `reference_resolution`, in the
/// texels of one map of that resolution (times it over the map's).
fn view_axis_dp_ds_of(
    maps: &[ShadowMap],
    selection: MapSelection,
    config: &IdealConfiguration,
    z: f64,
    reference_resolution: Option<u32>,
) -> Result<f64, SetupError> {
    let z = check_scalar("z", z)?.clamp(config.z_near, config.z_far);
    let map = selection
        .map_for(maps, DVec3::new(0.0, 0.0, -z))
        .and_then(|k| maps.get(k))
        .ok_or(SetupError::Unmeasurable {
            what: "the setup has no map for the view axis",
        })?;
    let (z_n, z_f) = (config.z_near, config.z_far);
    let failure = |what: &'static str| SetupError::Unmeasurable { what };
    let s = |z: f64| {
        map_coordinates(map, DVec3::new(0.0, 0.0, -z)).ok_or(failure("view axis behind the map"))
    };
    let h = 1e-5 * z;
    let (a, b) = ((z - h).max(z_n), (z + h).min(z_f));
    let dz_ds = (b - a) / (s(b)? - s(a)?).length();
    if !(dz_ds.is_finite() && dz_ds > 0.0) {
        return Err(failure("the map does not resolve the view axis"));
    }
    let texels = reference_resolution.map_or(1.0, |r| r as f64 / map.resolution as f64);
    Ok(z_n / z * dz_ds * texels)
}

/// Measures dp/ds = (z_n / z) dz/ds along the view axis of `config` from `map` (computed
/// for that configuration), at `samples` (at least 2) distances spaced geometrically from
/// z_n to z_f. ds is the length of the image of a step along the axis in normalised map
/// coordinates (central differences, one-sided at the ends).
///
/// Errors: fewer than 2 samples; a point of the axis behind the map's projection, or a
/// step along the axis that does not move in the map (the map does not resolve the axis).
pub fn view_axis_aliasing(
    map: &ShadowMap,
    config: &IdealConfiguration,
    samples: usize,
) -> Result<AliasingCurve, SetupError> {
    aliasing_curve(config, samples, |z| view_axis_dp_ds(map, config, z))
}

/// [`view_axis_aliasing`] for a setup, each point read from the map its selection picks.
pub fn setup_view_axis_aliasing(
    setup: &ShadowSetup,
    config: &IdealConfiguration,
    samples: usize,
) -> Result<AliasingCurve, SetupError> {
    aliasing_curve(config, samples, |z| setup_view_axis_dp_ds(setup, config, z))
}

fn aliasing_curve(
    config: &IdealConfiguration,
    samples: usize,
    dp_ds: impl Fn(f64) -> Result<f64, SetupError>,
) -> Result<AliasingCurve, SetupError> {
    if samples < 2 {
        return Err(SetupError::InvalidParameter {
            name: "samples (at least 2)",
            value: samples as f64,
        });
    }
    let (z_n, z_f) = (config.z_near, config.z_far);
    let ratio = z_f / z_n;
    let mut zs = Vec::with_capacity(samples);
    let mut values = Vec::with_capacity(samples);
    for k in 0..samples {
        let z = (z_n * ratio.powf(k as f64 / (samples - 1) as f64)).clamp(z_n, z_f);
        zs.push(z);
        values.push(dp_ds(z)?);
    }
    let (mut k_max, mut k_min) = (0, 0);
    for (k, v) in values.iter().enumerate() {
        if *v > values[k_max] {
            k_max = k;
        }
        if *v < values[k_min] {
            k_min = k;
        }
    }
    Ok(AliasingCurve {
        max: values[k_max],
        z_of_max: zs[k_max],
        min: values[k_min],
        z_of_min: zs[k_min],
        at_near: values[0],
        at_far: values[samples - 1],
        z: zs,
        dp_ds: values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::MapSettings;
    use crate::setup::compute_setup;
    use crate::techniques::{Focused, Lispsm, Psm, Uniform};

    fn curve(technique: &dyn crate::ShadowTechnique, gamma: f64) -> AliasingCurve {
        let config = IdealConfiguration::new(1.0, 100.0, gamma).unwrap();
        let setup = compute_setup(
            technique,
            &config.camera().unwrap(),
            &config.light().unwrap(),
            &config.scene().unwrap(),
            MapSettings::with_resolution(1024),
        )
        .unwrap();
        assert_eq!(setup.fallback(), None);
        view_axis_aliasing(&setup.maps[0], &config, 201).unwrap()
    }

    fn within(value: f64, expected: f64, tolerance: f64) -> bool {
        (value / expected - 1.0).abs() <= tolerance
    }

    /// The papers' numbers for z_n = 1, z_f = 100 (within 3%: the map's one-texel inset and
    /// padding).
    #[test]
    fn the_papers_numbers() {
        let uniform = curve(&Uniform, 90.0);
        assert!(
            within(uniform.max, 99.0, 0.03) && uniform.z_of_max == 1.0,
            "{uniform:?}"
        );
        let focused = curve(&Focused, 90.0);
        assert!(within(focused.at_near, 99.0, 0.03), "{}", focused.at_near);
        let psm = curve(
            &Psm {
                slide_back: Some(0.0),
                limit: false,
            },
            90.0,
        );
        assert!(
            within(psm.max, 99.0, 0.03) && psm.z_of_max == 100.0,
            "{psm:?}"
        );
        assert!(within(psm.at_near, 0.99, 0.03), "{}", psm.at_near);
        let lispsm = curve(&Lispsm::default(), 90.0);
        assert!(within(lispsm.at_near, 9.9, 0.03) && within(lispsm.at_far, 9.9, 0.03));
        assert!(within(lispsm.max, 9.9, 0.03));
        // The minimum near sqrt(z_n z_f) = 10 (the paper: "the local minimum at
        // sqrt(z_n z_f)").
        assert!(
            (lispsm.z_of_min / 10.0 - 1.0).abs() < 0.3,
            "{}",
            lispsm.z_of_min
        );
        let ideal = IdealConfiguration::new(1.0, 100.0, 90.0).unwrap();
        assert!((ideal.logarithmic_ideal() - 4.60517).abs() < 1e-5);
        // No map beats the logarithmic ideal's maximum.
        for c in [&uniform, &focused, &psm, &lispsm] {
            assert!(c.max > ideal.logarithmic_ideal());
        }
    }

    #[test]
    fn tilting_the_view_keeps_lispsm_near_its_optimum() {
        // LiSPSM's n grows as 1 / sin(gamma): the error stays far below the uniform map's.
        // (The paper's warp: the warp limit judges a frame's pixels, and this scene is the
        // frustum's box, which holds the eye.)
        for gamma in [30.0, 60.0, 120.0, 150.0] {
            let lispsm = Lispsm {
                limit: false,
                ..Lispsm::default()
            };
            let (lispsm, uniform) = (curve(&lispsm, gamma), curve(&Uniform, gamma));
            assert!(
                lispsm.max < 0.5 * uniform.max,
                "gamma {gamma}: {} vs {}",
                lispsm.max,
                uniform.max
            );
        }
    }

    #[test]
    fn bad_configurations_are_typed_errors() {
        assert!(matches!(
            IdealConfiguration::new(0.0, 100.0, 90.0),
            Err(SetupError::InvalidNearFar { .. })
        ));
        assert!(matches!(
            IdealConfiguration::new(10.0, 5.0, 90.0),
            Err(SetupError::InvalidNearFar { .. })
        ));
        assert!(matches!(
            IdealConfiguration::new(1.0, 100.0, 0.0),
            Err(SetupError::InvalidParameter { .. })
        ));
        assert!(matches!(
            IdealConfiguration::new(1.0, f64::NAN, 90.0),
            Err(SetupError::NonFinite { .. })
        ));
        let config = IdealConfiguration::new(1.0, 100.0, 90.0).unwrap();
        let map = ShadowMap {
            clip_from_world: glam::DMat4::IDENTITY,
            depth_from_world: glam::DVec4::ZERO,
            resolution: 1024,
            viewport_inset: 0,
            projection: crate::MapProjection::Orthographic,
            view_depth_range: None,
        };
        // The identity map sees the view axis edge-on: no resolution along it.
        assert!(matches!(
            view_axis_aliasing(&map, &config, 10),
            Err(SetupError::Unmeasurable { .. })
        ));
        assert!(view_axis_aliasing(&map, &config, 1).is_err());
    }
}
