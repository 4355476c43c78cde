//! What every focused or warped map of one part of a frame starts from, computed once and
//! shared: the focused map, the warp at each strength the warp limit tries, and TSM's
//! trapezoid all read the same visible scene and convex body B; the focused map itself (the
//! warps' fallback, the limit's reference, TSM's start) and the view warp's light space are
//! made once.
//!
//! A part is the whole view, a cascade's slice or one side of SPPSM's plane (see
//! [`crate::frame`]).

use std::cell::OnceCell;

use glam::DVec3;

use crate::body::focus_body;
use crate::camera::Camera;
use crate::focus::{VisibleScene, refine_codes};
use crate::frame::{Frame, frame_planes};
use crate::geometry::Plane;
use crate::light_space::Projector;
use crate::samples::ViewSamples;
use crate::setup::{Fallback, SetupInput, ShadowSetup};
use crate::techniques::focused::Focused;
use crate::techniques::view_warp::WarpSpace;

/// Which part of a frame a basis covers.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Part<'c> {
    /// The whole view.
    Whole,
    /// A slice: a camera with the frame camera's eye, orientation and lens but nearer far
    /// and farther near planes.
    Slice(&'c Camera),
    /// The side of a plane through the light's rays (a caster on the other side can not
    /// shadow a receiver on this one): receivers, P and casters are cut to it.
    Side(Plane),
}

/// The visible scene and B of one part of a frame.
pub(crate) struct FocusBasis<'f> {
    /// The frame this part belongs to.
    pub frame: &'f Frame<'f>,
    /// The setup's world-space tolerance.
    pub tolerance: f64,
    /// The light's projector in the frame fixed by the light alone.
    pub fixed: Projector,
    /// A spot light's frustum.
    pub light_planes: Option<[Plane; 6]>,
    /// The planes casters are cut by: a spot light's frustum (its near plane first), then a
    /// side's plane.
    pub caster_planes: Vec<Plane>,
    /// The part's view depths (a slice's near and far planes), for its share of the samples.
    depth_range: Option<(f64, f64)>,
    /// P (the part's view frustum clipped by the scene box and a spot's frustum) and the
    /// visible parts of the receivers.
    pub visible: VisibleScene,
    /// B's vertices (LiSPSM paper, section 3.3), built in the fixed frame (B does not depend
    /// on the rotation about the light direction); empty when no receiver is visible.
    pub body: Vec<DVec3>,
    /// The focused map on this basis, made on first use.
    focused: OnceCell<ShadowSetup>,
    /// The view warp's light space, made on first use.
    warp: OnceCell<Result<WarpSpace, Fallback>>,
    /// The part's samples (a slice's share of the frame's), made on first use.
    samples: OnceCell<ViewSamples>,
}

impl<'f> FocusBasis<'f> {
    /// The basis of `part` of `frame`.
    pub fn new(frame: &'f Frame<'f>, part: Part<'_>) -> Self {
        let tolerance = frame.tolerance;
        let light_planes = frame.light_planes;
        let scene = frame.input.scene;
        let mut caster_planes: Vec<Plane> = light_planes.iter().flatten().copied().collect();
        let (visible, depth_range) = match part {
            Part::Whole => (
                VisibleScene::from_codes(
                    frame.view_body.clone(),
                    scene,
                    &frame_planes(
                        frame.input.camera.frustum_planes(),
                        light_planes.as_ref(),
                        None,
                    ),
                    &frame.receiver_codes,
                    tolerance,
                ),
                None,
            ),
            Part::Slice(camera) => {
                let lens = camera.lens();
                let planes = frame_planes(camera.frustum_planes(), light_planes.as_ref(), None);
                // The slice's P is the frame's between the slice's near and far planes.
                let body = frame
                    .view_body
                    .clip(&planes[0], tolerance)
                    .clip(&planes[1], tolerance);
                // The near and far planes (bits 0 and 1) are the slice's own.
                let codes = refine_codes(
                    &frame.receiver_codes,
                    scene.receivers(),
                    &planes,
                    0b11,
                    tolerance,
                );
                (
                    VisibleScene::from_codes(body, scene, &planes, &codes, tolerance),
                    Some((lens.near, lens.far)),
                )
            }
            Part::Side(side) => {
                let body = frame.view_body.clip(&side, tolerance);
                let planes = frame_planes(
                    frame.input.camera.frustum_planes(),
                    light_planes.as_ref(),
                    Some(side),
                );
                let codes = refine_codes(
                    &frame.receiver_codes,
                    scene.receivers(),
                    &planes,
                    1 << (planes.len() - 1),
                    tolerance,
                );
                caster_planes.push(side);
                (
                    VisibleScene::from_codes(body, scene, &planes, &codes, tolerance),
                    None,
                )
            }
        };
        let body = if visible.visible_receivers() > 0 && !visible.view_body.is_empty() {
            focus_body(&visible.view_body, &frame.region, &frame.fixed, tolerance)
                .vertices(tolerance)
        } else {
            Vec::new()
        };
        Self {
            frame,
            tolerance,
            fixed: frame.fixed,
            light_planes,
            caster_planes,
            depth_range,
            visible,
            body,
            focused: OnceCell::new(),
            warp: OnceCell::new(),
            samples: OnceCell::new(),
        }
    }

    /// The focused map of `input` (the input this basis was made for), made once.
    pub fn focused(&self, input: &SetupInput<'_>) -> &ShadowSetup {
        self.focused.get_or_init(|| Focused.setup_on(input, self))
    }

    /// The view warp's light space for `input`, made once (the fallback where the warp is
    /// undefined; see [`WarpSpace::new`]).
    pub fn warp_space(&self, input: &SetupInput<'_>) -> &Result<WarpSpace, Fallback> {
        self.warp.get_or_init(|| WarpSpace::new(input, self))
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
}
