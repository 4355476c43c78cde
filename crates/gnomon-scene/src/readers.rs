//! The readers of the formats that come through other crates: OFF (`off-rs`), Wavefront OBJ
//! (`tobj`), PLY (`ply-rs-bw`) and STL (`stl_io`), each behind its own default-on feature.
//! Each returns positions and polygons (or an OBJ's parts by material) for the loader.

#[cfg(feature = "obj")]
use std::path::Path;

#[cfg(feature = "obj")]
use glam::DMat4;
#[cfg(any(feature = "off", feature = "obj", feature = "ply", feature = "stl"))]
use glam::DVec3;

#[cfg(any(feature = "off", feature = "ply", feature = "stl"))]
use crate::format::Polygons;
#[cfg(feature = "obj")]
use crate::format::RawPart;

#[cfg(feature = "off")]
/// The OFF header's vertex and face counts against the lines that follow it, so that a
/// short file says so (the parser reads a face line as a vertex with a colour and reports a
/// colour).
fn check_off_counts(text: &str) -> Result<(), String> {
    let mut lines = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty());
    let Some(first) = lines.next() else {
        return Err("the file is empty".into());
    };
    // The counts are on the keyword's line or the next one.
    let rest = first.trim_start_matches(|c: char| c.is_ascii_alphabetic());
    let counts_line = if rest.trim().is_empty() {
        lines.next().unwrap_or("")
    } else {
        rest
    };
    let counts: Vec<usize> = counts_line
        .split_whitespace()
        .take(2)
        .filter_map(|t| t.parse().ok())
        .collect();
    let [vertices, faces] = counts[..] else {
        return Err(format!(
            "the header's counts '{counts_line}' are not numbers"
        ));
    };
    let found = lines.count();
    if found < vertices + faces {
        return Err(format!(
            "the header declares {vertices} vertices and {faces} faces, but only {found} lines follow it"
        ));
    }
    Ok(())
}

#[cfg(feature = "off")]
pub(crate) fn parse_off(bytes: &[u8]) -> Result<Polygons, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not text: {e}"))?;
    check_off_counts(text)?;
    let options = off_rs::parser::options::Options {
        limits: off_rs::parser::options::Limits::MAX,
        ..Default::default()
    };
    let mesh = off_rs::parse(text, options).map_err(|e| match std::error::Error::source(&e) {
        Some(inner) => format!("{e}: {inner}"),
        None => e.to_string(),
    })?;
    let positions = mesh
        .vertices
        .iter()
        .map(|v| {
            DVec3::new(
                v.position.x as f64,
                v.position.y as f64,
                v.position.z as f64,
            )
        })
        .collect();
    Ok((
        positions,
        index_lists(mesh.faces.iter().map(|f| &f.vertices[..])),
    ))
}

#[cfg(feature = "obj")]
/// An OBJ's triangles, one part per material (in the order the materials first appear),
/// coloured by the material's `Kd` where its library (beside the file, `base`) has it.
pub(crate) fn parse_obj(
    bytes: &[u8],
    base: Option<&Path>,
    notes: &mut Vec<String>,
) -> Result<Vec<RawPart>, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = std::io::BufReader::new(bytes);
    let missing = std::cell::RefCell::new(Vec::new());
    let (models, materials) = tobj::load_obj_buf(&mut reader, &options, |library| match base {
        Some(base) => tobj::load_mtl(base.join(library)).or_else(|_| {
            missing.borrow_mut().push(library.display().to_string());
            Ok((Vec::new(), Default::default()))
        }),
        None => Ok((Vec::new(), Default::default())),
    })
    .map_err(|e| e.to_string())?;
    for library in missing.into_inner() {
        notes.push(format!(
            "material library {library} not found: drawn without its colours"
        ));
    }
    let materials = materials.unwrap_or_default();
    // Parts by material id (None: no material).
    let mut parts: Vec<(Option<usize>, RawPart)> = Vec::new();
    for model in models {
        let id = model.mesh.material_id.filter(|&i| i < materials.len());
        let k = match parts.iter().position(|(m, _)| *m == id) {
            Some(k) => k,
            None => {
                let material = id.map(|i| &materials[i]);
                parts.push((
                    id,
                    RawPart {
                        name: material.map_or(String::new(), |m| m.name.clone()),
                        positions: Vec::new(),
                        polygons: Vec::new(),
                        color: material
                            .and_then(|m| m.diffuse)
                            .filter(|c| c.iter().all(|v| v.is_finite()))
                            .map(|c| c.map(|v| v.clamp(0.0, 1.0))),
                        placements: vec![DMat4::IDENTITY],
                        uvs: Vec::new(),
                        cutout: None,
                    },
                ));
                parts.len() - 1
            }
        };
        let part = &mut parts[k].1;
        let base = part.positions.len() as i64;
        part.positions.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)),
        );
        part.polygons.extend(
            model
                .mesh
                .indices
                .chunks_exact(3)
                .map(|t| t.iter().map(|&i| base + i as i64).collect()),
        );
    }
    Ok(parts.into_iter().map(|(_, p)| p).collect())
}

