//! Extended perspective shadow maps (XPSM).
//!
//! After Gussev, as a book chapter on eXtended Perspective Shadow Maps presents it (whose
//! equations the steps below restate), with the w < epsilon_W fix of the blog post on robust
//! unit cube clipping.
//!
//! Light space looks along the light; V is the view direction there and p = V.xy / |V.xy| the
//! projection vector (the view direction made perpendicular to the light: the map's y axis,
//! so the chapter's final rotation of p onto +x is a relabelling here). The warp
//! w = 1 + len (p . (x, y)), with (x, y) relative to the eye and len = coef / |V.xy|, divides
//! x and y: points ahead of the eye are compressed, points near it magnified.
//!
//! Back-projection singularity: with m the smallest p . (x, y) over the convex body B (every
//! caster and receiver point that matters lies in B), len is clamped to
//! (epsilon_W - 1) / m when m < 0, so that w >= epsilon_W over all of B. (The chapter takes m
//! from the casters' and receivers' minima. B is their tight hull, and using it makes the
//! blog post's fix unnecessary, where points with w < epsilon_W contribute xy but not z: no
//! relevant point has w < epsilon_W, and casters are cut to B before their extents are taken.)
//!
//! Depth: the chapter biases z before the divide; here the compared depth is linear along
//! the light (`depth_from_world`), so the bias is in world units and the warp never touches
//! depth precision. Unit cube clipping as for the other warps (see `view_warp`).
//!
//! Degenerate cases: |V.xy| small (view along the light, the miner's lamp) falls back to the
//! focused map, an orthographic map as the chapter prescribes. Spot lights fall back to the
//! focused map (the chapter treats directional lights only). Nothing visible gives the
//! uniform map. Each is named in the diagnostics.

use crate::error::SetupError;
use crate::map::ShadowSetup;
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::on_whole_frame;
use crate::techniques::view_warp::view_warp_setup;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::warp_space::WarpChoice;

/// Extended perspective shadow map (XPSM, after Gussev): a perspective warp centred at the eye
/// along the view direction projected onto the map, with the back-projection clamp. See the
/// module documentation for each degenerate case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xpsm {
    /// Warp strength per world unit at |V.xy| = 1 (len = coef / |V.xy|); larger trades far
    /// resolution for near resolution. About 0.05 for scenes in metres.
    pub coef: f64,
    /// The smallest w allowed over the focus region, in (0, 1).
    pub epsilon_w: f64,
    /// Whether the warp is weakened where it would sample the view more coarsely than the
    /// focused map (see [`crate::Fallback::WarpLimited`]; len is scaled by the strength).
    pub limit: bool,
}

impl Default for Xpsm {
    /// coef 0.05, epsilon_W 0.085 (the chapter's values), with the warp limit.
    fn default() -> Self {
        Self {
            coef: 0.05,
            epsilon_w: 0.085,
            limit: true,
        }
    }
}

impl LimitedWarp for Xpsm {
    fn check(&self) -> Result<(), SetupError> {
        if !(self.coef.is_finite() && self.coef > 0.0) {
            return Err(SetupError::InvalidParameter {
                name: "xpsm coef",
                value: self.coef,
            });
        }
        if !(self.epsilon_w > 0.0 && self.epsilon_w < 1.0) {
            return Err(SetupError::InvalidParameter {
                name: "xpsm epsilon_w",
                value: self.epsilon_w,
            });
        }
        Ok(())
    }

    fn limited(&self) -> bool {
        self.limit
    }

    /// The setup with len scaled by `strength` (1: the chapter's, clamped).
    fn at_strength(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        strength: f64,
    ) -> Result<ShadowSetup, SetupError> {
        view_warp_setup(input, basis, self.name(), false, |c| {
            // |V.xy| is sin(gamma); the frame exists, so it is at least 1e-3.
            let mut len = self.coef / c.sin_gamma;
            let m = c.body_light.min.y - c.eye_light.y;
            if m < 0.0 {
                len = len.min((self.epsilon_w - 1.0) / m);
            }
            WarpChoice {
                y_origin: c.eye_light.y,
                inv_n: len * strength,
                k: 1.0,
            }
        })
    }
}

impl ShadowTechnique for Xpsm {
    fn name(&self) -> &'static str {
        "xpsm"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let crate::Light::Point(point) = input.light {
            return crate::techniques::per_face(self.name(), input, point, |input, basis| {
                self.setup_with(input, basis)
            });
        }
        on_whole_frame(input, |basis| self.setup_with(input, basis))
    }
}
