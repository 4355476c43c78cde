//! `gnomon demo`: every view and technique, the gallery.

use super::common::*;

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
