//! Perspective shadow maps (PSM), with Kozlov's fixes as the unit cube clipping blog post
//! recaps them.
//!
//! Stamminger and Drettakis, "Perspective shadow maps" (SIGGRAPH 2002); Kozlov, "Perspective
//! shadow maps: care and feeding" (GPU Gems, 2004); the blog post on robust unit cube clipping.
//!
//! The shadow map is built in the post-perspective space (PPS) of a virtual camera: the real
//! camera slid back along its view direction by `slide_back`, with its near and far planes at
//! the convex body B's nearest and farthest depth. A directional light becomes, in PPS, the
//! image of its direction's point at infinity: its vanishing point l, on the image of the
//! plane at infinity z = f / (f - n), beyond every finite point. Kozlov's three cases:
//! - directional in PPS (the light perpendicular to the view, l at infinity in PPS): an
//!   orthographic map along the light's PPS direction;
//! - a point light in PPS: a perspective map from l whose axis points to the visible
//!   receivers (the bounding cone);
//! - the inverted point light (the light behind the viewer, or a spot light behind the
//!   virtual camera, whose image lies beyond the image of the plane at infinity): the same
//!   projection from l. The inverse projection matrix Kozlov uses keeps PPS depth ordered
//!   along the rays. gnomon compares the linear world depth of `depth_from_world` instead,
//!   so only the 2D central projection from l matters, and every relevant point lies on one
//!   side of l.
//!
//! Casters: every caster point that can shadow a visible receiver lies in B. The virtual
//! camera slides back at least until B lies in front of it (Stamminger and Drettakis's
//! remedy for casters behind the viewer; Kozlov's near-plane clipping and z clamp address the
//! same points), and casters are cut to B's depth range before their extents are taken, so
//! none reaches the virtual camera's singular plane and none that matters is clipped. Unit
//! cube clipping then runs in the light's projection of PPS as for the other maps. The
//! clip-space z is w / 2 (never clipped); the renderer writes and compares the linear depth.
//!
//! The default slide, sqrt(z_n z_f) with z_f the far end of B, puts the virtual eye at
//! LiSPSM's n_opt from the near plane; `slide_back = 0` is the original PSM, whose perspective
//! aliasing follows the PSM line z (z_f - z_n) / z_f in the ideal case (LiSPSM paper, 4.3).
//!
//! Spot lights (the point-light case of Stamminger and Drettakis): l is the image of the
//! light's position, a normal point light when it is in front of the virtual camera and an
//! inverted one behind it. B, the visible receivers and the casters are cut to the light's
//! frustum first (the blog post's rule for spot lights), so every relevant point lies in
//! front of the light and on one side of l; when the axis toward the receivers would leave
//! one behind, the axis is the normal of the light plane's image, which has them all in
//! front.
//!
//! Degenerate cases: a flat B falls back to the focused map; nothing visible (or a spot
//! light that cannot see the view) gives the uniform map; each is named in the diagnostics.

use std::cell::OnceCell;

use glam::{DMat4, DVec3, DVec4};

use crate::bounds::SceneBounds;
use crate::boxes::Aabb;
use crate::camera::{Camera, Lens};
use crate::diagnostics::Fallback;
use crate::error::SetupError;
use crate::focus::{
    MapImages, ReceiverMap, VisibleScene, WalkedCasters, clipped_rectangle, walk_casters,
};
use crate::geometry::Plane;
use crate::light::Light;
use crate::light_space::{
    Extents, LightFrame, PlaneMap, Projector, RegionRows, corner_values, pad,
};
use crate::map::{MapProjection, MapSelection, ShadowMap, ShadowSetup};
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::FocusBasis;
use crate::techniques::focused::focused_map;
use crate::techniques::on_whole_frame;
use crate::techniques::view_warp::warp_diagnostics;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::{ANGULAR_PADDING, with_fallback};

/// Perspective shadow map (PSM, Stamminger and Drettakis 2002, with Kozlov's fixes): a map
/// built in the post-perspective space of a virtual camera slid back from the real one. See
/// the module documentation for the cases and how casters are kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Psm {
    /// How far the virtual camera slides back, in world units. `None`: sqrt(z_n z_f) (the
    /// virtual eye at LiSPSM's n_opt). Raised when B reaches behind the virtual camera.
    pub slide_back: Option<f64>,
    /// Whether the warp is weakened where it would sample the view more coarsely than the
    /// focused map (see [`crate::Fallback::WarpLimited`]; the virtual eye's distance from
    /// B's near side is divided by the strength).
    pub limit: bool,
}

