//! A shooter's strata: the m × m cells of its patch, the radiosity each
//! shoots, and the finer cells its unshot field is read at.

use glam::{DVec2, DVec3};

use super::{Shooter, ShotRadiosity};
use crate::mesh::Cell;
use crate::rgb::Rgb;
use crate::solver::light::patch_field::SampledField;

/// One subdivision of a shooter: its cells and the radiosity each shoots,
/// read where a stratum's jittered sample falls.
pub(super) struct Strata {
    pub(super) cells: Vec<Cell>,
    pub(super) radiosity: Vec<Rgb>,
    /// `sub` × `sub` values over each stratum's parameter square (see
    /// `PatchField::sampled`); empty for a uniform shot.
    pub(super) sampled: Vec<Rgb>,
    /// Whether each sampled cell's centre found an element of the patch.
    pub(super) found: Vec<bool>,
    /// For a field shot, each stratum's centre and the distance from it
    /// within which a receiver may stand closer to the stratum than its
    /// size (the farthest corner's distance plus the size).
    pub(super) beside: Vec<(DVec3, f64)>,
    pub(super) sub: usize,
}

/// How finely a shooting patch's unshot radiosity is read where a sample
/// falls: about this many cells per side of the patch, however few its
/// strata. A floor patch of 2 × 2 strata with a chair's base plate standing
/// on it then shoots nothing along the rays that start under the plate, and
/// shoots that power from the rest of the floor; read at each stratum's
/// centre, the plate's share of a stratum was lost on the plate's inside.
/// Sixteen per side gain little over eight and cost a fifth of the ray
/// throughput.
const SAMPLED_PER_SIDE: usize = 8;

impl Strata {
    /// The radiosity stratum k shoots along a ray to its sample at
    /// parameters (u, v).
    pub(super) fn at(&self, k: usize, uv: DVec2) -> Rgb {
        if self.sampled.is_empty() {
            return self.radiosity[k];
        }
        self.sampled[self.cell_of(k, uv)]
    }

    /// Whether the sampled cell that parameters (u, v) of stratum k fall in
    /// read an element at its centre (always, for a uniform shot).
    pub(super) fn found_at(&self, k: usize, uv: DVec2) -> bool {
        self.found.is_empty() || self.found[self.cell_of(k, uv)]
    }

    /// The index of the sampled cell that parameters (u, v) of stratum k
    /// fall in.
    fn cell_of(&self, k: usize, uv: DVec2) -> usize {
        k * self.sub * self.sub + sampled_cell(uv, self.sub)
    }
}

/// The cell, row by row, of a `sub` × `sub` grid over a parameter square
/// that parameters (u, v) fall in: where a sample reads the values of
/// [`PatchField::sampled`].
fn sampled_cell(uv: DVec2, sub: usize) -> usize {
    let cell = |w: f64| ((w * sub as f64) as usize).min(sub - 1);
    cell(uv.y) * sub + cell(uv.x)
}

impl Shooter {
    /// The m × m strata of the patch and the radiosity each shoots.
    pub(super) fn stratify(&self, side: usize) -> Strata {
        let mut cells = Vec::with_capacity(side * side);
        self.cell.subdivide(side, &mut cells);
        let sub = SAMPLED_PER_SIDE.div_ceil(side.max(1));
        let (radiosity, sampled, found, beside) = match &self.radiosity {
            ShotRadiosity::Uniform(b) => {
                (vec![*b; cells.len()], Vec::new(), Vec::new(), Vec::new())
            }
            ShotRadiosity::Field(field) => {
                let SampledField { sampled, found } = field.sampled(&cells, sub);
                let share = 1.0 / (sub * sub) as f64;
                let means = sampled
                    .chunks(sub * sub)
                    .map(|values| values.iter().copied().sum::<Rgb>() * share)
                    .collect();
                let beside = cells
                    .iter()
                    .map(|cell| {
                        let centre = cell.centre();
                        let reach = cell
                            .polygon()
                            .iter()
                            .map(|p| p.distance_squared(centre))
                            .fold(0.0, f64::max)
                            .sqrt();
                        (centre, reach + cell.area.sqrt())
                    })
                    .collect();
                (means, sampled, found, beside)
            }
        };
        Strata {
            cells,
            radiosity,
            sampled,
            found,
            beside,
            sub,
        }
    }
}
