//! The system that replaces Bevy's cascades with gnomon's fits, one setup per light and
//! camera.

use std::time::Instant;

use bevy_camera::{Camera as BevyCamera, PerspectiveProjection, Projection};
use bevy_ecs::prelude::*;
use bevy_light::cascade::{Cascade, CascadeShadowConfig, Cascades as BevyCascades};
use bevy_light::{DirectionalLight as BevyDirectionalLight, DirectionalLightShadowMap};
use bevy_transform::components::GlobalTransform;
use gnomon::{
    CascadeSplit, Cascades, Lens, Light, MAX_CASCADES, MapSelection, MapSettings, SceneBounds,
    ShadowSetup, ShadowTechnique, Technique, compute_setup,
};

use crate::convert::{cascade, from_bevy, read_point};
use crate::scene::GnomonScene;
use crate::settings::{DepthClipControl, Drawable, GnomonShadows, GnomonShadowsStatus};

/// One camera as the fit needs it.
struct View {
    entity: Entity,
    camera: gnomon::Camera,
}

/// What one light's setups give Bevy for one camera.
struct Fitted {
    cascades: Vec<Cascade>,
    /// The view depth where each map stops being read (Bevy's bounds).
    bounds: Vec<f32>,
    /// Bevy's blend band, as a fraction of each bound.
    overlap: f32,
    fallbacks: Vec<&'static str>,
}

/// The lights that gnomon fits.
type FittedLights<'w, 's> = Query<
    'w,
    's,
    (
        &'static GlobalTransform,
        &'static BevyDirectionalLight,
        &'static GnomonShadows,
        &'static mut CascadeShadowConfig,
        &'static mut BevyCascades,
        &'static mut GnomonShadowsStatus,
    ),
>;

/// Writes each [`GnomonShadows`] light's `Cascades` and cascade bounds from gnomon's setup
/// (runs after Bevy has built its own, which stay where a fit fails).
pub fn fit_cascades(
    scene: Res<GnomonScene>,
    device: Res<DepthClipControl>,
    shadow_map: Res<DirectionalLightShadowMap>,
    cameras: Query<(Entity, &GlobalTransform, &Projection, &BevyCamera)>,
    mut lights: FittedLights,
) {
    let mut ordered: Vec<_> = cameras.iter().filter(|c| c.3.is_active).collect();
    ordered.sort_by_key(|c| (c.3.order, c.0));
    for (transform, light, settings, mut config, mut cascades, mut status) in &mut lights {
        if !light.shadow_maps_enabled {
            continue;
        }
        let started = Instant::now();
        let outcome = fit_light(
            &scene,
            *device,
            shadow_map.size,
            transform,
            settings,
            &ordered,
            &mut cascades,
        );
        let report = match outcome {
            Ok((bounds, overlap, fallbacks, maps)) => {
                if config.bounds != bounds || config.overlap_proportion != overlap {
                    config.bounds = bounds;
                    config.overlap_proportion = overlap;
                }
                GnomonShadowsStatus {
                    error: None,
                    fallbacks,
                    setup_seconds: started.elapsed().as_secs_f64(),
                    maps,
                }
            }
            Err(error) => GnomonShadowsStatus {
                error: Some(error),
                ..Default::default()
            },
        };
        status.set_if_neq(report);
    }
}

/// Bounds, overlap, fallbacks and map count of one light's fits over every camera.
type LightFit = (Vec<f32>, f32, Vec<&'static str>, usize);

type CameraRow<'a> = (Entity, &'a GlobalTransform, &'a Projection, &'a BevyCamera);

