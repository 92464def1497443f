//! Patch shots: the light the vertices' shots leave, shot patch to patch
//! until the tolerance (`src/solver/patch_shots.rs`).

use crate::support::*;
use glam::DVec3;
use isorad::{Ambient, Rgb, Settings, Solver, StopReason, phase::silent};

/// Two closed rooms, each with a block on its floor and a lamp under its
/// ceiling, meshed at 0.5 m in patches of 1 m and solved at the default
/// solver settings but for `patch_tolerance`.
fn two_rooms(patch_tolerance: f64) -> Solver {
    let mut b = SceneBuilder::default();
    let wall = b.material("wall", 0.6, 0.0);
    let lamp = b.material("lamp", 0.0, 10.0);
    for room in 0..2 {
        let offset = DVec3::new(10.0 * f64::from(room), 0.0, 0.0);
        room_with_block(&mut b, wall, &format!("{room}"), offset);
        ceiling_lamp(&mut b, lamp, offset);
    }
    solved(b.scene, |solver| solver.patch_tolerance = patch_tolerance)
}

/// `scene` meshed at 0.5 m in patches of 1 m and solved to convergence at
/// the default solver settings but for what `adjust` changes.
fn solved(scene: isorad::Scene, adjust: impl FnOnce(&mut isorad::SolverSettings)) -> Solver {
    let mut settings = Settings::default();
    settings.mesh.max_edge = isorad::Length::Absolute(0.5);
    settings.mesh.patch_max_edge = isorad::Length::Absolute(1.0);
    adjust(&mut settings.solver);
    let mut solver = Solver::new(scene, settings).unwrap();
    assert_eq!(solver.run(), StopReason::Converged);
    solver
}

/// The closed rooms stop their vertices' shots at about half their light
/// unshot (counted at a tenth); the patch shots carry it to under 1 %,
/// and the ledger still closes: what they took off the unshot power is
/// absorbed, none of it escapes from rooms that keep their light.
#[test]
fn patch_shots_carry_the_light_left_to_the_tolerance_and_close_the_ledger() {
    let (alone, with) = (two_rooms(1.0), two_rooms(0.01));
    assert!(alone.patch_shot_summary().is_none());
    let summary = with.patch_shot_summary().expect("patch shots");
    println!("{summary:?}");
    assert_eq!(summary.unshot_before, alone.unshot_fraction());
    assert!(summary.unshot_before > 0.3, "{summary:?}");
    assert!(
        summary.unshot_after <= 0.01 && summary.sweeps >= 2,
        "{summary:?}"
    );
    assert_eq!(with.unshot_fraction(), summary.unshot_after);
    // The vertices' shots are the same.
    assert_eq!(with.radiosity(), alone.radiosity());
    let (ledger, before) = (with.energy_balance(), alone.energy_balance());
    let sum = ledger.absorbed + ledger.unshot + ledger.escaped;
    assert!((sum - ledger.emitted).abs().max_element() < 1e-9 * ledger.emitted.max_element());
    let emitted = ledger.emitted.element_sum();
    assert!((ledger.unshot.element_sum() / emitted - summary.unshot_after).abs() < 1e-12);
    let taken = before.unshot - ledger.unshot;
    let absorbed = ledger.absorbed - before.absorbed;
    let escaped = ledger.escaped - before.escaped;
    assert!((absorbed + escaped - taken).abs().max_element() < 1e-9 * emitted);
    assert!(
        escaped.max_element() < 1e-3 * taken.max_element(),
        "{escaped}"
    );
    // 2 to 32 rays a node, a budget of 8, in each zone that holds unshot
    // power (a zone without any casts none). These rooms have no small
    // patches to cluster (the blocks' faces are a quarter of a patch), so
    // each node is a patch.
    assert_eq!((summary.clusters, summary.clustered_patches), (0, 0));
    let patches = with.mesh().patches.len();
    let rays = summary.rays as usize;
    assert!(rays >= 2 * patches && rays <= 32 * patches, "{rays} rays");
}

/// A shot after the patch shots drops them, since they were made of the
/// unshot power it changes; the next run that converges makes them anew.
#[test]
fn a_shot_after_the_patch_shots_drops_them() {
    let mut solver = two_rooms(0.01);
    let made = solver.patch_shot_summary().expect("patch shots");
    let before = solver.convergence_fraction();
    assert!(solver.step());
    assert!(solver.patch_shot_summary().is_none());
    assert!(solver.unshot_fraction() > 0.3);
    assert!(solver.convergence_fraction() < before);
    solver.shoot_patches();
    let again = solver.patch_shot_summary().expect("patch shots again");
    assert!(again.unshot_before < made.unshot_before && again.unshot_after <= 0.01);
}

