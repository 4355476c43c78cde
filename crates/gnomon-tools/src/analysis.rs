//! `analyze`'s curves: perspective aliasing dp/ds along the view axis of every technique,
//! measured from its actual matrices in the LiSPSM paper's ideal configuration.

use gnomon::analysis::{AliasingCurve, IdealConfiguration, setup_view_axis_aliasing_in_texels};
use gnomon::{MapSettings, Psm, SetupError, ShadowTechnique, Technique, compute_setup};
use serde_json::{Value, json};

use crate::params::TechniqueParams;

/// One analysed technique.
#[derive(Debug, Clone)]
pub struct AnalysisRow {
    /// The technique's name (`psm-paper`: PSM as the papers draw it).
    pub label: String,
    /// The setup's fallback, if it took one.
    pub fallback: Option<&'static str>,
    /// Its curve, or why it cannot be measured.
    pub curve: Result<AliasingCurve, String>,
}

/// Every analysed technique's curve.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// The configuration (z_n, z_f, gamma).
    pub config: IdealConfiguration,
    /// Map size in texels.
    pub shadow_map: u32,
    /// One row per technique.
    pub rows: Vec<AnalysisRow>,
}

/// The techniques analysed: every technique with its parameters, and PSM as in the papers
/// (the virtual camera not slid back: n = z_n; no warp limit), which the LiSPSM paper's
/// Figure 6 plots.
fn techniques(params: &TechniqueParams) -> Vec<(String, Technique)> {
    let mut out = Vec::new();
    // The ideal configuration has a directional light.
    let sun = gnomon::Light::Directional(
        gnomon::DirectionalLight::new(glam::DVec3::NEG_Y).expect("a unit direction"),
    );
    for technique in Technique::all().into_iter().filter(|t| t.takes(&sun)) {
        // The papers' warps along the view axis: the warp limit judges a frame's pixels, and
        // the ideal configuration's scene is the view frustum's box, which holds the eye.
        let technique = TechniqueParams {
            no_warp_limit: true,
            ..*params
        }
        .apply(technique);
        // Cascades measured with no blend band.
        let technique = match technique {
            Technique::Cascades(c) => Technique::Cascades(gnomon::Cascades { blend: 0.0, ..c }),
            other => other,
        };
        if let Technique::Psm(_) = technique {
            out.push((
                "psm-paper".to_string(),
                Technique::Psm(Psm {
                    slide_back: Some(0.0),
                    limit: false,
                }),
            ));
        }
        out.push((technique.name().to_string(), technique));
    }
    out
}

/// The curves of every technique with `params`, `samples` distances from z_n to z_f, in the
/// texels of one `shadow_map` map (cascades with equal texels share them).
pub fn analyze(
    config: IdealConfiguration,
    params: &TechniqueParams,
    samples: usize,
    shadow_map: u32,
) -> Result<Analysis, SetupError> {
    let (camera, light, scene) = (config.camera()?, config.light()?, config.scene()?);
    let mut rows = Vec::new();
    for (label, technique) in techniques(params) {
        let map = MapSettings::with_resolution(shadow_map);
        let setup = compute_setup(&technique, &camera, &light, &scene, map)?;
        let curve = setup_view_axis_aliasing_in_texels(&setup, &config, samples, shadow_map)
            .map_err(|e| e.to_string());
        rows.push(AnalysisRow {
            label,
            fallback: setup.fallback().map(|f| f.name()),
            curve,
        });
    }
    Ok(Analysis {
        config,
        shadow_map,
        rows,
    })
}

impl Analysis {
    /// What `gnomon analyze --json` prints.
    pub fn to_json(&self) -> Value {
        let techniques: Vec<_> = self
            .rows
            .iter()
            .map(|r| match &r.curve {
                Ok(c) => json!({
                    "technique": r.label,
                    "fallback": r.fallback,
                    "max": c.max,
                    "z_of_max": c.z_of_max,
                    "at_z_n": c.at_near,
                    "at_z_f": c.at_far,
                    "min": c.min,
                    "z_of_min": c.z_of_min,
                    "curve": c.z.iter().zip(&c.dp_ds).map(|(z, v)| [*z, *v]).collect::<Vec<_>>(),
                }),
                Err(e) => json!({"technique": r.label, "fallback": r.fallback, "error": e}),
            })
            .collect();
        json!({
            "z_n": self.config.z_near,
            "z_f": self.config.z_far,
            "gamma_degrees": self.config.gamma_degrees,
            "shadow_map": self.shadow_map,
            "logarithmic_ideal": self.config.logarithmic_ideal(),
            "techniques": techniques,
        })
    }
}
