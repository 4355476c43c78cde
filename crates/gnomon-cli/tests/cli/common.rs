//! What the command tests share: running the binary, the demo's overview setup, temporary
//! folders, and the files (meshes, scene files) they write.

pub use std::process::{Command, Output};

pub use glam::{DMat4, DVec3, DVec4};
pub use serde_json::Value;

pub fn gnomon(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Runs a command the binary printed (`gnomon ...`) as a shell runs it, in `dir` (its
/// quoted arguments stay whole), and fails the test, showing its standard error, unless it
/// succeeds.
pub fn run_printed(command: &str, dir: &std::path::Path) {
    let out = Command::new("sh")
        .arg("-c")
        .arg(command.replacen("gnomon", env!("CARGO_BIN_EXE_gnomon"), 1))
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs the binary and fails the test, showing its standard error, unless it succeeds.
pub fn gnomon_ok(args: &[&str]) -> Output {
    let out = gnomon(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

pub const OVERVIEW: &[&str] = &[
    "setup",
    "--scene",
    "demo",
    "--eye",
    "260,190,260",
    "--target",
    "0,0,0",
    "--light-dir",
    "-0.4,-1,-0.25",
];

pub fn setup_json(extra: &[&str]) -> Value {
    let mut args = OVERVIEW.to_vec();
    args.extend_from_slice(extra);
    args.push("--json");
    let out = gnomon_ok(&args);
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

pub fn matrix(v: &Value) -> DMat4 {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(a.len(), 16);
    DMat4::from_cols_array(&a.try_into().unwrap())
}

/// The entry of `json["techniques"]` named `name`.
pub fn technique_row(json: &Value, name: &str) -> Value {
    json["techniques"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["technique"] == name)
        .unwrap_or_else(|| panic!("no {name} in {json}"))
        .clone()
}

pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gnomon-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `RENDER` with `--technique technique` and `extra`, its `--mask` read back (written as
/// `name`.png in `dir`).
pub fn render_mask(
    dir: &std::path::Path,
    technique: &str,
    extra: &[&str],
    name: &str,
) -> image::GrayImage {
    let mask = dir.join(format!("{name}.png"));
    let out = dir.join("frame.png");
    let mut args = RENDER.to_vec();
    args.extend(["--technique", technique]);
    args.extend(extra);
    args.extend([
        "--out",
        out.to_str().unwrap(),
        "--mask",
        mask.to_str().unwrap(),
    ]);
    gnomon_ok(&args);
    image::open(&mask).unwrap().into_luma8()
}

/// Each of `cases` (options after `RENDER`, a part of the error) exits with code 2 and says
/// so on stderr.
pub fn assert_render_refuses(cases: &[(Vec<&str>, &str)]) {
    for (extra, needle) in cases {
        let mut args = RENDER.to_vec();
        args.extend(extra.iter().copied());
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(needle), "{extra:?}: {stderr}");
    }
}

/// The view and sun the mesh tests look at their cube with.
pub const CUBE_VIEW: [&str; 6] = [
    "--eye",
    "12,9,14",
    "--target",
    "0,1,0",
    "--light-dir",
    "0.6,-1,-0.2",
];

/// A unit cube as an OFF file in `dir`, counter-clockwise quads.
pub fn write_off_cube(dir: &std::path::Path) -> std::path::PathBuf {
    let cube = dir.join("cube.off");
    std::fs::write(
        &cube,
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
         4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n",
    )
    .unwrap();
    cube
}

/// The unit cube of [`write_off_cube`] as a glTF buffer: its 8 f32 positions, then its 36
/// u32 indices (each quad as two triangles, counter-clockwise from outside).
pub fn gltf_cube_buffer() -> Vec<u8> {
    let corners = [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ];
    let quads = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [1, 2, 6, 5],
        [0, 4, 7, 3],
    ];
    let mut out = Vec::new();
    for c in corners {
        for x in c {
            out.extend_from_slice(&(x as f32).to_le_bytes());
        }
    }
    for q in quads {
        for i in [0, 1, 2, 0, 2, 3] {
            out.extend_from_slice(&(q[i] as u32).to_le_bytes());
        }
    }
    out
}

/// A glTF document instancing the cube of `cube.bin` at one node with `node` (its members),
/// and `extra` more top-level members.
pub fn gltf_cube(node: &str, extra: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}},
        "buffers": [{{"byteLength": 240, "uri": "cube.bin"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 96}},
                        {{"buffer": 0, "byteOffset": 96, "byteLength": 144}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 1]}},
                      {{"bufferView": 1, "componentType": 5125, "count": 36, "type": "SCALAR"}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
        "nodes": [{{"mesh": 0{sep}{node}}}],
        "scenes": [{{"nodes": [0]}}], "scene": 0{extra}}}"#,
        sep = if node.is_empty() { "" } else { ", " }
    )
}

/// Runs `gnomon compare` into `dir` and returns its report.json.
pub fn run_compare(
    dir: &std::path::Path,
    views: &str,
    techniques: &str,
    shadow_map: &str,
    size: &str,
) -> Value {
    gnomon_ok(&[
        "compare",
        "--views",
        views,
        "--techniques",
        techniques,
        "--shadow-map",
        shadow_map,
        "--size",
        size,
        "--out",
        dir.to_str().unwrap(),
    ]);
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// A scene file in `dir`: two cubes from one OFF file (one scaled, one turned and coloured)
/// on a ground slab, a view under the sun and one under a spot light.
pub fn write_scene_file(dir: &std::path::Path) -> std::path::PathBuf {
    write_off_cube(dir);
    let path = dir.join("two cubes.toml");
    std::fs::write(
        &path,
        r#"name = "two cubes"

[ground]
size = 40

[[object]]
mesh = "cube.off"
translate = [-3, 0, 0]
scale = 2

[[object]]
mesh = "cube.off"
name = "turned"
translate = [4, 0, 2]
rotate_y_degrees = 30
scale = 3
color = [0.9, 0.2, 0.2]

[[view]]
name = "sun"
eye = [14, 10, 16]
target = [0, 1, 0]
far = 100
light_dir = [0.6, -1, -0.2]

[[view]]
name = "lamp"
description = "a spot light over the cubes"
eye = [14, 10, 16]
target = [0, 1, 0]
fov = 50
near = 0.5
far = 100
spot = [0, 12, -6, 0, -1, 0.5, 40, 60]

[[view]]
name = "two suns"
eye = [14, 10, 16]
target = [0, 1, 0]
far = 100

[[view.light]]
light_dir = [0.6, -1, -0.2]

[[view.light]]
light_dir = [0.2, -1, -0.6]
"#,
    )
    .unwrap();
    path
}

pub const RENDER: &[&str] = &[
    "render",
    "--eye",
    "-230,220,200",
    "--target",
    "0,0,0",
    "--far",
    "800",
    "--light-dir",
    "1,-0.45,-0.35",
    "--size",
    "160x90",
    "--shadow-map",
    "1024",
];
