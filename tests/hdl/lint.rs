//! Lint gates on the generated Verilog: `verilator --lint-only -Wall` clean, and yosys
//! `proc; check -assert` with no latch cell, for every structural variant of the
//! generator (method, charge law, glitch filter on/off, degenerate thresholds) and for
//! random configurations.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tooltouch_hdl_gen::{generate, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::random::random_config;
use tooltouch_rtl_sim::runner::{lint_verilator, yosys_check};
use tooltouch_rtl_sim::write_design;

/// The structural variants the formal proof also covers (`tooltouch_hdl_gen::formal::variants`:
/// the default, the MCU diagnostics, each decision method under three charge laws, glitch
/// filters and rules, the narrowest and widest registers), then random configurations.
fn variants() -> Vec<(String, MeasureConfig, Options)> {
    let mut out = tooltouch_hdl_gen::formal::variants();
    let mut rng = ChaCha8Rng::seed_from_u64(0x11_17);
    out.extend((0..8).map(|i| {
        (
            format!("random {i}"),
            random_config(&mut rng),
            Options::default(),
        )
    }));
    out
}

#[test]
fn hdl_lint_verilator_wall_and_yosys_check_are_clean() {
    let work = tempfile::tempdir().expect("temporary folder");
    let variants = variants();
    assert!(variants.len() >= 21, "the structural variants went missing");
    for (i, (name, config, options)) in variants.iter().enumerate() {
        let dir = work.path().join(format!("v{i}"));
        let files =
            write_design(&dir, &generate(config, options), None).expect("writing the design");
        if let Err(e) = lint_verilator(&files) {
            panic!("variant {i} ({name}) {:?}: {e}", config.settings());
        }
        match yosys_check(&files, &dir) {
            Err(e) => panic!("variant {i} ({name}) {:?}: {e}", config.settings()),
            Ok(check) => assert!(
                check.dff_cells > 0,
                "variant {i} ({name}): yosys found no flip-flop at all:\n{}",
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
