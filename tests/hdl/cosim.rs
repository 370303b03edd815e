//! Co-simulation of the generated Verilog with the golden cycle model in Verilator and
//! Icarus: random configurations, random run-length pin stimuli with bursts, glitches,
//! same-clock edges and scale moves; every output on every cycle must equal the model's.
//!
//! `TOOLTOUCH_CASES=N` raises the number of random configurations (default 16).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use tooltouch_plant::random::{random_config, random_stimulus};
use tooltouch_rtl_sim::cosim::{cosim, CosimPlan};

/// Stimuli per configuration and their length, clocks.
const STIMULI: usize = 2;
const CYCLES: u64 = 30_000;

#[test]
fn hdl_random_configs_match_the_model_in_verilator_and_icarus() {
    let n = u64::from(tooltouch_model::testing::cases(16));
    let work = tempfile::tempdir().expect("temporary folder");
    let failures: Vec<String> = (0..n)
        .into_par_iter()
        .filter_map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0000 + i);
            let config = random_config(&mut rng);
            let stimuli: Vec<_> = (0..STIMULI)
                .map(|_| random_stimulus(&mut rng, &config, 50_000_000, CYCLES))
                .collect();
            // Every other configuration with the MCU's diagnostic counters readable.
            let plan = CosimPlan {
                lint: true,
                options: tooltouch_hdl_gen::Options {
                    mcu_diagnostics: i % 2 == 1,
                    ..Default::default()
                },
                ..CosimPlan::default()
            };
            let dir = work.path().join(format!("config{i}"));
            match cosim(&config, &stimuli, &dir, &plan) {
                Err(e) => Some(format!("config {i} ({:?}): {e}", config.settings())),
                Ok(report) => report.first_failure().map(|r| {
                    format!(
                        "config {i} ({:?}): {} {}",
                        config.settings(),
                        r.simulator,
                        r.first_mismatch.as_deref().unwrap_or(&r.output)
                    )
                }),
            }
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {n} configurations failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Directed corner configurations of the pulse counter's flattened logic (i_def 0 and 1,
/// windows of one and several revolutions, tiny windows that saturate), in Icarus.
#[test]
fn hdl_counter_corner_configs_match_the_model_in_icarus() {
    use tooltouch_model::MeasureSettings;
    use tooltouch_rtl_sim::runner::Simulator;
    let work = tempfile::tempdir().expect("temporary folder");
    let mut rng = ChaCha8Rng::seed_from_u64(0xc0de);
    for (i, (i_def, window_revs, glitch)) in
        [(0, 1, 0), (1, 1, 2), (1, 3, 0), (2, 2, 1), (15, 1, 0)]
            .into_iter()
            .enumerate()
    {
        let config = MeasureSettings {
            pulses_per_rev: 16,
            i_def,
            window_revs,
            glitch_cycles: glitch,
            ..Default::default()
        }
        .validate()
        .expect("valid corner configuration");
        let stimuli: Vec<_> = (0..STIMULI)
            .map(|_| random_stimulus(&mut rng, &config, 50_000_000, CYCLES))
            .collect();
        let plan = CosimPlan {
            simulators: vec![Simulator::Icarus],
            ..CosimPlan::default()
        };
        let report = cosim(&config, &stimuli, &work.path().join(format!("c{i}")), &plan)
            .expect("cosim runs");
        if let Some(r) = report.first_failure() {
            panic!(
                "corner {i} ({:?}): {}",
                config.settings(),
                r.first_mismatch.as_deref().unwrap_or(&r.output)
            );
        }
    }
}
