//! What the camera's pixels see of the lit receivers: a fact of the frame, computed once and
//! shared by every technique (and every cascade) that measures a map against another.
//!
//! Rays through a grid of pixels (about [`ViewSamples::RAYS`], spread over the image with its
//! aspect) are cast against the receiver boxes; the nearest hit inside the view frustum, on a
//! face that the light reaches (N.L > 0.1, as the renderer's metrics count; for a spot light
//! inside its cone and range), is a sample: the point, the face's normal and the world
//! footprint of one pixel there. The rays are binned per box by the box's image, so a box
//! costs its eight corners and the rays that can hit it.
//!
//! A map's undersampling at a sample is what the renderer measures per pixel: pixels per
//! texel along the worst direction, `1 / sigma_min` of the Jacobian from pixels to texels.
//! Only ratios between maps of one frame mean anything: the footprint is that of a pixel of
//! an image [`ViewSamples::REFERENCE_ROWS`] rows tall.
//!
//! Boxes stand for the receivers' shapes: a sphere's box is hit where the sphere is not, with
//! the normal of a face (the top of a torus's box, lit at grazing incidence, can rule the
//! statistics of every map), and casters that do not receive do not hide what lies behind
//! them. A renderer knows the real surfaces: [`ViewSamples::from_surface_points`] builds the
//! samples from what its pixels see (gnomon's renderer draws them in a small pass; an engine
//! can take them from its last frame's depth and normals, as sample distribution shadow maps
//! do), and a setup given them ([`crate::SetupInput::samples`]) uses them.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec3, DVec4};

use crate::bounds::SceneBounds;
use crate::camera::Camera;
use crate::light::Light;
use crate::map::{ShadowMap, ShadowSetup};

/// A visible, lit receiver point as one pixel sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewSample {
    /// The point, world space.
    pub position: DVec3,
    /// The unit normal of the box face it lies on, toward the camera.
    pub normal: DVec3,
    /// The world step across the surface for one pixel to the right.
    pub dp_dx: DVec3,
    /// The world step across the surface for one pixel up.
    pub dp_dy: DVec3,
    /// The distance along the view direction.
    pub view_depth: f64,
}

/// The samples of one frame; see the module documentation.
#[derive(Debug, Clone, Default)]
pub struct ViewSamples {
    samples: Vec<ViewSample>,
    /// What the undersampling measure reads of each sample, a column per coordinate, so that
    /// the measure's loop runs over several samples at once ([`Texels::least_squared_scales`]).
    columns: Columns,
}

impl PartialEq for ViewSamples {
    /// The same samples (the columns are made from them).
    fn eq(&self, other: &Self) -> bool {
        self.samples == other.samples
    }
}

/// The samples' positions and pixel footprints, one column per coordinate.
#[derive(Debug, Clone, Default)]
struct Columns {
    position: [Vec<f64>; 3],
    dp_dx: [Vec<f64>; 3],
    dp_dy: [Vec<f64>; 3],
}

impl Columns {
    fn new(samples: &[ViewSample]) -> Self {
        // A pass per column, each through its own closure (inlined: a shared `dyn` closure
        // cost a call per value).
        fn column(samples: &[ViewSample], f: impl Fn(&ViewSample) -> f64) -> Vec<f64> {
            samples.iter().map(f).collect()
        }
        Self {
            position: [
                column(samples, |s| s.position.x),
                column(samples, |s| s.position.y),
                column(samples, |s| s.position.z),
            ],
            dp_dx: [
                column(samples, |s| s.dp_dx.x),
                column(samples, |s| s.dp_dx.y),
                column(samples, |s| s.dp_dx.z),
            ],
            dp_dy: [
                column(samples, |s| s.dp_dy.x),
                column(samples, |s| s.dp_dy.y),
                column(samples, |s| s.dp_dy.z),
            ],
        }
    }
}

impl ViewSamples {
    /// About how many rays are cast.
    pub const RAYS: usize = 384;
    /// The footprints are those of a pixel of an image this many rows tall.
    pub const REFERENCE_ROWS: f64 = 1000.0;
    /// Below this many lit points (N.L > 0.1) the samples take every point the light reaches
    /// (see [`ViewSamples::from_surface_points`]).
    pub const MIN_LIT: usize = 16;

    /// The grid of rays for an image of `aspect` (width over height): (columns, rows), about
    /// [`ViewSamples::RAYS`] cells.
    pub fn grid(aspect: f64) -> (u32, u32) {
        let rows = ((Self::RAYS as f64 / aspect).sqrt().round() as u32).clamp(4, 64);
        let cols = ((rows as f64 * aspect).round() as u32).clamp(4, 64);
        (cols, rows)
    }

