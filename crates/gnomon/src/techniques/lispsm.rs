//! Light space perspective shadow maps (LiSPSM).
//!
//! Wimmer, Scherzer and Purgathofer, "Light Space Perspective Shadow Maps" (EGSR 2004,
//! revised 2005).
//!
//! Light space (section 3.4): the map's depth axis is the light direction; its +y axis (the
//! paper's light-space z) is the view direction made perpendicular to the light; x completes
//! the frame. In these coordinates (X, Y, Z) a perspective frustum P looks along +Y: its
//! projection reference point p sits at Y = Y_min - n (n in front of B's nearest Y), at the
//! eye's X and at the middle of B's Z range; its near and far planes are B's Y_min and Y_max.
//! Light rays (along Z) stay parallel under P, so the map is a plain orthographic map of the
//! warped space. With d = Y - Y_min + n and f = n + (Y_max - Y_min), the warped coordinates
//! are
//!
//! ```text
//! u = (X - X_eye) / d,   s = f (d - n) / (d (f - n)),   z = (Z - Z_mid) / d     (eq. 2)
//! ```
//!
//! computed with w = d / n = 1 + (Y - Y_min) / n so that n -> infinity is the orthographic
//! (focused) map with no loss of precision: `s = (Y - Y_min) (1 / (f - n) + 1 / n) / w`.
//!
//! The free parameter (section 4): n_opt = z_n + sqrt(z_f z_n) equalises the perspective
//! aliasing error dp/ds at the near and far planes in the ideal case (view perpendicular to
//! the light). In general n = (z_n + sqrt(z_n z_f')) / sin(gamma), with the section 4.4
//! refinement z_f' = z_n + (Y_max - Y_min) sin(gamma). Here z_n is the view depth at which
//! the visible scene begins. In the paper's ideal case (B = the view frustum) that is the
//! near plane's distance. When the view reaches the scene only beyond its near plane, it is
//! the least view depth of P: a distant view of the scene would otherwise be warped as if
//! the viewer stood in it, and the map spent on one corner. As gamma -> 0 (view along the
//! light) or 180 degrees (view into the light), n -> infinity and the map converges smoothly
//! to the focused map. The user may set n.
//!
//! The blog post's caster problem (casters clipped when only receivers define P, precision
//! lost when casters near P's singular plane d = 0 widen the depth range): P encloses B, and
//! every caster point that can shadow a visible receiver lies in B (section 3.3), so casters
//! are cut to B's Y range [Y_min, Y_max] before their warped extents are taken. There
//! d >= n, which is positive: no caster reaches the singular plane, none that matters is
//! clipped, and the ones behind p are irrelevant. The depth compared in the map is the
//! linear depth along the light (`depth_from_world`), so P's warp never touches depth
//! precision. The clip-space z is the warped z, unit-cube clipped so that the rasteriser
//! clips no relevant caster.
//!
//! Spot lights (end of section 3.4): light space is built after the spot's own perspective
//! transform, where its rays are parallel, and the construction above runs unchanged there
//! (see `view_warp`); B lies inside the spot's frustum, in front of its near plane, so the
//! combined map has no singularity over B. The paper's analysis of n does not carry over to
//! point lights (end of section 4): n keeps the ratio n / (Y_max - Y_min) that the formula
//! above gives with B's world depth along light space's y axis and gamma the angle between
//! the view direction and the light's ray through the eye; a user's n is read the same way.
//!
//! Degenerate cases: view parallel to the light (for a spot light: the view ray through the
//! light) falls back to the focused map (named in the diagnostics); nothing visible gives
//! the uniform map; a spot light that cannot see the view gives the uniform map.

use crate::error::SetupError;
use crate::map::ShadowSetup;
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::on_whole_frame;
use crate::techniques::view_warp::view_warp_setup;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::warp_space::WarpChoice;

/// Light space perspective shadow map (LiSPSM, Wimmer et al. 2004): a perspective warp in
/// light space along the view direction, with the paper's optimal warp strength n, then
/// unit cube clipping. See the module documentation for the construction and each
/// degenerate case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lispsm {
    /// The distance n of the projection reference point from B's near side, in world units.
    /// `None`: the paper's n_opt / sin(gamma) with the section 4.4 refinement.
    pub n: Option<f64>,
    /// Whether the warp is weakened where it would sample the view more coarsely than the
    /// focused map (see [`crate::Fallback::WarpLimited`]; 1 / n is scaled by the strength).
    pub limit: bool,
}

impl Default for Lispsm {
    /// n_opt, with the warp limit.
    fn default() -> Self {
        Self {
            n: None,
            limit: true,
        }
    }
}

impl LimitedWarp for Lispsm {
    fn check(&self) -> Result<(), SetupError> {
        match self.n {
            Some(n) if !(n.is_finite() && n > 0.0) => Err(SetupError::InvalidParameter {
                name: "lispsm n",
                value: n,
            }),
            _ => Ok(()),
        }
    }

    fn limited(&self) -> bool {
        self.limit
    }

    /// The setup with 1 / n scaled by `strength` (1: the paper's).
    fn at_strength(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        strength: f64,
    ) -> Result<ShadowSetup, SetupError> {
        view_warp_setup(input, basis, self.name(), true, |c| {
            // P's near plane at B's nearest Y; the projection reference point n before it.
            // The formula is in world units; for a spot light, light space's Y is in tangent
            // units, so 1 / n is scaled by B's world depth over its depth in light space
            // (which keeps n / (Y_max - Y_min) as the world formula gives it).
            let depth_along_view = c.body_light.max.y - c.body_light.min.y;
            let inv_n_world = match self.n {
                Some(n) => 1.0 / n,
                None => {
                    // n_opt / sin(gamma), with z_f replaced by z_n + (f - n) sin(gamma) (4.4),
                    // and z_n the view depth where the visible scene begins (the near plane's
                    // distance in the paper's ideal case, farther when the view reaches the
                    // scene only beyond it).
                    let z_n = c.near_depth;
                    c.sin_gamma / (z_n + (z_n * (z_n + c.depth_world * c.sin_gamma)).sqrt())
                }
            };
            let inv_n = strength * inv_n_world * c.depth_world / depth_along_view;
            WarpChoice {
                y_origin: c.body_light.min.y,
                inv_n,
                k: 1.0 / depth_along_view + inv_n,
            }
        })
    }
}

impl ShadowTechnique for Lispsm {
    fn name(&self) -> &'static str {
        "lispsm"
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
