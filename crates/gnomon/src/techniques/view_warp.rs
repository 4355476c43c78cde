//! Perspective warps of light space along the view direction, shared by LiSPSM and XPSM.
//!
//! Light space (LiSPSM paper, section 3.4): the map's depth axis is the light direction, its
//! +y axis the view direction made perpendicular to the light, x completes the frame. A warp
//! w = 1 + (Y - y_origin) inv_n divides X, Y and Z: light rays (along Z) stay parallel, so
//! the map is an orthographic map of the warped space, unit-cube clipped there. The
//! techniques differ only in where the warp is centred and how strong it is
//! ([`WarpChoice`]).
//!
//! Spot lights (LiSPSM paper, end of section 3.4: "for point lights, light space is defined
//! as above, but *after* the perspective transform associated with the point light"): light
//! space is the spot's post-perspective space ([`LightSpace::Spot`]), where its rays are
//! parallel to Z, so the warp applies unchanged. Its y axis is the image of the view
//! direction there. Let A and V be the homogeneous images of e and v: on the view ray
//! e + t v, the image moves along A.w V.xyz - V.w A.xyz for every t (the derivative of the
//! image, times its positive w^2). In world terms that is v (f . q_e) - q_e (f . v), with f
//! the spot's axis and q_e = e - spot position; it is perpendicular to f. Its length over
//! |q_e| plays sin(gamma). It is zero when the view ray passes through the light (the
//! miner's lamp), which falls back to the focused map.
//!
//! Casters are cut to B's extent along Y before their warped extents are taken: every
//! caster point that can shadow a visible receiver lies in B, and the techniques choose
//! warps with w > 0 over B, so no caster that matters reaches the warp's singular plane or
//! is clipped. (For a spot light the planes Y = const are world planes through the light,
//! and casters are also cut to the light's frustum, in front of its near plane.) The depth
//! compared in the map is linear along the light (`depth_from_world`); the clip-space z is
//! the warped z, unit-cube clipped so that the rasteriser clips no relevant caster (for a spot
//! light onto [0, 1/2], see `warped_map`).

use std::cell::OnceCell;

use glam::{DMat4, DVec3, DVec4};

use crate::diagnostics::{Diagnostics, Fallback, LightFrameKind};
use crate::error::SetupError;
use crate::focus::{
    Both, BoxSide, LightCorners, NearTip, ParallelBoxes, ReceiverMap, box_cut_vertices,
    classify_box, clipped_rectangle,
};
use crate::light::Light;
use crate::light_space::{Extents, PERSPECTIVE_CLIP_Z, Projector, pad};
use crate::map::{MapProjection, MapSelection, ShadowMap, ShadowSetup};
use crate::technique::SetupInput;
use crate::techniques::basis::FocusBasis;
use crate::techniques::focused::focused_map;
use crate::techniques::uniform::uniform_map;
use crate::techniques::warp_space::{
    LightParts, LightSpace, TreeCasters, Warp, WarpCasters, WarpChoice, WarpContext, WarpSpace,
    WarpedCasters,
};
use crate::techniques::{ANGULAR_PADDING, with_fallback};

/// The diagnostics a warp starts from (the visible receivers, B's vertices), or (as `Err`)
/// the uniform setup when no receiver is visible or the spot light cannot see the view.
pub(crate) fn warp_diagnostics(
    input: &SetupInput<'_>,
    technique: &'static str,
    basis: &FocusBasis,
) -> Result<Diagnostics, Box<ShadowSetup>> {
    let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
    let visible = &basis.visible;
    diagnostics.visible_receivers = visible.visible_receivers();
    let nothing_to_see = if visible.view_body.is_empty() && basis.frame.light_planes.is_some() {
        Some(Fallback::SpotLightMissesView)
    } else if visible.visible_receivers() == 0 {
        Some(Fallback::NoVisibleReceiver)
    } else {
        None
    };
    if let Some(fallback) = nothing_to_see {
        diagnostics.fallbacks.push(fallback);
        let map = uniform_map(input.light, input.scene, input.map, &mut diagnostics);
        return Err(Box::new(ShadowSetup {
            technique,
            maps: vec![map],
            selection: MapSelection::Single,
            diagnostics,
        }));
    }
    diagnostics.focus_body_vertices = basis.body().len();
    Ok(diagnostics)
}

