//! What a light asks of the plugin, what the plugin reports back, and which of gnomon's
//! techniques Bevy's directional-light shader can draw.

use std::fmt;

use bevy_ecs::prelude::*;
use bevy_light::cascade::CascadeShadowConfig;
use gnomon::{CascadeFit, CascadeSelect, Cascades, ShadowTechnique, Technique};

/// Put on a `DirectionalLight` entity: gnomon fits its shadow maps instead of Bevy.
///
/// The plugin writes the light's `Cascades` and the bounds and overlap of its
/// `CascadeShadowConfig` every frame; Bevy's own cascades stay in place on a frame where
/// the fit fails ([`GnomonShadowsStatus::error`] says why).
#[derive(Component, Clone, Debug, PartialEq)]
#[require(GnomonShadowsStatus)]
pub struct GnomonShadows {
    /// The technique: cascades fitted by focused, LiSPSM or XPSM maps (stable or not), or
    /// one uniform, focused, LiSPSM or XPSM map. Others are refused (see [`Drawable`]).
    pub technique: Technique,
    /// Beyond this view depth nothing is shadowed: the camera's far plane for the fit and
    /// Bevy's last cascade bound. Defaults to Bevy's `maximum_distance` (150).
    pub shadow_distance: f32,
}

impl Default for GnomonShadows {
    /// Four LiSPSM cascades (gnomon's default cascades), picked by view depth as Bevy picks.
    fn default() -> Self {
        Self {
            technique: Technique::Cascades(Cascades {
                select: CascadeSelect::ViewDepth,
                ..Cascades::default()
            }),
            shadow_distance: 150.0,
        }
    }
}

/// What the plugin did for a light on the last frame.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct GnomonShadowsStatus {
    /// Why gnomon's fit was not used (Bevy's cascades were kept), if it was not.
    pub error: Option<String>,
    /// The fallbacks gnomon's setup named, per camera, in the order of the cameras.
    pub fallbacks: Vec<&'static str>,
    /// Seconds the setups took, all cameras together.
    pub setup_seconds: f64,
    /// The number of maps Bevy draws per camera.
    pub maps: usize,
}

/// A technique Bevy's shader cannot draw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotDrawable {
    /// The technique's name.
    pub technique: String,
    /// Why Bevy cannot draw it.
    pub why: &'static str,
}

impl fmt::Display for NotDrawable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Bevy cannot draw {}: {}", self.technique, self.why)
    }
}

impl std::error::Error for NotDrawable {}

/// The techniques whose maps Bevy's directional-light shader draws as gnomon means them.
///
/// Bevy compares depth as the map's clip z over w and picks a map by view depth alone.
/// TSM and PSM keep clip z constant and carry depth in a separate row (gnomon's renderer
/// writes it as the fragment depth), SPPSM picks a map by a world plane, and point-light
/// techniques are not directional: those are refused.
pub struct Drawable;

impl Drawable {
    /// `Ok` for a technique Bevy draws, the reason otherwise.
    pub fn check(technique: &Technique) -> Result<(), NotDrawable> {
        let refuse = |why| {
            Err(NotDrawable {
                technique: technique.name().to_string(),
                why,
            })
        };
        const DEPTH_ROW: &str = "its clip z is constant and Bevy's shader compares clip z";
        match technique {
            Technique::Uniform(_)
            | Technique::Focused(_)
            | Technique::Lispsm(_)
            | Technique::Xpsm(_) => Ok(()),
            Technique::Tsm(_) | Technique::Psm(_) => refuse(DEPTH_ROW),
            Technique::Sppsm(_) => {
                refuse("its second map is picked by a world plane, Bevy picks by view depth")
            }
            Technique::Cube(_) | Technique::Paraboloid(_) => {
                refuse("it is a point light's technique, and the plugin fits directional lights")
            }
            Technique::Cascades(c) => match c.fit {
                CascadeFit::Tsm(_) | CascadeFit::Psm(_) => refuse(DEPTH_ROW),
                _ if c.select == CascadeSelect::Coverage => {
                    refuse("picking cascades by coverage needs a shader Bevy does not have")
                }
                _ if c.count > MAX_BEVY_CASCADES => {
                    refuse("Bevy draws at most 4 cascades per light")
                }
                _ if c.adaptive => refuse(
                    "adaptive cascades change their number per frame and Bevy's is fixed by its configuration",
                ),
                _ => Ok(()),
            },
        }
    }

    /// As [`Drawable::check`], on a device that clips depth as asked or not: without
    /// `DEPTH_CLIP_CONTROL`, Bevy's shadow pass clamps clip z before the divide by w, which
    /// is right only for orthographic maps, so warped fits are refused there.
    pub fn check_on(technique: &Technique, device: DepthClipControl) -> Result<(), NotDrawable> {
        Self::check(technique)?;
        let warped = match technique {
            Technique::Lispsm(_) | Technique::Xpsm(_) => true,
            Technique::Cascades(c) => {
                !c.stable && matches!(c.fit, CascadeFit::Lispsm(_) | CascadeFit::Xpsm(_))
            }
            _ => false,
        };
        if warped && !device.0 {
            return Err(NotDrawable {
                technique: technique.name().to_string(),
                why: "its maps are warped and this device lacks DEPTH_CLIP_CONTROL (use focused cascades)",
            });
        }
        Ok(())
    }

    /// The technique as Bevy can read it: stable cascades picked by view depth (gnomon's
    /// default for them is coverage, which Bevy's shader cannot do).
    pub(crate) fn for_bevy(technique: &Technique) -> Technique {
        match technique {
            Technique::Cascades(c) if c.select == CascadeSelect::Auto => {
                Technique::Cascades(Cascades {
                    select: CascadeSelect::ViewDepth,
                    ..*c
                })
            }
            t => *t,
        }
    }
}

/// Whether the render device has `DEPTH_CLIP_CONTROL`, which Bevy's directional shadow pass
/// needs to draw warped maps right. The plugin cannot see the device (it does not depend on
/// the renderer), so an app on a device without it says so:
/// `app.insert_resource(DepthClipControl(render_device.features().contains(...)))`.
/// Defaults to `true` (Vulkan, Metal and DX12 drivers have it).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthClipControl(pub bool);

impl Default for DepthClipControl {
    fn default() -> Self {
        Self(true)
    }
}

/// Bevy's `MAX_CASCADES_PER_LIGHT`.
pub const MAX_BEVY_CASCADES: usize = 4;

/// The light's own `CascadeShadowConfig` from before [`GnomonShadows`] came, given back
/// when it goes, so that Bevy's cascades come back as they were.
#[derive(Component, Clone, Debug)]
pub struct BevyCascadeConfig(pub CascadeShadowConfig);

/// Saves a light's cascade configuration when [`GnomonShadows`] is added and restores it
/// when it is removed (before Bevy builds its cascades, so that no frame draws Bevy's
/// cascades on gnomon's bounds).
pub fn keep_bevy_config(
    mut commands: Commands,
    added: Query<(Entity, &CascadeShadowConfig), Added<GnomonShadows>>,
    mut removed: RemovedComponents<GnomonShadows>,
    mut saved: Query<(&BevyCascadeConfig, &mut CascadeShadowConfig), Without<GnomonShadows>>,
) {
    for (entity, config) in &added {
        commands
            .entity(entity)
            .insert(BevyCascadeConfig(config.clone()));
    }
    for entity in removed.read() {
        if let Ok((own, mut config)) = saved.get_mut(entity) {
            *config = own.0.clone();
            commands.entity(entity).remove::<BevyCascadeConfig>();
        }
    }
}
