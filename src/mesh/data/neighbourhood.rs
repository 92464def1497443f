//! The mesh's adjacency: each vertex's neighbours and whether it lies on
//! its surface mesh's outline, for the whole mesh or a part of it.

use super::topology::Mesh;

impl Mesh {
    /// Each vertex's neighbours: the other corners of the elements around
    /// it, once each, in increasing order, as offsets into one list (CSR):
    /// vertex v's are `list[offsets[v]..offsets[v + 1]]`.
    #[must_use]
    pub fn vertex_neighbours(&self) -> (Vec<usize>, Vec<u32>) {
        let (offsets, neighbours, _) = self.whole_neighbourhood();
        (offsets, neighbours)
    }

    /// Whether each vertex lies on its surface mesh's outline: on an edge
    /// that one element alone uses. Where elements split to different
    /// depths meet, the coarse side's edge is used once too: the
    /// T-junction's vertex and that edge's two ends count as outline.
    #[must_use]
    pub fn outline_vertices(&self) -> Vec<bool> {
        self.whole_neighbourhood().2
    }

    /// [`Mesh::neighbourhood_of`] every element, in the mesh's numbering.
    fn whole_neighbourhood(&self) -> (Vec<usize>, Vec<u32>, Vec<bool>) {
        let elements: Vec<u32> = (0..self.elements.len() as u32).collect();
        self.neighbourhood_of(&elements, &Some, self.vertices.len())
    }

    /// [`Mesh::vertex_neighbours`] and [`Mesh::outline_vertices`] of the
    /// part of the mesh made of `elements`, whose corners `local` numbers
    /// from 0 to `count` (a room's, in its own numbering; corners it
    /// numbers none are left out).
    #[must_use]
    pub(crate) fn neighbourhood_of(
        &self,
        elements: &[u32],
        local: &dyn Fn(u32) -> Option<u32>,
        count: usize,
    ) -> (Vec<usize>, Vec<u32>, Vec<bool>) {
        use rayon::slice::ParallelSliceMut;
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(12 * elements.len());
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(4 * elements.len());
        for &e in elements {
            let mut corners = [0u32; 4];
            let mut n = 0;
            for &v in self.elements[e as usize].corners() {
                if let Some(i) = local(v) {
                    corners[n] = i;
                    n += 1;
                }
            }
            let corners = &corners[..n];
            for &a in corners {
                pairs.extend(corners.iter().filter(|&&b| b != a).map(|&b| (a, b)));
            }
            for k in 0..n {
                let (a, b) = (corners[k], corners[(k + 1) % n]);
                edges.push((a.min(b), a.max(b)));
            }
        }
        pairs.par_sort_unstable();
        pairs.dedup();
        let mut offsets = vec![0; count + 1];
        for &(a, _) in &pairs {
            offsets[a as usize + 1] += 1;
        }
        for v in 0..count {
            offsets[v + 1] += offsets[v];
        }
        edges.par_sort_unstable();
        let mut outline = vec![false; count];
        for run in edges.chunk_by(|a, b| a == b) {
            if let [(a, b)] = run {
                outline[*a as usize] = true;
                outline[*b as usize] = true;
            }
        }
        let neighbours = pairs.into_iter().map(|(_, b)| b).collect();
        (offsets, neighbours, outline)
    }
}
