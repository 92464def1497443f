//! Probes: the solution read at points, against analytic references.

use crate::support::*;
use glam::DVec3;
use isorad::{
    Ambient, ProbeMode, Scene, Solver, SolverSettings, SurfaceId,
    mesh::{Mesh, SquareMeshSettings, mesh_square},
    phase::silent,
    scene::ProbePoint,
};
use std::f64::consts::PI;

const RADIUS: f64 = 1.0;
const HEIGHT: f64 = 2.0;
const LIGHT_RADIANCE: f64 = 10.0;
const FLOOR_REFLECTANCE: f64 = 0.5;

/// A 64-gon emitter (ρ = 0) facing down over a floor, and optionally a black
/// blocker half-way.
fn disc_scene(blocker: bool) -> Scene {
    let mut b = SceneBuilder::default();
    let floor = b.material("floor", FLOOR_REFLECTANCE, 0.0);
    let light = b.material("light", 0.0, LIGHT_RADIANCE);
    let black = b.material("black", 0.0, 0.0);
    b.polygon("floor", floor, square_z(-10.0, 10.0, 0.0, true));
    b.polygon(
        "light",
        light,
        disc_facing_down(64, RADIUS, DVec3::new(0.0, 0.0, HEIGHT)),
    );
    if blocker {
        b.polygon("blocker", black, square_z(-1.0, 1.0, 1.0, false));
    }
    b.scene
}

fn solve(scene: &Scene, run: impl FnOnce(&Solver)) {
    let mut mesh_settings = SquareMeshSettings::for_scene(scene);
    mesh_settings.max_edge = 0.5;
    mesh_settings.patch_max_edge = 2.0;
    let mesh: Mesh = mesh_square(scene, &mesh_settings);
    let mut settings = SolverSettings::default();
    settings.tolerance = 1e-3;
    let mut solver = Solver::with_mesh(scene.clone(), mesh, settings).unwrap();
    solver.run();
    run(&solver);
}

fn at(x: f64, y: f64) -> ProbePoint {
    ProbePoint {
        position: DVec3::new(x, y, 0.0),
        normal: None,
        line: 1,
    }
}

#[test]
fn gather_matches_the_exact_disc_formula() {
    let scene = disc_scene(false);
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Everywhere, &silent);
        for x in [0.0, 0.3, 0.77, 1.0, 1.9, 3.3, 5.0] {
            let probe = solution.probe(&at(x, 0.1), ProbeMode::Gather).unwrap();
            let r = (x * x + 0.01_f64).sqrt();
            let expected = PI * LIGHT_RADIANCE * coaxial_disc_form_factor(RADIUS, HEIGHT, r);
            let error = (probe.irradiance.r - expected).abs() / expected;
            assert!(
                error < 0.005,
                "x = {x}: irradiance {} vs {expected} ({error:e})",
                probe.irradiance.r
            );
            let radiosity = FLOOR_REFLECTANCE * expected;
            assert!((probe.radiosity.r - radiosity).abs() < 0.005 * radiosity);
        }
    });
}

#[test]
fn gather_gradient_agrees_with_finite_differences() {
    let scene = disc_scene(false);
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Everywhere, &silent);
        let value = |x: f64, y: f64| {
            solution
                .probe(&at(x, y), ProbeMode::Gather)
                .unwrap()
                .radiosity
                .r
        };
        for (x, y) in [(0.4, 0.2), (1.3, -0.7), (2.5, 1.5), (-3.0, 0.5)] {
            let probe = solution.probe(&at(x, y), ProbeMode::Gather).unwrap();
            let h = 1e-4;
            let fd = DVec3::new(
                (value(x + h, y) - value(x - h, y)) / (2.0 * h),
                (value(x, y + h) - value(x, y - h)) / (2.0 * h),
                0.0,
            );
            let g = probe.gradient[0];
            assert!(
                (g - fd).length() <= 1e-4 * fd.length() + 1e-9,
                "({x}, {y}): {g} vs {fd}"
            );
            assert!(g.z.abs() < 1e-12, "the gradient lies in the floor's plane");
        }
    });
}

#[test]
fn a_shadowed_point_gets_no_direct_light() {
    let scene = disc_scene(true);
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Omitted, &silent);
        for mode in [ProbeMode::Gather, ProbeMode::Mesh] {
            let probe = solution.probe(&at(0.05, -0.1), mode).unwrap();
            assert_eq!(probe.irradiance, isorad::Rgb::ZERO, "{mode:?}");
        }
        let lit = solution.probe(&at(6.0, 0.0), ProbeMode::Gather).unwrap();
        assert!(lit.irradiance.r > 0.0);
    });
}

#[test]
fn mesh_mode_interpolates_vertices_and_has_the_interpolant_gradient() {
    let scene = disc_scene(false);
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Everywhere, &silent);
        let mesh = solution.mesh;
        // At a vertex, the value is the vertex's.
        let (index, vertex) = mesh
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| {
                v.surface == SurfaceId::new(0) && v.position.x > 1.0 && v.position.y > 1.0
            })
            .unwrap();
        let probe = solution
            .probe(
                &ProbePoint {
                    position: vertex.position,
                    normal: None,
                    line: 1,
                },
                ProbeMode::Mesh,
            )
            .unwrap();
        assert!(
            (probe.radiosity - solution.radiosity_at(index))
                .abs()
                .max_element()
                < 1e-12
        );
        // Inside one triangle the value is linear: the gradient predicts a small step exactly.
        let p = DVec3::new(1.61, 1.13, 0.0);
        let probe = solution
            .probe(
                &ProbePoint {
                    position: p,
                    normal: None,
                    line: 1,
                },
                ProbeMode::Mesh,
            )
            .unwrap();
        let step = DVec3::new(1e-3, -5e-4, 0.0);
        let moved = solution
            .probe(
                &ProbePoint {
                    position: p + step,
                    normal: None,
                    line: 1,
                },
                ProbeMode::Mesh,
            )
            .unwrap();
        let predicted = probe.radiosity.r + probe.gradient[0].dot(step);
        assert!(
            (moved.radiosity.r - predicted).abs() < 1e-9 * probe.radiosity.r,
            "{} vs {predicted}",
            moved.radiosity.r
        );
    });
}

