//! What every focused or warped map of one part of a frame starts from, computed once and
//! shared: the focused map, the warp at each strength the warp limit tries, and TSM's
//! trapezoid all read the same visible scene and convex body B; the focused map itself (the
//! warps' fallback, the limit's reference, TSM's start) and the view warp's light space are
//! made once.
//!
//! A part is the whole view, a cascade's slice or one side of SPPSM's plane (see
//! [`crate::frame`]).

use std::borrow::Cow;
use std::cell::OnceCell;

use glam::DVec3;

use crate::body::focus_body;
use crate::bvh::Classified;
use crate::camera::Camera;
use crate::diagnostics::Fallback;
use crate::focus::{ReuseCuts, VisibleScene, refine, refine_slices};
use crate::frame::{Frame, frame_planes};
use crate::geometry::Plane;
use crate::light_space::{Extents, Projector};
use crate::map::ShadowSetup;
use crate::samples::ViewSamples;
use crate::techniques::warp_space::WarpSpace;

/// Which part of a frame a basis covers.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Part<'c> {
    /// The whole view.
    Whole,
    /// A slice: a camera with the frame camera's eye, orientation and lens but nearer far
    /// and farther near planes, and the frame's receivers refined by its planes
    /// ([`slice_codes`]).
    Slice(&'c Camera, &'c Classified),
    /// The side of a plane through the light's rays (a caster on the other side can not
    /// shadow a receiver on this one): receivers, P and casters are cut to it.
    Side(Plane),
}

/// The visible scene and B of one part of a frame.
pub(crate) struct FocusBasis<'f> {
    /// The frame this part belongs to (its tolerance, the light's fixed frame and frustum).
    pub frame: &'f Frame<'f>,
    /// The planes casters are cut by: a spot light's frustum (its near plane first), then a
    /// side's plane.
    pub caster_planes: Vec<Plane>,
    /// The part's view depths (a slice's near and far planes), for its share of the samples.
    depth_range: Option<(f64, f64)>,
    /// P (the part's view frustum clipped by the scene box and a spot's frustum) and the
    /// visible parts of the receivers.
    pub visible: Cow<'f, VisibleScene>,
    /// B's vertices (LiSPSM paper, section 3.3), made on first use ([`Self::body`]).
    body: OnceCell<Vec<DVec3>>,
    /// The focused map on this basis, made on first use.
    focused: OnceCell<ShadowSetup>,
    /// The view warp's light space, made on first use.
    warp: OnceCell<Result<WarpSpace, Fallback>>,
    /// The part's samples (a slice's share of the frame's), made on first use.
    samples: OnceCell<ViewSamples>,
    /// The visible receivers' extents under the first projector asked for: the focused map
    /// and the view warp's light space both take them in the view-aligned light frame.
    receivers: OnceCell<(Projector, Extents)>,
}

impl<'f> FocusBasis<'f> {
    /// The basis of `part` of `frame`.
    pub fn new(frame: &'f Frame<'f>, part: Part<'_>) -> Self {
        let tolerance = frame.tolerance;
        let light_planes = frame.light_planes;
        let mut caster_planes: Vec<Plane> = light_planes.iter().flatten().copied().collect();
        let (visible, depth_range) = match part {
            Part::Whole => (Cow::Borrowed(frame.visible()), None),
            Part::Slice(camera, codes) => {
                let lens = camera.lens();
                let planes = slice_planes(frame, camera);
                // The slice's P is the frame's between the slice's near and far planes (0
                // and 1, the slice's own); the whole view's cuts are taken where it has them.
                let body = frame
                    .view_body
                    .clip(&planes[0], tolerance)
                    .clip(&planes[1], tolerance);
                let reuse = frame.has_visible();
                (
                    Cow::Owned(visible_scene(frame, body, &planes, codes, 0b11, reuse)),
                    Some((lens.near, lens.far)),
                )
            }
            Part::Side(side) => {
                let body = frame.view_body.clip(&side, tolerance);
                let mut planes = frame.receiver_planes.clone();
                planes.push(side);
                caster_planes.push(side);
                // The receivers the view's frustum cuts and the side does not are cut as
                // the whole view cuts them.
                let changed = 1 << (planes.len() - 1);
                (
                    Cow::Owned(refined(frame, body, &planes, changed, true)),
                    None,
                )
            }
        };
        Self {
            frame,
            caster_planes,
            depth_range,
            visible,
            body: OnceCell::new(),
            focused: OnceCell::new(),
            warp: OnceCell::new(),
            samples: OnceCell::new(),
            receivers: OnceCell::new(),
        }
    }

