//! The light space of a view-axis warp and the warp itself: what LiSPSM, PSM and XPSM compute
//! once per basis ([`WarpSpace`]) and reuse at every warp strength ([`Warp`]). See
//! [`view_warp`](super::view_warp) for the light space of directional and spot lights.

use std::cell::OnceCell;

use glam::{DMat4, DVec3, DVec4};

use crate::camera::Camera;
use crate::diagnostics::Fallback;
use crate::focus::ParallelBoxes;
use crate::geometry::Plane;
use crate::light::Light;
use crate::light_space::{Extents, LightFrame};
use crate::put_off::PutOff;

/// Light space before the warp: where light rays are parallel to Z.
#[derive(Debug, Clone, Copy)]
pub(crate) enum LightSpace {
    /// A directional light: (X, Y, Z) = (right . p, up . p, forward . p).
    Parallel(LightFrame),
    /// A spot light's post-perspective space: with q = p - position and d = forward . q,
    /// (X, Y, Z) = (right . q, up . q, -1) / d. A projective map (planes stay planes) that
    /// sends the rays from the light to lines along Z. Only for d > 0.
    Spot { frame: LightFrame, position: DVec3 },
}

impl LightSpace {
    /// The light space of `light` for `camera`'s view, and sin(gamma) (the view's angle to
    /// the light; for a spot light, to its rays there): the fallback where they are parallel.
    pub(super) fn of_view(camera: &Camera, light: &Light) -> Result<(Self, f64), Fallback> {
        let (eye, view) = (camera.eye(), camera.forward());
        match light {
            // Techniques see a point light's faces as spot lights, never the point itself.
            Light::Point(_) => Err(Fallback::LightParallelToView),
            Light::Directional(light) => {
                let frame = LightFrame::view_aligned(light.direction(), view)
                    .ok_or(Fallback::LightParallelToView)?;
                Ok((
                    LightSpace::Parallel(frame),
                    view.cross(light.direction()).length(),
                ))
            }
            Light::Spot(spot) => {
                // The image of the view direction in the spot's post-perspective space (see
                // the module documentation).
                let (f, q_e) = (spot.direction(), eye - spot.position());
                let v = view * f.dot(q_e) - q_e * f.dot(view);
                let frame = (q_e.length() > 0.0)
                    .then(|| LightFrame::view_aligned(f, v / q_e.length()))
                    .flatten()
                    .ok_or(Fallback::LightParallelToView)?;
                Ok((
                    LightSpace::Spot {
                        frame,
                        position: spot.position(),
                    },
                    v.length() / q_e.length(),
                ))
            }
        }
    }

    pub(super) fn frame(&self) -> &LightFrame {
        match self {
            LightSpace::Parallel(frame) | LightSpace::Spot { frame, .. } => frame,
        }
    }

    /// World -> homogeneous light space (X W, Y W, Z W, W).
    pub(super) fn light_from_world(&self) -> DMat4 {
        let rows = match self {
            LightSpace::Parallel(f) => [
                f.right.extend(0.0),
                f.up.extend(0.0),
                f.forward.extend(0.0),
                DVec4::W,
            ],
            LightSpace::Spot { frame: f, position } => {
                let row = |v: DVec3| v.extend(-v.dot(*position));
                [
                    row(f.right),
                    row(f.up),
                    DVec4::new(0.0, 0.0, 0.0, -1.0),
                    row(f.forward),
                ]
            }
        };
        DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose()
    }

    /// Light-space coordinates (X, Y, Z) of a world point.
    #[inline]
    pub(super) fn light(&self, p: DVec3) -> DVec3 {
        match self {
            LightSpace::Parallel(f) => DVec3::new(f.right.dot(p), f.up.dot(p), f.forward.dot(p)),
            LightSpace::Spot { frame: f, position } => {
                let q = p - *position;
                DVec3::new(f.right.dot(q), f.up.dot(q), -1.0) / f.forward.dot(q)
            }
        }
    }

    /// The world plane Y = y, its inside Y >= y (`above`) or Y <= y. For a spot light,
    /// up . q = y d is a plane through the light (valid in front of it, d > 0).
    pub(super) fn y_plane(&self, y: f64, above: bool) -> Plane {
        let sign = if above { 1.0 } else { -1.0 };
        match self {
            LightSpace::Parallel(f) => Plane {
                normal: sign * f.up,
                offset: -sign * y,
            },
            LightSpace::Spot { frame: f, position } => {
                Plane::through_point(*position, (sign * (f.up - y * f.forward)).normalize())
            }
        }
    }
}

