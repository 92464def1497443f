//! Which ambient term a solution carries ([`Ambient`]), and the
//! [`Solution`] a solver gives with it ([`crate::Solver::solution`]).

use crate::phase::PhaseReporter;
use crate::rgb::Rgb;
use crate::scene::Camera;
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::ambient::term::AmbientTerm;
use crate::solver::layout::CulledZones;
use crate::solver::reading::places::{ReadingPlace, zones_read};
use crate::solver::reading::solution::Solution;

/// Which ambient term a [`Solution`] carries
/// ([`crate::Solver::solution`]): the light not yet shot, gathered where
/// it will land, added to the light shot so far.
///
/// Every variant but [`Ambient::Omitted`] reports the term's progress
/// ([`crate::Phase::AmbientTerm`]), which takes minutes for a building;
/// nothing is reported when no light is left unshot (there is no
/// ambient term).
#[derive(Clone, Copy, Debug)]
pub enum Ambient<'p> {
    /// None: the solution from the light shot so far.
    Omitted,
    /// Everywhere: B_v + ρ_v G_v and H_v + G_v at every vertex, G_v the
    /// unshot light gathered along rays (a coarse final gather of what
    /// remains; see `solver/ambient/rays.rs`). What images and probes
    /// show.
    Everywhere,
    /// What readings at these places need (probes on surfaces, a
    /// calculation grid's points, a camera): where every place lies in a
    /// closed room (a zone that keeps its light, so that what is read
    /// there comes from that room alone), the ambient term is made for
    /// those rooms' vertices alone, and every other room holds the light
    /// shot so far. Where any place lies in no closed room, or no place
    /// is given, it is [`Ambient::Everywhere`]. A calculation grid on one
    /// office's work plane then costs that office's term, not the
    /// building's. Read the solution only at these places: elsewhere it
    /// lacks the light not yet shot, and [`Solution::probe`] refuses a
    /// point outside its rooms.
    For(&'p [ReadingPlace]),
    /// What an image from this camera needs: where the camera stands
    /// inside a closed room (a zone that keeps its light, whose walls hide
    /// the rest: [`Solution::triangles_seen_from`]), the ambient term is
    /// made for that room's vertices alone, and the other rooms hold the
    /// light shot so far; elsewhere it is [`Ambient::Everywhere`]. A view
    /// from one office of a building then costs that office's term (a
    /// second, where the building's is minutes). It is [`Ambient::For`]
    /// the camera's position, and its probes are refused outside the
    /// camera's room.
    SeenFrom(&'p Camera),
}

/// The solution of the solver whose parts are `term` with the `ambient`
/// term asked for, reporting its progress to `report`.
pub(crate) fn solution<'a>(
    term: &AmbientTerm<'a>,
    ambient: Ambient<'_>,
    report: PhaseReporter,
) -> Solution<'a> {
    match ambient {
        Ambient::Omitted => solution_from(term, AmbientIrradiance::Nowhere),
        Ambient::Everywhere => with_ambient_in(term, None, report),
        Ambient::For(places) => with_ambient_for(term, places, report),
        Ambient::SeenFrom(camera) => {
            with_ambient_for(term, &[ReadingPlace::InSpace(camera.position)], report)
        }
    }
}

/// The solution with the ambient term made in the closed rooms `places`
/// lie in ([`Ambient::For`]).
fn with_ambient_for<'a>(
    term: &AmbientTerm<'a>,
    places: &[ReadingPlace],
    report: PhaseReporter,
) -> Solution<'a> {
    let rooms = term
        .layout
        .zones
        .as_ref()
        .and_then(|CulledZones { zones, .. }| {
            let labels = zones.labels();
            (labels.count() > 1)
                .then(|| zones_read(labels, term.scene, term.visibility, places))
                .flatten()
        });
    with_ambient_in(term, rooms.as_deref(), report)
}

/// The solution with the ambient term made in the vertices of the zones
/// `only` lists, or in all by `None`.
fn with_ambient_in<'a>(
    term: &AmbientTerm<'a>,
    only: Option<&[usize]>,
    report: PhaseReporter,
) -> Solution<'a> {
    if term.light.unshot.iter().all(|b| *b == Rgb::ZERO) {
        return solution_from(term, AmbientIrradiance::Nowhere);
    }
    let ambient = term.irradiance(only, report);
    let mut solution = solution_from(term, ambient);
    if solution.zones.is_some() {
        solution.ambient_zones = only.map(<[usize]>::to_vec);
    }
    solution
}

/// A [`Solution`] of the scene, mesh and light shot of `term`'s solver,
/// with the `ambient` term added.
pub(crate) fn solution_from<'a>(
    term: &AmbientTerm<'a>,
    ambient: AmbientIrradiance,
) -> Solution<'a> {
    Solution {
        scene: term.scene,
        mesh: term.mesh,
        visibility: term.visibility,
        luminaires_shot: term.light.luminaire_shot.clone(),
        daylight: term
            .layout
            .daylight
            .as_ref()
            .filter(|_| term.light.daylight_shot),
        shot_irradiance: &term.light.irradiance,
        ambient,
        receiver_insets: &term.layout.receiver_insets,
        in_emitting_body: &term.layout.in_emitting_body,
        zones: term
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones.labels())
            .filter(|labels| labels.count() > 1),
        ambient_zones: None,
    }
}