    /// The samples of `camera`'s view of `scene`'s receiver boxes lit by `light`: rays through
    /// the cells of [`ViewSamples::grid`] against the boxes (see the module documentation).
    pub fn new(camera: &Camera, light: &Light, scene: &SceneBounds) -> Self {
        let lens = camera.lens();
        let (cols, rows) = Self::grid(lens.aspect);
        let (cols, rows) = (cols as usize, rows as usize);
        let tan_y = (0.5 * lens.fov_y_degrees.to_radians()).tan();
        let tan_x = tan_y * lens.aspect;
        let (eye, forward, right, up) =
            (camera.eye(), camera.forward(), camera.right(), camera.up());
        // The ray through cell (i, j): eye + t d, with t the view depth (forward . d = 1), and
        // the reciprocals of its components for the slab tests.
        let ndc = |i: usize, n: usize| (2.0 * i as f64 + 1.0) / n as f64 - 1.0;
        let rays: Vec<(DVec3, DVec3)> = (0..rows * cols)
            .map(|k| {
                let (i, j) = (k % cols, k / cols);
                let d = forward + right * (ndc(i, cols) * tan_x) + up * (ndc(j, rows) * tan_y);
                (d, d.recip())
            })
            .collect();
        let grid = Grid::new(camera, (tan_x, tan_y), (cols, rows));
        let arrays = scene.receiver_arrays();
        // Front to back through the receivers' hierarchy (a heap on the nearest view depth
        // z0 of each node's box). A hit at depth t hides every box whose nearest depth is
        // beyond t. So a node whose cells all hold a nearer hit is not opened, and a cell is
        // tested only against the boxes that can still be nearer than its hit.
        let tree = scene.receiver_tree();
        let mut nearest = vec![(f64::INFINITY, usize::MAX); rows * cols];
        let mut heap = BinaryHeap::new();
        let push = |heap: &mut BinaryHeap<Near>, node: usize| {
            if let Some((cells, z0)) =
                grid.cells_covered(tree.nodes.center_of(node), tree.nodes.half_of(node))
            {
                heap.push(Near { z0, node, cells });
            }
        };
        if !tree.is_empty() {
            push(&mut heap, 0);
        }
        while let Some(Near { z0, node, cells }) = heap.pop() {
            let (i0, i1, j0, j1) = cells;
            let hidden = (j0..=j1).all(|j| (i0..=i1).all(|i| nearest[j * cols + i].0 <= z0));
            if hidden {
                continue;
            }
            if !tree.is_leaf(node) {
                for child in tree.children(node) {
                    push(&mut heap, child);
                }
                continue;
            }
            for &b in tree.boxes_of(node) {
                let b = b as usize;
                let Some(((i0, i1, j0, j1), z0)) =
                    grid.cells_covered(arrays.center_of(b), arrays.half_of(b))
                else {
                    continue;
                };
                let aabb = &scene.receivers()[b];
                let (lo, hi) = (aabb.min() - eye, aabb.max() - eye);
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let k = j * cols + i;
                        if z0 >= nearest[k].0 {
                            continue;
                        }
                        if let Some((t, axis)) = ray_box(rays[k].1, lo, hi)
                            && t >= lens.near
                            && t <= lens.far
                            && t < nearest[k].0
                        {
                            nearest[k] = (t, axis);
                        }
                    }
                }
            }
        }
        let mut hits = Vec::with_capacity(rows * cols);
        for (&(t, axis), &(d, _)) in nearest.iter().zip(&rays) {
            if axis != usize::MAX {
                let mut normal = DVec3::ZERO;
                normal[axis] = -d[axis].signum();
                hits.push((eye + d * t, normal));
            }
        }
        Self::from_surface_points(camera, light, hits)
    }

    /// The samples from surface points that pixels see: (position, unit normal), world space,
    /// one per pixel of an image of `camera`'s aspect, about [`ViewSamples::RAYS`] of them
    /// (fewer or more only weight the statistics differently). Points the light does not reach
    /// (N.L > 0.1), or outside the view's depth range, are left out; normals are turned
    /// toward the camera. Where fewer than [`ViewSamples::MIN_LIT`] points pass, under a
    /// grazing light, every point the light reaches at all (N.L > 0) is a sample, so that the
    /// frame still judges the maps: with a handful of samples, a far coarser warp can pass.
    pub fn from_surface_points(
        camera: &Camera,
        light: &Light,
        points: impl IntoIterator<Item = (DVec3, DVec3)>,
    ) -> Self {
        let points: Vec<(DVec3, DVec3)> = points.into_iter().collect();
        let lit = Self::facing(camera, light, &points, LIT_N_DOT_L);
        if lit.len() >= Self::MIN_LIT {
            return lit;
        }
        let reached = Self::facing(camera, light, &points, 0.0);
        if reached.len() > lit.len() {
            reached
        } else {
            lit
        }
    }

    /// [`ViewSamples::from_surface_points`] with N.L above `min_n_dot_l`.
    fn facing(camera: &Camera, light: &Light, points: &[(DVec3, DVec3)], min_n_dot_l: f64) -> Self {
        let lens = camera.lens();
        let (eye, forward) = (camera.eye(), camera.forward());
        let pixel = 2.0 * (0.5 * lens.fov_y_degrees.to_radians()).tan() / Self::REFERENCE_ROWS;
        let (step_x, step_y) = (camera.right() * pixel, camera.up() * pixel);
        let mut samples = Vec::with_capacity(points.len());
        for &(p, normal) in points {
            let t = (p - eye).dot(forward);
            if !(t >= lens.near && t <= lens.far && normal.is_finite()) {
                continue;
            }
            // The ray through the point with forward . d = 1, so that p = eye + t d.
            let d = (p - eye) / t;
            let normal = if normal.dot(d) > 0.0 { -normal } else { normal };
            let n_dot_d = normal.dot(d);
            if !lit_facing(light, p, normal, min_n_dot_l) || n_dot_d >= 0.0 {
                continue;
            }
            // p(d) = e + d (n . (p0 - e)) / (n . d): dp = t (dd - d (n . dd) / (n . d)).
            let footprint = |dd: DVec3| t * (dd - d * (normal.dot(dd) / n_dot_d));
            samples.push(ViewSample {
                position: p,
                normal,
                dp_dx: footprint(step_x),
                dp_dy: footprint(step_y),
                view_depth: t,
            });
        }
        Self::from_vec(samples)
    }

    fn from_vec(samples: Vec<ViewSample>) -> Self {
        let columns = Columns::new(&samples);
        Self { samples, columns }
    }

    /// The samples.
    pub fn samples(&self) -> &[ViewSample] {
        &self.samples
    }

    /// How many samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Whether no pixel sees a lit receiver.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The samples that `keep` accepts.
    pub(crate) fn filtered(&self, keep: impl Fn(&ViewSample) -> bool) -> ViewSamples {
        Self::from_vec(self.samples.iter().filter(|s| keep(s)).copied().collect())
    }

    /// The samples whose view depth lies in [near, far] (a cascade's slice).
    pub fn within_depth(&self, near: f64, far: f64) -> ViewSamples {
        self.filtered(|s| (near..=far).contains(&s.view_depth))
    }

    /// The `q` quantile (0 to 1, nearest rank) of a setup's undersampling over the samples,
    /// each sample measured on the map it reads ([`crate::MapSelection::map_for`]; a sample
    /// no map covers is left out); `None` when no sample is measured.
    pub fn setup_undersampling_quantile(&self, setup: &ShadowSetup, q: f64) -> Option<f64> {
        // Each sample to the map it reads, in one pass (in the samples' order per map).
        let mut reads = vec![Vec::new(); setup.maps.len()];
        for s in &self.samples {
            if let Some(k) = setup.selection.map_for(&setup.maps, s.position) {
                reads[k].push(*s);
            }
        }
        let mut values = Vec::with_capacity(self.len());
        for (map, reads) in setup.maps.iter().zip(reads) {
            let reads = Self::from_vec(reads);
            values.extend(Texels::new(map).least_squared_scales(&reads.columns));
        }
        if values.is_empty() {
            return None;
        }
        // Selected on sigma_min^2, as in `undersampling_quantiles`.
        let rank = scale_rank(q, values.len() - 1);
        let (_, value, _) = values.select_nth_unstable_by(rank, f64::total_cmp);
        Some(undersampling_of(*value))
    }

    /// The `q` quantile (0 to 1, nearest rank) of `map`'s undersampling over the samples;
    /// `None` when there are none.
    pub fn undersampling_quantile(&self, map: &ShadowMap, q: f64) -> Option<f64> {
        self.undersampling_quantiles(map, [q]).map(|[v]| v)
    }

    /// Several quantiles of `map`'s undersampling at once (each sample measured once).
    pub fn undersampling_quantiles<const N: usize>(
        &self,
        map: &ShadowMap,
        qs: [f64; N],
    ) -> Option<[f64; N]> {
        let texels = Texels::new(map);
        // Selected on sigma_min^2, which falls as the undersampling grows: the
        // undersampling's rank r (ascending) is sigma_min^2's rank last - r, and only the
        // N values found pay for a square root and a division.
        let mut values = texels.least_squared_scales(&self.columns);
        if values.is_empty() {
            return None;
        }
        let last = values.len() - 1;
        // Nearest-rank quantiles by selection, largest rank first: each selection leaves the
        // values below its rank in front, where the next one selects.
        let ranks = qs.map(|q| scale_rank(q, last));
        let mut order: [usize; N] = std::array::from_fn(|i| i);
        order.sort_unstable_by(|a, b| ranks[*b].cmp(&ranks[*a]));
        let mut out = [0.0; N];
        let mut end = values.len();
        for &i in &order {
            let rank = ranks[i];
            let (_, value, _) = values[..end].select_nth_unstable_by(rank, f64::total_cmp);
            out[i] = undersampling_of(*value);
            end = rank + 1;
        }
        Some(out)
    }
}

