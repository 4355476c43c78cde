//! `gnomon view` in a window under Xvfb (on whatever backend `WGPU_BACKEND` picks: CI runs
//! these on Vulkan and on GL): its screenshots against `gnomon render` of the same frame, the
//! command it prints after a scripted run, its errors. Without Xvfb or an adapter they fail.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gnomon-view-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// One Xvfb at a time: `xvfb-run -a` picks a free display, and parallel starts can race.
static XVFB: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `gnomon view ARGS` in a 1280x720 Xvfb screen.
fn view(args: &[&str], dir: &Path) -> Output {
    let _one = XVFB.lock().unwrap_or_else(|e| e.into_inner());
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(env!("CARGO_BIN_EXE_gnomon"))
        .arg("view")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("xvfb-run runs (apt-get install -y xvfb xauth; scripts/test.sh installs them)");
    assert!(
        out.status.success(),
        "gnomon view {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs a `gnomon render ...` command line (as printed: no quoting needed here) writing `out`.
fn render(command: &str, out: &Path, dir: &Path) {
    let words: Vec<&str> = command.split_whitespace().collect();
    assert_eq!(words[..2], ["gnomon", "render"], "{command}");
    let status = Command::new(env!("CARGO_BIN_EXE_gnomon"))
        .args(&words[1..])
        .arg("--out")
        .arg(out)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&status.stderr)
    );
}

/// The share of pixels whose colours differ by at most 2 levels in every channel (rounding),
/// after checking that the images have the same size.
fn agreement(a: &Path, b: &Path) -> f64 {
    let a = image::open(a).unwrap().to_rgb8();
    let b = image::open(b).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), b.dimensions());
    let same = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).all(|(x, y)| x.abs_diff(y) <= 2))
        .count();
    same as f64 / (a.width() * a.height()) as f64
}

/// The last line of stdout: the render command of the last frame.
fn printed_command(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .last()
        .expect("a command on stdout")
        .to_string()
}

#[test]
fn the_screenshot_matches_render_of_the_same_view() {
    let dir = temp_dir("shot");
    for technique in ["lispsm", "volumes"] {
        let shot = dir.join(format!("{technique}.png"));
        let out = view(
            &[
                "--view",
                "overview",
                "--technique",
                technique,
                "--size",
                "640x360",
                "--no-ui",
                "--frames",
                "5",
                "--screenshot",
                shot.to_str().unwrap(),
            ],
            &dir,
        );
        let image = image::open(&shot).unwrap();
        assert_eq!((image.width(), image.height()), (640, 360));
        let reference = dir.join(format!("{technique}-render.png"));
        render(
            &format!("gnomon render --view overview --technique {technique} --size 640x360"),
            &reference,
            &dir,
        );
        let share = agreement(&shot, &reference);
        assert!(share >= 0.99, "{technique}: {share} of the pixels agree");
        // The printed command draws the same frame.
        let command = printed_command(&out);
        let again = dir.join(format!("{technique}-again.png"));
        render(&command, &again, &dir);
        assert!(agreement(&shot, &again) >= 0.99, "{command}");
    }
}

