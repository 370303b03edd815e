//! `cargo xtask formal`: the formal equivalence proofs of the generated Verilog against the
//! reference written from the model's semantics — with ABC and no invariants
//! (`tooltouch formal --dut`, `tests/hdl/formal_dut.rs`: every variant, the independent
//! designs, the faults) and by k-induction with the generator's invariants
//! (`tooltouch_hdl_gen::formal`, yosys `sat -tempinduct`) — for every configuration the
//! proof covers: the default, the
//! structural variants, `TOOLTOUCH_FORMAL_CONFIGS` random configurations (default 4), and
//! the injected faults, each of which must fail with a counterexample that `tooltouch
//! check` replays (docs/formal.md).
//!
//! The proofs are the tests of `tests/hdl/formal.rs` and `tests/hdl/formal_dut.rs`, run
//! with the ignored ones included;
//! `cargo xtask test` runs the same binary without it (the default configuration and the
//! faults). yosys is the only tool (its own SAT solver): `cargo xtask setup` installs it.

use anyhow::Result;

/// Runs every proof of `tests/hdl/formal.rs` and prints each verdict with its induction
/// length and wall time.
pub fn run() -> Result<()> {
    crate::process::run(
        &crate::process::root(),
        "cargo",
        &[
            "test",
            "--release",
            "--test",
            "hdl",
            "--",
            "formal::",
            "formal_dut::",
            "--include-ignored",
            "--nocapture",
        ],
    )
}
