//! `gnomon render`: the frame, mask and light view, filters, volumes, the lecture's other
//! techniques, soft shadows, errors.

use super::common::*;

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
