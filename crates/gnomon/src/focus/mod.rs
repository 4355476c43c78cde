//! Focusing: what the camera sees of the receivers, which casters can shadow it, and the unit
//! cube clipping rule that turns both into a map's extents.
//!
//! The rule (unit cube clipping blog post): in the light's clip space,
//! - XY = the intersection of the casters' and the receivers' extents: a receiver point
//!   outside the casters' extents can not be in shadow, a caster point outside the
//!   receivers' extents shadows nothing visible; points outside read the map's cleared
//!   border and come out lit;
//! - near = the casters' minimum depth: nothing that casts a shadow is clipped, and a
//!   receiver nearer than every caster compares below 0 and comes out lit;
//! - far = the receivers' maximum depth: every visible receiver compares inside [0, 1].

mod casters;
mod classify;
mod clip;
mod cuts;
mod visible;

pub(crate) use casters::{
    FaceImages, MapImages, NearTip, WalkedCasters, caster_extents, walk_casters,
};
pub(crate) use classify::{BoxSide, classify_box, refine, refine_slices};
pub(crate) use clip::{clipped_rectangle, unit_cube_clip};
pub(crate) use cuts::{FaceFrustum, LightCorners, ParallelBoxes, box_cut_vertices};
pub(crate) use visible::{Both, ReceiverMap, ReuseCuts, VisibleScene, box_planes};

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::{casters::*, classify::*, cuts::*};

    use glam::DVec3;

    use crate::bounds::SceneBounds;
    use crate::boxes::Aabb;
    use crate::bvh::{all_planes, straddled};
    use crate::geometry::{ConvexPolyhedron, Plane};

    use crate::light_space::{AxisFrustum, Extents, LightFrame, Projector};

    fn unit(v: [f64; 3]) -> DVec3 {
        let v = DVec3::from_array(v);
        if v.length() < 1e-3 {
            DVec3::X
        } else {
            v.normalize()
        }
    }

    /// The extents of the casters, caster by caster, as `caster_extents` defines them.
    fn casters_one_by_one(
        scene: &SceneBounds,
        projector: &Projector,
        receivers: &Extents,
        cut_planes: &[Plane],
        tolerance: f64,
    ) -> (Extents, usize) {
        let xy_slack = 1e-9 * (receivers.max - receivers.min).truncate().max_element();
        let over = Extents {
            min: (receivers.min.truncate() - xy_slack).extend(f64::NEG_INFINITY),
            max: (receivers.max.truncate() + xy_slack).extend(receivers.max.z),
        };
        let mut ext = Extents::EMPTY;
        let mut relevant = 0;
        for caster in scene.casters() {
            let mut points = Vec::new();
            match classify_box(caster, cut_planes, tolerance) {
                BoxSide::Outside => continue,
                BoxSide::Inside => points.extend(caster.corners()),
                BoxSide::Straddles(mask) => {
                    if !box_cut_vertices(caster, cut_planes, mask, tolerance, &mut points) {
                        continue;
                    }
                }
            }
            let mut e = Extents::EMPTY;
            for p in &points {
                e.add(projector.project(*p));
            }
            if receivers.xy_overlaps(&e, xy_slack) && e.min.z <= receivers.max.z {
                relevant += 1;
                ext = ext.union(&e.clamped_to(&over));
            }
        }
        (ext, relevant)
    }

    fn close(a: &Extents, b: &Extents, eps: f64) -> bool {
        let same = |x: f64, y: f64| x == y || (x - y).abs() <= eps;
        (0..3).all(|k| same(a.min[k], b.min[k]) && same(a.max[k], b.max[k]))
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

        /// Walking the scene's hierarchies gives what a pass over every box gives: the same
        /// visible receivers, the same receiver extents, the same caster extents, and a
        /// count of casters that holds every relevant one, for directional and spot lights,
        /// with and without a cutting side plane.
        #[test]
        fn hierarchy_walks_match_every_box(
            boxes in prop::collection::vec((prop::array::uniform3(-60.0f64..60.0), prop::array::uniform3(0.2f64..12.0), 0u8..3), 1..300),
            eye in prop::array::uniform3(-80.0f64..80.0),
            target in prop::array::uniform3(-30.0f64..30.0),
            light in prop::array::uniform3(-1.0f64..1.0),
            spot in any::<bool>(),
            side in prop::option::of(prop::array::uniform3(-1.0f64..1.0)),
        ) {
            use crate::bvh::test_scenes;
            use crate::frame::Frame;
            use crate::light::{DirectionalLight, Light, SpotLight};
            use crate::map::MapSettings;
            use crate::technique::SetupInput;
            use crate::techniques::basis::{FocusBasis, Part};
            let scene = test_scenes::mixed(&boxes);
            let camera = test_scenes::camera(eye, target);
            prop_assume!(camera.is_some());
            let camera = camera.unwrap();
            let target = DVec3::from_array(target);
            let direction = DVec3::from_array(light);
            prop_assume!(direction.length() > 0.1);
            let light = if spot {
                Light::Spot(SpotLight::new(DVec3::new(5.0, 60.0, -5.0), direction.with_y(-1.0), 50.0, 300.0).unwrap())
            } else {
                Light::Directional(DirectionalLight::new(direction.with_y(-direction.y.abs() - 0.1)).unwrap())
            };
            let input = SetupInput { camera: &camera, light: &light, scene: &scene, map: MapSettings::default(), samples: None };
            let frame = Frame::new(&input);
            let part = match side {
                Some(n) if DVec3::from_array(n).length() > 0.1 => {
                    // A plane through the light's rays, as SPPSM's.
                    let n = DVec3::from_array(n).normalize();
                    let along = match &light { Light::Directional(d) => d.direction(), Light::Spot(s) => s.direction(), Light::Point(_) => unreachable!() };
                    let n = (n - along * n.dot(along)).normalize_or_zero();
                    prop_assume!(n.length() > 0.5);
                    let through = match &light { Light::Directional(_) => target, Light::Spot(s) => s.position(), Light::Point(_) => unreachable!() };
                    Part::Side(Plane::through_point(through, n))
                }
                _ => Part::Whole,
            };
            let basis = FocusBasis::new(&frame, part);
            let tolerance = frame.tolerance;
            let planes = match part {
                Part::Side(p) => { let mut v = frame.receiver_planes.clone(); v.push(p); v }
                _ => frame.receiver_planes.clone(),
            };
            // Visible receivers, one by one.
            let mut count = 0;
            let mut vertices = Vec::new();
            if !basis.visible.view_body.is_empty() {
                for r in scene.receivers() {
                    match classify_box(r, &planes, tolerance) {
                        BoxSide::Outside => {}
                        BoxSide::Inside => { count += 1; vertices.extend(r.corners()); }
                        BoxSide::Straddles(mask) => {
                            if box_cut_vertices(r, &planes, mask, tolerance, &mut vertices) { count += 1; }
                        }
                    }
                }
            }
            prop_assert_eq!(basis.visible.visible_receivers(), count);
            prop_assume!(count > 0);
            let projectors = match &light {
                Light::Directional(d) => vec![
                    Projector::Parallel(LightFrame::fixed(d.direction())),
                    Projector::Parallel(LightFrame::view_aligned(d.direction(), camera.forward()).unwrap_or(LightFrame::fixed(d.direction()))),
                ],
                Light::Spot(s) => vec![Projector::Point { frame: LightFrame::fixed(s.direction()), position: s.position() }],
                Light::Point(_) => unreachable!(),
            };
            for projector in &projectors {
                let mut want = Extents::EMPTY;
                for v in &vertices { want.add(projector.project(*v)); }
                let got = basis.visible.receiver_extents(&scene, projector);
                let eps = 1e-9 * (1.0 + (want.max - want.min).abs().max_element() + want.min.abs().max_element());
                prop_assert!(close(&got, &want, eps), "receivers {:?} vs {:?}", got, want);
                let mut diagnostics = crate::diagnostics::Diagnostics::new(&camera, &light, &scene);
                let got = caster_extents(&scene, projector, &want, &basis.caster_planes, spot, tolerance, &mut diagnostics);
                let (want_casters, relevant) = casters_one_by_one(&scene, projector, &want, &basis.caster_planes, tolerance);
                // Subtrees that add nothing are counted whole: at least the relevant ones.
                prop_assert!(diagnostics.relevant_casters >= relevant
                    && (diagnostics.relevant_casters > 0) == (relevant > 0),
                    "{} counted, {relevant} relevant", diagnostics.relevant_casters);
                // The far side is not gathered (see `caster_extents`).
                let near_side = |e: &Extents| Extents { min: e.min, max: e.max.with_z(0.0) };
                if relevant > 0 {
                    prop_assert!(close(&near_side(&got), &near_side(&want_casters), eps),
                        "casters {:?} vs {:?}", got, want_casters);
                } else {
                    prop_assert!(got.is_empty());
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

        /// A cube face's closed forms agree with cutting the box by the face's frustum planes:
        /// the image of the part inside (empty where nothing is), and whether the near plane
        /// clips part of its surface ([`NearTip`]). Boxes are drawn around the light, across
        /// the sides, the near plane (the light inside a box, or beside it within the near
        /// distance) and the far plane.
        #[test]
        fn cube_face_closed_forms_match_the_cut(
            face in 0usize..6,
            lo in prop::array::uniform3(-12.0f64..12.0),
            size in prop::array::uniform3(0.0f64..10.0),
            scale in prop::sample::select(vec![1.0, 1e-3, 1e-6]),
            range in prop::sample::select(vec![5.0, 20.0, 1e3]),
            resolution in prop::sample::select(vec![16u32, 1024]),
        ) {
            use crate::light::{CubeFace, PointLight};
            let lo = DVec3::from_array(lo) * scale;
            let aabb = Aabb::new(lo, lo + DVec3::from_array(size) * scale).unwrap();
            let point = PointLight::new(DVec3::ZERO, range).unwrap();
            let spot = point.face_light(CubeFace::ALL[face], resolution);
            let frame = LightFrame::fixed(spot.direction());
            let projector = Projector::Point { frame, position: spot.position() };
            let t = spot.half_angle().tan();
            let axis = AxisFrustum::new(&frame, spot.position(), t, spot.near(), spot.range()).unwrap();
            let planes = spot.frustum_planes(frame.up);
            // The cut keeps points within a round-off of the planes (as the setups' tolerance
            // does): a flat box's vertices on a side plane come out a rounding off its face.
            let tol = 1e-12 * aabb.min().abs().max(aabb.max().abs()).max_element();
            let mut cut = Vec::new();
            let kept = box_cut_vertices(&aabb, &planes, all_planes(6), tol, &mut cut);
            let closed = axis.box_extents(&aabb);
            let scale = range.max(1.0);
            if kept {
                let mut slow = Extents::EMPTY;
                for p in &cut {
                    slow.add(projector.project(*p));
                }
                // A part thinner than round-off may come out empty in one and not the other.
                if !closed.is_empty() {
                    prop_assert!(close(&closed, &slow, 1e-9 * scale), "{closed:?} vs cut {slow:?}");
                } else {
                    prop_assert!((slow.max - slow.min).max_element() <= 1e-9 * scale, "{slow:?}");
                }
            } else {
                prop_assert!(closed.is_empty() || (closed.max - closed.min).max_element() <= 1e-9 * scale, "{closed:?}");
            }
            let scene = SceneBounds::new(vec![aabb], vec![aabb], None).unwrap();
            let mask = straddled(aabb.center(), aabb.half_extents(), &planes, all_planes(6), tol);
            if let Some(mask) = mask.filter(|m| m & 1 != 0) {
                let by_cut = NearTip::new(&scene, &planes, tol).clips(&aabb, mask, tol);
                prop_assert_eq!(axis.clips_tip(&aabb), by_cut);
            }
        }

        /// The allocation-free cut agrees with the general polyhedron clipper.
        #[test]
        fn box_cut_matches_polyhedron_clipping(
            lo in prop::array::uniform3(-10.0f64..10.0),
            size in prop::array::uniform3(0.0f64..8.0),
            planes in prop::collection::vec((prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-10.0f64..10.0)), 1..12),
        ) {
            let lo = DVec3::from_array(lo);
            let size = DVec3::from_array(size);
            prop_assume!(size.max_element() > 0.1);
            let aabb = Aabb::new(lo, lo + size).unwrap();
            let planes: Vec<Plane> = planes.iter().map(|(n, p)| Plane::through_point(DVec3::from_array(*p), unit(*n))).collect();
            let tol = 1e-9;
            let clipped = ConvexPolyhedron::from_box(&aabb).clip_all(&planes, tol);
            let mut fast = Vec::new();
            let mask = (1u32 << planes.len()) - 1;
            let any = box_cut_vertices(&aabb, &planes, mask, tol, &mut fast);
            let exact = clipped.vertices(tol);
            // Both find every vertex of the other (up to touching, measure-zero results).
            if !exact.is_empty() {
                prop_assert!(any);
                for v in &exact {
                    prop_assert!(fast.iter().any(|f| f.distance(*v) < 1e-6), "missing {v}: fast {fast:?} exact {exact:?}");
                }
            }
            for f in &fast {
                prop_assert!(exact.is_empty() || exact.iter().any(|v| f.distance(*v) < 1e-6) || clipped.is_empty(),
                    "extra {f}: fast {fast:?} exact {exact:?}");
            }
        }
    }
}
