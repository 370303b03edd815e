//! Lint gates on the generated Verilog: `verilator --lint-only -Wall` clean, and yosys
//! `proc; check -assert` with no latch cell, for every structural variant of the
//! generator (method, charge law, glitch filter on/off, degenerate thresholds) and for
//! random configurations.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tooltouch::hdl::random::random_config;
use tooltouch::hdl::runner::{lint_verilator, yosys_check};
use tooltouch::hdl::write_design;
use tooltouch_hdl_gen::{generate, Options};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::{MeasureConfig, MeasureSettings};

fn variants() -> Vec<MeasureConfig> {
    let mut out = vec![MeasureConfig::default()];
    for method in [
        DecisionMethod::SinglePulse,
        DecisionMethod::Counter,
        DecisionMethod::Density,
    ] {
        for (law, glitch, rearm, i_def, rule) in [
            (
                ChargeLaw::Exponential {
                    charge_shift: 0,
                    discharge_shift: 16,
                },
                0,
                0,
                0,
                ContactRule::Sampled,
            ),
            (
                ChargeLaw::Linear {
                    charge_step: 65535,
                    discharge_step: 1,
                },
                255,
                100,
                1023,
                ContactRule::Sticky,
            ),
            (
                ChargeLaw::Exponential {
                    charge_shift: 5,
                    discharge_shift: 3,
                },
                1,
                16384,
                7,
                ContactRule::Sticky,
            ),
        ] {
            out.push(
                MeasureSettings {
                    method,
                    charge_law: law,
                    glitch_cycles: glitch,
                    rearm_threshold: rearm,
                    i_def,
                    contact_rule: rule,
                    ..Default::default()
                }
                .validate()
                .expect("valid variant"),
            );
        }
    }
    // Extreme widths.
    for (ppr, revs, charge_bits, scale_bits) in [(16, 1, 4, 8), (16384, 16, 24, 32)] {
        let full = (1u32 << charge_bits) - 1;
        out.push(
            MeasureSettings {
                pulses_per_rev: ppr,
                window_revs: revs,
                i_def: 3,
                charge_bits,
                charge_law: ChargeLaw::Linear {
                    charge_step: full,
                    discharge_step: full,
                },
                fire_threshold: full,
                rearm_threshold: full - 1,
                scale_bits,
                ..Default::default()
            }
            .validate()
            .expect("valid extreme"),
        );
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0x11_17);
    out.extend((0..8).map(|_| random_config(&mut rng)));
    out
}

#[test]
fn hdl_lint_verilator_wall_and_yosys_check_are_clean() {
    let work = tempfile::tempdir().expect("temporary folder");
    for (i, config) in variants().iter().enumerate() {
        let dir = work.path().join(format!("v{i}"));
        let files = write_design(&dir, &generate(config, &Options::default()), None)
            .expect("writing the design");
        if let Err(e) = lint_verilator(&files) {
            panic!("variant {i} {:?}: {e}", config.settings());
        }
        match yosys_check(&files, &dir) {
            Err(e) => panic!("variant {i} {:?}: {e}", config.settings()),
            Ok(check) => assert!(
                check.dff_cells > 0,
                "variant {i}: yosys found no flip-flop at all:\n{}",
                check.log
            ),
        }
    }
}

#[test]
fn hdl_lint_catches_a_latch() {
    // The gate itself must be able to fail: an incomplete combinational assignment.
    let work = tempfile::tempdir().expect("temporary folder");
    let config = MeasureConfig::default();
    let mut design = generate(&config, &Options::default());
    let top = design
        .files
        .iter_mut()
        .find(|f| f.name == format!("{}.v", tooltouch_hdl_gen::TOP))
        .expect("top file");
    top.text = top
        .text
        .replace("            default: mcu_rdata = 32'd0;\n", "");
    let files = write_design(work.path(), &design, None).expect("writing");
    assert!(
        yosys_check(&files, work.path()).is_err(),
        "a case without default must infer a latch and fail the check"
    );
}
