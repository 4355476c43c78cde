//! Trapezoidal shadow maps (TSM).
//!
//! Martin and Tan, "Anti-aliasing and continuity with trapezoidal shadow maps" (EGSR 2004),
//! with its 80% rule as section 4 states it; unit cube clipping as the blog post says:
//! build the tight focused map first and run TSM in its clip space.
//!
//! In the focused map's normalised coordinates: Q = the convex hull of the projected view
//! body P (view frustum ∩ scene box), clipped to the focused map's inset square (every
//! shadowable visible receiver and every caster point that shadows one lies in Q). The centre
//! line runs from the projected centre of the near plane toward the projected centre of the
//! far plane (direction l). The top and base lines are perpendicular to l and touch Q; lambda
//! is their distance. The side lines pass through a projection point q at eta behind the top
//! line and touch Q.
//!
//! Where q goes. The paper's 80% rule: the point on the view axis at `focus` of the way from
//! the near plane to the far end of P, at distance delta' below the top line, maps to y = xi
//! (-0.6: 80% of the map lies between the top and it), which puts q at
//! eta = lambda delta' (1 + xi) / (lambda (1 - xi) - 2 delta'). The focus distance is where
//! the viewer's region of interest ends, well inside the view; the paper leaves it to the
//! application. Given as a fraction, `focus` is used as the rule says. By default (`focus:
//! None`) eta balances the perspective aliasing at both ends of the view as LiSPSM's n_opt
//! does. Along the centre line the map is the 1D perspective y(t) ~ 1 / (t + eta), so a
//! texel spans (t + eta)^2 / eta of t. dp/ds, that over the view depth z, is equal at z_n
//! (t = 0) and z_f (t = lambda) when eta = lambda sqrt(z_n) / (sqrt(z_f) - sqrt(z_n)), with
//! z_n and z_f the view depths where P begins and ends. In the LiSPSM paper's ideal
//! configuration (z_n = 1, z_f = 100, light perpendicular to the view) that is LiSPSM's warp:
//! dp/ds = 9.9 at both ends. (A focus at 80% of the depth with xi = -0.6 makes the
//! denominator vanish there: the side lines come out parallel and TSM is the focused map.)
//!
//! The 2D projective map sends this trapezoid to the inset square: with t the distance below
//! the top line, a the lateral offset from q and w = t + eta,
//!
//! ```text
//! x = (2 a - (r_max + r_min) w) / ((r_max - r_min) w),   y = (lambda w - 2 t (lambda + eta)) / (lambda w)
//! ```
//!
//! (r = a / w ranges over [r_min, r_max] inside the wedge). Depth is not warped: the map's
//! `depth_from_world` is the focused map's linear depth, and its clip-space z is the
//! constant 0.5 (z = 0.5 w), so the rasteriser never clips a caster by depth; the renderer
//! writes and compares the linear depth.
//!
//! Degenerate cases: spot lights and the view parallel to the light fall back to the focused
//! map. Parallel means within the sin(gamma) of 1e-3 below which LiSPSM and XPSM count it
//! parallel, where the centre line has no usable direction (the miner's lamp). When the 80%
//! rule asks for a projection point at or beyond infinity (delta' >= lambda (1 - xi) / 2),
//! the side lines are parallel and the map is the focused rectangle turned along the centre
//! line. Each is named in the diagnostics.

use glam::{DMat4, DVec2, DVec3, DVec4};

use crate::diagnostics::Fallback;
use crate::error::SetupError;
use crate::geometry::convex_hull_2d;
use crate::light::Light;
use crate::light_space::LightFrame;
use crate::map::{MapProjection, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::focused::focused_map;
use crate::techniques::on_whole_frame;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::with_fallback;

/// Trapezoidal shadow map (TSM, Martin and Tan 2004) over the focused map. See the module
/// documentation for the construction, where its projection point goes, and each degenerate
/// case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tsm {
    /// With `focus`: where the focus line lands in the map's y, in (-1, 1); -0.6 puts 80% of
    /// the map between the near side and the focus line.
    pub xi: f64,
    /// Where the focus point lies along the view, as a fraction of the way from the near plane
    /// to the far end of the view body, in [0, 1] (the 80% rule); `None`: the projection
    /// point that balances the aliasing at both ends of the view.
    pub focus: Option<f64>,
    /// Whether the warp is weakened where it would sample the view more coarsely than the
    /// focused map (see [`crate::Fallback::WarpLimited`]; eta is divided by the strength).
    pub limit: bool,
}

impl Default for Tsm {
    /// xi = -0.6; the projection point that balances the aliasing at z_n and z_f; the warp
    /// limit.
    fn default() -> Self {
        Self {
            xi: -0.6,
            focus: None,
            limit: true,
        }
    }
}