    /// B's vertices (LiSPSM paper, section 3.3), built in the fixed frame (B does not depend
    /// on the rotation about the light direction); empty when no receiver is visible. Made
    /// on first use: the warps and a spot light's focused map read it, a directional
    /// light's focused map does not (see [`crate::Focused`]), and B's dozen plane clips are
    /// a quarter of that map's setup.
    pub fn body(&self) -> &[DVec3] {
        self.body.get_or_init(|| {
            let (visible, frame) = (&self.visible, self.frame);
            if visible.visible_receivers() > 0 && !visible.view_body.is_empty() {
                focus_body(
                    &visible.view_body,
                    &frame.region,
                    &frame.fixed,
                    frame.tolerance,
                )
                .vertices(frame.tolerance)
            } else {
                Vec::new()
            }
        })
    }

    /// The visible receivers' extents under `projector`
    /// ([`VisibleScene::receiver_extents`]), made once for the first projector asked for.
    pub fn receiver_extents(&self, projector: &Projector) -> Extents {
        let scene = self.frame.input.scene;
        match self.receivers.get() {
            Some((cached, extents)) if cached == projector => *extents,
            Some(_) => self.visible.receiver_extents(scene, projector),
            None => {
                let extents = self.visible.receiver_extents(scene, projector);
                let _ = self.receivers.set((*projector, extents));
                extents
            }
        }
    }

    /// Keeps `extents`, the visible receivers' extents under `projector` made by another walk
    /// ([`VisibleScene::extents_under`] under two maps), where none are kept yet.
    pub fn keep_receiver_extents(&self, projector: &Projector, extents: Extents) {
        let _ = self.receivers.set((*projector, extents));
    }

    /// The focused map of this basis's input, made by `make` on first use
    /// ([`focused_map`](super::focused::focused_map)).
    pub fn focused_or(&self, make: impl FnOnce() -> ShadowSetup) -> &ShadowSetup {
        self.focused.get_or_init(make)
    }

    /// The view warp's light space for this basis's input, made by `make` on first use
    /// ([`warp_space`](super::view_warp::warp_space)).
    pub fn warp_space_or(
        &self,
        make: impl FnOnce() -> Result<WarpSpace, Fallback>,
    ) -> &Result<WarpSpace, Fallback> {
        self.warp.get_or_init(make)
    }

    /// The samples of this part: the frame's, or a slice's share of them.
    pub fn samples(&self) -> &ViewSamples {
        match self.depth_range {
            None => self.frame.samples(),
            Some((near, far)) => self
                .samples
                .get_or_init(|| self.frame.samples().within_depth(near, far)),
        }
    }

    /// Whether casters are cut by planes (a spot light's frustum, a side).
    pub fn cuts_casters(&self) -> bool {
        !self.caster_planes.is_empty()
    }

    /// Whether `caster_planes` begin with a spot light's near plane (a caster walk then
    /// counts the casters it clips).
    pub fn light_near_first(&self) -> bool {
        self.frame.light_planes.is_some()
    }
}

/// The visible scene of a part of `frame` whose P is `body`: the frame's receiver codes
/// refined against `planes` (the frame's, but for those named in `changed`), the cut ones
/// cut, or taken from the whole view's visible scene (`reuse`) where the same planes cut them.
fn refined(
    frame: &Frame<'_>,
    body: crate::geometry::ConvexPolyhedron,
    planes: &[Plane],
    changed: u32,
    reuse: bool,
) -> VisibleScene {
    let codes = refine(
        &frame.receiver_codes,
        frame.input.scene,
        planes,
        changed,
        frame.tolerance,
    );
    visible_scene(frame, body, planes, &codes, changed, reuse)
}

/// [`refined`] from the part's codes, refined already.
fn visible_scene(
    frame: &Frame<'_>,
    body: crate::geometry::ConvexPolyhedron,
    planes: &[Plane],
    codes: &Classified,
    changed: u32,
    reuse: bool,
) -> VisibleScene {
    let reuse = reuse.then(|| ReuseCuts {
        frame: frame.visible(),
        changed,
    });
    VisibleScene::from_classified(
        body,
        frame.input.scene,
        planes,
        codes,
        frame.tolerance,
        reuse,
    )
}

/// The planes of a slice of `frame` (`camera`: the frame camera's eye, orientation and lens
/// with its own near and far planes): its near and far planes first, then the frame's.
fn slice_planes(frame: &Frame<'_>, camera: &Camera) -> Vec<Plane> {
    frame_planes(camera.frustum_planes(), frame.light_planes.as_ref(), None)
}