/// What a technique sees when it chooses its warp.
pub(crate) struct WarpContext {
    /// B's extents in light space (X, Y, Z).
    pub body_light: Extents,
    /// B's extent along light space's y axis in world units (for a directional light the
    /// same as `body_light`'s; for a spot light measured along the frame's up direction).
    pub depth_world: f64,
    /// sin of the angle between the view and the light direction (for a spot light, between
    /// the view direction and the light's ray at the eye).
    pub sin_gamma: f64,
    /// The eye in light space (for a spot light: its image when it is in front of the light,
    /// with X clamped to B's; else B's centre).
    pub eye_light: DVec3,
    /// How far along the view the visible scene begins: the least view depth of P (the view
    /// frustum clipped by the scene box), at least the camera's near distance.
    pub near_depth: f64,
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
    pub(super) space: LightSpace,
    pub(super) x_eye: f64,
    pub(super) y_origin: f64,
    pub(super) z_mid: f64,
    /// The warp strength (LiSPSM: 1 / n; 0: no warp).
    pub(super) inv_n: f64,
    /// Scale of s (LiSPSM: 1 / (f - n) + 1 / n, so that s runs over [0, 1] across B).
    pub(super) k: f64,
}

impl Warp {
    /// Light-space coordinates (X, Y, Z) of a world point.
    #[inline]
    pub(super) fn light(&self, p: DVec3) -> DVec3 {
        self.space.light(p)
    }

    /// w at light-space Y.
    #[inline]
    pub(super) fn w(&self, y: f64) -> f64 {
        1.0 + (y - self.y_origin) * self.inv_n
    }

    /// (u, s, z) and w of light-space coordinates.
    pub(super) fn warp(&self, q: DVec3) -> (DVec3, f64) {
        let w = self.w(q.y);
        (
            DVec3::new(
                q.x - self.x_eye,
                (q.y - self.y_origin) * self.k,
                q.z - self.z_mid,
            ) / w,
            w,
        )
    }

    /// The extents of the warped light-space points.
    pub(super) fn points_extents(&self, points: &[DVec3]) -> Extents {
        let (x_eye, y_origin, z_mid, inv_n, k) =
            (self.x_eye, self.y_origin, self.z_mid, self.inv_n, self.k);
        let mut ext = Extents::EMPTY;
        for q in points {
            let dy = q.y - y_origin;
            let r = 1.0 / (1.0 + dy * inv_n);
            ext.add(DVec3::new((q.x - x_eye) * r, dy * k * r, (q.z - z_mid) * r));
        }
        ext
    }

    /// The warped extents of the light-space box [lo, hi], with its Y inside B's range so
    /// that w > 0. u = (X - X_eye) / w is largest at the smallest w when X - X_eye >= 0, and
    /// at the largest w otherwise (likewise z). s grows with Y. So six divisions give the
    /// exact extents of the box's image.
    pub(super) fn box_extents(&self, lo: DVec3, hi: DVec3) -> Extents {
        // Two divisions, then products (this runs once per caster).
        let r0 = 1.0 / (1.0 + (lo.y - self.y_origin) * self.inv_n);
        let r1 = 1.0 / (1.0 + (hi.y - self.y_origin) * self.inv_n);
        let range = |a: f64, b: f64| {
            let lo = a * if a < 0.0 { r0 } else { r1 };
            let hi = b * if b < 0.0 { r1 } else { r0 };
            (lo, hi)
        };
        let (u0, u1) = range(lo.x - self.x_eye, hi.x - self.x_eye);
        let (z0, z1) = range(lo.z - self.z_mid, hi.z - self.z_mid);
        let s0 = (lo.y - self.y_origin) * self.k * r0;
        let s1 = (hi.y - self.y_origin) * self.k * r1;
        Extents {
            min: DVec3::new(u0, s0, z0),
            max: DVec3::new(u1, s1, z1),
        }
    }

