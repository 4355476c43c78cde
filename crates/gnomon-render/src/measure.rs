//! How a frame is judged against the exact shadows and how its sampling error is summed up:
//! one definition for every front end (the command line's `compare` and `demo`, the Python
//! bindings' `compare`).

use crate::frame::PixelMetrics;
use crate::{MASK_EMPTY, MASK_LIT, MASK_UNLIT};

/// The N.L above which a pixel is judged: surfaces nearer edge-on to the light are dark
/// either way and no map resolves them.
pub const JUDGED_N_DOT_L: f32 = 0.1;

/// What one pixel of a map's mask says against the exact mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelVerdict {
    /// Not judged: no geometry in either mask, or a surface nearly edge-on to the light.
    NotJudged,
    /// The same as the exact mask.
    Agrees,
    /// Shadowed where the light reaches.
    FalseShadow,
    /// Lit where the light does not reach.
    MissedShadow,
}

impl PixelVerdict {
    /// The verdict of a pixel: the map's mask value, the exact one, and the pixel's N.L.
    pub fn of(map: u8, exact: u8, n_dot_l: f32) -> Self {
        let facing = n_dot_l > JUDGED_N_DOT_L;
        if map == MASK_EMPTY || exact == MASK_EMPTY || !facing {
            return PixelVerdict::NotJudged;
        }
        match (map, exact) {
            (MASK_UNLIT, MASK_LIT) => PixelVerdict::FalseShadow,
            (MASK_LIT, MASK_UNLIT) => PixelVerdict::MissedShadow,
            _ => PixelVerdict::Agrees,
        }
    }
}

/// A map's mask against the exact mask: the pixels judged and those wrong either way.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaskErrors {
    /// Pixels judged ([`PixelVerdict::of`]).
    pub compared: usize,
    /// Shadowed where the light reaches.
    pub false_shadow: usize,
    /// Lit where the light does not reach.
    pub missed_shadow: usize,
}

impl MaskErrors {
    /// The errors of a whole mask (`map`, `exact` and `n_dot_l` per pixel, in one order).
    pub fn of(map: &[u8], exact: &[u8], n_dot_l: &[f32]) -> Self {
        let mut errors = Self::default();
        for ((&m, &e), &n) in map.iter().zip(exact).zip(n_dot_l) {
            errors.add(PixelVerdict::of(m, e, n));
        }
        errors
    }

    /// Counts one pixel's verdict.
    pub fn add(&mut self, verdict: PixelVerdict) {
        match verdict {
            PixelVerdict::NotJudged => return,
            PixelVerdict::Agrees => {}
            PixelVerdict::FalseShadow => self.false_shadow += 1,
            PixelVerdict::MissedShadow => self.missed_shadow += 1,
        }
        self.compared += 1;
    }

    /// The share of judged pixels that are wrong, in percent.
    pub fn wrong_percent(&self) -> f64 {
        self.percent(self.false_shadow + self.missed_shadow)
    }

    /// The share of judged pixels falsely shadowed, in percent.
    pub fn false_shadow_percent(&self) -> f64 {
        self.percent(self.false_shadow)
    }

    /// The share of judged pixels falsely lit, in percent.
    pub fn missed_shadow_percent(&self) -> f64 {
        self.percent(self.missed_shadow)
    }

    fn percent(&self, n: usize) -> f64 {
        100.0 * n as f64 / self.compared.max(1) as f64
    }
}

/// How a map lookup's classification ([`PixelMetrics::unsure`]) holds against the exact
/// mask: of the judged pixels, those whose lookup is unsure, and the sure ones that are
/// wrong. Where the unsure pixels are decided exactly, the sure ones' errors are what is
/// left.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SureErrors {
    /// Pixels judged ([`PixelVerdict::of`]).
    pub compared: usize,
    /// Of those, the pixels whose lookup is unsure.
    pub unsure: usize,
    /// Of those, the pixels whose lookup is sure and wrong.
    pub sure_wrong: usize,
}

impl SureErrors {
    /// The classification of a whole mask (`map`, `exact`, `n_dot_l` and `unsure` per
    /// pixel, in one order).
    pub fn of(map: &[u8], exact: &[u8], n_dot_l: &[f32], unsure: &[bool]) -> Self {
        let mut errors = Self::default();
        for (((&m, &e), &n), &unsure) in map.iter().zip(exact).zip(n_dot_l).zip(unsure) {
            let verdict = PixelVerdict::of(m, e, n);
            if verdict == PixelVerdict::NotJudged {
                continue;
            }
            errors.compared += 1;
            errors.unsure += usize::from(unsure);
            errors.sure_wrong += usize::from(!unsure && verdict != PixelVerdict::Agrees);
        }
        errors
    }

    /// The share of judged pixels whose lookup is unsure, in percent.
    pub fn unsure_percent(&self) -> f64 {
        100.0 * self.unsure as f64 / self.compared.max(1) as f64
    }

    /// The share of judged pixels whose lookup is sure and wrong, in percent.
    pub fn sure_wrong_percent(&self) -> f64 {
        100.0 * self.sure_wrong as f64 / self.compared.max(1) as f64
    }
}

/// Percentiles of a per-pixel measure over the pixels where the map's sampling shows
/// ([`PixelMetrics::lit_facing`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Percentiles {
    /// The median.
    pub p50: f64,
    /// The 95th percentile.
    pub p95: f64,
    /// The 99th percentile.
    pub p99: f64,
    /// The largest value.
    pub max: f64,
    /// How many pixels were counted.
    pub pixels: usize,
}

impl PixelMetrics {
    /// The percentiles of `values` (one of this frame's measures, such as
    /// [`PixelMetrics::undersampling`]) over the lit, light-facing pixels the map sees;
    /// `None` where there are none.
    pub fn percentiles(&self, values: &[f32]) -> Option<Percentiles> {
        let mut v: Vec<f64> = (0..values.len())
            .filter(|&i| self.lit_facing(i))
            .map(|i| f64::from(values[i]))
            .filter(|x| x.is_finite())
            .collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        Some(Percentiles {
            p50: at(0.50),
            p95: at(0.95),
            p99: at(0.99),
            max: v[v.len() - 1],
            pixels: v.len(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_and_shares() {
        let map = [
            MASK_LIT, MASK_UNLIT, MASK_LIT, MASK_UNLIT, MASK_EMPTY, MASK_LIT,
        ];
        let exact = [
            MASK_LIT, MASK_LIT, MASK_UNLIT, MASK_UNLIT, MASK_LIT, MASK_UNLIT,
        ];
        let n_dot_l = [0.5, 0.5, 0.5, 0.5, 0.5, 0.05];
        let errors = MaskErrors::of(&map, &exact, &n_dot_l);
        assert_eq!(
            errors,
            MaskErrors {
                compared: 4,
                false_shadow: 1,
                missed_shadow: 1
            }
        );
        assert_eq!(errors.wrong_percent(), 50.0);
        assert_eq!(errors.false_shadow_percent(), 25.0);
        assert_eq!(MaskErrors::default().wrong_percent(), 0.0);
        // The second and third pixels are wrong; the second is unsure.
        let unsure = [false, true, false, true, true, false];
        let sure = SureErrors::of(&map, &exact, &n_dot_l, &unsure);
        assert_eq!(
            sure,
            SureErrors {
                compared: 4,
                unsure: 2,
                sure_wrong: 1
            }
        );
        assert_eq!(sure.unsure_percent(), 50.0);
        assert_eq!(sure.sure_wrong_percent(), 25.0);
    }
}