/// The rooms' ambient term reads what the patch shots gave each patch:
/// carried to a ten-thousandth, the rooms' images get the light the
/// ambient term's own patch iteration finds without them, to the noise of
/// their few rays; stopped at a fifth (one sweep), they lack the further
/// bounces of what is left, which the term no longer finds itself.
#[test]
fn the_ambient_term_reads_the_patch_shots() {
    let mean = |solver: &Solver| {
        let radiosity = solver.solution(Ambient::Everywhere, &silent).radiosity();
        radiosity.iter().copied().sum::<Rgb>().element_sum() / radiosity.len() as f64
    };
    let alone = two_rooms(1.0);
    let (a, b, c) = (mean(&alone), mean(&two_rooms(1e-4)), mean(&two_rooms(0.2)));
    let shot = alone.radiosity().iter().copied().sum::<Rgb>().element_sum()
        / alone.mesh().vertices.len() as f64;
    println!(
        "mean radiosity: {a:.4} without patch shots, {b:.4} with them to 1e-4, {c:.4} to 0.2, \
         {shot:.4} shot at the vertices"
    );
    assert!((a - b).abs() < 0.01 * a, "{a} against {b}");
    assert!(b > 1.1 * shot);
    // Read from the term's own iteration, all three would be the same.
    assert!(a != b && c < b, "{c} against {b}");
}

/// A run stopped short (at a shot limit, as the CLI's previews stop)
/// makes no patch shots; one that converges does.
#[test]
fn only_a_run_that_converges_makes_patch_shots() {
    let mut solver = two_rooms(1e-4);
    assert!(solver.patch_shot_summary().is_some());
    let limit = isorad::Until::default()
        .tolerance(0.0)
        .total_shots(solver.stats().shots + 1);
    assert_eq!(solver.run_until(&limit, |_| {}), StopReason::ShotLimit);
    assert!(solver.patch_shot_summary().is_none());
}

/// One closed room of [`room_with_block`] with its lamp, and a shelf of
/// 24 books (3 × 25 × 20 cm, two colours) standing on the floor along a
/// wall, solved at the default settings but for the patch clusters.
fn room_with_books(patch_clusters: bool) -> Solver {
    let mut b = SceneBuilder::default();
    let wall = b.material("wall", 0.6, 0.0);
    let lamp = b.material("lamp", 0.0, 10.0);
    let books = [b.material("red", 0.5, 0.0), b.material("cream", 0.8, 0.0)];
    room_with_block(&mut b, wall, "0", DVec3::ZERO);
    ceiling_lamp(&mut b, lamp, DVec3::ZERO);
    for k in 0..24 {
        let corner = DVec3::new(0.5 + 0.032 * f64::from(k), 0.0, 0.01);
        for face in box_faces(DVec3::new(0.03, 0.25, 0.2)) {
            let mut face: Vec<DVec3> = face.into_iter().map(|p| p + corner).collect();
            face.reverse();
            b.polygon("book", books[k as usize % 2], face);
        }
    }
    solved(b.scene, |solver| solver.patch_clusters = patch_clusters)
}

/// The books' small faces shoot and receive as a few clusters (spines,
/// tops and each side facing one way): the patch shots cast fewer rays
/// for the same light, and the ledger closes with the clusters' pooled
/// power.
#[test]
fn a_shelf_of_books_shoots_as_a_few_clusters() {
    let (alone, clustered) = (room_with_books(false), room_with_books(true));
    let (a, c) = (
        alone.patch_shot_summary().expect("patch shots"),
        clustered.patch_shot_summary().expect("patch shots"),
    );
    println!("{a:?}\n{c:?}");
    assert_eq!((a.clusters, a.clustered_patches), (0, 0));
    // 24 books of three faces in sight each (their bottoms stand on the
    // floor, their sides 2 mm apart hide each other) in a cluster or two
    // a direction: the spines, the tops and the backs against the wall
    // (the row crosses a cube of the patch edge).
    assert!(c.clustered_patches >= 3 * 24, "{c:?}");
    assert!(c.clusters <= 6, "{c:?}");
    assert!(c.rays + 150 < a.rays, "{} against {} rays", c.rays, a.rays);
    assert!(c.unshot_after <= 1e-4 && a.unshot_after <= 1e-4);
    let ledger = clustered.energy_balance();
    let sum = ledger.absorbed + ledger.unshot + ledger.escaped;
    assert!((sum - ledger.emitted).abs().max_element() < 1e-9 * ledger.emitted.max_element());
    // The same light, to the noise of the patch shots' few rays (measured
    // 0.01 %): over the room, and on the books themselves.
    let mean = |solver: &Solver, of: &dyn Fn(&str) -> bool| {
        let radiosity = solver.solution(Ambient::Everywhere, &silent).radiosity();
        let (scene, mesh) = (solver.scene(), solver.mesh());
        let (sum, count) = mesh
            .vertices
            .iter()
            .zip(&radiosity)
            .filter(|(v, _)| of(&scene.surface(v.surface).name))
            .fold((0.0, 0usize), |(s, n), (_, b)| (s + b.element_sum(), n + 1));
        sum / count as f64
    };
    let room = |name: &str| name != "lamp";
    let book = |name: &str| name == "book";
    for of in [&room as &dyn Fn(&str) -> bool, &book] {
        let (a, c) = (mean(&alone, of), mean(&clustered, of));
        println!("mean radiosity {a:.4} alone, {c:.4} clustered");
        assert!((a - c).abs() < 0.001 * a, "{a} against {c}");
    }
    // The clusters' extent is the patch edge the mesh was asked for.
    let edge = clustered.mesh().longest_patch_edge();
    assert!(edge > 0.9 && edge <= 1.0 + 1e-9, "{edge}");
}
