//! The plugin's cost per frame in a Bevy world: its two systems (the scene's boxes, then the
//! fit) for 4 LiSPSM cascades over a street-level city of 10^3 and 10^4 static mesh
//! entities, and with a tenth of them moving every frame.
//!
//! `cargo bench -p bevy_gnomon --bench plugin`

use bevy::camera::primitives::Aabb as BevyAabb;
use bevy::camera::{PerspectiveProjection, Projection};
use bevy::ecs::system::SystemId;
use bevy::prelude::*;
use bevy_gnomon::{GnomonShadows, fit_cascades, track_scene};
use criterion::{Criterion, criterion_group, criterion_main};

#[path = "../tests/bare/mod.rs"]
mod bare;

/// An app with `n` box meshes on a square grid, a camera at street level and a sun, updated
/// once (so that Bevy's bounds, transforms and cascades exist), and the plugin's systems.
fn city(n: usize) -> (App, Vec<Entity>, [SystemId; 2]) {
    let mut app = bare::app(true);
    let side = (n as f64).sqrt().ceil() as usize;
    let entities = (0..n)
        .map(|i| {
            let (x, z) = ((i % side) as f32 * 12.0, (i / side) as f32 * 12.0);
            let h = 4.0 + (i * 7 % 11) as f32 * 2.0;
            app.world_mut()
                .spawn((
                    Mesh3d::default(),
                    BevyAabb::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0)),
                    Transform::from_xyz(x, h, z).with_scale(Vec3::new(4.0, h, 4.0)),
                ))
                .id()
        })
        .collect();
    // The visible part stays the same while the city grows: the far plane inside it.
    app.world_mut().spawn((
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            far: 250.0,
            ..default()
        }),
        Transform::from_xyz(-6.0, 2.0, -6.0).looking_at(Vec3::new(60.0, 2.0, 60.0), Vec3::Y),
    ));
    app.world_mut().spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            ..default()
        },
        GnomonShadows::default(),
        Transform::default().looking_to(Vec3::new(0.4, -0.8, 0.3), Vec3::Y),
    ));
    app.update();
    let systems = [
        app.world_mut().register_system(track_scene),
        app.world_mut().register_system(fit_cascades),
    ];
    (app, entities, systems)
}

fn plugin(c: &mut Criterion) {
    for n in [1_000, 10_000] {
        let (mut app, entities, systems) = city(n);
        c.bench_function(&format!("plugin/static/{n}"), |b| {
            b.iter(|| {
                for s in systems {
                    app.world_mut().run_system(s).unwrap();
                }
            })
        });
        let mut frame = 0u32;
        c.bench_function(&format!("plugin/moving_tenth/{n}"), |b| {
            b.iter(|| {
                // Up one frame, down the next: the boxes move, the city stays.
                frame += 1;
                let lift = Vec3::Y * if frame.is_multiple_of(2) { 0.5 } else { -0.5 };
                for &e in entities.iter().step_by(10) {
                    let mut t = app.world_mut().get_mut::<GlobalTransform>(e).unwrap();
                    *t = GlobalTransform::from(
                        t.compute_transform() * Transform::from_translation(lift),
                    );
                }
                for s in systems {
                    app.world_mut().run_system(s).unwrap();
                }
            })
        });
    }
}

criterion_group!(benches, plugin);
criterion_main!(benches);
