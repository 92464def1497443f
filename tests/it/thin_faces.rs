//! Faces one element across (a shelved book's spine between its taller
//! neighbours): the mesh shows the face's mean light, not its edges'.

use crate::support::*;
use glam::DVec3;
use isorad::{
    Ambient, Scene, Solver, SolverSettings, SurfaceId,
    mesh::{SquareMeshSettings, mesh_square},
    phase::silent,
};

/// Width and height of the spine.
const WIDTH: f64 = 0.06;
const HEIGHT: f64 = 0.28;

/// A spine 6 cm × 28 cm at z = 0 facing −z, in a slot between two fins
/// that stand 8 cm out on either side (the neighbours sticking out past
/// it), lit by a 2 m square panel a metre in front.
fn spine_in_a_slot() -> Scene {
    let mut b = SceneBuilder::default();
    let paper = b.material("paper", 0.6, 0.0);
    let light = b.material("light", 0.0, 10.0);
    let front = DVec3::new(WIDTH / 2.0, HEIGHT / 2.0, -1.0);
    let quad = |x: [f64; 2], z: [f64; 2]| {
        vec![
            DVec3::new(x[0], 0.0, z[0]),
            DVec3::new(x[1], 0.0, z[1]),
            DVec3::new(x[1], HEIGHT, z[1]),
            DVec3::new(x[0], HEIGHT, z[0]),
        ]
    };
    b.polygon_facing("spine", paper, quad([0.0, WIDTH], [0.0, 0.0]), front);
    let slot = DVec3::new(WIDTH / 2.0, HEIGHT / 2.0, -0.04);
    b.polygon_facing("fin", paper, quad([0.0, 0.0], [0.0, -0.08]), slot);
    b.polygon_facing("fin", paper, quad([WIDTH, WIDTH], [0.0, -0.08]), slot);
    light_panel(&mut b, light, front);
    b.scene
}

/// A 2 m square light panel centred at `front`, facing the spine.
fn light_panel(b: &mut SceneBuilder, light: usize, front: DVec3) {
    let panel = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, y)| front + DVec3::new(x, y, 0.0))
        .collect();
    b.polygon_facing("light", light, panel, DVec3::ZERO);
}

/// The scene's square mesh at 20 cm elements and 1 m patches: the spine
/// (surface 0) one element across and two tall.
fn spine_mesh(scene: &Scene) -> isorad::mesh::Mesh {
    let mut mesh_settings = SquareMeshSettings::for_scene(scene);
    mesh_settings.max_edge = 0.2;
    mesh_settings.patch_max_edge = 1.0;
    mesh_square(scene, &mesh_settings)
}

/// `scene` on `mesh`, solved to 0.1 % unshot power.
fn solved_to_a_thousandth(scene: Scene, mesh: isorad::mesh::Mesh) -> Solver {
    let mut settings = SolverSettings::default();
    settings.tolerance = 1e-3;
    let mut solver = Solver::with_mesh(scene, mesh, settings).unwrap();
    solver.run();
    solver
}

/// The distinct values of `coordinate` over the spine's (surface 0's)
/// vertices, in micrometres.
fn spine_coordinates(
    mesh: &isorad::mesh::Mesh,
    coordinate: impl Fn(DVec3) -> f64,
) -> std::collections::BTreeSet<i64> {
    mesh.vertices
        .iter()
        .filter(|v| v.surface == SurfaceId::new(0))
        .map(|v| (coordinate(v.position) * 1e6).round() as i64)
        .collect()
}

/// The mean of gather probes over an n × n grid of cell centres of the
/// spine between x0 and x1 (fractions of its width).
fn probed_mean(solution: &isorad::Solution<'_>, (x0, x1): (f64, f64), n: usize) -> f64 {
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let x = WIDTH * (x0 + (x1 - x0) * (i as f64 + 0.5) / n as f64);
            let y = HEIGHT * (j as f64 + 0.5) / n as f64;
            sum += gather_at(solution, DVec3::new(x, y, 0.0), Some(DVec3::NEG_Z))
                .irradiance
                .r;
        }
    }
    sum / (n * n) as f64
}