/// A node of the receivers' hierarchy that the view may see: its cells and nearest view
/// depth, ordered nearest first in a max-heap.
struct Near {
    z0: f64,
    node: usize,
    cells: (usize, usize, usize, usize),
}

impl PartialEq for Near {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Near {}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Near {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .z0
            .total_cmp(&self.z0)
            .then(other.node.cmp(&self.node))
    }
}

/// A map's rows as the undersampling measure reads them, taken out of its matrix once.
struct Texels {
    x: DVec4,
    y: DVec4,
    w: DVec4,
    scale: f64,
}

impl Texels {
    fn new(map: &ShadowMap) -> Self {
        let m = map.clip_from_world;
        Self {
            x: m.row(0),
            y: m.row(1),
            w: m.row(3),
            scale: 0.5 * map.resolution as f64,
        }
    }

    /// See [`undersampling`].
    #[inline]
    fn undersampling(&self, sample: &ViewSample) -> f64 {
        undersampling_of(self.least_squared_scale(sample))
    }

    /// The least eigenvalue of J^T J (J: the Jacobian from pixels to texels at `sample`),
    /// the square of J's least singular value sigma_min; 0 where the map does not see the
    /// point (w <= 0) or the value is not a number. The undersampling, 1 / sigma_min, falls
    /// as it grows ([`undersampling_of`]), so quantiles can be selected on it and take their
    /// square root and reciprocal once.
    #[inline]
    fn least_squared_scale(&self, sample: &ViewSample) -> f64 {
        self.least_squared_scale_at(
            sample.position.to_array(),
            sample.dp_dx.to_array(),
            sample.dp_dy.to_array(),
        )
    }

