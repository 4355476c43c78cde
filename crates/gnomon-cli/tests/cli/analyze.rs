//! `gnomon analyze`: the papers' dp/ds figures.

use super::common::*;

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
