//! tooltouch-metrology: how right the decided diameter is (docs/accuracy.md). The error
//! budget predicted from the settings ([`budget`]), the same figures simulated
//! ([`simulate`]), both over the variants and a sweep ([`sweep`]), and repeats at one Z
//! averaged ([`averaging`], the law of S8), the calibration on a reference part (S1–S3,
//! [`calibration`]), and the fault campaign: how often a misbehaving machine gets a wrong
//! diameter through as a good one ([`campaign`]).
//!
//! It builds on the golden model and the simulated lathe (`tooltouch-model`,
//! `tooltouch-plant`) and on nothing that runs hardware or writes files for a user: never
//! the CLI (`tooltouch`), the co-simulation, the plots or the tuning sweeps, which may
//! depend on it.

pub mod averaging;
pub mod budget;
pub mod calibration;
pub mod campaign;
pub mod simulate;
pub mod sweep;

pub use budget::{predict, predict_all, Outcome, Prediction, Reference, Term, TermKind, Variant};
pub use simulate::{simulate, Simulated};
