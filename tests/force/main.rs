//! Integration tests of the force path: configuration, fixed point against float, plant scenarios, vectors, wear.
//!
//! One test binary per area (`cargo test --release --test force`); one module per topic
//! (`cargo test --release --test force <topic>::`).

mod config;
mod estimator;
mod mismatch;
mod nonlinear;
mod properties;
mod scenario;
mod sqrt;
mod vectors;
mod wear_presets;
mod wear_scenario;
mod wear_settle;
mod wear_short_cuts;
mod wear_transients;
