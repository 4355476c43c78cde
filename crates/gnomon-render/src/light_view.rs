use gnomon::{Camera, ShadowMap};

/// The shadow map as the light sees it (near = dark, far = light) with the camera's view
/// frustum drawn over it in red, as in the second row of the LiSPSM paper's Figure 9.
pub(crate) fn draw(
    depth_bytes: &[u8],
    resolution: u32,
    camera: &Camera,
    map: &ShadowMap,
) -> Vec<u8> {
    let n = resolution as usize;
    let mut rgba = vec![0u8; n * n * 4];
    for (i, texel) in depth_bytes.chunks_exact(4).enumerate() {
        let d = f32::from_le_bytes([texel[0], texel[1], texel[2], texel[3]]).clamp(0.0, 1.0);
        let v = (40.0 + 215.0 * d) as u8;
        rgba[i * 4..i * 4 + 4].copy_from_slice(&[v, v, v, 255]);
    }
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
    for (a, b) in edges {
        // Draw the edge in small steps so that it bends correctly under a perspective map.
        let steps = 256;
        let mut previous: Option<(f64, f64)> = None;
        for s in 0..=steps {
            let p = corners[a].lerp(corners[b], s as f64 / steps as f64);
            let texel = map.project(p).map(|ndc| {
                (
                    (0.5 + 0.5 * ndc.x) * resolution as f64,
                    (0.5 - 0.5 * ndc.y) * resolution as f64,
                )
            });
            if let (Some(p0), Some(p1)) = (previous, texel) {
                line(&mut rgba, n, p0, p1);
            }
            previous = texel;
        }
    }
    rgba
}

fn line(rgba: &mut [u8], n: usize, (x0, y0): (f64, f64), (x1, y1): (f64, f64)) {
    let steps = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as usize).clamp(1, 4 * n);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
        if x >= 0.0 && y >= 0.0 && (x as usize) < n && (y as usize) < n {
            let i = (y as usize * n + x as usize) * 4;
            rgba[i..i + 4].copy_from_slice(&[230, 40, 30, 255]);
        }
    }
}
