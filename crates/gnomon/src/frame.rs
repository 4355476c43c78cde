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
//! planes the part adds) instead of classifying the scene again. The receivers are classified
//! through their hierarchy ([`crate::bvh`]): whole subtrees inside or outside the view, boxes
//! one by one only near its planes.

use std::sync::OnceLock;

use crate::bounds::SceneBounds;
use crate::bvh::{Classified, all_planes};
use crate::camera::Camera;
use crate::focus::{ReuseCuts, VisibleScene, box_planes, refine};
use crate::geometry::{ConvexPolyhedron, Plane};
use crate::light::Light;
use crate::light_space::{Projector, fixed_projector};
use crate::samples::ViewSamples;
use crate::technique::SetupInput;

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
    /// The receivers against `receiver_planes` (empty when P is).
    pub receiver_codes: Classified,
    /// A point light's view frame this frame of one of its cube faces refines: its visible
    /// scene (whose cuts by the view's planes alone are taken) and the bits of the face's
    /// planes.
    parent: Option<(&'a VisibleScene, u32)>,
    /// The whole view's visible scene, made on first use.
    visible: OnceLock<VisibleScene>,
    /// The view samples when the input has none, cast on first use.
    cast_samples: OnceLock<ViewSamples>,
}

impl<'a> Frame<'a> {
    /// The frame of `input`.
    pub fn new(input: &SetupInput<'a>) -> Self {
        let (tolerance, fixed, light_planes, region) = light_facts(input);
        let view_body = view_body(input.camera, input.scene, light_planes.as_ref(), tolerance);
        let receiver_planes =
            frame_planes(input.camera.frustum_planes(), light_planes.as_ref(), None);
        let mut receiver_codes = Classified::default();
        let tree = input.scene.receiver_tree();
        if !view_body.is_empty() && !tree.is_empty() {
            tree.classify(
                input.scene.receiver_arrays(),
                &receiver_planes,
                tolerance,
                [(0, all_planes(receiver_planes.len()))],
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
            parent: None,
            visible: OnceLock::new(),
            cast_samples: OnceLock::new(),
        }
    }

    /// The frame of one cube face of a point light, refined from the point light's frame
    /// `view` (the same camera and scene; its receivers classified against the view's planes
    /// alone). `input`'s light is the face's spot light, and P and the receivers are only cut
    /// again by the face's frustum. The same frame as [`Frame::new`] of `input` would make.
    pub fn of_face(view: &'a Frame<'a>, input: &SetupInput<'a>) -> Self {
        let (tolerance, fixed, Some(light_planes), region) = light_facts(input) else {
            return Self::new(input);
        };
        let view_body = view.view_body.clip_all(&light_planes, tolerance);
        let receiver_planes =
            frame_planes(input.camera.frustum_planes(), Some(&light_planes), None);
        // The face's planes follow the view's six.
        let changed = all_planes(receiver_planes.len()) & !all_planes(6);
        let (receiver_codes, parent) = if view_body.is_empty() {
            (Classified::default(), None)
        } else {
            let codes = refine(
                &view.receiver_codes,
                input.scene,
                &receiver_planes,
                changed,
                tolerance,
            );
            (codes, Some((view.visible(), changed)))
        };
        Self {
            input: *input,
            tolerance,
            fixed,
            light_planes: Some(light_planes),
            region,
            view_body,
            receiver_planes,
            receiver_codes,
            parent,
            visible: OnceLock::new(),
            cast_samples: OnceLock::new(),
        }
    }

    /// What the whole view sees of the receivers, made once.
    pub fn visible(&self) -> &VisibleScene {
        self.visible.get_or_init(|| {
            VisibleScene::from_classified(
                self.view_body.clone(),
                self.input.scene,
                &self.receiver_planes,
                &self.receiver_codes,
                self.tolerance,
                self.parent
                    .map(|(frame, changed)| ReuseCuts { frame, changed }),
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

/// What a frame knows of its light alone: the setup's tolerance, the light's projector in its
/// fixed frame, a spot light's frustum, and the region B lies in (the scene box clipped by
/// that frustum).
fn light_facts(input: &SetupInput<'_>) -> (f64, Projector, Option<[Plane; 6]>, ConvexPolyhedron) {
    let tolerance = tolerance(input.scene, Some(input.camera), input.light);
    let fixed = fixed_projector(input.light);
    let light_planes = match input.light {
        Light::Directional(_) | Light::Point(_) => None,
        Light::Spot(spot) => Some(spot.frustum_planes(fixed.frame().up)),
    };
    let region = ConvexPolyhedron::from_box(&input.scene.scene_box())
        .clip_all(light_planes.iter().flatten(), tolerance);
    (tolerance, fixed, light_planes, region)
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

/// The world-space tolerance of one setup: a billionth of the distances involved (the scene
/// box's diagonal plus how far the camera and light are from it). For a spot or point light
/// it is at most a thousandth of its near plane's distance, which is a billionth of the
/// range with the near plane at [`crate::SPOT_NEAR_FRACTION`] of it. The clips keep points
/// up to the tolerance outside the near plane, and the light's projection divides by their
/// depth: a lamp of 0.1 m range in a 500 m scene has its near plane 1e-7 from it, under the
/// 5e-7 the scene alone gives.
pub(crate) fn tolerance(scene: &SceneBounds, camera: Option<&Camera>, light: &Light) -> f64 {
    let scene_box = scene.scene_box();
    let center = scene_box.center();
    let mut scale = scene_box.diagonal();
    if let Some(camera) = camera {
        scale += (camera.eye() - center).length();
    }
    let near = match light {
        Light::Directional(_) => f64::INFINITY,
        Light::Spot(spot) => {
            scale += (spot.position() - center).length() + spot.range();
            spot.near()
        }
        Light::Point(point) => {
            scale += (point.position() - center).length() + point.range();
            point.near()
        }
    };
    (1e-9 * scale).min(1e-3 * near)
}
