//! Light space: the frame a shadow map is built in, projecting world points into it, extents
//! there, and turning extents into a map's matrices.

use glam::{DMat4, DVec2, DVec3, DVec4};

use crate::boxes::Aabb;
use crate::geometry::Plane;
use crate::light::Light;
use crate::map::{MapProjection, MapSettings, ShadowMap};

/// Below this sin(gamma) the view direction counts as parallel to the light.
pub(crate) const PARALLEL_SIN_GAMMA: f64 = 1e-3;

/// An orthonormal frame looking along a light direction: `right = forward x up`, so that
/// a map built in it has the handedness of an ordinary camera's clip space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LightFrame {
    pub right: DVec3,
    pub up: DVec3,
    /// The direction the light travels (the map's depth axis).
    pub forward: DVec3,
}

impl LightFrame {
    /// The frame fixed by the light direction alone: `up` is world +Y (or +Z when the light is
    /// nearly vertical) made perpendicular to `forward`.
    pub fn fixed(forward: DVec3) -> Self {
        let hint = if forward.y.abs() < 0.9 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        Self::from_up_hint(forward, hint)
    }

    /// The LiSPSM paper's light space (section 3.4): up is the view direction made
    /// perpendicular to the light. `None` when they are parallel.
    pub fn view_aligned(forward: DVec3, view_direction: DVec3) -> Option<Self> {
        let up = view_direction - forward * forward.dot(view_direction);
        (up.length() >= PARALLEL_SIN_GAMMA).then(|| Self::from_up_hint(forward, up))
    }

    fn from_up_hint(forward: DVec3, hint: DVec3) -> Self {
        let right = forward.cross(hint).normalize();
        let up = right.cross(forward);
        Self { right, up, forward }
    }
}

/// How world points are projected into a map's plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Projector {
    /// Orthographic along the frame's forward: (right . p, up . p, forward . p).
    Parallel(LightFrame),
    /// Perspective from `position`: with X, Y, d the frame coordinates of `p - position`,
    /// (X / d, Y / d, d). Only for points with d > 0.
    Point { frame: LightFrame, position: DVec3 },
}

impl Projector {
    pub fn frame(&self) -> &LightFrame {
        match self {
            Projector::Parallel(f) => f,
            Projector::Point { frame, .. } => frame,
        }
    }

    /// (x, y, depth) of a world point; see the variants.
    #[inline]
    pub fn project(&self, p: DVec3) -> DVec3 {
        match self {
            Projector::Parallel(f) => DVec3::new(f.right.dot(p), f.up.dot(p), f.forward.dot(p)),
            Projector::Point { frame: f, position } => {
                let q = p - *position;
                let d = f.forward.dot(q);
                DVec3::new(f.right.dot(q) / d, f.up.dot(q) / d, d)
            }
        }
    }

    /// The extents of a box. For a point projector every corner must be in front (d > 0).
    pub fn box_extents(&self, aabb: &Aabb) -> Extents {
        match self {
            Projector::Parallel(f) => {
                // The image of a box under a rotation: centre plus |R| times the half extents.
                let c = self.project(aabb.center());
                let e = aabb.half_extents();
                let h = DVec3::new(
                    f.right.abs().dot(e),
                    f.up.abs().dot(e),
                    f.forward.abs().dot(e),
                );
                Extents {
                    min: c - h,
                    max: c + h,
                }
            }
            Projector::Point { frame, position } => {
                if let Some(ext) = axis_box_extents(frame, *position, aabb) {
                    return ext;
                }
                let mut ext = Extents::EMPTY;
                for c in aabb.corners() {
                    ext.add(self.project(c));
                }
                ext
            }
        }
    }

    /// The projector's map plane as rows (x, y, w) on homogeneous points (p, 1): the image's
    /// x and y are x / w and y / w, and a point projector's w is positive in front of it
    /// (it is its depth there).
    pub fn plane_rows(&self) -> [DVec4; 3] {
        let f = self.frame();
        match self {
            Projector::Parallel(_) => [f.right.extend(0.0), f.up.extend(0.0), DVec4::W],
            Projector::Point { position, .. } => {
                let row = |v: DVec3| v.extend(-v.dot(*position));
                [row(f.right), row(f.up), row(f.forward)]
            }
        }
    }

