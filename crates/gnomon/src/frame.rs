//! The facts of one frame, computed once and shared by every technique, every cascade and
//! every SPPSM side that reads them: the tolerance, the light's fixed frame and frustum, the
//! region B lies in, P (the view frustum clipped by the scene box and a spot light's frustum),
//! each receiver's place against the view and light frusta, the casters' light-space boxes,
//! and the view samples.
//!
//! A technique works on a part of the frame (a [`crate::techniques::basis::FocusBasis`]): all
//! of it, a cascade's slice (the same eye and orientation, nearer far and farther near
//! planes), or one side of a plane through the light's rays (SPPSM). A part refines the
//! frame's classification (only the receivers the frame sees are tested again, against the
//! planes the part adds) instead of classifying the scene again. A spatial index over the
//! scene's boxes would sit here, under the same structure.

use std::cell::{Cell, OnceCell};

use glam::DVec3;

use crate::bounds::{BoxArrays, SceneBounds};
use crate::focus::{VisibleScene, box_planes, classify_boxes};
use crate::geometry::{ConvexPolyhedron, Plane};
use crate::light::Light;
use crate::light_space::{Extents, LightFrame, Projector};
use crate::samples::ViewSamples;
use crate::setup::SetupInput;
use crate::techniques::{fixed_projector, tolerance};

/// The shared facts of one camera, light and scene; see the module documentation.
pub(crate) struct Frame<'a> {
    /// The frame's input (its camera is the whole view's).
    pub input: SetupInput<'a>,
    /// The setup's world-space tolerance (it depends on the eye, not on the near and far
    /// planes, so a slice shares it).
    pub tolerance: f64,
    /// The light's projector in the frame fixed by the light alone.
    pub fixed: Projector,
    /// A spot light's frustum.
    pub light_planes: Option<[Plane; 6]>,
    /// The scene box clipped by a spot light's frustum: B lies in it.
    pub region: ConvexPolyhedron,
    /// P of the whole view.
    pub view_body: ConvexPolyhedron,
    /// The planes receivers are classified against: the view frustum's, then the light's
    /// ([`frame_planes`]).
    pub receiver_planes: Vec<Plane>,
    /// Each receiver against `receiver_planes` ([`classify_boxes`]'s codes; empty when P is).
    pub receiver_codes: Vec<u32>,
    /// The light frame aligned with the view (directional lights; `None` when the view is
    /// parallel to the light or the light is a spot).
    pub aligned: Option<LightFrame>,
    /// The casters' boxes in `aligned`, made on first use.
    aligned_casters: OnceCell<LightBoxes>,
    /// The casters' boxes in the fixed frame of a directional light, made on first use.
    fixed_casters: OnceCell<LightBoxes>,
    /// How often each of the two was asked for: a frame that one setup reads once does not
    /// pay for the copy, so each is made on its second request.
    requests: [Cell<u32>; 2],
    /// The whole view's visible scene, made on first use.
    visible: OnceCell<VisibleScene>,
    /// The view samples when the input has none, cast on first use.
    cast_samples: OnceCell<ViewSamples>,
}

impl<'a> Frame<'a> {
    /// The frame of `input`.
    pub fn new(input: &SetupInput<'a>) -> Self {
        let tolerance = tolerance(input.scene, Some(input.camera), input.light);
        let fixed = fixed_projector(input.light);
        let (light_planes, aligned) = match input.light {
            Light::Directional(light) => (
                None,
                LightFrame::view_aligned(light.direction(), input.camera.forward()),
            ),
            Light::Spot(spot) => (Some(spot.frustum_planes(fixed.frame().up)), None),
        };
        let scene_box = input.scene.scene_box();
        let region = ConvexPolyhedron::from_box(&scene_box)
            .clip_all(light_planes.iter().flatten(), tolerance);
        let view_body = view_body(input.camera, input.scene, light_planes.as_ref(), tolerance);
        let receiver_planes =
            frame_planes(input.camera.frustum_planes(), light_planes.as_ref(), None);
        let mut receiver_codes = Vec::new();
        if !view_body.is_empty() {
            classify_boxes(
                input.scene.receiver_arrays(),
                &receiver_planes,
                tolerance,
                &mut receiver_codes,
            );
        }
        Self {
            input: *input,
            tolerance,
            fixed,
            light_planes,
            region,
            view_body,
            receiver_planes,
            receiver_codes,
            aligned,
            aligned_casters: OnceCell::new(),
            fixed_casters: OnceCell::new(),
            requests: Default::default(),
            visible: OnceCell::new(),
            cast_samples: OnceCell::new(),
        }
    }

    /// The casters' boxes under `frame` when it is one of a directional light's two frames
    /// (the frame's view-aligned one, the warps' light space and the focused map's usual
    /// frame, or the one fixed by the light), made once (on the second request) and shared;
    /// `None` for any other frame, and on the first request.
    pub fn casters_in(&self, frame: &LightFrame) -> Option<&LightBoxes> {
        let boxes = self.input.scene.caster_arrays();
        let which = if self.aligned.as_ref() == Some(frame) {
            0
        } else {
            match (&self.fixed, self.input.light) {
                (Projector::Parallel(fixed), Light::Directional(_)) if fixed == frame => 1,
                _ => return None,
            }
        };
        let cache = [&self.aligned_casters, &self.fixed_casters][which];
        if cache.get().is_none() {
            let requests = &self.requests[which];
            requests.set(requests.get() + 1);
            if requests.get() < 2 {
                return None;
            }
        }
        Some(cache.get_or_init(|| LightBoxes::new(boxes, frame)))
    }