    /// [`Self::least_squared_scale`] of every sample, from the columns, in a loop that the
    /// compiler runs on several samples at once.
    fn least_squared_scales(&self, columns: &Columns) -> Vec<f64> {
        let n = columns.position[0].len();
        let [px, py, pz] = columns.position.each_ref().map(|c| &c[..n]);
        let [dxx, dxy, dxz] = columns.dp_dx.each_ref().map(|c| &c[..n]);
        let [dyx, dyy, dyz] = columns.dp_dy.each_ref().map(|c| &c[..n]);
        let mut out = vec![0.0; n];
        for (i, out) in out.iter_mut().enumerate() {
            *out = self.least_squared_scale_at(
                [px[i], py[i], pz[i]],
                [dxx[i], dxy[i], dxz[i]],
                [dyx[i], dyy[i], dyz[i]],
            );
        }
        out
    }

    /// [`Self::least_squared_scale`] at a point with its pixel footprints, written without
    /// branches (so that [`Self::least_squared_scales`] vectorises).
    #[inline(always)]
    fn least_squared_scale_at(&self, p: [f64; 3], dp_dx: [f64; 3], dp_dy: [f64; 3]) -> f64 {
        let (rx, ry, rw) = (self.x, self.y, self.w);
        // The rows times (p, 1).
        let row = |r: DVec4| r.x * p[0] + r.y * p[1] + r.z * p[2] + r.w;
        let (cx, cy, cw) = (row(rx), row(ry), row(rw));
        let inv_w = 1.0 / cw;
        let (x, y) = (cx * inv_w, cy * inv_w);
        // The gradients of the map's x and y over world space, dotted with a footprint.
        let gradient = |r: DVec4, t: f64| {
            [
                (r.x - rw.x * t) * inv_w,
                (r.y - rw.y * t) * inv_w,
                (r.z - rw.z * t) * inv_w,
            ]
        };
        let (gx, gy) = (gradient(rx, x), gradient(ry, y));
        let dot = |g: [f64; 3], d: [f64; 3]| g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
        let scale = self.scale;
        let (jx0, jx1) = (scale * dot(gx, dp_dx), scale * dot(gy, dp_dx));
        let (jy0, jy1) = (scale * dot(gx, dp_dy), scale * dot(gy, dp_dy));
        // J^T J = [[a, b], [b, c]]: its eigenvalues are the squared singular values.
        let a = jx0 * jx0 + jx1 * jx1;
        let b = jx0 * jy0 + jx1 * jy1;
        let c = jy0 * jy0 + jy1 * jy1;
        let root = (0.25 * (a - c) * (a - c) + b * b).max(0.0).sqrt();
        // f64::max takes the number where one side is NaN: a NaN comes out as 0.
        let value = (0.5 * (a + c) - root).max(0.0);
        // Where the map does not see the point (w <= 0, or not a number): 0.
        if cw > 0.0 { value } else { 0.0 }
    }
}

/// The rank, among least squared scales sorted ascending (`last` the highest rank), of the
/// undersampling's nearest-rank `q` quantile: the undersampling falls as the scale grows.
fn scale_rank(q: f64, last: usize) -> usize {
    last - ((q.clamp(0.0, 1.0) * last as f64).round() as usize).min(last)
}

/// The undersampling 1 / sigma_min from sigma_min^2 ([`Texels::least_squared_scale`]);
/// infinite where it is 0.
#[inline]
fn undersampling_of(least_squared_scale: f64) -> f64 {
    let sigma_min = least_squared_scale.sqrt();
    if sigma_min > 0.0 {
        1.0 / sigma_min
    } else {
        f64::INFINITY
    }
}

/// Pixels per texel along the worst direction at `sample` in `map` (`1 / sigma_min` of the
/// Jacobian from pixels to texels, as the renderer measures it); infinite where the map does
/// not see the point (w <= 0) or does not resolve it.
pub fn undersampling(map: &ShadowMap, sample: &ViewSample) -> f64 {
    Texels::new(map).undersampling(sample)
}

/// The N.L above which a surface counts as lit, as the renderer's metrics count.
const LIT_N_DOT_L: f64 = 0.1;

