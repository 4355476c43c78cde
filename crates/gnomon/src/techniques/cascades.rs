//! Cascaded shadow maps: the view cut into slices by view depth, one map per slice, each
//! fitted by a single-map technique (a warp per cascade), or stable cascades.
//!
//! z-partitioning: Zhang et al., "Parallel-split shadow maps" (2006; the practical split
//! z_i = lambda z_n (z_f / z_n)^(i/K) + (1 - lambda) (z_n + (z_f - z_n) i / K)); Lloyd et
//! al. 2006 (z-partitioning with a warp per slice gives the lowest maximum error). Each slice
//! is a camera with the same eye, orientation and field of view and the slice's near and far
//! planes, so a slice's map is its technique's map for that camera. That is unit cube
//! clipping over the casters that can shadow the slice's visible receivers, and the warp
//! limit on the slice's share of the frame's view samples. Casters outside the slice count
//! too: a caster between the light and the slice is in the light's column over it, which
//! the technique's focusing keeps.
//!
//! The slices run from where the visible scene begins to where it ends or the shadow
//! distance, whichever is nearer: a slice spent on empty space before or after the scene
//! would waste its texels. The scene begins at the least view depth of P (the view frustum
//! clipped by the scene box and a spot light's frustum), at least the near plane. Explicit
//! split distances, and stable cascades (whose slices must not change with the view), run
//! from the near plane to the shadow distance. Where the shadow distance cuts the visible
//! scene, shadows fade out over its last 10%, and nothing beyond it is shadowed.
//!
//! Shared work: the frame's facts ([`crate::frame`]: P, each receiver against the view, the
//! casters in light space, the view samples) are computed once; each slice is a
//! [`crate::techniques::basis::Part::Slice`] of them, whose receivers are only tested again
//! against its near and far planes, every slice's in one walk of the frame's receivers
//! ([`crate::focus::refine_slices`]). The slices share nothing they write, so fitted slices
//! run in parallel where the (opt-in) `parallel` feature is on (`crate::parallel`), with the
//! same maps.
//!
//! Blending: map i + 1 also covers the last `blend` fraction of slice i, where a pixel mixes
//! both (the renderer's blend band), so its slice camera starts there.
//!
//! Stable cascades (directional lights): each slice is bounded by the sphere around its eight
//! frustum corners, whose radius depends on the lens and the split depths only, not on where
//! the camera is or looks. The map is a square of that size in texels, in the frame fixed by
//! the light alone, with its centre snapped to whole texels and its depth range the scene
//! box's along the light. The texel grid then stays put in the world while the camera
//! translates or turns, which is what engines ship (Bevy, Godot, Unity, three.js, Filament's
//! stable mode). The cost is the texels outside the receivers: a sphere's square holds the
//! slice with room to spare, and does not shrink to what is visible.
//!
//! Picking a map: by default a fitted cascade's point reads its view depth's slice's map, and
//! a stable cascade's point the first map whose square holds it ([`CascadeSelect`]). A
//! stable map holds every caster over its square (its depth range is the scene box's), and the
//! nearer slices' maps are finer and reach past their slices (the sphere's square), so picking
//! by coverage reads finer texels there, and halves the stable cascades' wrong pixels on the
//! demo's sun views (CHANGELOG.md). A fitted map holds only its slice's depth range and
//! casters, so it is picked by depth.

use glam::{DMat4, DVec3, DVec4};

use crate::MIN_RESOLUTION;
use crate::camera::{Camera, Lens};
use crate::diagnostics::{Diagnostics, Fallback, LightFrameKind, MapDiagnostics};
use crate::error::SetupError;
use crate::frame::Frame;
use crate::geometry::ConvexPolyhedron;
use crate::light::Light;
use crate::light_space::LightFrame;
use crate::map::{
    CascadeSlices, MAX_CASCADES, MapProjection, MapSelection, MapSettings, ShadowMap, ShadowSetup,
};
use crate::samples::ViewSamples;
use crate::technique::{SetupInput, ShadowTechnique};
use crate::techniques::basis::{FocusBasis, Part, slice_codes};
use crate::techniques::focused::focused_map;
use crate::techniques::warp_limit::LimitedWarp;
use crate::techniques::{Focused, Lispsm, Psm, Tsm, Xpsm};

