//! The Gouraud rasterizer on the Cornell box's solved mesh at 512 × 512,
//! one and 3 × 3 samples per pixel. The solve (tolerance 0.05) is setup.

use criterion::{Criterion, criterion_group, criterion_main};
use isorad::{
    RenderSettings, Solver, SolverSettings, SquareMeshSettings, Visibility, load_scene,
    mesh_square, mesh_triangles, rasterize,
};

fn rasterizer(c: &mut Criterion) {
    // Solve once: mesh, BVH, shooting to 5 % unshot power.
    let scene = load_scene("cornell").expect("built-in Cornell box").scene;
    let mesh = mesh_square(&scene, &SquareMeshSettings::for_scene(&scene));
    let visibility = Visibility::new(&scene);
    let mut settings = SolverSettings::default();
    settings.tolerance = 0.05;
    let mut solver = Solver::new(&scene, &mesh, &visibility, settings).expect("valid settings");
    solver.run(|_| {});
    let triangles = mesh_triangles(&mesh, &solver.radiosity_with_ambient());
    let mut camera = scene.camera_or_default();
    (camera.width, camera.height) = (512, 512);

    let mut group = c.benchmark_group("rasterize_cornell_512");
    group.sample_size(20);
    for supersampling in [1, 3] {
        let settings = RenderSettings::default().with_supersampling(supersampling);
        group.bench_function(format!("supersampling_{supersampling}"), |b| {
            b.iter(|| rasterize(&triangles, &camera, &settings))
        });
    }
    group.finish();
}

criterion_group!(benches, rasterizer);
criterion_main!(benches);
