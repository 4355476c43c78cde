use gnomon::{Camera, ShadowMap};

/// The largest side of a light-view picture: larger maps are shown at this size.
pub(crate) const MAX_LIGHT_VIEW: u32 = 2048;

/// Draws the camera's view frustum in red over a map's light-view picture (`rgba`, `size`
/// square, from the light-view pass: near dark, far light), as in the second row of the
/// LiSPSM paper's Figure 9. The lines are three pixels wide so that they show in thumbnails.
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