impl WarpSpace {
    /// The light space of `basis`, or the fallback where a warp is undefined: view parallel
    /// to the light (for a spot light, the view ray through it), B empty or flat.
    pub fn new(input: &SetupInput<'_>, basis: &FocusBasis) -> Result<Self, Fallback> {
        let (eye, view) = (input.camera.eye(), input.camera.forward());
        let (space, sin_gamma) = LightSpace::of_view(input.camera, input.light)?;
        let (visible, body, tolerance) = (&basis.visible, basis.body(), basis.frame.tolerance);
        let linear_row = input.light.linear_depth_row();
        let linear = |p: DVec3| linear_row.dot(p.extend(1.0));

        // B in light space: P's near and far planes, and the reference point's Z.
        let mut body_light = Extents::EMPTY;
        let mut body_linear = f64::INFINITY;
        let mut body_up = (f64::INFINITY, f64::NEG_INFINITY);
        for p in body {
            body_light.add(space.light(*p));
            body_linear = body_linear.min(linear(*p));
            let y = space.frame().up.dot(*p);
            body_up = (body_up.0.min(y), body_up.1.max(y));
        }
        let depth_along_view = body_light.max.y - body_light.min.y;
        let flat = match space {
            LightSpace::Parallel(_) => tolerance,
            LightSpace::Spot { .. } => ANGULAR_PADDING,
        };
        if body.len() < 4 || depth_along_view.is_nan() || depth_along_view <= flat {
            return Err(Fallback::DegenerateFocusBody);
        }
        let (eye_light, depth_world) = match space {
            LightSpace::Parallel(_) => (space.light(eye), depth_along_view),
            LightSpace::Spot { frame, position } => {
                let center = 0.5 * (body_light.min + body_light.max);
                let eye_light = if frame.forward.dot(eye - position) > tolerance {
                    let e = space.light(eye);
                    e.with_x(e.x.clamp(body_light.min.x, body_light.max.x))
                } else {
                    center
                };
                (eye_light, body_up.1 - body_up.0)
            }
        };
        let near_depth = visible
            .view_body
            .points()
            .iter()
            .map(|p| view.dot(*p - eye))
            .fold(f64::INFINITY, f64::min);
        let near = input.camera.lens().near;
        let near_depth = if near_depth.is_finite() {
            near_depth.max(near)
        } else {
            near
        };

        // A spot light's receivers: light-space vertices, and the linear depth range. A
        // directional light's stay in the scene's hierarchy (see `view_warp_setup`).
        let light_parts = OnceCell::new();
        let receiver_points = match space {
            LightSpace::Spot { .. } => {
                let (points, parts) = spot_light_parts(input, basis, &space, &body_light);
                let _ = light_parts.set(parts);
                points
            }
            LightSpace::Parallel(_) => Vec::new(),
        };
        Ok(Self {
            space,
            sin_gamma,
            body_light,
            body_linear,
            eye_light,
            depth_world,
            near_depth,
            receiver_points,
            light_parts,
            caster_count: input.scene.casters().len(),
        })
    }
}

/// A spot light's visible receivers' vertices in light space, and what their extents there
/// decide.
fn spot_light_parts(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    space: &LightSpace,
    body_light: &Extents,
) -> (Vec<DVec3>, LightParts) {
    let linear_row = input.light.linear_depth_row();
    let mut points = Vec::new();
    let mut receivers_light = Extents::EMPTY;
    let mut receivers_linear = (f64::INFINITY, f64::NEG_INFINITY);
    basis.visible.for_each_vertex(input.scene, |p| {
        let q = space.light(p);
        receivers_light.add(q);
        points.push(q);
        let z = linear_row.dot(p.extend(1.0));
        receivers_linear = (receivers_linear.0.min(z), receivers_linear.1.max(z));
    });
    let parts = light_parts_of(
        input,
        basis,
        space,
        body_light,
        &receivers_light,
        receivers_linear,
    );
    (points, parts)
}

