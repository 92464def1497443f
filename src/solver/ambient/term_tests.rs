//! Tests of the ambient term made room by room from a solver's parts
//! (`term.rs`): kept and streamed rays, one room's term among all, and
//! refined rooms.

use crate::meshing::MeshKind;
use crate::phase::silent;
use crate::rgb::Rgb;
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::test_scenes::two_closed_rooms;
use crate::solver::{Settings, Solver};

/// `solver`'s ambient term, its rays kept or not, in the zones `only`
/// lists or all.
fn term(solver: &Solver, keep: bool, only: Option<&[usize]>) -> AmbientIrradiance {
    solver
        .ambient_term()
        .irradiance_keeping(keep, only, &silent)
}

/// The ambient term made room by room is the same whether the rooms'
/// rays are kept between images or cast for each and dropped, and
/// each room's rays stay in it: the second room, lit twice as
/// brightly, gets twice the first's light within the rays' noise.
#[test]
fn rooms_kept_or_cast_again_give_the_same_ambient_term() {
    let mut settings = Settings::default();
    settings.mesh.max_edge = crate::Length::Absolute(0.5);
    let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
    assert!(solver.closed_zones() >= 2, "{}", solver.closed_zones());
    // Both lamps' shots: half the rooms' light is still unshot.
    solver.step();
    solver.step();
    let streamed = term(&solver, false, None);
    let kept = term(&solver, true, None);
    let again = term(&solver, true, None);
    assert!(streamed == kept, "kept and streamed rays differ");
    assert!(kept == again, "the kept rays changed");
    let kept = kept.at_every(solver.mesh().vertices.len());
    // Σ A G over the elements of the room from x0 to x0 + 4.
    let room_total = |x0: f64| -> f64 {
        let mesh = solver.mesh();
        let in_room = |x: f64| (x0 - 0.1..=x0 + 4.1).contains(&x);
        mesh.elements
            .iter()
            .filter(|e| in_room(mesh.vertices[e.vertices[0] as usize].position.x))
            .map(|e| e.corner_mean(|v| kept[v as usize]).element_sum() * e.area)
            .sum()
    };
    let (a, b) = (room_total(0.0), room_total(5.0));
    assert!(a > 0.0 && (2.0 * a - b).abs() < 0.01 * b, "{a} against {b}");
}

/// A term made in one room between two made in all keeps the other
/// rooms' rays and changes nothing: the rays found again by their
/// vertices, the patches' rays cast for the one room kept with the
/// rest.
#[test]
fn one_rooms_term_keeps_the_other_rooms_rays() {
    let mut settings = Settings::default();
    settings.mesh.max_edge = crate::Length::Absolute(0.5);
    let mut solver = Solver::new(two_closed_rooms(), settings.clone()).expect("a valid scene");
    solver.step();
    solver.step();
    let zones = solver
        .ambient_term()
        .layout
        .zones
        .as_ref()
        .map(|culled| culled.zones.labels().clone());
    let zones = zones.expect("closed zones");
    let zone_of = |v: usize| zones.of(solver.mesh().vertices[v].surface);
    let room = zone_of(0);
    let one = term(&solver, true, Some(&[room]));
    let rays = |s: &Solver| {
        let state = s.ambient_term().state;
        state.rays.lock().map(|c| c.rooms.len()).unwrap_or(0)
    };
    assert_eq!(rays(&solver), 1, "one room's rays cast");
    let all = term(&solver, true, None);
    let kept = rays(&solver);
    let one_again = term(&solver, true, Some(&[room]));
    assert_eq!(rays(&solver), kept, "the other rooms' rays dropped");
    let all_again = term(&solver, true, None);
    assert!(all == all_again && one == one_again);
    let count = solver.mesh().vertices.len();
    let (one_at, all_at) = (one.at_every(count), all.at_every(count));
    for (v, g) in one_at.iter().enumerate() {
        if zone_of(v) == room {
            assert!((*g - all_at[v]).abs().max_element() <= 1e-6 * all_at[v].max_element());
        } else {
            assert_eq!(*g, Rgb::ZERO);
        }
    }
    assert!(
        matches!(one, AmbientIrradiance::At { .. }),
        "one room's term alone"
    );
    // The whole term is the one a solver that never drew one room
    // makes, streamed or kept: the rays do not depend on the order.
    let mut fresh = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
    fresh.step();
    fresh.step();
    assert!(all == term(&fresh, false, None));
    assert!(all == term(&fresh, true, None));
}

/// An adaptive mesh's rooms keep the rays of the rooms whose vertices
/// stay as they were and cast those of the rooms refinement grows: the
/// term is what rays all cast afresh give.
#[test]
fn refined_rooms_cast_their_new_vertices_rays() {
    let mut settings = Settings::default();
    settings.mesh.max_edge = crate::Length::Absolute(0.5);
    settings.mesh.kind = MeshKind::Adaptive;
    let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
    let before = solver.mesh().vertices.len();
    let _ = term(&solver, true, None);
    for _ in 0..4 {
        solver.step();
    }
    assert!(
        solver.mesh().vertices.len() > before,
        "{before} vertices, none added"
    );
    let kept = term(&solver, true, None);
    let streamed = term(&solver, false, None);
    assert!(
        kept == streamed,
        "kept and streamed rays differ after refinement"
    );
    let count = solver.mesh().vertices.len();
    assert!(kept.at_every(count).iter().any(|g| g.element_sum() > 0.0));
}
