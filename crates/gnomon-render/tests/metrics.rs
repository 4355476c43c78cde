//! The per-pixel sampling metrics (texels per pixel from shader derivatives) against finite
//! differences of the matrices: on a ground plane of known orientation, each pixel's
//! Jacobian of texel coordinates by screen pixels is rebuilt on the CPU from the camera's
//! and the map's matrices (rays through the pixel and its right and lower neighbours hit the
//! plane: forward differences, as a 2x2 quad's fragment derivatives), and the
//! renderer's undersampling (1 / sigma_min) and area ratio (1 / |det J|) agree within 5%,
//! for a focused map and for perspective warps (LiSPSM, PSM).

mod common;

use glam::{DVec2, DVec3, DVec4};
use gnomon::{Camera, DirectionalLight, Focused, Lens, Light, Lispsm, Psm, ShadowTechnique};
use gnomon_render::{RenderScene, RenderSettings};

const SIZE: u32 = 192;

/// A ground slab (top at y = 0) and one box standing on it.
fn scene() -> RenderScene {
    common::box_on_ground(
        60.0,
        "box",
        DVec3::new(2.0, 3.0, 2.0),
        DVec3::new(-8.0, 0.0, -20.0),
    )
}

/// (1 / sigma_min, 1 / |det|) of the Jacobian with columns `jx`, `jy`.
fn reduce(jx: DVec2, jy: DVec2) -> (f64, f64) {
    let (a, b, c) = (jx.dot(jx), jx.dot(jy), jy.dot(jy));
    let root = (0.25 * (a - c).powi(2) + b * b).sqrt();
    let sigma_min = (0.5 * (a + c) - root).max(0.0).sqrt();
    (1.0 / sigma_min, 1.0 / (jx.x * jy.y - jx.y * jy.x).abs())
}

#[test]
fn per_pixel_metrics_match_finite_differences_of_the_matrices() {
    let scene = scene();
    let mut renderer = common::renderer(&scene);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        metrics: true,
        ..RenderSettings::default()
    };
    let lens = Lens {
        fov_y_degrees: 60.0,
        aspect: 1.0,
        near: 0.5,
        far: 150.0,
    };
    let camera = Camera::look_at(
        DVec3::new(6.0, 9.0, 14.0),
        DVec3::new(-2.0, 0.0, -25.0),
        DVec3::Y,
        lens,
    )
    .unwrap();
    let light = Light::Directional(DirectionalLight::new(DVec3::new(0.4, -1.0, -0.2)).unwrap());
    let to_light = -DVec3::new(0.4, -1.0, -0.2).normalize();
    let techniques: [(&str, &dyn ShadowTechnique); 3] = [
        ("focused", &Focused),
        ("lispsm", &Lispsm::default()),
        ("psm", &Psm::default()),
    ];
    let world_from_clip = camera.clip_from_world().inverse();
    // The ground point seen through a position on the screen (pixel units, y down).
    let ground_point = |x: f64, y: f64| {
        let ndc = DVec2::new(x / SIZE as f64 * 2.0 - 1.0, 1.0 - y / SIZE as f64 * 2.0);
        let unproject = |z: f64| {
            let p: DVec4 = world_from_clip * DVec4::new(ndc.x, ndc.y, z, 1.0);
            p.truncate() / p.w
        };
        let (near, far) = (unproject(0.0), unproject(1.0));
        let t = near.y / (near.y - far.y);
        near + (far - near) * t
    };
    for (name, technique) in techniques {
        let (setup, frame) = common::render(
            &mut renderer,
            &scene,
            technique,
            &camera,
            &light,
            1024,
            &settings,
        );
        let map = setup.maps[0];
        let metrics = frame.metrics.as_ref().expect("metrics asked for");
        let texel = |p: DVec3| {
            let clip = map.clip_from_world * p.extend(1.0);
            clip.truncate().truncate() / clip.w * 0.5 * map.resolution as f64
        };
        let (mut compared, mut worst_error) = (0, 0.0f64);
        for py in (8..SIZE - 8).step_by(12) {
            for px in (8..SIZE - 8).step_by(12) {
                let i = (py * SIZE + px) as usize;
                // Ground pixels only: N.L of the ground (+Y), to a thousandth.
                if !metrics.measured(i) || (metrics.n_dot_l[i] as f64 - to_light.y).abs() > 1e-3 {
                    continue;
                }
                // One-pixel forward differences from the pixel's centre, as the fragment
                // derivatives of the top-left pixel of a 2x2 quad (px, py are even).
                let (cx, cy) = (px as f64 + 0.5, py as f64 + 0.5);
                let here = texel(ground_point(cx, cy));
                let jx = texel(ground_point(cx + 1.0, cy)) - here;
                let jy = texel(ground_point(cx, cy + 1.0)) - here;
                let (undersampling, area) = reduce(jx, jy);
                let gpu = (metrics.undersampling[i] as f64, metrics.area[i] as f64);
                let errors = [gpu.0 / undersampling - 1.0, gpu.1 / area - 1.0];
                for e in errors {
                    worst_error = worst_error.max(e.abs());
                }
                assert!(
                    errors.iter().all(|e| e.abs() < 0.05),
                    "{name} at pixel ({px}, {py}): GPU {gpu:?}, matrices ({undersampling}, {area})"
                );
                compared += 1;
            }
        }
        println!("{name}: {compared} ground pixels, largest relative difference {worst_error:.4}");
        assert!(compared > 80, "{name}: only {compared} pixels compared");
    }
}
