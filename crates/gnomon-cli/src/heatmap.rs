//! The per-pixel sampling error as a heat map with a legend, and its percentiles.
//!
//! Colours follow log2 of the undersampling (pixels per texel along the worst direction):
//! blue where the map is oversampled (more than one texel per pixel), white at exactly one
//! texel per pixel, then yellow, orange, red and dark red up to 32 pixels per texel. Pixels
//! without geometry are dark grey; geometry the map does not see is magenta.

use gnomon_render::PixelMetrics;
use serde_json::{Value, json};

/// The scale's ends, in log2 of pixels per texel: 1/8 and 32.
const LOG2_MIN: f64 = -3.0;
const LOG2_MAX: f64 = 5.0;

/// The legend strip's height in pixels.
const LEGEND_HEIGHT: u32 = 30;

/// Colour stops (log2 value, RGB).
const STOPS: [(f64, [u8; 3]); 6] = [
    (-3.0, [40, 70, 170]),
    (0.0, [245, 245, 245]),
    (1.0, [250, 220, 60]),
    (2.0, [245, 140, 30]),
    (3.5, [215, 40, 30]),
    (5.0, [110, 0, 20]),
];

/// The colour of an undersampling value.
pub fn color(undersampling: f64) -> [u8; 3] {
    let v = undersampling.log2().clamp(LOG2_MIN, LOG2_MAX);
    for pair in STOPS.windows(2) {
        let ((a, ca), (b, cb)) = (pair[0], pair[1]);
        if v <= b {
            let t = (v - a) / (b - a);
            return [0, 1, 2]
                .map(|k| (ca[k] as f64 + (cb[k] as f64 - ca[k] as f64) * t).round() as u8);
        }
    }
    STOPS[STOPS.len() - 1].1
}

/// 3x5 pixel glyphs for the legend's labels, one row per 3 bits (top first).
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b111, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b010, 0b010, 0b010],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '/' => [0b001, 0b001, 0b010, 0b100, 0b100],
        _ => return None,
    })
}

/// The heat map of `metrics` (`width` x `height`), with a legend strip below it: the colour
/// scale from 1/8 to 32 pixels per texel with ticks and labels at the powers of two.
/// RGBA bytes; the image is `width` x (`height` + 30).
pub fn draw(metrics: &PixelMetrics, width: u32, height: u32) -> Vec<u8> {
    let total_height = height + LEGEND_HEIGHT;
    let mut out = vec![0u8; (width * total_height * 4) as usize];
    let mut put = |x: u32, y: u32, rgb: [u8; 3]| {
        if x < width && y < total_height {
            let i = ((y * width + x) * 4) as usize;
            out[i..i + 4].copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
        }
    };
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let u = metrics.undersampling[i] as f64;
            let rgb = if u == 0.0 {
                [50, 50, 50]
            } else if !metrics.measured(i) {
                [230, 0, 230]
            } else {
                color(u)
            };
            put(x, y, rgb);
        }
    }
    // The legend: a background, the colour bar, ticks and labels.
    for y in height..total_height {
        for x in 0..width {
            put(x, y, [255, 255, 255]);
        }
    }
    let margin = 8.min(width / 4);
    let bar = width.saturating_sub(2 * margin).max(1);
    let log2_at = |x: u32| LOG2_MIN + (LOG2_MAX - LOG2_MIN) * (x - margin) as f64 / bar as f64;
    for x in margin..margin + bar {
        let rgb = color(log2_at(x).exp2());
        for y in height + 3..height + 13 {
            put(x, y, rgb);
        }
    }
    let scale = if width >= 480 { 2 } else { 1 };
    for k in LOG2_MIN as i32..=LOG2_MAX as i32 {
        let x = margin + ((k as f64 - LOG2_MIN) / (LOG2_MAX - LOG2_MIN) * bar as f64) as u32;
        let x = x.min(margin + bar - 1);
        for y in height + 13..height + 16 {
            put(x, y, [0, 0, 0]);
        }
        let label = if k < 0 {
            format!("1/{}", 1u32 << (-k))
        } else {
            format!("{}", 1u32 << k)
        };
        let label_width = label.len() as u32 * 4 * scale;
        let mut cx = x.saturating_sub(label_width / 2);
        for c in label.chars() {
            if let Some(rows) = glyph(c) {
                for (r, bits) in rows.iter().enumerate() {
                    for b in 0..3u32 {
                        if bits >> (2 - b) & 1 == 1 {
                            for dy in 0..scale {
                                for dx in 0..scale {
                                    put(
                                        cx + b * scale + dx,
                                        height + 17 + r as u32 * scale + dy,
                                        [0, 0, 0],
                                    );
                                }
                            }
                        }
                    }
                }
            }
            cx += 4 * scale;
        }
    }
    out
}

/// p50, p95, p99 and max of `values` over the visible pixels that face the light
/// ([`PixelMetrics::lit_facing`]: N.L > 0.1), as JSON (null when none).
pub fn percentiles(metrics: &PixelMetrics, values: &[f32]) -> Value {
    let mut v: Vec<f64> = (0..values.len())
        .filter(|&i| metrics.lit_facing(i))
        .map(|i| values[i] as f64)
        .filter(|x| x.is_finite())
        .collect();
    if v.is_empty() {
        return Value::Null;
    }
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
    json!({
        "p50": at(0.50),
        "p95": at(0.95),
        "p99": at(0.99),
        "max": v[v.len() - 1],
        "pixels": v.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_texel_per_pixel_is_white_and_undersampling_is_warm() {
        assert_eq!(color(1.0), [245, 245, 245]);
        let [r, _, b] = color(8.0);
        assert!(r > 150 && b < 60, "{:?}", color(8.0));
        let [r, _, b] = color(0.25);
        assert!(b > r, "{:?}", color(0.25));
        assert_eq!(color(1e9), color(32.0));
        assert_eq!(color(1e-9), color(0.125));
    }

    #[test]
    fn percentiles_skip_unmeasured_pixels() {
        let n = 101;
        let metrics = PixelMetrics {
            undersampling: (0..n)
                .map(|i| if i == 0 { 0.0 } else { i as f32 })
                .collect(),
            area: vec![1.0; n],
            n_dot_l: vec![1.0; n],
        };
        let p = percentiles(&metrics, &metrics.undersampling);
        assert_eq!(p["pixels"], 100);
        assert_eq!(p["max"], 100.0);
        assert_eq!(p["p50"].as_f64().unwrap().round(), 51.0);
        let image = draw(&metrics, 101, 1);
        assert_eq!(image.len(), 101 * (1 + LEGEND_HEIGHT as usize) * 4);
        assert_eq!(&image[..4], &[50, 50, 50, 255], "no geometry is dark grey");
    }
}
