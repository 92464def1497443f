#[path = "../tests/support/mod.rs"]
mod support;
use glam::DVec3;
use isorad::*;
use std::time::Instant;
fn run(
    scene: &Scene,
    max_edge: f64,
    patch: f64,
    k: FormFactorKernel,
    tol: f64,
) -> (Mesh, Vec<Rgb>, f64, u64) {
    let mut s = SquareMeshSettings::for_scene(scene);
    s.max_edge = max_edge;
    s.patch_max_edge = patch;
    let mesh = mesh_square(scene, &s);
    let vis = Visibility::new(scene);
    let mut st = SolverSettings::default();
    st.tolerance = tol;
    st.kernel = k;
    let t = Instant::now();
    let mut solver = Solver::new(scene, &mesh, &vis, st).unwrap();
    solver.run(|_| {});
    let r = solver.radiosity().to_vec();
    let rays = solver.rays();
    (mesh, r, t.elapsed().as_secs_f64(), rays)
}
fn main() {
    for k in [
        FormFactorKernel::Mixed,
        FormFactorKernel::Wallace,
        FormFactorKernel::Exact,
    ] {
        let scene = support::closed_cube(0.5, 1.0);
        let (_, r, t, rays) = run(&scene, 0.1, 0.25, k, 1e-3);
        let e = std::f64::consts::PI * 2.0;
        let worst = r.iter().map(|b| (b.x / e - 1.0).abs()).fold(0.0, f64::max);
        let mean = r.iter().map(|b| b.x / e - 1.0).sum::<f64>() / r.len() as f64;
        println!(
            "{:8} cube: worst {:.4} mean {:+.4} {:.2}s {} rays",
            k.name(),
            worst,
            mean,
            t,
            rays
        );
        let mut b = support::SceneBuilder::default();
        let floor = b.material("floor", 0.5, 0.0);
        let light = b.material("light", 0.0, 10.0);
        b.polygon("floor", floor, support::square_z(-10.0, 10.0, 0.0, true));
        b.polygon(
            "light",
            light,
            support::disc_facing_down(64, 1.0, DVec3::new(0.0, 0.0, 2.0)),
        );
        let scene = b.scene;
        let (mesh, r, t, _) = run(&scene, 0.25, 2.0, k, 1e-3);
        let peak = support::coaxial_disc_form_factor(1.0, 2.0, 0.0);
        let mut worst: f64 = 0.0;
        for (v, b) in mesh.vertices.iter().zip(&r) {
            if v.surface != 0 {
                continue;
            }
            let x = v.position.truncate().length();
            let f = support::coaxial_disc_form_factor(1.0, 2.0, x);
            if f > 0.01 * peak {
                worst = worst.max((b.x / (0.5 * 10.0 * std::f64::consts::PI * f) - 1.0).abs());
            }
        }
        println!("{:8} disc: worst {:.4} {:.2}s", k.name(), worst, t);
        let scene = load_scene("cornell").unwrap().scene;
        let d = scene.diagonal();
        let (_, r, t, rays) = run(&scene, d / 40.0, d / 8.0, k, 0.01);
        let mean = r.iter().map(|b| b.element_sum()).sum::<f64>() / r.len() as f64;
        println!(
            "{:8} cornell: mean vertex B {:.4} {:.2}s {} rays",
            k.name(),
            mean,
            t,
            rays
        );
    }
}