    /// The extents of points (for a point projector, points in front of it).
    pub fn points_extents(&self, points: &[DVec3]) -> Extents {
        let mut ext = Extents::EMPTY;
        for p in points {
            ext.add(self.project(*p));
        }
        ext
    }

    /// The world plane of the rays through the 2D line `n2 . (x, y) + c2 = 0` of the map plane,
    /// its inside where `n2 . (x, y) + c2 >= 0`.
    pub fn plane_from_line(&self, n2: DVec2, c2: f64) -> Option<Plane> {
        let f = self.frame();
        let (normal, offset) = match self {
            Projector::Parallel(_) => (n2.x * f.right + n2.y * f.up, c2),
            Projector::Point { position, .. } => {
                let n = n2.x * f.right + n2.y * f.up + c2 * f.forward;
                (n, -n.dot(*position))
            }
        };
        let len = normal.length();
        (len > 0.0 && len.is_finite()).then(|| Plane {
            normal: normal / len,
            offset: offset / len,
        })
    }
}

/// A projector composed with a projective map of world points (`source_from_world`): the
/// homogeneous rows of (x w, y w, w) on world points, so that a world point reaches the
/// map plane with one reciprocal.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlaneMap {
    rows: [DVec4; 3],
}

impl PlaneMap {
    pub fn new(projector: &Projector, source_from_world: DMat4) -> Self {
        let world_from_source_rows = source_from_world.transpose();
        Self {
            rows: projector.plane_rows().map(|r| world_from_source_rows * r),
        }
    }

    /// The rows (x, y, w) on world points (p, 1): the projector's composed with the map.
    pub fn rows(&self) -> [DVec4; 3] {
        self.rows
    }

    /// (x, y, 0) of a world point with w > 0.
    #[inline]
    pub fn project(&self, p: DVec3) -> DVec3 {
        let h = p.extend(1.0);
        let r = 1.0 / self.rows[2].dot(h);
        DVec3::new(self.rows[0].dot(h) * r, self.rows[1].dot(h) * r, 0.0)
    }

    /// The (x, y) extents of a box whose corners all have w > 0, else `None`: each row's value
    /// at a corner is its value at the centre plus or minus its products with the half
    /// extents, and one pass over the corners both tests and projects them.
    #[inline(always)]
    pub fn box_extents_ahead(&self, aabb: &Aabb) -> Option<Extents> {
        let corners = corner_values(&self.rows, aabb);
        if corners.iter().any(|[_, _, w]| *w <= 0.0) {
            return None;
        }
        let mut ext = Extents::EMPTY;
        for [x, y, w] in corners {
            let r = 1.0 / w;
            ext.add(DVec3::new(x * r, y * r, 0.0));
        }
        Some(ext)
    }
}

/// A region of a [`PlaneMap`] (x and y, with a linear depth z along the light) as affine rows
/// on world points, to find the boxes wholly outside it without projecting their corners:
/// such a box lies where w > 0 and one of the region's bounding rows is negative.
pub(crate) struct RegionRows {
    /// w, then x - x0 w, x1 w - x, y - y0 w, y1 w - y and z1 - z: each negative beyond one
    /// side of the region.
    rows: [DVec4; 6],
    abs: [DVec3; 6],
}

impl RegionRows {
    /// The rows of `region`'s x, y and far z under `map` and `depth_row`; `None` where they
    /// are not finite.
    pub fn new(map: &PlaneMap, depth_row: DVec4, region: &Extents) -> Option<Self> {
        let [x, y, w] = map.rows;
        let (lo, hi) = (region.min, region.max);
        let rows = [
            w,
            x - w * lo.x,
            w * hi.x - x,
            y - w * lo.y,
            w * hi.y - y,
            DVec4::W * hi.z - depth_row,
        ];
        rows.iter().all(|r| r.is_finite()).then(|| Self {
            rows,
            abs: rows.map(|r| r.truncate().abs()),
        })
    }

    /// Whether the box of centre `c` and half extents `h` lies wholly outside the region,
    /// where w > 0 on all of it; `None` where w may reach 0. The same as testing its
    /// corners' images, but for rounding.
    #[inline(always)]
    pub fn box_outside(&self, c: DVec3, h: DVec3) -> Option<bool> {
        let c = c.extend(1.0);
        let (rows, abs) = (&self.rows, &self.abs);
        if rows[0].dot(c) - abs[0].dot(h) <= 0.0 {
            return None;
        }
        Some((1..6).any(|k| rows[k].dot(c) + abs[k].dot(h) < 0.0))
    }
}