#[test]
fn a_spine_one_element_across_shows_its_mean_light() {
    let scene = spine_in_a_slot();
    let mesh = spine_mesh(&scene);
    let spine = SurfaceId::new(0);
    let across = spine_coordinates(&mesh, |p| p.x);
    assert_eq!(across.len(), 2, "the spine is one element across");
    // Its vertices gather at the two-point Gauss abscissae of its width.
    let gauss = (1.0 - 1.0 / 3f64.sqrt()) / 2.0;
    for vertex in mesh.vertices.iter().filter(|v| v.surface == spine) {
        let x = vertex.receiver_position().x / WIDTH;
        assert!(
            (x - gauss).abs() < 0.01 || (x - (1.0 - gauss)).abs() < 0.01,
            "a spine vertex gathers at x = {x} of the width"
        );
    }
    let solver = solved_to_a_thousandth(scene, mesh);
    let solution = solver.solution(Ambient::Omitted, &silent);
    let shown = solution.surface_totals()[spine.index()].mean_irradiance.r;
    let exact = probed_mean(&solution, (0.0, 1.0), 12);
    // What the spine's corners see, in the strips along its two edges the
    // fins shade: gathered there, the mesh would show that.
    let edges =
        0.5 * (probed_mean(&solution, (0.0, 0.02), 4) + probed_mean(&solution, (0.98, 1.0), 4));
    let error = (shown - exact).abs() / exact;
    let edge_error = (edges - exact).abs() / exact;
    assert!(
        error < 0.05 && edge_error > 0.06,
        "the spine shows {shown} W/m² for a mean of {exact} ({:.1} %); its edges see {edges} \
         ({:.1} %)",
        100.0 * error,
        100.0 * edge_error
    );
}

#[test]
fn a_triangle_one_element_gathers_at_the_three_point_rule() {
    let mut b = SceneBuilder::default();
    let paper = b.material("paper", 0.6, 0.0);
    let light = b.material("light", 0.0, 10.0);
    let corners = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.1, 0.0, 0.0),
        DVec3::new(0.0, 0.08, 0.0),
    ];
    b.polygon_facing("tag", paper, corners.to_vec(), DVec3::new(0.0, 0.0, -1.0));
    b.polygon("light", light, square_z(-1.0, 1.0, -1.0, true));
    let scene = b.scene;
    let mut settings = SquareMeshSettings::for_scene(&scene);
    settings.max_edge = 0.2;
    let mesh = mesh_square(&scene, &settings);
    let tag: Vec<_> = mesh
        .vertices
        .iter()
        .filter(|v| v.surface == SurfaceId::new(0))
        .collect();
    assert_eq!(tag.len(), 3, "the tag is one element");
    for vertex in tag {
        // 2/3 of its own corner and 1/6 of each other one.
        let others: DVec3 = corners.iter().sum::<DVec3>() - vertex.position;
        let rule = vertex.position * (2.0 / 3.0) + others / 6.0;
        assert!(
            vertex.receiver_position().distance(rule) < 1e-3,
            "{} gathers at {}, not {rule}",
            vertex.position,
            vertex.receiver_position()
        );
    }
}

/// Height of the neighbour beside the spine in
/// [`spine_beside_a_shorter_neighbour`].
const NEIGHBOUR_TOP: f64 = 0.3 * HEIGHT;

