//! `gnomon setup`: the JSON's shape and what its maps cover, each light kind, fallbacks, SPPSM and
//! cascades.

use super::common::*;

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

/// Cascades on the command line: `analyze` reproduces the table from the matrices
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
