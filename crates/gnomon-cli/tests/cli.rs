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

/// Runs a command the binary printed (`gnomon ...`) as a shell runs it, in `dir` (its
/// quoted arguments stay whole), and fails the test, showing its standard error, unless it
/// succeeds.
fn run_printed(command: &str, dir: &std::path::Path) {
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
fn gnomon_ok(args: &[&str]) -> Output {
    let out = gnomon(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
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
    let out = gnomon_ok(&args);
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
    let out = gnomon_ok(&[
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
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["maps"][0]["projection"], "perspective");
}

#[test]
fn point_light_gives_a_map_per_cube_face_it_needs() {
    // A lamp above the tallest block, the camera above it: the faces beside and below it see
    // the city; the one looking up sees nothing and gets no map.
    let out = gnomon_ok(&[
        "setup",
        "--eye",
        "-60,90,60",
        "--target",
        "-78,0,-78",
        "--point",
        "-63.5,70,-77,300",
        "--technique",
        "cube",
        "--json",
    ]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["technique"], "cube");
    assert_eq!(json["selection"]["kind"], "cube_faces");
    let faces: Vec<&str> = json["selection"]["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    let maps = json["maps"].as_array().unwrap();
    assert_eq!(faces.len(), maps.len());
    assert!(faces.contains(&"-y") && !faces.contains(&"+y"), "{faces:?}");
    assert_eq!(
        json["diagnostics"]["cube_faces_skipped"].as_u64().unwrap() as usize,
        6 - faces.len()
    );
    assert!(maps.iter().all(|m| m["projection"] == "perspective"));
    // Techniques that do not take the light are refused in one line.
    for (light, technique, expected) in [
        (["--light-dir", "0,-1,0"], "cube", "needs a point light"),
        (
            ["--point", "0,10,0,50"],
            "sppsm",
            "does not take point lights",
        ),
        (
            ["--point", "0,10,0,50"],
            "cascades",
            "does not take point lights",
        ),
    ] {
        let mut args = vec!["setup", "--eye", "0,2,0", "--target", "1,2,0"];
        args.extend(light);
        args.extend(["--technique", technique]);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{technique}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
    }
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
        (&[], "--light-dir, --spot and --point, or a named --view"),
        (&["--point", "0,10,0,-5"], "range"),
        (&["--point", "0,10,0"], "4 comma-separated"),
        (
            &["--point", "0,10,0,50", "--spot", "0,10,0,0,-1,0,30,50"],
            "cannot be used",
        ),
        (&["--view", "nowhere"], "unknown view"),
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
    gnomon_ok(&[
        "demo",
        "--out",
        dir.to_str().unwrap(),
        "--width",
        "320",
        "--shadow-map",
        "512",
    ]);
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("setups.json")).unwrap()).unwrap();
    let entries = json.as_array().unwrap();
    // Every view with every map technique, SPPSM with one map's texels, paraboloid maps with
    // a cube's, projective shadows, object IDs, IDs and depth, the three cascade rows,
    // planar shadows on the ground, the exact shadow volumes, and soft shadows (the area
    // light's reference and PCSS) (a row that cannot draw a view's light is an entry that
    // says so).
    assert_eq!(
        entries.len(),
        gnomon_scene::DEMO_VIEWS.len() * (gnomon::Technique::NAMES.len() + 3 + 2 + 3 + 1 + 1 + 2)
    );
    for view in gnomon_scene::DEMO_VIEWS {
        let pcss = entries
            .iter()
            .find(|e| e["view"] == view.name && e["technique"] == "pcss")
            .unwrap_or_else(|| panic!("{}: no pcss entry", view.name));
        assert!(pcss["penumbra_error"].as_f64().unwrap() < 0.5, "{pcss}");
        assert!(dir.join(format!("{}_soft.png", view.name)).exists());
        assert!(dir.join(format!("{}_pcss.png", view.name)).exists());
    }
    let skipped = entries.iter().filter(|e| e["skipped"].is_string()).count();
    assert!(
        skipped > 0,
        "the lamp views leave out SPPSM and the cascades"
    );
    for row in [
        "projective",
        "object-id",
        "id-depth",
        "sppsm-same-texels",
        "paraboloid-cube-texels",
        "cascades-stable",
        "cascades-lispsm",
        "cascades-best",
    ] {
        assert!(
            entries.iter().any(|e| e["technique"] == row),
            "no {row} in the demo"
        );
    }
    // The front page: the rows a user compares, each judged, on a few sun views; every image
    // either page names was written.
    let front = std::fs::read_to_string(dir.join("index.html")).unwrap();
    for row in [
        "cascades-stable",
        "cascades-best",
        "sppsm",
        "volumes",
        "soft",
    ] {
        assert!(
            front.contains(&format!("<b>{row}</b>")),
            "no {row} on the front page"
        );
    }
    assert!(front.matches("%</b> wrong").count() >= 3, "{front}");
    assert!(front.contains("_crop_wrong.png") && front.contains("all.html"));
    let all = std::fs::read_to_string(dir.join("all.html")).unwrap();
    for view in gnomon_scene::DEMO_VIEWS {
        assert!(
            all.contains(&format!("<h2>{} ", view.name)),
            "{}",
            view.name
        );
    }
    assert!(all.contains("gnomon render") && all.contains("not drawn here"));
    for page in [&front, &all] {
        for image in page.split("src=\"").skip(1) {
            let name = &image[..image.find('"').unwrap()];
            assert!(dir.join(name).exists(), "{name} is named but not written");
        }
    }
    for view in gnomon_scene::DEMO_VIEWS {
        let volumes = entries
            .iter()
            .find(|e| e["view"] == view.name && e["technique"] == "volumes")
            .unwrap_or_else(|| panic!("{}: no volumes entry", view.name));
        assert!(volumes["volume_triangles"].as_u64().unwrap() > 100);
        assert!(dir.join(format!("{}_volumes.png", view.name)).exists());
        assert!(dir.join(format!("{}_planar.png", view.name)).exists());
        assert!(
            entries
                .iter()
                .any(|e| e["view"] == view.name && e["technique"] == "planar"),
            "{}: no planar entry",
            view.name
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The entry of `json["techniques"]` named `name`.
fn technique_row(json: &Value, name: &str) -> Value {
    json["techniques"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["technique"] == name)
        .unwrap_or_else(|| panic!("no {name} in {json}"))
        .clone()
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gnomon-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const RENDER: &[&str] = &[
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

#[test]
fn render_writes_frame_mask_and_light_view() {
    let dir = temp_dir("render");
    let (frame, mask, light) = (
        dir.join("frame.png"),
        dir.join("mask.png"),
        dir.join("light.png"),
    );
    let mut args = RENDER.to_vec();
    args.extend([
        "--out",
        frame.to_str().unwrap(),
        "--mask",
        mask.to_str().unwrap(),
    ]);
    args.extend(["--light-view", light.to_str().unwrap()]);
    gnomon_ok(&args);
    assert_eq!(image::image_dimensions(&frame).unwrap(), (160, 90));
    assert_eq!(image::image_dimensions(&light).unwrap(), (1024, 1024));
    let mask = image::open(&mask).unwrap().into_luma8();
    let mut counts = std::collections::BTreeMap::new();
    for p in mask.pixels() {
        *counts.entry(p.0[0]).or_insert(0) += 1;
    }
    assert!(
        counts.keys().all(|v| [0u8, 128, 255].contains(v)),
        "mask values {counts:?}"
    );
    assert!(
        counts.len() == 3,
        "lit, unlit and empty pixels all appear: {counts:?}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn filters_change_the_image_but_not_the_one_tap_mask() {
    let dir = temp_dir("filters");
    let mut masks = Vec::new();
    let mut frames = Vec::new();
    for pcf in ["none", "2x2", "5x5"] {
        let (frame, mask) = (
            dir.join(format!("{pcf}.png")),
            dir.join(format!("{pcf}_mask.png")),
        );
        let mut args = RENDER.to_vec();
        args.extend([
            "--pcf",
            pcf,
            "--out",
            frame.to_str().unwrap(),
            "--mask",
            mask.to_str().unwrap(),
        ]);
        gnomon_ok(&args);
        masks.push(image::open(&mask).unwrap().into_luma8().into_raw());
        frames.push(image::open(&frame).unwrap().into_rgba8().into_raw());
    }
    assert!(masks.windows(2).all(|w| w[0] == w[1]));
    assert_ne!(frames[0], frames[2], "5x5 PCF must soften shadow edges");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn render_without_an_adapter_says_what_to_install() {
    let out = Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(RENDER)
        .args([
            "--out",
            std::env::temp_dir()
                .join("gnomon-never-written.png")
                .to_str()
                .unwrap(),
        ])
        .env("WGPU_BACKEND", "metal")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1);
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
}

#[test]
fn render_refuses_a_far_plane_beyond_the_precise_range_before_any_work() {
    let dir = temp_dir("far");
    let out_path = dir.join("far.png");
    // RENDER's far plane (800) moved to 2000 km.
    let mut args: Vec<&str> = RENDER
        .iter()
        .map(|a| if *a == "800" { "2000000" } else { *a })
        .collect();
    args.extend(["--out", out_path.to_str().unwrap()]);
    let out = gnomon(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("draws precisely"), "{stderr}");
    assert!(!out_path.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn render_rejects_bad_sizes_with_exit_code_2() {
    for size in ["0x10", "10", "axb", "99999x10"] {
        let mut args = RENDER.to_vec();
        args.extend(["--size", size]);
        let out = gnomon(&args);
        assert_eq!(out.status.code(), Some(2), "{size}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr)
                .trim_end()
                .lines()
                .count(),
            1
        );
    }
}

#[test]
fn export_writes_every_triangle_as_obj() {
    let dir = temp_dir("export");
    let obj = dir.join("scene.obj");
    let out = gnomon(&["export", "--scene", "demo", "--obj", obj.to_str().unwrap()]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&obj).unwrap();
    let vertices = text.lines().filter(|l| l.starts_with("v ")).count();
    let faces: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(faces.len(), gnomon_scene::demo().world_triangles().len());
    // Every face refers to an existing vertex (OBJ indices start at 1).
    for f in faces {
        for index in f.split_whitespace().skip(1) {
            let i: usize = index.parse().unwrap();
            assert!((1..=vertices).contains(&i));
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--technique volumes` draws exact shadows: its mask agrees with the focused map's one-tap
/// mask on almost every pixel of the same view (both against the same scene), and asking for
/// a light view (which volumes do not have) is a usage error.
#[test]
fn render_with_shadow_volumes_writes_a_mask_like_the_maps() {
    let dir = temp_dir("volumes");
    let mask = |technique: &str| {
        let path = dir.join(format!("{technique}.png"));
        let frame = dir.join(format!("{technique}_frame.png"));
        let mut args = RENDER.to_vec();
        args.extend([
            "--out",
            frame.to_str().unwrap(),
            "--mask",
            path.to_str().unwrap(),
            "--technique",
            technique,
            "--pcf",
            "none",
        ]);
        gnomon_ok(&args);
        image::open(&path).unwrap().into_luma8()
    };
    let (volumes, focused) = (mask("volumes"), mask("focused"));
    let differing = volumes
        .pixels()
        .zip(focused.pixels())
        .filter(|(a, b)| a != b)
        .count();
    let shadowed = volumes.pixels().filter(|p| p.0[0] == 0).count();
    assert!(shadowed > 100, "{shadowed} unlit pixels");
    assert!(
        differing * 100 < volumes.len(),
        "{differing} of {} pixels differ",
        volumes.len()
    );
    let mut args = RENDER.to_vec();
    args.extend(["--technique", "volumes", "--light-view", "x.png"]);
    assert_eq!(gnomon(&args).status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `RENDER` with `--technique technique` and `extra`, its `--mask` read back (written as
/// `name`.png in `dir`).
fn render_mask(
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
fn assert_render_refuses(cases: &[(Vec<&str>, &str)]) {
    for (extra, needle) in cases {
        let mut args = RENDER.to_vec();
        args.extend(extra.iter().copied());
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(needle), "{extra:?}: {stderr}");
    }
}

/// `render --technique planar`: the ground's shadows agree with the exact volumes' there, a
/// receiver plane given by hand works, and its misuses are usage errors.
#[test]
fn render_planar_shadows_on_the_ground() {
    let dir = temp_dir("planar");
    let planar = render_mask(&dir, "planar", &[], "planar");
    let exact = render_mask(&dir, "volumes", &[], "volumes");
    // Planar shadows are the exact ones on the ground (the rest lit): the few differences lie
    // along shadow edges, which are most of a shadow at this size (the renderer's tests check
    // the interior against the oracle).
    let shadowed = planar.pixels().filter(|p| p.0[0] == 0).count();
    let false_shadow = planar
        .pixels()
        .zip(exact.pixels())
        .filter(|(p, e)| p.0[0] == 0 && e.0[0] == 255)
        .count();
    assert!(shadowed > 20, "{shadowed} shadowed pixels");
    assert!(false_shadow * 10 < shadowed, "{false_shadow} of {shadowed}");
    // The ground's top face by hand (y = 0 upward) gives the same shadows.
    assert_eq!(
        render_mask(&dir, "planar", &["--receiver-plane", "0,1,0,0"], "by-hand"),
        planar
    );
    assert_render_refuses(&[
        (
            vec!["--technique", "focused", "--receiver-plane", "0,1,0,0"],
            "--receiver-plane",
        ),
        (
            vec!["--technique", "planar", "--receiver-plane", "0,0,0,1"],
            "no normal",
        ),
        (
            vec!["--technique", "planar", "--receiver-plane", "0,1,0,-900"],
            "misses",
        ),
        (
            vec!["--technique", "planar", "--json"],
            "planar shadows have none",
        ),
        (
            vec!["--technique", "planar", "--stencil", "z-pass"],
            "--stencil",
        ),
    ]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render --technique projective`: the casters' coverage on the focused map, the ground a
/// receiver only, casters lit: its shadows on the ground agree with the exact ones' there.
#[test]
fn render_projective_shadows() {
    let dir = temp_dir("projective");
    let projective = render_mask(&dir, "projective", &[], "projective");
    let planar = render_mask(&dir, "planar", &[], "planar");
    // Both shadow the ground alone, each exactly up to its resolution: they agree but at
    // the shadows' edges.
    let shadowed = projective.pixels().filter(|p| p.0[0] == 0).count();
    let differing = projective
        .pixels()
        .zip(planar.pixels())
        .filter(|(p, q)| p != q)
        .count();
    assert!(shadowed > 20, "{shadowed}");
    assert!(differing * 4 < shadowed, "{differing} of {shadowed}");
    assert_render_refuses(&[(
        vec!["--technique", "projective", "--lispsm-n", "3"],
        "--lispsm-n does nothing",
    )]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render --technique object-id` and `id-depth`: the focused map read by object IDs agrees
/// with the exact volumes but near outlines (and, for object IDs, on objects that shadow
/// themselves: the demo's are boxes), with no bias at all for object IDs.
#[test]
fn render_object_id_shadows() {
    let dir = temp_dir("object-id");
    let exact = render_mask(&dir, "volumes", &[], "exact");
    let no_bias = [
        "--bias-constant",
        "0",
        "--bias-slope",
        "0",
        "--normal-offset",
        "0",
    ];
    for (technique, extra) in [("object-id", &no_bias[..]), ("id-depth", &[][..])] {
        let mask = render_mask(&dir, technique, extra, technique);
        let geometry = exact.pixels().filter(|p| p.0[0] != 128).count();
        let shadowed = mask.pixels().filter(|p| p.0[0] == 0).count();
        let differing = mask
            .pixels()
            .zip(exact.pixels())
            .filter(|(p, q)| p != q)
            .count();
        assert!(shadowed > geometry / 20, "{technique}: {shadowed}");
        assert!(
            differing * 100 < geometry,
            "{technique}: {differing} of {geometry} differ from the exact mask"
        );
    }
    assert_render_refuses(&[(
        vec!["--technique", "object-id", "--lispsm-n", "3"],
        "--lispsm-n does nothing",
    )]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render --technique volumes --area-light R`: soft shadows whose factor lies between the
/// hard shadows' lit and unlit, with a penumbra; misuses are usage errors.
#[test]
fn render_soft_shadows_of_an_area_light() {
    let dir = temp_dir("soft");
    let hard = render_mask(&dir, "volumes", &[], "hard");
    let soft = render_mask(
        &dir,
        "volumes",
        &["--area-light", "4", "--area-samples", "16"],
        "soft",
    );
    // The hard mask has no penumbra; the soft one does, in steps of 1/16.
    let penumbra = soft.pixels().filter(|p| p.0[0] > 0 && p.0[0] < 255).count();
    assert!(hard.pixels().all(|p| [0, 128, 255].contains(&p.0[0])));
    assert!(penumbra > 20, "{penumbra} penumbra pixels");
    assert_render_refuses(&[
        (
            vec!["--technique", "focused", "--area-light", "2"],
            "--area-light",
        ),
        (
            vec!["--technique", "volumes", "--area-light", "60"],
            "area light radius",
        ),
        (
            vec![
                "--technique",
                "volumes",
                "--area-light",
                "1",
                "--area-samples",
                "0",
            ],
            "area light samples",
        ),
        (
            vec!["--technique", "volumes", "--area-samples", "8"],
            "--area-light",
        ),
    ]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render --pcf pcss --area-light R`: PCSS on a shadow map; its mask is the shadow factor,
/// close to the soft volumes' of the same area light; misuses are usage errors.
#[test]
fn render_pcss_of_an_area_light() {
    let dir = temp_dir("pcss");
    let reference = render_mask(
        &dir,
        "volumes",
        &["--area-light", "4", "--area-samples", "64"],
        "reference",
    );
    let pcss = render_mask(
        &dir,
        "lispsm",
        &["--pcf", "pcss", "--area-light", "4"],
        "pcss",
    );
    let hard = render_mask(&dir, "lispsm", &[], "hard");
    let penumbra = pcss.pixels().filter(|p| p.0[0] > 5 && p.0[0] < 250).count();
    assert!(penumbra > 20, "{penumbra} penumbra pixels");
    assert!(hard.pixels().all(|p| [0, 128, 255].contains(&p.0[0])));
    // Where either is in a penumbra, PCSS stays near the reference.
    let (mut sum, mut count) = (0.0, 0);
    for (p, r) in pcss.pixels().zip(reference.pixels()) {
        let (p, r) = (p.0[0] as f64 / 255.0, r.0[0] as f64 / 255.0);
        if (0.02..0.98).contains(&p) || (0.02..0.98).contains(&r) {
            sum += (p - r).abs();
            count += 1;
        }
    }
    assert!(
        sum / (count as f64) < 0.15,
        "{} over {count}",
        sum / count as f64
    );
    assert_render_refuses(&[
        (
            vec!["--technique", "lispsm", "--pcf", "pcss"],
            "--area-light R",
        ),
        (
            vec![
                "--technique",
                "lispsm",
                "--pcf",
                "pcss",
                "--area-light",
                "50",
            ],
            "area light radius",
        ),
        (
            vec![
                "--technique",
                "object-id",
                "--pcf",
                "pcss",
                "--area-light",
                "1",
            ],
            "reads none",
        ),
        (
            vec![
                "--technique",
                "lispsm",
                "--pcf",
                "pcss",
                "--area-light",
                "1",
                "--area-samples",
                "8",
            ],
            "--area-samples",
        ),
    ]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--mesh` renders a mesh file on a ground slab: a cube from an OFF file casts a shadow,
/// and the per-caster stencil gives the same mask as z-fail; missing or broken files are
/// usage errors naming the file.
#[test]
fn render_a_mesh_file_with_shadow_volumes() {
    let dir = temp_dir("mesh");
    let cube = write_off_cube(&dir);
    let render = |stencil: &str, mesh: &std::path::Path| {
        let mask = dir.join(format!("{stencil}.png"));
        let mut args = vec![
            "render",
            "--mesh",
            mesh.to_str().unwrap(),
            "--mesh-height",
            "4",
        ];
        let frame = dir.join("frame.png");
        args.extend(CUBE_VIEW);
        args.extend([
            "--technique",
            "volumes",
            "--stencil",
            stencil,
            "--size",
            "160x90",
            "--out",
            frame.to_str().unwrap(),
            "--mask",
            mask.to_str().unwrap(),
        ]);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(out.status.success(), "{stderr}");
        (image::open(&mask).unwrap().into_luma8(), stderr)
    };
    let (z_fail, _) = render("z-fail", &cube);
    let (per_caster, report) = render("per-caster", &cube);
    assert!(report.contains("1 z-pass"), "{report}");
    assert_eq!(z_fail, per_caster);
    // The same cube from a glTF file beside its buffer, under a mirroring and moving node:
    // placed on the slab it is the same cube, so it casts the same shadow (the winding under
    // a mirror is checked in gnomon-scene's tests).
    std::fs::write(dir.join("cube.bin"), gltf_cube_buffer()).unwrap();
    let gltf = dir.join("cube.gltf");
    std::fs::write(
        &gltf,
        gltf_cube(r#""scale": [-1, 1, 1], "translation": [5, 0, 0]"#, ""),
    )
    .unwrap();
    let (from_gltf, _) = render("z-fail", &gltf);
    let differ = from_gltf
        .pixels()
        .zip(z_fail.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ * 1000 <= z_fail.len(), "{differ} pixels differ");
    std::fs::write(
        dir.join("draco.gltf"),
        gltf_cube(
            "",
            r#", "extensionsRequired": ["KHR_draco_mesh_compression"]"#,
        ),
    )
    .unwrap();
    let shadowed = z_fail.pixels().filter(|p| p.0[0] == 0).count();
    let lit = z_fail.pixels().filter(|p| p.0[0] == 255).count();
    assert!(
        shadowed > 200 && lit > 2000,
        "{shadowed} shadowed, {lit} lit"
    );

    std::fs::write(
        dir.join("broken.ply"),
        "ply\nformat ascii 1.0\nend_header\n",
    )
    .unwrap();
    for (file, says) in [
        (dir.join("missing.off"), "cannot read"),
        (dir.join("broken.ply"), "not a valid .ply file"),
        (dir.join("cube.3ds"), "unknown mesh format"),
        (
            dir.join("draco.gltf"),
            "requires the glTF extension KHR_draco_mesh_compression",
        ),
    ] {
        let mut args = vec!["render", "--mesh", file.to_str().unwrap()];
        args.extend(CUBE_VIEW);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(says) && stderr.contains(file.to_str().unwrap()),
            "{stderr}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The view and sun the mesh tests look at their cube with.
const CUBE_VIEW: [&str; 6] = [
    "--eye",
    "12,9,14",
    "--target",
    "0,1,0",
    "--light-dir",
    "0.6,-1,-0.2",
];

/// A unit cube as an OFF file in `dir`, counter-clockwise quads.
fn write_off_cube(dir: &std::path::Path) -> std::path::PathBuf {
    let cube = dir.join("cube.off");
    std::fs::write(
        &cube,
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
         4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n",
    )
    .unwrap();
    cube
}

/// `gnomon setup --mesh` prints the matrices for a mesh file on its slab (bounds from the
/// drawn vertices, the same as `render` hands the core), without a GPU; a missing file is a
/// usage error naming it, and `--mesh` with `--scene` is refused.
#[test]
fn setup_reads_a_mesh_file() {
    let dir = temp_dir("setup-mesh");
    let cube = write_off_cube(&dir);
    let setup = |extra: &[&str]| {
        let mut args = vec!["setup", "--json"];
        args.extend(CUBE_VIEW);
        args.extend_from_slice(extra);
        gnomon(&args)
    };
    let out = setup(&["--mesh", cube.to_str().unwrap(), "--mesh-height", "4"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let diagnostics = &json["diagnostics"];
    assert_eq!(diagnostics["relevant_casters"], 1, "{json}");
    assert_eq!(diagnostics["visible_receivers"], 2, "{json}");
    // The cube stands 4 high over the origin: its top centre lands inside the map.
    let m: Vec<f64> = json["maps"][0]["clip_from_world"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let clip = DMat4::from_cols_slice(&m) * DVec4::new(0.0, 4.0, 0.0, 1.0);
    assert!(clip.x.abs() < clip.w && clip.y.abs() < clip.w, "{clip}");
    let missing = dir.join("missing.off");
    let out = setup(&["--mesh", missing.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(missing.to_str().unwrap()), "{stderr}");
    let out = setup(&["--mesh", cube.to_str().unwrap(), "--scene", "demo"]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// The unit cube of [`write_off_cube`] as a glTF buffer: its 8 f32 positions, then its 36
/// u32 indices (each quad as two triangles, counter-clockwise from outside).
fn gltf_cube_buffer() -> Vec<u8> {
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
fn gltf_cube(node: &str, extra: &str) -> String {
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

/// `gnomon bench` times every named view with each technique asked for, in one run, and
/// gives each one's ratio to the focused map; bad technique names and zero frames are usage
/// errors.
#[test]
fn bench_times_techniques_side_by_side() {
    let out = gnomon_ok(&[
        "bench",
        "--frames",
        "1",
        "--size",
        "64x36",
        "--shadow-map",
        "256",
        "--techniques",
        "focused,volumes-per-caster,planar,projective",
        "--json",
    ]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let results = json["results"].as_array().unwrap();
    assert_eq!(results.len(), 4 * gnomon_scene::DEMO_VIEWS.len());
    for r in results {
        assert!(r["frame_ms"].as_f64().unwrap() > 0.0, "{r}");
        let ratio = r["vs_baseline"].as_f64().unwrap();
        if r["technique"] == "focused" {
            assert_eq!(ratio, 1.0);
        } else {
            assert!(
                ["volumes-per-caster", "planar", "projective"]
                    .contains(&r["technique"].as_str().unwrap()),
                "{r}"
            );
            assert!(ratio > 0.0 && ratio.is_finite());
        }
    }
    assert_eq!(json["baseline"], "focused");
    let summary = json["summary"].as_array().unwrap();
    assert_eq!(summary.len(), 4);
    assert_eq!(summary[0]["mean_vs_baseline"], 1.0);
    let s = &summary[1];
    let (lo, mean, hi) = (
        s["min_vs_baseline"].as_f64().unwrap(),
        s["mean_vs_baseline"].as_f64().unwrap(),
        s["max_vs_baseline"].as_f64().unwrap(),
    );
    assert!(0.0 < lo && lo <= mean && mean <= hi, "{s}");
    for bad in [
        vec!["bench", "--techniques", "focused,shadowy"],
        vec![
            "bench",
            "--techniques",
            "psm,sppsm",
            "--baseline",
            "focused",
        ],
        vec!["bench", "--frames", "0"],
        vec!["bench", "--scene", "nowhere"],
    ] {
        let out = gnomon(&bad);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
}

/// A baseline that refuses a view's light gives no ratio there: `vs_baseline` is null, the
/// table says n/a, and a technique with no view that both it and the baseline draw has no
/// summary figures (they read 0.00x and -0.00x).
#[test]
fn bench_gives_no_ratio_where_the_baseline_refuses_the_light() {
    let args = |views: &str| {
        [
            "bench",
            "--views",
            views,
            "--frames",
            "1",
            "--size",
            "64x36",
            "--shadow-map",
            "256",
            "--techniques",
            "sppsm,focused",
            "--baseline",
            "sppsm",
        ]
        .map(String::from)
    };
    let lamp_only = args("street_lamp");
    let lamp_only: Vec<&str> = lamp_only.iter().map(String::as_str).collect();
    let out = gnomon_ok(&[lamp_only.as_slice(), &["--json"]].concat());
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let focused = json["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["technique"] == "focused")
        .unwrap()
        .clone();
    assert!(focused["frame_ms"].as_f64().unwrap() > 0.0, "{focused}");
    assert!(focused["vs_baseline"].is_null(), "{focused}");
    for s in json["summary"].as_array().unwrap() {
        assert!(s["mean_vs_baseline"].is_null(), "{s}");
    }
    let text = String::from_utf8(gnomon_ok(&lamp_only).stdout).unwrap();
    assert!(
        text.contains("n/a (no view whose light both it and sppsm take)"),
        "{text}"
    );
    // With a sun view too, the ratios come from it alone.
    let both = args("street_lamp,street");
    let both: Vec<&str> = both.iter().map(String::as_str).collect();
    let out = gnomon_ok(&[both.as_slice(), &["--json"]].concat());
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let summary = json["summary"].as_array().unwrap();
    assert_eq!(summary[0]["mean_vs_baseline"], 1.0);
    assert!(summary[1]["mean_vs_baseline"].as_f64().unwrap() > 0.0);
}

/// `gnomon analyze` reproduces the papers from the techniques' matrices (z_n = 1,
/// z_f = 100): uniform 99 at z_n, PSM as in the papers 99 at z_f, LiSPSM 9.9 at both ends,
/// each within 3%, and the logarithmic ideal 4.61; it plots every curve.
#[test]
fn analyze_reproduces_the_papers() {
    let dir = temp_dir("analyze");
    let plot = dir.join("curves.svg");
    let out = gnomon_ok(&[
        "analyze",
        "--zn",
        "1",
        "--zf",
        "100",
        "--json",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let row = |name: &str| technique_row(&json, name);
    let near = |v: &Value, expected: f64| (v.as_f64().unwrap() / expected - 1.0).abs() <= 0.03;
    let uniform = row("uniform");
    assert!(
        near(&uniform["max"], 99.0) && uniform["z_of_max"] == 1.0,
        "{uniform}"
    );
    let psm = row("psm-paper");
    assert!(near(&psm["max"], 99.0) && psm["z_of_max"] == 100.0, "{psm}");
    let lispsm = row("lispsm");
    assert!(
        near(&lispsm["at_z_n"], 9.9) && near(&lispsm["at_z_f"], 9.9),
        "{lispsm}"
    );
    assert!(near(&lispsm["max"], 9.9), "{lispsm}");
    assert!((json["logarithmic_ideal"].as_f64().unwrap() - 4.605).abs() < 0.001);
    for t in json["techniques"].as_array().unwrap() {
        assert!(
            t["curve"].as_array().unwrap().len() == 200,
            "{}",
            t["technique"]
        );
    }
    let svg = std::fs::read_to_string(&plot).unwrap();
    for name in [
        "uniform",
        "focused",
        "psm-paper",
        "lispsm",
        "tsm",
        "xpsm",
        "logarithmic ideal",
    ] {
        assert!(svg.contains(name), "{name} not in the plot");
    }
    // Coinciding curves say so in the legend (the focused map is the uniform one in the ideal
    // configuration), and the legend lies beside the plot, right of its 880 pixels.
    assert!(
        svg.contains("focused (= uniform)"),
        "coinciding curves unmarked"
    );
    let legend_x = svg
        .split("<text")
        .filter(|t| t.contains("logarithmic ideal"))
        .find_map(|t| {
            let x = t.split("x=\"").nth(1)?.split('"').next()?;
            x.parse::<f64>().ok()
        })
        .expect("the legend entry's position");
    assert!(legend_x > 880.0, "legend at x = {legend_x}");
    // The table says the same.
    let out = gnomon(&["analyze", "--gamma", "60"]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && table.contains("gamma = 60") && table.contains("lispsm"));
    for bad in [
        vec!["analyze", "--zn", "0"],
        vec!["analyze", "--zn", "5", "--zf", "2"],
        vec!["analyze", "--gamma", "180"],
        vec!["analyze", "--samples", "1"],
    ] {
        assert_eq!(gnomon(&bad).status.code(), Some(2), "{bad:?}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--error-map` writes the sampling error as a heat map with a legend strip under the frame,
/// and `--json` gives its percentiles; a bigger map lowers them (fewer pixels per texel).
#[test]
fn render_writes_an_error_map_and_its_percentiles() {
    let dir = temp_dir("error-map");
    let run = |shadow_map: &str| {
        let path = dir.join(format!("error_{shadow_map}.png"));
        let frame = dir.join("frame.png");
        // RENDER without its --shadow-map.
        let mut args: Vec<&str> = RENDER[..RENDER.len() - 2].to_vec();
        args.extend([
            "--shadow-map",
            shadow_map,
            "--out",
            frame.to_str().unwrap(),
            "--error-map",
            path.to_str().unwrap(),
            "--json",
        ]);
        let out = gnomon_ok(&args);
        let json: Value = serde_json::from_slice(&out.stdout).unwrap();
        let image = image::open(&path).unwrap().into_rgba8();
        (json, image)
    };
    let (small, image) = run("512");
    let (large, _) = run("2048");
    assert_eq!(
        image.dimensions(),
        (160, 90),
        "the frame's size, the legend over its bottom strip"
    );
    let p = |j: &Value, k: &str| j["undersampling"][k].as_f64().unwrap();
    for j in [&small, &large] {
        assert!(j["undersampling"]["pixels"].as_u64().unwrap() > 5000, "{j}");
        assert!(
            p(j, "p50") <= p(j, "p95") && p(j, "p95") <= p(j, "p99") && p(j, "p99") <= p(j, "max")
        );
        assert!(j["area_undersampling"]["p50"].as_f64().unwrap() > 0.0);
        // One map, drawing the casters whose boxes reach it.
        let drawn = j["casters_drawn"].as_array().unwrap();
        assert_eq!(drawn.len(), 1, "{j}");
        let drawn = drawn[0].as_u64().unwrap();
        assert!(drawn > 0 && drawn <= j["casters"].as_u64().unwrap(), "{j}");
    }
    // A narrow spot light over one corner of the city: most casters are not drawn.
    let spot = dir.join("spot.png");
    let out = gnomon_ok(&[
        "render",
        "--eye",
        "-150,60,150",
        "--target",
        "-100,0,100",
        "--spot",
        "-100,60,100,0,-1,0,20,100",
        "--size",
        "160x90",
        "--out",
        spot.to_str().unwrap(),
        "--json",
    ]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let drawn = j["casters_drawn"][0].as_u64().unwrap();
    assert!(
        drawn > 0 && 10 * drawn < j["casters"].as_u64().unwrap(),
        "{j}"
    );
    // Four times the resolution: four times fewer pixels per texel, to a few percent.
    let ratio = p(&small, "p50") / p(&large, "p50");
    assert!((ratio / 4.0 - 1.0).abs() < 0.05, "p50 ratio {ratio}");
    let mut args = RENDER.to_vec();
    args.extend(["--technique", "volumes", "--error-map", "x.png"]);
    assert_eq!(gnomon(&args).status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `compare` refuses frames too large for its grids before it makes its folder.
#[test]
fn compare_refuses_frames_too_large_for_its_grids() {
    let dir = temp_dir("compare-large").join("report");
    let out = gnomon(&[
        "compare",
        "--size",
        "9000x8000",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("4096"), "{stderr}");
    assert!(!dir.exists());
}

/// Runs `gnomon compare` into `dir` and returns its report.json.
fn run_compare(
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

/// A row that refuses the first view's light (SPPSM under a lamp) is n/a there, as in any
/// other view, and the rows after it are compared: the untimed first frame, which compiles
/// the pipelines, takes the first row that can draw the light (it took the first row, and the
/// run failed).
#[test]
fn compare_starts_with_a_view_whose_light_the_first_row_refuses() {
    let dir = temp_dir("compare-refused-first");
    let report = run_compare(&dir, "street_lamp,street", "sppsm,focused", "256", "64x36");
    let rows = |view: usize| {
        report["views"][view]["techniques"]
            .as_array()
            .unwrap()
            .clone()
    };
    let lamp = rows(0);
    assert_eq!(lamp[0]["technique"], "sppsm");
    assert_eq!(lamp[0]["skipped"], "takes no point light", "{lamp:?}");
    let focused = lamp.iter().find(|r| r["technique"] == "focused").unwrap();
    assert!(
        focused["compared_pixels"].as_u64().unwrap() > 0,
        "{focused}"
    );
    // Under the sun every row draws.
    assert!(
        rows(1).iter().all(|r| r.get("skipped").is_none()),
        "{:?}",
        rows(1)
    );
}

/// `gnomon compare` renders each view with each technique and the exact volumes, and writes
/// a grid per view, a Markdown table and JSON: wrong pixels against the volumes (a 2048 map
/// is wrong on fewer pixels than a 256 one), undersampling percentiles, times.
#[test]
fn compare_has_planar_and_projective_rows() {
    let dir = temp_dir("compare-planar");
    for techniques in [
        "planar",
        "focused,planar",
        "projective,planar",
        "object-id,id-depth,planar",
    ] {
        let json = run_compare(&dir, "overview,low_sun", techniques, "512", "160x90");
        for view in 0..2 {
            let rows = json["views"][view]["techniques"].as_array().unwrap();
            let planar = rows.iter().find(|r| r["technique"] == "planar").unwrap();
            assert_eq!(planar["maps"], 0);
            assert!(
                planar["compared_pixels"].as_u64().unwrap() > 1000,
                "{planar}"
            );
            // The demo's ground carries most of its shadows.
            assert!(planar["wrong_percent"].as_f64().unwrap() < 5.0, "{planar}");
            assert!(
                planar["command"]
                    .as_str()
                    .unwrap()
                    .contains("--technique planar")
            );
            if let Some(projective) = rows.iter().find(|r| r["technique"] == "projective") {
                // The ground receives the casters' light map; the casters stay lit.
                assert!(
                    projective["wrong_percent"].as_f64().unwrap() < 5.0,
                    "{projective}"
                );
                let command = projective["command"].as_str().unwrap();
                assert!(
                    command.contains("--technique projective --shadow-map 512"),
                    "{command}"
                );
            }
            assert!(rows.iter().all(|r| r["penumbra_error"].is_null()));
            for name in ["object-id", "id-depth"] {
                if let Some(row) = rows.iter().find(|r| r["technique"] == name) {
                    // Wrong only near the outlines the light sees, at this map size.
                    assert!(row["wrong_percent"].as_f64().unwrap() < 2.0, "{row}");
                    let command = row["command"].as_str().unwrap();
                    assert!(
                        command.contains(&format!("--technique {name} --shadow-map 512")),
                        "{command}"
                    );
                }
            }
        }
        let rows = techniques.split(',').count() as u32;
        let grid = image::open(dir.join("overview.png")).unwrap();
        assert_eq!(grid.height(), (rows + 1) * 90);
    }
    let markdown = std::fs::read_to_string(dir.join("index.md")).unwrap();
    assert!(markdown.contains("| planar |"), "{markdown}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `compare --area-light R`: each map row read by depth gets the penumbra error of its filter
/// against the soft volumes of the same area light, PCSS's well below the hard shadows', and
/// commands that reproduce the rows and the reference.
#[test]
fn compare_measures_pcss_penumbrae() {
    let dir = temp_dir("compare-pcss");
    let run = |filter: &str| -> Value {
        let out = gnomon(&[
            "compare",
            "--views",
            "overview,low_sun",
            "--techniques",
            "focused,cascades-best,object-id",
            "--shadow-map",
            "1024",
            "--size",
            "160x90",
            "--pcf",
            filter,
            "--area-light",
            "2",
            "--area-samples",
            "16",
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
    };
    let hard = run("2x2");
    let pcss = run("pcss");
    for (v, view) in pcss["views"].as_array().unwrap().iter().enumerate() {
        let soft = view["soft_command"].as_str().unwrap();
        assert!(
            soft.contains("--technique volumes --size 160x90 --area-light 2 --area-samples 16"),
            "{soft}"
        );
        for (r, row) in view["techniques"].as_array().unwrap().iter().enumerate() {
            let depth = row["technique"] != "object-id";
            assert_eq!(row["penumbra_error"].is_number(), depth, "{row}");
            if !depth {
                continue;
            }
            let error = row["penumbra_error"].as_f64().unwrap();
            let hard_error = hard["views"][v]["techniques"][r]["penumbra_error"]
                .as_f64()
                .unwrap();
            assert!(row["penumbra_pixels"].as_u64().unwrap() > 0, "{row}");
            assert!(error < 0.8 * hard_error, "{row}: hard {hard_error}");
            // The row's command reproduces it.
            let command = row["command"].as_str().unwrap();
            assert!(
                command.contains("--pcf pcss --area-light 2 --out"),
                "{command}"
            );
            run_printed(command, &dir);
        }
    }
    let markdown = std::fs::read_to_string(dir.join("index.md")).unwrap();
    assert!(markdown.contains("mean penumbra error"), "{markdown}");
    let out = gnomon(&[
        "compare", "--views", "overview", "--size", "64x36", "--pcf", "pcss",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--area-light R"));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn compare_writes_grids_tables_and_json() {
    let dir = temp_dir("compare");
    let run = |shadow_map: &str| {
        run_compare(
            &dir,
            "street,low_sun",
            "focused,lispsm",
            shadow_map,
            "240x135",
        )
    };
    let coarse = run("256");
    let fine = run("2048");
    let markdown = std::fs::read_to_string(dir.join("index.md")).unwrap();
    assert!(markdown.contains("| focused |") && markdown.contains("## street"));
    for view in ["street", "low_sun"] {
        let grid = image::open(dir.join(format!("{view}.png"))).unwrap();
        // Three columns; a row per technique and one for the volumes, each the frame's size
        // (the error map's legend lies over its bottom strip).
        assert_eq!((grid.width(), grid.height()), (3 * 240, 3 * 135));
    }
    let wrong = |json: &Value, view: usize, technique: usize| {
        json["views"][view]["techniques"][technique]["wrong_percent"]
            .as_f64()
            .unwrap()
    };
    for view in 0..2 {
        for technique in 0..2 {
            let row = &fine["views"][view]["techniques"][technique];
            assert!(row["compared_pixels"].as_u64().unwrap() > 5000, "{row}");
            assert!(row["undersampling"]["p99"].as_f64().unwrap() > 0.0, "{row}");
            assert!(row["frame_ms"].as_f64().unwrap() > 0.0, "{row}");
            let (c, f) = (
                wrong(&coarse, view, technique),
                wrong(&fine, view, technique),
            );
            assert!(
                f < 5.0 && f < c,
                "view {view} technique {technique}: {f}% vs {c}%"
            );
        }
    }
    for bad in [
        vec!["compare", "--views", "nowhere"],
        vec!["compare", "--techniques", "blurry"],
    ] {
        assert_eq!(gnomon(&bad).status.code(), Some(2), "{bad:?}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// SPPSM on the command line: the setup JSON has both maps, the plane (positive side = the
/// perspective map, containing the light direction) and how the casters fall on it; render
/// tints by map and shows both maps in the light view.
#[test]
fn sppsm_setup_and_render() {
    let view = [
        "--eye",
        "120,25,190",
        "--target",
        "0,5,0",
        "--light-dir",
        "1,-0.18,0.3",
        "--shadow-map",
        "512",
    ];
    let mut args = vec![
        "setup",
        "--technique",
        "sppsm",
        "--sppsm-with",
        "lispsm",
        "--sppsm-iterations",
        "4",
        "--json",
    ];
    args.extend(view);
    let out = gnomon_ok(&args);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["technique"], "sppsm");
    assert_eq!(json["maps"].as_array().unwrap().len(), 2);
    assert_eq!(json["selection"]["kind"], "plane");
    let plane: Vec<f64> = json["selection"]["plane_world"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let d = DVec3::new(1.0, -0.18, 0.3).normalize();
    let n = DVec3::new(plane[0], plane[1], plane[2]);
    assert!(
        (n.length() - 1.0).abs() < 1e-9 && n.dot(d).abs() < 1e-9,
        "{plane:?}"
    );
    let sides = &json["diagnostics"]["casters_by_side"];
    let total = ["focused_only", "perspective_only", "both"]
        .iter()
        .map(|k| sides[k].as_u64().unwrap())
        .sum::<u64>();
    assert_eq!(
        total,
        json["diagnostics"]["relevant_casters"].as_u64().unwrap()
            + json["diagnostics"]["culled_casters"].as_u64().unwrap()
    );

    let dir = temp_dir("sppsm");
    let light = dir.join("light.png");
    let render = |tint: bool| {
        let frame = dir.join(format!("frame_{tint}.png"));
        let mut args = vec!["render", "--technique", "sppsm", "--size", "160x90"];
        args.extend(view);
        args.extend([
            "--out",
            frame.to_str().unwrap(),
            "--light-view",
            light.to_str().unwrap(),
        ]);
        if tint {
            args.push("--tint");
        }
        gnomon_ok(&args);
        let frame = image::open(&frame).unwrap().into_rgb8();
        let red = frame
            .pixels()
            .filter(|p| p.0[0] as i32 > p.0[2] as i32 + 20)
            .count();
        let blue = frame
            .pixels()
            .filter(|p| p.0[2] as i32 > p.0[0] as i32 + 20)
            .count();
        (red, blue)
    };
    let ((red, blue), (plain_red, plain_blue)) = (render(true), render(false));
    let light_view = image::open(&light).unwrap();
    assert_eq!(
        (light_view.width(), light_view.height()),
        (1024, 512),
        "both maps side by side"
    );
    // The tint turns the perspective map's pixels red and the focused map's blue.
    assert!(
        red > plain_red + 200 && blue > plain_blue + 200,
        "{red} / {plain_red} red, {blue} / {plain_blue} blue"
    );
    let mut bad = vec!["setup", "--technique", "sppsm", "--sppsm-iterations", "0"];
    bad.extend(view);
    assert_eq!(gnomon(&bad).status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Each bad input a new user met (the robustness issue's list): exit code 2, one line on
/// stderr that says what is wrong, no panic, and no file written.
#[test]
fn bad_options_and_outputs_are_refused_before_any_work() {
    let dir = temp_dir("refused");
    let file = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (frame, jpg, error_jpg) = (file("frame.png"), file("x.jpg"), file("e.jpg"));
    let nested = file("missing/deeper/x.png");
    let dir_path = dir.to_str().unwrap().to_string();
    let zero_link = file("zero.off");
    std::os::unix::fs::symlink("/dev/zero", &zero_link).unwrap();
    // An OFF file shorter than its header says.
    let short_off = file("short.off");
    std::fs::write(&short_off, "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    // Any closed mesh of the repository's tests will do; the knot is fetched by
    // scripts/fetch-meshes.sh, so a cube written here stands in for it.
    let knot = file("cube.off");
    std::fs::write(
        &knot,
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
         4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n",
    )
    .unwrap();
    let render = |extra: &[&str]| {
        let mut args: Vec<String> = RENDER.iter().map(|s| s.to_string()).collect();
        if !extra.contains(&"--out") {
            args.extend(["--out".into(), frame.clone()]);
        }
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    let plain = |args: &[&str]| args.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            render(&["--technique", "volumes-z-pass", "--stencil", "z-fail"]),
            "drop --stencil",
        ),
        (render(&["--technique", "nope"]), "volumes-per-caster"),
        (
            plain(&[
                "setup",
                "--eye",
                "0,2,0",
                "--target",
                "1,2,0",
                "--light-dir",
                "0,-1,0",
                "--technique",
                "volumes",
            ]),
            "needs a shadow-map technique",
        ),
        (render(&["--bias-constant", "nan"]), "bias-constant"),
        (render(&["--normal-offset", "nan"]), "normal-offset"),
        (render(&["--bias-slope", "inf"]), "bias-slope"),
        (render(&["--bias-constant", "-0.1"]), "bias-constant"),
        (render(&["--normal-offset", "1e9"]), "normal-offset"),
        (render(&["--out", &jpg]), ".png"),
        (render(&["--error-map", &error_jpg]), ".png"),
        (render(&["--mask", "/proc/m.png"]), "cannot be written"),
        (render(&["--out", &dir_path]), "folder"),
        (render(&["--out", &nested]), "does not exist"),
        (render(&["--tint"]), "--tint"),
        (render(&["--stencil", "z-pass"]), "--stencil"),
        (
            render(&["--lispsm-n", "5"]),
            "--lispsm-n does nothing for focused",
        ),
        (render(&["--mesh", &zero_link]), "not a regular file"),
        (
            render(&["--mesh", &short_off]),
            "declares 4 vertices and 1 faces",
        ),
        (
            render(&["--mesh", &knot, "--mesh-height", "1e12"]),
            "height must be a positive number up to 1e7",
        ),
        (render(&["--aspect", "1e30"]), "from 1e-6 to 1e6"),
        (
            plain(&[
                "analyze",
                "--zn",
                "1",
                "--zf",
                "100",
                "--psm-slide-back",
                "1e12",
            ]),
            "psm slide back",
        ),
        (
            plain(&[
                "analyze",
                "--zn",
                "1",
                "--zf",
                "100",
                "--plot",
                &file("x.png"),
            ]),
            ".svg",
        ),
        (
            plain(&["demo", "--width", "0", "--out", &file("demo")]),
            "width",
        ),
        (
            plain(&["demo", "--width", "100000", "--out", &file("demo")]),
            "width",
        ),
        (
            plain(&[
                "compare",
                "--techniques",
                "focused,focused",
                "--out",
                &file("report"),
            ]),
            "twice",
        ),
    ];
    for (args, expected) in &cases {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = gnomon(&refs);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(
            stderr.contains(expected),
            "{args:?}: expected '{expected}' in {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    // Nothing was written: the folder holds only the link made above.
    let mut left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    left.sort();
    assert_eq!(
        left,
        vec![
            std::ffi::OsString::from("cube.off"),
            std::ffi::OsString::from("short.off"),
            std::ffi::OsString::from("zero.off")
        ],
        "{left:?}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render`'s lens follows the image's aspect unless `--aspect` is given.
#[test]
fn the_aspect_follows_the_image_unless_given() {
    let dir = temp_dir("aspect");
    let render = |name: &str, extra: &[&str]| {
        let path = dir.join(name);
        // RENDER's 160x90 made square.
        let mut args: Vec<&str> = RENDER
            .iter()
            .map(|a| if *a == "160x90" { "120x120" } else { *a })
            .collect();
        args.extend(["--out", path.to_str().unwrap()]);
        args.extend(extra);
        gnomon_ok(&args);
        std::fs::read(path).unwrap()
    };
    let default = render("default.png", &[]);
    assert_eq!(default, render("square.png", &["--aspect", "1"]));
    assert_ne!(default, render("wide.png", &["--aspect", "1.7778"]));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `gnomon analyze --json | head`: the closed pipe ends the program quietly.
#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args([
            "analyze",
            "--zn",
            "1",
            "--zf",
            "100",
            "--json",
            "--samples",
            "2000",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read a little, then close the pipe, as `head -c 10` does.
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 10];
    std::io::Read::read_exact(&mut stdout, &mut first).unwrap();
    drop(stdout);
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}

/// Every cell of `compare`'s report says the `gnomon render` command that draws it, and that
/// command reproduces the cell's frame.
#[test]
fn compare_cells_are_reproduced_by_their_render_commands() {
    let dir = temp_dir("reproduce");
    let report = run_compare(&dir, "street", "lispsm", "512", "160x90");
    let row = &report["views"][0]["techniques"][0];
    let command = row["command"].as_str().unwrap();
    assert!(command.starts_with("gnomon render "), "{command}");
    let markdown = std::fs::read_to_string(dir.join("index.md")).unwrap();
    assert!(markdown.contains(command), "the report lists the command");
    // Run it, writing into the test's folder.
    let frame = dir.join("frame.png");
    let args: Vec<String> = command
        .split_whitespace()
        .skip(1)
        .map(|a| match a {
            "frame.png" => frame.to_str().unwrap().to_string(),
            "mask.png" => dir.join("mask.png").to_str().unwrap().to_string(),
            "error.png" => dir.join("error.png").to_str().unwrap().to_string(),
            other => other.to_string(),
        })
        .collect();
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = gnomon(&refs);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // The grid's first cell is the frame.
    let grid = image::open(dir.join("street.png")).unwrap().to_rgba8();
    let single = image::open(&frame).unwrap().to_rgba8();
    let (w, h) = single.dimensions();
    assert_eq!((w, h), (160, 90));
    let mut differing = 0;
    for y in 0..h {
        for x in 0..w {
            if grid.get_pixel(x, y) != single.get_pixel(x, y) {
                differing += 1;
            }
        }
    }
    assert_eq!(
        differing, 0,
        "{differing} pixels differ from the report's cell"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The warp limit at compare's settings (640x360, 2048 maps, every named view): no warp's
/// wrong-pixel share exceeds the focused map's by more than 20% plus 0.03 percentage points
/// (and one pixel, for ties at shadow edges), and none has a 95th percentile of undersampling
/// above the focused map's; where the limit fired the fallback says so. Without the limit
/// XPSM breaks the rule in `light_behind` (it did before the limit). (The slack was 0.02
/// points until the normal offset came to be measured along the normal's image in the map:
/// TSM in `dueling_frusta` then read 91 of 44712 pixels wrong against the focused map's 67,
/// single pixels along shadow edges, while sampling finer, p95 4.90 against 5.49.)
#[test]
fn no_warp_samples_worse_than_the_focused_map() {
    let dir = temp_dir("warp-limit");
    let report = run_compare(
        &dir,
        "all",
        "focused,psm,lispsm,tsm,xpsm",
        "2048",
        "640x360",
    );
    let mut limited = 0;
    for view in report["views"].as_array().unwrap() {
        // A point light's warps are limited per cube face, on that face's samples; the
        // frame's percentile over all faces is not what each limit compares.
        if view["light"]["point"].is_object() {
            continue;
        }
        let rows = view["techniques"].as_array().unwrap();
        let row = |name: &str| rows.iter().find(|r| r["technique"] == name).unwrap();
        let focused = row("focused");
        let f_wrong = focused["wrong_percent"].as_f64().unwrap();
        let f_p95 = focused["undersampling"]["p95"].as_f64().unwrap();
        for name in ["psm", "lispsm", "tsm", "xpsm"] {
            let r = row(name);
            let pixel = 100.0 / r["compared_pixels"].as_f64().unwrap();
            let wrong = r["wrong_percent"].as_f64().unwrap();
            let p95 = r["undersampling"]["p95"].as_f64().unwrap();
            let at = format!("{} {name}: {r}", view["view"]);
            assert!(wrong <= 1.2 * f_wrong + 0.03 + pixel, "{at}");
            assert!(p95 <= f_p95 * (1.0 + 1e-6), "{at} against {f_p95}");
            if let Some(fallback) = r["fallback"].as_str() {
                limited += usize::from(fallback.starts_with("warp_"));
            }
        }
    }
    assert!(limited >= 4, "the limit fired in {limited} cells");
    // Without the limit the rule breaks.
    gnomon_ok(&[
        "compare",
        "--views",
        "light_behind",
        "--techniques",
        "focused,xpsm",
        "--no-warp-limit",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let rows = &report["views"][0]["techniques"];
    let p95 = |k: usize| rows[k]["undersampling"]["p95"].as_f64().unwrap();
    assert!(p95(1) > 2.0 * p95(0), "{rows}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Cascades on the command line: `analyze` reproduces the issue's table from the matrices
/// (four log slices sharing one map's texels: focused about 4.33, LiSPSM at most 2.5), the
/// setup JSON names the slices, render tints them, and bad cascade options are one line and
/// exit code 2.
#[test]
fn cascades_on_the_command_line() {
    let analyze = |fit: &str| -> f64 {
        let out = gnomon_ok(&[
            "analyze",
            "--zn",
            "1",
            "--zf",
            "100",
            "--cascades",
            "4",
            "--cascade-split",
            "log",
            "--equal-texels",
            "--cascade-fit",
            fit,
            "--json",
        ]);
        let json: Value = serde_json::from_slice(&out.stdout).unwrap();
        technique_row(&json, "cascades")["max"].as_f64().unwrap()
    };
    let (focused, lispsm) = (analyze("focused"), analyze("lispsm"));
    assert!((focused / 4.33 - 1.0).abs() < 0.02, "{focused}");
    assert!(lispsm <= 2.5 && lispsm > 2.3, "{lispsm}");

    let view = [
        "--eye",
        "-190,14,58",
        "--target",
        "0,4,10",
        "--light-dir",
        "0.85,-0.4,-0.15",
    ];
    let mut setup = vec!["setup", "--technique", "cascades", "--json"];
    setup.extend(view);
    setup.extend(["--cascades", "3", "--cascade-split", "20,80"]);
    let json: Value = serde_json::from_slice(&gnomon_ok(&setup).stdout).unwrap();
    assert_eq!(json["selection"]["kind"], "cascades", "{json}");
    assert_eq!(json["maps"].as_array().unwrap().len(), 3);
    let depths: Vec<f64> = json["selection"]["view_depths"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(depths[1..3], [20.0, 80.0]);
    assert_eq!(json["selection"]["select"], "view_depth", "{json}");
    // Stable cascades pick by coverage unless asked for view depth.
    for (extra, select) in [
        (vec![], "coverage"),
        (vec!["--cascade-select", "depth"], "view_depth"),
        (vec!["--cascade-select", "coverage"], "coverage"),
    ] {
        let mut args = vec!["setup", "--technique", "cascades", "--json", "--stable"];
        args.extend(view);
        args.extend(&extra);
        let json: Value = serde_json::from_slice(&gnomon_ok(&args).stdout).unwrap();
        assert_eq!(json["selection"]["select"], select, "{extra:?}: {json}");
    }

    let dir = temp_dir("cascades");
    let out = dir.join("tinted.png");
    let mut render = vec![
        "render",
        "--technique",
        "cascades",
        "--tint",
        "--size",
        "160x90",
    ];
    render.extend(view);
    render.extend(["--out", out.to_str().unwrap()]);
    gnomon_ok(&render);
    assert!(out.exists());

    for (bad, expected) in [
        (vec!["--cascades", "9"], "cascade count"),
        (
            vec!["--cascades", "3", "--cascade-split", "80,20"],
            "split distance",
        ),
        (
            vec!["--cascades", "4", "--cascade-split", "20,80"],
            "split distances",
        ),
        (vec!["--cascade-split", "sideways"], "first-log"),
        (vec!["--cascade-lambda", "2"], "lambda"),
        (vec!["--cascade-blend", "0.7"], "blend"),
        (vec!["--shadow-distance", "-5"], "shadow distance"),
        (
            vec!["--stable", "--cascade-fit", "lispsm"],
            "--cascade-fit does nothing",
        ),
        (
            vec!["--cascade-select", "coverage"],
            "only when they are stable",
        ),
        (vec!["--cascade-select", "sideways"], "coverage"),
    ] {
        let mut args = vec!["setup", "--technique", "cascades"];
        args.extend(view);
        args.extend(&bad);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{bad:?}: {stderr}");
        assert!(stderr.contains(expected), "{bad:?}: {stderr}");
    }
    // Cascade options with another technique do nothing: refused.
    let mut args = vec!["setup", "--technique", "focused", "--cascades", "3"];
    args.extend(view);
    let out = gnomon(&args);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `gnomon flicker`: stable cascades keep their shadows still while the camera dollies and
/// pans (false flicker at most 0.01% on two named views), where the focused map swims; bad
/// paths and sizes are one line and exit code 2.
#[test]
fn stable_cascades_do_not_flicker() {
    for (view, path) in [("street", "dolly"), ("light_behind", "pan")] {
        let out = gnomon_ok(&[
            "flicker",
            "--view",
            view,
            "--path",
            path,
            "--frames",
            "8",
            "--size",
            "200x112",
            "--techniques",
            "focused,cascades-stable",
            "--json",
        ]);
        let json: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["path"], path);
        let (focused, stable) = (
            technique_row(&json, "focused"),
            technique_row(&json, "cascades-stable"),
        );
        assert!(stable["judged"].as_u64().unwrap() > 10_000, "{stable}");
        let (f, s) = (
            focused["false_flicker"].as_f64().unwrap(),
            stable["false_flicker"].as_f64().unwrap(),
        );
        println!("{view} {path}: focused {f}, stable {s}");
        assert!(s <= 1e-4, "{view} {path}: {stable}");
        assert!(f > 1e-3, "{view} {path}: {focused}");
        assert!(
            stable["command"]
                .as_str()
                .unwrap()
                .contains("--techniques cascades-stable")
        );
    }
    for (bad, expected) in [
        (vec!["--view", "street", "--frames", "1"], "frames"),
        (vec!["--view", "street", "--size", "1000x20"], "512"),
        (
            vec![
                "--eye",
                "0,5,0",
                "--target",
                "10,0,0",
                "--spot",
                "0,20,0,0,-1,0,30,100",
                "--path",
                "sun",
            ],
            "directional",
        ),
        (
            vec!["--view", "street", "--techniques", "blurry"],
            "unknown technique",
        ),
        (vec!["--view", "street", "--step", "-1"], "step"),
    ] {
        let mut args = vec!["flicker"];
        args.extend(&bad);
        let out = gnomon(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{bad:?}: {stderr}");
        assert!(stderr.contains(expected), "{bad:?}: {stderr}");
    }
}

/// A scene file in `dir`: two cubes from one OFF file (one scaled, one turned and coloured)
/// on a ground slab, a view under the sun and one under a spot light.
fn write_scene_file(dir: &std::path::Path) -> std::path::PathBuf {
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

/// `render` warns when casters reach within a spot or point light's near distance, where the
/// maps clip them (a lamp at a cube's wall shines out through the clipped face), and says
/// nothing for a lamp in the open or well inside a box.
#[test]
fn render_warns_of_casters_at_the_light() {
    let dir = temp_dir("near-clip");
    let scene = write_scene_file(&dir);
    let out_png = dir.join("lamp.png");
    let render = |point: &str| {
        let out = gnomon(&[
            "render",
            "--scene-file",
            scene.to_str().unwrap(),
            "--view",
            "sun",
            "--point",
            point,
            "--technique",
            "cube",
            "--size",
            "96x54",
            "--out",
            out_png.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        stderr
    };
    // Inside the cube at x -3 to -1, y 0 to 2, 0.02 mm below its top: nearer than the near
    // distance (a millionth of the range, 5e-5 m), so the top is clipped.
    let at_the_wall = render("-2,1.99998,1,50");
    assert!(
        at_the_wall.contains("warning:") && at_the_wall.contains("near distance (5.000e-5 m"),
        "{at_the_wall}"
    );
    // 2 cm below its top: the cube's box holds the light, but its walls lie beyond the near
    // plane and lose nothing.
    let inside = render("-2,1.98,1,50");
    assert!(!inside.contains("near distance"), "{inside}");
    let open = render("0,6,0,50");
    assert!(!open.contains("near distance"), "{open}");
}

/// `--scene-file` in setup (no GPU): its named views give the camera and the light, explicit
/// options override them, and an unknown view lists the file's.
#[test]
fn setup_reads_a_scene_file_and_its_views() {
    let dir = temp_dir("scene-file-setup");
    let file = write_scene_file(&dir);
    let file = file.to_str().unwrap();
    let setup = |extra: &[&str]| -> Value {
        let mut args = vec!["setup", "--scene-file", file, "--json"];
        args.extend_from_slice(extra);
        serde_json::from_slice(&gnomon_ok(&args).stdout).unwrap()
    };
    let sun = setup(&["--view", "sun"]);
    assert_eq!(sun["diagnostics"]["relevant_casters"], 2, "{sun}");
    assert_eq!(sun["diagnostics"]["visible_receivers"], 3, "{sun}");
    let explicit = setup(&[
        "--eye",
        "14,10,16",
        "--target",
        "0,1,0",
        "--far",
        "100",
        "--light-dir",
        "0.6,-1,-0.2",
    ]);
    assert_eq!(sun["maps"], explicit["maps"]);
    // The spot view: a perspective map; its field of view applies unless given.
    let lamp = setup(&["--view", "lamp"]);
    assert_eq!(lamp["maps"][0]["projection"], "perspective", "{lamp}");
    let wider = setup(&["--view", "lamp", "--fov", "70"]);
    assert_ne!(lamp["maps"], wider["maps"]);
    let same = setup(&["--view", "lamp", "--fov", "50", "--near", "0.5"]);
    assert_eq!(lamp["maps"], same["maps"]);
    let out = gnomon(&["setup", "--scene-file", file, "--view", "nope"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("known: sun, lamp, two suns"), "{stderr}");
    // A view of two lights: setup takes the first and says so.
    let out = gnomon_ok(&[
        "setup",
        "--scene-file",
        file,
        "--view",
        "two suns",
        "--json",
    ]);
    let two: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(two["maps"], sun["maps"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("has 2 lights; setup uses the first"));
    let out = gnomon(&[
        "setup",
        "--scene-file",
        file,
        "--mesh",
        file,
        "--view",
        "sun",
    ]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A broken scene file (unknown key, missing mesh, bad number, no light) is one line naming
/// the file, the line and the key, and exit code 2, in every command.
#[test]
fn broken_scene_files_give_one_line_and_exit_code_2() {
    let dir = temp_dir("scene-file-errors");
    write_off_cube(&dir);
    let cases = [
        (
            "[ground]\nsize = 10\n\n[[object]]\nmesh = \"cube.off\"\nscael = 2\n",
            6,
            "scael",
            "unknown field",
        ),
        (
            "[[object]]\nmesh = \"cube.off\"\n\n[[object]]\nmesh = \"gone.off\"\n",
            5,
            "mesh",
            "gone.off",
        ),
        (
            "[[object]]\nmesh = \"cube.off\"\nscale = \"two\"\n",
            3,
            "scale",
            "a scale is a positive number",
        ),
        (
            "[[object]]\nmesh = \"cube.off\"\nscale = -2\n",
            3,
            "scale",
            "positive",
        ),
        (
            "[[object]]\nmesh = \"cube.off\"\ntranslate = [0, inf, 0]\n",
            3,
            "translate",
            "finite",
        ),
        (
            "[[object]]\nmesh = \"cube.off\"\n\n[[view]]\nname = \"v\"\neye = [5, 5, 5]\ntarget = [0, 0, 0]\n",
            4,
            "view",
            "needs a light",
        ),
    ];
    for (k, (text, line, key, says)) in cases.iter().enumerate() {
        let path = dir.join(format!("broken{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        for command in [
            vec![
                "setup",
                "--scene-file",
                p,
                "--eye",
                "5,5,5",
                "--target",
                "0,0,0",
                "--light-dir",
                "0,-1,0",
            ],
            vec!["render", "--scene-file", p, "--view", "v"],
            vec!["export", "--scene-file", p, "--obj", "out.obj"],
        ] {
            let out = gnomon(&command);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{text}: {stderr}");
            assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
            let place = format!("{p}:{line}: key '{key}'");
            assert!(
                stderr.contains(&place) && stderr.contains(says),
                "{text}: expected '{place}' and '{says}' in {stderr}"
            );
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// A scene file through the commands that draw: render's map mask agrees with its exact
/// volumes, export writes every object, compare's cells carry `--scene-file` and their
/// commands run, and demo, bench and flicker go over its views.
#[test]
fn scene_files_work_in_every_command() {
    let dir = temp_dir("scene-file-commands");
    let file = write_scene_file(&dir);
    let file = file.to_str().unwrap();
    let mask = |technique: &str, view: &str| {
        let path = dir.join(format!("{technique}-{view}.png"));
        let frame = dir.join("frame.png");
        gnomon_ok(&[
            "render",
            "--scene-file",
            file,
            "--view",
            view,
            "--technique",
            technique,
            "--size",
            "256x144",
            "--out",
            frame.to_str().unwrap(),
            "--mask",
            path.to_str().unwrap(),
        ]);
        image::open(&path).unwrap().into_luma8()
    };
    // Lit by either of two suns: less shadow than under the first alone.
    let sun_shadow = mask("volumes", "sun")
        .pixels()
        .filter(|p| p.0[0] == 0)
        .count();
    let two_shadow = mask("volumes", "two suns")
        .pixels()
        .filter(|p| p.0[0] == 0)
        .count();
    assert!(
        two_shadow * 4 < sun_shadow * 3,
        "{two_shadow} shadowed pixels with two suns, {sun_shadow} with one"
    );
    for view in ["sun", "lamp", "two suns"] {
        let exact = mask("volumes", view);
        let map = mask("lispsm", view);
        let (mut judged, mut differ) = (0, 0);
        for (a, b) in exact.pixels().zip(map.pixels()) {
            if a.0[0] != 128 && b.0[0] != 128 {
                judged += 1;
                differ += usize::from(a != b);
            }
        }
        let shadowed = exact.pixels().filter(|p| p.0[0] == 0).count();
        assert!(shadowed > 100, "{view}: {shadowed} shadowed pixels");
        assert!(
            differ * 100 <= judged,
            "{view}: {differ} of {judged} pixels differ"
        );
    }
    let obj = dir.join("scene.obj");
    gnomon_ok(&[
        "export",
        "--scene-file",
        file,
        "--obj",
        obj.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&obj).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 3 * 12);
    assert_eq!(text.lines().filter(|l| l.starts_with("o ")).count(), 3);
    let report = dir.join("compare");
    gnomon_ok(&[
        "compare",
        "--scene-file",
        file,
        "--views",
        "sun,lamp,two suns",
        "--techniques",
        "focused",
        "--size",
        "128x72",
        "--shadow-map",
        "512",
        "--out",
        report.to_str().unwrap(),
    ]);
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(json["scene"], "two cubes");
    assert!(json["views"][1]["light"]["spot"]["range"] == 60.0, "{json}");
    let command = json["views"][1]["techniques"][0]["command"]
        .as_str()
        .unwrap();
    assert!(command.contains("--scene-file '"), "{command}");
    // The command as a shell runs it (the file's name has a space: it is quoted).
    run_printed(command, &dir);
    let demo = dir.join("demo");
    gnomon_ok(&[
        "demo",
        "--scene-file",
        file,
        "--views",
        "lamp",
        "--width",
        "64",
        "--shadow-map",
        "256",
        "--out",
        demo.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(demo.join("index.html")).unwrap();
    assert!(html.contains("two cubes") && html.contains("a spot light over the cubes"));
    let out = gnomon_ok(&[
        "bench",
        "--scene-file",
        file,
        "--frames",
        "1",
        "--techniques",
        "focused",
        "--size",
        "64x36",
        "--json",
    ]);
    let bench: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(bench.to_string().contains("\"lamp\""), "{bench}");
    gnomon_ok(&[
        "flicker",
        "--scene-file",
        file,
        "--view",
        "sun",
        "--frames",
        "2",
        "--techniques",
        "focused",
        "--size",
        "64x36",
    ]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `compare --suite` and `bench --suite` go over every scene file of a folder: a report per
/// scene and a summary; a scene whose model is missing fails before any work, naming the
/// fetch script.
#[test]
fn compare_and_bench_go_over_a_suite() {
    let dir = temp_dir("suite");
    write_scene_file(&dir);
    std::fs::copy(dir.join("two cubes.toml"), dir.join("again.toml")).unwrap();
    let out = dir.join("report");
    gnomon_ok(&[
        "compare",
        "--suite",
        dir.to_str().unwrap(),
        "--techniques",
        "focused",
        "--size",
        "64x36",
        "--shadow-map",
        "256",
        "--out",
        out.to_str().unwrap(),
    ]);
    let index = std::fs::read_to_string(out.join("index.md")).unwrap();
    for scene in ["again", "two cubes"] {
        assert!(
            index.contains(&format!(
                "| [{scene}]({}/index.md) | 3 | focused |",
                scene.replace(' ', "%20")
            )),
            "{index}"
        );
        assert!(out.join(scene).join("report.json").is_file());
    }
    let bench = gnomon_ok(&[
        "bench",
        "--suite",
        dir.to_str().unwrap(),
        "--techniques",
        "focused",
        "--frames",
        "1",
        "--size",
        "64x36",
        "--json",
    ]);
    let bench: Value = serde_json::from_slice(&bench.stdout).unwrap();
    let views: Vec<&str> = bench["results"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["view"].as_str().unwrap())
        .collect();
    assert_eq!(
        views,
        [
            "again/sun",
            "again/lamp",
            "again/two suns",
            "two cubes/sun",
            "two cubes/lamp",
            "two cubes/two suns"
        ]
    );
    std::fs::write(
        dir.join("broken.toml"),
        "[[object]]\nmesh = \"models/gone.obj\"\n",
    )
    .unwrap();
    let failed = gnomon(&[
        "compare",
        "--suite",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&failed.stderr);
    assert_eq!(failed.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("broken.toml:2: key 'mesh'") && stderr.contains("fetch-suite.sh"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The built-in city: 10^4 buildings, its named views, and a setup over thousands of casters.
#[test]
fn the_city_scene_has_many_casters_and_its_views() {
    let out = gnomon_ok(&["setup", "--scene", "city", "--view", "avenue", "--json"]);
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let casters = json["diagnostics"]["relevant_casters"].as_u64().unwrap();
    assert!(casters > 1000, "{json}");
    let out = gnomon(&["setup", "--scene", "city", "--view", "street"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr.contains("known: overview, avenue, dueling_frusta"),
        "{stderr}"
    );
}