/// The receivers' linear depth range and the casters a warp may need, from the receivers'
/// light-space extents (`receivers_light`) and linear depth range.
fn light_parts_of(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    space: &LightSpace,
    body_light: &Extents,
    receivers_light: &Extents,
    receivers_linear: (f64, f64),
) -> LightParts {
    let tolerance = basis.frame.tolerance;
    let linear_row = input.light.linear_depth_row();
    let linear = |p: DVec3| linear_row.dot(p.extend(1.0));
    let receivers_z = receivers_linear.1;
    // Casters, cut to B's Y range (see the module documentation), and culled where no
    // strength can make them relevant.
    let casters = match &space {
        LightSpace::Parallel(frame) if !basis.cuts_casters() => {
            // Light rays are columns of constant (X, Y) before and after the warp, so a
            // caster beside the receivers' columns is culled before any division.
            let slack = 1e-9
                * (receivers_light.max - receivers_light.min)
                    .truncate()
                    .max_element();
            WarpCasters::Tree(TreeCasters {
                frame: *frame,
                columns: Extents {
                    min: (receivers_light.min.truncate() - slack)
                        .max(glam::DVec2::new(f64::NEG_INFINITY, body_light.min.y))
                        .extend(f64::NEG_INFINITY),
                    max: (receivers_light.max.truncate() + slack)
                        .min(glam::DVec2::new(f64::INFINITY, body_light.max.y))
                        .extend(receivers_z),
                },
                y_range: (body_light.min.y, body_light.max.y),
            })
        }
        _ => {
            // Cut each caster by the light's frustum (its near plane first) and a side,
            // and B's Y range: all world planes.
            let mut planes = basis.caster_planes.clone();
            let light_near_first = basis.light_near_first();
            planes.push(space.y_plane(body_light.min.y, true));
            planes.push(space.y_plane(body_light.max.y, false));
            let mut points = Vec::new();
            let mut casters = Vec::new();
            let mut near_tip: Option<NearTip> = None;
            for caster in input.scene.casters() {
                let start = points.len();
                let near_clipped = match classify_box(caster, &planes, tolerance) {
                    BoxSide::Outside => continue,
                    BoxSide::Inside => {
                        points.extend_from_slice(&caster.corners());
                        false
                    }
                    BoxSide::Straddles(mask) => {
                        if !box_cut_vertices(caster, &planes, mask, tolerance, &mut points) {
                            continue;
                        }
                        light_near_first
                            && mask & 1 != 0
                            && near_tip
                                .get_or_insert_with(|| {
                                    NearTip::new(input.scene, &planes, tolerance)
                                })
                                .clips(caster, mask, tolerance)
                    }
                };
                let z_min = points[start..]
                    .iter()
                    .map(|p| linear(*p))
                    .fold(f64::INFINITY, f64::min);
                if z_min <= receivers_z {
                    for p in &mut points[start..] {
                        *p = space.light(*p);
                    }
                    casters.push((start as u32, points.len() as u32, z_min, near_clipped));
                } else {
                    points.truncate(start);
                }
            }
            WarpCasters::Points { points, casters }
        }
    };
    LightParts {
        receivers_linear,
        casters,
    }
}