#[test]
fn a_scripted_run_moves_the_camera_and_the_sun_and_its_command_reproduces_the_frame() {
    let dir = temp_dir("script");
    let script = dir.join("moves.jsonl");
    std::fs::write(
        &script,
        "{\"frame\": 1, \"key\": \"W\", \"down\": true}\n\
         {\"frame\": 3, \"key\": \"W\", \"down\": false}\n\
         {\"frame\": 3, \"drag\": [40, -10], \"button\": \"right\"}\n\
         {\"frame\": 4, \"drag\": [-30, 20], \"button\": \"left\"}\n\
         {\"frame\": 5, \"drag\": [60, 15], \"button\": \"middle\"}\n\
         {\"frame\": 6, \"scroll\": 2}\n\
         {\"frame\": 6, \"key\": \"Up\", \"down\": true}\n\
         {\"frame\": 8, \"key\": \"Up\", \"down\": false}\n",
    )
    .unwrap();
    let still = view(
        &["--view", "overview", "--size", "800x360", "--frames", "2"],
        &dir,
    );
    let shot = dir.join("moved.png");
    // With the panel: the 3D view is the window right of it.
    let moved = view(
        &[
            "--view",
            "overview",
            "--technique",
            "focused",
            "--size",
            "800x360",
            "--frames",
            "10",
            "--script",
            script.to_str().unwrap(),
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        &dir,
    );
    let (before, after) = (printed_command(&still), printed_command(&moved));
    let option = |command: &str, name: &str| {
        command
            .split_whitespace()
            .find(|w| w.starts_with(name))
            .unwrap_or_else(|| panic!("no {name} in {command}"))
            .to_string()
    };
    for name in ["--eye=", "--target=", "--light-dir="] {
        assert_ne!(option(&before, name), option(&after, name), "{name}");
    }
    let image = image::open(&shot).unwrap();
    let words: Vec<&str> = after.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "--size").unwrap();
    assert_eq!(
        words[at + 1],
        format!("{}x{}", image.width(), image.height())
    );
    assert!(
        image.width() < 800 && image.height() == 360,
        "the panel takes the left"
    );
    let again = dir.join("again.png");
    render(&after, &again, &dir);
    let share = agreement(&shot, &again);
    assert!(share >= 0.99, "{after}: {share}");
}

/// The share of pixels in columns `columns` whose colours agree within rounding.
fn agreement_in(a: &Path, b: &Path, columns: std::ops::Range<u32>) -> f64 {
    let a = image::open(a).unwrap().to_rgb8();
    let b = image::open(b).unwrap().to_rgb8();
    let (mut same, mut all) = (0usize, 0usize);
    for y in 0..a.height() {
        for x in columns.clone() {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            all += 1;
            same += usize::from(p.0.iter().zip(q.0).all(|(s, t)| s.abs_diff(t) <= 2));
        }
    }
    same as f64 / all as f64
}

#[test]
fn split_screen_draws_each_technique_on_its_side() {
    let dir = temp_dir("split");
    let shot = dir.join("split.png");
    view(
        &[
            "--view",
            "overview",
            "--technique",
            "lispsm",
            "--split",
            "volumes",
            "--size",
            "320x180",
            "--no-ui",
            "--frames",
            "3",
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        &dir,
    );
    for (technique, columns) in [("lispsm", 0..158), ("volumes", 160..320)] {
        let reference = dir.join(format!("{technique}.png"));
        render(
            &format!("gnomon render --view overview --technique {technique} --size 320x180"),
            &reference,
            &dir,
        );
        let share = agreement_in(&shot, &reference, columns);
        assert!(share >= 0.99, "{technique}: {share}");
    }
    // The divider is white.
    let image = image::open(&shot).unwrap().to_rgb8();
    assert!((0..180).all(|y| image.get_pixel(159, y).0 == [255, 255, 255]));
}

#[test]
fn bad_input_is_one_line_and_exit_code_2_before_any_window() {
    let dir = temp_dir("bad");
    let script = dir.join("bad.jsonl");
    std::fs::write(&script, "{\"frame\": 1, \"key\": \"W\", \"down\": true}\n{\"frame\": 2, \"key\": \"Z\", \"down\": true}\n").unwrap();
    let script = script.to_str().unwrap().to_string();
    for (args, needle) in [
        (
            vec!["--view", "overview", "--script", script.as_str()],
            "line 2: unknown key 'Z'",
        ),
        (vec!["--view", "nowhere"], "unknown view 'nowhere'"),
        (
            vec!["--view", "overview", "--frames", "0"],
            "--frames must be at least 1",
        ),
        (
            vec![
                "--view",
                "overview",
                "--frames",
                "1",
                "--screenshot",
                "shot.txt",
            ],
            "shot.txt",
        ),
        (
            vec![
                "--view",
                "overview",
                "--technique",
                "focused",
                "--lispsm-n",
                "3",
            ],
            "--lispsm-n does nothing for focused",
        ),
    ] {
        // No display needed: everything is checked before the window opens.
        let out = Command::new(env!("CARGO_BIN_EXE_gnomon"))
            .arg("view")
            .args(&args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}
