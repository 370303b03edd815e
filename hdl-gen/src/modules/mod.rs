//! The generators, one file per generated file and named as it: `tt_pulse_counter.rs`
//! writes `tt_pulse_counter.v`, `tt_testbench_main.rs` writes `tt_testbench_main.cpp`.
//! Each design module's file holds one `emit(&Context) -> VerilogFile`: its Verilog
//! template and the widths, constants and variants it reads from the configuration. The
//! helpers they share (header, template filler, literals, constant comparisons) are in
//! [`crate::emit`]; the MCU register map in [`crate::mcu`].

pub(crate) mod tt_checks;
pub(crate) mod tt_density_detector;
pub(crate) mod tt_edge_detect;
pub(crate) mod tt_formal_miter;
pub(crate) mod tt_fpga;
pub(crate) mod tt_fpga_spi;
pub(crate) mod tt_frontend;
pub(crate) mod tt_frontend_ref;
pub(crate) mod tt_glitch_filter;
pub(crate) mod tt_measurement;
pub(crate) mod tt_position_latch;
pub(crate) mod tt_pulse_counter;
pub(crate) mod tt_quadrature_decoder;
pub(crate) mod tt_spi;
pub(crate) mod tt_synchronizer;
pub(crate) mod tt_testbench;
pub(crate) mod tt_testbench_main;

use crate::design::VerilogFile;
use crate::emit::Context;

/// The design's files in compile order: leaves first, then the simulation top and the
/// chip top.
pub(crate) fn design(ctx: &Context) -> Vec<VerilogFile> {
    vec![
        tt_synchronizer::emit(ctx),
        tt_glitch_filter::emit(ctx),
        tt_edge_detect::emit(ctx),
        tt_pulse_counter::emit(ctx),
        tt_density_detector::emit(ctx),
        tt_quadrature_decoder::emit(ctx),
        tt_position_latch::emit(ctx),
        tt_checks::emit(ctx),
        tt_measurement::emit(ctx),
        tt_frontend::emit(ctx),
        tt_fpga::emit(ctx),
    ]
}

#[cfg(test)]
mod tests {
    use crate::design::{Fault, Options};
    use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod};
    use tooltouch_model::MeasureSettings;

    #[test]
    fn no_hole_is_left_unfilled_in_any_variant() {
        for method in [
            DecisionMethod::SinglePulse,
            DecisionMethod::Counter,
            DecisionMethod::Density,
        ] {
            for law in [
                ChargeLaw::Linear {
                    charge_step: 3,
                    discharge_step: 1,
                },
                ChargeLaw::Exponential {
                    charge_shift: 0,
                    discharge_shift: 16,
                },
            ] {
                for glitch in [0, 3] {
                    let c = MeasureSettings {
                        method,
                        charge_law: law,
                        glitch_cycles: glitch,
                        rearm_threshold: 0,
                        ..Default::default()
                    }
                    .validate()
                    .unwrap();
                    for fault in [Fault::None, Fault::FesBeforeIndex] {
                        for mcu_diagnostics in [false, true] {
                            let options = Options {
                                fault,
                                mcu_diagnostics,
                            };
                            let d = crate::generate(&c, &options);
                            for f in &d.files {
                                assert!(!f.text.contains("${"), "{} {method:?}", f.name);
                            }
                        }
                    }
                }
            }
        }
    }
}