impl LimitedWarp for Tsm {
    fn check(&self) -> Result<(), SetupError> {
        if !(self.xi > -1.0 && self.xi < 1.0) {
            return Err(SetupError::InvalidParameter {
                name: "tsm xi",
                value: self.xi,
            });
        }
        if let Some(focus) = self.focus.filter(|f| !(0.0..=1.0).contains(f)) {
            return Err(SetupError::InvalidParameter {
                name: "tsm focus",
                value: focus,
            });
        }
        Ok(())
    }

    fn limited(&self) -> bool {
        self.limit
    }

    /// The setup with eta divided by `strength` (the projection point moved away).
    fn at_strength(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        strength: f64,
    ) -> Result<ShadowSetup, SetupError> {
        let mut setup = focused_map(input, basis).clone();
        setup.technique = self.name();
        let fallback_setup = setup.clone();
        let fall_back =
            |fallback: Fallback| Ok(with_fallback(fallback_setup.clone(), "tsm", fallback));
        if matches!(input.light, Light::Spot(_)) {
            return fall_back(Fallback::SpotLightNotWarped);
        }
        // Within LiSPSM's and XPSM's parallel threshold the centre line below is a stub whose
        // direction is rounding noise: a trapezoid along it would warp toward an arbitrary
        // side of the view.
        if let Light::Directional(light) = input.light
            && LightFrame::view_aligned(light.direction(), input.camera.forward()).is_none()
        {
            return fall_back(Fallback::LightParallelToView);
        }
        // A uniform fallback of the focused map (nothing visible) stays as it is.
        if setup
            .diagnostics
            .fallbacks
            .iter()
            .any(|f| matches!(f, Fallback::NoVisibleReceiver))
        {
            return Ok(setup);
        }
        let focused = setup.maps[0];
        // P's vertices (a directional light: no light frustum cuts it).
        let tolerance = basis.frame.tolerance;
        let body = basis.visible.view_body.vertices(tolerance);
        let ndc = |p: DVec3| focused.project(p).map(|v| v.truncate());
        let Some(q_polygon) = clipped_hull(
            body.iter().filter_map(|p| ndc(*p)).collect(),
            focused.inset_ndc(),
        ) else {
            return fall_back(Fallback::DegenerateFocusBody);
        };

        // The centre line, from the near plane's centre toward the far end of P.
        let camera = input.camera;
        let (eye, forward, near) = (camera.eye(), camera.forward(), camera.lens().near);
        let far = body
            .iter()
            .map(|p| (*p - eye).dot(forward))
            .fold(near, f64::max);
        let (Some(near_center), Some(far_center)) =
            (ndc(eye + forward * near), ndc(eye + forward * far))
        else {
            return fall_back(Fallback::DegenerateFocusBody);
        };
        let (l, t_min, lambda) = match centre_line(&q_polygon, near_center, far_center) {
            Ok(line) => line,
            Err(fallback) => return fall_back(fallback),
        };
        let side = l.perp();
        let eta = match self.focus {
            Some(focus) => {
                let focus_point =
                    ndc(eye + forward * (near + focus * (far - near))).unwrap_or(near_center);
                // delta' below the top line, kept a little off the top so that eta stays
                // positive.
                let delta = (focus_point.dot(l) - t_min).clamp(1e-3 * lambda, lambda);
                let denominator = lambda * (1.0 - self.xi) - 2.0 * delta;
                (denominator > 1e-9 * lambda)
                    .then(|| lambda * delta * (1.0 + self.xi) / denominator)
            }
            None => {
                // z_n: where P begins along the view (at least the near plane).
                let z_n = body
                    .iter()
                    .map(|p| (*p - eye).dot(forward))
                    .fold(far, f64::min)
                    .max(near);
                let (root_n, root_f) = (z_n.sqrt(), far.sqrt());
                (root_f > root_n * (1.0 + 1e-9)).then(|| lambda * root_n / (root_f - root_n))
            }
        };
        let eta = eta.map(|eta| eta / strength);
        let centre_lateral = near_center.dot(side);
        let rows = trapezoid_rows(
            &focused,
            &q_polygon,
            (l, side, centre_lateral),
            t_min,
            lambda,
            eta,
        );
        let map = ShadowMap {
            clip_from_world: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
            projection: MapProjection::Perspective,
            ..focused
        };
        setup.maps[0] = map;
        Ok(setup)
    }
}

impl ShadowTechnique for Tsm {
    fn name(&self) -> &'static str {
        "tsm"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let Light::Point(point) = input.light {
            return crate::techniques::per_face(self.name(), input, point, |input, basis| {
                self.setup_with(input, basis)
            });
        }
        on_whole_frame(input, |basis| self.setup_with(input, basis))
    }
}

