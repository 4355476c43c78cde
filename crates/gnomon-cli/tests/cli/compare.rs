//! `gnomon compare`: grids, tables and JSON, rows that refuse a light, planar and projective rows,
//! PCSS, the warp limit, suites.

use super::common::*;

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
