//! The Gouraud rasterizer on the Cornell box's solved mesh at 512 × 512,
//! one and 3 × 3 samples per pixel. The solve (tolerance 0.05) is setup.

use criterion::{Criterion, criterion_group, criterion_main};
use isorad::{
    Ambient, RenderSettings, Settings, Solver, load_scene, phase::silent, render::rasterize,
};

fn rasterizer(c: &mut Criterion) {
    // Solve once: mesh, BVH, shooting to 5 % unshot power.
    let scene = load_scene("cornell").expect("built-in Cornell box").scene;
    let mut camera = scene.camera_or_default();
    let mut settings = Settings::default();
    settings.solver.tolerance = 0.05;
    let mut solver = Solver::new(scene, settings).expect("valid settings");
    solver.run();
    let triangles = solver.solution(Ambient::Everywhere, &silent).triangles();
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