/// How the view is cut into slices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CascadeSplit {
    /// Zhang et al.'s practical split: lambda times the logarithmic split plus (1 - lambda)
    /// times the uniform one (lambda in [0, 1]; three.js uses 0.5).
    Practical {
        /// The weight of the logarithmic split.
        lambda: f64,
    },
    /// z_i = z_n (z_f / z_n)^(i / K): the same ratio of depths per slice.
    Log,
    /// z_i = z_n + (z_f - z_n) i / K.
    Uniform,
    /// The first slice ends at `first`, the others split the rest logarithmically: z_1 =
    /// first, z_i = first (z_f / first)^((i - 1) / (K - 1)) (Bevy's rule: its first bound
    /// defaults to 5 to 10 m).
    FirstThenLog {
        /// Where the first slice ends (clamped inside the view's range).
        first: f64,
    },
    /// The K - 1 view depths between the slices, increasing, between the near plane and the
    /// shadow distance.
    Distances {
        /// How many of `depths` are used (K - 1).
        count: usize,
        /// The depths.
        depths: [f64; MAX_CASCADES - 1],
    },
}

/// The single-map technique that fits each slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CascadeFit {
    /// The focused map.
    Focused,
    /// LiSPSM (Filament's choice inside its cascades).
    Lispsm(Lispsm),
    /// TSM.
    Tsm(Tsm),
    /// XPSM.
    Xpsm(Xpsm),
    /// PSM.
    Psm(Psm),
}

impl CascadeFit {
    /// The names [`CascadeFit::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["focused", "lispsm", "tsm", "xpsm", "psm"];

    /// The technique with default parameters by name.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name.to_ascii_lowercase().as_str() {
            "focused" => Self::Focused,
            "lispsm" => Self::Lispsm(Lispsm::default()),
            "tsm" => Self::Tsm(Tsm::default()),
            "xpsm" => Self::Xpsm(Xpsm::default()),
            "psm" => Self::Psm(Psm::default()),
            _ => return None,
        })
    }

    /// The setup of a slice on its basis.
    fn setup_with(
        &self,
        input: &SetupInput<'_>,
        basis: &FocusBasis,
    ) -> Result<ShadowSetup, SetupError> {
        let warp: &dyn LimitedWarp = match self {
            Self::Focused => {
                input.map.validate()?;
                return Ok(focused_map(input, basis).clone());
            }
            Self::Lispsm(t) => t,
            Self::Tsm(t) => t,
            Self::Xpsm(t) => t,
            Self::Psm(t) => t,
        };
        warp.setup_with(input, basis)
    }

    fn as_dyn(&self) -> &dyn ShadowTechnique {
        match self {
            Self::Focused => &Focused,
            Self::Lispsm(t) => t,
            Self::Tsm(t) => t,
            Self::Xpsm(t) => t,
            Self::Psm(t) => t,
        }
    }

    /// The technique's name.
    pub fn name(&self) -> &'static str {
        self.as_dyn().name()
    }
}

/// How a point picks among the cascades' maps (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CascadeSelect {
    /// Coverage for stable cascades, view depth for the others.
    #[default]
    Auto,
    /// The map of the slice the point's view depth falls in (Bevy, Godot, Unity's split fit).
    ViewDepth,
    /// The first (finest) map whose square holds the point, up to its view depth's slice
    /// (stable cascades only: [`CascadeSlices::covers`]).
    Coverage,
}

