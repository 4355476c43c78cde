//! What a frame is drawn with: [`RenderSettings`] (size, filter, bias, what the main pass
//! reads) and [`SceneTarget`] (the caller's target for `encode_scene`).

/// How the main pass filters shadow-map lookups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// One tap: a texel is in or out.
    None,
    /// The hardware's 2x2 bilinear comparison.
    #[default]
    Hardware2x2,
    /// 5x5 taps, averaged (percentage closer filtering).
    Pcf5x5,
    /// Percentage-closer soft shadows (Fernando 2005) of area lights of
    /// [`RenderSettings::area_light_radius`]: a blocker search, the penumbra's width from the
    /// blockers' distance, a filter that wide (discs across the light's rays, carried into
    /// each map by its local Jacobian: right on warped maps and cascades too).
    Pcss,
}

/// Depth bias against shadow acne.
///
/// The world-unit parts default to 2 cm and 1 m, scaled down with the scene in scenes smaller
/// than [`DepthBias::FULL_SIZE_DIAGONAL`] across (the diagonal of the scene's box when the
/// renderer was made), so that a tabletop, or a scene modelled in millimetres, is not lit
/// through its shadows: a 2 cm bias lit most of a random scene scaled to a fifth of a metre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthBias {
    /// Constant bias in world units along the light (`None`: [`DepthBias::CONSTANT_WORLD`],
    /// scaled in small scenes).
    pub constant_world: Option<f64>,
    /// Slope-scaled bias: this many texels' worth of the surface's depth slope.
    pub slope_texels: f64,
    /// Upper limit of the slope-scaled bias, in world units (`None`:
    /// [`DepthBias::MAX_SLOPE_WORLD`], scaled in small scenes); where a map's texels are
    /// wider than `max_slope_world / max_slope_texels`, the cap is `max_slope_texels` texel
    /// widths instead.
    pub max_slope_world: Option<f64>,
    /// The slope bias's cap in texel widths (the texel measured across the light where the
    /// depth pass draws), when that exceeds `max_slope_world`: a cap in metres alone held the
    /// slope term to a fraction of a texel in a scene kilometres across (the suite's terrain,
    /// at 2 to 10 m a texel, was speckled with acne over its slopes).
    pub max_slope_texels: f64,
    /// Normal offset: the lookup moves this many texels along the geometric normal (scaled
    /// by 1 - N.L, so surfaces facing the light move little). A texel is measured along the
    /// normal's image in the map (the step that moves the lookup one texel), at most the
    /// texel's largest world side: a receding surface changes depth across a texel along that
    /// image, so that step clears it, and the lookup does not run several texels along a fine
    /// axis past the focus region's edge.
    pub normal_offset_texels: f64,
}

impl DepthBias {
    /// The default constant bias in a scene at least [`DepthBias::FULL_SIZE_DIAGONAL`] across.
    pub const CONSTANT_WORLD: f64 = 0.02;
    /// The default cap of the slope bias in such a scene.
    pub const MAX_SLOPE_WORLD: f64 = 1.0;
    /// The default cap of the slope bias in texel widths, where that is larger: maps whose
    /// texels are under a third of [`DepthBias::MAX_SLOPE_WORLD`] keep the metre cap.
    pub const MAX_SLOPE_TEXELS: f64 = 3.0;
    /// Scenes whose box's diagonal is shorter than this have the defaults scaled by their
    /// diagonal over it.
    pub const FULL_SIZE_DIAGONAL: f64 = 10.0;

    /// The constant bias and the slope bias's cap in world units, for a scene of `diagonal`.
    pub fn world(&self, diagonal: f64) -> (f64, f64) {
        let scale = (diagonal / Self::FULL_SIZE_DIAGONAL).clamp(f64::MIN_POSITIVE, 1.0);
        (
            self.constant_world.unwrap_or(Self::CONSTANT_WORLD * scale),
            self.max_slope_world
                .unwrap_or(Self::MAX_SLOPE_WORLD * scale),
        )
    }
}

impl Default for DepthBias {
    /// 2 cm constant, 2 texels of slope (at most 1 m or 3 texel widths, whichever is
    /// larger), a 1-texel normal offset; the world parts scaled down in scenes under 10 m
    /// across.
    fn default() -> Self {
        Self {
            constant_world: None,
            slope_texels: 2.0,
            max_slope_world: None,
            max_slope_texels: Self::MAX_SLOPE_TEXELS,
            normal_offset_texels: 1.0,
        }
    }
}

