//! The C interface called as C calls it: raw pointers, status codes, the last message.

use std::ffi::{CStr, c_char};
use std::ptr::{null, null_mut};

use gnomon::{MapSettings, SceneBounds, ShadowTechnique, Technique};
use serde_json::Value;

use super::*;

fn message() -> String {
    // SAFETY: the thread's message, valid until its next call.
    unsafe { CStr::from_ptr(gnomon_last_error_message()) }
        .to_str()
        .unwrap()
        .to_string()
}

fn blocks() -> (Vec<GnomonBox>, Vec<GnomonBox>) {
    let casters = vec![
        GnomonBox {
            min: [-20.0, 0.0, -26.0],
            max: [20.0, 16.0, -14.0],
        },
        GnomonBox {
            min: [20.0, 0.0, 4.0],
            max: [28.0, 40.0, 12.0],
        },
        GnomonBox {
            min: [-3.0, 0.0, 20.0],
            max: [3.0, 6.0, 26.0],
        },
    ];
    let mut receivers = vec![GnomonBox {
        min: [-100.0, -5.0, -100.0],
        max: [100.0, 0.0, 100.0],
    }];
    receivers.extend(&casters);
    (casters, receivers)
}

fn new_scene() -> *mut GnomonScene {
    let (casters, receivers) = blocks();
    let mut scene = null_mut();
    // SAFETY: the vectors hold the counts given.
    let status = unsafe {
        gnomon_scene_new(
            casters.as_ptr(),
            casters.len(),
            receivers.as_ptr(),
            receivers.len(),
            &mut scene,
        )
    };
    assert_eq!(status, GNOMON_OK, "{}", message());
    scene
}

const CAMERA: GnomonCamera = GnomonCamera {
    eye: [-30.0, 3.0, 60.0],
    target: [10.0, 4.0, -10.0],
    up: [0.0, 1.0, 0.0],
    fov_y_degrees: 60.0,
    aspect: 16.0 / 9.0,
    near_plane: 1.0,
    far_plane: 300.0,
};

fn lights() -> [GnomonLight; 3] {
    [
        GnomonLight {
            kind: GNOMON_LIGHT_SUN,
            position: [0.0; 3],
            direction: [0.4, -0.8, -0.45],
            half_angle_degrees: 0.0,
            range: 0.0,
        },
        GnomonLight {
            kind: GNOMON_LIGHT_SPOT,
            position: [10.0, 30.0, 20.0],
            direction: [-0.3, -1.0, -0.4],
            half_angle_degrees: 40.0,
            range: 150.0,
        },
        GnomonLight {
            kind: GNOMON_LIGHT_POINT,
            position: [0.0, 12.0, 5.0],
            direction: [0.0; 3],
            half_angle_degrees: 0.0,
            range: 80.0,
        },
    ]
}

fn setup(
    scene: *const GnomonScene,
    light: &GnomonLight,
    technique: &CStr,
    options: &CStr,
) -> (i32, GnomonSetupResult) {
    let mut result = std::mem::MaybeUninit::<GnomonSetupResult>::zeroed();
    // SAFETY: valid pointers throughout; a zeroed result is a valid one.
    let status = unsafe {
        gnomon_setup(
            scene,
            &CAMERA,
            light,
            technique.as_ptr(),
            options.as_ptr(),
            1024,
            result.as_mut_ptr(),
        )
    };
    (status, unsafe { result.assume_init() })
}