/// The values of `rows` (affine functions of world points, coefficients on (p, 1)) at a box's
/// eight corners: each its value at the centre plus or minus its products with the half
/// extents, with no product of a matrix per corner.
#[inline(always)]
pub(crate) fn corner_values<const K: usize>(rows: &[DVec4; K], b: &Aabb) -> [[f64; K]; 8] {
    let (c, h) = (b.center().extend(1.0), b.half_extents());
    let parts = rows.map(|r| (r.dot(c), r.truncate() * h));
    std::array::from_fn(|corner| {
        let sign = |bit: usize| if corner & bit == 0 { -1.0 } else { 1.0 };
        let s = DVec3::new(sign(1), sign(2), sign(4));
        parts.map(|(base, d)| base + d.dot(s))
    })
}

/// [`Projector::box_extents`] of a point projector whose frame's axes are world axes (a cube
/// face's, [`crate::light::PointLight::face_light`]); `None` for any other frame. Each frame
/// coordinate of a corner is then one world coordinate times its axis's nonzero component
/// (the dot product's other terms are zeros). So the corners' (x, d) pairs are the four
/// pairs of the box's x and d ranges, and likewise for y. That gives the corners' images
/// with two divisions per axis instead of sixteen, with the same values.
fn axis_box_extents(frame: &LightFrame, position: DVec3, aabb: &Aabb) -> Option<Extents> {
    let axes = world_axes(frame)?;
    let (x, y, d) = axis_ranges(&axes, position, aabb);
    let over = |(lo, hi): (f64, f64)| {
        let (near, far) = (lo / d.0, lo / d.1);
        let (near_hi, far_hi) = (hi / d.0, hi / d.1);
        (near.min(far), near_hi.max(far_hi))
    };
    let ((x0, x1), (y0, y1)) = (over(x), over(y));
    Some(Extents {
        min: DVec3::new(x0, y0, d.0),
        max: DVec3::new(x1, y1, d.1),
    })
}

/// For each of a frame's right, up and forward: the world axis it lies along (0, 1, 2) and
/// its sign; `None` unless all three are world axes (a cube face's frame).
fn world_axes(frame: &LightFrame) -> Option<[(usize, f64); 3]> {
    let axis = |v: DVec3| match (v.x != 0.0, v.y != 0.0, v.z != 0.0) {
        (true, false, false) => Some((0, v.x)),
        (false, true, false) => Some((1, v.y)),
        (false, false, true) => Some((2, v.z)),
        _ => None,
    };
    Some([axis(frame.right)?, axis(frame.up)?, axis(frame.forward)?])
}

/// The ranges of a box's frame coordinates x, y and d.
type FrameRanges = ((f64, f64), (f64, f64), (f64, f64));

/// The ranges of the frame coordinates (x, y, d) of `aabb - position`, for the frame whose
/// [`world_axes`] are `axes`: each one world coordinate's range times the axis's component.
#[inline]
fn axis_ranges(axes: &[(usize, f64); 3], position: DVec3, aabb: &Aabb) -> FrameRanges {
    let (lo, hi) = (
        (aabb.min() - position).to_array(),
        (aabb.max() - position).to_array(),
    );
    let range = |axis| axis_range(&lo, &hi, axis);
    (range(axes[0]), range(axes[1]), range(axes[2]))
}

/// The range of one frame coordinate, the world axis and sign `(k, s)` of [`world_axes`],
/// over the box from `lo` to `hi` (relative to the light).
#[inline(always)]
fn axis_range(lo: &[f64; 3], hi: &[f64; 3], (k, s): (usize, f64)) -> (f64, f64) {
    if s > 0.0 {
        (lo[k], hi[k])
    } else {
        (-hi[k], -lo[k])
    }
}

/// A cube face's frustum under its own point projector, whose frame's axes are world axes
/// ([`crate::light::PointLight::face_light`]): the points with depth d in `[near, far]` and
/// `|x|, |y| <= tangent * d` in frame coordinates from the light. A box's frame coordinates
/// then range over a box too, which makes the image of a box's part inside the frustum a
/// closed form ([`AxisFrustum::box_extents`]) where other frames need the box cut by the
/// frustum's planes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AxisFrustum {
    position: DVec3,
    axes: [(usize, f64); 3],
    tangent: f64,
    inv_tangent: f64,
    near: f64,
    far: f64,
}

