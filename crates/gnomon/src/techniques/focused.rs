//! Focused shadow map (FSM) with unit cube clipping.
//!
//! Focusing: Brabec, Annen and Seidel, "Practical shadow mapping" (JGT 2002), and the convex
//! body B of Wimmer, Scherzer and Purgathofer, "Light Space Perspective Shadow Maps" (EGSR
//! 2004, section 3.3). Unit cube clipping: the blog post on robust unit cube clipping for
//! uniform, TSM, LiSPSM, PSM and XPSM maps (after Kozlov).

use crate::body::usable_body_extents;
use crate::diagnostics::{Diagnostics, Fallback, LightFrameKind};
use crate::error::SetupError;
use crate::focus::{caster_extents, unit_cube_clip};
use crate::geometry::ConvexPolyhedron;
use crate::light::{Light, PointLight};
use crate::light_space::{Extents, LightFrame, Projector, build_map};
use crate::map::{MapSelection, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::faces::faces;
use crate::techniques::uniform::{uniform_map, within_cone};
use crate::techniques::{ANGULAR_PADDING, on_whole_frame};

/// Focused shadow map (FSM): the light's projection (orthographic for a directional light,
/// the spot light's perspective for a spot light) fitted to what the camera sees, by unit
/// cube clipping. XY is the intersection of the relevant casters' and the visible receivers'
/// extents. Near is the casters' minimum depth (for a spot light, raised to the convex body
/// B's nearest point), far the receivers' maximum depth. A one-texel border (the viewport
/// inset) stays clear so that lookups outside the focus region read as lit.
///
/// Light frame (directional light): the LiSPSM paper's light space (map +y = the view
/// direction projected onto the map plane) when B's rectangle in it (which is P's, the view
/// frustum's in the scene box) is no larger than in the frame fixed by the light alone, else
/// the fixed frame; so the map is never coarser than the uniform map. Spot lights use the
/// fixed frame.
///
/// Degenerate cases, each named in the diagnostics:
/// - view parallel to the light: the fixed frame ([`Fallback::LightParallelToView`]);
/// - no visible receiver, or a spot light that cannot see the view frustum: the uniform map
///   ([`Fallback::NoVisibleReceiver`], [`Fallback::SpotLightMissesView`]);
/// - no caster that can shadow a visible receiver: the map is fitted to the receivers alone
///   ([`Fallback::NoCasterForReceivers`]);
/// - a spot light's B empty or flat: the near plane is the casters' minimum alone
///   ([`Fallback::DegenerateFocusBody`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Focused;

impl ShadowTechnique for Focused {
    fn name(&self) -> &'static str {
        "focused"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let Light::Point(point) = input.light {
            return crate::techniques::focused_per_face(self.name(), input, point);
        }
        input.map.validate()?;
        Ok(on_whole_frame(input, |basis| self.setup_on(input, basis)))
    }
}

impl Focused {
    /// The focused map of `input` on its (shared) visible scene and B.
    pub(crate) fn setup_on(&self, input: &SetupInput<'_>, basis: &FocusBasis) -> ShadowSetup {
        let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
        let tolerance = basis.frame.tolerance;
        let map = match focus(input, basis, &mut diagnostics) {
            Some((projector, region)) => map_of(&projector, &region, input, tolerance),
            None => uniform_map(input.light, input.scene, input.map, &mut diagnostics),
        };
        ShadowSetup {
            technique: self.name(),
            maps: vec![map],
            selection: MapSelection::Single,
            diagnostics,
        }
    }
}

/// The focused map of `region` under `projector`, padded as the focused map is.
fn map_of(
    projector: &Projector,
    region: &Extents,
    input: &SetupInput<'_>,
    tolerance: f64,
) -> ShadowMap {
    let xy_padding = match projector {
        Projector::Parallel(_) => tolerance,
        Projector::Point { .. } => ANGULAR_PADDING,
    };
    build_map(projector, region, input.map, xy_padding, tolerance)
}

/// The focused projector and region, or `None` when the uniform map is the fallback.
pub(crate) fn focus(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    diagnostics: &mut Diagnostics,
) -> Option<(Projector, Extents)> {
    let (projector, receivers, body_extents) = focus_receivers(input, basis, diagnostics)?;
    let casters = caster_extents(
        input.scene,
        &projector,
        &receivers,
        &basis.caster_planes,
        basis.frame.light_planes.is_some(),
        basis.frame.tolerance,
        diagnostics,
    );
    match unit_cube_clip(&receivers, &casters, body_extents.as_ref()) {
        Some(region) => Some((projector, region)),
        None => {
            diagnostics.fallbacks.push(Fallback::NoCasterForReceivers);
            Some((projector, receivers))
        }
    }
}