/// The result equals the core's setup through the JSON every front end prints.
fn assert_matches_json(result: &GnomonSetupResult, json: &Value) {
    let maps = json["maps"].as_array().unwrap();
    assert_eq!(result.map_count as usize, maps.len());
    for (map, expected) in result.maps.iter().zip(maps) {
        let clip: Vec<f64> = serde_json::from_value(expected["clip_from_world"].clone()).unwrap();
        assert_eq!(map.clip_from_world.to_vec(), clip);
        assert_eq!(
            map.clip_from_world_f32.to_vec(),
            clip.iter().map(|&v| v as f32).collect::<Vec<_>>()
        );
        let depth: Vec<f64> = serde_json::from_value(expected["depth_from_world"].clone()).unwrap();
        assert_eq!(map.depth_from_world.to_vec(), depth);
        assert_eq!(
            u64::from(map.resolution),
            expected["resolution"].as_u64().unwrap()
        );
        match expected["view_depth_range"].as_array() {
            Some(r) => {
                assert_eq!(map.has_view_depth_range, 1);
                assert_eq!(
                    map.view_depth_range.to_vec(),
                    vec![r[0].as_f64().unwrap(), r[1].as_f64().unwrap()]
                );
            }
            None => assert_eq!(map.has_view_depth_range, 0),
        }
        let names: Vec<&str> = expected["fallbacks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap())
            .collect();
        assert_eq!(fallback_names(map.fallbacks), names);
    }
    let kinds = [
        "single",
        "plane",
        "cascades",
        "dual_paraboloid",
        "cube_faces",
    ];
    assert_eq!(
        kinds[result.selection.kind as usize],
        json["selection"]["kind"]
    );
    let first = json["fallback"].as_str().unwrap_or("none");
    // SAFETY: a static string.
    assert_eq!(
        unsafe { CStr::from_ptr(gnomon_fallback_name(result.fallback)) }
            .to_str()
            .unwrap(),
        first
    );
}

fn fallback_names(mask: u32) -> Vec<&'static str> {
    (1..32)
        .filter(|code| mask & (1 << code) != 0)
        .map(|code| {
            unsafe { CStr::from_ptr(gnomon_fallback_name(code)) }
                .to_str()
                .unwrap()
        })
        .collect()
}

#[test]
fn every_technique_and_light_equals_the_core() {
    let scene = new_scene();
    let (casters, receivers) = blocks();
    let aabbs = |b: &[GnomonBox]| b.iter().map(|b| b.aabb().unwrap()).collect::<Vec<_>>();
    let bounds = SceneBounds::new(aabbs(&casters), aabbs(&receivers), None).unwrap();
    let mut compared = 0;
    for light in lights() {
        let core_light = light.light().unwrap();
        for technique in Technique::all()
            .into_iter()
            .filter(|t| t.takes(&core_light))
        {
            let name = std::ffi::CString::new(technique.name()).unwrap();
            let (status, result) = setup(scene, &light, &name, c"");
            assert_eq!(status, GNOMON_OK, "{}: {}", technique.name(), message());
            let expected = gnomon::compute_setup(
                &technique,
                &CAMERA.camera().unwrap(),
                &core_light,
                &bounds,
                MapSettings::with_resolution(1024),
            )
            .unwrap();
            assert_matches_json(&result, &gnomon_tools::setup_json(&expected));
            compared += 1;
        }
    }
    assert!(compared >= 20, "{compared}");
    unsafe { gnomon_scene_free(scene) };
}

#[test]
fn cube_faces_and_cascades_fill_their_selection() {
    let scene = new_scene();
    let [sun, _, point] = lights();
    let (_, cube) = setup(scene, &point, c"cube", c"");
    assert_eq!(cube.selection.kind, GNOMON_SELECTION_CUBE_FACES);
    assert_eq!(cube.selection.face_count, cube.map_count);
    assert_eq!(cube.selection.position, [0.0, 12.0, 5.0]);
    let (_, cascades) = setup(
        scene,
        &sun,
        c"cascades",
        c"--cascades 3 --cascade-split uniform",
    );
    let s = cascades.selection;
    assert_eq!(
        (s.kind, s.cascade_count, cascades.map_count),
        (GNOMON_SELECTION_CASCADES, 3, 3)
    );
    assert!(s.view_depths[..4].windows(2).all(|w| w[0] < w[1]));
    unsafe { gnomon_scene_free(scene) };
}

