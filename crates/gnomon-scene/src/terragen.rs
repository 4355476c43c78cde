//! Terragen heightfields (`.ter`): a grid of 16-bit heights as a triangle mesh, y up.
//!
//! The file: `TERRAGEN` `TERRAIN ` then chunks, each a 4-byte tag and its data (little
//! endian): `SIZE` (i16: points on the shorter side minus one, then 2 bytes of padding),
//! `XPTS` and `YPTS` (i16 each and padding; both default to SIZE + 1), `SCAL` (three f32:
//! metres per terrain unit along x, y and height; default 30), `CRAD` (f32), `CRVM` (u32 and
//! its padding), `ALTW` (i16 HeightScale, i16 BaseHeight, then XPTS * YPTS i16 heights, x
//! fastest) and `EOF `. A point's elevation in terrain units is
//! BaseHeight + h * HeightScale / 65536.
//!
//! The mesh: point (i, j) at (i * scal_x, elevation * scal_z, j * scal_y) in metres (the
//! terrain's y axis becomes the world's z), two triangles per grid cell, counter-clockwise
//! seen from above.

use glam::DVec3;

use crate::format::Polygons;

/// The most grid points a heightfield may have (8193 x 8193).
const MAX_POINTS: usize = 8193 * 8193;

fn i16_at(bytes: &[u8], at: usize) -> Option<i16> {
    bytes
        .get(at..at + 2)
        .map(|b| i16::from_le_bytes([b[0], b[1]]))
}

