//! Integration tests of the generated Verilog against the model: co-simulation, faults, the lathe run, lint, the testbench under both simulators.
//!
//! One test binary per area (`cargo test --release --test hdl`); one module per topic
//! (`cargo test --release --test hdl <topic>::`).

#[path = "../common/mod.rs"]
mod common;

mod abi_c;
mod contract;
mod cosim;
mod faults;
mod formal;
mod formal_dut;
mod fst;
mod lathe;
mod lint;
mod reference;
mod scoreboard;
mod stress;
mod testbench_tools;