/// What to render and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels (headless frames).
    pub width: u32,
    /// Image height in pixels (headless frames).
    pub height: u32,
    /// Shadow-map filtering.
    pub filter: Filter,
    /// Depth bias.
    pub bias: DepthBias,
    /// Ambient light, 0 to 1.
    pub ambient: f64,
    /// Also return the shadow maps as the light sees them, with the view frustum drawn over
    /// them (headless frames).
    pub light_view: bool,
    /// The largest side of each map's light-view picture in texels (at most the map's own
    /// resolution and 2048): a gallery's thumbnails need far fewer than a 2048 map has.
    pub light_view_size: u32,
    /// Also return the per-pixel sampling metrics ([`crate::Frame::metrics`]; headless).
    pub metrics: bool,
    /// Two-map setups: tint each pixel by the map it reads (red: the second, perspective
    /// map; blue: the first, focused map), as in the SPPSM paper's figures.
    pub tint: bool,
    /// How the main pass reads the shadow maps: by depth (every shadow-map technique), or as
    /// another of the shadows lecture's light-space maps.
    pub read: MapRead,
    /// The radius of every light's area for [`Filter::Pcss`]: a directional light's angular
    /// radius in degrees (the sun's is 0.27), a spot or point light's in world units (a disc
    /// facing the receiver); 0 gives hard shadows.
    pub area_light_radius: f64,
}

/// How the main pass reads a frame's shadow maps (the same matrices, another test).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MapRead {
    /// The depth comparison of a shadow map (Williams): shadowed where a caster is nearer
    /// the light than the point.
    #[default]
    Depth,
    /// Projective texture shadows (the shadows lecture's light maps): each map read as a
    /// texture of where casters are, whatever their depth (a receiver in front of a caster
    /// gets its shadow too), and the casters drawn fully lit (they shadow neither themselves
    /// nor each other).
    Coverage,
    /// Object-ID shadow maps (the lecture's "Object ID Shadows"): beside each map's depth,
    /// the ID of the object nearest the light per texel (every instance is an object); a
    /// point is shadowed where it finds another object's ID, with no bias, and an object
    /// never shadows itself (a concave one should be split into convex parts). IDs alias
    /// where objects meet as the light sees them: a point near its object's outline can read
    /// the texel of the object beside it.
    ObjectId,
    /// IDs and depth (the lecture's "Combining Shadow and Object Maps"): another object's ID
    /// shadows, and where the texel holds the point's own object its depth decides, so that
    /// objects shadow themselves too.
    IdDepth,
}

impl MapRead {
    /// Whether the depth passes write object IDs for it.
    pub fn reads_ids(self) -> bool {
        matches!(self, MapRead::ObjectId | MapRead::IdDepth)
    }

    /// `GNOMON_READ_*` of lookup.wgsl (projective shadows read by depth: their records make
    /// every caster nearer than every point).
    pub(crate) fn code(self) -> u32 {
        match self {
            MapRead::Depth | MapRead::Coverage => 0,
            MapRead::ObjectId => 1,
            MapRead::IdDepth => 2,
        }
    }
}

/// The constant depth bias of a projective map's depth pass, in depth units: every caster
/// (at depth 1/2 there) lands at depth 0, so a covered texel shadows any point (read at 1/2)
/// and an empty one (1) none.
pub(crate) const PROJECTIVE_DEPTH_BIAS: f64 = -4.0;

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            filter: Filter::default(),
            bias: DepthBias::default(),
            ambient: 0.25,
            light_view: false,
            light_view_size: 2048,
            metrics: false,
            tint: false,
            read: MapRead::Depth,
            area_light_radius: 0.0,
        }
    }
}

/// A caller's colour target for [`crate::Renderer::encode_scene`].
#[derive(Debug, Clone, Copy)]
pub struct SceneTarget<'a> {
    /// The view drawn into (multisampled when `sample_count` > 1).
    pub view: &'a wgpu::TextureView,
    /// Its format (any renderable colour format; surfaces are often Bgra8).
    pub format: wgpu::TextureFormat,
    /// Its size in pixels.
    pub width: u32,
    /// Its size in pixels.
    pub height: u32,
    /// Its sample count.
    pub sample_count: u32,
    /// Where a multisampled target resolves to.
    pub resolve_target: Option<&'a wgpu::TextureView>,
    /// The colour to clear to first (`None`: keep what is there).
    pub clear: Option<wgpu::Color>,
}