/// Whether the light reaches a surface at `p` with normal `n` (N.L > `min_n_dot_l`; a spot
/// light also needs `p` inside its cone and range, a point light within its range).
fn lit_facing(light: &Light, p: DVec3, n: DVec3, min_n_dot_l: f64) -> bool {
    match light {
        Light::Point(l) => {
            let to_light = l.position() - p;
            let distance = to_light.length();
            distance >= l.near()
                && distance <= l.range()
                && n.dot(to_light / distance) > min_n_dot_l
        }
        Light::Directional(l) => n.dot(-l.direction()) > min_n_dot_l,
        Light::Spot(s) => {
            let to_light = s.position() - p;
            let distance = to_light.length();
            let along = -to_light.dot(s.direction());
            distance > 0.0
                && n.dot(to_light / distance) > min_n_dot_l
                && along >= s.near()
                && distance <= s.range()
                && along >= distance * s.half_angle().cos()
        }
    }
}

/// The camera's grid of rays, ready to bound the cells a box can be hit in.
struct Grid {
    eye: DVec3,
    /// The camera's axes, and their absolute values.
    axes: [DVec3; 3],
    abs_axes: [DVec3; 3],
    near: f64,
    far: f64,
    /// The view frustum's four side planes through the eye (outward normals, world space),
    /// and their absolute values.
    sides: [DVec3; 4],
    abs_sides: [DVec3; 4],
    /// 1 / tan of the half fields of view.
    inv_tan: (f64, f64),
    cols: usize,
    rows: usize,
}

impl Grid {
    fn new(camera: &Camera, (tan_x, tan_y): (f64, f64), (cols, rows): (usize, usize)) -> Self {
        let axes = [camera.right(), camera.up(), camera.forward()];
        let [r, u, f] = axes;
        let sides = [r - f * tan_x, -r - f * tan_x, u - f * tan_y, -u - f * tan_y];
        let lens = camera.lens();
        Self {
            eye: camera.eye(),
            axes,
            abs_axes: axes.map(DVec3::abs),
            near: lens.near,
            far: lens.far,
            sides,
            abs_sides: sides.map(DVec3::abs),
            inv_tan: (1.0 / tan_x, 1.0 / tan_y),
            cols,
            rows,
        }
    }

    /// The grid cells (i0, i1, j0, j1) whose rays can hit the box of `centre` and `half`
    /// extents (through the box around it in camera coordinates), or `None` when it lies
    /// wholly before the near plane, beyond the far plane or beside the view. A box reaching
    /// behind the eye covers every cell unless it lies beside a side plane.
    /// Also gives the box's nearest view depth.
    #[inline]
    fn cells_covered(
        &self,
        centre: DVec3,
        half: DVec3,
    ) -> Option<((usize, usize, usize, usize), f64)> {
        let c = centre - self.eye;
        let [r, u, f] = self.axes;
        let [ar, au, af] = self.abs_axes;
        // The box in camera coordinates (right, up, forward), bounded by a box there: its
        // centre and the half extents |R| h.
        let (cz, hz) = (f.dot(c), af.dot(half));
        let (z0, z1) = (cz - hz, cz + hz);
        if z1 < self.near || z0 > self.far {
            return None;
        }
        let (cols, rows) = (self.cols, self.rows);
        if z0 <= 0.5 * self.near {
            // It reaches behind the eye, where its image is unbounded; but a box wholly
            // beside one of the frustum's side planes meets no ray (a street's row of
            // buildings through the eye would otherwise be opened to its last leaf).
            let beside = (0..4).any(|k| self.sides[k].dot(c) - self.abs_sides[k].dot(half) > 0.0);
            return (!beside).then_some(((0, cols - 1, 0, rows - 1), z0));
        }
        let (r0, r1) = (1.0 / z0, 1.0 / z1);
        // x / z over the camera-space box: least at the nearest depth when x < 0, else at the
        // farthest (and the other way round for the largest); in units of the half field.
        let bounds = |lo: f64, hi: f64, inv_tan: f64| {
            let least = lo * if lo < 0.0 { r0 } else { r1 };
            let most = hi * if hi > 0.0 { r0 } else { r1 };
            (least * inv_tan, most * inv_tan)
        };
        let (cx, hx) = (r.dot(c), ar.dot(half));
        let (cy, hy) = (u.dot(c), au.dot(half));
        let (x0, x1) = bounds(cx - hx, cx + hx, self.inv_tan.0);
        let (y0, y1) = bounds(cy - hy, cy + hy, self.inv_tan.1);
        if x0 > 1.0 || x1 < -1.0 || y0 > 1.0 || y1 < -1.0 {
            return None;
        }
        // Cell i's centre is at (2 i + 1) / n - 1: the cells whose centres lie in [lo, hi].
        // The positions are clamped to [-1, n] first, so that truncation (toward zero, of
        // a value at least -1 shifted by one) is a floor.
        let range = |lo: f64, hi: f64, n: usize| {
            let last_cell = n as f64 - 1.0;
            let first = ((lo + 1.0) * 0.5 * n as f64 - 0.5).clamp(-1.0, n as f64);
            let last = ((hi + 1.0) * 0.5 * n as f64 - 0.5).clamp(-1.0, n as f64);
            let floor = |v: f64| (v + 1.0) as i64 - 1;
            let first_floor = floor(first);
            let first = first_floor + i64::from((first_floor as f64) < first);
            let first = first.max(0);
            let last = floor(last).min(last_cell as i64);
            (first <= last).then_some((first as usize, last as usize))
        };
        let (i0, i1) = range(x0, x1, cols)?;
        let (j0, j1) = range(y0, y1, rows)?;
        Some(((i0, i1, j0, j1), z0))
    }
}

