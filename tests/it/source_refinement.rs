//! Source-side refinement: a shooter close to a receiver is sampled finely
//! enough (Wallace's adaptive source subdivision, with Lambert's exact factor
//! on near strata) that a lamp next to a wall, or the floor at the foot of a
//! block, shows no blotches: every receiving vertex matches the exact,
//! unoccluded point-to-polygon form factor.

use crate::support::*;
use glam::DVec3;
use isorad::{
    Scene, Solver, SolverSettings, SurfaceId,
    mesh::{Mesh, SquareMeshSettings, mesh_square},
    radiometry::polygon_form_factor,
};
use std::f64::consts::PI;

const WALL_REFLECTANCE: f64 = 0.5;
/// Emitted radiance of the lamps: exitance E = π.
const LAMP_RADIANCE: f64 = 1.0;

fn solve(scene: &Scene, max_edge: f64) -> (Mesh, Vec<f64>) {
    let mut settings = SquareMeshSettings::for_scene(scene);
    settings.max_edge = max_edge;
    settings.patch_max_edge = 0.25;
    let mesh = mesh_square(scene, &settings);
    let mut solver_settings = SolverSettings::default();
    solver_settings.tolerance = 1e-4;
    let mut solver = Solver::with_mesh(scene.clone(), mesh, solver_settings).unwrap();
    solver.run();
    let radiosity = solver.radiosity().iter().map(|b| b.r).collect();
    (solver.mesh().clone(), radiosity)
}

/// Worst relative error over the receiver's vertices where the exact value
/// is above 1 % of its peak, and the worst absolute error elsewhere as a
/// fraction of the peak; with the number of vertices checked.
fn worst_errors(
    mesh: &Mesh,
    radiosity: &[f64],
    receiver: SurfaceId,
    exact: impl Fn(DVec3) -> f64,
) -> (f64, f64, usize) {
    let values: Vec<(f64, f64)> = mesh
        .vertices
        .iter()
        .zip(radiosity)
        .filter(|(v, _)| v.surface == receiver)
        .map(|(v, &b)| (b, exact(v.receiver_position())))
        .collect();
    let peak = values.iter().map(|(_, e)| *e).fold(0.0, f64::max);
    let (mut relative, mut absolute, mut checked) = (0.0f64, 0.0f64, 0);
    for (b, e) in values {
        if e > 0.01 * peak {
            relative = relative.max((b - e).abs() / e);
            checked += 1;
        } else {
            absolute = absolute.max((b - e).abs() / peak);
        }
    }
    (relative, absolute, checked)
}

/// A 1 m × 1 m wall (x = 0, facing +x) and a 10 cm square lamp with its
/// nearest point 2 cm from the wall: parallel to it and facing it, or
/// perpendicular to it and facing down. Nothing else reflects (the lamp is
/// black), so the wall's radiosity is exactly ρ E F(v → lamp).
fn lamp_by_a_wall(perpendicular: bool) -> (Scene, Vec<DVec3>) {
    let mut b = SceneBuilder::default();
    let wall = b.material("wall", WALL_REFLECTANCE, 0.0);
    let lamp = b.material("lamp", 0.0, LAMP_RADIANCE);
    let square = |a: DVec3, u: DVec3, v: DVec3| vec![a, a + u, a + u + v, a + v];
    b.polygon_facing(
        "wall",
        wall,
        square(DVec3::ZERO, DVec3::Y, DVec3::Z),
        DVec3::X,
    );
    let lamp_polygon = if perpendicular {
        square(DVec3::new(0.02, 0.45, 0.5), 0.1 * DVec3::X, 0.1 * DVec3::Y)
    } else {
        square(DVec3::new(0.02, 0.45, 0.45), 0.1 * DVec3::Y, 0.1 * DVec3::Z)
    };
    let towards = if perpendicular {
        DVec3::new(0.07, 0.5, 0.0)
    } else {
        DVec3::new(0.0, 0.5, 0.5)
    };
    b.polygon_facing("lamp", lamp, lamp_polygon, towards);
    let polygon = b.scene.surfaces[1].vertices().to_vec();
    (b.scene, polygon)
}