/// The convex hull of `points`, clipped to the square [-s, s]^2, counter-clockwise; `None`
/// when less than a polygon remains.
fn clipped_hull(points: Vec<DVec2>, s: f64) -> Option<Vec<DVec2>> {
    let hull = convex_hull_2d(&points);
    if hull.len() < 3 {
        return None;
    }
    let mut polygon: Vec<DVec2> = hull.iter().map(|&i| points[i]).collect();
    // Sutherland-Hodgman against the four sides: keep n . p <= s.
    for n in [DVec2::X, -DVec2::X, DVec2::Y, -DVec2::Y] {
        let mut out = Vec::with_capacity(polygon.len() + 2);
        for (i, a) in polygon.iter().enumerate() {
            let b = polygon[(i + 1) % polygon.len()];
            let (da, db) = (s - n.dot(*a), s - n.dot(b));
            if da >= 0.0 {
                out.push(*a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                out.push(*a + (b - *a) * (da / (da - db)));
            }
        }
        polygon = out;
        if polygon.len() < 3 {
            return None;
        }
    }
    Some(polygon)
}

/// The rows of world -> trapezoid clip space, as combinations of the focused map's rows
/// (its clip x, y and w: for the focused map's normalised coordinates (x_f, y_f) = (X, Y) / W).
/// `axes`: the centre line's direction, its perpendicular, and the centre line's lateral
/// coordinate (along the perpendicular).
fn trapezoid_rows(
    focused: &ShadowMap,
    polygon: &[DVec2],
    axes: (DVec2, DVec2, f64),
    t_min: f64,
    lambda: f64,
    eta: Option<f64>,
) -> [DVec4; 4] {
    let (l, side, centre_lateral) = axes;
    let m = focused.clip_from_world;
    let (x_row, y_row, w_row) = (m.row(0), m.row(1), m.row(3));
    let s = focused.inset_ndc();
    // Homogeneous t (distance below the top line) of a world point: (x_f l.x + y_f l.y - t_min) W.
    let t_row = x_row * l.x + y_row * l.y - w_row * t_min;
    let pad = |lo: f64, hi: f64| {
        let m = 1e-9 * (hi - lo).abs().max(1e-300);
        (lo - m, hi + m)
    };
    match eta {
        Some(eta) => {
            // q: on the centre line, eta above the top line; a: the lateral offset from q.
            let a_row = x_row * side.x + y_row * side.y - w_row * centre_lateral;
            let (mut r_min, mut r_max) = (f64::INFINITY, f64::NEG_INFINITY);
            for p in polygon {
                let r = (p.dot(side) - centre_lateral) / (p.dot(l) - t_min + eta);
                r_min = r_min.min(r);
                r_max = r_max.max(r);
            }
            let (r_min, r_max) = pad(r_min, r_max);
            let lambda = lambda * (1.0 + 1e-9);
            // w = t + eta, scaled by 1 / eta so that the rows stay of moderate size.
            let w = (t_row + w_row * eta) / eta;
            let x = (a_row * (2.0 / eta) - w * (r_max + r_min)) * (s / (r_max - r_min));
            let y = (w * lambda - t_row * (2.0 * (lambda + eta) / eta)) * (s / lambda);
            [x, y, w * 0.5, w]
        }
        None => {
            // Parallel side lines: the rectangle turned along the centre line.
            let a_row = x_row * side.x + y_row * side.y;
            let (a_min, a_max) = polygon
                .iter()
                .map(|p| p.dot(side))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), a| {
                    (lo.min(a), hi.max(a))
                });
            let (a_min, a_max) = pad(a_min, a_max);
            let lambda = lambda * (1.0 + 1e-9);
            let x = (a_row * 2.0 - w_row * (a_max + a_min)) * (s / (a_max - a_min));
            let y = (w_row - t_row * (2.0 / lambda)) * s;
            [x, y, w_row * 0.5, w_row]
        }
    }
}

/// The trapezoid's centre line through the near and far ends of the view in the focused map
/// (`near_center`, `far_center`): its direction l, and where Q's points begin along it and
/// how far they reach (t_min, lambda); the fallback where the line or Q is degenerate.
fn centre_line(
    q_polygon: &[DVec2],
    near_center: DVec2,
    far_center: DVec2,
) -> Result<(DVec2, f64, f64), Fallback> {
    let extent = q_polygon.iter().fold(0.0f64, |m, p| m.max(p.length()));
    let centre = far_center - near_center;
    if centre.length() <= 1e-6 * extent.max(1e-300) {
        return Err(Fallback::LightParallelToView);
    }
    let l = centre.normalize();
    let t_min = q_polygon
        .iter()
        .map(|p| p.dot(l))
        .fold(f64::INFINITY, f64::min);
    let t_max = q_polygon
        .iter()
        .map(|p| p.dot(l))
        .fold(f64::NEG_INFINITY, f64::max);
    let lambda = t_max - t_min;
    if lambda.is_nan() || lambda <= 0.0 {
        return Err(Fallback::DegenerateFocusBody);
    }
    Ok((l, t_min, lambda))
}
