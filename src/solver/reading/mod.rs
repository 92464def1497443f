//! Reading a solve: the [`Solution`](crate::solver::Solution) a solver
//! gives with the ambient term asked for (`request.rs`), read at any point
//! of a surface by final gather with penumbra refinement (`gather.rs`,
//! `penumbra.rs`) or by mesh interpolation (`interpolation.rs`), its
//! per-surface totals, and the places a reading is made at (`places.rs`).

pub(super) mod gather;
pub(super) mod interpolation;
pub(super) mod penumbra;
pub(super) mod places;
pub(super) mod request;
pub(super) mod solution;
