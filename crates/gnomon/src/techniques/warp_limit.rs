//! The warp limit: no warp samples what the camera sees more coarsely than the focused map
//! it starts from.
//!
//! A perspective warp (PSM, LiSPSM, TSM, XPSM) moves texels from the far part of the view to
//! the near part. Where the view's receivers are mostly far, or seen from the side, that can
//! make the map coarser than the focused map for most pixels (XPSM in the demo's
//! `light_behind` view, for one). The limit compares both maps where the pixels are: over the frame's
//! [`crate::ViewSamples`] it takes the 95th percentile of pixels per texel along the worst
//! direction (the renderer's undersampling metric) of each. While the warp's is larger, the
//! strength is halved (LiSPSM's 1 / n and XPSM's len times the strength; PSM's virtual eye
//! and TSM's projection point moved away by its inverse), at most [`HALVINGS`] times; then
//! the focused map is used. The halving also stops, for the focused map, where it made both
//! figures worse: the figures move from the warp's toward the unwarped map's (close to the
//! focused map's) as the strength falls, so once weakening stops helping, the weaker warps
//! are not expected to beat the focused map by the margin, and building them costs a whole
//! setup each.
//! [`Fallback::WarpLimited`] and [`Fallback::WarpCoarserThanFocused`] name what happened, and
//! [`crate::Diagnostics::warp_strength`] the strength kept.
//!
//! The limit judges on the samples of the part it sets up (a cascade's slice, a cube face):
//! below [`FEW_SAMPLES`] for gross failures only; a part with none keeps the warp unjudged.
//!
//! The limit is a choice of ours, not the papers': each paper's strength is optimal for its
//! error model along the view axis (the LiSPSM paper's ideal configuration, where no limit
//! fires), not for the frame's pixels. Each warp technique has a `limit` switch.

