use gnomon::{Camera, ShadowMap};

/// The largest side of a light-view picture: larger maps are shown at this size.
pub(crate) const MAX_LIGHT_VIEW: u32 = 2048;

/// Draws the camera's view frustum in red over a map's light-view picture (`rgba`, `size`
/// square, from the light-view pass: near dark, far light), as in the second row of the
/// LiSPSM paper's Figure 9. The lines widen with the picture (one pixel below 1024, three
/// from 1024, five from 2048) so that they show in thumbnails.
pub(crate) fn draw_frustum(rgba: &mut [u8], size: u32, camera: &Camera, map: &ShadowMap) {
    let n = size as usize;
    let corners = camera.frustum_corners();
    let edges = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let width = (size / 512).max(1) as i64;
    for (a, b) in edges {
        // Draw the edge in small steps so that it bends correctly under a perspective map.
        let steps = 256;
        let mut previous: Option<(f64, f64)> = None;
        for s in 0..=steps {
            let p = corners[a].lerp(corners[b], s as f64 / steps as f64);
            let texel = map.project(p).map(|ndc| {
                (
                    (0.5 + 0.5 * ndc.x) * size as f64,
                    (0.5 - 0.5 * ndc.y) * size as f64,
                )
            });
            if let (Some(p0), Some(p1)) = (previous, texel) {
                line(rgba, n, p0, p1, width);
            }
            previous = texel;
        }
    }
}

fn line(rgba: &mut [u8], n: usize, (x0, y0): (f64, f64), (x1, y1): (f64, f64), width: i64) {
    let steps = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as usize).clamp(1, 4 * n);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
        for dy in -(width / 2)..=width / 2 {
            for dx in -(width / 2)..=width / 2 {
                let (px, py) = (x.floor() as i64 + dx, y.floor() as i64 + dy);
                if px >= 0 && py >= 0 && (px as usize) < n && (py as usize) < n {
                    let i = (py as usize * n + px as usize) * 4;
                    rgba[i..i + 4].copy_from_slice(&[230, 40, 30, 255]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, DVec3, DVec4};
    use gnomon::{Lens, MapProjection};

    /// The frustum's lines are several pixels wide on a large picture, so that they show in
    /// the gallery's thumbnails (one pixel on 2048 did not).
    #[test]
    fn frustum_lines_are_wide_enough_to_see_in_a_thumbnail() {
        let size = 2048;
        let camera = Camera::look_at(
            DVec3::new(0.0, 10.0, 30.0),
            DVec3::ZERO,
            DVec3::Y,
            Lens {
                far: 60.0,
                ..Lens::default()
            },
        )
        .unwrap();
        // A map looking straight down over a 200 m square.
        let clip_from_world = DMat4::from_cols(
            DVec4::new(0.01, 0.0, 0.0, 0.0),
            DVec4::new(0.0, 0.0, 0.001, 0.0),
            DVec4::new(0.0, -0.01, 0.0, 0.0),
            DVec4::new(0.0, 0.0, 0.5, 1.0),
        );
        let map = ShadowMap {
            clip_from_world,
            depth_from_world: DVec4::new(0.0, 0.001, 0.0, 0.5),
            resolution: size,
            viewport_inset: 1,
            projection: MapProjection::Orthographic,
            view_depth_range: None,
        };
        let mut rgba = vec![255u8; (size * size * 4) as usize];
        draw_frustum(&mut rgba, size, &camera, &map);
        let red = |x: usize, y: usize| rgba[(y * size as usize + x) * 4 + 1] == 40;
        // Along every row, red runs are at least 4 pixels long where a line crosses it.
        let mut runs = Vec::new();
        for y in (0..size as usize).step_by(64) {
            let mut run = 0;
            for x in 0..size as usize {
                if red(x, y) {
                    run += 1;
                } else if run > 0 {
                    runs.push(run);
                    run = 0;
                }
            }
        }
        assert!(!runs.is_empty(), "no line crosses the sampled rows");
        assert!(runs.iter().all(|&r| r >= 4), "runs {runs:?}");
    }
}
