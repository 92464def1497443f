//! Adaptive meshing while solving: the hierarchy stays valid, the energy
//! ledger stays closed, and on the Cornell box it reaches the square
//! mesher's error with fewer vertices.

use glam::DVec2;
use isorad::{
    Ambient, Length, MeshKind, ProbeMode, Scene, Settings, Solver, load_scene, phase::silent,
    scene::ProbePoint,
};
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

/// Points on the named surfaces (rectangles), one at a random place in each
/// cell of an n × n grid over each, 3 % of their extent inside their edges.
/// Jittered, not on a lattice: a lattice lined up with the elements' edges
/// would measure the mesh at its vertices only.
fn probe_points(scene: &Scene, names: &[&str], n: usize) -> Vec<ProbePoint> {
    let mut state = 0x9E37_79B9_7F4A_7C15_u64;
    let mut random = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1_u64 << 53) as f64
    };
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
        let step = (max - min - 2.0 * margin) / n as f64;
        for j in 0..n {
            for i in 0..n {
                let cell = DVec2::new(i as f64 + random(), j as f64 + random());
                points.push(ProbePoint {
                    position: surface.frame().to_world(min + margin + step * cell),
                    normal: Some(surface.normal()),
                    line: 0,
                });
            }
        }
    }
    points
}

/// The radiosity (sum of channels) at each point: the rendered mesh's, or
/// a final gather's.
fn radiosities(solver: &Solver, points: &[ProbePoint], mode: ProbeMode) -> Vec<f64> {
    let solution = solver.solution(Ambient::Everywhere, &silent);
    points
        .par_iter()
        .map(|p| {
            let probe = solution.probe(p, mode).expect("on a surface");
            probe.radiosity.element_sum()
        })
        .collect()
}

/// Relative RMS difference of `values` against `reference`, over the points
/// that receive light (under the blocks nothing does, and nothing is drawn).
fn relative_rms(values: &[f64], reference: &[f64]) -> f64 {
    let mean = reference.iter().sum::<f64>() / reference.len() as f64;
    let (mut error, mut signal) = (0.0, 0.0);
    for (v, r) in values.iter().zip(reference) {
        if *r > 0.02 * mean {
            error += (v - r).powi(2);
            signal += r * r;
        }
    }
    (error / signal).sqrt()
}

/// The vertex count at which the square meshes' (vertices, error) curve
/// reaches `error`: log–log interpolation between the two meshes whose
/// errors bracket it (extrapolated from the nearest two outside). An error
/// below every square mesh's, where the curve has flattened (shadow
/// boundaries leave the finer grids little to gain), needs at least the
/// finest mesh's vertices: that lower bound is returned instead of an
/// extrapolation along a flat curve.
fn square_vertices_for(curve: &[(f64, f64)], error: f64) -> f64 {
    let &(finest_vertices, _) = curve.last().expect("a curve");
    let least = curve.iter().map(|&(_, e)| e).fold(f64::INFINITY, f64::min);
    if error <= least {
        return finest_vertices;
    }
    let k = curve
        .windows(2)
        .position(|w| w[1].1 <= error)
        .unwrap_or(curve.len() - 2);
    let ((v0, e0), (v1, e1)) = (curve[k], curve[k + 1]);
    let slope = (v1 / v0).ln() / (e1 / e0).ln();
    v0 * ((error / e0).ln() * slope).exp()
}

#[test]
fn the_hierarchy_is_valid_balanced_and_the_ledger_closed_after_an_adaptive_solve() {
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
    // Neighbours differ by at most one level: no edge of an element carries
    // more than the one hanging vertex a neighbour a level finer puts there.
    let mesh = solver.mesh();
    for (index, element) in mesh.elements.iter().enumerate() {
        let corners = element.corners();
        let outline = mesh.element_outline(element);
        let at = |v: u32| {
            outline
                .iter()
                .position(|&w| w == v)
                .expect("corner on outline")
        };
        for k in 0..corners.len() {
            let (from, to) = (at(corners[k]), at(corners[(k + 1) % corners.len()]));
            let between = (to + outline.len() - from) % outline.len() - 1;
            assert!(
                between <= 1,
                "element {index}: {between} hanging vertices on edge {k}"
            );
        }
    }
}

/// On the Cornell box, against one reference for all meshes (a final gather
/// from a square mesh of 1/80 of the diagonal at 6,400 jittered points on
/// the floor, back wall, red wall and ceiling): adaptive meshing, started
/// from the square mesher's default grid (1/40), needs fewer vertices than
/// square meshes for the same error. Prints the figures.
#[test]
fn adaptive_meshing_reaches_the_square_error_with_fewer_vertices_on_the_cornell_box() {
    let names = ["floor", "back_wall", "red_wall", "ceiling"];
    let points = probe_points(&cornell(), &names, 40);
    let fine = solve(MeshKind::Square, 1.0 / 80.0);
    let reference = radiosities(&fine, &points, ProbeMode::Gather);
    let error_of = |solver: &Solver| {
        let values = radiosities(solver, &points, ProbeMode::Mesh);
        (
            solver.mesh().vertices.len() as f64,
            relative_rms(&values, &reference),
        )
    };
    let mut curve = Vec::new();
    for fraction in [40.0, 60.0] {
        curve.push(error_of(&solve(MeshKind::Square, 1.0 / fraction)));
    }
    curve.push(error_of(&fine));
    for (&(vertices, error), fraction) in curve.iter().zip([40, 60, 80]) {
        println!("square 1/{fraction}: {vertices} vertices, RMS error {error:.4}");
    }
    let (vertices, error) = error_of(&solve(MeshKind::Adaptive, 1.0 / 40.0));
    let square = square_vertices_for(&curve, error);
    println!(
        "adaptive from 1/40: {vertices} vertices, RMS error {error:.4}; square meshes need \
         about {square:.0} vertices for that error ({:.0} % more)",
        100.0 * (square / vertices - 1.0)
    );
    assert!(
        error < curve[0].1,
        "adaptive error {error} not below its starting grid's {}",
        curve[0].1
    );
    assert!(
        vertices < square,
        "adaptive: {vertices} vertices where square meshes need {square:.0}"
    );
}

/// A preview before the mesh splits and the image after it: the ambient
/// term, averaged over each vertex's neighbours, has one value per vertex
/// of the split mesh, every one finite.
#[test]
fn the_ambient_term_follows_the_mesh_as_it_splits() {
    let mut settings = Settings::default();
    settings.mesh.kind = MeshKind::Adaptive;
    settings.mesh.max_edge = Length::OfDiagonal(1.0 / 20.0);
    let mut solver = Solver::new(cornell(), settings).expect("valid settings");
    let before = solver
        .solution(Ambient::Everywhere, &silent)
        .irradiance()
        .len();
    solver.run();
    let after = solver.solution(Ambient::Everywhere, &silent).irradiance();
    assert!(
        after.len() > before,
        "{} vertices, {before} before",
        after.len()
    );
    assert_eq!(after.len(), solver.mesh().vertices.len());
    assert!(after.iter().all(|h| h.is_finite()));
}
