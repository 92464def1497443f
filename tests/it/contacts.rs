//! Objects standing on surfaces: contact lines in the mesh, nothing hidden
//! kept, no darkness bleeding out from under a block.

use crate::support::*;
use glam::DVec3;
use isorad::{
    ProbeMode, Scene, Solver, SolverSettings, SurfaceId,
    mesh::{Mesh, SquareMeshSettings, mesh_square},
    scene::ProbePoint,
};

/// A 4 × 4 floor (z = 0) with a unit cube standing on it, centred at the
/// origin and turned by 20°, open at the bottom like the Cornell box's
/// blocks, under a light as large as the floor at z = 4.
fn block_on_floor() -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 20.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    let turn = 20f64.to_radians();
    let corner = |k: usize, z: f64| {
        let a = turn + std::f64::consts::FRAC_PI_2 * k as f64 + std::f64::consts::FRAC_PI_4;
        DVec3::new(a.cos() * 0.5f64.sqrt(), a.sin() * 0.5f64.sqrt(), z)
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
        b.polygon_facing("block", white, side, outward);
    }
    b.polygon("block", white, (0..4).map(|k| corner(k, 1.0)).collect());
    b.polygon("light", light, square_z(-2.0, 2.0, 4.0, false));
    b.scene
}

fn mesh_of(scene: &Scene) -> Mesh {
    let mut settings = SquareMeshSettings::for_scene(scene);
    settings.max_edge = 0.2;
    settings.patch_max_edge = 1.0;
    mesh_square(scene, &settings)
}

#[test]
fn the_floor_under_a_block_is_cut_out_along_the_contact_lines() {
    let scene = block_on_floor();
    let mesh = mesh_of(&scene);
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    mesh.validate(&areas).unwrap();
    let floor: f64 = mesh
        .elements
        .iter()
        .filter(|e| e.surface == SurfaceId::new(0))
        .map(|e| e.area)
        .sum();
    assert!(
        (floor - (16.0 - 1.0)).abs() < 1e-9,
        "floor elements cover {floor}"
    );
    // No floor vertex strictly inside the block's footprint (|rotated x|, |y| < 0.5).
    let turn = -20f64.to_radians();
    for v in mesh
        .vertices
        .iter()
        .filter(|v| v.surface == SurfaceId::new(0))
    {
        let p = v.position;
        let (x, y) = (
            p.x * turn.cos() - p.y * turn.sin(),
            p.x * turn.sin() + p.y * turn.cos(),
        );
        assert!(
            x.abs().max(y.abs()) > 0.5 - 1e-9,
            "vertex under the block at {p}"
        );
    }
    // The block's own faces are untouched grids.
    assert!(
        mesh.elements
            .iter()
            .filter(|e| e.surface != SurfaceId::new(0))
            .all(|e| !e.is_triangle)
    );
}

#[test]
fn no_darkness_bleeds_out_from_under_a_block() {
    let scene = block_on_floor();
    let mesh = mesh_of(&scene);
    let mut settings = SolverSettings::default();
    settings.tolerance = 1e-3;
    let mut solver = Solver::with_mesh(scene, mesh, settings).unwrap();
    solver.run();
    let solution = solver.solution_with_ambient();
    // Just outside each side of the block, the rendered mesh agrees with an
    // exact gather: the dark floor under the block no longer exists.
    let mut worst: f64 = 0.0;
    for k in 0..4 {
        let a = 20f64.to_radians() + std::f64::consts::FRAC_PI_2 * k as f64;
        for along in [-0.3, 0.0, 0.3] {
            let (c, s) = (a.cos(), a.sin());
            let p = DVec3::new(c * 0.52 - s * along, s * 0.52 + c * along, 0.0);
            let point = ProbePoint {
                position: p,
                normal: None,
                line: 1,
            };
            let exact = solution
                .probe(&point, ProbeMode::Gather)
                .unwrap()
                .radiosity
                .r;
            let shown = solution.probe(&point, ProbeMode::Mesh).unwrap().radiosity.r;
            worst = worst.max((shown - exact).abs() / exact);
        }
    }
    assert!(
        worst < 0.1,
        "mesh vs gather just outside the block: {worst}"
    );
}