impl Default for Psm {
    /// The slide of sqrt(z_n z_f), with the warp limit.
    fn default() -> Self {
        Self {
            slide_back: None,
            limit: true,
        }
    }
}

impl LimitedWarp for Psm {
    fn check(&self) -> Result<(), SetupError> {
        match self.slide_back {
            Some(s) if !(s.is_finite() && (0.0..=crate::MAX_COORDINATE).contains(&s)) => {
                Err(SetupError::InvalidParameter {
                    name: "psm slide back",
                    value: s,
                })
            }
            _ => Ok(()),
        }
    }

    fn limited(&self) -> bool {
        self.limit
    }

    /// The setup with the virtual eye's distance from B's near side divided by `strength`:
    /// B's depth range along the view, the virtual camera, the map's projector in its
    /// post-perspective space (PPS), the receivers and the casters under the map, the map.
    fn at_strength(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
        strength: f64,
    ) -> Result<ShadowSetup, SetupError> {
        let mut diagnostics = match warp_diagnostics(input, self.name(), basis) {
            Ok(diagnostics) => diagnostics,
            Err(uniform) => return Ok(*uniform),
        };
        // B's depth range along the view.
        let Some(view_depths) = body_view_depths(input.camera, basis) else {
            let focused = focused_map(input, basis).clone();
            return Ok(with_fallback(focused, "psm", Fallback::DegenerateFocusBody));
        };
        // The virtual camera and its PPS.
        let pps = Pps::new(
            basis,
            self.virtual_camera(input.camera, view_depths, strength)?,
        );
        // Receivers in PPS and along the light, then the map's projector in PPS.
        let (scene, visible) = (input.scene, &basis.visible);
        let linear_row = input.light.linear_depth_row();
        let receiver_box = receivers_under(visible, scene, pps.rows, |h| pps.of(DVec4::from(h)));
        let receivers_z = receivers_under(visible, scene, [linear_row], |[l]| {
            Some(DVec3::new(0.0, 0.0, l))
        })
        .max
        .z;
        let projector = pps.projector(input, visible, &receiver_box);
        // The receivers under the map (its x and y; its z is the linear depth along the
        // light, what the casters are culled against).
        let plane_map = PlaneMap::new(&projector, pps.from_world);
        let [map_x, map_y, map_w] = plane_map.rows();
        let parallel = matches!(projector, Projector::Parallel(_));
        let map_rows = [map_x, map_y, map_w, pps.rows[3], linear_row];
        let receivers = receivers_under(visible, scene, map_rows, |[x, y, w, pps_w, l]| {
            let front = pps_w > 0.0 && (parallel || w > 0.0);
            front.then(|| DVec3::new(x / w, y / w, l))
        })
        .with_max_z(receivers_z);
        // The casters that can shadow them, cut to B's depth slab.
        let slab = pps.caster_slab(input.camera, basis, &projector, view_depths, map_w);
        let walked = walk_map_casters(input, basis, &plane_map, &receivers, &slab);
        walked.count_into(scene, &mut diagnostics);
        // The map over the receivers and casters.
        let body_z = basis
            .body()
            .iter()
            .map(|p| linear_row.dot(p.extend(1.0)))
            .fold(f64::INFINITY, f64::min);
        let (region, linear) =
            fitted_region(&walked, &receivers, (receivers_z, body_z), &mut diagnostics);
        let map = psm_map(
            &projector,
            &region,
            linear,
            pps.from_world,
            linear_row,
            input,
            basis.frame.tolerance,
        );
        Ok(ShadowSetup {
            technique: self.name(),
            maps: vec![map],
            selection: MapSelection::Single,
            diagnostics,
        })
    }
}

impl Psm {
    /// The virtual camera: slid back so that B (its view depths `b0`, `b1`) lies at least the
    /// camera's near distance in front of it, the slide from B's near side divided by
    /// `strength`.
    fn virtual_camera(
        &self,
        camera: &Camera,
        (b0, b1): (f64, f64),
        strength: f64,
    ) -> Result<Camera, SetupError> {
        let (eye, forward, near) = (camera.eye(), camera.forward(), camera.lens().near);
        let requested = self
            .slide_back
            .unwrap_or_else(|| (near * b1.max(near)).sqrt());
        let slide = (b0 + requested.max(near - b0)) / strength - b0;
        Camera::look_at(
            eye - forward * slide,
            eye - forward * slide + forward,
            camera.up(),
            Lens {
                near: b0 + slide,
                far: b1 + slide,
                ..camera.lens()
            },
        )
    }
}