/// Fits one light for every active camera: the first camera (lowest order) by the
/// technique, the others on its slices, since Bevy keeps one list of bounds per light.
fn fit_light(
    scene: &GnomonScene,
    device: DepthClipControl,
    resolution: usize,
    transform: &GlobalTransform,
    settings: &GnomonShadows,
    cameras: &[CameraRow<'_>],
    cascades: &mut BevyCascades,
) -> Result<LightFit, String> {
    Drawable::check_on(&settings.technique, device).map_err(|e| e.to_string())?;
    let bounds = scene
        .bounds
        .as_ref()
        .ok_or("no mesh casts or receives shadows")?;
    let direction = from_bevy(transform.forward().into());
    let light = gnomon::DirectionalLight::new(direction)
        .map(Light::Directional)
        .map_err(|e| e.to_string())?;
    let map = MapSettings::with_resolution(resolution as u32);
    let views = cameras
        .iter()
        .map(|&(entity, t, projection, _)| {
            view(entity, t, projection, settings.shadow_distance)
                .map(|camera| View { entity, camera })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let Some((first, others)) = views.split_first() else {
        return Err("no active camera".into());
    };
    let technique = Drawable::for_bevy(&settings.technique);
    let lead = fit_view(&technique, first, &light, bounds, map, transform)?;
    let on_slices = on_bounds(&technique, &lead.bounds);
    let others = others
        .iter()
        .map(|v| fit_view(&on_slices, v, &light, bounds, map, transform).map(|f| (v.entity, f)))
        .collect::<Result<Vec<_>, _>>()?;
    let (bounds, overlap, maps) = (lead.bounds, lead.overlap, lead.cascades.len());
    let mut fallbacks = lead.fallbacks;
    cascades.cascades.insert(first.entity, lead.cascades);
    for (entity, fitted) in others {
        fallbacks.extend(fitted.fallbacks);
        cascades.cascades.insert(entity, fitted.cascades);
    }
    Ok((bounds, overlap, fallbacks, maps))
}

/// gnomon's camera for a Bevy camera, its far plane at the shadow distance.
fn view(
    entity: Entity,
    transform: &GlobalTransform,
    projection: &Projection,
    shadow_distance: f32,
) -> Result<gnomon::Camera, String> {
    let Projection::Perspective(PerspectiveProjection {
        fov,
        aspect_ratio,
        near,
        far,
        ..
    }) = projection
    else {
        return Err(format!(
            "camera {entity} is not perspective: gnomon fits perspective cameras"
        ));
    };
    let lens = Lens {
        fov_y_degrees: f64::from(*fov).to_degrees(),
        aspect: f64::from(*aspect_ratio),
        near: f64::from(*near),
        far: f64::from(far.min(shadow_distance)),
    };
    let eye = from_bevy(transform.translation());
    let forward = from_bevy(transform.forward().into());
    let up = from_bevy(transform.up().into());
    gnomon::Camera::look_at(eye, eye + forward, up, lens)
        .map_err(|e| format!("camera {entity}: {e}"))
}

/// The same technique with its slices ending at `bounds` (so that a second camera's maps
/// are read where Bevy's one list of bounds says).
fn on_bounds(technique: &Technique, bounds: &[f32]) -> Technique {
    let Technique::Cascades(c) = technique else {
        return *technique;
    };
    let mut depths = [0.0; MAX_CASCADES - 1];
    let inner = &bounds[..bounds.len() - 1];
    for (d, b) in depths.iter_mut().zip(inner) {
        *d = f64::from(*b);
    }
    Technique::Cascades(Cascades {
        count: bounds.len(),
        split: CascadeSplit::Distances {
            count: inner.len(),
            depths,
        },
        shadow_distance: bounds.last().map(|&b| f64::from(b)),
        ..*c
    })
}

/// One camera's setup, as Bevy's cascades.
fn fit_view(
    technique: &Technique,
    view: &View,
    light: &Light,
    scene: &SceneBounds,
    map: MapSettings,
    light_transform: &GlobalTransform,
) -> Result<Fitted, String> {
    let setup = compute_setup(technique, &view.camera, light, scene, map)
        .map_err(|e| format!("{}: {e}", technique.name()))?;
    let depths = read_depths(&setup, &view.camera);
    let rotation = light_transform.rotation();
    let cascades = setup
        .maps
        .iter()
        .zip(&depths)
        .map(|(m, d)| cascade(m, rotation, read_point(&view.camera, *d)))
        .collect();
    Ok(Fitted {
        cascades,
        bounds: depths.iter().map(|d| d[1] as f32).collect(),
        overlap: overlap(&depths),
        fallbacks: setup
            .diagnostics
            .fallbacks
            .iter()
            .map(|f| f.name())
            .collect(),
    })
}

/// The view depths each map is read over: its slice with the blend band before it, or the
/// whole lens for a single map.
fn read_depths(setup: &ShadowSetup, camera: &gnomon::Camera) -> Vec<[f64; 2]> {
    let lens = camera.lens();
    match &setup.selection {
        MapSelection::Cascades(_) => setup
            .maps
            .iter()
            .map(|m| m.view_depth_range.unwrap_or([lens.near, lens.far]))
            .collect(),
        _ => vec![[lens.near, lens.far]; setup.maps.len()],
    }
}

/// Bevy blends cascade i into i + 1 over [(1 - overlap) far_i, far_i]: the largest overlap
/// whose band starts where map i + 1 already covers, for every i (a hair less, so that
/// rounding to f32 does not start the band before the map).
fn overlap(depths: &[[f64; 2]]) -> f32 {
    if depths.len() < 2 {
        return 0.0;
    }
    let largest = depths
        .windows(2)
        .map(|w| 1.0 - w[1][0] / w[0][1])
        .fold(f64::INFINITY, f64::min)
        .clamp(0.0, 1.0);
    (largest * (1.0 - 1e-5)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_starts_where_the_next_map_begins() {
        let depths = [[1.0, 10.0], [9.0, 40.0], [37.0, 100.0]];
        let o = f64::from(overlap(&depths));
        // 1 - 9/10 = 0.1 and 1 - 37/40 = 0.075: the smaller, so both bands are covered.
        assert!((o - 0.075).abs() < 1e-5, "{o}");
        for w in depths.windows(2) {
            assert!((1.0 - o) * w[0][1] >= w[1][0] - 1e-9);
        }
        assert_eq!(overlap(&[[1.0, 50.0]]), 0.0);
    }
}
