//! How right the decided diameter is (docs/accuracy.md): the error budget predicted from the
//! settings ([`budget`]), the same figures simulated ([`simulate`]), and repeats at one Z
//! averaged (S8, [`averaging`]).

pub mod averaging;
pub mod budget;
pub mod simulate;

pub use budget::{predict, predict_all, Outcome, Prediction, Reference, Term, TermKind, Variant};
pub use simulate::{simulate, Simulated};