/// The frame's receivers refined by each slice's planes (`cameras` as in [`Part::Slice`]), for
/// the slices' [`Part::Slice`]: in one walk of the frame's receivers where the slices share
/// their planes' normals, as a cascade's slices of one camera do ([`refine_slices`]), else
/// one refinement each. The same codes either way.
pub(crate) fn slice_codes(frame: &Frame<'_>, cameras: &[Camera]) -> Vec<Classified> {
    let planes: Vec<Vec<Plane>> = cameras.iter().map(|c| slice_planes(frame, c)).collect();
    let scene = frame.input.scene;
    refine_slices(&frame.receiver_codes, scene, &planes, frame.tolerance).unwrap_or_else(|| {
        planes
            .iter()
            .map(|p| refine(&frame.receiver_codes, scene, p, 0b11, frame.tolerance))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::*;
    use crate::bounds::SceneBounds;
    use crate::boxes::Aabb;
    use crate::camera::Lens;
    use crate::light::{DirectionalLight, Light, SpotLight};
    use crate::map::MapSettings;
    use crate::technique::SetupInput;
    use crate::techniques::focused::focused_map;

    fn close_sets(a: &[DVec3], b: &[DVec3], eps: f64) -> bool {
        a.iter().all(|p| b.iter().any(|q| p.distance(*q) <= eps))
            && b.iter().all(|p| a.iter().any(|q| p.distance(*q) <= eps))
    }

    fn vertices(basis: &FocusBasis, scene: &SceneBounds) -> Vec<DVec3> {
        let mut out = Vec::new();
        basis.visible.for_each_vertex(scene, |p| out.push(p));
        out
    }

    /// Boxes (lowest corner, size) that cast and receive over a ground slab that receives.
    fn city(boxes: &[([f64; 3], [f64; 3])]) -> SceneBounds {
        let boxes: Vec<Aabb> = boxes
            .iter()
            .map(|(lo, size)| {
                let lo = DVec3::from_array(*lo).with_y(lo[1].abs() * 0.2);
                Aabb::new(lo, lo + DVec3::from_array(*size)).unwrap()
            })
            .collect();
        let ground =
            Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
        let mut receivers = boxes.clone();
        receivers.push(ground);
        SceneBounds::new(boxes, receivers, None).unwrap()
    }

    /// The property tests' camera (near 0.5, far 150, looking from `eye` at `target`) and
    /// light (a directional light from above along `light`, or with `spot` a spot 80 m up
    /// shining down along it), or `None` for the draws they skip: the eye on the target, a
    /// view along the vertical, no light direction.
    fn camera_and_light(
        eye: [f64; 3],
        target: [f64; 3],
        light: [f64; 3],
        spot: bool,
    ) -> Option<(Camera, Light)> {
        let (eye, target) = (DVec3::from_array(eye), DVec3::from_array(target));
        let direction = DVec3::from_array(light);
        if eye.distance(target) <= 1.0
            || (target - eye).normalize().y.abs() >= 0.99
            || direction.length() <= 0.1
        {
            return None;
        }
        let lens = Lens {
            near: 0.5,
            far: 150.0,
            ..Lens::default()
        };
        let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
        let light = if spot {
            let down = direction.with_y(-1.0);
            Light::Spot(SpotLight::new(DVec3::new(0.0, 80.0, 0.0), down, 50.0, 300.0).unwrap())
        } else {
            let down = direction.with_y(-direction.y.abs() - 0.1);
            Light::Directional(DirectionalLight::new(down).unwrap())
        };
        Some((camera, light))
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

        /// A slice refined from the frame sees what a frame of the slice's own camera sees:
        /// the same receiver parts and the same B.
        #[test]
        fn a_slice_of_the_frame_is_the_slice_camera_s_frame(
            boxes in prop::collection::vec((prop::array::uniform3(-40.0f64..40.0), prop::array::uniform3(0.5f64..15.0)), 1..40),
            eye in prop::array::uniform3(-60.0f64..60.0),
            target in prop::array::uniform3(-20.0f64..20.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            spot in any::<bool>(),
            cut in (0.0f64..1.0, 0.0f64..1.0),
        ) {
            let scene = city(&boxes);
            let view_and_light = camera_and_light(eye, target, light, spot);
            prop_assume!(view_and_light.is_some());
            let (camera, light) = view_and_light.unwrap();
            let lens = camera.lens();
            let whole = Camera::from_view_from_world(camera.view_from_world(), lens).unwrap();
            let input = SetupInput { camera: &whole, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            let (a, b) = (lens.near + cut.0 * 100.0, lens.near + cut.1 * 100.0);
            let (near, far) = (a.min(b), a.max(b) + 1.0);
            let slice = Camera::from_view_from_world(camera.view_from_world(), Lens { near, far, ..lens }).unwrap();
            let codes = slice_codes(&frame, std::slice::from_ref(&slice));
            let refined = FocusBasis::new(&frame, Part::Slice(&slice, &codes[0]));
            let slice_input = SetupInput { camera: &slice, ..input };
            let own_frame = Frame::new(&slice_input);
            let direct = FocusBasis::new(&own_frame, Part::Whole);
            prop_assert_eq!(refined.visible.visible_receivers(), direct.visible.visible_receivers());
            let eye = camera.eye().length();
            let eps = 1e-6 * (1.0 + eye);
            prop_assert!(close_sets(&vertices(&refined, &scene), &vertices(&direct, &scene), eps));
            prop_assert!(close_sets(refined.body(), direct.body(), 1e-5 * (1.0 + eye)),
                "B {:?} vs {:?}", refined.body(), direct.body());
        }

        /// A cascade's slices refined in one walk of the frame's receivers get, item for
        /// item and in order, what refining each slice alone gives, blend bands (overlapping
        /// slices) and spot lights included; and the one walk is taken.
        #[test]
        fn slices_refined_in_one_walk_match_each_refined_alone(
            boxes in prop::collection::vec((prop::array::uniform3(-40.0f64..40.0), prop::array::uniform3(0.5f64..15.0)), 1..60),
            eye in prop::array::uniform3(-60.0f64..60.0),
            target in prop::array::uniform3(-20.0f64..20.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            spot in any::<bool>(),
            cuts in prop::collection::vec(0.0f64..1.0, 2..10),
            blend in 0.0f64..0.5,
        ) {
            let scene = city(&boxes);
            let view_and_light = camera_and_light(eye, target, light, spot);
            prop_assume!(view_and_light.is_some());
            let (camera, light) = view_and_light.unwrap();
            let lens = camera.lens();
            let input = SetupInput { camera: &camera, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            // Split depths over the view, each slice reaching back over a blend band.
            let mut depths: Vec<f64> = cuts.iter().map(|t| lens.near + t * (lens.far - lens.near)).collect();
            depths.sort_by(f64::total_cmp);
            depths.dedup();
            prop_assume!(depths.len() >= 2);
            let cameras: Vec<Camera> = depths
                .windows(2)
                .map(|w| {
                    let near = (w[0] - blend * (w[1] - w[0])).max(lens.near);
                    Camera::from_view_from_world(camera.view_from_world(), Lens { near, far: w[1], ..lens }).unwrap()
                })
                .collect();
            let planes: Vec<Vec<Plane>> = cameras.iter().map(|c| slice_planes(&frame, c)).collect();
            let one_walk = refine_slices(&frame.receiver_codes, &scene, &planes, frame.tolerance);
            prop_assert!(one_walk.is_some(), "the slices did not share their planes");
            let alone: Vec<Classified> = planes
                .iter()
                .map(|p| refine(&frame.receiver_codes, &scene, p, 0b11, frame.tolerance))
                .collect();
            prop_assert_eq!(one_walk.unwrap(), alone.clone());
            prop_assert_eq!(slice_codes(&frame, &cameras), alone);
        }

        /// Under a directional light, B's rectangle in either light frame is P's (each point of
        /// B lies on a ray from P toward the light), which is what lets the focused map pick
        /// its frame from P; and a focused map leaves B unbuilt.
        #[test]
        fn b_has_p_s_rectangle_under_a_parallel_projection(
            boxes in prop::collection::vec((prop::array::uniform3(-40.0f64..40.0), prop::array::uniform3(0.5f64..15.0)), 1..30),
            eye in prop::array::uniform3(-60.0f64..60.0),
            target in prop::array::uniform3(-20.0f64..20.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            far in 5.0f64..400.0,
        ) {
            let scene = city(&boxes);
            let (eye, target) = (DVec3::from_array(eye), DVec3::from_array(target));
            prop_assume!(eye.distance(target) > 1.0 && (target - eye).normalize().y.abs() < 0.99);
            let lens = Lens { near: 0.5, far, ..Lens::default() };
            let camera = Camera::look_at(eye, target, DVec3::Y, lens).unwrap();
            let direction = DVec3::from_array(light);
            prop_assume!(direction.length() > 0.1);
            let sun = DirectionalLight::new(direction.with_y(-direction.y.abs() - 0.1)).unwrap();
            let light = Light::Directional(sun);
            let input = SetupInput { camera: &camera, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            let basis = FocusBasis::new(&frame, Part::Whole);
            let _ = focused_map(&input, &basis);
            prop_assert!(basis.body.get().is_none(), "the focused map built B");
            prop_assume!(basis.visible.visible_receivers() > 0);
            let mut projectors = vec![frame.fixed];
            if let Some(aligned) = crate::light_space::LightFrame::view_aligned(sun.direction(), camera.forward()) {
                projectors.push(Projector::Parallel(aligned));
            }
            let eps = 1e-6 * (1.0 + eye.length() + 100.0);
            for projector in &projectors {
                let p = projector.points_extents(basis.visible.view_body.points());
                let b = projector.points_extents(basis.body());
                prop_assert!((p.min - b.min).truncate().abs().max_element() <= eps
                    && (p.max - b.max).truncate().abs().max_element() <= eps,
                    "P {:?} vs B {:?}", p, b);
            }
        }
    }
}
