//! The irradiance every vertex has received, kept in single precision.
//!
//! One value per vertex of the whole mesh, for the solve's whole life: at
//! 24 bytes (`Rgb`'s three `f64`) it held 410 MiB of a million quads'
//! view. In `f32` it takes 12. Each shot's light is added in `f64` and the
//! sum rounded to `f32`, which moves it by at most half a unit in `f32`'s
//! last place (6 · 10⁻⁸ of the value): n shots move a vertex's value by at
//! most n times that, 0.006 % after a thousand, far below an image's noise.
//! The ledger's powers are summed from the shots in `f64`; adaptive
//! refinement alone reads these values into it (the power a split moves).

use rayon::prelude::*;

use crate::rgb::Rgb;
use crate::solver::light::indexed_update::par_update_at;

/// Irradiance H per vertex (W/m²), by vertex index.
#[derive(Clone, Debug, Default)]
pub(crate) struct VertexIrradiance {
    values: Vec<[f32; 3]>,
}

impl VertexIrradiance {
    /// Zero at each of `vertices` vertices.
    pub(crate) fn zeros(vertices: usize) -> VertexIrradiance {
        VertexIrradiance {
            values: vec![[0.0; 3]; vertices],
        }
    }

    /// How many vertices it holds.
    pub(crate) fn len(&self) -> usize {
        self.values.len()
    }

    /// Vertex `v`'s irradiance.
    pub(crate) fn at(&self, v: usize) -> Rgb {
        widened(self.values[v])
    }

    /// Every vertex's, in order.
    pub(crate) fn to_vec(&self) -> Vec<Rgb> {
        self.values.par_iter().map(|&h| widened(h)).collect()
    }

    /// Appends a vertex's (one a refinement added).
    pub(crate) fn push(&mut self, irradiance: Rgb) {
        self.values.push(irradiance.to_f32_array());
    }

    /// Adds `incident[k]` at vertex `vertices[k]` for every k, in parallel;
    /// `vertices` ascending (see [`par_update_at`]).
    pub(crate) fn add_at(&mut self, vertices: &[u32], incident: &[Rgb]) {
        par_update_at(&mut self.values, vertices, &|k, h| {
            *h = (widened(*h) + incident[k]).to_f32_array();
        });
    }
}

fn widened([r, g, b]: [f32; 3]) -> Rgb {
    Rgb::new(f64::from(r), f64::from(g), f64::from(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A thousand shots of sizes over eight decades onto one vertex land
    /// within a thousand half-units of `f32`'s last place of their `f64`
    /// sum; untouched vertices keep their values.
    #[test]
    fn shots_add_up_within_single_precision() {
        let mut store = VertexIrradiance::zeros(3);
        let vertices = [0, 2];
        store.add_at(&vertices, &[Rgb::splat(1e4), Rgb::new(1.0, 2.0, 3.0)]);
        let mut exact = Rgb::splat(1e4);
        let mut state = 12_345_u64;
        for _ in 0..1000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            let decade = (state >> 40) % 8;
            let shot = Rgb::new(1.0, 0.5, 0.25) * 10f64.powi(decade as i32 - 4);
            store.add_at(&vertices[..1], &[shot]);
            exact += shot;
        }
        let h = store.at(0);
        let bound = 1000.0 * 0.5 * f64::from(f32::EPSILON) * exact.r;
        for (got, want) in h.to_array().into_iter().zip(exact.to_array()) {
            assert!((got - want).abs() <= bound, "{h} against {exact}");
        }
        assert!(h.r > 1e4 + 100.0, "{h}");
        assert_eq!(store.at(1), Rgb::ZERO);
        assert_eq!(store.at(2), Rgb::new(1.0, 2.0, 3.0));
        assert_eq!(store.to_vec().len(), store.len());
    }
}