    /// The rows of world -> (u w, s w, z w, w): the warp on homogeneous light-space
    /// coordinates, after light space.
    pub(super) fn rows(&self) -> [DVec4; 4] {
        let warp_from_light = DMat4::from_cols(
            DVec4::new(1.0, 0.0, 0.0, -self.x_eye),
            DVec4::new(0.0, self.k, 0.0, -self.k * self.y_origin),
            DVec4::new(0.0, 0.0, 1.0, -self.z_mid),
            DVec4::new(0.0, self.inv_n, 0.0, 1.0 - self.y_origin * self.inv_n),
        )
        .transpose();
        let m = warp_from_light * self.space.light_from_world();
        [m.row(0), m.row(1), m.row(2), m.row(3)]
    }
}

/// What a view-axis warp needs at every strength, computed once per basis: light space, B
/// there, the visible receivers' vertices there, and the casters that can matter at any
/// strength. Those are cut to B's Y range, with the ones beside and behind the receivers
/// culled: both tests are the same before and after the warp.
pub(crate) struct WarpSpace {
    pub(super) space: LightSpace,
    pub(super) sin_gamma: f64,
    /// B's extents in light space, and its least linear depth along the light.
    pub(super) body_light: Extents,
    pub(super) body_linear: f64,
    pub(super) eye_light: DVec3,
    pub(super) depth_world: f64,
    pub(super) near_depth: f64,
    /// The visible receivers' vertices in light space, for a spot light (for a directional
    /// light the receivers are read from the scene's hierarchy at each strength).
    pub(super) receiver_points: Vec<DVec3>,
    /// What the receivers' extents in light space decide, made with a spot light's
    /// vertices, or, for a directional light, after the first warp's walk of the receivers
    /// (which gathers their light-space extents too: [`WarpSpace::receivers_under`]).
    pub(super) light_parts: OnceCell<LightParts>,
    /// How many casters the scene has.
    pub(super) caster_count: usize,
}

/// What a warp reads of the visible receivers' extents in light space: their linear depth
/// range along the light, and the casters that can matter.
pub(super) struct LightParts {
    pub(super) receivers_linear: (f64, f64),
    pub(super) casters: WarpCasters,
}

/// The casters a warp may need, in light space.
pub(super) enum WarpCasters {
    /// The scene's casters, walked through their hierarchy at each strength (a directional
    /// light with nothing else cutting them).
    Tree(TreeCasters),
    /// The vertices of each caster's cut part, as ranges of `points`, with their least
    /// linear depth and whether a spot light's near plane clips part of the caster away.
    Points {
        points: Vec<DVec3>,
        casters: Vec<(u32, u32, f64, bool)>,
    },
}

/// The casters of a directional light's warp, culled where no strength can make them
/// relevant. A caster matters only where its light-space box meets `columns`: the receivers'
/// columns, grown by a slack and cut to B's Y range, up to the receivers' far depth. Its Y is
/// cut to `y_range` (B's) before it is warped.
pub(super) struct TreeCasters {
    pub(super) frame: LightFrame,
    pub(super) columns: Extents,
    pub(super) y_range: (f64, f64),
}

/// What the relevant casters give a warp: their warped extents (in x and y only as far as
/// they lie over the receivers), their least linear depth and how many casters are not
/// culled (see [`crate::Diagnostics::relevant_casters`]).
pub(super) struct WarpedCasters {
    pub(super) extents: Extents,
    pub(super) linear_min: f64,
    pub(super) relevant: usize,
    /// How many of the relevant casters a spot light's near plane clips.
    pub(super) near_clipped: usize,
}

impl WarpSpace {
    /// The warp of this space that `choose` picks from what the space knows of B and the eye.
    pub(super) fn warp(&self, choose: impl FnOnce(&WarpContext) -> WarpChoice) -> Warp {
        let body_light = self.body_light;
        let choice = choose(&WarpContext {
            body_light,
            depth_world: self.depth_world,
            sin_gamma: self.sin_gamma,
            eye_light: self.eye_light,
            near_depth: self.near_depth,
        });
        Warp {
            space: self.space,
            x_eye: self.eye_light.x,
            y_origin: choice.y_origin,
            z_mid: 0.5 * (body_light.min.z + body_light.max.z),
            inv_n: choice.inv_n,
            k: choice.k,
        }
    }
}