/// Cascaded shadow maps: see the module documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cascades {
    /// The number of slices K, 1 to [`MAX_CASCADES`].
    pub count: usize,
    /// How the view is cut.
    pub split: CascadeSplit,
    /// Beyond this view depth nothing is shadowed (`None`: the camera's far plane).
    pub shadow_distance: Option<f64>,
    /// The technique fitting each slice.
    pub fit: CascadeFit,
    /// The blend band between neighbours, as a fraction of the slice (0 to 0.5).
    pub blend: f64,
    /// Stable cascades (directional lights): a texel grid fixed in the world.
    pub stable: bool,
    /// The K maps share the texels of one map of the setup's resolution (each is
    /// resolution / sqrt(K) on a side) instead of each having that resolution.
    pub equal_texels: bool,
    /// How a point picks its map.
    pub select: CascadeSelect,
    /// The number of cascades chosen per view, up to `count`. 1, 2, ... cascades are set up in
    /// turn while each number's maps undersample the frame's view samples less at the median
    /// (each sample on the map it reads) than the number before; the last that did is kept.
    /// With `equal_texels`, slicing the view pays only where it shrinks the maps' footprints
    /// more than their texel counts. Under a grazing sun, or a view along the light, the
    /// slices' maps cover nearly the whole view's area with fewer texels each. It stops at the
    /// first number that does not help, rather than try them all, because most views keep one
    /// or two cascades (the book's Results, "Cascades and flicker", measures the choice). Not
    /// with explicit split distances.
    pub adaptive: bool,
    /// With `adaptive`, the number of cascades the previous frame kept, if any (values above
    /// `count` read as `count`). The search above keeps it unless the number it finds
    /// undersamples the view samples less at the median by more than [`ADAPTIVE_HYSTERESIS`]
    /// (it sets that number up too when the search did not reach it). Otherwise a camera that
    /// moves slowly would switch between two numbers whose medians are close, and every
    /// switch moves every shadow edge (`gnomon flicker`). The
    /// core keeps no state between frames; a frame loop hands back `maps.len()` of the
    /// setup before.
    pub adaptive_previous: Option<usize>,
}

/// How much lower (as a fraction) the median undersampling of the number of cascades that
/// adaptive cascades find must be than the previous frame's number's for the setup to
/// switch to it (see [`Cascades::adaptive_previous`]).
pub const ADAPTIVE_HYSTERESIS: f64 = 0.1;

impl Default for Cascades {
    /// Four LiSPSM cascades, the practical split with lambda 0.5, blend 0.1, not stable.
    fn default() -> Self {
        Self {
            count: 4,
            split: CascadeSplit::Practical { lambda: 0.5 },
            shadow_distance: None,
            fit: CascadeFit::Lispsm(Lispsm::default()),
            blend: 0.1,
            stable: false,
            equal_texels: false,
            select: CascadeSelect::Auto,
            adaptive: false,
            adaptive_previous: None,
        }
    }
}