impl AxisFrustum {
    /// The frustum of a point projector with `frame` at `position`; `None` unless the frame's
    /// axes are world axes.
    pub fn new(
        frame: &LightFrame,
        position: DVec3,
        tangent: f64,
        near: f64,
        far: f64,
    ) -> Option<Self> {
        Some(Self {
            position,
            axes: world_axes(frame)?,
            tangent,
            inv_tangent: 1.0 / tangent,
            near,
            far,
        })
    }

    /// The extents of the image of `aabb`'s part inside the frustum (empty where it misses
    /// the frustum), exactly, with no cut. Let [x0, x1], [y0, y1], [d0, d1] be the box's frame
    /// coordinates. Its part's depth starts at the least depth d at which each range meets
    /// `[-tangent d, tangent d]`: the larger of d0, `near` and each range's distance from 0
    /// over the tangent. It ends at the lesser of d1 and `far`. Where x1 > 0, x / d is
    /// greatest at the part's least depth (there x is x1 or the frustum's side, `tangent d`),
    /// else at its greatest depth; likewise for the least x and for y.
    #[inline]
    pub fn box_extents(&self, aabb: &Aabb) -> Extents {
        // Plain comparisons rather than f64::max and min (no NaN reaches here): this runs for
        // every box and node a cube face's walks meet.
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let (lo, hi) = (
            (aabb.min() - self.position).to_array(),
            (aabb.max() - self.position).to_array(),
        );
        let range = |axis| axis_range(&lo, &hi, axis);
        let (d0, d1) = range(self.axes[2]);
        let (near, far) = (max(d0, self.near), min(d1, self.far));
        if near > far {
            return Extents::EMPTY;
        }
        let ((x0, x1), (y0, y1)) = (range(self.axes[0]), range(self.axes[1]));
        let t = self.tangent;
        let gap = |lo: f64, hi: f64| max(max(lo, -hi), 0.0);
        let near = max(near, max(gap(x0, x1), gap(y0, y1)) * self.inv_tangent);
        if near > far {
            return Extents::EMPTY;
        }
        // Two divisions rather than four (a division takes several times a product's time).
        let (inv_near, inv_far) = (1.0 / near, 1.0 / far);
        let span = |lo: f64, hi: f64| {
            let least = if lo < 0.0 {
                max(lo * inv_near, -t)
            } else {
                lo * inv_far
            };
            let most = if hi > 0.0 {
                min(hi * inv_near, t)
            } else {
                hi * inv_far
            };
            (least, most)
        };
        let ((xl, xm), (yl, ym)) = (span(x0, x1), span(y0, y1));
        Extents {
            min: DVec3::new(xl, yl, near),
            max: DVec3::new(xm, ym, far),
        }
    }

    /// Whether `aabb` meets the frustum's tip, the pyramid from the light to the near plane:
    /// at some depth d in `[0, near]` both its x and y ranges meet `[-tangent d, tangent d]`.
    pub fn meets_tip(&self, aabb: &Aabb) -> bool {
        self.ranges_meet_tip(axis_ranges(&self.axes, self.position, aabb))
    }

    /// [`Self::meets_tip`] of a box's frame coordinate ranges.
    fn ranges_meet_tip(&self, ((x0, x1), (y0, y1), (d0, d1)): FrameRanges) -> bool {
        let t = self.tangent;
        let gap = |lo: f64, hi: f64| lo.max(-hi).max(0.0);
        d0.max(0.0).max(gap(x0, x1) / t).max(gap(y0, y1) / t) <= d1.min(self.near)
    }

    /// The tangent of the frustum's half-angle: its sides are `|x|, |y| <= tangent`.
    pub fn tangent(&self) -> f64 {
        self.tangent
    }