/// The spine of [`spine_in_a_slot`] with one neighbour, a millimetre to its
/// right, that stands 4 cm further forward and reaches only
/// [`NEIGHBOUR_TOP`]: its side faces the spine's edge, its top crosses the
/// spine's plane, its own spine faces the light.
fn spine_beside_a_shorter_neighbour() -> Scene {
    let mut b = SceneBuilder::default();
    let paper = b.material("paper", 0.6, 0.0);
    let light = b.material("light", 0.0, 10.0);
    let front = DVec3::new(WIDTH / 2.0, HEIGHT / 2.0, -1.0);
    let rect = |x: [f64; 2], y: [f64; 2], z: [f64; 2]| {
        vec![
            DVec3::new(x[0], y[0], z[0]),
            DVec3::new(x[1], y[0], z[1]),
            DVec3::new(x[1], y[1], z[1]),
            DVec3::new(x[0], y[1], z[0]),
        ]
    };
    b.polygon_facing(
        "spine",
        paper,
        rect([0.0, WIDTH], [0.0, HEIGHT], [0.0, 0.0]),
        front,
    );
    let (x0, x1, z0, z1) = (WIDTH + 0.001, WIDTH + 0.061, -0.04, 0.16);
    let side = DVec3::new(0.0, 0.0, z0);
    b.polygon_facing(
        "side",
        paper,
        rect([x0, x0], [0.0, NEIGHBOUR_TOP], [z0, z1]),
        side,
    );
    let top = [
        DVec3::new(x0, NEIGHBOUR_TOP, z0),
        DVec3::new(x1, NEIGHBOUR_TOP, z0),
        DVec3::new(x1, NEIGHBOUR_TOP, z1),
        DVec3::new(x0, NEIGHBOUR_TOP, z1),
    ];
    b.polygon_facing("top", paper, top.to_vec(), DVec3::new(x0, 1.0, z0));
    b.polygon_facing(
        "its spine",
        paper,
        rect([x0, x1], [0.0, NEIGHBOUR_TOP], [z0, z0]),
        front,
    );
    light_panel(&mut b, light, front);
    b.scene
}

/// A neighbour that stands further forward shades a spine's edge up to
/// its own top and not above it; the spine's mesh gets a row of vertices
/// at that height, so that the mesh shows the light below the neighbour's
/// top and above it, each band within 3 % of a gather's mean over it
/// (+2.0 % and −0.5 %; without the row, +4.9 % below).
#[test]
fn a_spine_gets_a_row_where_a_neighbour_standing_further_forward_ends() {
    let scene = spine_beside_a_shorter_neighbour();
    let mesh = spine_mesh(&scene);
    let heights = spine_coordinates(&mesh, |p| p.y);
    let row = (NEIGHBOUR_TOP * 1e6).round() as i64;
    assert!(
        heights.iter().any(|&h| (h - row).abs() <= 1),
        "rows at {heights:?} µm, none at the neighbour's top, {row} µm"
    );
    let solver = solved_to_a_thousandth(scene, mesh);
    let solution = solver.solution(Ambient::Omitted, &silent);
    // Mesh and gather over the spine's width, in bands above and below the
    // neighbour's top.
    let band = |y0: f64, y1: f64, mode: isorad::ProbeMode| {
        let n = 8;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = WIDTH * (i as f64 + 0.5) / n as f64;
                let y = y0 + (y1 - y0) * (j as f64 + 0.5) / n as f64;
                let point = isorad::scene::ProbePoint {
                    position: DVec3::new(x, y, 0.0),
                    normal: Some(DVec3::NEG_Z),
                    line: 1,
                };
                sum += solution.probe(&point, mode).unwrap().irradiance.r;
            }
        }
        sum / (n * n) as f64
    };
    for (y0, y1) in [(0.0, NEIGHBOUR_TOP), (NEIGHBOUR_TOP, HEIGHT)] {
        let shown = band(y0, y1, isorad::ProbeMode::Mesh);
        let exact = band(y0, y1, isorad::ProbeMode::Gather);
        let error = (shown - exact) / exact;
        println!(
            "band {y0:.3}–{y1:.3} m: the mesh shows {shown:.4}, a gather {exact:.4} ({:+.1} %)",
            100.0 * error
        );
        assert!(
            error.abs() < 0.03,
            "from {y0} to {y1} m the spine shows {shown} W/m² for a mean of {exact} ({:+.1} %)",
            100.0 * error
        );
    }
}
