//! Mesh files, scene files and the city in every command; `gnomon export`.

use super::common::*;

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
