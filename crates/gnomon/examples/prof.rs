use glam::DVec3;
use gnomon::*;
fn city(n: usize) -> SceneBounds {
    let side = (n as f64).sqrt().ceil() as usize;
    let pitch = 380.0 / side as f64;
    let mut boxes = Vec::new();
    for k in 0..n {
        let (i, j) = ((k % side) as f64, (k / side) as f64);
        let h = 2.0 + ((k * 7919) % 38) as f64;
        let min = DVec3::new(-190.0 + i * pitch, 0.0, -190.0 + j * pitch);
        boxes.push(Aabb::new(min, min + DVec3::new(0.6 * pitch, h, 0.6 * pitch)).unwrap());
    }
    let ground = Aabb::new(
        DVec3::new(-200.0, -1.0, -200.0),
        DVec3::new(200.0, 0.0, 200.0),
    )
    .unwrap();
    let mut r = boxes.clone();
    r.push(ground);
    SceneBounds::new(boxes, r, None).unwrap()
}
fn main() {
    let camera = Camera::look_at(
        DVec3::new(-150.0, 30.0, 180.0),
        DVec3::new(20.0, 0.0, -20.0),
        DVec3::Y,
        Lens::default(),
    )
    .unwrap();
    let sun = Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, -0.3)).unwrap());
    let scene = city(1000);
    let settings = MapSettings::with_resolution(2048);
    let s = compute_setup(&Cascades::default(), &camera, &sun, &scene, settings).unwrap();
    println!("{:?}", s.diagnostics);
    let samples = ViewSamples::new(&camera, &sun, &scene);
    println!("samples {}", samples.len());
    for (name, t) in [
        ("focused", Technique::Focused(Focused)),
        ("lispsm", Technique::Lispsm(Lispsm::default())),
    ] {
        let s = compute_setup(&t, &camera, &sun, &scene, settings).unwrap();
        println!("{name} {:?}", s.diagnostics);
    }
    let n = 300;
    if std::env::var("SHOW").is_ok() {
        let s = compute_setup(&Lispsm::default(), &camera, &sun, &scene, settings).unwrap();
        println!("{:?}\n{:?}", s.maps[0].clip_from_world, s.diagnostics);
        return;
    }
    if let Ok(v) = std::env::var("LOOP") {
        let t: Box<dyn ShadowTechnique> = match v.as_str() {
            "focused" => Box::new(Focused),
            "lispsm" => Box::new(Lispsm::default()),
            "cascades" => Box::new(Cascades::default()),
            "sppsm" => Box::new(Sppsm::default()),
            "cascfixed" => {
                let samples = ViewSamples::new(&camera, &sun, &scene);
                let reps: u32 = std::env::var("REPS")
                    .ok()
                    .and_then(|r| r.parse().ok())
                    .unwrap_or(3000);
                for _ in 0..reps {
                    std::hint::black_box(
                        compute_setup_with_samples(
                            &Cascades::default(),
                            &camera,
                            &sun,
                            &scene,
                            settings,
                            &samples,
                        )
                        .unwrap(),
                    );
                }
                return;
            }
            "psm" => Box::new(Psm {
                limit: false,
                ..Psm::default()
            }),
            _ => Box::new(Cascades {
                fit: CascadeFit::Focused,
                ..Cascades::default()
            }),
        };
        let reps: u32 = std::env::var("REPS")
            .ok()
            .and_then(|r| r.parse().ok())
            .unwrap_or(3000);
        let t0 = std::time::Instant::now();
        for _ in 0..reps {
            std::hint::black_box(
                compute_setup(t.as_ref(), &camera, &sun, &scene, settings).unwrap(),
            );
        }
        println!("{v} {:?}", t0.elapsed() / reps);
        return;
    }
    macro_rules! best {
        ($name:expr, $e:expr) => {{
            let mut best = std::time::Duration::MAX;
            for _ in 0..9 {
                let t0 = std::time::Instant::now();
                for _ in 0..n {
                    std::hint::black_box($e);
                }
                best = best.min(t0.elapsed() / n);
            }
            println!("{} {:?}", $name, best);
        }};
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "best") {
        best!("samples", ViewSamples::new(&camera, &sun, &scene));
        best!(
            "focused",
            compute_setup(&Focused, &camera, &sun, &scene, settings).unwrap()
        );
        best!(
            "lispsm",
            compute_setup(&Lispsm::default(), &camera, &sun, &scene, settings).unwrap()
        );
        best!(
            "cascades",
            compute_setup(&Cascades::default(), &camera, &sun, &scene, settings).unwrap()
        );
        best!(
            "cascades+samples",
            compute_setup_with_samples(
                &Cascades::default(),
                &camera,
                &sun,
                &scene,
                settings,
                &samples
            )
            .unwrap()
        );
        best!(
            "sppsm",
            compute_setup(&Sppsm::default(), &camera, &sun, &scene, settings).unwrap()
        );
        for it in [1, 2, 3, 5] {
            best!(
                format!("sppsm it {it}"),
                compute_setup(
                    &Sppsm {
                        iterations: it,
                        ..Sppsm::default()
                    },
                    &camera,
                    &sun,
                    &scene,
                    settings
                )
                .unwrap()
            );
        }
        best!(
            "psm unlimited",
            compute_setup(
                &Psm {
                    limit: false,
                    ..Psm::default()
                },
                &camera,
                &sun,
                &scene,
                settings
            )
            .unwrap()
        );
        return;
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "casc") {
        for _ in 0..10000 {
            std::hint::black_box(
                compute_setup_with_samples(
                    &Cascades::default(),
                    &camera,
                    &sun,
                    &scene,
                    settings,
                    &samples,
                )
                .unwrap(),
            );
        }
        return;
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "sppsm") {
        for _ in 0..5000 {
            std::hint::black_box(
                compute_setup(&Sppsm::default(), &camera, &sun, &scene, settings).unwrap(),
            );
        }
        return;
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "psm") {
        for _ in 0..5000 {
            std::hint::black_box(
                compute_setup(
                    &Psm {
                        limit: false,
                        ..Psm::default()
                    },
                    &camera,
                    &sun,
                    &scene,
                    settings,
                )
                .unwrap(),
            );
        }
        return;
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "samples") {
        for _ in 0..20000 {
            std::hint::black_box(ViewSamples::new(&camera, &sun, &scene));
        }
        return;
    }
    if std::env::var("ONLY").is_ok_and(|v| v == "focused") {
        for _ in 0..40000 {
            std::hint::black_box(compute_setup(&Focused, &camera, &sun, &scene, settings).unwrap());
        }
        return;
    }
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(ViewSamples::new(&camera, &sun, &scene));
    }
    println!("samples {:?}", t0.elapsed() / n);
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(
            compute_setup_with_samples(
                &Cascades::default(),
                &camera,
                &sun,
                &scene,
                settings,
                &samples,
            )
            .unwrap(),
        );
    }
    println!("cascades with samples {:?}", t0.elapsed() / n);
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(
            compute_setup(&Cascades::default(), &camera, &sun, &scene, settings).unwrap(),
        );
    }
    println!("cascades {:?}", t0.elapsed() / n);
    let f = Cascades {
        fit: CascadeFit::Focused,
        ..Cascades::default()
    };
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(compute_setup(&f, &camera, &sun, &scene, settings).unwrap());
    }
    println!("cascades focused {:?}", t0.elapsed() / n);
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(compute_setup(&Focused, &camera, &sun, &scene, settings).unwrap());
    }
    println!("focused {:?}", t0.elapsed() / n);
}
#[allow(dead_code)]
fn only_samples() {}
