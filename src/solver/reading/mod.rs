//! Reading a solve: the [`Solution`](crate::solver::Solution) at any point
//! of a surface (by final gather, with penumbra refinement, or by mesh
//! interpolation), per-surface totals, and the places a reading is made at.

pub(super) mod penumbra;
pub(super) mod places;
pub(super) mod request;
pub(super) mod solution;
