//! Perspective warps of light space along the view direction, shared by LiSPSM and XPSM.
//!
//! Light space (LiSPSM paper, section 3.4): the map's depth axis is the light direction, its
//! +y axis the view direction made perpendicular to the light, x completes the frame. A warp
//! w = 1 + (Y - y_origin) inv_n divides X, Y and Z: light rays (along Z) stay parallel, so
//! the map is an orthographic map of the warped space, unit-cube clipped there. The
//! techniques differ only in where the warp is centred and how strong it is
//! ([`WarpChoice`]).
//!
//! Casters are cut to B's extent along Y before their warped extents are taken: every
//! caster point that can shadow a visible receiver lies in B, and the techniques choose
//! warps with w > 0 over B, so no caster that matters reaches the warp's singular plane or
//! is clipped. The depth compared in the map is linear along the light
//! (`depth_from_world`); the clip-space z is the warped z, unit-cube clipped so that the
//! rasteriser clips no relevant caster.

use glam::{DMat4, DVec3, DVec4};

use crate::body::focus_body;
use crate::error::SetupError;
use crate::focus::VisibleScene;
use crate::geometry::ConvexPolyhedron;
use crate::light::Light;
use crate::light_space::{Extents, LightFrame, Projector, pad};
use crate::setup::{
    Diagnostics, Fallback, LightFrameKind, MapProjection, MapSelection, SetupInput, ShadowMap,
    ShadowSetup, ShadowTechnique,
};
use crate::techniques::focused::Focused;
use crate::techniques::uniform::uniform_map;
use crate::techniques::{fixed_projector, tolerance, with_fallback};

/// What a technique sees when it chooses its warp.
pub(crate) struct WarpContext<'a> {
    /// The setup's input.
    pub input: &'a SetupInput<'a>,
    /// B's extents in light space (X, Y, Z).
    pub body_light: Extents,
    /// sin of the angle between the view and the light direction.
    pub sin_gamma: f64,
    /// The eye in light space.
    pub eye_light: DVec3,
}

/// Where a warp is centred along Y and how strong it is; see [`Warp`].
pub(crate) struct WarpChoice {
    pub y_origin: f64,
    pub inv_n: f64,
    pub k: f64,
}

/// A perspective warp of light space along its y axis (the view direction made
/// perpendicular to the light), centred at x = `x_eye`, z = `z_mid`:
/// w = 1 + (Y - y_origin) inv_n, (u, s, z) = (X - x_eye, (Y - y_origin) k, Z - z_mid) / w.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Warp {
    frame: LightFrame,
    x_eye: f64,
    y_origin: f64,
    z_mid: f64,
    /// The warp strength (LiSPSM: 1 / n; 0: no warp).
    inv_n: f64,
    /// Scale of s (LiSPSM: 1 / (f - n) + 1 / n, so that s runs over [0, 1] across B).
    k: f64,
}

impl Warp {
    /// Light-space coordinates (X, Y, Z) of a world point.
    fn light(&self, p: DVec3) -> DVec3 {
        let f = &self.frame;
        DVec3::new(f.right.dot(p), f.up.dot(p), f.forward.dot(p))
    }

    /// (u, s, z) and w of light-space coordinates.
    fn warp(&self, q: DVec3) -> (DVec3, f64) {
        let w = 1.0 + (q.y - self.y_origin) * self.inv_n;
        (
            DVec3::new(
                q.x - self.x_eye,
                (q.y - self.y_origin) * self.k,
                q.z - self.z_mid,
            ) / w,
            w,
        )
    }

    /// The warped extents of the light-space box [lo, hi], with its Y inside B's range so
    /// that w > 0. u = (X - X_eye) / w is largest at
    /// the smallest w when X - X_eye >= 0 and at the largest w otherwise (likewise z); s grows
    /// with Y. So six divisions give the exact extents of the box's image.
    fn box_extents(&self, lo: DVec3, hi: DVec3) -> Extents {
        let w0 = 1.0 + (lo.y - self.y_origin) * self.inv_n;
        let w1 = 1.0 + (hi.y - self.y_origin) * self.inv_n;
        let range = |a: f64, b: f64| {
            let lo = if a < 0.0 { a / w0 } else { a / w1 };
            let hi = if b < 0.0 { b / w1 } else { b / w0 };
            (lo, hi)
        };
        let (u0, u1) = range(lo.x - self.x_eye, hi.x - self.x_eye);
        let (z0, z1) = range(lo.z - self.z_mid, hi.z - self.z_mid);
        let s0 = (lo.y - self.y_origin) * self.k / w0;
        let s1 = (hi.y - self.y_origin) * self.k / w1;
        Extents {
            min: DVec3::new(u0, s0, z0),
            max: DVec3::new(u1, s1, z1),
        }
    }

