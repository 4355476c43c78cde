//! Setup time with 10, 100 and 1000 caster boxes on a ground slab: boxes that only cast
//! (`_casters_only`) and boxes that cast and receive (the rest); and `scale/`: 10^3, 10^4 and
//! 10^5 boxes; `street/`: a city that grows from 10^3 to 10^5 boxes around a street-level camera
//! that sees the same part of it.
//!
//! `cargo bench -p gnomon-core --bench setup`

use std::hint::black_box;

#[path = "common/city.rs"]
mod city;

use city::{
    adaptive_cascades, bench_camera, city, lamp, lamp_over_city, spot, street_camera, street_city,
    sun,
};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use gnomon::{
    Cascades, Cube, Focused, Lispsm, MapSettings, Psm, ShadowTechnique, Sppsm, Tsm, Uniform,
    ViewSamples, Xpsm, compute_setup, compute_setup_with_samples,
};

fn bench(c: &mut Criterion) {
    let (camera, sun, spot) = (bench_camera(), sun(), spot());
    let (lamp, street_lamp, lamp_over) = (lamp(250.0), lamp(40.0), lamp_over_city());
    let settings = MapSettings::with_resolution(2048);
    let mut group = c.benchmark_group("setup");
    for n in [10usize, 100, 1000] {
        let casters_only = city(n, false);
        group.bench_with_input(
            BenchmarkId::new("focused_directional_casters_only", n),
            &casters_only,
            |b, s| {
                b.iter(|| compute_setup(&Focused, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        group.bench_with_input(
            BenchmarkId::new("lispsm_directional_casters_only", n),
            &casters_only,
            |b, s| {
                b.iter(|| {
                    compute_setup(&Lispsm::default(), black_box(&camera), &sun, s, settings)
                        .unwrap()
                })
            },
        );
        let scene = city(n, true);
        group.bench_with_input(
            BenchmarkId::new("tsm_directional_casters_only", n),
            &casters_only,
            |b, s| {
                b.iter(|| {
                    compute_setup(&Tsm::default(), black_box(&camera), &sun, s, settings).unwrap()
                })
            },
        );
        group.bench_with_input(
            BenchmarkId::new("xpsm_directional_casters_only", n),
            &casters_only,
            |b, s| {
                b.iter(|| {
                    compute_setup(&Xpsm::default(), black_box(&camera), &sun, s, settings).unwrap()
                })
            },
        );
        group.bench_with_input(
            BenchmarkId::new("psm_directional_casters_only", n),
            &casters_only,
            |b, s| {
                b.iter(|| {
                    compute_setup(&Psm::default(), black_box(&camera), &sun, s, settings).unwrap()
                })
            },
        );
        group.bench_with_input(BenchmarkId::new("lispsm_directional", n), &scene, |b, s| {
            b.iter(|| {
                compute_setup(&Lispsm::default(), black_box(&camera), &sun, s, settings).unwrap()
            })
        });
        group.bench_with_input(
            BenchmarkId::new("uniform_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&Uniform, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        group.bench_with_input(
            BenchmarkId::new("focused_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&Focused, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        group.bench_with_input(
            BenchmarkId::new("view_samples_from_boxes", n),
            &scene,
            |b, s| b.iter(|| ViewSamples::new(black_box(&camera), &sun, s)),
        );
        let unlimited = Lispsm {
            limit: false,
            ..Lispsm::default()
        };
        group.bench_with_input(
            BenchmarkId::new("lispsm_without_limit_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&unlimited, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        group.bench_with_input(BenchmarkId::new("sppsm_directional", n), &scene, |b, s| {
            b.iter(|| {
                compute_setup(&Sppsm::default(), black_box(&camera), &sun, s, settings).unwrap()
            })
        });
        let cascades = Cascades::default();
        group.bench_with_input(
            BenchmarkId::new("cascades_4_lispsm_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&cascades, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        // The renderer's way: the frame's samples drawn on the GPU and handed in (here cast
        // once outside the timing), so the setup does not cast its own from the boxes.
        let samples = ViewSamples::new(&camera, &sun, &scene);
        group.bench_with_input(
            BenchmarkId::new("cascades_4_lispsm_directional_given_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &cascades,
                        black_box(&camera),
                        &sun,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            },
        );
        let adaptive = adaptive_cascades();
        group.bench_with_input(
            BenchmarkId::new("cascades_adaptive_directional_given_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &adaptive,
                        black_box(&camera),
                        &sun,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            },
        );
        group.bench_with_input(
            BenchmarkId::new("lispsm_directional_given_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &Lispsm::default(),
                        black_box(&camera),
                        &sun,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            },
        );
        let stable = Cascades {
            stable: true,
            ..Cascades::default()
        };
        group.bench_with_input(
            BenchmarkId::new("cascades_4_stable_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&stable, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        group.bench_with_input(BenchmarkId::new("focused_spot", n), &scene, |b, s| {
            b.iter(|| compute_setup(&Focused, black_box(&camera), &spot, s, settings).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("lispsm_spot", n), &scene, |b, s| {
            b.iter(|| {
                compute_setup(&Lispsm::default(), black_box(&camera), &spot, s, settings).unwrap()
            })
        });
        group.bench_with_input(BenchmarkId::new("cube_point", n), &scene, |b, s| {
            b.iter(|| compute_setup(&Cube, black_box(&camera), &lamp, s, settings).unwrap())
        });
        for (name, light) in [
            ("cube_point_given_samples", &lamp),
            ("cube_point_40m_given_samples", &street_lamp),
            ("cube_point_over_city_given_samples", &lamp_over),
        ] {
            let samples = ViewSamples::new(&camera, light, &scene);
            group.bench_with_input(BenchmarkId::new(name, n), &scene, |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &Cube,
                        black_box(&camera),
                        light,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            });
        }
        group.bench_with_input(BenchmarkId::new("psm_spot", n), &scene, |b, s| {
            b.iter(|| {
                compute_setup(&Psm::default(), black_box(&camera), &spot, s, settings).unwrap()
            })
        });
    }
    group.finish();
    // Scale: the real-scene issue's figures, 10^3 to 10^5 boxes that cast and receive.
    let mut scale = c.benchmark_group("scale");
    scale.sample_size(10);
    let cascades = Cascades::default();
    for n in [1_000usize, 10_000, 100_000] {
        let scene = city(n, true);
        let samples = ViewSamples::new(&camera, &sun, &scene);
        scale.bench_with_input(
            BenchmarkId::new("focused_directional", n),
            &scene,
            |b, s| {
                b.iter(|| compute_setup(&Focused, black_box(&camera), &sun, s, settings).unwrap())
            },
        );
        scale.bench_with_input(
            BenchmarkId::new("lispsm_casting_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup(&Lispsm::default(), black_box(&camera), &sun, s, settings)
                        .unwrap()
                })
            },
        );
        scale.bench_with_input(
            BenchmarkId::new("sppsm_given_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &Sppsm::default(),
                        black_box(&camera),
                        &sun,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            },
        );
        scale.bench_with_input(
            BenchmarkId::new("bounds_and_hierarchies", n),
            &n,
            |b, &n| b.iter(|| city(black_box(n), true)),
        );
        scale.bench_with_input(
            BenchmarkId::new("cascades_4_lispsm_given_samples", n),
            &scene,
            |b, s| {
                b.iter(|| {
                    compute_setup_with_samples(
                        &cascades,
                        black_box(&camera),
                        &sun,
                        s,
                        settings,
                        &samples,
                    )
                    .unwrap()
                })
            },
        );
    }
    scale.finish();
    // Street: a city that grows outward while the camera sees the same streets; an engine
    // without our renderer casts the samples itself, so these do too.
    let mut street = c.benchmark_group("street");
    street.sample_size(20);
    let camera = street_camera();
    for n in [1_000usize, 10_000, 100_000] {
        let scene = street_city(n);
        let techniques: [(&str, &dyn ShadowTechnique); 3] = [
            ("focused", &Focused),
            ("lispsm", &Lispsm::default()),
            ("sppsm", &Sppsm::default()),
        ];
        for (name, technique) in techniques {
            street.bench_with_input(BenchmarkId::new(name, n), &scene, |b, s| {
                b.iter(|| compute_setup(technique, black_box(&camera), &sun, s, settings).unwrap())
            });
        }
    }
    street.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
