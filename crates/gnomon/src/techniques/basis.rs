//! What every focused or warped map of one setup starts from, computed once and shared: the
//! focused map, the warp at each strength the warp limit tries, and TSM's trapezoid all read
//! the same visible scene and convex body B, and the focused map itself (the warps' fallback,
//! the limit's reference, TSM's start) is made once.

use std::cell::OnceCell;

use glam::DVec3;

use crate::body::focus_body;
use crate::focus::VisibleScene;
use crate::geometry::{ConvexPolyhedron, Plane};
use crate::light::Light;
use crate::light_space::Projector;
use crate::setup::{SetupInput, ShadowSetup};
use crate::techniques::focused::Focused;
use crate::techniques::{fixed_projector, tolerance};

/// The visible scene and B of one camera, light and scene.
pub(crate) struct FocusBasis {
    /// The setup's world-space tolerance.
    pub tolerance: f64,
    /// The light's projector in the frame fixed by the light alone.
    pub fixed: Projector,
    /// A spot light's frustum.
    pub light_planes: Option<[Plane; 6]>,
    /// P (the view frustum clipped by the scene box and a spot's frustum) and the visible
    /// parts of the receivers.
    pub visible: VisibleScene,
    /// B's vertices (LiSPSM paper, section 3.3), built in the fixed frame (B does not depend
    /// on the rotation about the light direction); empty when no receiver is visible.
    pub body: Vec<DVec3>,
    /// The focused map on this basis, made on first use.
    focused: OnceCell<ShadowSetup>,
}

impl FocusBasis {
    pub fn new(input: &SetupInput<'_>) -> Self {
        let tolerance = tolerance(input.scene, Some(input.camera), input.light);
        let fixed = fixed_projector(input.light);
        let light_planes = match input.light {
            Light::Directional(_) => None,
            Light::Spot(spot) => Some(spot.frustum_planes(fixed.frame().up)),
        };
        let visible =
            VisibleScene::new(input.camera, input.scene, light_planes.as_ref(), tolerance);
        let body = if visible.visible_receivers() > 0 && !visible.view_body.is_empty() {
            let region = ConvexPolyhedron::from_box(&input.scene.scene_box())
                .clip_all(light_planes.iter().flatten(), tolerance);
            focus_body(&visible.view_body, &region, &fixed, tolerance).vertices(tolerance)
        } else {
            Vec::new()
        };
        Self {
            tolerance,
            fixed,
            light_planes,
            visible,
            body,
            focused: OnceCell::new(),
        }
    }

    /// The focused map of `input` (the input this basis was made for), made once.
    pub fn focused(&self, input: &SetupInput<'_>) -> &ShadowSetup {
        self.focused.get_or_init(|| Focused.setup_on(input, self))
    }
}