    /// Whether part of `aabb`'s surface lies in the frustum's tip, which the near plane clips
    /// from the map: the box meets the tip ([`Self::meets_tip`]) and does not hold the whole
    /// tip (the light and the near plane's corners) inside.
    pub fn clips_tip(&self, aabb: &Aabb) -> bool {
        let ranges = axis_ranges(&self.axes, self.position, aabb);
        let ((x0, x1), (y0, y1), (d0, d1)) = ranges;
        let r = self.tangent * self.near;
        let holds = x0 < -r && x1 > r && y0 < -r && y1 > r && d0 < 0.0 && d1 > self.near;
        !holds && self.ranges_meet_tip(ranges)
    }
}

/// An axis-aligned box in a projector's (x, y, depth) space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Extents {
    pub min: DVec3,
    pub max: DVec3,
}

impl Extents {
    pub const EMPTY: Extents = Extents {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// Everything: the image of a box a map cannot bound (part of it behind the map's centre).
    pub const ALL: Extents = Extents {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };

    #[inline]
    pub fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    #[inline]
    pub fn union(&self, o: &Extents) -> Extents {
        Extents {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The box cut to the square `|x|, |y| <= t` (a spot light's, in its own projector's
    /// tangent units); empty (and [`Extents::is_empty`]) where it misses the square.
    #[inline]
    pub fn within_square(&self, t: f64) -> Extents {
        Extents {
            min: self.min.max(DVec3::new(-t, -t, f64::NEG_INFINITY)),
            max: self.max.min(DVec3::new(t, t, f64::INFINITY)),
        }
    }

    /// Area of the xy rectangle (0 when empty).
    pub fn xy_area(&self) -> f64 {
        let s = (self.max - self.min).truncate().max(DVec2::ZERO);
        s.x * s.y
    }

    /// The same box with its greatest depth `z`.
    #[inline]
    pub fn with_max_z(&self, z: f64) -> Extents {
        Extents {
            min: self.min,
            max: self.max.with_z(z),
        }
    }

    /// Whether `o` lies inside (touching counts).
    #[inline]
    pub fn contains(&self, o: &Extents) -> bool {
        self.min.cmple(o.min).all() && o.max.cmple(self.max).all()
    }

    /// The part of this box inside `o` (empty when they do not meet).
    #[inline]
    pub fn clamped_to(&self, o: &Extents) -> Extents {
        Extents {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        }
    }

    /// Whether the xy rectangles overlap (touching counts), `slack` added around `self`.
    #[inline]
    pub fn xy_overlaps(&self, o: &Extents, slack: f64) -> bool {
        self.min.x - slack <= o.max.x
            && o.min.x <= self.max.x + slack
            && self.min.y - slack <= o.max.y
            && o.min.y <= self.max.y + slack
    }
}

/// Grows `[lo, hi]` by a millionth of its width plus `absolute` on each side, so that points
/// on the boundary stay inside after rounding and an interval of zero width gets a size.
pub(crate) fn pad(lo: f64, hi: f64, absolute: f64) -> (f64, f64) {
    let m = 1e-6 * (hi - lo) + absolute;
    (lo - m, hi + m)
}

/// Builds a shadow map from a projector and the region to cover: `xy` the rectangle in the
/// projector's (x, y), `depth` the interval along the light. The region is padded slightly
/// (see [`pad`]), mapped to the inset square, and depth [near, far] to [0, 1].
/// The clip-space z of a map seen from a point (a spot light's, a cube face's) runs from 0 at
/// its near plane toward this, never to 1. Their near planes lie at a millionth of the range
/// ([`crate::SPOT_NEAR_FRACTION`]). So the usual perspective z, 1 - near / d up to a scale,
/// puts every point farther than a few near distances within a few f32 roundings of 1. There
/// a rasteriser, which works in f32, clips some of them as beyond the far plane, and a cube
/// face can lose its casters. Running to 1/2, the far side keeps its distance from the clip
/// volume's boundary. The depth compared is linear along the light
/// ([`crate::ShadowMap::depth_from_world`]), so nothing else reads this z.
pub(crate) const PERSPECTIVE_CLIP_Z: f64 = 0.5;

pub(crate) fn build_map(
    projector: &Projector,
    region: &Extents,
    settings: MapSettings,
    xy_padding: f64,
    depth_padding: f64,
) -> ShadowMap {
    let (x0, x1) = pad(region.min.x, region.max.x, xy_padding);
    let (y0, y1) = pad(region.min.y, region.max.y, xy_padding);
    let (mut z0, z1) = pad(region.min.z, region.max.z, depth_padding);
    let s = settings.inset_ndc();
    let (ax, bx) = (2.0 * s / (x1 - x0), -s * (x1 + x0) / (x1 - x0));
    let (ay, by) = (2.0 * s / (y1 - y0), -s * (y1 + y0) / (y1 - y0));
    let f = projector.frame();
    // Rows of clip_from_world, the linear depth row, and the projection kind.
    let (rows, depth_from_world, projection) = match projector {
        Projector::Parallel(_) => {
            let dz = z1 - z0;
            let depth = (f.forward / dz).extend(-z0 / dz);
            let rows = [
                (ax * f.right).extend(bx),
                (ay * f.up).extend(by),
                depth,
                DVec4::W,
            ];
            (rows, depth, MapProjection::Orthographic)
        }
        Projector::Point { position, .. } => {
            // The near plane must stay in front of the light.
            if z0 <= 0.0 {
                z0 = 0.5 * region.min.z;
            }
            let dz = z1 - z0;
            // With X, Y, d the frame coordinates of p - position:
            // clip = (ax X + bx d, ay Y + by d, (d - z0) / 2, d). The clip z runs from 0 at
            // the near plane toward 1/2 (see `PERSPECTIVE_CLIP_Z`).
            let row = |v: DVec3, c: f64| v.extend(c - v.dot(*position));
            let rows = [
                row(ax * f.right + bx * f.forward, 0.0),
                row(ay * f.up + by * f.forward, 0.0),
                row(f.forward * PERSPECTIVE_CLIP_Z, -PERSPECTIVE_CLIP_Z * z0),
                row(f.forward, 0.0),
            ];
            (
                rows,
                row(f.forward / dz, -z0 / dz),
                MapProjection::Perspective,
            )
        }
    };
    ShadowMap {
        clip_from_world: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
        depth_from_world,
        resolution: settings.resolution,
        viewport_inset: settings.viewport_inset,
        projection,
        view_depth_range: None,
    }
}

/// The projector a uniform map uses for `light`: the light frame fixed by its direction.
pub(crate) fn fixed_projector(light: &Light) -> Projector {
    match light {
        Light::Directional(l) => Projector::Parallel(LightFrame::fixed(l.direction())),
        Light::Spot(s) => Projector::Point {
            frame: LightFrame::fixed(s.direction()),
            position: s.position(),
        },
        Light::Point(p) => Projector::Point {
            frame: LightFrame::fixed(DVec3::NEG_Y),
            position: p.position(),
        },
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

        /// The centre-plus-signed-half-extents corners give the same extents as projecting
        /// the eight corners one by one, and none where a corner lies behind the map's centre.
        #[test]
        fn plane_map_box_extents_match_the_corners(
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..5.0),
            position in prop::array::uniform3(-5.0f64..5.0),
        ) {
            let projector = Projector::Point {
                frame: LightFrame::fixed(DVec3::new(0.2, -1.0, 0.3).normalize()),
                position: DVec3::from_array(position) + DVec3::new(0.0, 40.0, 0.0),
            };
            let source_from_world = DMat4::from_cols_array(&[
                1.0, 0.1, 0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 0.1, 0.0, 1.0, 0.01, 0.0, 0.0, 0.0, 1.0,
            ]);
            let map = PlaneMap::new(&projector, source_from_world);
            let lo = DVec3::from_array(lo);
            let aabb = Aabb::new(lo, lo + DVec3::from_array(size) + 1e-3).unwrap();
            let fast = map.box_extents_ahead(&aabb).expect("every box lies below the light");
            // A box above the light has corners behind the map's centre: no bounded image.
            let above = Aabb::new(lo + 80.0 * DVec3::Y, lo + 80.0 * DVec3::Y + 1.0).unwrap();
            prop_assert!(map.box_extents_ahead(&above).is_none());
            let mut slow = Extents::EMPTY;
            for c in aabb.corners() {
                let h = source_from_world * c.extend(1.0);
                slow.add(projector.project(h.truncate() / h.w).truncate().extend(0.0));
            }
            prop_assert!((fast.min - slow.min).abs().max_element() < 1e-9, "{fast:?} vs {slow:?}");
            prop_assert!((fast.max - slow.max).abs().max_element() < 1e-9, "{fast:?} vs {slow:?}");
        }

        /// A region's rows find the boxes whose corners' images (x and y under the map, z
        /// along a depth row) lie wholly beside it or behind its far side, with none where a
        /// corner lies behind the map's centre; regions are drawn around the box's image so
        /// that it lies inside, across a side or beyond it, and only images within rounding
        /// of a side are left out.
        #[test]
        fn region_rows_find_the_boxes_outside_as_their_corners_do(
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..5.0),
            up in 0.0f64..60.0,
            shift in prop::array::uniform3(-1.5f64..1.5),
            grow in 0.05f64..1.0,
        ) {
            let map = PlaneMap::new(
                &Projector::Point {
                    frame: LightFrame::fixed(DVec3::new(0.2, -1.0, 0.3).normalize()),
                    position: DVec3::new(0.0, 40.0, 0.0),
                },
                DMat4::from_cols_array(&[
                    1.0, 0.1, 0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 0.1, 0.0, 1.0, 0.01, 0.0, 0.0, 0.0, 1.0,
                ]),
            );
            let depth_row = DVec4::new(0.2, -1.0, 0.3, 5.0);
            let lo = DVec3::from_array(lo) + up * DVec3::Y;
            let aabb = Aabb::new(lo, lo + DVec3::from_array(size) + 1e-3).unwrap();
            let (c, h) = (aabb.center(), aabb.half_extents());
            let (z, dz) = (depth_row.dot(c.extend(1.0)), depth_row.truncate().abs().dot(h));
            // A region of the image's size, moved by `shift` of it and scaled by `grow`.
            let image = map.box_extents_ahead(&aabb).map(|e| Extents {
                min: e.min.with_z(z - dz),
                max: e.max.with_z(z + dz),
            });
            let reference = image.unwrap_or(Extents { min: DVec3::splat(-1.0), max: DVec3::ONE });
            let span = reference.max - reference.min;
            let middle = (reference.min + reference.max) / 2.0 + DVec3::from_array(shift) * span;
            let region = Extents { min: middle - span * grow, max: middle + span * grow };
            let rows = RegionRows::new(&map, depth_row, &region).expect("finite");
            let got = rows.box_outside(c, h);
            let Some(image) = image else {
                prop_assert_eq!(got, None);
                return Ok(());
            };
            let gaps = [
                image.max.x - region.min.x,
                region.max.x - image.min.x,
                image.max.y - region.min.y,
                region.max.y - image.min.y,
                region.max.z - image.min.z,
            ];
            let scale = image.min.abs().max(image.max.abs()).max(region.max.abs()).max_element();
            prop_assume!(gaps.iter().all(|g| g.abs() > 1e-9 * (scale + 1.0)));
            prop_assert_eq!(got, Some(gaps.iter().any(|g| *g < 0.0)));
        }

        /// Under a cube face's frame (world axes) a box's extents are its corners' images,
        /// to the bit; under any other frame the corners are projected one by one.
        #[test]
        fn cube_face_box_extents_are_the_corners_images(
            face in 0usize..6,
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..5.0),
            along in 0.01f64..20.0,
            beside in prop::array::uniform3(-20.0f64..20.0),
        ) {
            let face = crate::light::CubeFace::ALL[face];
            let frame = LightFrame::fixed(face.axis());
            let lo = DVec3::from_array(lo);
            let aabb = Aabb::new(lo, lo + DVec3::from_array(size)).unwrap();
            // The light behind the box's nearest point along the face's axis, anywhere
            // beside it.
            let axis = face.axis();
            let nearest = if axis.max_element() > 0.0 { aabb.min() } else { aabb.max() };
            let beside = DVec3::from_array(beside);
            let position = nearest - axis * along + beside - axis * axis.dot(beside);
            let fast = axis_box_extents(&frame, position, &aabb);
            let projector = Projector::Point { frame, position };
            let mut slow = Extents::EMPTY;
            for c in aabb.corners() {
                slow.add(projector.project(c));
            }
            prop_assert_eq!(fast, Some(slow));
            prop_assert_eq!(projector.box_extents(&aabb), slow);
            let tilted = LightFrame::fixed((axis + DVec3::splat(1e-3)).normalize());
            prop_assert_eq!(axis_box_extents(&tilted, position, &aabb), None);
        }
    }
}