    /// The rows of world -> (u w, s w, z w, w).
    fn rows(&self) -> [DVec4; 4] {
        let f = &self.frame;
        let w = (self.inv_n * f.up).extend(1.0 - self.y_origin * self.inv_n);
        [
            f.right.extend(-self.x_eye),
            (self.k * f.up).extend(-self.k * self.y_origin),
            f.forward.extend(-self.z_mid),
            w,
        ]
    }
}

/// What every camera-dependent warp starts from: the visible scene, B's vertices, the
/// tolerance and the diagnostics so far.
pub(crate) struct WarpBasis {
    pub visible: VisibleScene,
    pub body: Vec<DVec3>,
    pub tolerance: f64,
    pub diagnostics: Diagnostics,
}

/// The visible scene and B for `input`, or (as `Err`) the uniform setup when no receiver is
/// visible.
pub(crate) fn warp_basis(
    input: &SetupInput<'_>,
    technique: &'static str,
) -> Result<WarpBasis, ShadowSetup> {
    let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
    let tolerance = tolerance(input.scene, Some(input.camera), input.light);
    let visible = VisibleScene::new(input.camera, input.scene, None, tolerance);
    diagnostics.visible_receivers = visible.visible_receivers();
    if visible.visible_receivers() == 0 {
        diagnostics.fallbacks.push(Fallback::NoVisibleReceiver);
        let map = uniform_map(input.light, input.scene, input.map, &mut diagnostics);
        return Err(ShadowSetup {
            technique,
            maps: vec![map],
            selection: MapSelection::Single,
            diagnostics,
        });
    }
    let region = ConvexPolyhedron::from_box(&input.scene.scene_box());
    let body = focus_body(
        &visible.view_body,
        &region,
        &fixed_projector(input.light),
        tolerance,
    )
    .vertices(tolerance);
    diagnostics.focus_body_vertices = body.len();
    Ok(WarpBasis {
        visible,
        body,
        tolerance,
        diagnostics,
    })
}

