//! The full progressive solve of the Cornell box to 1 % unshot power (the
//! default tolerance), on every core rayon finds; meshing and the BVH are
//! setup, measured apart in `prepare`.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use isorad::{
    Solver, SolverSettings, load_scene,
    mesh::{SquareMeshSettings, mesh_square},
    scene::Visibility,
};

fn solve(c: &mut Criterion) {
    let scene = load_scene("cornell").expect("built-in Cornell box").scene;
    let mesh_settings = SquareMeshSettings::for_scene(&scene);
    let mesh = mesh_square(&scene, &mesh_settings);
    let mut settings = SolverSettings::default();
    settings.tolerance = 0.01;

    let mut group = c.benchmark_group("cornell");
    group.sample_size(10);
    group.bench_function("prepare_mesh_and_bvh", |b| {
        b.iter(|| {
            let mesh = mesh_square(&scene, &mesh_settings);
            let visibility = Visibility::new(&scene);
            (mesh.vertices.len(), visibility.triangle_count())
        })
    });
    group.bench_function("solve_tolerance_0.01", |b| {
        b.iter_batched(
            || {
                Solver::with_mesh(scene.clone(), mesh.clone(), settings.clone())
                    .expect("valid settings")
            },
            |mut solver| {
                solver.run();
                solver.stats().rays
            },
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, solve);
criterion_main!(benches);