/// B's least and greatest depth along the view, or `None` where B is too flat for a
/// virtual camera (fewer than four points, or no depth range beyond the tolerance).
fn body_view_depths(camera: &Camera, basis: &FocusBasis) -> Option<(f64, f64)> {
    let (body, tolerance) = (basis.body(), basis.frame.tolerance);
    let (eye, forward) = (camera.eye(), camera.forward());
    let depth = |p: DVec3| (p - eye).dot(forward);
    let b0 = body.iter().map(|p| depth(*p)).fold(f64::INFINITY, f64::min);
    let b1 = body
        .iter()
        .map(|p| depth(*p))
        .fold(f64::NEG_INFINITY, f64::max);
    (body.len() >= 4 && !b1.is_nan() && b1 - b0 > tolerance).then_some((b0, b1))
}

/// The post-perspective space of the virtual camera: its matrix, its rows as affine
/// functions of world points, and B there.
struct Pps {
    from_world: DMat4,
    rows: [DVec4; 4],
    body: Vec<DVec3>,
}

impl Pps {
    fn new(basis: &FocusBasis, virtual_camera: Camera) -> Self {
        let from_world = virtual_camera.clip_from_world();
        let to_pps = |p: DVec3| -> DVec3 {
            let h = from_world * p.extend(1.0);
            h.truncate() / h.w
        };
        Self {
            from_world,
            rows: [0, 1, 2, 3].map(|i| from_world.row(i)),
            body: basis.body().iter().map(|p| to_pps(*p)).collect(),
        }
    }

    /// PPS of homogeneous PPS coordinates in front of the virtual camera.
    fn of(&self, h: DVec4) -> Option<DVec3> {
        (h.w > 0.0).then(|| h.truncate() / h.w)
    }

    /// The map's projector in PPS, from the light there (a directional light's vanishing
    /// point, a spot light's position): its cone must hold every visible receiver
    /// (`receiver_box` their PPS box) and all of B (every relevant caster lies in B).
    fn projector(
        &self,
        input: &SetupInput<'_>,
        visible: &VisibleScene,
        receiver_box: &Extents,
    ) -> Projector {
        let scene = input.scene;
        let l_h = self.from_world * input.light.homogeneous_source();
        let center = 0.5 * (receiver_box.min + receiver_box.max);
        let extent = (receiver_box.max - receiver_box.min).length().max(1e-300);
        // Whether every point of B and of the receivers lies in front of `l` along `axis`
        // (a convex cone around the axis, in PPS).
        let in_front = |l: DVec3, axis: DVec3| {
            let ahead = |q: DVec3| (q - l).dot(axis) > 1e-9 * (q - l).length();
            let pps_ahead = |h: [f64; 4]| self.of(DVec4::from(h)).is_some_and(&ahead);
            self.body.iter().all(|q| ahead(*q))
                && visible.all(
                    scene,
                    |p| pps_ahead(self.rows.map(|r| r.dot(p.extend(1.0)))),
                    |b| corner_values(&self.rows, b).into_iter().all(pps_ahead),
                )
        };
        // The axis used when the one toward the receivers leaves a point behind. Every finite
        // point in front of the virtual camera lies on the -z side of a directional light's
        // vanishing point (z = f (d - n) / (d (f - n)) < f / (f - n)). For a spot light, the
        // PPS image of its plane passes through l and has every relevant point (in front of
        // both the light and the virtual camera) on its inner side.
        let fallback_axis = match input.light {
            Light::Directional(_) => -DVec3::Z,
            Light::Spot(_) | Light::Point(_) => {
                let plane = self.from_world.inverse().transpose() * input.light.linear_depth_row();
                plane.truncate().normalize_or(-DVec3::Z)
            }
        };
        pps_projector(l_h, center, extent, in_front, fallback_axis)
    }