/// The setup of a view-axis warp: the focused map where the warp is undefined (spot lights,
/// view parallel to the light, a flat B), the uniform map when nothing is visible, else the
/// warp `choose` picks, with unit cube clipping in warped space.
pub(crate) fn view_warp_setup(
    input: &SetupInput<'_>,
    technique: &'static str,
    choose: impl FnOnce(&WarpContext) -> WarpChoice,
) -> Result<ShadowSetup, SetupError> {
    input.map.validate()?;
    let fallback = |fallback: Fallback| -> Result<ShadowSetup, SetupError> {
        Ok(with_fallback(Focused.setup(input)?, technique, fallback))
    };
    let Light::Directional(light) = input.light else {
        return fallback(Fallback::SpotLightNotWarped);
    };
    let Some(frame) = LightFrame::view_aligned(light.direction(), input.camera.forward()) else {
        return fallback(Fallback::LightParallelToView);
    };
    let WarpBasis {
        visible,
        body,
        tolerance,
        mut diagnostics,
    } = match warp_basis(input, technique) {
        Ok(basis) => basis,
        Err(uniform) => return Ok(uniform),
    };
    diagnostics.light_frame = LightFrameKind::ViewAligned;

    // B in light space: P's near and far planes, and the reference point's Z.
    let projector = Projector::Parallel(frame);
    let mut body_light = Extents::EMPTY;
    for p in &body {
        body_light.add(projector.project(*p));
    }
    let depth_along_view = body_light.max.y - body_light.min.y;
    if body.len() < 4 || depth_along_view.is_nan() || depth_along_view <= tolerance {
        return fallback(Fallback::DegenerateFocusBody);
    }
    let sin_gamma = input.camera.forward().cross(light.direction()).length();
    let eye_light = projector.project(input.camera.eye());
    let choice = choose(&WarpContext {
        input,
        body_light,
        sin_gamma,
        eye_light,
    });
    let warp = Warp {
        frame,
        x_eye: eye_light.x,
        y_origin: choice.y_origin,
        z_mid: 0.5 * (body_light.min.z + body_light.max.z),
        inv_n: choice.inv_n,
        k: choice.k,
    };

    // Receivers: warped extents, and the linear depth range (world Z).
    let mut receivers = Extents::EMPTY;
    let mut receivers_z = f64::NEG_INFINITY;
    visible.for_each_vertex(input.scene, |p| {
        let q = warp.light(p);
        receivers.add(warp.warp(q).0);
        receivers_z = receivers_z.max(q.z);
    });
    let mut body_warped = Extents::EMPTY;
    for p in &body {
        body_warped.add(warp.warp(warp.light(*p)).0);
    }

    // Casters, cut to B's Y range (see the module documentation).
    let mut casters = Extents::EMPTY;
    let mut casters_z = f64::INFINITY;
    let mut relevant = 0;
    let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
    for caster in input.scene.casters() {
        let e = projector.box_extents(caster);
        let (y0, y1) = (e.min.y.max(body_light.min.y), e.max.y.min(body_light.max.y));
        if y0 > y1 {
            continue;
        }
        let lo = DVec3::new(e.min.x, y0, e.min.z);
        let hi = DVec3::new(e.max.x, y1, e.max.z);
        let warped = warp.box_extents(lo, hi);
        if !receivers.xy_overlaps(&warped, xy_slack) || e.min.z > receivers_z {
            continue;
        }
        relevant += 1;
        casters = casters.union(&warped);
        casters_z = casters_z.min(e.min.z);
    }
    diagnostics.relevant_casters = relevant;
    diagnostics.culled_casters = input.scene.casters().len() - relevant;

    // Unit cube clipping in warped space; B bounds the near side as for the focused map.
    let (region, linear) = if relevant == 0 {
        diagnostics.fallbacks.push(Fallback::NoCasterForReceivers);
        let min_z = receivers.min.z;
        (receivers, (min_z, receivers_z))
    } else {
        let lo = receivers.min.max(casters.min).truncate();
        let hi = receivers.max.min(casters.max).truncate();
        let mid = 0.5 * (lo + hi);
        let near = casters.min.z.max(body_warped.min.z).min(receivers.max.z);
        let near_linear = casters_z.max(body_light.min.z).min(receivers_z);
        (
            Extents {
                min: lo.min(mid).extend(near),
                max: hi.max(mid).extend(receivers.max.z),
            },
            (near_linear, receivers_z),
        )
    };
    let map = warped_map(&warp, &region, linear, input.map, tolerance);
    Ok(ShadowSetup {
        technique,
        maps: vec![map],
        selection: MapSelection::Single,
        diagnostics,
    })
}

/// The map of a warp: the warped region to the inset square and [0, 1] depth; the linear
/// depth interval (world Z along the light) to `depth_from_world`.
fn warped_map(
    warp: &Warp,
    region: &Extents,
    linear: (f64, f64),
    settings: crate::setup::MapSettings,
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
            -lo / (hi - lo)
        };
        row * a + w_row * b
    };
    let rows = [
        clip_row(x_row, u0, u1, 2.0 * s, true),
        clip_row(y_row, v0, v1, 2.0 * s, true),
        clip_row(z_row, z0, z1, 1.0, false),
        w_row,
    ];
    let f = warp.frame.forward;
    ShadowMap {
        clip_from_world: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
        depth_from_world: (f / (l1 - l0)).extend(-l0 / (l1 - l0)),
        resolution: settings.resolution,
        viewport_inset: settings.viewport_inset,
        projection: if warp.inv_n > 0.0 {
            MapProjection::Perspective
        } else {
            MapProjection::Orthographic
        },
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

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
            let warp = Warp { frame, x_eye, y_origin, z_mid, inv_n, k: 1.0 / 120.0 + inv_n };
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