impl Cascades {
    fn validate(&self, lens: &Lens) -> Result<(), SetupError> {
        let invalid = |name: &'static str, value: f64| SetupError::InvalidParameter { name, value };
        if !(1..=MAX_CASCADES).contains(&self.count) {
            return Err(invalid("cascade count (1 to 8)", self.count as f64));
        }
        if !(0.0..=0.5).contains(&self.blend) {
            return Err(invalid("cascade blend (0 to 0.5)", self.blend));
        }
        if self.select == CascadeSelect::Coverage && !self.stable {
            return Err(SetupError::CoverageNeedsStable);
        }
        if let Some(d) = self.shadow_distance
            && !(d.is_finite() && d > lens.near)
        {
            return Err(invalid("shadow distance (beyond the near plane)", d));
        }
        if self.adaptive_previous == Some(0) {
            return Err(invalid("previous frame's cascade count (at least 1)", 0.0));
        }
        if self.adaptive && matches!(self.split, CascadeSplit::Distances { .. }) {
            return Err(SetupError::InvalidParameter {
                name: "adaptive cascades with split distances (the distances fix the count)",
                value: self.count as f64,
            });
        }
        match self.split {
            CascadeSplit::Practical { lambda } if !(0.0..=1.0).contains(&lambda) => {
                Err(invalid("cascade lambda (0 to 1)", lambda))
            }
            CascadeSplit::FirstThenLog { first } if !(first.is_finite() && first > 0.0) => {
                Err(invalid("cascade first bound", first))
            }
            CascadeSplit::Distances { count, depths } => {
                if count + 1 != self.count {
                    return Err(invalid(
                        "cascade split distances (one fewer than the cascades)",
                        count as f64,
                    ));
                }
                let end = self.shadow_distance.unwrap_or(lens.far).min(lens.far);
                let mut last = lens.near;
                for &d in &depths[..count] {
                    if !(d.is_finite() && d > last && d < end) {
                        return Err(invalid(
                            "cascade split distance (increasing, between the near plane and the shadow distance)",
                            d,
                        ));
                    }
                    last = d;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// The slices' view depths and where the fade begins, for `camera` over `scene`; `None`
    /// when the view frustum does not meet the scene box.
    fn slices(&self, camera: &Camera, view_body: &ConvexPolyhedron) -> Option<CascadeSlices> {
        let lens = camera.lens();
        let k = self.count;
        let distance = self.shadow_distance.unwrap_or(lens.far).min(lens.far);
        let (eye, forward) = (camera.eye(), camera.forward());
        let (p0, p1) = view_body
            .points()
            .iter()
            .map(|p| (*p - eye).dot(forward))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), d| {
                (a.min(d), b.max(d))
            });
        if p0.is_nan() || p1.is_nan() || p0 > p1 {
            return None;
        }
        let mut depths = [0.0; MAX_CASCADES + 1];
        // Stable cascades keep their slices (so their spheres) whatever the view: from the
        // near plane to the shadow distance.
        let (z0, zk) = match self.split {
            _ if self.stable => (lens.near, distance),
            CascadeSplit::Distances { .. } => (lens.near, distance),
            _ => (p0.max(lens.near), p1.min(distance)),
        };
        if zk.is_nan() || zk <= z0 * (1.0 + 1e-9) {
            return None;
        }
        for (i, depth) in depths.iter_mut().enumerate().take(k + 1) {
            let t = i as f64 / k as f64;
            let log = z0 * (zk / z0).powf(t);
            let uniform = z0 + (zk - z0) * t;
            *depth = match self.split {
                CascadeSplit::Practical { lambda } => lambda * log + (1.0 - lambda) * uniform,
                CascadeSplit::Log => log,
                CascadeSplit::Uniform => uniform,
                CascadeSplit::FirstThenLog { first } => {
                    let first = first.clamp(z0 + 1e-6 * (zk - z0), zk - 1e-6 * (zk - z0));
                    if i == 0 {
                        z0
                    } else {
                        first * (zk / first).powf((i - 1) as f64 / (k - 1).max(1) as f64)
                    }
                }
                CascadeSplit::Distances { depths: given, .. } => {
                    if i == 0 {
                        z0
                    } else if i == k {
                        zk
                    } else {
                        given[i - 1]
                    }
                }
            };
        }
        depths[0] = z0;
        depths[k] = zk;
        // The fade only where the shadow distance cuts what the camera sees.
        let fade_start = if distance < p1 {
            (0.9 * distance).max(depths[k - 1])
        } else {
            zk
        };
        Some(CascadeSlices {
            count: k,
            view_depths: depths,
            blend: self.blend,
            fade_start,
            depth_row_world: forward.extend(-forward.dot(eye)),
            by_coverage: false,
        })
    }

    /// [`Cascades::adaptive`]: the setups of 1, 2, ... cascades while each lowers the median
    /// undersampling over the view samples; the last that lowered it is kept, or the
    /// previous frame's number within [`ADAPTIVE_HYSTERESIS`] of it.
    fn adaptive_setup(
        &self,
        input: &SetupInput<'_>,
        frame: &Frame<'_>,
        samples: &ViewSamples,
    ) -> Result<ShadowSetup, SetupError> {
        let setup_of = |count: usize| -> Result<(f64, ShadowSetup), SetupError> {
            let fixed = Cascades {
                count,
                adaptive: false,
                adaptive_previous: None,
                ..*self
            };
            let setup = fixed.setup_on(input, frame)?;
            let median = samples
                .setup_undersampling_quantile(&setup, 0.5)
                .unwrap_or(f64::INFINITY);
            Ok((median, setup))
        };
        let previous = self.adaptive_previous.map(|p| p.min(self.count));
        // The numbers tried, with their medians; the previous frame's setup if it is one.
        let mut kept: Option<(f64, ShadowSetup)> = None;
        let mut found: Option<(f64, ShadowSetup)> = None;
        for count in 1..=self.count {
            let (median, setup) = setup_of(count)?;
            let stops = found.as_ref().is_some_and(|(least, _)| median >= *least);
            if previous == Some(count) {
                kept = Some((median, setup.clone()));
            }
            if stops {
                // Slicing finer stopped paying (see `Cascades::adaptive`).
                break;
            }
            found = Some((median, setup));
        }
        let (median, setup) = found.expect("count is at least 1");
        let kept = match (previous, kept) {
            (Some(p), None) if p != setup.maps.len() => Some(setup_of(p)?),
            (_, kept) => kept,
        };
        match kept {
            Some((kept_median, kept_setup))
                if kept_setup.maps.len() != setup.maps.len()
                    && median >= (1.0 - ADAPTIVE_HYSTERESIS) * kept_median =>
            {
                Ok(kept_setup)
            }
            _ => Ok(setup),
        }
    }
}

impl ShadowTechnique for Cascades {
    fn name(&self) -> &'static str {
        "cascades"
    }

    fn setup(&self, input: &SetupInput<'_>) -> Result<ShadowSetup, SetupError> {
        if let Light::Point(_) = input.light {
            // Several maps per light do not fit a point light's one map per cube face.
            return Err(SetupError::PointLightUnsupported {
                technique: self.name(),
            });
        }
        input.map.validate()?;
        let lens = input.camera.lens();
        self.validate(&lens)?;
        let adaptive = self.adaptive && self.count > 1;
        // Adaptive cascades read the view samples of every count tried: cast once.
        let cast;
        let input = match input.samples {
            None if adaptive => {
                cast = ViewSamples::new(input.camera, input.light, input.scene);
                SetupInput {
                    samples: Some(&cast),
                    ..*input
                }
            }
            _ => *input,
        };
        let adaptive_samples = input.samples.filter(|_| adaptive);
        // The frame's facts (P, the receivers against the view, the casters in light space,
        // the samples) once, for every count tried; each slice refines them.
        // Slices are cameras made from the view matrix; the frame's camera is made the same
        // way, so that their eye and axes (and so the view frustum's side planes and the
        // view-aligned light frame) are the same to the last bit.
        let whole = Camera::from_view_from_world(input.camera.view_from_world(), lens)?;
        let frame = Frame::new(&SetupInput {
            camera: &whole,
            ..input
        });
        if let Some(samples) = adaptive_samples {
            return self.adaptive_setup(&input, &frame, samples);
        }
        self.setup_on(&input, &frame)
    }
}

impl Cascades {
    /// The setup of `self.count` cascades on `frame` (`input`'s, its camera the whole view's
    /// made from the view matrix).
    fn setup_on(
        &self,
        input: &SetupInput<'_>,
        frame: &Frame<'_>,
    ) -> Result<ShadowSetup, SetupError> {
        let lens = input.camera.lens();
        let view_from_world = input.camera.view_from_world();
        let Some(slices) = self.slices(input.camera, &frame.view_body) else {
            // The view does not reach the scene: one map, as the fit gives it.
            let mut setup = self.fit.as_dyn().setup(input)?;
            setup.technique = self.name();
            return Ok(setup);
        };
        let k = slices.count;
        let settings = self.slice_settings(input.map, k)?;
        let stable_sun = match input.light {
            Light::Directional(d) if self.stable => Some(d.direction()),
            _ => None,
        };
        let mut diagnostics = Diagnostics::new(input.camera, input.light, input.scene);
        if self.stable && stable_sun.is_none() {
            diagnostics
                .fallbacks
                .push(Fallback::StableNeedsDirectionalLight);
        }
        // Map i's view depths: it also covers the blend band at the end of slice i - 1.
        let range = |i: usize| {
            let [near, far] = slices.map_view_depths(i);
            (near, far)
        };
        // The fitted slices' receivers are refined from the frame's in one walk
        // (`slice_codes`).
        let fitted_cameras = if stable_sun.is_some() {
            Vec::new()
        } else {
            fitted_slice_cameras(input.camera, &slices)?
        };
        let codes = slice_codes(frame, &fitted_cameras);
        // The slices are independent given the frame: fitted slices in parallel with the
        // `parallel` feature (see `crate::parallel`; a stable slice is too little work to hand
        // to another thread), merged in order.
        let slice = |i: usize| -> Result<_, SetupError> {
            if let Some(direction) = stable_sun {
                let (near, far) = range(i);
                let camera =
                    Camera::from_view_from_world(view_from_world, Lens { near, far, ..lens })?;
                return Ok((stable_map(&camera, direction, input.scene, settings), None));
            }
            let camera = &fitted_cameras[i];
            let slice_input = SetupInput {
                camera,
                map: settings,
                ..*input
            };
            let basis = FocusBasis::new(frame, Part::Slice(camera, &codes[i]));
            let setup = self.fit.setup_with(&slice_input, &basis)?;
            Ok((setup.maps[0], Some(setup.diagnostics)))
        };
        let fitted = if stable_sun.is_some() {
            (0..k).map(slice).collect()
        } else {
            crate::parallel::map_in_order(k, slice)
        };
        let mut maps = Vec::with_capacity(k);
        // Each map's own fallbacks: the setup's so far (stable cascades of a spot light) and
        // its slice's.
        let shared = diagnostics.fallbacks.clone();
        for (i, slice) in fitted.into_iter().enumerate() {
            let (mut map, slice_diagnostics) = slice?;
            let mut own = MapDiagnostics {
                fallbacks: shared.clone(),
                warp_strength: None,
            };
            match slice_diagnostics {
                Some(d) => {
                    own.fallbacks
                        .extend(d.fallbacks.iter().filter(|f| !shared.contains(f)));
                    own.warp_strength = d.warp_strength;
                    merge(&mut diagnostics, &d, i == 0);
                }
                None => diagnostics.light_frame = LightFrameKind::Fixed,
            }
            map.view_depth_range = Some(slices.map_view_depths(i));
            diagnostics.maps.push(own);
            maps.push(map);
        }
        // Stable maps hold every caster over their squares: picked by coverage unless asked
        // otherwise (a spot light's fitted maps, which stable falls back to, by depth).
        let mut slices = slices;
        slices.by_coverage = stable_sun.is_some() && self.select != CascadeSelect::ViewDepth;
        Ok(ShadowSetup {
            technique: self.name(),
            maps,
            selection: MapSelection::Cascades(slices),
            diagnostics,
        })
    }