#[test]
fn a_lamp_two_centimetres_from_a_wall_leaves_no_blotches() {
    for perpendicular in [false, true] {
        let (scene, lamp) = lamp_by_a_wall(perpendicular);
        let (mesh, radiosity) = solve(&scene, 0.02);
        let exitance = PI * LAMP_RADIANCE;
        let lamp_normal = isorad::internals::newell_normal(&lamp);
        let lamp_centre = lamp.iter().copied().sum::<DVec3>() / lamp.len() as f64;
        let (relative, absolute, checked) =
            worst_errors(&mesh, &radiosity, SurfaceId::new(0), |x| {
                // The lamp emits from its front only.
                if lamp_normal.dot(x - lamp_centre) <= 0.0 {
                    return 0.0;
                }
                WALL_REFLECTANCE * exitance * polygon_form_factor(x, DVec3::X, &lamp)
            });
        println!(
            "lamp 2 cm from a wall, {}: worst vertex error {relative:.5} relative \
             ({checked} vertices), {absolute:.5} of the peak elsewhere",
            if perpendicular {
                "perpendicular"
            } else {
                "parallel"
            }
        );
        assert!(checked > 100, "{checked} vertices checked");
        assert!(relative < 0.01, "worst relative error {relative}");
        assert!(
            absolute < 0.001,
            "worst absolute error {absolute} of the peak"
        );
    }
}

/// A 4 × 4 floor with a black unit cube standing on it at the origin and a
/// 1 m square lamp, facing down, 1.5 m up and 1 m beyond the cube's +x face.
/// Floor points in front of that face (x > 0.5, |y| < 0.5) see the whole
/// lamp past the cube, and only the lamp lights the floor.
fn block_lit_from_the_side() -> (Scene, Vec<DVec3>) {
    let mut b = SceneBuilder::default();
    let floor = b.material("floor", WALL_REFLECTANCE, 0.0);
    let black = b.material("black", 0.0, 0.0);
    let lamp = b.material("lamp", 0.0, LAMP_RADIANCE);
    b.polygon("floor", floor, square_z(-2.0, 2.0, 0.0, true));
    let corner = |k: usize, z: f64| {
        let (x, y) = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)][k % 4];
        DVec3::new(x, y, z)
    };
    let centre = DVec3::new(0.0, 0.0, 0.5);
    for k in 0..4 {
        let side = vec![
            corner(k, 0.0),
            corner(k + 1, 0.0),
            corner(k + 1, 1.0),
            corner(k, 1.0),
        ];
        let outward = 2.0 * (0.5 * (corner(k, 0.5) + corner(k + 1, 0.5))) - centre;
        b.polygon_facing("block", black, side, outward);
    }
    b.polygon("block", black, (0..4).map(|k| corner(k, 1.0)).collect());
    let lamp_polygon = vec![
        DVec3::new(1.5, -0.5, 1.5),
        DVec3::new(2.5, -0.5, 1.5),
        DVec3::new(2.5, 0.5, 1.5),
        DVec3::new(1.5, 0.5, 1.5),
    ];
    b.polygon_facing("lamp", lamp, lamp_polygon, DVec3::new(2.0, 0.0, 0.0));
    let polygon = b.scene.surfaces.last().unwrap().vertices().to_vec();
    (b.scene, polygon)
}

#[test]
fn floor_at_the_foot_of_a_block_matches_the_exact_factor() {
    let (scene, lamp) = block_lit_from_the_side();
    let (mesh, radiosity) = solve(&scene, 0.05);
    let exitance = PI * LAMP_RADIANCE;
    let (mut worst, mut worst_near, mut checked) = (0.0f64, 0.0f64, 0);
    for (vertex, &b) in mesh.vertices.iter().zip(&radiosity) {
        let x = vertex.receiver_position();
        if vertex.surface != SurfaceId::new(0) || x.x <= 0.5 || x.y.abs() >= 0.5 {
            continue;
        }
        let exact = WALL_REFLECTANCE * exitance * polygon_form_factor(x, DVec3::Z, &lamp);
        let error = (b - exact).abs() / exact;
        worst = worst.max(error);
        // Just outside the contact line: within 5 cm of the block's face.
        if x.x < 0.55 {
            worst_near = worst_near.max(error);
        }
        checked += 1;
    }
    println!(
        "floor in front of a block: worst vertex error {worst:.5} ({checked} vertices), \
         {worst_near:.5} within 5 cm of the contact"
    );
    assert!(checked > 100, "{checked} vertices checked");
    assert!(worst < 0.02, "worst relative error {worst}");
}
