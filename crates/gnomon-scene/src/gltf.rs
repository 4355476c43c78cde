//! glTF 2.0 triangles in the scene's world frame (see [`crate::load`]'s documentation).

use std::path::{Path, PathBuf};

use std::sync::Arc;

use glam::{DMat4, DVec2, DVec3};
use gltf::mesh::Mode;

use crate::format::{LoadError, MeshFormat, RawPart};
use crate::mesh::{Cutout, Wrap};

/// Every triangle of the default scene (else the first, else every root node) of a glTF
/// document in `bytes`: one part per material of each mesh (coloured by its base colour
/// factor), in the mesh's frame, placed at every node that uses the mesh (the node
/// hierarchy's transforms composed; a mesh several nodes share is read once); primitives
/// that are not triangle lists are skipped and named in `notes`, as are alpha-masked
/// materials whose constant alpha is below their cutoff (never drawn). An alpha-masked
/// material with a base colour texture becomes a [`Cutout`] of its part: the texture's alpha
/// times the factor's, read at the primitive's texture coordinates.
/// `base`: the folder buffer files are relative to (`None`: only buffers inside the file).
pub(crate) fn parts(
    bytes: &[u8],
    base: Option<&Path>,
    notes: &mut Vec<String>,
) -> Result<Vec<RawPart>, LoadError> {
    let parse_error = |message: String| LoadError::Parse {
        path: PathBuf::new(),
        format: MeshFormat::Gltf,
        message,
    };
    // A required extension is refused before the crate's own validation, which reports it
    // less plainly.
    if let Some(extension) = required_extensions(bytes).into_iter().next() {
        return Err(LoadError::UnsupportedExtension {
            path: PathBuf::new(),
            extension,
        });
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice(bytes).map_err(|e| parse_error(e.to_string()))?;
    let buffers = match base {
        Some(base) => gltf::import_buffers(&document, Some(base), blob),
        None if document.buffers().all(
            |b| !matches!(b.source(), gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:")),
        ) =>
        {
            gltf::import_buffers(&document, None, blob)
        }
        None => Err(gltf::Error::UnsupportedScheme),
    }
    .map_err(|e| parse_error(format!("cannot read its buffers: {e}")))?;

    let mut out = Collector {
        visited: vec![false; document.nodes().len()],
        buffers: &buffers,
        base,
        cutouts: std::collections::HashMap::new(),
        parts: Vec::new(),
        mesh_parts: std::collections::HashMap::new(),
        notes,
        error: None,
    };
    let roots: Vec<gltf::Node> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        // No scene: every node that is no other node's child.
        None => {
            let children: std::collections::HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    for node in roots {
        out.node(&node, DMat4::IDENTITY, 0);
    }
    if let Some(message) = out.error {
        return Err(parse_error(message));
    }
    if document
        .materials()
        .any(|m| m.pbr_metallic_roughness().base_color_texture().is_some())
    {
        out.notes.push(
            "base colour textures are not drawn (parts take their material's base colour factor); an alpha-masked material's texture gives its holes"
                .into(),
        );
    }
    let holes = out.cutouts.values().filter(|c| c.is_some()).count();
    if holes > 0 {
        out.notes.push(format!(
            "{holes} alpha-masked material(s) cut holes in the shadow maps and the camera's view; exact volumes and planar shadows draw them whole"
        ));
    }
    if document
        .materials()
        .any(|m| m.alpha_mode() == gltf::material::AlphaMode::Blend)
    {
        out.notes
            .push("blended (transparent) materials are drawn opaque and cast shadows".into());
    }
    Ok(out.parts.into_iter().map(|(_, p)| p).collect())
}

/// The names in the document's `extensionsRequired` (JSON or GLB); empty when there are none
/// or the file does not parse (the parser then says why).
fn required_extensions(bytes: &[u8]) -> Vec<String> {
    let json: &[u8] = match gltf::Glb::from_slice(bytes) {
        Ok(glb) => return json_required(&glb.json),
        Err(_) => bytes,
    };
    json_required(json)
}

fn json_required(json: &[u8]) -> Vec<String> {
    let Ok(root) = gltf::json::deserialize::from_slice::<gltf::json::Root>(json) else {
        return Vec::new();
    };
    root.extensions_required
}

/// Nodes deeper than this are refused (a cycle, or a file built to exhaust the stack).
const MAX_DEPTH: usize = 256;

struct Collector<'a> {
    /// The nodes met so far: glTF's nodes form trees, so a node met twice is a cycle or a
    /// shared child, refused (either could multiply the work without bound).
    visited: Vec<bool>,
    buffers: &'a [gltf::buffer::Data],
    /// The folder image files are relative to.
    base: Option<&'a Path>,
    /// Each alpha-masked material's cutout, once read (`None`: it has no holes, or its
    /// texture could not be read).
    cutouts: std::collections::HashMap<usize, Option<Arc<Cutout>>>,
    /// The parts by (mesh, material index; `None`: the default material), in order of
    /// appearance.
    parts: Vec<((usize, Option<usize>), RawPart)>,
    /// The parts each mesh read so far made (a mesh met again is only placed again).
    mesh_parts: std::collections::HashMap<usize, Vec<usize>>,
    notes: &'a mut Vec<String>,
    error: Option<String>,
}

impl Collector<'_> {
    fn node(&mut self, node: &gltf::Node, parent: DMat4, depth: usize) {
        if self.error.is_some() {
            return;
        }
        if depth > MAX_DEPTH {
            self.error = Some(format!("its node hierarchy is deeper than {MAX_DEPTH}"));
            return;
        }
        match self.visited.get_mut(node.index()) {
            Some(seen) if !*seen => *seen = true,
            _ => {
                self.error = Some(format!(
                    "node {} is reached twice (nodes must form trees: a cycle or a shared child)",
                    node.index()
                ));
                return;
            }
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            if !self.mesh_parts.contains_key(&mesh.index()) {
                let first = self.parts.len();
                for primitive in mesh.primitives() {
                    self.primitive(&mesh, &primitive);
                }
                // The parts this mesh made are the new ones: a part's key holds its mesh.
                let made = (first..self.parts.len()).collect();
                self.mesh_parts.insert(mesh.index(), made);
            }
            for &k in &self.mesh_parts[&mesh.index()] {
                self.parts[k].1.placements.push(world);
            }
        }
        for child in node.children() {
            self.node(&child, world, depth + 1);
        }
    }

    /// Reads a triangle primitive of `mesh` into its material's part, in the mesh's frame.
    fn primitive(&mut self, mesh: &gltf::Mesh, primitive: &gltf::Primitive) {
        let name = || format!("mesh {}", mesh.index());
        if primitive.mode() != Mode::Triangles {
            self.notes.push(format!(
                "skipped a {:?} primitive of {} (only triangle lists are read)",
                primitive.mode(),
                name()
            ));
            return;
        }
        let material = primitive.material();
        if fully_cut(&material) {
            self.notes.push(format!(
                "skipped a primitive of {}: its material's alpha is below its cutoff",
                name()
            ));
            return;
        }
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let Some(positions) = reader.read_positions() else {
            self.notes.push(format!(
                "skipped a primitive of {} without positions",
                name()
            ));
            return;
        };
        let cutout = self.cutout(&material);
        let uvs = match &cutout {
            Some(_) => self.cutout_uvs(&reader, &material, &name()),
            None => Vec::new(),
        };
        let k = self.part_of(mesh, &material, &cutout);
        let part = &mut self.parts[k].1;
        let start = part.positions.len() as i64;
        part.positions
            .extend(positions.map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into())));
        let count = part.positions.len() as i64 - start;
        if part.cutout.is_some() {
            if uvs.len() as i64 == count {
                part.uvs.extend(uvs);
            } else {
                // One primitive without texture coordinates: the part is drawn whole.
                part.cutout = None;
            }
        }
        let indices: Vec<i64> = match reader.read_indices() {
            Some(indices) => indices.into_u32().map(i64::from).collect(),
            None => (0..count).collect(),
        };
        if !indices.len().is_multiple_of(3) {
            self.error = Some(format!(
                "a triangle primitive of {} has {} indices, not a multiple of three",
                name(),
                indices.len()
            ));
            return;
        }
        for t in indices.chunks_exact(3) {
            if let Some(&bad) = t.iter().find(|&&i| i >= count) {
                self.error = Some(format!(
                    "a triangle of {} uses vertex {bad}, but the primitive has {count}",
                    name()
                ));
                return;
            }
            let (a, b, c) = (start + t[0], start + t[1], start + t[2]);
            self.parts[k].1.polygons.push(vec![a, b, c]);
        }
    }
}