impl WarpSpace {
    /// The visible receivers' extents under `warp` (one of this light space's). For a
    /// directional light the first call also gathers their extents in light space, in the
    /// same walk: they make the light-space parts ([`Self::light_parts`]) and are kept in
    /// `basis` (the focused map reads them).
    fn receivers_under(&self, input: &SetupInput<'_>, basis: &FocusBasis, warp: &Warp) -> Extents {
        let scene = input.scene;
        let frame = match &self.space {
            LightSpace::Parallel(frame) => frame,
            LightSpace::Spot { .. } => return warp.points_extents(&self.receiver_points),
        };
        let tree = scene.receiver_tree();
        let arrays = scene.receiver_arrays();
        let nodes = ParallelBoxes::new(&tree.nodes, frame);
        let boxes = ParallelBoxes::new(arrays, frame);
        let corners = LightCorners::new(frame);
        let node_image = |light: &Extents| warp.box_extents(light.min, light.max);
        // The warped box around a receiver's light-space box. A cut receiver's whole box may
        // reach behind the warp's centre, where its image bounds nothing (a wholly visible one
        // lies in B: w > 0); w is linear in Y, so the box's Y range tells.
        let box_bound = |light: &Extents| {
            if warp.w(light.min.y) <= 0.0 || warp.w(light.max.y) <= 0.0 {
                return Extents::ALL;
            }
            warp.box_extents(light.min, light.max)
        };
        // Exact: the warped corners (the light-space box's Y range is the corners', so none
        // is behind the centre when the bound is finite).
        let box_image = |i: usize, bound: Extents| {
            if bound == Extents::ALL {
                return bound;
            }
            let c = warp.light(arrays.center_of(i));
            warp.points_extents(&corners.corners(c, arrays.half_of(i)))
        };
        let points_image = |points: &[DVec3]| {
            let mut ext = Extents::EMPTY;
            for p in points {
                ext.add(warp.warp(warp.light(*p)).0);
            }
            ext
        };
        if self.light_parts.get().is_some() {
            return basis.visible.extents_under(
                scene,
                ReceiverMap {
                    node: |n| node_image(&nodes.extents(n)),
                    region: |c, h| box_bound(&boxes.extents_of(c, h)),
                    bound: |i| box_bound(&boxes.extents(i)),
                    exact: box_image,
                    points: points_image,
                    prune_cuts: true,
                },
            );
        }
        // Both maps: light space (a box's bound is its exact image) and the warp's.
        let both_bound = |light: Extents| Both {
            first: light,
            second: box_bound(&light),
        };
        let both = basis.visible.extents_under(
            scene,
            ReceiverMap {
                node: |n| {
                    let light = nodes.extents(n);
                    Both {
                        first: light,
                        second: node_image(&light),
                    }
                },
                region: |c, h| both_bound(boxes.extents_of(c, h)),
                bound: |i| both_bound(boxes.extents(i)),
                exact: |i, bound: Both| Both {
                    first: bound.first,
                    second: box_image(i, bound.second),
                },
                // A point's light-space coordinates are its image under the projector: made
                // once.
                points: |points: &[DVec3]| {
                    let (mut first, mut second) = (Extents::EMPTY, Extents::EMPTY);
                    for p in points {
                        let q = warp.light(*p);
                        first.add(q);
                        second.add(warp.warp(q).0);
                    }
                    Both { first, second }
                },
                prune_cuts: true,
            },
        );
        basis.keep_receiver_extents(&Projector::Parallel(*frame), both.first);
        let _ = self
            .light_parts
            .set(self.parallel_light_parts(input, basis, &both.first));
        both.second
    }

    /// What the visible receivers' extents in light space decide: made with a spot light's
    /// vertices, or by a directional light's first [`Self::receivers_under`] (else here, from
    /// `basis`).
    fn light_parts(&self, input: &SetupInput<'_>, basis: &FocusBasis) -> &LightParts {
        self.light_parts.get_or_init(|| match self.space {
            LightSpace::Parallel(frame) => {
                let receivers_light = basis.receiver_extents(&Projector::Parallel(frame));
                self.parallel_light_parts(input, basis, &receivers_light)
            }
            LightSpace::Spot { .. } => {
                spot_light_parts(input, basis, &self.space, &self.body_light).1
            }
        })
    }

    /// A directional light's light-space parts from the receivers' extents in light space,
    /// whose Z is the linear depth along the light.
    fn parallel_light_parts(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        receivers_light: &Extents,
    ) -> LightParts {
        light_parts_of(
            input,
            basis,
            &self.space,
            &self.body_light,
            receivers_light,
            (receivers_light.min.z, receivers_light.max.z),
        )
    }

    /// The casters under `warp` that overlap the receivers' warped extents (`receivers`) in
    /// x and y, as [`WarpedCasters`].
    fn casters_under(
        parts: &LightParts,
        scene: &crate::bounds::SceneBounds,
        warp: &Warp,
        receivers: &Extents,
    ) -> WarpedCasters {
        match &parts.casters {
            WarpCasters::Tree(tree) => tree.warped(scene, warp, receivers),
            WarpCasters::Points { points, casters } => {
                let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
                let mut out = WarpedCasters {
                    extents: Extents::EMPTY,
                    linear_min: f64::INFINITY,
                    relevant: 0,
                    near_clipped: 0,
                };
                for &(start, end, z_min, near_clipped) in casters {
                    let warped = warp.points_extents(&points[start as usize..end as usize]);
                    if receivers.xy_overlaps(&warped, xy_slack) {
                        out.relevant += 1;
                        out.near_clipped += usize::from(near_clipped);
                        out.extents = out.extents.union(&warped);
                        out.linear_min = out.linear_min.min(z_min);
                    }
                }
                out
            }
        }
    }
}