#[cfg(feature = "ply")]
pub(crate) fn parse_ply(bytes: &[u8]) -> Result<Polygons, String> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut reader = std::io::BufReader::new(bytes);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        .map_err(|e| e.to_string())?;
    let scalar = |p: &Property| -> Option<f64> {
        Some(match *p {
            Property::Char(v) => v as f64,
            Property::UChar(v) => v as f64,
            Property::Short(v) => v as f64,
            Property::UShort(v) => v as f64,
            Property::Int(v) => v as f64,
            Property::UInt(v) => v as f64,
            Property::Float(v) => v as f64,
            Property::Double(v) => v,
            _ => return None,
        })
    };
    let list = |p: &Property| -> Option<Vec<i64>> {
        Some(match p {
            Property::ListChar(v) => v.iter().map(|&i| i as i64).collect(),
            Property::ListUChar(v) => v.iter().map(|&i| i as i64).collect(),
            Property::ListShort(v) => v.iter().map(|&i| i as i64).collect(),
            Property::ListUShort(v) => v.iter().map(|&i| i as i64).collect(),
            Property::ListInt(v) => v.iter().map(|&i| i as i64).collect(),
            Property::ListUInt(v) => v.iter().map(|&i| i as i64).collect(),
            _ => return None,
        })
    };
    let vertices = ply.payload.get("vertex").ok_or("no 'vertex' element")?;
    let mut positions = Vec::with_capacity(vertices.len());
    for (k, v) in vertices.iter().enumerate() {
        let coordinate = |name: &str| {
            v.get(name)
                .and_then(scalar)
                .ok_or_else(|| format!("vertex {k} has no numeric '{name}'"))
        };
        positions.push(DVec3::new(
            coordinate("x")?,
            coordinate("y")?,
            coordinate("z")?,
        ));
    }
    let mut faces = Vec::new();
    for (k, f) in ply.payload.get("face").into_iter().flatten().enumerate() {
        let indices = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| format!("face {k} has no integer list 'vertex_indices'"))?;
        faces.push(indices);
    }
    Ok((positions, faces))
}

#[cfg(any(feature = "off", feature = "stl"))]
/// Faces' vertex indices as the polygons [`crate::Mesh::from_polygons`] takes.
fn index_lists<'a>(faces: impl Iterator<Item = &'a [usize]>) -> Vec<Vec<i64>> {
    faces
        .map(|f| f.iter().map(|&i| i as i64).collect())
        .collect()
}

#[cfg(feature = "stl")]
pub(crate) fn parse_stl(bytes: &[u8]) -> Result<Polygons, String> {
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let positions = mesh
        .vertices
        .iter()
        .map(|v| DVec3::new(v[0].into(), v[1].into(), v[2].into()))
        .collect();
    Ok((
        positions,
        index_lists(mesh.faces.iter().map(|f| &f.vertices[..])),
    ))
}
