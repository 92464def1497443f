//! The ambient term's estimates averaged over each vertex's neighbours.
//!
//! A vertex's ambient irradiance G_v is a Monte Carlo estimate over its
//! 96 rays (see `solver/ambient/rays.rs`), and neighbouring vertices' estimates are
//! independent: seen pixel by pixel, the noise of a term that carries
//! half the light of a closed room (all its reflected light, in the
//! offices, after their lamps' shots). The light
//! it estimates, what surfaces some way off will still send, changes
//! slowly: over a distance d by about d / R of itself, R the harmonic mean
//! distance to where the rays land (Ward, Rubinstein & Clear 1988, the
//! irradiance cache's error bound). So each vertex takes the weighted mean
//! of its own estimate and its mesh neighbours' u,
//!
//! ```text
//!   G'_v = (G_v + Σ_u k_u G_u) / (1 + Σ_u k_u)
//!   k_u  = max(0, 1 − d_uv / (2 min(R_u, R_v))) · max(0, 1 − |S_u − S_v| / (3 σ_uv))
//! ```
//!
//! S the estimates' sums over the channels and σ_uv the standard error of
//! their difference, each bounded from its rays' strata collapsed in pairs
//! (Cochran 1977, §5A.12). The first factor keeps a vertex beside an
//! object, whose rays land close, from its neighbours further out; the
//! second keeps apart estimates that differ by more than their noise: the
//! wall just above a book standing 2 cm in front of it, lit by the book's
//! top, and the wall a little higher (`tests/it/contacts.rs`). A vertex
//! on its surface mesh's outline keeps its own estimate: its neighbours
//! lie on one side, and their mean leans toward the surface's interior (a
//! wall's foot toward its middle). Inside a regular grid a vertex's
//! neighbours surround it symmetrically, and the mean of a field that
//! changes linearly is its value there; where lattices meet, or in a
//! contour or contact triangulation, the weighted neighbours' centre
//! sits off the vertex, and the mean leans along the field's gradient by
//! a fraction of an element.
//!
//! Under a lamp not yet shot, the floor's estimates of its light are
//! about 22 % off on average (`tests/it/solver.rs`), less than half of
//! what the raw estimates are off.
//!
//! # References
//! G. J. Ward, F. M. Rubinstein, R. D. Clear, "A Ray Tracing Solution for
//! Diffuse Interreflection", SIGGRAPH 1988 (the error bound d / R, R the
//! harmonic mean distance of a sample's rays); W. G. Cochran, *Sampling
//! Techniques*, 3rd ed. (1977), §5A.12 (collapsed strata).

use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::solver::ambient::rays::AmbientEstimate;
use crate::solver::ambient::rooms::{LocalIndex, Room};

/// A neighbour's weight falls to 0 this many times the smaller of its and
/// the vertex's harmonic mean distance away: farther, the wall above a
/// book 2 cm in front of it strays from a gather (`tests/it/contacts.rs`).
pub(crate) const REACH: f64 = 2.0;

/// A neighbour's weight falls to 0 where its estimate differs from the
/// vertex's by this many standard errors of their difference.
pub(crate) const AGREEMENT: f64 = 3.0;

/// Each vertex's mesh neighbours in a room, and whether it lies on its
/// surface mesh's outline: what the averaging reads of the mesh. Vertices
/// are the room's (their places in [`Room::vertices`]).
#[derive(Clone, Debug)]
pub(crate) struct Neighbourhood {
    offsets: Vec<usize>,
    neighbours: Vec<u32>,
    outline: Vec<bool>,
}

impl Neighbourhood {
    /// The neighbourhood of every vertex of `room`, whose members `local`
    /// has entered: the other corners of the elements it is a corner of,
    /// and whether it ends an edge (between consecutive corners) that one
    /// element alone uses. Where elements split to different depths meet,
    /// the coarse side's edge is used once too: the T-junction's vertex and
    /// that edge's two ends count as outline. A room's elements use only
    /// its own vertices (a room is a set of whole surfaces).
    #[must_use]
    pub(crate) fn new(mesh: &Mesh, room: &Room, local: &LocalIndex) -> Neighbourhood {
        let number = |v: u32| local.vertex(v as usize).map(|i| i as u32);
        let (offsets, neighbours, outline) =
            mesh.neighbourhood_of(&room.elements, &number, room.vertices.len());
        Neighbourhood {
            offsets,
            neighbours,
            outline,
        }
    }
}