use crate::diagnostics::Fallback;
use crate::error::SetupError;
use crate::map::{ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::focused::focused_map;
use crate::techniques::focused::receivers_map;
use crate::techniques::with_fallback;

/// The share of the samples whose undersampling is compared (its upper quantile).
pub(crate) const QUANTILE: f64 = 0.95;
/// The warp's worst sample must be at least this much finer than the focused map's: the
/// worst of a few hundred samples is a rough estimate of the worst pixel.
pub(crate) const MAX_MARGIN: f64 = 0.9;
/// How many times the strength may be halved before the focused map is used.
pub(crate) const HALVINGS: u32 = 3;
/// Below this many samples (a cube face's or a far cascade slice's share of the frame's) the
/// figures are too few to weigh a close call: their 95th percentile is their worst sample,
/// and [`MAX_MARGIN`] allows for the worst of a few hundred. They still show a gross
/// failure: such a part's warp is kept unless its worst sample is more than [`GROSS`] times
/// that of the map focused on the receivers alone (`focused::receivers_map`: never finer
/// than the focused map, and made without walking the casters). Left unjudged, a PSM cube
/// face seen by a handful of samples was far coarser than the focused map there.
pub(crate) const FEW_SAMPLES: usize = crate::samples::ViewSamples::MIN_LIT;
/// How many times coarser a worst sample must be to fail a part that only a few samples see.
/// A slightly coarser warp over a few samples still beat the focused map on the demo's far
/// cascade slices, while the cube faces that failed in random scenes were coarser by far
/// more (the measurements are in CHANGELOG.md).
pub(crate) const GROSS: f64 = 4.0;

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
/// the focused map. A share of fewer than [`FEW_SAMPLES`] only needs no more than [`GROSS`]
/// times as coarse as the map focused on the receivers alone. With `enabled` false, when the
/// full-strength setup is not a warp (a fallback), or when no sample sees the share, it is
/// that setup. `build` and the focused map share the basis.
fn limit_warp(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    technique: &'static str,
    enabled: bool,
    build: impl Fn(f64) -> Result<ShadowSetup, SetupError>,
) -> Result<ShadowSetup, SetupError> {
    let setup = build(1.0)?;
    if !enabled || !is_warp(&setup) {
        return Ok(setup);
    }
    // A part of the view where no sample is seen (hidden behind nearer receivers, or lit
    // at too grazing an angle) gives nothing to judge by: the warp is kept. A few samples
    // (a cube face's or a far slice's share) are judged for gross failures only (see
    // `FEW_SAMPLES`).
    let samples = basis.samples();
    if samples.is_empty() {
        return Ok(setup);
    }
    // The 95th percentile and the worst sample.
    let measure = |map: &ShadowMap| {
        samples
            .undersampling_quantiles(map, [QUANTILE, 1.0])
            .unwrap_or([f64::INFINITY; 2])
    };
    let reference = if samples.len() < FEW_SAMPLES {
        // Passing needs only the worst sample no more than GROSS times that of the map
        // focused on the receivers alone (the margin on the worst sample undone), which is
        // never finer than the focused map and needs no walk of the casters.
        let worst = receivers_map(input, basis).map_or(f64::INFINITY, |map| measure(&map)[1]);
        [f64::INFINITY, GROSS / MAX_MARGIN * worst]
    } else {
        measure(&focused_map(input, basis).maps[0])
    };
    let mut built = Some(setup);
    let strength = pick_strength(reference, |strength| {
        let setup = match built.take() {
            Some(setup) if strength == 1.0 => setup,
            _ => build(strength)?,
        };
        let figures = measure(&setup.maps[0]);
        built = Some(setup);
        Ok(figures)
    })?;
    match (strength, built) {
        (Some(strength), Some(mut setup)) => {
            if strength < 1.0 {
                setup.diagnostics.fallbacks.push(Fallback::WarpLimited);
            }
            setup.diagnostics.warp_strength = Some(strength);
            Ok(setup)
        }
        _ => {
            let focused = focused_map(input, basis).clone();
            let mut focused = with_fallback(focused, technique, Fallback::WarpCoarserThanFocused);
            focused.diagnostics.warp_strength = Some(0.0);
            Ok(focused)
        }
    }
}

/// The strength the limit keeps, given the focused map's figures (`reference`: the
/// undersampling's [`QUANTILE`] and worst sample) and a way to measure the warp's at a
/// strength, called with 1, 1/2, ... 1/2^[`HALVINGS`] in turn. It is the first whose figures
/// pass, or `None` (the focused map) when none does or a halving made both figures worse
/// (see the module documentation); `measure` is not called again after that.
fn pick_strength<E>(
    reference: [f64; 2],
    mut measure: impl FnMut(f64) -> Result<[f64; 2], E>,
) -> Result<Option<f64>, E> {
    let mut strength = 1.0;
    let mut previous = [f64::INFINITY; 2];
    for halving in 0..=HALVINGS {
        if halving > 0 {
            strength *= 0.5;
        }
        let ours = measure(strength)?;
        if ours[0] <= reference[0] && ours[1] <= MAX_MARGIN * reference[1] {
            return Ok(Some(strength));
        }
        if ours[0] >= previous[0] && ours[1] >= previous[1] {
            break;
        }
        previous = ours;
    }
    Ok(None)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The strengths `pick_strength` measures and what it keeps, when the warp's figures at
    /// strengths 1, 1/2, ... are `figures` (the focused map's: [4.0, 4.0]).
    fn run(figures: &[[f64; 2]]) -> (Vec<f64>, Option<f64>) {
        let mut asked = Vec::new();
        let kept = pick_strength::<()>([4.0, 4.0], |strength| {
            asked.push(strength);
            Ok(figures[asked.len() - 1])
        })
        .unwrap();
        (asked, kept)
    }

    #[test]
    fn the_strongest_warp_that_passes_is_kept() {
        // Passing needs the quantile no coarser and the worst sample 10% finer than focused.
        assert_eq!(run(&[[3.0, 3.5]]), (vec![1.0], Some(1.0)));
        assert_eq!(
            run(&[[5.0, 6.0], [4.5, 5.0], [3.9, 3.5]]),
            (vec![1.0, 0.5, 0.25], Some(0.25))
        );
        // The worst sample only 5% finer at every strength: all four tried, focused kept.
        let close = [[3.0, 3.8], [3.1, 3.7], [3.2, 3.65], [3.3, 3.62]];
        assert_eq!(run(&close), (vec![1.0, 0.5, 0.25, 0.125], None));
    }

    #[test]
    fn the_halving_stops_where_it_makes_both_figures_worse() {
        // Better than focused but not by the margin, and worse at half strength: the weaker
        // warps are not built.
        assert_eq!(
            run(&[[4.13, 4.37], [4.24, 4.42], [0.0, 0.0]]),
            (vec![1.0, 0.5], None)
        );
        // One figure better is enough to go on.
        assert_eq!(
            run(&[[4.13, 4.37], [4.24, 4.30], [3.0, 3.0]]),
            (vec![1.0, 0.5, 0.25], Some(0.25))
        );
    }
}