#[test]
fn a_point_on_no_surface_is_an_error_naming_its_line() {
    let scene = disc_scene(false);
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Everywhere, &silent);
        let point = ProbePoint {
            position: DVec3::new(0.0, 0.0, 0.5),
            normal: None,
            line: 7,
        };
        let message = solution
            .probe(&point, ProbeMode::Gather)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(":7:") && message.contains("no surface"),
            "{message}"
        );
        // The right place but facing the wrong way.
        let point = ProbePoint {
            position: DVec3::new(0.0, 0.0, 0.0),
            normal: Some(-DVec3::Z),
            line: 9,
        };
        assert!(solution.probe(&point, ProbeMode::Gather).is_err());
    });
}

/// A 0.2 m square lamp (ρ = 0) facing down 1.6 m over a black floor, and a
/// black table top 0.8 m below it whose edge x = 0 runs parallel to the
/// lamp's edges: a floor point (x, 0, 0) sees the part x_e ≥ −x of the lamp,
/// so the penumbra spans −0.1 < x < 0.1.
const LAMP_HALF: f64 = 0.1;
const LAMP_HEIGHT: f64 = 1.6;

fn penumbra_scene() -> Scene {
    let mut b = SceneBuilder::default();
    let black = b.material("black", 0.0, 0.0);
    let light = b.material("light", 0.0, LIGHT_RADIANCE);
    b.polygon("floor", black, square_z(-3.0, 3.0, 0.0, true));
    b.polygon("lamp", light, lamp_polygon(-LAMP_HALF));
    b.polygon(
        "table",
        black,
        vec![
            DVec3::new(-2.0, -2.0, 0.8),
            DVec3::new(0.0, -2.0, 0.8),
            DVec3::new(0.0, 2.0, 0.8),
            DVec3::new(-2.0, 2.0, 0.8),
        ],
    );
    b.scene
}

/// The part x ≥ `from` of the lamp, facing down.
fn lamp_polygon(from: f64) -> Vec<DVec3> {
    let from = from.clamp(-LAMP_HALF, LAMP_HALF);
    vec![
        DVec3::new(from, -LAMP_HALF, LAMP_HEIGHT),
        DVec3::new(from, LAMP_HALF, LAMP_HEIGHT),
        DVec3::new(LAMP_HALF, LAMP_HALF, LAMP_HEIGHT),
        DVec3::new(LAMP_HALF, -LAMP_HALF, LAMP_HEIGHT),
    ]
}

/// The exact irradiance at (x, 0, 0): π L times Lambert's factor of the
/// visible part of the lamp.
fn exact_penumbra(x: f64) -> f64 {
    if -x >= LAMP_HALF {
        return 0.0;
    }
    PI * LIGHT_RADIANCE
        * isorad::radiometry::polygon_form_factor(
            DVec3::new(x, 0.0, 0.0),
            DVec3::Z,
            &lamp_polygon(-x),
        )
}

#[test]
fn gather_resolves_a_penumbra_against_the_exact_visible_lamp() {
    let scene = penumbra_scene();
    solve(&scene, |solver| {
        let solution = solver.solution(Ambient::Omitted, &silent);
        let maximum = exact_penumbra(1.0);
        let xs: Vec<f64> = (-100..=110)
            .step_by(5)
            .map(|k| f64::from(k) * 1e-3)
            .collect();
        let start = std::time::Instant::now();
        let probes: Vec<_> = xs
            .iter()
            .map(|&x| solution.probe(&at(x, 0.0), ProbeMode::Gather).unwrap())
            .collect();
        let per_probe = start.elapsed().as_secs_f64() / xs.len() as f64;
        let (mut worst, mut failures) = (0.0_f64, Vec::new());
        for (&x, probe) in xs.iter().zip(&probes) {
            let exact = exact_penumbra(x);
            if exact < 0.02 * maximum {
                continue;
            }
            let (value, error) = (probe.irradiance.r, probe.standard_error.r);
            let relative = (value - exact).abs() / exact;
            worst = worst.max(relative);
            if !(relative < 0.01 || ((value - exact).abs() < 3.0 * error && error <= 0.005 * exact))
            {
                failures.push(format!(
                    "x = {x}: irradiance {value} ± {error} vs exact {exact} ({relative:.2e})"
                ));
            }
        }
        eprintln!(
            "penumbra: worst relative error {worst:.2e}, {:.2} ms per probe",
            per_probe * 1e3
        );
        assert!(failures.is_empty(), "{}", failures.join("\n"));
        // The jitter is keyed by the point: probing again gives the same bits.
        let again = solution.probe(&at(xs[3], 0.0), ProbeMode::Gather).unwrap();
        assert_eq!(again, probes[3]);
        // Fully lit and fully hidden points sample nothing uncertain.
        for x in [-0.3, 0.5] {
            let probe = solution.probe(&at(x, 0.0), ProbeMode::Gather).unwrap();
            assert_eq!(probe.standard_error, isorad::Rgb::ZERO, "x = {x}");
        }
    });
}