    /// The planes casters are cut by. First a spot light's frustum: its near plane first, so
    /// that the walk counts the casters it clips, and the frustum keeps them in front of the
    /// light. Then B's depth range (planes perpendicular to the view) and, for a perspective
    /// map in PPS, the front of its centre: d = axis . (P - l W) >= d_min W / 2 is a plane of
    /// homogeneous PPS coordinates, a world plane through `from_world`. `map_w` is the map's
    /// w row on world points.
    fn caster_slab(
        &self,
        camera: &Camera,
        basis: &FocusBasis,
        projector: &Projector,
        (b0, b1): (f64, f64),
        map_w: DVec4,
    ) -> Vec<Plane> {
        let (eye, forward) = (camera.eye(), camera.forward());
        let mut slab = basis.caster_planes.clone();
        slab.extend([
            Plane::through_point(eye + forward * b0, forward),
            Plane::through_point(eye + forward * b1, -forward),
        ]);
        if let Projector::Point { frame, position } = projector {
            // Every relevant point has d >= the smallest d over B and the receivers; cutting
            // at half of it keeps them all and keeps cut vertices off the singular plane d = 0.
            let d = |q: DVec3| (q - *position).dot(frame.forward);
            // d of a point's PPS image: the map's w row over PPS's w.
            let receivers_d = receivers_under(
                &basis.visible,
                basis.frame.input.scene,
                [map_w, self.rows[3]],
                |[w, pps_w]| (pps_w > 0.0).then(|| DVec3::splat(w / pps_w)),
            );
            let d_min = self
                .body
                .iter()
                .map(|q| d(*q))
                .fold(receivers_d.min.x, f64::min);
            let pps_plane = frame
                .forward
                .extend(-frame.forward.dot(*position) - 0.5 * d_min);
            let world = self.from_world.transpose() * pps_plane;
            let normal = world.truncate();
            if normal.length() > 0.0 {
                slab.push(Plane {
                    normal: normal / normal.length(),
                    offset: world.w / normal.length(),
                });
            }
        }
        slab
    }
}

/// The casters through their hierarchy, cut by `slab`, under the map (`plane_map`'s x and
/// y, with their linear depth along the light) over `receivers`.
fn walk_map_casters(
    input: &SetupInput<'_>,
    basis: &FocusBasis,
    plane_map: &PlaneMap,
    receivers: &Extents,
    slab: &[Plane],
) -> WalkedCasters {
    let scene = input.scene;
    let linear_row = input.light.linear_depth_row();
    let linear = |p: DVec3| linear_row.dot(p.extend(1.0));
    let on_map = |p: DVec3| plane_map.project(p).with_z(linear(p));
    let row = linear_row.truncate().abs();
    let box_on_map = |b: &Aabb| {
        // The corners' images bound the box's where the map's w is positive on all of it
        // (in front of the virtual camera and of l); else the walk must open or cut it.
        let Some(e) = plane_map.box_extents_ahead(b) else {
            return Extents::ALL;
        };
        let (c, r) = (linear(b.center()), row.dot(b.half_extents()));
        Extents {
            min: e.min.with_z(c - r),
            max: e.max.with_z(c + r),
        }
    };
    let tree = scene.caster_tree();
    // A node the slab crosses can only be culled: tested against the receivers' region as
    // world rows, made once for the walk, rather than by its corners' images.
    let region = OnceCell::new();
    let images = MapImages {
        node: |n: usize| box_on_map(&tree.node_box(n)),
        caster: |i: usize| box_on_map(&scene.casters()[i]),
        point: on_map,
        cut_node_outside: |n: usize, over: &Extents| {
            let region = region.get_or_init(|| RegionRows::new(plane_map, linear_row, over));
            let (c, h) = tree.nodes.center_half(n);
            region.as_ref()?.box_outside(c, h)
        },
    };
    walk_casters(
        scene,
        &images,
        receivers,
        slab,
        basis.light_near_first(),
        basis.frame.tolerance,
    )
}

/// The map's region in x and y (the receivers' extents where casters fall on them) and its
/// linear depth range (from the nearest caster, or B, to the farthest receiver), from the
/// receivers' and B's least linear depths (`receivers_z`, `body_z`). Without a relevant
/// caster it is the receivers', with [`Fallback::NoCasterForReceivers`].
fn fitted_region(
    walked: &WalkedCasters,
    receivers: &Extents,
    (receivers_z, body_z): (f64, f64),
    diagnostics: &mut crate::diagnostics::Diagnostics,
) -> (Extents, (f64, f64)) {
    let casters = &walked.extents;
    if walked.relevant == 0 {
        diagnostics.fallbacks.push(Fallback::NoCasterForReceivers);
        return (
            *receivers,
            (receivers_z.min(body_z.max(receivers_z - 1.0)), receivers_z),
        );
    }
    let (lo, hi) = clipped_rectangle(receivers, casters);
    let near_z = casters.min.z.max(body_z).min(receivers_z);
    (
        Extents {
            min: lo.extend(0.0),
            max: hi.extend(0.0),
        },
        (near_z, receivers_z),
    )
}

