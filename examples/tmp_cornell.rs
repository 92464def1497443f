use isorad::*;
use std::time::Instant;
fn main() {
    let loaded = load_scene("cornell").unwrap();
    let scene = loaded.scene;
    let t = Instant::now();
    let mesh = mesh_square(&scene, &SquareMeshSettings::for_scene(&scene));
    let vis = Visibility::new(&scene);
    println!(
        "mesh {} patches {} elements {} vertices, {:.3}s",
        mesh.patches.len(),
        mesh.elements.len(),
        mesh.vertices.len(),
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let mut solver = Solver::new(&scene, &mesh, &vis, SolverSettings::default()).unwrap();
    solver.run(|_| {});
    let s = t.elapsed().as_secs_f64();
    println!(
        "shots {} rays {} {:.3}s {:.2} Mrays/s unshot {:.4}",
        solver.shots(),
        solver.rays(),
        s,
        solver.rays() as f64 / s / 1e6,
        solver.unshot_fraction()
    );
    println!("{:?}", solver.energy_balance());
}
