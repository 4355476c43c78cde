//! Each degenerate but valid configuration gives a sane map and names its fallback.

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Fallback, Focused, Lens, Light, LightFrameKind, Lispsm,
    MapSettings, Psm, SceneBounds, ShadowTechnique, SpotLight, Uniform, compute_setup,
};

fn lens() -> Lens {
    Lens {
        fov_y_degrees: 60.0,
        aspect: 1.5,
        near: 0.5,
        far: 200.0,
    }
}

fn ground() -> Aabb {
    Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap()
}

fn post() -> Aabb {
    Aabb::new(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 6.0, 1.0)).unwrap()
}

fn scene() -> SceneBounds {
    SceneBounds::new(vec![post()], vec![ground(), post()], None).unwrap()
}

fn sun(x: f64, y: f64, z: f64) -> Light {
    Light::Directional(DirectionalLight::new(DVec3::new(x, y, z)).unwrap())
}

fn focused(camera: &Camera, light: &Light, scene: &SceneBounds) -> gnomon::ShadowSetup {
    compute_setup(&Focused, camera, light, scene, MapSettings::default()).unwrap()
}

fn uniform(camera: &Camera, light: &Light, scene: &SceneBounds) -> gnomon::ShadowSetup {
    compute_setup(&Uniform, camera, light, scene, MapSettings::default()).unwrap()
}

#[test]
fn ordinary_view_has_no_fallback() {
    // Looking diagonally across the ground under a high sun: the view-aligned frame fits the
    // frustum's diagonal footprint tighter than the frame fixed to the world axes.
    let narrow = Lens {
        fov_y_degrees: 30.0,
        far: 40.0,
        ..lens()
    };
    let camera =
        Camera::look_at(DVec3::new(20.0, 4.0, 20.0), DVec3::ZERO, DVec3::Y, narrow).unwrap();
    let setup = focused(&camera, &sun(0.1, -1.0, 0.05), &scene());
    assert_eq!(setup.fallback(), None);
    assert_eq!(setup.diagnostics.light_frame, LightFrameKind::ViewAligned);
    assert_eq!(setup.diagnostics.relevant_casters, 1);
    assert_eq!(setup.diagnostics.visible_receivers, 2);
}

#[test]
fn miners_lamp_uses_the_fixed_frame() {
    // Looking straight down along a vertical sun.
    let camera =
        Camera::look_at(DVec3::new(0.0, 40.0, 0.0), DVec3::ZERO, DVec3::Z, lens()).unwrap();
    let setup = focused(&camera, &sun(0.0, -1.0, 0.0), &scene());
    assert_eq!(setup.fallback(), Some(Fallback::LightParallelToView));
    assert_eq!(setup.diagnostics.light_frame, LightFrameKind::Fixed);
    // The post's top still lands in the map.
    let p = setup.maps[0].project(DVec3::new(0.0, 6.0, 0.0)).unwrap();
    assert!(p.x.abs() < 1.0 && p.y.abs() < 1.0 && (0.0..=1.0).contains(&p.z));
}

#[test]
fn nothing_visible_gives_the_uniform_map() {
    let camera = Camera::look_at(
        DVec3::new(0.0, 40.0, 0.0),
        DVec3::new(0.0, 80.0, 0.0),
        DVec3::Z,
        lens(),
    )
    .unwrap();
    let light = sun(0.3, -1.0, 0.0);
    let setup = focused(&camera, &light, &scene());
    assert_eq!(
        setup.diagnostics.fallbacks,
        vec![Fallback::NoVisibleReceiver]
    );
    assert_eq!(setup.maps, uniform(&camera, &light, &scene()).maps);
}

#[test]
fn no_receiver_at_all_gives_the_uniform_map() {
    let scene = SceneBounds::new(vec![post()], vec![], Some(ground())).unwrap();
    let camera =
        Camera::look_at(DVec3::new(0.0, 10.0, 30.0), DVec3::ZERO, DVec3::Y, lens()).unwrap();
    let setup = focused(&camera, &sun(0.3, -1.0, 0.0), &scene);
    assert_eq!(setup.fallback(), Some(Fallback::NoVisibleReceiver));
}

#[test]
fn no_caster_fits_the_map_to_the_receivers() {
    let scene = SceneBounds::new(vec![], vec![ground()], None).unwrap();
    let camera =
        Camera::look_at(DVec3::new(0.0, 10.0, 30.0), DVec3::ZERO, DVec3::Y, lens()).unwrap();
    let setup = focused(&camera, &sun(0.3, -1.0, 0.0), &scene);
    assert_eq!(setup.fallback(), Some(Fallback::NoCasterForReceivers));
    assert_eq!(setup.diagnostics.relevant_casters, 0);
    // A caster far to the side of what the camera sees is culled the same way.
    let aside = Aabb::new(DVec3::new(40.0, 0.0, 40.0), DVec3::new(42.0, 3.0, 42.0)).unwrap();
    let scene = SceneBounds::new(vec![aside], vec![ground()], None).unwrap();
    let camera = Camera::look_at(
        DVec3::new(-40.0, 5.0, -20.0),
        DVec3::new(-40.0, 0.0, -40.0),
        DVec3::Y,
        lens(),
    )
    .unwrap();
    let setup = focused(&camera, &sun(0.0, -1.0, 0.1), &scene);
    assert_eq!(setup.fallback(), Some(Fallback::NoCasterForReceivers));
    assert_eq!(setup.diagnostics.culled_casters, 1);
}

