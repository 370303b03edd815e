//! tooltouch-hdl-gen: writes the Verilog-2005 of the FPGA measurement front end from the
//! model's [`MeasureConfig`], and the self-checking testbench that compares it, every
//! cycle and every output bit, with vectors written by the golden model.
//!
//! The generated design reproduces `tooltouch_model::FrontEnd::clock` exactly:
//!
//! | module | model | registers |
//! | --- | --- | --- |
//! | `tt_synchronizer` | `FrontEnd::sync1/sync2` | 2 × 6 |
//! | `tt_glitch_filter` | `FrontEnd::filter` | 6 levels + 6 × `glitch_bits` counters |
//! | `tt_edge_detect` | `filtered ^ FrontEnd::previous` | 8 strobes (rising edges, armed index/FES, scale step), registered one clock early |
//! | `tt_pulse_counter` | `PulseCounter` (docs/domain.md §2.3) | count, last window count, revs, reached |
//! | `tt_density_detector` | `DensityDetector` (docs/domain.md §2.4) | charge, armed, fired |
//! | `tt_quadrature_decoder` | `QuadratureDecoder` (docs/domain.md §1) | position, errors (the phase is the filtered levels') |
//! | `tt_position_latch` | `PositionLatch` | valid, position |
//! | `tt_checks` | `MeasurementChecks` | faults, revolution's FES count, index seen, FES idle count, windows to confirm, confirmed |
//! | `tt_measurement` | `Measurement` | armed, contact, sticky, revolutions, pulses |
//! | `tt_frontend` (simulation top) | `FrontEnd` + MCU register file | none of its own |
//! | `tt_fpga` (chip top) | — | the registered MCU address and read data |
//! | `tt_spi` (SPI design) | — | SPI slave, run-time thresholds, status, settings CRC |
//! | `tt_fpga_spi` (board top) | — | none of its own |
//!
//! Every register has the model's power-on value both as a Verilog initializer and as
//! the value a synchronous `rst` loads (the chip top's MCU bus registers, which hold no
//! state, only the initializer); every update is a non-blocking assignment. The
//! edges detected in one clock drive the kernel in the model's canonical order
//! arm → contact → index → FES → scale: each block receives that clock's strobes and
//! computes its next state as the *sequential composition* of the model's methods
//! (`*_a` wires: after arm, `*_i`: after index, `*_p`: after the FES pulse), so two
//! edges in the same clock act exactly as the model's consecutive calls do.
//!
//! For speed (≥ 150 MHz on an iCE40 HX8K) without changing the contract's latency, what
//! the kernel's decisions need is computed one clock early and registered: the edge
//! stage decodes the strobes from the glitch filter's next levels, the sticky contact bit
//! is kept as the next pulse will read it, the counter's `i_def` comparisons are registers
//! stepped by equalities, and the decision is written flat over flip-flops (two LUT
//! levels before the latches). Constant thresholds are written as bit logic, not as
//! comparisons (which yosys maps to carry chains).
//!
//! Every width and constant is read from the [`MeasureConfig`]; the header of every file
//! names the configuration hash ([`MeasureConfig::hash`]).
//!
//! ## Layout
//!
//! One source file per generated file, named as the file it writes:
//! `src/modules/tt_pulse_counter.rs` writes `tt_pulse_counter.v`, and so on for every
//! module of the table, the testbench (`tt_testbench.rs`) and its Verilator driver
//! (`tt_testbench_main.rs` → `tt_testbench_main.cpp`). The helpers they share (file
//! header, `${NAME}` template filler, literals, comparisons with a constant) are in
//! `src/emit.rs`, the MCU register map in `src/mcu.rs`.
//!
//! ## The reference and the formal proof
//!
//! [`reference`] writes `tt_frontend_ref`, a plain front end with the same ports written
//! straight from the model's semantics (one register per model state field, the model's
//! statements in the model's order), co-simulated against the model like the design.
//! [`formal`] proves the optimized design equal to it on every input sequence: a miter
//! (`src/modules/tt_formal_miter.rs`) with the register-correspondence invariants the
//! generator knows, proven by k-induction in yosys; a failed proof yields a counterexample
//! from power-on that `tooltouch check` replays against the golden model (docs/formal.md).
//!
//! The generated files of two configurations are committed under `hdl-gen/snapshots/`
//! and compared byte for byte by `tests/snapshots.rs`, so every change of the generator
//! shows as a diff of the Verilog; `cargo xtask bless-hdl` rewrites them.
//!
//! ## The SPI design
//!
//! [`generate_spi`] writes the board top [`SPI_TOP`] (`tt_fpga_spi`) of both boards
//! (`hdl-gen/boards/*.pcf`): the kernel with its thresholds as input ports (the
//! generators' tunable mode; [`generate`] keeps them constants), driven by the registers of
//! the SPI register interface `tt_spi`, whose register map is the MCU map plus one word per
//! model output no MCU word shows ([`spi`], docs/CONTRACT.md).
//!
//! ## The scoreboards' output lists
//!
//! [`scoreboard_lists`] writes the lists of outputs in the DPI-C and VPI scoreboards and
//! their bench (`host/abi/{sv,c,verilog}`: ports, names, width checks, comparisons) from
//! [`output_ports`], as generated regions of those hand-written files;
//! `tests/scoreboard_lists.rs` fails when the committed regions differ, and
//! `cargo xtask bless-hdl` rewrites them too.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod config_include;
mod design;
mod emit;
pub mod formal;
mod mcu;
mod modules;
mod outputs;
pub mod scoreboard_lists;
pub mod spi;