/// The view warp's light space for `input` on `basis` (the input it was made for), made once
/// per basis: the fallback where the warp is undefined (see [`WarpSpace::new`]).
pub(crate) fn warp_space<'b>(
    input: &SetupInput<'_>,
    basis: &'b FocusBasis,
) -> &'b Result<WarpSpace, Fallback> {
    basis.warp_space_or(|| WarpSpace::new(input, basis))
}

/// The setup of a view-axis warp: the focused map where the warp is undefined (view
/// parallel to the light, a flat B, spot lights unless `warps_spot_lights`), the uniform map
/// when nothing is visible, else the warp `choose` picks, with unit cube clipping in warped
/// space.
pub(crate) fn view_warp_setup(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    technique: &'static str,
    warps_spot_lights: bool,
    choose: impl FnOnce(&WarpContext) -> WarpChoice,
) -> Result<ShadowSetup, SetupError> {
    input.map.validate()?;
    let fallback = |fallback: Fallback| -> Result<ShadowSetup, SetupError> {
        Ok(with_fallback(
            focused_map(input, basis).clone(),
            technique,
            fallback,
        ))
    };
    if matches!(input.light, Light::Spot(_)) && !warps_spot_lights {
        return fallback(Fallback::SpotLightNotWarped);
    }
    let prepared = warp_space(input, basis);
    if let Err(Fallback::LightParallelToView) = prepared {
        return fallback(Fallback::LightParallelToView);
    }
    let mut diagnostics = match warp_diagnostics(input, technique, basis) {
        Ok(diagnostics) => diagnostics,
        Err(uniform) => return Ok(*uniform),
    };
    let ws = match prepared {
        Ok(ws) => ws,
        Err(f) => return fallback(*f),
    };
    diagnostics.light_frame = LightFrameKind::ViewAligned;
    let linear_row = input.light.linear_depth_row();
    let warp = ws.warp(choose);

    // Receivers: warped extents.
    let receivers = ws.receivers_under(input, basis, &warp);
    let parts = ws.light_parts(input, basis);
    let receivers_linear = parts.receivers_linear;
    let receivers_z = receivers_linear.1;
    let mut body_warped = Extents::EMPTY;
    for p in basis.body() {
        body_warped.add(warp.warp(warp.light(*p)).0);
    }

    // Casters: their warped extents, kept where they overlap the receivers' columns.
    let WarpedCasters {
        extents: casters,
        linear_min: casters_z,
        relevant,
        near_clipped,
    } = WarpSpace::casters_under(parts, input.scene, &warp, &receivers);
    diagnostics.relevant_casters = relevant;
    diagnostics.culled_casters = ws.caster_count - relevant;
    diagnostics.casters_clipped_by_light_near = near_clipped;

    // Unit cube clipping in warped space; B bounds the near side as for the focused map.
    let (region, linear_range) = if relevant == 0 {
        diagnostics.fallbacks.push(Fallback::NoCasterForReceivers);
        (receivers, receivers_linear)
    } else {
        let (lo, hi) = clipped_rectangle(&receivers, &casters);
        let near = casters.min.z.max(body_warped.min.z).min(receivers.max.z);
        let near_linear = casters_z.max(ws.body_linear).min(receivers_z);
        (
            Extents {
                min: lo.extend(near),
                max: hi.extend(receivers.max.z),
            },
            (near_linear, receivers_z),
        )
    };
    let map = warped_map(
        &warp,
        &region,
        linear_range,
        linear_row,
        input.map,
        basis.frame.tolerance,
    );
    Ok(ShadowSetup {
        technique,
        maps: vec![map],
        selection: MapSelection::Single,
        diagnostics,
    })
}

