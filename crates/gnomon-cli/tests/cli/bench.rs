//! `gnomon bench`: techniques timed side by side against a baseline.

use super::common::*;

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
