//! Independent parts of one setup (a cascade's fitted slices) on several threads.
//!
//! With the opt-in `parallel` feature the parts run on rayon's global thread pool; without
//! it (the default), in turn on the calling thread. Each part reads the frame's shared facts
//! ([`crate::frame::Frame`], whose lazily made parts are `OnceLock`s) and makes its own
//! basis, so the results do not depend on the threads: they are the same to the bit either
//! way, and come back in the parts' order.
//!
//! When it pays: setups run back to back, where the slices keep both cores busy. In a frame
//! loop the pool's threads go to sleep between frames, and waking them costs about what the
//! second core saves; a cube face's or a stable slice's work is less than a wake-up. So the
//! feature is off by default: an engine that sets up several lights back to back, or whose
//! threads wake cheaply, turns it on (the measurements are in CHANGELOG.md).

/// `f(0), f(1), ... f(count - 1)`, in that order, computed in parallel where the feature is
/// on.
pub(crate) fn map_in_order<T, F>(count: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        // The even parts, then the odd ones: rayon splits the list in halves, one per
        // thread, and neighbouring parts (a cascade's slices) tend to cost alike, so each
        // half gets its share of the near and of the far ones. One part per job, so that a
        // thread that runs out of work takes the other's next part.
        let order: Vec<usize> = (0..count).step_by(2).chain((1..count).step_by(2)).collect();
        let mut done: Vec<(usize, T)> = order
            .into_par_iter()
            .with_max_len(1)
            .map(|i| (i, f(i)))
            .collect();
        done.sort_unstable_by_key(|(i, _)| *i);
        done.into_iter().map(|(_, t)| t).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..count).map(f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_order() {
        let out = map_in_order(50, |i| i * i);
        assert_eq!(out, (0..50).map(|i| i * i).collect::<Vec<_>>());
    }

    /// Eight cascades over a city of 900 boxes from many views and suns, and LiSPSM on the
    /// cube faces of a lamp among the buildings, are the same to the bit on one thread as on
    /// rayon's pool: the slices share nothing they write.
    #[cfg(feature = "parallel")]
    #[test]
    fn cascades_do_not_depend_on_the_threads() {
        use glam::DVec3;

        use crate::{
            Aabb, Camera, Cascades, DirectionalLight, Lens, Light, Lispsm, MapSettings, PointLight,
            SceneBounds, ShadowTechnique, compute_setup,
        };

        let mut boxes = Vec::new();
        for k in 0..900 {
            let (i, j) = ((k % 30) as f64, (k / 30) as f64);
            let min = DVec3::new(-90.0 + 6.0 * i, 0.0, -90.0 + 6.0 * j);
            let h = 1.0 + ((k * 7919) % 23) as f64;
            boxes.push(Aabb::new(min, min + DVec3::new(4.0, h, 4.0)).unwrap());
        }
        let mut receivers = boxes.clone();
        receivers
            .push(Aabb::new(DVec3::new(-95.0, -1.0, -95.0), DVec3::new(95.0, 0.0, 95.0)).unwrap());
        let scene = SceneBounds::new(boxes, receivers, None).unwrap();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let many = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let technique = Cascades {
            count: 8,
            ..Cascades::default()
        };
        for view in 0..12 {
            let a = view as f64 * 0.52;
            let eye = DVec3::new(80.0 * a.cos(), 5.0 + 4.0 * view as f64, 80.0 * a.sin());
            let camera =
                Camera::look_at(eye, DVec3::new(0.0, 0.0, 0.0), DVec3::Y, Lens::default()).unwrap();
            let sun = DVec3::new((a * 3.0).sin(), -0.3 - 0.05 * view as f64, (a * 2.0).cos());
            let sun = Light::Directional(DirectionalLight::new(sun).unwrap());
            let lamp = DVec3::new(30.0 * (a * 5.0).sin(), 3.0 + view as f64, 30.0 * a.cos());
            let lamp = Light::Point(PointLight::new(lamp, 150.0).unwrap());
            let cases: [(&(dyn ShadowTechnique + Sync), &Light); 2] =
                [(&technique, &sun), (&Lispsm::default(), &lamp)];
            for (technique, light) in cases {
                let setup = || {
                    compute_setup(technique, &camera, light, &scene, MapSettings::default())
                        .unwrap()
                };
                let (serial, parallel) = (one.install(setup), many.install(setup));
                let name = technique.name();
                assert_eq!(serial.maps, parallel.maps, "{name}, view {view}");
                assert_eq!(serial.selection, parallel.selection, "{name}, view {view}");
                assert_eq!(serial.diagnostics.fallbacks, parallel.diagnostics.fallbacks);
                assert_eq!(
                    serial.diagnostics.warp_strength,
                    parallel.diagnostics.warp_strength
                );
            }
        }
    }
}
