//! The renderer as an engine uses it: frames that make no new GPU resources once warm, several
//! shadowed lights in one frame, instances that move, and images read back in bands.

mod common;

use glam::{DMat4, DVec3};
use gnomon::{
    Camera, DirectionalLight, Focused, Light, MapSettings, SpotLight, Sppsm, compute_setup,
};
use gnomon_render::{RenderScene, RenderSettings, ShadowedLight, StencilMode};

const SIZE: u32 = 256;

fn overview() -> (Camera, Light) {
    let camera = common::square_camera(DVec3::new(230.0, 200.0, 230.0), DVec3::ZERO, 1.0, 800.0);
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.3)).unwrap());
    (camera, sun)
}

/// The setup of `technique` for the camera and light over `bounds`, maps of `resolution`.
fn setup(
    technique: &dyn gnomon::ShadowTechnique,
    camera: &Camera,
    light: &Light,
    bounds: &gnomon::SceneBounds,
    resolution: u32,
) -> gnomon::ShadowSetup {
    compute_setup(
        technique,
        camera,
        light,
        bounds,
        MapSettings::with_resolution(resolution),
    )
    .unwrap()
}

fn settings() -> RenderSettings {
    common::square_settings(SIZE)
}

#[test]
fn steady_state_frames_make_no_buffer_or_texture() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (camera, light) = overview();
    let bounds = scene.bounds().unwrap();
    let map =
        |technique: &dyn gnomon::ShadowTechnique| setup(technique, &camera, &light, &bounds, 1024);
    let (focused, sppsm) = (map(&Focused), map(&Sppsm::default()));
    let settings = RenderSettings {
        metrics: true,
        light_view: true,
        ..settings()
    };
    // Warm: every kind of frame once.
    let first = renderer
        .render(&camera, &light, &focused, &settings)
        .unwrap();
    renderer.render(&camera, &light, &sppsm, &settings).unwrap();
    renderer
        .render_volumes(&camera, &light, &settings, StencilMode::ZFail)
        .unwrap();
    let warm = renderer.resources_created();
    for k in 0..100 {
        let frame = renderer
            .render(&camera, &light, &focused, &settings)
            .unwrap();
        assert_eq!(frame.color, first.color, "frame {k} differs from the first");
    }
    for _ in 0..10 {
        renderer.render(&camera, &light, &sppsm, &settings).unwrap();
        renderer
            .render_volumes(&camera, &light, &settings, StencilMode::PerCaster)
            .unwrap();
    }
    assert_eq!(
        renderer.resources_created(),
        warm,
        "steady-state frames made buffers or textures"
    );
    // The count counts: a larger frame needs larger targets.
    renderer
        .render(
            &camera,
            &light,
            &focused,
            &RenderSettings {
                width: 300,
                ..settings
            },
        )
        .unwrap();
    assert!(renderer.resources_created() > warm);
}

#[test]
fn a_sun_and_a_spot_light_with_shadow_maps_in_one_frame_agree_with_the_oracle() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let camera = common::square_camera(
        DVec3::new(-40.0, 150.0, 120.0),
        DVec3::new(-80.0, 0.0, -60.0),
        1.0,
        500.0,
    );
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, 0.3)).unwrap());
    let spot = Light::Spot(
        SpotLight::new(
            DVec3::new(0.0, 120.0, 40.0),
            DVec3::new(-0.6, -1.0, -0.8),
            40.0,
            400.0,
        )
        .unwrap(),
    );
    let bounds = scene.bounds().unwrap();
    let setup = |light: &Light, resolution| setup(&Focused, &camera, light, &bounds, resolution);
    // Maps of different sizes: layers of one array, the smaller in a corner of its layer.
    let (sun_setup, spot_setup) = (setup(&sun, 2048), setup(&spot, 1024));
    let frame = renderer
        .render_lights(
            &camera,
            &[
                ShadowedLight {
                    light: &sun,
                    setup: &sun_setup,
                },
                ShadowedLight {
                    light: &spot,
                    setup: &spot_setup,
                },
            ],
            &settings(),
        )
        .unwrap();
    assert_eq!(frame.light_masks.len(), 2);
    for (k, light) in [sun, spot].iter().enumerate() {
        let oracle = common::oracle(&scene, &camera, light, SIZE, SIZE);
        let a = common::mask_agreement(&frame.light_masks[k], &oracle, 0.1);
        println!(
            "light {k}: {:.3}% of {} pixels ({} shadowed)",
            100.0 * a.fraction(),
            a.compared,
            a.shadowed
        );
        assert!(a.compared > 10_000 && a.shadowed > 1000, "light {k}: {a:?}");
        assert!(a.fraction() >= 0.995, "light {k}: {a:?}");
    }
    // The combined mask is lit where either light reaches.
    for (i, m) in frame.mask.iter().enumerate() {
        let any = frame.light_masks.iter().map(|l| l[i]).max().unwrap();
        assert_eq!(*m, any, "pixel {i}");
    }
    // Two lights are brighter than one wherever the second reaches.
    let one = renderer
        .render(&camera, &sun, &sun_setup, &settings())
        .unwrap();
    let brighter = (0..frame.mask.len())
        .filter(|&i| frame.light_masks[1][i] == gnomon_render::MASK_LIT)
        .filter(|&i| frame.color[4 * i..4 * i + 3] > one.color[4 * i..4 * i + 3])
        .count();
    let spot_lit = frame.light_masks[1]
        .iter()
        .filter(|m| **m == gnomon_render::MASK_LIT)
        .count();
    assert!(
        brighter as f64 > 0.9 * spot_lit as f64,
        "{brighter} of {spot_lit} spot-lit pixels brighter"
    );
}