#[test]
fn null_pointers_and_bad_input_give_codes_and_one_line() {
    let scene = new_scene();
    let [sun, ..] = lights();
    let mut result = std::mem::MaybeUninit::<GnomonSetupResult>::zeroed();
    let status = unsafe {
        gnomon_setup(
            null(),
            &CAMERA,
            &sun,
            c"focused".as_ptr(),
            null(),
            1024,
            result.as_mut_ptr(),
        )
    };
    assert_eq!(
        (status, message().as_str()),
        (GNOMON_ERROR_NULL, "scene is a null pointer")
    );
    let status = unsafe {
        gnomon_setup(
            scene,
            &CAMERA,
            &sun,
            c"focused".as_ptr(),
            null(),
            1024,
            null_mut(),
        )
    };
    assert_eq!(
        (status, message().as_str()),
        (GNOMON_ERROR_NULL, "result is a null pointer")
    );
    let status = unsafe {
        gnomon_setup(
            scene,
            &CAMERA,
            &sun,
            null::<c_char>(),
            null(),
            1024,
            result.as_mut_ptr(),
        )
    };
    assert_eq!(status, GNOMON_ERROR_NULL);
    for (technique, options, light, expected) in [
        (c"lisp", c"", sun, "unknown technique 'lisp'"),
        (c"focused", c"--cascades 3", sun, "--cascades"),
        (c"cascades", c"--cascades 0", sun, "cascade count"),
        (
            c"focused",
            c"",
            GnomonLight { kind: 7, ..sun },
            "light kind 7",
        ),
        (
            c"focused",
            c"",
            GnomonLight {
                direction: [0.0; 3],
                ..sun
            },
            "zero length",
        ),
    ] {
        let (status, _) = setup(scene, &light, technique, options);
        let text = message();
        assert_eq!(status, GNOMON_ERROR_INVALID, "{text}");
        assert!(text.contains(expected) && !text.contains('\n'), "{text}");
    }
    let (status, _) = setup(scene, &sun, c"focused", c"");
    assert_eq!((status, message().as_str()), (GNOMON_OK, ""));
    // Bad boxes and counts that change are refused; the scene stays as it was.
    let (casters, receivers) = blocks();
    let inverted = [GnomonBox {
        min: [1.0; 3],
        max: [0.0; 3],
    }];
    let mut other = null_mut();
    let status = unsafe { gnomon_scene_new(inverted.as_ptr(), 1, null(), 0, &mut other) };
    assert!(
        status == GNOMON_ERROR_INVALID && message().starts_with("casters[0]: "),
        "{}",
        message()
    );
    assert!(other.is_null());
    let status = unsafe { gnomon_scene_new(null(), 2, null(), 0, &mut other) };
    assert_eq!(
        (status, message().as_str()),
        (GNOMON_ERROR_NULL, "casters is a null pointer")
    );
    let status = unsafe {
        gnomon_scene_move(
            scene,
            casters.as_ptr(),
            2,
            receivers.as_ptr(),
            receivers.len(),
        )
    };
    assert_eq!(status, GNOMON_ERROR_INVALID, "{}", message());
    let (status, _) = setup(scene, &sun, c"focused", c"");
    assert_eq!(status, GNOMON_OK);
    unsafe { gnomon_scene_free(scene) };
    unsafe { gnomon_scene_free(null_mut()) };
}

#[test]
fn moving_boxes_equals_a_new_scene() {
    let scene = new_scene();
    let (mut casters, mut receivers) = blocks();
    for b in casters.iter_mut().chain(receivers.iter_mut().skip(1)) {
        b.min[0] += 3.0;
        b.max[0] += 3.0;
    }
    let status = unsafe {
        gnomon_scene_move(
            scene,
            casters.as_ptr(),
            casters.len(),
            receivers.as_ptr(),
            receivers.len(),
        )
    };
    assert_eq!(status, GNOMON_OK, "{}", message());
    let mut rebuilt = null_mut();
    unsafe {
        gnomon_scene_new(
            casters.as_ptr(),
            casters.len(),
            receivers.as_ptr(),
            receivers.len(),
            &mut rebuilt,
        )
    };
    let [sun, ..] = lights();
    for technique in [c"focused", c"lispsm", c"cascades"] {
        let (_, a) = setup(scene, &sun, technique, c"");
        let (_, b) = setup(rebuilt, &sun, technique, c"");
        for (ma, mb) in a.maps.iter().zip(&b.maps).take(a.map_count as usize) {
            for (x, y) in ma.clip_from_world.iter().zip(&mb.clip_from_world) {
                assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{x} {y}");
            }
        }
    }
    unsafe { gnomon_scene_free(scene) };
    unsafe { gnomon_scene_free(rebuilt) };
}

#[test]
fn fallback_codes_name_the_core_fallbacks() {
    for f in FALLBACKS {
        let name = unsafe { CStr::from_ptr(gnomon_fallback_name(fallback_code(f))) };
        assert_eq!(name.to_str().unwrap(), f.name());
    }
    assert_eq!(
        unsafe { CStr::from_ptr(gnomon_fallback_name(0)) }
            .to_str()
            .unwrap(),
        "none"
    );
    assert_eq!(
        unsafe { CStr::from_ptr(gnomon_fallback_name(99)) }
            .to_str()
            .unwrap(),
        ""
    );
    let version = unsafe { CStr::from_ptr(gnomon_version()) };
    assert_eq!(version.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
}