/// Where the ray `t d` (t >= 0) from the origin enters the box [lo, hi] (relative to the
/// ray's origin), given `inv` = 1 / d per component, and the axis of the face it enters
/// through; `None` when it misses or starts inside. (A zero component gives infinite
/// reciprocals: the slab is all or nothing, and a NaN from 0 x infinity is ignored by min and
/// max.)
fn ray_box(inv: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, usize)> {
    let a = lo * inv;
    let b = hi * inv;
    let near = a.min(b);
    let far = a.max(b);
    let t_exit = far.x.min(far.y).min(far.z);
    let (t_enter, axis) = if near.x >= near.y && near.x >= near.z {
        (near.x, 0)
    } else if near.y >= near.z {
        (near.y, 1)
    } else {
        (near.z, 2)
    };
    (t_enter > 0.0 && t_enter <= t_exit).then_some((t_enter, axis))
}

#[cfg(test)]
mod tests {
    use glam::DMat4;

    use super::*;
    use crate::boxes::Aabb;
    use crate::camera::Lens;
    use crate::light::DirectionalLight;
    use crate::map::MapProjection;

    fn ground_scene() -> SceneBounds {
        let ground = Aabb::new(
            DVec3::new(-100.0, -1.0, -100.0),
            DVec3::new(100.0, 0.0, 100.0),
        );
        SceneBounds::new(vec![], vec![ground.unwrap()], None).unwrap()
    }