impl ShadowTechnique for Psm {
    fn name(&self) -> &'static str {
        "psm"
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

/// The light's projection in PPS: orthographic along the light's PPS direction when l (its
/// vanishing point or position) is at (or practically at) infinity, else perspective from
/// it, its axis toward the receivers, or `fallback_axis` when some of `points` would lie
/// behind that axis.
fn pps_projector(
    l_h: DVec4,
    center: DVec3,
    extent: f64,
    in_front: impl Fn(DVec3, DVec3) -> bool,
    fallback_axis: DVec3,
) -> Projector {
    let direction = l_h.truncate();
    if l_h.w.abs() * extent <= 1e-9 * direction.length() {
        return Projector::Parallel(LightFrame::fixed(-direction.normalize()));
    }
    let l = direction / l_h.w;
    if (center - l).length() > 1e7 * extent {
        return Projector::Parallel(LightFrame::fixed((center - l).normalize()));
    }
    let axis = (center - l).normalize();
    let axis = if in_front(l, axis) {
        axis
    } else {
        fallback_axis
    };
    Projector::Point {
        frame: LightFrame::fixed(axis),
        position: l,
    }
}

/// The extents of the visible receiver parts under a map given by `rows`, affine functions
/// of world points (coefficients on (p, 1)), read through the scene's hierarchy. `image`
/// takes a point's row values to its image, or to `None` where the map has none (behind the
/// virtual camera or the map's centre). A box with such a corner has no bounded image, and is
/// opened. A box's corners cost no product of a matrix ([`corner_values`]).
fn receivers_under<const K: usize>(
    visible: &VisibleScene,
    scene: &SceneBounds,
    rows: [DVec4; K],
    image: impl Fn([f64; K]) -> Option<DVec3>,
) -> Extents {
    let tree = scene.receiver_tree();
    let box_image = |b: &Aabb| {
        let mut e = Extents::EMPTY;
        for values in corner_values(&rows, b) {
            match image(values) {
                Some(q) => e.add(q),
                None => return Extents::ALL,
            }
        }
        e
    };
    visible.extents_under(
        scene,
        ReceiverMap {
            node: |n| box_image(&tree.node_box(n)),
            region: |c, h| box_image(&Aabb::from_min_max_unchecked(c - h, c + h)),
            bound: |i| box_image(&scene.receivers()[i]),
            exact: |_, exact| exact,
            points: |points: &[DVec3]| {
                let mut e = Extents::EMPTY;
                for p in points {
                    let p = p.extend(1.0);
                    // Every visible point has an image (it lies in P, in front of both).
                    if let Some(q) = image(rows.map(|r| r.dot(p))) {
                        e.add(q);
                    }
                }
                e
            },
            prune_cuts: true,
        },
    )
}

/// The PSM's matrices: the projector's rows on homogeneous PPS coordinates, times
/// `pps_from_world`; clip z = w / 2; linear depth along the light (`linear_row`) over
/// `linear`.
fn psm_map(
    projector: &Projector,
    region: &Extents,
    linear: (f64, f64),
    pps_from_world: DMat4,
    linear_row: DVec4,
    input: &SetupInput<'_>,
    tolerance: f64,
) -> ShadowMap {
    let padding = match projector {
        Projector::Parallel(_) => {
            1e-9 * (region.max - region.min)
                .truncate()
                .max_element()
                .max(1e-300)
        }
        Projector::Point { .. } => ANGULAR_PADDING,
    };
    let (x0, x1) = pad(region.min.x, region.max.x, padding);
    let (y0, y1) = pad(region.min.y, region.max.y, padding);
    let (l0, l1) = pad(linear.0, linear.1, tolerance);
    let s = input.map.inset_ndc();
    let (ax, bx) = (2.0 * s / (x1 - x0), -s * (x1 + x0) / (x1 - x0));
    let (ay, by) = (2.0 * s / (y1 - y0), -s * (y1 + y0) / (y1 - y0));
    let f = projector.frame();
    // Rows acting on homogeneous PPS coordinates (X, Y, Z, W).
    let rows = match projector {
        Projector::Parallel(_) => [
            (ax * f.right).extend(bx),
            (ay * f.up).extend(by),
            DVec4::new(0.0, 0.0, 0.0, 0.5),
            DVec4::W,
        ],
        Projector::Point { position, .. } => {
            // (v . (P - l W)) for the PPS point P / W.
            let row = |v: DVec3| v.extend(-v.dot(*position));
            let w = row(f.forward);
            [
                row(ax * f.right + bx * f.forward),
                row(ay * f.up + by * f.forward),
                w * 0.5,
                w,
            ]
        }
    };
    let clip_from_pps = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
    ShadowMap {
        clip_from_world: clip_from_pps * pps_from_world,
        depth_from_world: (linear_row - DVec4::W * l0) / (l1 - l0),
        resolution: input.map.resolution,
        viewport_inset: input.map.viewport_inset,
        projection: MapProjection::Perspective,
        view_depth_range: None,
    }
}