/// The ambient irradiance `estimates` of `room`'s vertices (in its order,
/// whose neighbourhood is `around`) averaged over each inner vertex's
/// neighbours, each weighted by its distance over the smaller harmonic
/// mean distance `harmonic_distance` and by how far the two estimates
/// differ over their noise (see the module docs).
#[must_use]
pub(crate) fn smoothed(
    mesh: &Mesh,
    room: &Room,
    around: &Neighbourhood,
    estimates: &[AmbientEstimate],
    harmonic_distance: &[f64],
) -> Vec<Rgb> {
    let Neighbourhood {
        offsets,
        neighbours,
        outline,
    } = around;
    let position = |i: usize| mesh.vertices[room.vertices[i] as usize].position;
    (0..estimates.len())
        .into_par_iter()
        .map(|v| {
            let own = estimates[v];
            let (Some(&from), Some(&to)) = (offsets.get(v), offsets.get(v + 1)) else {
                return own.irradiance;
            };
            if outline.get(v).is_none_or(|&on| on) {
                return own.irradiance;
            }
            let x = position(v);
            let reach = harmonic_distance.get(v).copied().unwrap_or(0.0);
            let (mut sum, mut weight) = (own.irradiance, 1.0);
            for &u in &neighbours[from..to] {
                let u = u as usize;
                let (Some(other), Some(&r)) = (estimates.get(u), harmonic_distance.get(u)) else {
                    continue;
                };
                let d = x.distance(position(u));
                let near = 1.0 - d / (REACH * r.min(reach));
                let noise = own.standard_error.hypot(other.standard_error);
                let gap = (other.irradiance.element_sum() - own.irradiance.element_sum()).abs();
                let alike = if gap == 0.0 {
                    1.0
                } else {
                    1.0 - gap / (AGREEMENT * noise)
                };
                let k = near.max(0.0) * alike.max(0.0);
                if k > 0.0 && k.is_finite() {
                    sum += other.irradiance * k;
                    weight += k;
                }
            }
            sum / weight
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SurfaceId;
    use glam::DVec3;

    /// Estimates of `values`, each with standard error `error` (of the sum
    /// of its channels).
    fn noisy(values: &[Rgb], error: f64) -> Vec<AmbientEstimate> {
        values
            .iter()
            .map(|&irradiance| AmbientEstimate {
                irradiance,
                standard_error: error,
            })
            .collect()
    }

    /// The whole mesh as one room, and its neighbourhood.
    fn whole(mesh: &Mesh) -> (Room, Neighbourhood) {
        let room = Room::whole(mesh);
        let mut local = LocalIndex::new(mesh);
        local.enter(&room);
        let around = Neighbourhood::new(mesh, &room, &local);
        (room, around)
    }

    /// An n × n grid of unit quads on the plane z = 0.
    fn grid(n: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for j in 0..=n {
            for i in 0..=n {
                mesh.add_vertex(
                    DVec3::new(f64::from(i), f64::from(j), 0.0),
                    SurfaceId::new(0),
                );
            }
        }
        let side = f64::from(n);
        let cell = crate::mesh::Cell::quad(
            DVec3::ZERO,
            DVec3::new(side, 0.0, 0.0),
            DVec3::new(side, side, 0.0),
            DVec3::new(0.0, side, 0.0),
        );
        let patch = mesh.add_patch(SurfaceId::new(0), cell);
        for j in 0..n {
            for i in 0..n {
                let v = |i: u32, j: u32| j * (n + 1) + i;
                mesh.add_element(&[v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)], patch);
            }
        }
        mesh
    }

    /// A room's neighbourhood, in its own indices, is the mesh's: the
    /// second of two grids on two surfaces, as a room of its own, has the
    /// grid's outline and neighbours, and those the whole mesh gives its
    /// vertices.
    #[test]
    fn a_rooms_neighbourhood_is_the_meshs() {
        let mut mesh = grid(3);
        let second = grid(4);
        let offset = mesh.vertices.len() as u32;
        for vertex in &second.vertices {
            mesh.add_vertex(vertex.position + DVec3::Z, SurfaceId::new(1));
        }
        let patch = mesh.add_patch(SurfaceId::new(1), second.patches[0].cell);
        for element in &second.elements {
            let corners: Vec<u32> = element.corners().iter().map(|&v| v + offset).collect();
            mesh.add_element(&corners, patch);
        }
        let rooms = Room::all(&mesh, 2, &|s| Some(s.index()));
        let mut local = LocalIndex::new(&mesh);
        local.enter(&rooms[1]);
        let around = Neighbourhood::new(&mesh, &rooms[1], &local);
        let (offsets, neighbours) = mesh.vertex_neighbours();
        let outline = mesh.outline_vertices();
        assert_eq!(rooms[1].vertices.len(), 25);
        // The 4 × 4 grid's 16 boundary vertices are its outline, and a
        // corner's neighbours are its quad's three other corners.
        assert_eq!(around.outline.iter().filter(|&&on| on).count(), 16);
        assert_eq!(
            &around.neighbours[around.offsets[0]..around.offsets[1]],
            &[1, 5, 6]
        );
        for (i, &v) in rooms[1].vertices.iter().enumerate() {
            let v = v as usize;
            let mut expected: Vec<u32> = neighbours[offsets[v]..offsets[v + 1]]
                .iter()
                .map(|&u| local.vertex(u as usize).expect("in the room") as u32)
                .collect();
            expected.sort_unstable();
            let got = &around.neighbours[around.offsets[i]..around.offsets[i + 1]];
            assert_eq!(got, expected.as_slice(), "vertex {v}");
            assert_eq!(around.outline[i], outline[v], "vertex {v}");
        }
    }

    /// A field linear in x and y comes out unchanged; the outline keeps
    /// its own values whatever they are.
    #[test]
    fn a_linear_field_is_kept_and_the_outline_untouched() {
        let mesh = grid(6);
        let (room, around) = whole(&mesh);
        let raw: Vec<Rgb> = mesh
            .vertices
            .iter()
            .map(|v| Rgb::splat(2.0 + 0.3 * v.position.x - 0.1 * v.position.y))
            .collect();
        let far = vec![100.0; raw.len()];
        let out = smoothed(&mesh, &room, &around, &noisy(&raw, 1.0), &far);
        for (v, (a, b)) in raw.iter().zip(&out).enumerate() {
            assert!((a.r - b.r).abs() < 1e-12, "vertex {v}: {a:?} → {b:?}");
        }
        // A corner far off the field: it keeps its value, and its inner
        // neighbour, which it pulls, is the only other to move.
        let mut spiked = raw.clone();
        spiked[0] = Rgb::splat(40.0);
        let out = smoothed(&mesh, &room, &around, &noisy(&spiked, 100.0), &far);
        let moved: Vec<usize> = (0..raw.len())
            .filter(|&v| (out[v].r - raw[v].r).abs() > 1e-9)
            .collect();
        assert_eq!(moved, [0, 8]);
        assert_eq!(out[0], spiked[0]);
    }

    /// A vertex whose rays land close (an object beside it) is neither
    /// averaged with its neighbours nor averaged into theirs, however far
    /// theirs land: the smaller of the two distances sets the reach.
    #[test]
    fn a_vertex_whose_rays_land_close_keeps_to_itself() {
        let mesh = grid(6);
        let (room, around) = whole(&mesh);
        let raw: Vec<Rgb> = (0..mesh.vertices.len())
            .map(|v| Rgb::splat(1.0 + 0.01 * v as f64))
            .collect();
        // Vertex (3, 3), its rays landing 0.1 away; the others' 100 away.
        let close = 3 * 7 + 3;
        let mut distances = vec![100.0; raw.len()];
        distances[close] = 0.1;
        let out = smoothed(&mesh, &room, &around, &noisy(&raw, 1.0), &distances);
        assert_eq!(out[close], raw[close]);
        let alone = distances.iter().map(|_| 100.0).collect::<Vec<_>>();
        let with = smoothed(&mesh, &room, &around, &noisy(&raw, 1.0), &alone);
        for neighbour in [close - 1, close + 1, close - 7, close + 7] {
            assert_ne!(
                out[neighbour], with[neighbour],
                "{neighbour} still takes it"
            );
            assert_ne!(
                out[neighbour], raw[neighbour],
                "{neighbour} averages nothing"
            );
        }
    }

    /// Independent noise on the inner vertices, uniform in ±0.5 on each
    /// channel (a standard error of 0.87 on their sum), reported as 0.9:
    /// its variance falls by more than 4 (nine estimates, the neighbours
    /// weighed by how far they stand apart over the noise); with the rays
    /// landing close (R small against the grid's spacing) nothing is
    /// averaged, nor where the estimates claim no noise.
    #[test]
    fn noise_averages_out_where_the_rays_land_far() {
        let mesh = grid(40);
        let mut state = 7u64;
        let raw: Vec<Rgb> = (0..mesh.vertices.len())
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                Rgb::splat(1.0 + ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5))
            })
            .collect();
        let inner: Vec<usize> = (0..mesh.vertices.len())
            .filter(|&v| {
                let p = mesh.vertices[v].position;
                p.x > 0.0 && p.x < 40.0 && p.y > 0.0 && p.y < 40.0
            })
            .collect();
        let variance = |values: &[Rgb]| {
            let mean = inner.iter().map(|&v| values[v].r).sum::<f64>() / inner.len() as f64;
            inner
                .iter()
                .map(|&v| (values[v].r - mean).powi(2))
                .sum::<f64>()
                / inner.len() as f64
        };
        let (room, around) = whole(&mesh);
        // Estimates of standard error `error`, their rays landing `reach` off.
        let smooth = |error: f64, reach: f64| {
            smoothed(
                &mesh,
                &room,
                &around,
                &noisy(&raw, error),
                &vec![reach; raw.len()],
            )
        };
        let far = smooth(0.9, 50.0);
        assert!(
            variance(&far) < variance(&raw) / 4.0,
            "{} against {}",
            variance(&far),
            variance(&raw)
        );
        assert_eq!(smooth(0.9, 0.2), raw);
        // Nor where the estimates claim no noise: their differences are real.
        assert_eq!(smooth(0.0, 50.0), raw);
    }
}
