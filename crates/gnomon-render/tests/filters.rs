//! Shadow-map filters measured on a straight shadow edge: one tap gives only the lit and the
//! shadowed colour; hardware 2x2 gives values between them in a band about one texel wide;
//! 5x5 PCF in a band about five texels wide (a kernel four times too wide, or 2x2 reduced to
//! one nearest tap, fails).

mod common;

use glam::DVec3;
use gnomon::{Camera, DirectionalLight, Focused, Lens, Light};
use gnomon_render::{Filter, MASK_EMPTY, RenderSettings};

const SIZE: u32 = 512;

#[test]
fn filters_spread_a_shadow_edge_over_their_kernels_width() {
    // A wide box on a ground that does not cast, seen from straight above; the light slants
    // in x, so the shadow's edges run along z and x.
    let scene = common::box_on_ground(
        40.0,
        "slab",
        DVec3::new(6.0, 2.0, 6.0),
        DVec3::new(-4.0, 0.0, -4.0),
    );
    let mut renderer = common::renderer(&scene);
    let camera = Camera::look_at(
        DVec3::new(0.0, 60.0, 0.0),
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, -1.0),
        Lens {
            fov_y_degrees: 40.0,
            aspect: 1.0,
            near: 1.0,
            far: 200.0,
        },
    )
    .unwrap();
    let light = Light::Directional(DirectionalLight::new(DVec3::new(0.6, -1.0, 0.3)).unwrap());
    let render = |renderer: &mut gnomon_render::Renderer, filter| {
        let settings = RenderSettings {
            width: SIZE,
            height: SIZE,
            filter,
            ambient: 0.25,
            ..RenderSettings::default()
        };
        // A small map: a texel spans several pixels, so bands are resolved.
        common::render(renderer, &scene, &Focused, &camera, &light, 128, &settings).1
    };
    let one = render(&mut renderer, Filter::None);
    // Ground pixels: the lit and the shadowed one-tap colours (red channel), from the mask.
    let ground: Vec<usize> = (0..one.mask.len())
        .filter(|&i| one.mask[i] != MASK_EMPTY && one.color[4 * i + 1] < 200)
        .collect();
    let red = |frame: &gnomon_render::Frame, i: usize| frame.color[4 * i] as i32;
    let lit = ground
        .iter()
        .filter(|&&i| one.mask[i] == gnomon_render::MASK_LIT)
        .map(|&i| red(&one, i))
        .max()
        .unwrap();
    let shadowed = ground
        .iter()
        .filter(|&&i| one.mask[i] == gnomon_render::MASK_UNLIT)
        .map(|&i| red(&one, i))
        .min()
        .unwrap();
    assert!(lit > shadowed + 40, "lit {lit}, shadowed {shadowed}");
    // Pixels strictly between the two colours.
    let between = |frame: &gnomon_render::Frame| {
        ground
            .iter()
            .filter(|&&i| {
                let r = red(frame, i);
                r > shadowed + 2 && r < lit - 2
            })
            .count()
    };
    let outside = |frame: &gnomon_render::Frame| {
        ground
            .iter()
            .filter(|&&i| {
                let r = red(frame, i);
                r < shadowed - 2 || r > lit + 2
            })
            .count()
    };
    let (hardware, pcf) = (
        render(&mut renderer, Filter::Hardware2x2),
        render(&mut renderer, Filter::Pcf5x5),
    );
    let (n_one, n_2x2, n_5x5) = (between(&one), between(&hardware), between(&pcf));
    println!("pixels between lit and shadowed: one tap {n_one}, 2x2 {n_2x2}, 5x5 {n_5x5}");
    // Every filtered value lies between the one-tap values.
    for frame in [&one, &hardware, &pcf] {
        assert_eq!(outside(frame), 0);
    }
    assert_eq!(n_one, 0, "one tap gives only lit and shadowed");
    // 2x2 blends over about one texel; 5x5 over about five (the band's area grows with its
    // width along the same edges).
    assert!(n_2x2 > 200, "2x2 blends {n_2x2} pixels");
    let ratio = n_5x5 as f64 / n_2x2 as f64;
    assert!((2.5..8.0).contains(&ratio), "5x5 / 2x2 band ratio {ratio}");
}
