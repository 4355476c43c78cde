//! A setup as JSON: what `gnomon setup --json` prints and the bindings' `to_json` return.

use gnomon::{MapProjection, MapSelection, ShadowSetup};
use serde_json::{Value, json};

/// The JSON form of a setup: `{"technique", "fallback", "maps", "selection", "diagnostics"}`;
/// matrices column-major.
pub fn setup_json(setup: &ShadowSetup) -> Value {
    let d = &setup.diagnostics;
    let maps: Vec<Value> = setup
        .maps
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let own = setup.map_diagnostics(i);
            json!({
                "clip_from_world": m.clip_from_world.to_cols_array(),
                "depth_from_world": m.depth_from_world.to_array(),
                "resolution": m.resolution,
                "viewport_inset": m.viewport_inset,
                "projection": match m.projection {
                    MapProjection::Orthographic => "orthographic",
                    MapProjection::Perspective => "perspective",
                    MapProjection::Paraboloid => "paraboloid",
                },
                "view_depth_range": m.view_depth_range,
                "fallbacks": own.fallbacks.iter().map(|f| f.name()).collect::<Vec<_>>(),
                "warp_strength": own.warp_strength,
            })
        })
        .collect();
    json!({
        "technique": setup.technique,
        "fallback": setup.fallback().map(|f| f.name()),
        "maps": maps,
        "selection": match setup.selection {
            MapSelection::Single => json!({ "kind": "single" }),
            MapSelection::Plane { plane_world } => json!({
                "kind": "plane",
                "plane_world": plane_world.to_array(),
            }),
            MapSelection::Cascades(c) => json!({
                "kind": "cascades",
                "view_depths": c.depths(),
                "blend": c.blend,
                "fade_start": c.fade_start,
                "select": if c.by_coverage { "coverage" } else { "view_depth" },
            }),
            MapSelection::DualParaboloid { position, axis } => json!({
                "kind": "dual_paraboloid",
                "position": position.to_array(),
                "axis": axis.to_array(),
            }),
            MapSelection::CubeFaces(c) => json!({
                "kind": "cube_faces",
                "faces": c.faces().iter().map(|f| f.name()).collect::<Vec<_>>(),
                "position": c.position.to_array(),
            }),
        },
        "diagnostics": {
            "fallbacks": d.fallbacks.iter().map(|f| json!({"name": f.name(), "reason": f.reason()})).collect::<Vec<_>>(),
            "light_frame": d.light_frame.name(),
            "gamma_degrees": d.gamma_degrees,
            "visible_receivers": d.visible_receivers,
            "relevant_casters": d.relevant_casters,
            "culled_casters": d.culled_casters,
            "casters_clipped_by_light_near": d.casters_clipped_by_light_near,
            "focus_body_vertices": d.focus_body_vertices,
            "scene_box_grown": d.scene_box_grown,
            "warp_strength": d.warp_strength,
            "cube_faces_skipped": d.cube_faces_skipped,
            "casters_by_side": d.casters_by_side.map(|c| json!({
                "focused_only": c.focused_only,
                "perspective_only": c.perspective_only,
                "both": c.both,
            })),
        },
    })
}
