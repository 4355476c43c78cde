//! The per-pixel sampling error as a heat map with a legend, and its percentiles.
//!
//! Colours follow log2 of the undersampling (pixels per texel along the worst direction):
//! blue where the map is oversampled (more than one texel per pixel), white at exactly one
//! texel per pixel, then yellow, orange, red, dark red and purple up to 256 pixels per texel;
//! black above (the legend's overflow box, "> 256"). Pixels without geometry are dark grey;
//! geometry the map does not see is magenta. The legend (the scale in px/texel, its ticks and
//! the overflow box) lies over the image's bottom strip, so that the map has the frame's size.

use gnomon_render::PixelMetrics;
use serde_json::{Value, json};

/// The scale's ends, in log2 of pixels per texel: 1/8 and 256.
const LOG2_MIN: f64 = -3.0;
const LOG2_MAX: f64 = 8.0;

/// Above the scale.
const OVERFLOW: [u8; 3] = [0, 0, 0];

/// The legend strip's height in pixels.
const LEGEND_HEIGHT: u32 = 30;

/// Colour stops (log2 value, RGB).
const STOPS: [(f64, [u8; 3]); 7] = [
    (-3.0, [40, 70, 170]),
    (0.0, [245, 245, 245]),
    (1.0, [250, 220, 60]),
    (2.0, [245, 140, 30]),
    (3.5, [215, 40, 30]),
    (5.0, [110, 0, 20]),
    (8.0, [120, 40, 150]),
];

/// The colour of an undersampling value.
pub fn color(undersampling: f64) -> [u8; 3] {
    if undersampling.log2() > LOG2_MAX {
        return OVERFLOW;
    }
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
        '>' => [0b100, 0b010, 0b001, 0b010, 0b100],
        'p' => [0b111, 0b101, 0b111, 0b100, 0b100],
        'x' => [0b000, 0b101, 0b010, 0b101, 0b000],
        't' => [0b010, 0b111, 0b010, 0b010, 0b011],
        'e' => [0b111, 0b100, 0b111, 0b100, 0b111],
        'l' => [0b100, 0b100, 0b100, 0b100, 0b111],
        _ => return None,
    })
}

/// The heat map of `metrics` (`width` x `height`, RGBA), with the legend over its bottom
/// strip (when the image is at least three strips tall): the colour scale from 1/8 to 256
/// pixels per texel with ticks and labels at every other power of two, the unit, and the
/// overflow box.
pub fn draw(metrics: &PixelMetrics, width: u32, height: u32) -> Vec<u8> {
    let mut out = vec![0u8; (width * height * 4) as usize];
    let mut put = |x: u32, y: u32, rgb: [u8; 3]| {
        if x < width && y < height {
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
    if height < 3 * LEGEND_HEIGHT || width < 64 {
        return out;
    }
    let top = height - LEGEND_HEIGHT;
    // The legend: a background, the colour bar, the overflow box, ticks and labels.
    for y in top..height {
        for x in 0..width {
            put(x, y, [255, 255, 255]);
        }
    }
    let scale = if width >= 480 { 2 } else { 1 };
    let text = |put: &mut dyn FnMut(u32, u32, [u8; 3]), label: &str, x: u32, y: u32| {
        let mut cx = x;
        for c in label.chars() {
            if let Some(rows) = glyph(c) {
                for (r, bits) in rows.iter().enumerate() {
                    for b in 0..3u32 {
                        if bits >> (2 - b) & 1 == 1 {
                            for dy in 0..scale {
                                for dx in 0..scale {
                                    put(cx + b * scale + dx, y + r as u32 * scale + dy, [0, 0, 0]);
                                }
                            }
                        }
                    }
                }
            }
            cx += 4 * scale;
        }
    };
    let unit = "px/texel";
    let unit_width = unit.len() as u32 * 4 * scale + 6;
    let overflow_width = 4 * 4 * scale + 8;
    let margin = 6u32;
    let bar = width
        .saturating_sub(2 * margin + unit_width + overflow_width)
        .max(8);
    text(&mut put, unit, margin, top + 5);
    let x0 = margin + unit_width;
    let log2_at = |x: u32| LOG2_MIN + (LOG2_MAX - LOG2_MIN) * (x - x0) as f64 / bar as f64;
    for x in x0..x0 + bar {
        let rgb = color(log2_at(x).exp2());
        for y in top + 3..top + 13 {
            put(x, y, rgb);
        }
    }
    // The overflow box and its label.
    let xo = x0 + bar + 4;
    for x in xo..xo + 8 {
        for y in top + 3..top + 13 {
            put(x, y, OVERFLOW);
        }
    }
    text(&mut put, ">256", xo, top + 17);
    for k in (LOG2_MIN as i32..=LOG2_MAX as i32).filter(|k| k % 2 != 0 || *k == 0) {
        let x = x0 + ((k as f64 - LOG2_MIN) / (LOG2_MAX - LOG2_MIN) * bar as f64) as u32;
        let x = x.min(x0 + bar - 1);
        for y in top + 13..top + 16 {
            put(x, y, [0, 0, 0]);
        }
        let label = if k < 0 {
            format!("1/{}", 1u32 << (-k))
        } else {
            format!("{}", 1u32 << k)
        };
        let label_width = label.len() as u32 * 4 * scale;
        text(
            &mut put,
            &label,
            x.saturating_sub(label_width / 2),
            top + 17,
        );
    }
    out
}

/// p50, p95, p99 and max of `values` over the visible pixels that face the light
/// ([`PixelMetrics::lit_facing`]: N.L > 0.1), as JSON (null when none).
pub fn percentiles(metrics: &PixelMetrics, values: &[f32]) -> Value {
    metrics.percentiles(values).map_or(Value::Null, |p| {
        json!({
            "p50": p.p50,
            "p95": p.p95,
            "p99": p.p99,
            "max": p.max,
            "pixels": p.pixels,
        })
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
        // Above 256 the overflow colour, apart from every value on the scale.
        assert_eq!(color(1e9), OVERFLOW);
        assert_eq!(color(266.0), OVERFLOW);
        assert_ne!(color(255.0), OVERFLOW);
        assert_ne!(color(32.0), color(128.0));
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
            unsure: vec![false; n],
        };
        let p = percentiles(&metrics, &metrics.undersampling);
        assert_eq!(p["pixels"], 100);
        assert_eq!(p["max"], 100.0);
        assert_eq!(p["p50"].as_f64().unwrap().round(), 51.0);
        // The map has the frame's size; too small for the legend, it has none.
        let image = draw(&metrics, 101, 1);
        assert_eq!(image.len(), 101 * 4);
        assert_eq!(&image[..4], &[50, 50, 50, 255], "no geometry is dark grey");
        // Large enough, the legend lies over the bottom strip: white background, the bar.
        let big = PixelMetrics {
            undersampling: vec![1.0; 200 * 100],
            area: vec![1.0; 200 * 100],
            n_dot_l: vec![1.0; 200 * 100],
            unsure: vec![false; 200 * 100],
        };
        let image = draw(&big, 200, 100);
        assert_eq!(image.len(), 200 * 100 * 4);
        let at = |x: usize, y: usize| &image[(y * 200 + x) * 4..(y * 200 + x) * 4 + 3];
        assert_eq!(
            at(100, 10),
            &[245, 245, 245],
            "one texel per pixel above the legend"
        );
        assert_eq!(at(199, 99), &[255, 255, 255], "the legend's background");
    }
}
