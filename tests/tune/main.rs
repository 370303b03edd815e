//! Integration tests of tuning sweeps: the cost model against yosys, sharding and merge, the
//! float reference, the optimizer, the range instrumentation (`ranges`).
//!
//! One test binary per area (`cargo test --release --test tune`); one module per topic
//! (`cargo test --release --test tune <topic>::`).

mod cost_model;
mod firmware_cost;
mod merge;
mod optimize;
mod ranges;
mod reference;