    #[test]
    fn a_camera_over_the_ground_sees_it_lit_from_above() {
        let camera = Camera::look_at(
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::new(0.0, 0.0, -20.0),
            DVec3::Y,
            Lens::default(),
        )
        .unwrap();
        let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.2, -1.0, 0.1)).unwrap());
        let samples = ViewSamples::new(&camera, &sun, &ground_scene());
        // The lower part of the image sees the ground, the upper part the sky.
        assert!(samples.len() > ViewSamples::RAYS / 4, "{}", samples.len());
        assert!(samples.len() < ViewSamples::RAYS, "{}", samples.len());
        for s in samples.samples() {
            assert!(s.position.y.abs() < 1e-9 && s.normal == DVec3::Y);
            assert!(
                (s.view_depth - (s.position - camera.eye()).dot(camera.forward())).abs() < 1e-9
            );
            // A pixel's footprint lies in the ground plane.
            assert!(s.dp_dx.y.abs() < 1e-12 && s.dp_dy.y.abs() < 1e-12);
        }
        // Lit from below: nothing.
        let under = Light::Directional(DirectionalLight::new(DVec3::Y).unwrap());
        assert!(ViewSamples::new(&camera, &under, &ground_scene()).is_empty());
        // A slice keeps what lies in it.
        let slice = samples.within_depth(10.0, 30.0);
        assert!(!slice.is_empty() && slice.len() < samples.len());
        assert!(
            slice
                .samples()
                .iter()
                .all(|s| (10.0..=30.0).contains(&s.view_depth))
        );
        // A sun 3 degrees over the horizon (N.L 0.05 on the ground): no pixel sees N.L > 0.1,
        // so every pixel that sees the ground lit at all is a sample; a sun 3 degrees under
        // the horizon still gives none.
        let grazing = |elevation: f64| {
            let e = elevation.to_radians();
            Light::Directional(DirectionalLight::new(DVec3::new(e.cos(), -e.sin(), 0.0)).unwrap())
        };
        let low = ViewSamples::new(&camera, &grazing(3.0), &ground_scene());
        assert_eq!(low.len(), samples.len());
        assert!(ViewSamples::new(&camera, &grazing(-3.0), &ground_scene()).is_empty());
    }

    /// The samples as every ray cast against every receiver box would give them.
    fn brute_force(camera: &Camera, light: &Light, scene: &SceneBounds) -> ViewSamples {
        let lens = camera.lens();
        let (cols, rows) = ViewSamples::grid(lens.aspect);
        let (cols, rows) = (cols as usize, rows as usize);
        let tan_y = (0.5 * lens.fov_y_degrees.to_radians()).tan();
        let tan_x = tan_y * lens.aspect;
        let ndc = |i: usize, n: usize| (2.0 * i as f64 + 1.0) / n as f64 - 1.0;
        let eye = camera.eye();
        let mut hits = Vec::new();
        for k in 0..rows * cols {
            let (i, j) = (k % cols, k / cols);
            let d = camera.forward()
                + camera.right() * (ndc(i, cols) * tan_x)
                + camera.up() * (ndc(j, rows) * tan_y);
            let mut nearest = (f64::INFINITY, usize::MAX);
            for b in scene.receivers() {
                if let Some((t, axis)) = ray_box(d.recip(), b.min() - eye, b.max() - eye)
                    && t >= lens.near
                    && t <= lens.far
                    && t < nearest.0
                {
                    nearest = (t, axis);
                }
            }
            let (t, axis) = nearest;
            if axis != usize::MAX {
                let mut normal = DVec3::ZERO;
                normal[axis] = -d[axis].signum();
                hits.push((eye + d * t, normal));
            }
        }
        ViewSamples::from_surface_points(camera, light, hits)
    }

    #[test]
    fn street_level_views_cast_every_ray_against_every_box_that_can_be_seen() {
        // A town of 400 boxes on a 5 m grid; cameras at eye level in its streets, so that rows
        // of boxes pass through the eye's plane, beside the view or into it.
        let mut seed = 7u64;
        let mut random = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut receivers = Vec::new();
        for k in 0..400 {
            let (i, j) = ((k % 20) as f64 * 5.0 - 50.0, (k / 20) as f64 * 5.0 - 50.0);
            let h = 1.0 + 20.0 * random();
            receivers
                .push(Aabb::new(DVec3::new(i, 0.0, j), DVec3::new(i + 3.0, h, j + 3.0)).unwrap());
        }
        receivers
            .push(Aabb::new(DVec3::new(-60.0, -1.0, -60.0), DVec3::new(60.0, 0.0, 60.0)).unwrap());
        let scene = SceneBounds::new(vec![], receivers, None).unwrap();
        let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.2)).unwrap());
        let mut seen = 0;
        for _ in 0..300 {
            // In a street (x or z between two boxes) or anywhere, near the ground.
            let along = 5.0 * (random() * 20.0).floor() - 48.5;
            let across = 100.0 * random() - 50.0;
            let (x, z) = if random() < 0.5 {
                (along, across)
            } else {
                (across, along)
            };
            let eye = DVec3::new(x, 0.2 + 2.0 * random(), z);
            let yaw = std::f64::consts::TAU * random();
            let pitch = 0.6 * (random() - 0.5);
            let dir = DVec3::new(
                yaw.cos() * pitch.cos(),
                pitch.sin(),
                yaw.sin() * pitch.cos(),
            );
            let lens = Lens {
                near: 0.05 + random(),
                far: 20.0 + 150.0 * random(),
                fov_y_degrees: 20.0 + 100.0 * random(),
                aspect: 0.5 + 2.0 * random(),
            };
            let camera = Camera::look_at(eye, eye + dir, DVec3::Y, lens).unwrap();
            let samples = ViewSamples::new(&camera, &sun, &scene);
            assert_eq!(samples, brute_force(&camera, &sun, &scene), "{camera:?}");
            seen += samples.len();
        }
        assert!(seen > 300 * ViewSamples::RAYS / 4, "{seen}");
    }

    #[test]
    fn undersampling_of_a_map_looking_straight_down() {
        // A camera straight above the ground at height h, a map over [-50, 50]^2 of 1000
        // texels: a texel is 0.1 m; a pixel of the reference image at the centre is
        // h 2 tan(fov/2) / rows.
        let h = 20.0;
        let lens = Lens {
            fov_y_degrees: 60.0,
            aspect: 1.0,
            near: 1.0,
            far: 100.0,
        };
        let camera =
            Camera::look_at(DVec3::new(0.0, h, 0.0), DVec3::ZERO, DVec3::NEG_Z, lens).unwrap();
        let sun = Light::Directional(DirectionalLight::new(-DVec3::Y).unwrap());
        let samples = ViewSamples::new(&camera, &sun, &ground_scene());
        // x = X / 50, y = -Z / 50 (looking down with -Z up in the map).
        let clip_from_world = DMat4::from_cols_array(&[
            0.02, 0.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, //
            0.0, -0.02, 0.0, 0.0, //
            0.0, 0.0, 0.5, 1.0,
        ]);
        let map = ShadowMap {
            clip_from_world,
            depth_from_world: glam::DVec4::ZERO,
            resolution: 1000,
            viewport_inset: 1,
            projection: MapProjection::Orthographic,
            view_depth_range: None,
        };
        let centre = samples
            .samples()
            .iter()
            .min_by(|a, b| a.position.length().total_cmp(&b.position.length()))
            .unwrap();
        let pixel = h * 2.0 * (30.0f64).to_radians().tan() / ViewSamples::REFERENCE_ROWS;
        let expected = 0.1 / pixel;
        let got = undersampling(&map, centre);
        assert!((got / expected - 1.0).abs() < 0.05, "{got} vs {expected}");
        // Twice the texels: half the undersampling, everywhere.
        let finer = ShadowMap {
            resolution: 2000,
            ..map
        };
        let q = samples.undersampling_quantile(&map, 0.95).unwrap();
        let q_finer = samples.undersampling_quantile(&finer, 0.95).unwrap();
        assert!((q / q_finer - 2.0).abs() < 1e-9);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, failure_persistence: None, ..proptest::prelude::ProptestConfig::default() })]

        /// The quantiles selected on sigma_min^2 are the nearest-rank quantiles of the
        /// undersampling itself, sorted: maps with any rows, so that some samples lie behind
        /// them (w <= 0, infinite undersampling) and many tie there.
        #[test]
        fn quantiles_are_those_of_the_sorted_undersampling(
            rows in proptest::array::uniform16(-1.0f64..1.0),
            behind in proptest::bool::ANY,
            qs in proptest::array::uniform3(0.0f64..1.0),
            eye in proptest::array::uniform3(-50.0f64..50.0),
        ) {
            let eye = DVec3::from_array(eye).with_y(eye[1].abs() + 2.0);
            let camera = Camera::look_at(eye, DVec3::ZERO, DVec3::Y, Lens::default()).unwrap();
            let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.2, -1.0, 0.1)).unwrap());
            let samples = ViewSamples::new(&camera, &sun, &ground_scene());
            proptest::prop_assume!(!samples.is_empty());
            let mut m = DMat4::from_cols_array(&rows);
            if !behind {
                // w = 1 everywhere: an orthographic map, every sample finite.
                m = DMat4::from_cols(m.x_axis.with_w(0.0), m.y_axis.with_w(0.0), m.z_axis.with_w(0.0), m.w_axis.with_w(1.0));
            }
            let map = ShadowMap {
                clip_from_world: m,
                depth_from_world: glam::DVec4::ZERO,
                resolution: 1024,
                viewport_inset: 1,
                projection: MapProjection::Orthographic,
                view_depth_range: None,
            };
            let mut sorted: Vec<f64> = samples.samples().iter().map(|s| undersampling(&map, s)).collect();
            sorted.sort_by(f64::total_cmp);
            let last = sorted.len() - 1;
            let want = [qs[0], qs[1], qs[2], 1.0, 0.0].map(|q| sorted[((q * last as f64).round() as usize).min(last)]);
            let got = samples.undersampling_quantiles(&map, [qs[0], qs[1], qs[2], 1.0, 0.0]).unwrap();
            proptest::prop_assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{:?} vs {:?}", got, want);
        }

        /// The samples cast through the receivers' hierarchy are those of every ray against
        /// every box: the nearest hit per ray.
        #[test]
        fn samples_through_the_hierarchy_match_every_box(
            boxes in proptest::collection::vec((proptest::array::uniform3(-60.0f64..60.0), proptest::array::uniform3(0.2f64..12.0)), 1..200),
            eye in proptest::array::uniform3(-80.0f64..80.0),
            target in proptest::array::uniform3(-30.0f64..30.0),
        ) {
            let mut receivers: Vec<Aabb> = boxes.iter().map(|(lo, size)| {
                let lo = DVec3::from_array(*lo).with_y(lo[1].abs() * 0.3);
                Aabb::new(lo, lo + DVec3::from_array(*size)).unwrap()
            }).collect();
            receivers.push(Aabb::new(DVec3::new(-70.0, -1.0, -70.0), DVec3::new(70.0, 0.0, 70.0)).unwrap());
            let scene = SceneBounds::new(vec![], receivers.clone(), None).unwrap();
            let (eye, target) = (DVec3::from_array(eye), DVec3::from_array(target));
            proptest::prop_assume!(eye.distance(target) > 1.0 && (target - eye).normalize().y.abs() < 0.99);
            let lens = Lens { near: 0.5, far: 150.0, ..Lens::default() };
            let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
            let light = Light::Directional(DirectionalLight::new(DVec3::new(0.3, -1.0, 0.4)).unwrap());
            let got = ViewSamples::new(&camera, &light, &scene);
            // Every ray against every box.
            let (cols, rows) = ViewSamples::grid(lens.aspect);
            let tan_y = (0.5 * lens.fov_y_degrees.to_radians()).tan();
            let tan_x = tan_y * lens.aspect;
            let ndc = |i: u32, n: u32| (2.0 * i as f64 + 1.0) / n as f64 - 1.0;
            let mut hits = Vec::new();
            for j in 0..rows {
                for i in 0..cols {
                    let d = camera.forward() + camera.right() * (ndc(i, cols) * tan_x) + camera.up() * (ndc(j, rows) * tan_y);
                    let best = receivers.iter().filter_map(|b| {
                        ray_box(d.recip(), b.min() - eye, b.max() - eye)
                            .filter(|(t, _)| *t >= lens.near && *t <= lens.far)
                    }).min_by(|a, b| a.0.total_cmp(&b.0));
                    if let Some((t, axis)) = best {
                        let mut normal = DVec3::ZERO;
                        normal[axis] = -d[axis].signum();
                        hits.push((eye + d * t, normal));
                    }
                }
            }
            let want = ViewSamples::from_surface_points(&camera, &light, hits);
            proptest::prop_assert_eq!(got.len(), want.len());
            for (a, b) in got.samples().iter().zip(want.samples()) {
                proptest::prop_assert!(a.position.distance(b.position) <= 1e-9 * (1.0 + a.position.length()), "{:?} vs {:?}", a, b);
            }
        }
    }
}
