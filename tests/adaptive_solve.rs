//! Adaptive meshing while solving: the hierarchy stays valid, the energy
//! ledger stays closed, and on the Cornell box it reaches the square
//! mesher's error with fewer vertices.

use glam::DVec2;
use isorad::{Length, MeshKind, ProbeMode, ProbePoint, Scene, Settings, Solver, load_scene};
use rayon::prelude::*;

fn cornell() -> Scene {
    load_scene("cornell").expect("built-in scene").scene
}

fn solve(kind: MeshKind, max_edge_fraction: f64) -> Solver {
    let mut settings = Settings::default();
    // Many shadow samples: the vertices' sampling noise would otherwise
    // hide the interpolation error being measured.
    settings.solver.direct_samples = 256;
    settings.solver.max_samples = 1024;
    settings.mesh.kind = kind;
    settings.mesh.max_edge = Length::OfDiagonal(max_edge_fraction);
    let mut solver = Solver::new(cornell(), settings).expect("valid settings");
    solver.run();
    solver
}

/// Points on a lattice over the named surfaces (rectangles), 3 % of their
/// extent inside their edges.
fn probe_points(scene: &Scene, names: &[&str], n: usize) -> Vec<ProbePoint> {
    let mut points = Vec::new();
    for surface in scene
        .surfaces
        .iter()
        .filter(|s| names.contains(&s.name.as_str()))
    {
        let outline = surface.plane_vertices();
        let (min, max) = outline.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let margin = 0.03 * (max - min);
        let step = (max - min - 2.0 * margin) / (n - 1) as f64;
        for j in 0..n {
            for i in 0..n {
                let p = min + margin + step * DVec2::new(i as f64, j as f64);
                points.push(ProbePoint {
                    position: surface.frame().to_world(p),
                    normal: Some(surface.normal()),
                    line: 0,
                });
            }
        }
    }
    points
}

/// Relative RMS difference of the rendered mesh's values against a final
/// gather at the same points (sum of channels), over points that receive
/// light (under the blocks nothing does, and nothing is drawn).
fn mesh_error(solver: &Solver, points: &[ProbePoint]) -> f64 {
    let solution = solver.solution(true);
    let pairs: Vec<(f64, f64)> = points
        .par_iter()
        .map(|p| {
            let gathered = solution.probe(p, ProbeMode::Gather).expect("on a surface");
            let meshed = solution.probe(p, ProbeMode::Mesh).expect("on a surface");
            (
                meshed.radiosity.element_sum(),
                gathered.radiosity.element_sum(),
            )
        })
        .collect();
    let mean = pairs.iter().map(|p| p.1).sum::<f64>() / pairs.len() as f64;
    let lit: Vec<&(f64, f64)> = pairs.iter().filter(|p| p.1 > 0.02 * mean).collect();
    let error = lit.iter().map(|(m, g)| (m - g).powi(2)).sum::<f64>();
    let signal = lit.iter().map(|(_, g)| g * g).sum::<f64>();
    (error / signal).sqrt()
}

#[test]
fn the_hierarchy_is_valid_and_the_ledger_closed_after_an_adaptive_solve() {
    let solver = solve(MeshKind::Adaptive, 1.0 / 40.0);
    let hierarchy = solver.hierarchy().expect("adaptive solve");
    let areas: Vec<f64> = solver.scene().surfaces.iter().map(|s| s.area()).collect();
    hierarchy.validate(solver.mesh(), &areas).unwrap();
    assert!(
        hierarchy.len() > hierarchy.roots().len(),
        "nothing was split"
    );
    assert_eq!(solver.radiosity().len(), solver.mesh().vertices.len());
    let balance = solver.energy_balance();
    let total = balance.absorbed + balance.unshot + balance.escaped;
    let imbalance = ((total - balance.emitted).abs() / balance.emitted).max_element();
    println!("adaptive Cornell: ledger imbalance {imbalance:.1e}");
    assert!(imbalance < 1e-9, "imbalance {imbalance}");
    for radiosity in solver.radiosity() {
        assert!(radiosity.is_finite() && radiosity.min_element() >= 0.0);
    }
}

/// On the Cornell box, against a final gather: adaptive meshing starts from
/// the square mesher's default grid (1/40 of the diagonal) and must end with
/// less error than it; the test prints how many vertices a square mesh needs
/// for the same error, interpolated log–log between 1/40 and 1/60.
#[test]
fn adaptive_meshing_beats_its_starting_grid_on_the_cornell_box() {
    let points = probe_points(&cornell(), &["floor", "back_wall", "red_wall"], 14);
    let mut rows = Vec::new();
    for (kind, fraction) in [
        (MeshKind::Square, 1.0 / 40.0),
        (MeshKind::Square, 1.0 / 60.0),
        (MeshKind::Adaptive, 1.0 / 40.0),
    ] {
        let solver = solve(kind, fraction);
        let error = mesh_error(&solver, &points);
        let vertices = solver.mesh().vertices.len();
        println!(
            "{kind:?} from 1/{:.0}: {vertices} vertices, RMS error {error:.4}",
            1.0 / fraction
        );
        rows.push((vertices as f64, error));
    }
    let [(v40, e40), (v60, e60), (adaptive_vertices, adaptive_error)] = rows[..] else {
        unreachable!()
    };
    let slope = (v60 / v40).ln() / (e60 / e40).ln();
    let square_equivalent = v40 * ((adaptive_error / e40).ln() * slope).exp();
    println!(
        "a square mesh needs about {square_equivalent:.0} vertices for the adaptive mesh's \
         error {adaptive_error:.4}; the adaptive mesh has {adaptive_vertices:.0}"
    );
    assert!(
        adaptive_error < e40,
        "adaptive error {adaptive_error} not below its starting grid's {e40}"
    );
}
