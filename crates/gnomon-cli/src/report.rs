//! Setups as JSON and as text, and the record every command writes of one row in one view.

use gnomon::{MapSelection, ShadowSetup};
use serde_json::{Value, json};

/// A human-readable summary of a setup.
pub fn setup_text(setup: &ShadowSetup) -> String {
    use std::fmt::Write;
    let d = &setup.diagnostics;
    let mut s = String::new();
    let _ = writeln!(s, "technique: {}", setup.technique);
    if setup.fallback().is_some() {
        for f in &d.fallbacks {
            let _ = writeln!(s, "fallback:  {f}");
        }
    } else {
        let _ = writeln!(s, "fallback:  none");
    }
    let _ = writeln!(
        s,
        "light frame {}, gamma {:.1} deg; {} visible receivers, {} relevant casters ({} culled), {}",
        d.light_frame.name(),
        d.gamma_degrees,
        d.visible_receivers,
        d.relevant_casters,
        d.culled_casters,
        match d.focus_body_vertices {
            0 => "no focus body B (not computed, or empty)".to_string(),
            n => format!("focus body B of {n} vertices"),
        }
    );
    if let Some(strength) = d.warp_strength {
        let _ = writeln!(
            s,
            "warp strength: {strength} of the technique's (the warp limit; 0: the focused map)"
        );
    }
    s.push_str(&selection_text(setup));
    for i in 0..setup.maps.len() {
        s.push_str(&map_text(setup, i));
    }
    s
}

/// The lines on how a setup's maps are selected, and its casters by side (SPPSM).
fn selection_text(setup: &ShadowSetup) -> String {
    use std::fmt::Write;
    let d = &setup.diagnostics;
    let mut s = String::new();
    if let MapSelection::Cascades(c) = setup.selection {
        let depths: Vec<String> = c.depths().iter().map(|d| format!("{d:.3}")).collect();
        let _ = writeln!(
            s,
            "selection: cascades over view depths {} (map i from z_i to z_i+1), blend {} of a slice, fade from {:.3}{}",
            depths.join(", "),
            c.blend,
            c.fade_start,
            if c.by_coverage {
                "; a point reads the first map whose square holds it (coverage)"
            } else {
                ""
            }
        );
    }
    if let MapSelection::Plane { plane_world: p } = setup.selection {
        let _ = writeln!(
            s,
            "selection: plane {:.6} x + {:.6} y + {:.6} z + {:.6} > 0 reads map 1 (perspective), else map 0 (focused)",
            p.x, p.y, p.z, p.w
        );
    }
    if let MapSelection::CubeFaces(c) = setup.selection {
        let faces: Vec<&str> = c.faces().iter().map(|f| f.name()).collect();
        let _ = writeln!(
            s,
            "selection: cube faces {} (map i is the i-th; a point reads its direction's major axis), {} face(s) skipped with nothing to shadow",
            faces.join(", "),
            d.cube_faces_skipped
        );
    }
    if let MapSelection::DualParaboloid { axis, .. } = setup.selection {
        let _ = writeln!(
            s,
            "selection: dual paraboloid, map 0 the hemisphere around ({}, {}, {}), map 1 the other",
            axis.x, axis.y, axis.z
        );
    }
    if let Some(c) = d.casters_by_side {
        let _ = writeln!(
            s,
            "casters: {} in the focused map only, {} in the perspective map only, {} in both",
            c.focused_only, c.perspective_only, c.both
        );
    }
    s
}

/// Map `i` of a setup: its size, projection, view depths, fallbacks and matrices.
fn map_text(setup: &ShadowSetup, i: usize) -> String {
    use std::fmt::Write;
    let m = &setup.maps[i];
    let mut s = String::new();
    let _ = writeln!(
        s,
        "map {i}: {}x{} {:?}, inset {} texel(s), depth range {:.3} world units",
        m.resolution,
        m.resolution,
        m.projection,
        m.viewport_inset,
        m.depth_range_world()
    );
    if let Some([near, far]) = m.view_depth_range {
        let _ = writeln!(s, "  serves view depths {near:.3} to {far:.3}");
    }
    if setup.maps.len() > 1 {
        let own = setup.map_diagnostics(i);
        let names: Vec<&str> = own.fallbacks.iter().map(|f| f.name()).collect();
        let _ = writeln!(
            s,
            "  fallbacks: {}",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        );
    }
    let _ = writeln!(s, "  clip_from_world (rows):");
    for r in 0..4 {
        let row = m.clip_from_world.row(r);
        let _ = writeln!(
            s,
            "    [{:>12.6} {:>12.6} {:>12.6} {:>12.6}]",
            row.x, row.y, row.z, row.w
        );
    }
    let v = m.depth_from_world;
    let _ = writeln!(
        s,
        "  depth_from_world: [{:.6} {:.6} {:.6} {:.6}]",
        v.x, v.y, v.z, v.w
    );
    s
}

/// A named view's light: `{"directional": [x, y, z]}` (the direction it travels) or
/// `{"spot": {"position", "direction", "half_angle_degrees", "range"}}` or
/// `{"point": {"position", "range"}}`.
pub fn view_light_json(light: &gnomon_scene::ViewLight) -> Value {
    match *light {
        gnomon_scene::ViewLight::Directional { direction } => {
            json!({ "directional": direction.to_array() })
        }
        gnomon_scene::ViewLight::Spot {
            position,
            direction,
            half_angle_degrees,
            range,
        } => json!({ "spot": {
            "position": position.to_array(),
            "direction": direction.to_array(),
            "half_angle_degrees": half_angle_degrees,
            "range": range,
        }}),
        gnomon_scene::ViewLight::Point { position, range } => json!({ "point": {
            "position": position.to_array(),
            "range": range,
        }}),
    }
}

/// One row's record in one view, as compare, demo, bench and flicker write it: the view where
/// the record stands alone (not nested in its view's), the row's name, then its own figures
/// (a JSON object) in their order.
pub fn row_record(view: Option<&str>, technique: &str, figures: Value) -> Value {
    let mut record = serde_json::Map::new();
    if let Some(view) = view {
        record.insert("view".into(), json!(view));
    }
    record.insert("technique".into(), json!(technique));
    if let Value::Object(figures) = figures {
        record.extend(figures);
    }
    Value::Object(record)
}

/// The record of a row that the view's lights refuse, and why.
pub fn skipped_record(view: Option<&str>, technique: &str, why: &str) -> Value {
    row_record(view, technique, json!({ "skipped": why }))
}
