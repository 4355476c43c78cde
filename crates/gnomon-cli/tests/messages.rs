//! What a new user reads: one-line messages that name the real range of an option, the files a
//! command wrote, and no driver noise (Mesa's XDG_RUNTIME_DIR error) on a headless machine.

use std::process::{Command, Output};

fn gnomon(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Exit code 2 and one line on stderr that contains `expected`.
fn refused(args: &[&str], expected: &str) {
    let out = gnomon(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: {stderr}");
}

const STREET: [&str; 4] = ["--scene", "demo", "--view", "street"];

#[test]
fn a_negative_size_is_named_as_such() {
    for size in ["-640x480", "640x-480"] {
        let mut args = vec!["render", "--size", size];
        args.extend(STREET);
        refused(&args, "negative size");
    }
}

#[test]
fn shadow_map_sizes_out_of_range_name_the_real_range() {
    for size in [
        "--shadow-map=-5",
        "--shadow-map=100000",
        "--shadow-map=4",
        "--shadow-map=x",
    ] {
        let mut args = vec!["setup", size];
        args.extend(STREET);
        refused(&args, "give 8 to 32768 texels");
    }
    // The range's ends are taken.
    for size in ["--shadow-map=8", "--shadow-map=32768"] {
        let mut args = vec!["setup", size];
        args.extend(STREET);
        assert!(gnomon(&args).status.success(), "{size}");
    }
}

#[test]
fn setup_names_the_focus_body_in_words() {
    let mut args = vec!["setup", "--technique", "lispsm"];
    args.extend(STREET);
    let out = gnomon(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("focus body B of "), "{text}");
    assert!(!text.contains("B has 0 vertices"), "{text}");
    // Uniform maps compute no B, and say so.
    let mut args = vec!["setup", "--technique", "uniform"];
    args.extend(STREET);
    let text = String::from_utf8_lossy(&gnomon(&args).stdout).to_string();
    assert!(text.contains("no focus body B"), "{text}");
}

/// Without `NODEVICE_SELECT` in the environment, a command that opens the GPU prints no Mesa
/// device-select noise, and `render`'s closing line lists every file it wrote.
#[test]
fn render_is_quiet_and_lists_what_it_wrote() {
    let dir = std::env::temp_dir().join(format!("gnomon-messages-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (frame, mask, light) = (file("frame.png"), file("mask.png"), file("light.png"));
    let mut args = vec!["render", "--size", "64x36", "--shadow-map", "256"];
    args.extend(STREET);
    args.extend(["--out", &frame, "--mask", &mask, "--light-view", &light]);
    let out = Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(&args)
        .env_remove("NODEVICE_SELECT")
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    for path in [&frame, &mask, &light] {
        assert!(std::path::Path::new(path).exists(), "{path}");
        assert!(
            stderr.contains(path.as_str()),
            "{path} not listed: {stderr}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}
