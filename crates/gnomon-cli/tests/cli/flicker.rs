//! `gnomon flicker`: stable cascades along camera paths.

use super::common::*;

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
