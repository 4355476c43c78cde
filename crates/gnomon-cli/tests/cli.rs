//! The `gnomon` binary: JSON output of `setup`, one-line errors with exit code 2, `demo`.

use std::process::{Command, Output};

use glam::{DMat4, DVec3, DVec4};
use serde_json::Value;

fn gnomon(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(args)
        .output()
        .expect("the binary runs")
}

const OVERVIEW: &[&str] = &[
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

fn setup_json(extra: &[&str]) -> Value {
    let mut args = OVERVIEW.to_vec();
    args.extend_from_slice(extra);
    args.push("--json");
    let out = gnomon(&args);
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn matrix(v: &Value) -> DMat4 {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(a.len(), 16);
    DMat4::from_cols_array(&a.try_into().unwrap())
}

#[test]
fn setup_json_has_the_documented_shape_and_covers_a_visible_roof() {
    for technique in ["uniform", "focused"] {
        let json = setup_json(&["--technique", technique, "--shadow-map", "2048"]);
        let keys: Vec<&str> = json
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(
            keys,
            ["technique", "fallback", "maps", "selection", "diagnostics"]
        );
        assert_eq!(json["technique"], technique);
        assert!(json["fallback"].is_null());
        assert_eq!(json["selection"]["kind"], "single");
        let map = &json["maps"][0];
        assert_eq!(map["resolution"], 2048);
        assert_eq!(map["viewport_inset"], 1);
        assert_eq!(map["depth_from_world"].as_array().unwrap().len(), 4);
        let clip_from_world = matrix(&map["clip_from_world"]);
        // The centre of a roof the overview sees.
        let block = gnomon_scene::demo()
            .objects
            .into_iter()
            .find(|o| o.name == "block_4_4")
            .unwrap();
        let bounds = block.world_bounds().unwrap();
        let roof = DVec3::new(bounds.center().x, bounds.max().y, bounds.center().z);
        let clip = clip_from_world * roof.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let inset = 1.0 - 2.0 / 2048.0;
        assert!(
            ndc.x.abs() <= inset && ndc.y.abs() <= inset,
            "{technique}: roof lands at {ndc}"
        );
        assert!((0.0..=1.0).contains(&ndc.z));
        let depth: Vec<f64> = map["depth_from_world"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let linear = DVec4::from_slice(&depth).dot(roof.extend(1.0));
        assert!((0.0..=1.0).contains(&linear));
        if technique == "focused" {
            assert!(json["diagnostics"]["visible_receivers"].as_u64().unwrap() > 0);
        }
    }
}

#[test]
fn focused_is_tighter_than_uniform_in_the_overview() {
    let area = |json: &Value| {
        let m = matrix(&json["maps"][0]["clip_from_world"]);
        1.0 / (m.row(0).truncate().length() * m.row(1).truncate().length())
    };
    let uniform = area(&setup_json(&["--technique", "uniform"]));
    let focused = area(&setup_json(&["--technique", "focused"]));
    assert!(
        focused < 0.8 * uniform,
        "focused footprint {focused} vs uniform {uniform}"
    );
}

#[test]
fn spot_light_gives_a_perspective_map() {
    let out = gnomon(&[
        "setup",
        "--eye",
        "-150,20,150",
        "--target",
        "0,0,0",
        "--spot",
        "-100,80,100,1,-1,-1,35,300",
        "--technique",
        "focused",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["maps"][0]["projection"], "perspective");
}

#[test]
fn degenerate_configurations_name_their_fallback() {
    // Looking straight down along a vertical sun: the miner's lamp.
    let out = gnomon(&[
        "setup",
        "--eye",
        "0,300,0",
        "--target",
        "0,0,0",
        "--up",
        "0,0,-1",
        "--light-dir",
        "0,-1,0",
        "--technique",
        "focused",
        "--json",
    ]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["fallback"], "light_parallel_to_view");
    // Looking away from the scene into the sky: nothing visible.
    let out = gnomon(&[
        "setup",
        "--eye",
        "0,500,0",
        "--target",
        "0,1000,0",
        "--up",
        "0,0,1",
        "--light-dir",
        "0,-1,0",
        "--technique",
        "focused",
        "--json",
    ]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["fallback"], "no_visible_receiver");
    assert_eq!(
        json["diagnostics"]["fallbacks"].as_array().unwrap().len(),
        1
    );
}

#[test]
fn bad_input_gives_one_line_and_exit_code_2() {
    let base = [
        "setup",
        "--eye",
        "0,2,0",
        "--target",
        "1,2,0",
        "--technique",
        "focused",
    ];
    let cases: &[(&[&str], &str)] = &[
        (&["--light-dir", "0,0,0"], "zero length"),
        (&["--light-dir", "0,-1,0", "--fov", "nan"], "field of view"),
        (&["--light-dir", "0,-1,0", "--fov", "180"], "field of view"),
        (
            &["--light-dir", "0,-1,0", "--near", "10", "--far", "5"],
            "near",
        ),
        (&["--light-dir", "0,-1,0", "--near", "0"], "near"),
        (&["--light-dir", "0,-1,0", "--aspect", "-1"], "aspect"),
        (
            &["--light-dir", "0,-1,0", "--shadow-map", "3"],
            "resolution",
        ),
        (&["--light-dir", "0,-1,nan"], "finite"),
        (&["--light-dir", "0,-1"], "3 comma-separated"),
        (&["--spot", "0,10,0,0,-1,0,90,50"], "half-angle"),
        (&["--spot", "0,10,0,0,-1,0,30,0"], "range"),
        (
            &["--light-dir", "0,-1,0", "--spot", "0,10,0,0,-1,0,30,50"],
            "cannot be used",
        ),
        (&[], "required"),
        (
            &["--light-dir", "0,-1,0", "--scene", "moon"],
            "unknown scene",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert_eq!(
            stderr.trim_end().lines().count(),
            1,
            "{extra:?}: not one line: {stderr}"
        );
        assert!(
            stderr.contains(expected),
            "{extra:?}: '{stderr}' lacks '{expected}'"
        );
        assert!(out.stdout.is_empty());
    }
    let out = gnomon(&[
        "setup",
        "--eye",
        "1e300,0,0",
        "--target",
        "1,2,0",
        "--technique",
        "uniform",
        "--light-dir",
        "0,-1,0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("out of range"));
    // Same eye and target.
    let out = gnomon(&[
        "setup",
        "--eye",
        "1,2,0",
        "--target",
        "1,2,0",
        "--technique",
        "uniform",
        "--light-dir",
        "0,-1,0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let out = gnomon(&[
        "setup",
        "--eye",
        "1,2,0",
        "--target",
        "1,3,0",
        "--technique",
        "bogus",
        "--light-dir",
        "0,-1,0",
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn demo_writes_every_view_and_technique() {
    let dir = std::env::temp_dir().join(format!("gnomon-demo-test-{}", std::process::id()));
    let out = gnomon(&["demo", "--out", dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("setups.json")).unwrap()).unwrap();
    let entries = json.as_array().unwrap();
    assert_eq!(
        entries.len(),
        gnomon_scene::DEMO_VIEWS.len() * gnomon::Technique::NAMES.len()
    );
    assert!(
        std::fs::read_to_string(dir.join("index.html"))
            .unwrap()
            .contains("overview")
    );
    std::fs::remove_dir_all(dir).unwrap();
}