/// The map of a warp: the warped region to the inset square and [0, 1] depth; the linear
/// depth interval (`linear_row`, world units along the light) to `depth_from_world`.
fn warped_map(
    warp: &Warp,
    region: &Extents,
    linear: (f64, f64),
    linear_row: DVec4,
    settings: crate::map::MapSettings,
    tolerance: f64,
) -> ShadowMap {
    let scale = (region.max - region.min).abs().max_element().max(1e-300);
    let (u0, u1) = pad(region.min.x, region.max.x, 1e-9 * scale);
    let (v0, v1) = pad(region.min.y, region.max.y, 1e-9 * scale);
    let (z0, z1) = pad(region.min.z, region.max.z, 1e-9 * scale);
    let (l0, l1) = pad(linear.0, linear.1, tolerance);
    let s = settings.inset_ndc();
    let [x_row, y_row, z_row, w_row] = warp.rows();
    // NDC = a * coordinate + b, times w.
    let clip_row = |row: DVec4, lo: f64, hi: f64, a_scale: f64, centered: bool| {
        let a = a_scale / (hi - lo);
        let b = if centered {
            -0.5 * a_scale * (hi + lo) / (hi - lo)
        } else {
            -a_scale * lo / (hi - lo)
        };
        row * a + w_row * b
    };
    // A spot light's post-perspective Z (-1 / d) crowds everything farther than a few of
    // its near distances (a millionth of its range) at the far end of the unit cube: its
    // clip z runs to 1/2 only, as the spot's own maps' do (see `PERSPECTIVE_CLIP_Z`).
    let z_scale = match warp.space {
        LightSpace::Spot { .. } => PERSPECTIVE_CLIP_Z,
        LightSpace::Parallel(_) => 1.0,
    };
    let rows = [
        clip_row(x_row, u0, u1, 2.0 * s, true),
        clip_row(y_row, v0, v1, 2.0 * s, true),
        clip_row(z_row, z0, z1, z_scale, false),
        w_row,
    ];
    let perspective = warp.inv_n > 0.0 || matches!(warp.space, LightSpace::Spot { .. });
    ShadowMap {
        clip_from_world: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
        depth_from_world: (linear_row - DVec4::W * l0) / (l1 - l0),
        resolution: settings.resolution,
        viewport_inset: settings.viewport_inset,
        projection: if perspective {
            MapProjection::Perspective
        } else {
            MapProjection::Orthographic
        },
        view_depth_range: None,
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::light_space::LightFrame;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

        /// The warp's walks of the scene's hierarchies give what a pass over every box gives:
        /// the receivers' warped extents, and the relevant casters' extents and nearest
        /// depth, and whether there is any, at any strength.
        #[test]
        fn warped_walks_match_every_box(
            boxes in prop::collection::vec((prop::array::uniform3(-60.0f64..60.0), prop::array::uniform3(0.2f64..12.0), 0u8..3), 1..300),
            eye in prop::array::uniform3(-80.0f64..80.0),
            target in prop::array::uniform3(-30.0f64..30.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            n in prop_oneof![Just(f64::INFINITY), 0.5f64..500.0],
        ) {
            use crate::bvh::test_scenes;
            use crate::frame::Frame;
            use crate::light::DirectionalLight;
            use crate::map::MapSettings;
            use crate::techniques::basis::Part;
            let scene = test_scenes::mixed(&boxes);
            let camera = test_scenes::camera(eye, target);
            prop_assume!(camera.is_some());
            let camera = camera.unwrap();
            let direction = DVec3::from_array(light);
            prop_assume!(direction.length() > 0.1);
            let light = Light::Directional(DirectionalLight::new(direction.with_y(-direction.y.abs() - 0.1)).unwrap());
            let input = SetupInput { camera: &camera, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            let basis = FocusBasis::new(&frame, Part::Whole);
            prop_assume!(basis.visible.visible_receivers() > 0);
            let Ok(ws) = WarpSpace::new(&input, &basis) else { return Ok(()) };
            let LightSpace::Parallel(light_frame) = ws.space else { unreachable!() };
            let inv_n = 1.0 / n;
            let warp = Warp {
                space: ws.space,
                x_eye: ws.eye_light.x,
                y_origin: ws.body_light.min.y - if n.is_finite() { n } else { 0.0 },
                z_mid: 0.5 * (ws.body_light.min.z + ws.body_light.max.z),
                inv_n,
                k: 1.0 / (ws.body_light.max.y - ws.body_light.min.y) + inv_n,
            };
            let mut want = Extents::EMPTY;
            basis.visible.for_each_vertex(&scene, |p| want.add(warp.warp(warp.light(p)).0));
            let got = ws.receivers_under(&input, &basis, &warp);
            // The walk that gathered light space's extents too gives what a walk of each
            // map alone gives, to the bit.
            let projector = Projector::Parallel(light_frame);
            prop_assert_eq!(basis.receiver_extents(&projector), basis.visible.receiver_extents(&scene, &projector));
            prop_assert_eq!(ws.receivers_under(&input, &basis, &warp), got);
            let scale = 1.0 + (want.max - want.min).abs().max_element() + want.min.abs().max_element();
            let close = |a: DVec3, b: DVec3| (a - b).abs().max_element() <= 1e-9 * scale;
            prop_assert!(close(got.min, want.min) && close(got.max, want.max), "receivers {:?} vs {:?}", got, want);

            // Casters one by one, as `TreeCasters::warped` defines them.
            let parts = ws.light_parts(&input, &basis);
            let WarpCasters::Tree(tree) = &parts.casters else { unreachable!() };
            let xy_slack = 1e-9 * (want.max - want.min).truncate().max_element();
            let over = Extents {
                min: (want.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
                max: (want.max.truncate() + xy_slack).extend(f64::INFINITY),
            };
            let boxes = ParallelBoxes::new(scene.caster_arrays(), &light_frame);
            let (c, (y0, y1)) = (&tree.columns, tree.y_range);
            let (mut ext, mut linear_min, mut relevant) = (Extents::EMPTY, f64::INFINITY, 0);
            for i in 0..scene.casters().len() {
                let l = boxes.extents(i);
                let meets = c.min.x <= l.max.x && l.min.x <= c.max.x && c.min.y <= l.max.y
                    && l.min.y <= c.max.y && l.min.z <= c.max.z;
                if !meets { continue; }
                let image = warp.box_extents(l.min.with_y(l.min.y.max(y0)), l.max.with_y(l.max.y.min(y1)));
                if want.xy_overlaps(&image, xy_slack) {
                    relevant += 1;
                    ext = ext.union(&image.clamped_to(&over));
                    linear_min = linear_min.min(l.min.z);
                }
            }
            let got = WarpSpace::casters_under(parts, &scene, &warp, &want);
            // Subtrees that add nothing are counted whole: at least the relevant ones.
            prop_assert!(got.relevant >= relevant && (got.relevant > 0) == (relevant > 0));
            if relevant > 0 {
                prop_assert!(close(got.extents.min, ext.min), "casters {:?} vs {:?}", got.extents, ext);
                prop_assert!(close(got.extents.max.truncate().extend(0.0), ext.max.truncate().extend(0.0)), "casters {:?} vs {:?}", got.extents, ext);
                prop_assert_eq!(got.linear_min, linear_min);
            }
        }

        /// The six-division extents equal the extents of the eight warped corners.
        #[test]
        fn box_extents_match_the_warped_corners(
            lo in prop::array::uniform3(-50.0f64..50.0),
            size in prop::array::uniform3(0.0f64..40.0),
            x_eye in -30.0f64..30.0,
            z_mid in -30.0f64..30.0,
            n in prop_oneof![Just(f64::INFINITY), 0.01f64..1000.0],
        ) {
            let frame = LightFrame::fixed(DVec3::new(0.3, -1.0, 0.2).normalize());
            let y_origin = -60.0;
            let inv_n = 1.0 / n;
            let warp = Warp { space: LightSpace::Parallel(frame), x_eye, y_origin, z_mid, inv_n, k: 1.0 / 120.0 + inv_n };
            let lo = DVec3::from_array(lo);
            let hi = lo + DVec3::from_array(size);
            let fast = warp.box_extents(lo, hi);
            let mut slow = Extents::EMPTY;
            for i in 0..8 {
                let q = DVec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
                slow.add(warp.warp(q).0);
            }
            prop_assert!((fast.min - slow.min).abs().max_element() < 1e-9, "{fast:?} vs {slow:?}");
            prop_assert!((fast.max - slow.max).abs().max_element() < 1e-9, "{fast:?} vs {slow:?}");
        }
    }
}
