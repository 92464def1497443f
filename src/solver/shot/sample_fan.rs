//! A patch's sample vertices for coarse reception: the vertices nearest its
//! corners and its centre, the fan of triangles they span in the patch's
//! plane, and every other vertex's weights over them.

use glam::{DVec2, DVec3};

use crate::mesh::{Cell, Mesh};

/// The most sample vertices a patch has: one per corner and its centre.
const SAMPLES: usize = 5;

/// A patch samples a shot at a fan of samples only when it has at least
/// this many vertices per sample; with fewer, at its centre alone.
const VERTICES_PER_SAMPLE: usize = 2;

/// Weights over three sample vertices (summing to 1), in single precision
/// to keep a vertex's record small.
pub(crate) type SampleWeights = [(u32, f32); 3];

/// A patch's sample vertices and the fan of triangles they span, in the
/// patch's plane.
pub(crate) struct SampleFan {
    /// Sample vertices and their plane coordinates.
    samples: Vec<(u32, DVec2)>,
    /// Triangles of samples (indices into `samples`).
    triangles: Vec<[usize; 3]>,
    /// The plane's origin and axes.
    frame: (DVec3, DVec3, DVec3),
}

impl SampleFan {
    /// The samples of a patch of shape `cell` with `vertices`: the vertex
    /// nearest each corner and the one nearest the centre, spanning a fan
    /// of triangles, when there are three or more distinct ones and
    /// [`VERTICES_PER_SAMPLE`] vertices per sample; else the vertex nearest
    /// the centre alone, whose value the others take (a book's spine); None
    /// for a patch of one vertex.
    pub(crate) fn new(mesh: &Mesh, cell: &Cell, vertices: &[u32]) -> Option<SampleFan> {
        let corners = cell.polygon();
        let nearest = |point: DVec3| {
            vertices.iter().copied().min_by(|&a, &b| {
                let da = mesh.vertices[a as usize]
                    .receiver_position()
                    .distance_squared(point);
                let db = mesh.vertices[b as usize]
                    .receiver_position()
                    .distance_squared(point);
                da.total_cmp(&db).then(a.cmp(&b))
            })
        };
        let centre = nearest(cell.centre())?;
        if vertices.len() < 2 {
            return None;
        }
        let origin = corners[0];
        let u = (corners[1] - origin).normalize_or_zero();
        let normal = (corners[1] - origin).cross(corners[2] - origin);
        let v = normal.cross(u).normalize_or_zero();
        let frame = (origin, u, v);
        let to_plane = |s: u32| {
            let d = mesh.vertices[s as usize].receiver_position() - origin;
            DVec2::new(d.dot(u), d.dot(v))
        };
        let constant = SampleFan {
            samples: vec![(centre, to_plane(centre))],
            triangles: Vec::new(),
            frame,
        };
        if u == DVec3::ZERO || v == DVec3::ZERO {
            return Some(constant);
        }
        let mut corner_samples: Vec<u32> = Vec::with_capacity(SAMPLES);
        for &corner in corners {
            let s = nearest(corner)?;
            if !corner_samples.contains(&s) {
                corner_samples.push(s);
            }
        }
        let with_centre = !corner_samples.contains(&centre);
        let count = corner_samples.len() + usize::from(with_centre);
        let spans = corner_samples.len() >= 3 || (with_centre && corner_samples.len() == 2);
        if !spans || vertices.len() < VERTICES_PER_SAMPLE * count {
            return Some(constant);
        }
        let mut samples: Vec<(u32, DVec2)> =
            corner_samples.iter().map(|&s| (s, to_plane(s))).collect();
        let ring = samples.len();
        let triangles: Vec<[usize; 3]> = if with_centre {
            samples.push((centre, to_plane(centre)));
            (0..ring)
                .filter(|&k| ring > 2 || k == 0)
                .map(|k| [k, (k + 1) % ring, ring])
                .collect()
        } else {
            (1..ring - 1).map(|k| [0, k, k + 1]).collect()
        };
        let area = |[a, b, c]: [usize; 3]| {
            let (a, b, c) = (samples[a].1, samples[b].1, samples[c].1);
            (b - a).perp_dot(c - a)
        };
        let triangles: Vec<[usize; 3]> = triangles
            .into_iter()
            .filter(|&t| area(t).abs() > 1e-12 * cell.area)
            .collect();
        if triangles.is_empty() {
            return Some(constant);
        }
        Some(SampleFan {
            samples,
            triangles,
            frame,
        })
    }

    /// Vertex `v`'s weights over three samples, None when it is a sample:
    /// linear over the fan triangle it lies in (the one where its least
    /// barycentric coordinate is greatest), negative coordinates clamped,
    /// so that a vertex outside the fan takes the values of its nearest
    /// edge; the centre sample's alone on a patch without a fan.
    pub(crate) fn weights(&self, mesh: &Mesh, v: u32) -> Option<SampleWeights> {
        if self.samples.iter().any(|&(s, _)| s == v) {
            return None;
        }
        if self.triangles.is_empty() {
            let s = self.samples[0].0;
            return Some([(s, 1.0), (s, 0.0), (s, 0.0)]);
        }
        let (origin, u, w) = self.frame;
        let d = mesh.vertices[v as usize].receiver_position() - origin;
        let x = DVec2::new(d.dot(u), d.dot(w));
        let mut best = ([0.0; 3], f64::NEG_INFINITY, [0usize; 3]);
        for &[a, b, c] in &self.triangles {
            let (pa, pb, pc) = (self.samples[a].1, self.samples[b].1, self.samples[c].1);
            let det = (pb - pa).perp_dot(pc - pa);
            let lb = (x - pa).perp_dot(pc - pa) / det;
            let lc = (pb - pa).perp_dot(x - pa) / det;
            let coordinates = [1.0 - lb - lc, lb, lc];
            let least = coordinates.iter().copied().fold(f64::INFINITY, f64::min);
            if least > best.1 {
                best = (coordinates, least, [a, b, c]);
            }
        }
        let (coordinates, _, corners) = best;
        let clamped = coordinates.map(|l| l.max(0.0));
        let sum: f64 = clamped.iter().sum();
        let weight = |k: usize| {
            let l = if sum > 0.0 {
                clamped[k] / sum
            } else {
                1.0 / 3.0
            };
            (self.samples[corners[k]].0, l as f32)
        };
        Some([weight(0), weight(1), weight(2)])
    }
}
