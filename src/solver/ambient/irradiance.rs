//! The ambient irradiance G_v a solution adds to the light shot (see
//! `solver/ambient/rays.rs`): at every vertex, or at the vertices of the rooms
//! it was gathered in alone.
//!
//! An image taken inside one office of a building gathers the term in that
//! office; its values are kept for its vertices alone, 28 bytes each, not
//! for the building's (24 bytes a vertex, 430 MB for 17.9 million). The
//! light shot stays the solver's own: a [`crate::Solution`] borrows it.

use crate::rgb::Rgb;

/// G_v per mesh vertex, W/m², zero where none was gathered.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) enum AmbientIrradiance {
    /// None gathered (a solution of the light shot alone, or nothing
    /// left unshot).
    #[default]
    Nowhere,
    /// At every vertex, by index.
    Everywhere(Vec<Rgb>),
    /// At the vertices listed, ascending, and zero at the others.
    At {
        /// The vertices, ascending.
        vertices: Vec<u32>,
        /// Their values, in the same order.
        values: Vec<Rgb>,
    },
}

impl AmbientIrradiance {
    /// The term of some rooms: each room's vertices with their values, in
    /// the same order (a vertex in one room at most).
    pub(crate) fn of_rooms(rooms: impl IntoIterator<Item = (u32, Rgb)>) -> AmbientIrradiance {
        let mut pairs: Vec<(u32, Rgb)> = rooms.into_iter().collect();
        pairs.sort_unstable_by_key(|&(v, _)| v);
        let (vertices, values) = pairs.into_iter().unzip();
        AmbientIrradiance::At { vertices, values }
    }

    /// G at vertex v.
    pub(crate) fn at(&self, v: usize) -> Rgb {
        match self {
            AmbientIrradiance::Nowhere => Rgb::ZERO,
            AmbientIrradiance::Everywhere(values) => values[v],
            AmbientIrradiance::At { vertices, values } => u32::try_from(v)
                .ok()
                .and_then(|v| vertices.binary_search(&v).ok())
                .map_or(Rgb::ZERO, |k| values[k]),
        }
    }

    /// G at each of a mesh's `count` vertices.
    #[cfg(test)]
    pub(crate) fn at_every(&self, count: usize) -> Vec<Rgb> {
        (0..count).map(|v| self.at(v)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rooms' values are found at their vertices, in whatever order the
    /// rooms came, and zero elsewhere; the whole mesh's by index.
    #[test]
    fn a_room_s_term_is_read_at_its_vertices_and_zero_elsewhere() {
        let grey = |x: f64| Rgb::new(x, x, x);
        let term = AmbientIrradiance::of_rooms([(7, grey(7.0)), (2, grey(2.0)), (5, grey(5.0))]);
        let read: Vec<Rgb> = (0..9).map(|v| term.at(v)).collect();
        let mut expected = vec![Rgb::ZERO; 9];
        for v in [2, 5, 7] {
            expected[v] = grey(v as f64);
        }
        assert_eq!(read, expected);
        assert_eq!(term.at(usize::MAX), Rgb::ZERO);
        let everywhere = AmbientIrradiance::Everywhere(expected.clone());
        assert_eq!(
            (0..9).map(|v| everywhere.at(v)).collect::<Vec<_>>(),
            expected
        );
        assert_eq!(AmbientIrradiance::Nowhere.at(3), Rgb::ZERO);
    }
}
