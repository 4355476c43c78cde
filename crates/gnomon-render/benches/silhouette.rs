//! Shadow-volume geometry on the CPU, one core: silhouette extraction (each triangle
//! classified as facing the light or not, then the edges between the two kinds) and the
//! whole volume (caps and extruded sides), in triangles of the caster per second, for the
//! demo's torus knot and, when fetched (scripts/fetch-meshes.sh), the knot and the bunny.
//!
//! `cargo bench -p gnomon-render --bench silhouette`

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{DMat4, DVec3, DVec4};
use gnomon::volumes::{MeshTopology, OpenMeshPolicy, VolumeParts, extrude_volume};
use gnomon::{DirectionalLight, Light, SpotLight};
use gnomon_scene::{Mesh, Shape};

fn meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![(
        "torus_knot_demo".to_string(),
        Shape::TorusKnot {
            p: 2,
            q: 3,
            major_radius: 6.0,
            minor_radius: 3.0,
            tube_radius: 1.2,
        }
        .mesh(),
    )];
    let dir = std::env::var_os("GNOMON_MESH_DIR").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes"),
        PathBuf::from,
    );
    for file in ["knot1.off", "bunny00.off"] {
        match Mesh::load(&dir.join(file)) {
            Ok(mesh) => out.push((file.trim_end_matches(".off").to_string(), mesh)),
            Err(e) => eprintln!("skipping {file}: {e} (run scripts/fetch-meshes.sh)"),
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let lights = [
        (
            "sun",
            Light::Directional(DirectionalLight::new(DVec3::new(0.5, -1.0, -0.3)).unwrap()),
        ),
        (
            "spot",
            Light::Spot(
                SpotLight::new(
                    DVec3::new(3.0, 4.0, 2.0),
                    DVec3::new(-0.5, -1.0, -0.4),
                    50.0,
                    100.0,
                )
                .unwrap(),
            ),
        ),
    ];
    let mut group = c.benchmark_group("silhouette");
    for (name, mesh) in meshes() {
        let topology =
            MeshTopology::new(&mesh.positions, &mesh.indices, OpenMeshPolicy::Reject).unwrap();
        let triangles = topology.triangles().len();
        group.throughput(Throughput::Elements(triangles as u64));
        for (light_name, light) in &lights {
            let toward = |p: DVec3| match light {
                Light::Directional(d) => -d.direction(),
                Light::Spot(s) => s.position() - p,
                Light::Point(l) => l.position() - p,
            };
            group.bench_function(
                BenchmarkId::new(format!("edges_{light_name}"), &name),
                |b| {
                    let mut facing = Vec::with_capacity(triangles);
                    b.iter(|| {
                        facing.clear();
                        let p = topology.positions();
                        facing.extend(topology.triangles().iter().map(|t| {
                            let [a, b, c] = t.map(|i| p[i as usize]);
                            (b - a).cross(c - a).dot(toward(a)) > 0.0
                        }));
                        black_box(topology.silhouette_edges(&facing))
                    })
                },
            );
            group.bench_function(
                BenchmarkId::new(format!("volume_{light_name}"), &name),
                |b| {
                    let mut out: Vec<DVec4> = Vec::new();
                    b.iter(|| {
                        out.clear();
                        black_box(extrude_volume(
                            &topology,
                            DMat4::IDENTITY,
                            light,
                            VolumeParts::Closed,
                            &mut out,
                        ))
                    })
                },
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