use tooltouch_model::MeasureConfig;

pub use config_include::{config_include, CONFIG_INCLUDE};
pub use design::{Design, Fault, Options, VerilogFile, FPGA_TOP, TOP};
pub use mcu::{McuRegister, McuWord, MCU_ADDR_BITS, MCU_DATA_BITS, MCU_REGISTERS};
pub use modules::tt_frontend_ref::{reference, REFERENCE_TOP};
pub use modules::tt_testbench::{
    testbench, TestbenchSpec, EXPECT_HEX, MAX_CYCLES, MAX_DEPTH, STIM_HEX, STIM_WORD_BITS,
    TESTBENCH,
};
pub use modules::tt_testbench_main::{verilator_main, VERILATOR_MAIN};
pub use outputs::{
    mask, output_fields, output_ports, output_values, outputs_width, OutputField, OutputPort,
    IRQ_SOURCE,
};
pub use spi::{Threshold, SPI_TOP};

/// Writes the Verilog of the front end for `config`.
pub fn generate(config: &MeasureConfig, options: &Options) -> Design {
    let ctx = emit::Context::new(config, options);
    Design {
        files: modules::design(&ctx),
        config_hash: config.hash(),
    }
}

/// Writes the SPI design for `config`: the kernel with the thresholds as input ports,
/// the simulation top `tt_frontend` with those ports, the register interface `tt_spi`
/// and the chip top [`SPI_TOP`] (files in compile order, the top last). Its own file set:
/// its `tt_frontend` has more ports than [`generate`]'s.
pub fn generate_spi(config: &MeasureConfig, options: &Options) -> Design {
    let mut ctx = crate::emit::Context::new(config, options);
    ctx.tunable = true;
    let mut files = crate::modules::design(&ctx);
    files.retain(|f| f.name != format!("{}.v", crate::FPGA_TOP));
    files.push(crate::modules::tt_spi::emit(&ctx));
    files.push(crate::modules::tt_fpga_spi::emit(&ctx));
    Design {
        files,
        config_hash: config.hash(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::MeasureOutputs;

    #[test]
    fn every_file_names_the_config_hash_and_its_module() {
        let c = MeasureConfig::default();
        let d = generate(&c, &Options::default());
        let hash = format!("{:016x}", c.hash());
        assert_eq!(d.files.len(), 11);
        assert_eq!(d.files[9].name, format!("{TOP}.v"));
        assert_eq!(d.files[10].name, format!("{FPGA_TOP}.v"));
        for f in &d.files {
            assert!(f.text.contains(&hash), "{} lacks the hash", f.name);
            let module = f.name.trim_end_matches(".v");
            assert!(f.text.contains(&format!("module {module}")), "{}", f.name);
        }
    }

    #[test]
    fn output_widths_follow_the_config() {
        let c = MeasureConfig::default();
        let f = output_fields(&c);
        assert_eq!(f[3].width, 24);
        assert_eq!(f[8].width, 11);
        assert_eq!(f[10].width, 16);
        assert_eq!(
            outputs_width(&c),
            6 + 3 * 24 + 8 + 22 + 16 + 16 + 32 + 1 + 7
        );
    }

    #[test]
    fn negative_positions_are_truncated_to_scale_bits() {
        let c = MeasureConfig::default();
        let o = MeasureOutputs {
            position: -1,
            ..Default::default()
        };
        assert_eq!(output_values(&c, &o)[6], 0xff_ffff);
    }

    #[test]
    fn a_fault_changes_the_text() {
        let c = MeasureConfig::default();
        let good = generate(&c, &Options::default());
        for fault in Fault::ALL {
            assert!(fault.applies_to(&c), "{fault:?} at the default");
            assert_ne!(
                good,
                generate(
                    &c,
                    &Options {
                        fault,
                        ..Options::default()
                    }
                ),
                "{fault:?}"
            );
        }
    }
}