    /// What the whole view sees of the receivers, made once.
    pub fn visible(&self) -> &VisibleScene {
        self.visible.get_or_init(|| {
            VisibleScene::from_codes(
                self.view_body.clone(),
                self.input.scene,
                &self.receiver_planes,
                &self.receiver_codes,
                self.tolerance,
                None,
            )
        })
    }

    /// Whether the whole view's visible scene has been made.
    pub fn has_visible(&self) -> bool {
        self.visible.get().is_some()
    }

    /// The frame's view samples: the input's, or cast against the receiver boxes once.
    pub fn samples(&self) -> &ViewSamples {
        match self.input.samples {
            Some(samples) => samples,
            None => self.cast_samples.get_or_init(|| {
                ViewSamples::new(self.input.camera, self.input.light, self.input.scene)
            }),
        }
    }
}

/// The planes a part of the frame classifies receivers against: the view frustum (near, far,
/// left, right, bottom, top), the light's frustum, then a side plane.
pub(crate) fn frame_planes(
    frustum: [Plane; 6],
    light_planes: Option<&[Plane; 6]>,
    side: Option<Plane>,
) -> Vec<Plane> {
    let mut planes = frustum.to_vec();
    planes.extend(light_planes.iter().copied().flatten());
    planes.extend(side);
    planes
}

/// P: `camera`'s view frustum clipped by the scene box and a spot light's frustum.
pub(crate) fn view_body(
    camera: &crate::camera::Camera,
    scene: &SceneBounds,
    light_planes: Option<&[Plane; 6]>,
    tolerance: f64,
) -> ConvexPolyhedron {
    ConvexPolyhedron::from_hexahedron(&camera.frustum_corners())
        .clip_all(&box_planes(&scene.scene_box()), tolerance)
        .clip_all(light_planes.into_iter().flatten(), tolerance)
}

/// Boxes in a light frame, one array per coordinate (so that a pass over them vectorises):
/// box i spans [lo[k][i], hi[k][i]] along the frame's right, up and forward axes.
pub(crate) struct LightBoxes {
    pub lo: [Vec<f64>; 3],
    pub hi: [Vec<f64>; 3],
}

impl LightBoxes {
    /// The boxes of `boxes` in `frame`: a box's image is its projected centre plus and minus
    /// |R| times its half extents.
    pub fn new(boxes: &BoxArrays, frame: &LightFrame) -> Self {
        let axes = [frame.right, frame.up, frame.forward];
        let n = boxes.len();
        let ([cx, cy, cz], [hx, hy, hz]) = boxes.columns();
        // One pass per axis, so that it vectorises.
        let side = |axis: DVec3, sign: f64| -> Vec<f64> {
            let a = axis.abs() * sign;
            (0..n)
                .map(|i| {
                    axis.x * cx[i]
                        + axis.y * cy[i]
                        + axis.z * cz[i]
                        + (a.x * hx[i] + a.y * hy[i] + a.z * hz[i])
                })
                .collect()
        };
        Self {
            lo: axes.map(|a| side(a, -1.0)),
            hi: axes.map(|a| side(a, 1.0)),
        }
    }

    /// How many boxes.
    pub fn len(&self) -> usize {
        self.lo[0].len()
    }

    /// The boxes that overlap the xy rectangle of `rect` (grown by `slack`, touching counts)
    /// and begin no farther along the light than `max_z`, and whose y range meets `y_range`:
    /// their indices, appended to `out`.
    pub fn overlapping(
        &self,
        rect: &Extents,
        slack: f64,
        max_z: f64,
        y_range: (f64, f64),
        out: &mut Vec<u32>,
    ) {
        let (x0, x1) = (rect.min.x - slack, rect.max.x + slack);
        let (y0, y1) = (
            (rect.min.y - slack).max(y_range.0),
            (rect.max.y + slack).min(y_range.1),
        );
        let n = self.len();
        let (lx, ly, lz) = (&self.lo[0][..n], &self.lo[1][..n], &self.lo[2][..n]);
        let (hx, hy) = (&self.hi[0][..n], &self.hi[1][..n]);
        for i in 0..n {
            let keep =
                (x0 <= hx[i]) & (lx[i] <= x1) & (y0 <= hy[i]) & (ly[i] <= y1) & (lz[i] <= max_z);
            if keep {
                out.push(i as u32);
            }
        }
    }

    /// Box `i`.
    #[inline]
    pub fn get(&self, i: usize) -> Extents {
        Extents {
            min: DVec3::new(self.lo[0][i], self.lo[1][i], self.lo[2][i]),
            max: DVec3::new(self.hi[0][i], self.hi[1][i], self.hi[2][i]),
        }
    }
}