/// Whether an alpha-masked material is cut entirely by its constant alpha: never drawn (its
/// texture's alpha, if any, is not read: drawn opaque otherwise).
fn fully_cut(material: &gltf::Material) -> bool {
    let pbr = material.pbr_metallic_roughness();
    material.alpha_mode() == gltf::material::AlphaMode::Mask
        && pbr.base_color_texture().is_none()
        && pbr.base_color_factor()[3] < material.alpha_cutoff().unwrap_or(0.5)
}

impl Collector<'_> {
    /// The texture coordinates a material's cutout reads (none, named in the notes, where the
    /// primitive has none: it is drawn without its holes).
    fn cutout_uvs<'a, 's, F>(
        &mut self,
        reader: &gltf::mesh::Reader<'a, 's, F>,
        material: &gltf::Material,
        name: &str,
    ) -> Vec<DVec2>
    where
        F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
    {
        let set = material
            .pbr_metallic_roughness()
            .base_color_texture()
            .map_or(0, |t| t.tex_coord());
        match reader.read_tex_coords(set) {
            Some(uvs) => uvs
                .into_f32()
                .map(|[u, v]| DVec2::new(u.into(), v.into()))
                .collect(),
            None => {
                self.notes.push(format!(
                    "a primitive of {name} has no texture coordinates {set}: drawn without its material's holes"
                ));
                Vec::new()
            }
        }
    }

    /// The part of a mesh's primitives of one material: made on its first primitive.
    fn part_of(
        &mut self,
        mesh: &gltf::Mesh,
        material: &gltf::Material,
        cutout: &Option<Arc<Cutout>>,
    ) -> usize {
        let key = (mesh.index(), material.index());
        if let Some(k) = self.parts.iter().position(|(m, _)| *m == key) {
            return k;
        }
        let [r, g, b, _] = material.pbr_metallic_roughness().base_color_factor();
        let mesh_name = format!("mesh {}", mesh.index());
        self.parts.push((
            key,
            RawPart {
                name: match key.1 {
                    Some(i) => format!("{mesh_name} material {i}"),
                    None => mesh_name,
                },
                positions: Vec::new(),
                polygons: Vec::new(),
                // The default material (no material given) is white.
                color: key.1.map(|_| [r, g, b].map(|v| v.clamp(0.0, 1.0))),
                placements: Vec::new(),
                uvs: Vec::new(),
                cutout: cutout.clone(),
            },
        ));
        self.parts.len() - 1
    }

    /// The cutout of an alpha-masked material with a base colour texture (read once per
    /// material); `None` for other materials, a texture without holes, or one that cannot be
    /// read (named in the notes: the part is drawn whole).
    fn cutout(&mut self, material: &gltf::Material) -> Option<Arc<Cutout>> {
        let index = material.index()?;
        if material.alpha_mode() != gltf::material::AlphaMode::Mask {
            return None;
        }
        let info = material.pbr_metallic_roughness().base_color_texture()?;
        if let Some(known) = self.cutouts.get(&index) {
            return known.clone();
        }
        let texture = info.texture();
        let factor = material.pbr_metallic_roughness().base_color_factor()[3];
        let cutout = match gltf::image::Data::from_source(
            texture.source().source(),
            self.base,
            self.buffers,
        ) {
            Ok(image) => {
                let sampler = texture.sampler();
                let wrap = |mode: gltf::texture::WrappingMode| match mode {
                    gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
                    gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
                    gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
                };
                let cutout = Cutout {
                    width: image.width,
                    height: image.height,
                    alpha: texel_alpha(&image)
                        .map(|a| (f32::from(a) * factor.clamp(0.0, 1.0)).round() as u8)
                        .collect(),
                    cutoff: material.alpha_cutoff().unwrap_or(0.5),
                    wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
                };
                (cutout.alpha.len() == (image.width * image.height) as usize
                    && cutout.width > 0
                    && cutout.height > 0
                    && cutout.has_holes())
                .then(|| Arc::new(cutout))
            }
            Err(e) => {
                self.notes.push(format!(
                    "cannot read the texture of alpha-masked material {index} ({e}): drawn without its holes"
                ));
                None
            }
        };
        self.cutouts.insert(index, cutout.clone());
        cutout
    }
}