/// The map focused on the visible receivers alone, before unit cube clipping cuts it to the
/// casters' extents (which it holds): in x and y never finer than the focused map at any
/// point, and made without walking the casters. `None` where the focused map falls back to
/// the uniform map.
pub(crate) fn receivers_map(input: &SetupInput<'_>, basis: &FocusBasis) -> Option<ShadowMap> {
    let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
    let (projector, receivers, _) = focus_receivers(input, basis, &mut diagnostics)?;
    Some(map_of(&projector, &receivers, input, basis.frame.tolerance))
}

/// The focused map's light frame, the visible receivers' extents in it and B's (a spot
/// light's, where usable), or `None` when the uniform map is the fallback.
fn focus_receivers(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    diagnostics: &mut Diagnostics,
) -> Option<(Projector, Extents, Option<Extents>)> {
    let (tolerance, visible, light_planes) = (
        basis.frame.tolerance,
        &basis.visible,
        &basis.frame.light_planes,
    );
    diagnostics.visible_receivers = visible.visible_receivers();
    if visible.view_body.is_empty() && light_planes.is_some() {
        diagnostics.fallbacks.push(Fallback::SpotLightMissesView);
        return None;
    }
    if visible.visible_receivers() == 0 {
        diagnostics.fallbacks.push(Fallback::NoVisibleReceiver);
        return None;
    }
    // Only now, when the map is focused, does the frame matter.
    if let Light::Directional(light) = input.light
        && LightFrame::view_aligned(light.direction(), input.camera.forward()).is_none()
    {
        diagnostics.fallbacks.push(Fallback::LightParallelToView);
    }
    let projector = choose_frame(input, &visible.view_body, basis.frame.fixed, diagnostics);
    let mut receivers = basis.receiver_extents(&projector);
    if let Light::Spot(spot) = input.light {
        receivers = within_cone(receivers, spot);
    }
    // B raises a spot light's near plane, where a perspective depth wants it as far from the
    // light as it can be. An orthographic depth has even precision over its range, so a
    // directional light's map does not build B (its dozen plane clips were a quarter of the
    // setup).
    let body_extents = match input.light {
        Light::Directional(_) => None,
        _ => {
            let body = basis.body();
            diagnostics.focus_body_vertices = body.len();
            let extents = usable_body_extents(body, &projector, &receivers, tolerance);
            if extents.is_none() {
                diagnostics.fallbacks.push(Fallback::DegenerateFocusBody);
            }
            extents
        }
    };
    Some((projector, receivers, body_extents))
}

/// Picks the light frame: for a directional light the view-aligned frame when P's rectangle
/// in it is no larger than in the fixed frame. P (the view frustum in the scene box) has the
/// rectangle of B under a parallel projection (each point of B lies on a ray from P toward the
/// light), so this is the map "fitted to B" without building B. Since the visible receivers
/// lie in P and P in the scene box, the focused map is then never coarser than the uniform
/// map.
fn choose_frame(
    input: &SetupInput<'_>,
    view_body: &ConvexPolyhedron,
    fixed: Projector,
    diagnostics: &mut Diagnostics,
) -> Projector {
    diagnostics.light_frame = LightFrameKind::Fixed;
    let Light::Directional(light) = input.light else {
        return fixed;
    };
    let Some(frame) = LightFrame::view_aligned(light.direction(), input.camera.forward()) else {
        return fixed;
    };
    let aligned = Projector::Parallel(frame);
    let points = view_body.points();
    let area = |projector: &Projector| projector.points_extents(points).xy_area();
    if !points.is_empty() && area(&aligned) <= area(&fixed) {
        diagnostics.light_frame = LightFrameKind::ViewAligned;
        aligned
    } else {
        fixed
    }
}

/// The focused map per cube face (`cube`, and `focused` for a point light): where the light
/// stands inside the scene box, each face is fitted straight from the point light's frame,
/// with no frame of its own.
pub(crate) fn focused_per_face(
    name: &'static str,
    input: &SetupInput<'_>,
    point: &PointLight,
) -> Result<ShadowSetup, SetupError> {
    faces(name, input, point, true, |input, basis| {
        Ok(Focused.setup_on(input, basis))
    })
}

/// The focused map of `input` on `basis` (the input it was made for), made once: the map a
/// warp is compared with and falls back to.
pub(crate) fn focused_map<'b>(input: &SetupInput<'_>, basis: &'b FocusBasis) -> &'b ShadowSetup {
    basis.focused_or(|| Focused.setup_on(input, basis))
}
