//! The registry: every technique by name, and the checked entry points that run one.

use std::fmt;
use std::str::FromStr;

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::error::SetupError;
use crate::light::Light;
use crate::map::{MapSettings, ShadowMap, ShadowSetup};
use crate::samples::ViewSamples;
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::{
    Cascades, Cube, DualParaboloid, Focused, Lispsm, Psm, Sppsm, Tsm, Uniform, Xpsm,
};

/// Every technique gnomon has, by name, for command lines and configuration files.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Technique {
    /// Uniform shadow map (SSM).
    Uniform(Uniform),
    /// Focused shadow map with unit cube clipping (FSM).
    Focused(Focused),
    /// Light space perspective shadow map (LiSPSM).
    Lispsm(Lispsm),
    /// Trapezoidal shadow map (TSM).
    Tsm(Tsm),
    /// Extended perspective shadow map (XPSM).
    Xpsm(Xpsm),
    /// Perspective shadow map (PSM).
    Psm(Psm),
    /// Separating-plane perspective shadow maps (SPPSM): the focused map and a perspective
    /// one.
    Sppsm(Sppsm),
    /// Cascaded shadow maps: a map per slice of the view, each fitted by a single-map
    /// technique, or stable cascades.
    Cascades(Cascades),
    /// A point light's cube maps, each face focused.
    Cube(Cube),
    /// A point light's two paraboloid maps.
    Paraboloid(DualParaboloid),
}

impl Technique {
    /// The names [`Technique::from_str`] accepts.
    pub const NAMES: &'static [&'static str] = &[
        "uniform",
        "focused",
        "psm",
        "lispsm",
        "tsm",
        "xpsm",
        "sppsm",
        "cascades",
        "cube",
        "paraboloid",
    ];

    /// Each technique with default parameters.
    pub fn all() -> Vec<Technique> {
        Self::NAMES
            .iter()
            .map(|n| n.parse().expect("every listed name parses"))
            .collect()
    }

    /// Whether the technique takes `light`: `cube` and `paraboloid` take point lights only; SPPSM and the
    /// cascades (several maps per light) take every light but point lights; the others take
    /// every light (a point light per cube face).
    pub fn takes(&self, light: &Light) -> bool {
        let point = matches!(light, Light::Point(_));
        match self {
            Technique::Cube(_) | Technique::Paraboloid(_) => point,
            Technique::Sppsm(_) | Technique::Cascades(_) => !point,
            _ => true,
        }
    }

    /// The technique for the next frame of a frame loop whose last setup with it was
    /// `setup`: adaptive cascades learn the number of cascades kept
    /// ([`Cascades::adaptive_previous`](crate::Cascades::adaptive_previous)); every other
    /// technique is unchanged (they keep no state between frames).
    pub fn for_next_frame(&self, setup: &ShadowSetup) -> Technique {
        match self {
            Technique::Cascades(c) if c.adaptive => Technique::Cascades(crate::Cascades {
                adaptive_previous: Some(setup.maps.len().max(1)),
                ..*c
            }),
            other => *other,
        }
    }

    fn as_dyn(&self) -> &dyn ShadowTechnique {
        match self {
            Technique::Uniform(t) => t,
            Technique::Focused(t) => t,
            Technique::Lispsm(t) => t,
            Technique::Tsm(t) => t,
            Technique::Xpsm(t) => t,
            Technique::Psm(t) => t,
            Technique::Sppsm(t) => t,
            Technique::Cascades(t) => t,
            Technique::Cube(t) => t,
            Technique::Paraboloid(t) => t,
        }
    }
}

impl ShadowTechnique for Technique {
    fn name(&self) -> &'static str {
        self.as_dyn().name()
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        self.as_dyn().setup(input)
    }
}

/// The error for an unknown technique name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownTechnique(pub String);

impl fmt::Display for UnknownTechnique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown technique '{}' (known: {})",
            self.0,
            Technique::NAMES.join(", ")
        )
    }
}