#[test]
fn a_moved_instance_casts_its_shadow_where_it_now_stands() {
    let mut scene = common::box_on_ground(
        30.0,
        "post",
        DVec3::new(1.0, 4.0, 1.0),
        DVec3::new(-8.0, 0.0, 0.0),
    );
    let mut renderer = common::renderer(&scene);
    let camera = common::square_camera(DVec3::new(0.0, 30.0, 30.0), DVec3::ZERO, 1.0, 200.0);
    let light = Light::Directional(DirectionalLight::new(DVec3::new(0.6, -1.0, 0.2)).unwrap());
    let moved = DMat4::from_translation(DVec3::new(6.0, 4.0, 3.0));
    renderer.set_instance_transform(1, moved).unwrap();
    scene.instances[1].world_from_object = moved;
    // The renderer's bounds follow the instance, and so does its shadow.
    let bounds = renderer.scene_bounds().unwrap();
    assert_eq!(bounds.scene_box(), scene.bounds().unwrap().scene_box());
    let setup = setup(&Focused, &camera, &light, &bounds, 1024);
    let frame = renderer
        .render(&camera, &light, &setup, &settings())
        .unwrap();
    let oracle = common::oracle(&scene, &camera, &light, SIZE, SIZE);
    let a = common::agreement(&frame, &oracle, 0.1);
    assert!(a.shadowed > 150 && a.fraction() >= 0.995, "{a:?}");
    let volumes = renderer
        .render_volumes(&camera, &light, &settings(), StencilMode::ZFail)
        .unwrap();
    let a = common::agreement(&volumes.frame, &oracle, 0.1);
    assert!(a.shadowed > 150 && a.fraction() >= 0.999, "volumes: {a:?}");
    assert!(renderer.set_instance_transform(2, moved).is_err());
}

#[test]
fn images_read_back_in_bands_equal_one_copy() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (camera, light) = overview();
    let bounds = scene.bounds().unwrap();
    let setup = setup(&Focused, &camera, &light, &bounds, 512);
    let settings = RenderSettings {
        width: 300,
        height: 170,
        metrics: true,
        light_view: true,
        ..RenderSettings::default()
    };
    let whole = renderer.render(&camera, &light, &setup, &settings).unwrap();
    // Bands of one row (and of 7 rows) give the same images.
    for band in [1, 7 * 300 * 16] {
        renderer.set_readback_band_bytes(band);
        let banded = renderer.render(&camera, &light, &setup, &settings).unwrap();
        assert_eq!(banded.color, whole.color);
        assert_eq!(banded.mask, whole.mask);
        assert_eq!(banded.metrics, whole.metrics);
        assert_eq!(banded.light_view, whole.light_view);
    }
    assert!(whole.mask.contains(&gnomon_render::MASK_UNLIT));
}

/// Copies an Rgba8 texture to the CPU (plain wgpu, as a caller would).
fn read_rgba8(gpu: &gnomon_render::Gpu, texture: &wgpu::Texture) -> Vec<u8> {
    let (w, h) = (texture.width(), texture.height());
    let row = (w * 4).div_ceil(256) * 256;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (row * h) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    buffer.map_async(wgpu::MapMode::Read, .., |_| {});
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .unwrap();
    let data = buffer.get_mapped_range(..).unwrap();
    data.chunks_exact(row as usize)
        .flat_map(|line| line[..(w * 4) as usize].to_vec())
        .collect()
}

#[test]
fn the_scene_drawn_into_a_multisampled_target_of_the_callers_matches_the_headless_frame() {
    let scene = RenderScene::from_layout(&gnomon_scene::demo());
    let mut renderer = common::renderer(&scene);
    let (camera, light) = overview();
    let bounds = renderer.scene_bounds().unwrap();
    let setup = setup(&Focused, &camera, &light, &bounds, 1024);
    let reference = renderer
        .render(&camera, &light, &setup, &settings())
        .unwrap();
    let gpu = renderer.gpu().clone();
    let texture = |samples, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage,
            view_formats: &[],
        })
    };
    let msaa = texture(4, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let resolved = texture(
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let (msaa_view, resolved_view) = (
        msaa.create_view(&Default::default()),
        resolved.create_view(&Default::default()),
    );
    renderer
        .prepare(
            &camera,
            &[ShadowedLight {
                light: &light,
                setup: &setup,
            }],
            &settings(),
        )
        .unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode_shadow_maps(&mut encoder);
    renderer
        .encode_scene(
            &mut encoder,
            &gnomon_render::SceneTarget {
                view: &msaa_view,
                format: wgpu::TextureFormat::Rgba8UnormSrgb,
                width: SIZE,
                height: SIZE,
                sample_count: 4,
                resolve_target: Some(&resolved_view),
                clear: Some(wgpu::Color::BLACK),
            },
        )
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let image = read_rgba8(&gpu, &resolved);
    // Multisampling changes edges only: most pixels equal the single-sampled frame's
    // (where the sky is, ours is black: compare where the reference has geometry).
    let (mut geometry, mut close) = (0, 0);
    for (i, m) in reference.mask.iter().enumerate() {
        if *m == gnomon_render::MASK_EMPTY {
            continue;
        }
        geometry += 1;
        let same = (0..3).all(|c| image[4 * i + c].abs_diff(reference.color[4 * i + c]) <= 3);
        close += usize::from(same);
    }
    println!("{close} of {geometry} geometry pixels match");
    assert!(geometry > 20_000 && close as f64 >= 0.95 * geometry as f64);
}