#[test]
fn spot_light_that_cannot_see_the_view() {
    // A spot pointing away from everything the camera sees.
    let spot = Light::Spot(
        SpotLight::new(
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::new(0.0, -1.0, -0.2),
            20.0,
            30.0,
        )
        .unwrap(),
    );
    let camera = Camera::look_at(
        DVec3::new(0.0, 3.0, 45.0),
        DVec3::new(0.0, 3.0, 60.0),
        DVec3::Y,
        lens(),
    )
    .unwrap();
    let setup = focused(&camera, &spot, &scene());
    assert_eq!(setup.fallback(), Some(Fallback::SpotLightMissesView));
    assert_eq!(setup.maps, uniform(&camera, &spot, &scene()).maps);
}

#[test]
fn spot_light_that_misses_the_scene_covers_its_cone() {
    let spot =
        Light::Spot(SpotLight::new(DVec3::new(0.0, 100.0, 0.0), DVec3::Y, 30.0, 50.0).unwrap());
    let camera =
        Camera::look_at(DVec3::new(0.0, 10.0, 30.0), DVec3::ZERO, DVec3::Y, lens()).unwrap();
    let setup = uniform(&camera, &spot, &scene());
    assert_eq!(setup.fallback(), Some(Fallback::SpotLightMissesScene));
    // The whole cone: a point on its axis at half range lands at the centre.
    let p = setup.maps[0].project(DVec3::new(0.0, 125.0, 0.0)).unwrap();
    assert!(p.x.abs() < 1e-9 && p.y.abs() < 1e-9 && (0.0..=1.0).contains(&p.z));
}

#[test]
fn caster_reaching_in_front_of_the_spot_near_plane_is_reported() {
    // A lamp post whose top holds the spot light 0.01 mm above it: the post crosses the
    // light's near plane (3e-5 m below the light, a millionth of its range).
    let top = 10.0 - 1e-5;
    let lamp = Aabb::new(DVec3::new(-0.2, 0.0, -0.2), DVec3::new(0.2, top, 0.2)).unwrap();
    let scene = SceneBounds::new(vec![lamp, post()], vec![ground()], None).unwrap();
    let spot =
        Light::Spot(SpotLight::new(DVec3::new(0.0, 10.0, 0.0), -DVec3::Y, 60.0, 30.0).unwrap());
    let camera =
        Camera::look_at(DVec3::new(0.0, 10.0, 30.0), DVec3::ZERO, DVec3::Y, lens()).unwrap();
    let setup = focused(&camera, &spot, &scene);
    assert_eq!(setup.diagnostics.casters_clipped_by_light_near, 1);
    assert!(setup.diagnostics.relevant_casters >= 2);
    // Every technique that fits the spot's frustum counts it: the warps' own maps (no limit,
    // so that they are not the focused map they fall back to) and every technique as it
    // comes. (The uniform map covers the whole cone and walks no casters.)
    let unlimited: [&dyn ShadowTechnique; 2] = [
        &Psm {
            limit: false,
            ..Psm::default()
        },
        &Lispsm {
            limit: false,
            ..Lispsm::default()
        },
    ];
    let every = gnomon::Technique::all();
    let fitted = every
        .iter()
        .filter(|t| t.takes(&spot) && t.name() != "uniform")
        .map(|t| t as &dyn ShadowTechnique);
    for technique in unlimited.into_iter().chain(fitted) {
        let setup =
            compute_setup(technique, &camera, &spot, &scene, MapSettings::default()).unwrap();
        assert_eq!(
            setup.diagnostics.casters_clipped_by_light_near,
            1,
            "{}",
            technique.name()
        );
    }
    // A wall beside the lamp crosses the near plane's height, but a metre from the light,
    // where the frustum is a hair's width: nothing of it is clipped, and nothing is counted.
    let wall = Aabb::new(DVec3::new(1.0, 0.0, -3.0), DVec3::new(1.5, 20.0, 3.0)).unwrap();
    let scene = SceneBounds::new(vec![wall, post()], vec![ground()], None).unwrap();
    let setup = focused(&camera, &spot, &scene);
    assert!(setup.diagnostics.relevant_casters >= 1);
    assert_eq!(setup.diagnostics.casters_clipped_by_light_near, 0);
    // The light inside the post, half a metre below its top: the post's box holds the whole
    // space the near plane cuts off, and its walls lie beyond it; nothing is counted.
    let lamp = Aabb::new(DVec3::new(-0.2, 0.0, -0.2), DVec3::new(0.2, 10.5, 0.2)).unwrap();
    let scene = SceneBounds::new(vec![lamp, post()], vec![ground()], None).unwrap();
    let setup = focused(&camera, &spot, &scene);
    assert_eq!(setup.diagnostics.casters_clipped_by_light_near, 0);
}

#[test]
fn given_scene_box_too_small_is_grown_and_said() {
    let small = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0)).unwrap();
    let scene = SceneBounds::new(vec![post()], vec![ground(), post()], Some(small)).unwrap();
    let camera =
        Camera::look_at(DVec3::new(0.0, 10.0, 30.0), DVec3::ZERO, DVec3::Y, lens()).unwrap();
    let setup = focused(&camera, &sun(-0.3, -1.0, 0.2), &scene);
    assert!(setup.diagnostics.scene_box_grown);
}

#[test]
fn camera_from_a_view_matrix_gives_the_same_setup() {
    let camera = Camera::look_at(
        DVec3::new(3.0, 10.0, 30.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::Y,
        lens(),
    )
    .unwrap();
    let again = Camera::from_view_from_world(camera.view_from_world(), lens()).unwrap();
    let a = focused(&camera, &sun(-0.3, -1.0, 0.2), &scene());
    let b = focused(&again, &sun(-0.3, -1.0, 0.2), &scene());
    let diff = (a.maps[0].clip_from_world - b.maps[0].clip_from_world)
        .abs()
        .to_cols_array();
    assert!(diff.iter().all(|d| *d < 1e-9));
}
