//! The progressive shooting solver and its source sampling.

mod progressive;
mod sampling;
mod settings;
mod solution;
mod source_sampling;

pub use progressive::{EnergyBalance, Solver};
pub use settings::{FormFactorKernel, SolverSettings};
pub use solution::{Probe, ProbeMode, Solution};