impl TreeCasters {
    /// Whether a light-space box meets the columns.
    #[inline]
    pub(super) fn meets(&self, l: &Extents) -> bool {
        self.columns.xy_overlaps(l, 0.0) && l.min.z <= self.columns.max.z
    }

    /// The casters under `warp` whose warped boxes overlap `receivers` (the receivers'
    /// warped extents) in x and y: their extents, least linear depth and count. A subtree
    /// whose node lies outside the columns or beside the receivers is culled whole. One whose
    /// image (over the receivers) and depths add nothing to what is gathered so far is
    /// counted whole without being opened. One that would add only in x and y is put off to
    /// the end, when the extents have grown, and opened then, the farthest-reaching first,
    /// where they still do not hold it ([`PutOff`]). Children nearer the light are opened
    /// first, so that the nearest depth is found early.
    pub(super) fn warped(
        &self,
        scene: &crate::bounds::SceneBounds,
        warp: &Warp,
        receivers: &Extents,
    ) -> WarpedCasters {
        let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
        let over = Extents {
            min: (receivers.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
            max: (receivers.max.truncate() + xy_slack).extend(f64::INFINITY),
        };
        let (y0, y1) = self.y_range;
        // The warped box of a light-space box cut to B's Y range.
        let warped = |l: &Extents| {
            let (lo, hi) = (l.min.with_y(l.min.y.max(y0)), l.max.with_y(l.max.y.min(y1)));
            warp.box_extents(lo, hi)
        };
        let tree = scene.caster_tree();
        let nodes = ParallelBoxes::new(&tree.nodes, &self.frame);
        let boxes = ParallelBoxes::new(scene.caster_arrays(), &self.frame);
        // Their far side does not matter (see `caster_extents`).
        let mut extents = Extents {
            min: DVec3::INFINITY,
            max: DVec3::NEG_INFINITY.with_z(f64::INFINITY),
        };
        let mut linear_min = f64::INFINITY;
        let mut relevant = 0;
        // Nodes with their light-space boxes, and whether to open the node without a test
        // (one taken from the put-off subtrees).
        let mut stack = Vec::with_capacity(64);
        if !tree.is_empty() {
            stack.push((0usize, nodes.extents(0), false));
        }
        let mut put_off = PutOff::new(&over);
        loop {
            while let Some((node, light, open)) = stack.pop() {
                if !open {
                    if !self.meets(&light) {
                        continue;
                    }
                    let image = warped(&light);
                    if !receivers.xy_overlaps(&image, xy_slack) {
                        continue;
                    }
                    // What the node's boxes can add: their images over the receivers, and
                    // their depths (a box's lie within its node's). Where the depths do not,
                    // the node is counted whole: unopened if the extents hold its image, else
                    // put off (only its x and y may add, which the extents may hold once
                    // they have grown).
                    let over_receivers = image.clamped_to(&over);
                    if image.min.z >= extents.min.z && light.min.z >= linear_min {
                        relevant += tree.size(node);
                        if !extents.contains(&over_receivers) {
                            put_off.push((node, light), over_receivers);
                        }
                        continue;
                    }
                }
                if !tree.is_leaf(node) {
                    // The child nearer the light is opened first.
                    let [a, b] = tree.children(node).map(|c| (c, nodes.extents(c), false));
                    if a.1.min.z < b.1.min.z {
                        stack.extend([b, a]);
                    } else {
                        stack.extend([a, b]);
                    }
                    continue;
                }
                for &i in tree.boxes_of(node) {
                    let light = boxes.extents(i as usize);
                    if !self.meets(&light) {
                        continue;
                    }
                    let image = warped(&light);
                    if receivers.xy_overlaps(&image, xy_slack) {
                        relevant += 1;
                        extents = extents.union(&image.clamped_to(&over));
                        linear_min = linear_min.min(light.min.z);
                    }
                }
            }
            // A put-off subtree's depths were held when it was put off, and still are; it is
            // opened (and counted again) where the extents do not hold its image now.
            match put_off.pop(&extents) {
                Some((node, light)) => {
                    relevant -= tree.size(node);
                    stack.push((node, light, true));
                }
                None => break,
            }
        }
        WarpedCasters {
            extents,
            linear_min,
            relevant,
            near_clipped: 0,
        }
    }
}
