//! The warp limit: no warp samples what the camera sees more coarsely than the focused map
//! it starts from.
//!
//! A perspective warp (PSM, LiSPSM, TSM, XPSM) moves texels from the far part of the view to
//! the near part. Where the view's receivers are mostly far, or seen from the side, that can
//! make the map coarser than the focused map for most pixels (the robustness issue's XPSM in
//! the demo's `light_behind` view: 95% of pixels below 172 pixels per texel against the
//! focused map's 26). The limit compares both maps where the pixels are: over the frame's
//! [`ViewSamples`] it takes the 95th percentile of pixels per texel along the worst
//! direction (the renderer's undersampling metric) of each. While the warp's is larger, the
//! strength is halved (LiSPSM's 1 / n and XPSM's len times the strength; PSM's virtual eye
//! and TSM's projection point moved away by its inverse), at most [`HALVINGS`] times; then
//! the focused map is used. [`Fallback::WarpLimited`] and [`Fallback::WarpCoarserThanFocused`]
//! name what happened, and [`crate::Diagnostics::warp_strength`] the strength kept.
//!
//! The limit is a choice of ours, not the papers': each paper's strength is optimal for its
//! error model along the view axis (the LiSPSM paper's ideal configuration, where no limit
//! fires), not for the frame's pixels. Each warp technique has a `limit` switch.

use crate::error::SetupError;
use crate::setup::{Fallback, SetupInput, ShadowSetup, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::with_fallback;

/// The share of the samples whose undersampling is compared (its upper quantile).
pub(crate) const QUANTILE: f64 = 0.95;
/// The warp's worst sample must be at least this much finer than the focused map's: the
/// worst of a few hundred samples is a rough estimate of the worst pixel.
pub(crate) const MAX_MARGIN: f64 = 0.9;
/// How many times the strength may be halved before the focused map is used.
pub(crate) const HALVINGS: u32 = 3;
/// Below this many samples the frame says too little to judge, and the warp is kept.
pub(crate) const MIN_SAMPLES: usize = 16;

/// A perspective warp that the limit weakens (PSM, LiSPSM, TSM, XPSM): its parameters' check,
/// whether the limit is on, and its setup at a strength (1: the paper's).
pub(crate) trait LimitedWarp: ShadowTechnique {
    /// Checks the technique's own parameters.
    fn check(&self) -> Result<(), SetupError>;
    /// Whether the limit is on.
    fn limited(&self) -> bool;
    /// The setup on `basis` with the warp's strength scaled by `strength`.
    fn at_strength(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        strength: f64,
    ) -> Result<ShadowSetup, SetupError>;

    /// The setup on `basis` (a part of the frame; `input`'s camera is the part's), limited.
    fn setup_with(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
    ) -> Result<ShadowSetup, SetupError> {
        input.map.validate()?;
        self.check()?;
        limit_warp(input, basis, self.name(), self.limited(), |strength| {
            self.at_strength(input, basis, strength)
        })
    }
}

/// The setup `build` gives at the largest strength in 1, 1/2, ... 1/2^HALVINGS whose map
/// samples `basis`'s share of the frame's view no more coarsely than the focused map, else
/// the focused map; with `enabled` false, or when the full-strength setup is not a warp (a
/// fallback), that setup. `build` and the focused map share the basis.
fn limit_warp(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    technique: &'static str,
    enabled: bool,
    build: impl Fn(f64) -> Result<ShadowSetup, SetupError>,
) -> Result<ShadowSetup, SetupError> {
    let mut setup = build(1.0)?;
    if !enabled || !is_warp(&setup) {
        return Ok(setup);
    }
    let samples = basis.samples();
    if samples.len() < MIN_SAMPLES {
        return Ok(setup);
    }
    let focused = basis.focused(input);
    // The 95th percentile and the worst sample.
    let measure = |s: &ShadowSetup| {
        samples
            .undersampling_quantiles(&s.maps[0], [QUANTILE, 1.0])
            .unwrap_or([f64::INFINITY; 2])
    };
    let reference = measure(focused);
    let mut strength = 1.0;
    for halving in 0..=HALVINGS {
        if halving > 0 {
            strength *= 0.5;
            setup = build(strength)?;
        }
        let ours = measure(&setup);
        if ours[0] <= reference[0] && ours[1] <= MAX_MARGIN * reference[1] {
            if halving > 0 {
                setup.diagnostics.fallbacks.push(Fallback::WarpLimited);
            }
            setup.diagnostics.warp_strength = Some(strength);
            return Ok(setup);
        }
    }
    let mut focused = with_fallback(focused.clone(), technique, Fallback::WarpCoarserThanFocused);
    focused.diagnostics.warp_strength = Some(0.0);
    Ok(focused)
}

/// Whether a technique's setup is its warp (not the focused or uniform map it fell back to).
fn is_warp(setup: &ShadowSetup) -> bool {
    !setup.diagnostics.fallbacks.iter().any(|f| {
        matches!(
            f,
            Fallback::NoVisibleReceiver
                | Fallback::LightParallelToView
                | Fallback::SpotLightMissesView
                | Fallback::DegenerateFocusBody
                | Fallback::SpotLightNotWarped
        )
    })
}