impl std::error::Error for UnknownTechnique {}

impl FromStr for Technique {
    type Err = UnknownTechnique;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "uniform" | "ssm" => Ok(Technique::Uniform(Uniform)),
            "focused" | "fsm" => Ok(Technique::Focused(Focused)),
            "lispsm" => Ok(Technique::Lispsm(Lispsm::default())),
            "tsm" => Ok(Technique::Tsm(Tsm::default())),
            "xpsm" => Ok(Technique::Xpsm(Xpsm::default())),
            "psm" => Ok(Technique::Psm(Psm::default())),
            "sppsm" => Ok(Technique::Sppsm(Sppsm::default())),
            "cascades" | "csm" => Ok(Technique::Cascades(Cascades::default())),
            "cube" => Ok(Technique::Cube(Cube)),
            "paraboloid" | "dpsm" => Ok(Technique::Paraboloid(DualParaboloid)),
            _ => Err(UnknownTechnique(s.to_string())),
        }
    }
}

/// Computes a setup with `technique`: validates the map settings, runs the technique and
/// checks that every matrix is finite.
pub fn compute_setup(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
) -> Result<ShadowSetup, SetupError> {
    checked_setup(technique, camera, light, scene, map, None)
}

/// [`compute_setup`] with the frame's [`ViewSamples`]: what the renderer's pixels see (its
/// real surfaces, where the core knows only boxes), or samples shared by several setups of one
/// frame. The warp limit compares maps on them.
pub fn compute_setup_with_samples(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
    samples: &ViewSamples,
) -> Result<ShadowSetup, SetupError> {
    checked_setup(technique, camera, light, scene, map, Some(samples))
}

fn checked_setup(
    technique: &dyn ShadowTechnique,
    camera: &Camera,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
    samples: Option<&ViewSamples>,
) -> Result<ShadowSetup, SetupError> {
    map.validate()?;
    let setup = technique.setup(&SetupInput {
        camera,
        light,
        scene,
        map,
        samples,
    })?;
    if setup.maps.iter().all(ShadowMap::is_finite) {
        Ok(setup)
    } else {
        Err(SetupError::NumericalFailure {
            technique: technique.name(),
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::boxes::Aabb;
    use crate::camera::Lens;
    use crate::light::{DirectionalLight, PointLight, SpotLight};

    /// `Technique::takes` says what the setups themselves refuse: a technique takes a light
    /// exactly when its setup does not refuse it for its kind.
    #[test]
    fn takes_agrees_with_the_setups_refusals() {
        let ground =
            Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
        let block = Aabb::new(DVec3::new(-5.0, 0.0, -5.0), DVec3::new(5.0, 10.0, 5.0)).unwrap();
        let scene = SceneBounds::new(vec![block], vec![ground, block], None).unwrap();
        let camera = Camera::look_at(
            DVec3::new(30.0, 20.0, 30.0),
            DVec3::ZERO,
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let lights = [
            Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.2)).unwrap()),
            Light::Spot(
                SpotLight::new(DVec3::new(0.0, 40.0, 10.0), -DVec3::Y, 50.0, 100.0).unwrap(),
            ),
            Light::Point(PointLight::new(DVec3::new(8.0, 6.0, 8.0), 60.0).unwrap()),
        ];
        for technique in Technique::all() {
            for light in &lights {
                let result =
                    compute_setup(&technique, &camera, light, &scene, MapSettings::default());
                let refused = matches!(
                    result,
                    Err(SetupError::NeedsPointLight { .. }
                        | SetupError::PointLightUnsupported { .. })
                );
                assert_eq!(
                    technique.takes(light),
                    !refused,
                    "{} with {light:?}: {result:?}",
                    technique.name()
                );
                assert!(
                    refused || result.is_ok(),
                    "{}: {result:?}",
                    technique.name()
                );
            }
        }
    }
}