/// Each texel's alpha (0 to 255) of a decoded glTF image: 255 where it has no alpha channel.
fn texel_alpha(image: &gltf::image::Data) -> Box<dyn Iterator<Item = u8> + '_> {
    use gltf::image::Format;
    let p = &image.pixels;
    match image.format {
        Format::R8G8B8A8 => Box::new(p.chunks_exact(4).map(|t| t[3])),
        Format::R16G16B16A16 => Box::new(p.chunks_exact(8).map(|t| t[7])),
        Format::R32G32B32A32FLOAT => Box::new(p.chunks_exact(16).map(|t| {
            let a = f32::from_le_bytes([t[12], t[13], t[14], t[15]]);
            (a.clamp(0.0, 1.0) * 255.0).round() as u8
        })),
        _ => Box::new(std::iter::repeat_n(
            255,
            (image.width * image.height) as usize,
        )),
    }
}

#[cfg(test)]
mod tests {
    use crate::Mesh;
    use crate::Wrap;
    use crate::format::{LoadError, MeshFormat};
    use crate::load::tests::{CUBE_OFF, volume};
    use glam::{DVec2, DVec3};

    /// A unit cube's buffer (the OFF tests' cube): 8 f32 positions, then 36 u32 indices
    /// (counter-clockwise from outside).
    fn cube_buffer() -> Vec<u8> {
        let (positions, faces) = crate::readers::parse_off(CUBE_OFF.as_bytes()).unwrap();
        let mut out = Vec::new();
        for p in &positions {
            for x in p.to_array() {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        for quad in &faces {
            for i in [0, 1, 2, 0, 2, 3] {
                out.extend_from_slice(&(quad[i] as u32).to_le_bytes());
            }
        }
        out
    }

    fn base64(bytes: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let b = [
                chunk[0],
                *chunk.get(1).unwrap_or(&0),
                *chunk.get(2).unwrap_or(&0),
            ];
            let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
            for k in 0..4 {
                if k <= chunk.len() {
                    out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    /// A document: the cube instanced by two nodes under a parent scaled by 2, one of them
    /// mirrored (scale -1 along x); `buffer` the buffer's JSON (uri or none), `extra` more
    /// top-level members.
    fn document(buffer: &str, extra: &str) -> String {
        format!(
            r#"{{"asset": {{"version": "2.0"}},
            "buffers": [{buffer}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 96}},
                            {{"buffer": 0, "byteOffset": 96, "byteLength": 144}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                            "min": [0, 0, 0], "max": [1, 1, 1]}},
                          {{"bufferView": 1, "componentType": 5125, "count": 36, "type": "SCALAR"}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}},
                                        {{"attributes": {{"POSITION": 0}}, "mode": 1}}]}}],
            "nodes": [{{"mesh": 0, "translation": [10, 0, 0]}},
                      {{"mesh": 0, "translation": [-10, 0, 0], "scale": [-1, 1, 1]}},
                      {{"children": [0, 1], "scale": [2, 2, 2]}}],
            "scenes": [{{"nodes": [2]}}], "scene": 0{extra}}}"#
        )
    }

    fn embedded(extra: &str) -> String {
        let buffer = cube_buffer();
        document(
            &format!(
                r#"{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}"#,
                buffer.len(),
                base64(&buffer)
            ),
            extra,
        )
    }

    fn glb() -> Vec<u8> {
        let buffer = cube_buffer();
        let mut json = document(&format!(r#"{{"byteLength": {}}}"#, buffer.len()), "").into_bytes();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = buffer;
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    fn check_two_cubes(m: &Mesh) {
        assert_eq!(m.triangle_count(), 24);
        // Each cube is scaled by 2 (volume 8); the mirrored one is wound outward too.
        assert!((volume(m) - 16.0).abs() < 1e-9, "volume {}", volume(m));
        let (lo, hi) = m.bounds();
        assert!((lo - DVec3::new(-22.0, 0.0, 0.0)).length() < 1e-9, "{lo}");
        assert!((hi - DVec3::new(22.0, 2.0, 2.0)).length() < 1e-9, "{hi}");
    }

    /// The cube (an embedded buffer) under the nodes `nodes`, the scene's roots `roots`.
    fn cube_document(nodes: &str, roots: &str) -> String {
        let buffer = cube_buffer();
        format!(
            r#"{{"asset": {{"version": "2.0"}},
            "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 96}},
                            {{"buffer": 0, "byteOffset": 96, "byteLength": 144}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                            "min": [0, 0, 0], "max": [1, 1, 1]}},
                          {{"bufferView": 1, "componentType": 5125, "count": 36, "type": "SCALAR"}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
            "nodes": [{nodes}], "scenes": [{{"nodes": [{roots}]}}], "scene": 0}}"#,
            buffer.len(),
            base64(&buffer)
        )
    }

    #[test]
    fn the_cube_reads_as_the_off_files_cube() {
        let gltf = Mesh::parse(
            cube_document(r#"{"mesh": 0}"#, "0").as_bytes(),
            MeshFormat::Gltf,
        )
        .unwrap();
        let off = Mesh::parse(CUBE_OFF.as_bytes(), MeshFormat::Off).unwrap();
        assert_eq!(
            crate::load::tests::sorted_triangles(&gltf),
            crate::load::tests::sorted_triangles(&off)
        );
    }

    /// A rotated node inside a moved and scaled one: the cube's corners land where the
    /// transforms, composed by hand, put them.
    #[test]
    fn a_nested_rotated_scaled_node_lands_where_computed_by_hand() {
        // Child: 90 degrees about y (x goes to -z), then moved by (0, 0, 1); parent: scaled by
        // 2, then moved by (1, 2, 3).
        let doc = cube_document(
            r#"{"children": [1], "translation": [1, 2, 3], "scale": [2, 2, 2]},
               {"mesh": 0, "rotation": [0, 0.70710678, 0, 0.70710678], "translation": [0, 0, 1]}"#,
            "0",
        );
        let m = Mesh::parse(doc.as_bytes(), MeshFormat::Gltf).unwrap();
        for (corner, expected) in [
            (DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 2.0, 3.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 2.0, 5.0)),
            (DVec3::new(1.0, 1.0, 1.0), DVec3::new(3.0, 4.0, 3.0)),
        ] {
            assert!(
                m.positions.iter().any(|p| (*p - expected).length() < 1e-6),
                "corner {corner} should land at {expected}"
            );
        }
        let (lo, hi) = m.bounds();
        assert!((lo - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-6, "{lo}");
        assert!((hi - DVec3::new(3.0, 4.0, 5.0)).length() < 1e-6, "{hi}");
        // Rotation keeps the winding: outward, volume 2^3.
        assert!((volume(&m) - 8.0).abs() < 1e-5, "volume {}", volume(&m));
    }

    /// The two cubes, each node's mesh its own material: `second` is the second material.
    fn with_materials(second: &str) -> Vec<crate::MeshPart> {
        let doc = embedded(&format!(
            r#", "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [1, 0.5, 0, 1]}}}}, {second}]"#
        ));
        let (start, end) = (
            doc.find("\"meshes\"").unwrap(),
            doc.find("\"nodes\"").unwrap(),
        );
        let doc = format!(
            r#"{}"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0}}]}},
                          {{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 1}}]}}],
            {}"#,
            &doc[..start],
            &doc[end..]
        )
        .replacen(r#""mesh": 0, "translation": [-10"#, r#""mesh": 1, "translation": [-10"#, 1);
        let (parts, notes) = Mesh::parse_parts(doc.as_bytes(), MeshFormat::Gltf, None).unwrap();
        assert!(notes.len() <= 1, "{notes:?}");
        parts
    }

    #[test]
    fn materials_make_parts_with_their_base_colour() {
        let parts =
            with_materials(r#"{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1]}}"#);
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].color, Some([1.0, 0.5, 0.0]));
        assert_eq!(parts[1].color, Some([0.0, 0.0, 1.0]));
        assert!(parts.iter().all(|p| p.mesh.triangle_count() == 12));
        // The first cube stands at x = 20 (scaled by 2 after its move), the mirrored one at -20.
        let (a, b) = (parts[0].flattened(), parts[1].flattened());
        assert!(a.bounds().0.x > 19.0 && b.bounds().1.x < -19.0);
        // An alpha-masked material whose alpha is below its cutoff is never drawn.
        let masked = with_materials(
            r#"{"alphaMode": "MASK", "alphaCutoff": 0.5, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 0.2]}}"#,
        );
        assert_eq!(masked.len(), 1);
        assert_eq!(masked[0].color, Some([1.0, 0.5, 0.0]));
    }

    #[test]
    fn nodes_are_flattened_in_the_world_frame_with_mirrors_rewound() {
        check_two_cubes(&Mesh::parse(embedded("").as_bytes(), MeshFormat::Gltf).unwrap());
        check_two_cubes(&Mesh::parse(&glb(), MeshFormat::Gltf).unwrap());
        // A .gltf beside its .bin, through the file loader; the line primitive is named.
        let dir = std::env::temp_dir().join(format!("gnomon-gltf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("cube.bin"), cube_buffer()).unwrap();
        let text = document(r#"{"byteLength": 240, "uri": "cube.bin"}"#, "");
        std::fs::write(dir.join("two cubes.gltf"), text).unwrap();
        let (mesh, notes) = Mesh::load_with_notes(&dir.join("two cubes.gltf")).unwrap();
        check_two_cubes(&mesh);
        // The mesh both nodes use is read once: one note for its line primitive.
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("Lines"), "{notes:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A unit quad in the xz plane (normal +y) with texture coordinates u = x, v = z, in an
    /// alpha-masked material (cutoff 0.5, alpha factor `factor`) whose 4x4 texture's alpha is
    /// `alpha` (row by row), clamped at its edges.
    fn masked_quad(alpha: [u8; 16], factor: f32) -> String {
        let mut buffer = Vec::new();
        let corners = [[0.0f32, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        for [x, z] in corners {
            for v in [x, 0.0, z] {
                buffer.extend_from_slice(&v.to_le_bytes());
            }
        }
        for [x, z] in corners {
            for v in [x, z] {
                buffer.extend_from_slice(&v.to_le_bytes());
            }
        }
        for i in [0u32, 1, 2, 0, 2, 3] {
            buffer.extend_from_slice(&i.to_le_bytes());
        }
        let rgba: Vec<u8> = alpha.iter().flat_map(|&a| [200, 120, 40, a]).collect();
        let mut png = Vec::new();
        image::write_buffer_with_format(
            &mut std::io::Cursor::new(&mut png),
            &rgba,
            4,
            4,
            image::ExtendedColorType::Rgba8,
            image::ImageFormat::Png,
        )
        .unwrap();
        format!(
            r#"{{"asset": {{"version": "2.0"}},
            "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                            {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                            {{"buffer": 0, "byteOffset": 80, "byteLength": 24}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                            "min": [0, 0, 0], "max": [1, 0, 1]}},
                          {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                          {{"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}}],
            "images": [{{"uri": "data:image/png;base64,{}"}}],
            "samplers": [{{"wrapS": 33071, "wrapT": 33648}}],
            "textures": [{{"source": 0, "sampler": 0}}],
            "materials": [{{"alphaMode": "MASK", "alphaCutoff": 0.5,
                            "pbrMetallicRoughness": {{"baseColorFactor": [1, 1, 1, {factor}],
                                                      "baseColorTexture": {{"index": 0}}}}}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}},
                                         "indices": 2, "material": 0}}]}}],
            "nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}], "scene": 0}}"#,
            buffer.len(),
            base64(&buffer),
            base64(&png),
        )
    }

    /// An alpha-masked material's texture becomes the part's cutout: its alpha times the
    /// factor, the sampler's wrap modes, texture coordinates on every vertex; the holes are
    /// where the alpha is below the cutoff.
    #[test]
    fn masked_textures_become_cutouts() {
        // The left half (u < 0.5) transparent, the right half opaque.
        let alpha = [0, 0, 255, 255].repeat(4).try_into().unwrap();
        let text = masked_quad(alpha, 1.0);
        let (parts, notes) = Mesh::parse_parts(
            text.as_bytes(),
            MeshFormat::Gltf,
            Some(std::path::Path::new(".")),
        )
        .unwrap();
        assert_eq!(parts.len(), 1);
        let mesh = &parts[0].mesh;
        let cutout = mesh.cutout.as_ref().expect("a cutout");
        assert_eq!((cutout.width, cutout.height), (4, 4));
        assert_eq!(cutout.wrap, [Wrap::ClampToEdge, Wrap::MirroredRepeat]);
        assert_eq!(cutout.cutoff, 0.5);
        assert_eq!(mesh.uvs.len(), mesh.positions.len());
        for (p, uv) in mesh.positions.iter().zip(&mesh.uvs) {
            assert_eq!((p.x, p.z), (uv.x, uv.y));
        }
        assert!(!cutout.solid_at(DVec2::new(0.1, 0.5)));
        assert!(cutout.solid_at(DVec2::new(0.9, 0.5)));
        // Bilinear between texel centres: halfway at u = 0.5.
        assert!((cutout.alpha_at(DVec2::new(0.5, 0.3)) - 0.5).abs() < 1e-9);
        // Clamped beyond u = 1, mirrored in v.
        assert!(cutout.solid_at(DVec2::new(1.7, 0.5)) && !cutout.solid_at(DVec2::new(-3.0, 1.7)));
        assert!(
            notes.iter().any(|n| n.contains("alpha-masked")),
            "{notes:?}"
        );
        // The material's alpha factor scales the texture's: 0.4 leaves nothing above 0.5,
        // and a texture without holes gives no cutout.
        let faded = masked_quad([255; 16], 0.4);
        let (parts, _) = Mesh::parse_parts(
            faded.as_bytes(),
            MeshFormat::Gltf,
            Some(std::path::Path::new(".")),
        )
        .unwrap();
        let cutout = parts[0].mesh.cutout.as_ref().expect("a cutout");
        assert!(cutout.alpha.iter().all(|&a| a == 102));
        let solid = masked_quad([255; 16], 1.0);
        let (parts, _) = Mesh::parse_parts(
            solid.as_bytes(),
            MeshFormat::Gltf,
            Some(std::path::Path::new(".")),
        )
        .unwrap();
        assert!(parts[0].mesh.cutout.is_none() && parts[0].mesh.uvs.is_empty());
        // A unreadable texture: drawn whole, named in the notes.
        let broken = text.replace("data:image/png;base64,", "data:image/png;base64,AAAA");
        let (parts, notes) = Mesh::parse_parts(
            broken.as_bytes(),
            MeshFormat::Gltf,
            Some(std::path::Path::new(".")),
        )
        .unwrap();
        assert!(parts[0].mesh.cutout.is_none());
        assert!(
            notes.iter().any(|n| n.contains("cannot read the texture")),
            "{notes:?}"
        );
    }

    /// A mesh that two nodes use is one part placed twice (once mirrored), in the mesh's own
    /// frame, and its placements flatten to the world-frame cubes.
    #[test]
    fn a_shared_mesh_is_one_part_placed_at_each_node() {
        let (parts, _) =
            Mesh::parse_parts(embedded("").as_bytes(), MeshFormat::Gltf, None).unwrap();
        assert_eq!(parts.len(), 1);
        let part = &parts[0];
        assert_eq!(part.mesh.triangle_count(), 12);
        // The unit cube where the buffer puts it.
        let (lo, hi) = part.mesh.bounds();
        assert!(lo.abs().max_element() < 1e-9 && (hi - DVec3::ONE).abs().max_element() < 1e-9);
        assert_eq!(part.placements.len(), 2);
        let determinants: Vec<f64> = part.placements.iter().map(|m| m.determinant()).collect();
        assert!((determinants[0] - 8.0).abs() < 1e-9 && (determinants[1] + 8.0).abs() < 1e-9);
        assert!(
            (part.placements[0].transform_point3(DVec3::ZERO) - DVec3::new(20.0, 0.0, 0.0))
                .length()
                < 1e-9
        );
        check_two_cubes(&part.flattened());
    }

    #[test]
    fn bad_gltf_files_give_clear_errors() {
        let draco = embedded(
            r#", "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]"#,
        );
        let e = Mesh::parse(draco.as_bytes(), MeshFormat::Gltf).unwrap_err();
        assert!(
            matches!(&e, LoadError::UnsupportedExtension { extension, .. } if extension == "KHR_draco_mesh_compression"),
            "{e}"
        );
        assert!(e.to_string().contains("KHR_draco_mesh_compression"), "{e}");
        // Not JSON; a buffer file that is not there (only data URIs without a folder).
        for bad in [
            "{not json",
            &document(r#"{"byteLength": 240, "uri": "missing.bin"}"#, ""),
        ] {
            let e = Mesh::parse(bad.as_bytes(), MeshFormat::Gltf).unwrap_err();
            assert!(
                matches!(
                    e,
                    LoadError::Parse {
                        format: MeshFormat::Gltf,
                        ..
                    }
                ),
                "{e}"
            );
        }
        // Only lines: no triangles.
        let lines = embedded("").replace(r#"{"attributes": {"POSITION": 0}, "indices": 1},"#, "");
        let e = Mesh::parse(lines.as_bytes(), MeshFormat::Gltf).unwrap_err();
        assert!(matches!(e, LoadError::NoTriangles { .. }), "{e}");
        // An index past the positions.
        let mut buffer = cube_buffer();
        buffer[96..100].copy_from_slice(&9u32.to_le_bytes());
        let text = document(
            &format!(
                r#"{{"byteLength": 240, "uri": "data:application/octet-stream;base64,{}"}}"#,
                base64(&buffer)
            ),
            "",
        );
        let e = Mesh::parse(text.as_bytes(), MeshFormat::Gltf).unwrap_err();
        assert!(e.to_string().contains("vertex 9"), "{e}");
    }
}