    /// Each slice's map settings: `map`'s, with `equal_texels` the resolution divided by
    /// sqrt(k) so that k maps hold as many texels as one.
    fn slice_settings(&self, map: MapSettings, k: usize) -> Result<MapSettings, SetupError> {
        let settings = MapSettings {
            resolution: if self.equal_texels {
                ((map.resolution as f64 / (k as f64).sqrt()).floor() as u32).max(MIN_RESOLUTION)
            } else {
                map.resolution
            },
            ..map
        };
        settings.validate()?;
        Ok(settings)
    }
}

/// The cameras of the fitted slices. A fitted map covers its slice and a millionth of the
/// slice's length beyond each end (within the view), so that a point the selection routes to
/// it at a border lands inside. A receiver that only touches a slice's near or far plane is
/// not the slice's (touching counts as outside), yet its points on that plane are read
/// there: a flat ground exactly at a border, as in the light_straight_down property case.
fn fitted_slice_cameras(
    camera: &Camera,
    slices: &CascadeSlices,
) -> Result<Vec<Camera>, SetupError> {
    let (lens, view_from_world) = (camera.lens(), camera.view_from_world());
    (0..slices.count)
        .map(|i| {
            let [near, far] = slices.map_view_depths(i);
            let margin = 1e-6 * (far - near);
            let slice_lens = Lens {
                near: (near - margin).max(lens.near),
                far: (far + margin).min(lens.far),
                ..lens
            };
            Camera::from_view_from_world(view_from_world, slice_lens)
        })
        .collect()
}

/// Adds a slice's diagnostics: its fallbacks (each named once), the largest counts, the
/// weakest warp.
fn merge(into: &mut Diagnostics, slice: &Diagnostics, first: bool) {
    for f in &slice.fallbacks {
        if !into.fallbacks.contains(f) {
            into.fallbacks.push(*f);
        }
    }
    if first {
        into.light_frame = slice.light_frame;
    }
    into.visible_receivers = into.visible_receivers.max(slice.visible_receivers);
    into.relevant_casters = into.relevant_casters.max(slice.relevant_casters);
    into.culled_casters = into.culled_casters.max(slice.culled_casters);
    into.casters_clipped_by_light_near = into
        .casters_clipped_by_light_near
        .max(slice.casters_clipped_by_light_near);
    into.focus_body_vertices = into.focus_body_vertices.max(slice.focus_body_vertices);
    into.warp_strength = match (into.warp_strength, slice.warp_strength) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
}

/// A stable cascade's map: the square around the slice's bounding sphere, in the light's
/// fixed frame, its centre snapped to whole texels (see the module documentation).
fn stable_map(
    slice: &Camera,
    direction: DVec3,
    scene: &crate::bounds::SceneBounds,
    settings: MapSettings,
) -> ShadowMap {
    let lens = slice.lens();
    let tan_y = (0.5 * lens.fov_y_degrees.to_radians()).tan();
    let spread = (tan_y * tan_y * (1.0 + lens.aspect * lens.aspect)).sqrt();
    // The rings of the near and far corners (radii a, b), length l apart along the axis; the
    // sphere through both has its centre x beyond the near plane with a^2 + x^2 =
    // b^2 + (l - x)^2, kept on the slice's axis.
    let (a, b, l) = (lens.near * spread, lens.far * spread, lens.far - lens.near);
    let x = ((b * b - a * a + l * l) / (2.0 * l)).clamp(0.0, l);
    let radius = (a * a + x * x)
        .sqrt()
        .max((b * b + (l - x) * (l - x)).sqrt());
    let centre = slice.eye() + slice.forward() * (lens.near + x);
    let frame = LightFrame::fixed(direction);
    // n texels inside the inset; the sphere's square of 2 r plus two texels of room for the
    // snap: texel t = 2 r / (n - 2), half size h = n t / 2.
    let n = (settings.resolution - 2 * settings.viewport_inset) as f64;
    let texel = 2.0 * radius / (n - 2.0);
    let half = 0.5 * n * texel;
    let snap = |v: f64| (v / texel).round() * texel;
    let (cx, cy) = (snap(frame.right.dot(centre)), snap(frame.up.dot(centre)));
    // Depth: the scene box along the light, so that no caster is left out.
    let (z0, z1) = scene
        .scene_box()
        .corners()
        .iter()
        .map(|c| frame.forward.dot(*c))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
            (lo.min(z), hi.max(z))
        });
    let margin = 1e-6 * (z1 - z0);
    let (z0, z1) = (z0 - margin, z1 + margin);
    let s = settings.inset_ndc();
    let depth = (frame.forward / (z1 - z0)).extend(-z0 / (z1 - z0));
    let rows = [
        (frame.right * (s / half)).extend(-cx * s / half),
        (frame.up * (s / half)).extend(-cy * s / half),
        depth,
        DVec4::W,
    ];
    ShadowMap {
        clip_from_world: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
        depth_from_world: depth,
        resolution: settings.resolution,
        viewport_inset: settings.viewport_inset,
        projection: MapProjection::Orthographic,
        view_depth_range: None,
    }
}