fn f32_at(bytes: &[u8], at: usize) -> Option<f32> {
    bytes
        .get(at..at + 4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The heightfield's grid as positions and quads (see the module documentation).
pub(crate) fn parse_ter(bytes: &[u8]) -> Result<Polygons, String> {
    if bytes.len() < 16 || &bytes[..16] != b"TERRAGENTERRAIN " {
        return Err("it does not start with TERRAGENTERRAIN".into());
    }
    let short = || "the file ends inside a chunk".to_string();
    let (mut size, mut xpts, mut ypts) = (None, None, None);
    let mut scale = [30.0f64; 3];
    let mut at = 16;
    loop {
        let tag = bytes.get(at..at + 4).ok_or("the file ends before ALTW")?;
        at += 4;
        match tag {
            b"SIZE" => size = Some(i16_at(bytes, at).ok_or_else(short)?),
            b"XPTS" => xpts = Some(i16_at(bytes, at).ok_or_else(short)?),
            b"YPTS" => ypts = Some(i16_at(bytes, at).ok_or_else(short)?),
            b"SCAL" => {
                for (k, s) in scale.iter_mut().enumerate() {
                    *s = f64::from(f32_at(bytes, at + 4 * k).ok_or_else(short)?);
                }
            }
            b"CRAD" | b"CRVM" => {}
            b"ALTW" => break,
            b"EOF " => return Err("no ALTW (heights) chunk".into()),
            other => {
                return Err(format!(
                    "unknown chunk '{}'",
                    String::from_utf8_lossy(other)
                ));
            }
        }
        at += match tag {
            b"SCAL" => 12,
            _ => 4,
        };
    }
    if !scale.iter().all(|s| s.is_finite() && *s > 0.0) {
        return Err(format!("SCAL {scale:?} is not three positive numbers"));
    }
    let size = size.ok_or("no SIZE chunk before ALTW")?;
    let points = |n: Option<i16>| -> Result<usize, String> {
        let n = i32::from(n.unwrap_or(size.saturating_add(1)));
        if n < 2 {
            return Err(format!("a grid of {n} points on a side has no cells"));
        }
        Ok(n as usize)
    };
    let (nx, ny) = (points(xpts)?, points(ypts)?);
    if nx * ny > MAX_POINTS {
        return Err(format!("a {nx} x {ny} grid is larger than gnomon reads"));
    }
    let height_scale = f64::from(i16_at(bytes, at).ok_or_else(short)?);
    let base_height = f64::from(i16_at(bytes, at + 2).ok_or_else(short)?);
    at += 4;
    if bytes.len() < at + 2 * nx * ny {
        return Err(format!(
            "ALTW holds fewer than the {nx} x {ny} heights of the grid"
        ));
    }
    let mut positions = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let h = f64::from(i16_at(bytes, at + 2 * (j * nx + i)).ok_or_else(short)?);
            let elevation = base_height + h * height_scale / 65536.0;
            positions.push(DVec3::new(
                i as f64 * scale[0],
                elevation * scale[2],
                j as f64 * scale[1],
            ));
        }
    }
    let index = |i: usize, j: usize| (j * nx + i) as i64;
    let mut quads = Vec::with_capacity((nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            quads.push(vec![
                index(i, j),
                index(i, j + 1),
                index(i + 1, j + 1),
                index(i + 1, j),
            ]);
        }
    }
    Ok((positions, quads))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::{Mesh, MeshFormat};

    /// A 3 x 2 heightfield (XPTS 3, YPTS 2), 10 m per unit, heights 0..5 times 4096 with
    /// HeightScale 16 and BaseHeight 1: elevations 1 + h / 4096 units.
    pub(crate) fn small_ter() -> Vec<u8> {
        let mut b = b"TERRAGENTERRAIN ".to_vec();
        let tag = |b: &mut Vec<u8>, t: &[u8]| b.extend_from_slice(t);
        tag(&mut b, b"SIZE");
        b.extend_from_slice(&1i16.to_le_bytes());
        b.extend_from_slice(&[0, 0]);
        tag(&mut b, b"XPTS");
        b.extend_from_slice(&3i16.to_le_bytes());
        b.extend_from_slice(&[0, 0]);
        tag(&mut b, b"YPTS");
        b.extend_from_slice(&2i16.to_le_bytes());
        b.extend_from_slice(&[0, 0]);
        tag(&mut b, b"SCAL");
        for _ in 0..3 {
            b.extend_from_slice(&10.0f32.to_le_bytes());
        }
        tag(&mut b, b"CRAD");
        b.extend_from_slice(&6370.0f32.to_le_bytes());
        tag(&mut b, b"ALTW");
        b.extend_from_slice(&16i16.to_le_bytes());
        b.extend_from_slice(&1i16.to_le_bytes());
        for h in 0..6i16 {
            b.extend_from_slice(&(h * 4096).to_le_bytes());
        }
        tag(&mut b, b"EOF ");
        b
    }

    #[test]
    fn a_heightfield_is_a_grid_of_upward_triangles() {
        let m = Mesh::parse(&small_ter(), MeshFormat::Ter).unwrap();
        assert_eq!(m.triangle_count(), 2 * 2);
        // Point (i, j) = (2, 1) is height 5: elevation 1 + 5 * 4096 * 16 / 65536 = 6 units.
        let top = m
            .positions
            .iter()
            .copied()
            .fold(DVec3::NEG_INFINITY, DVec3::max);
        assert_eq!(top, DVec3::new(20.0, 60.0, 10.0));
        let (lo, _) = m.bounds();
        assert_eq!(lo, DVec3::new(0.0, 10.0, 0.0));
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0, "a triangle faces down");
        }
    }

    #[test]
    fn broken_heightfields_are_refused() {
        let good = small_ter();
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (b"TERRAGEN".to_vec(), "TERRAGENTERRAIN"),
            (good[..good.len() - 10].to_vec(), "fewer than"),
            (good[..40].to_vec(), "ends"),
            (
                [&good[..16], b"WHAT", &good[20..]].concat(),
                "unknown chunk 'WHAT'",
            ),
        ];
        for (bytes, says) in cases {
            let e = Mesh::parse(&bytes, MeshFormat::Ter)
                .unwrap_err()
                .to_string();
            assert!(e.contains(says), "{e}");
        }
    }
}
