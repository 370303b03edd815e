//! The force estimator characterized against the dynamometer (docs/estimator.md): the plant's
//! channels against what they model (dynamometer step response, the power signal's lag,
//! phase voltages and currents, noise), the no-load identification's convergence, and
//! properties over seeded random operating points — the synthesized estimate (F9) is
//! faster than the power-only one and its steady-state error stays within its bound.
//! Properties, not recorded numbers: the noise streams may change with the random crates.
//! A few cases by default; `PROPTEST_CASES` (or `TOOLTOUCH_CASES`) runs more.

use proptest::prelude::*;
use std::f64::consts::PI;
use tooltouch_model::force::sampling::{AdcScales, Sampler, ADC_MID};
use tooltouch_plant::drive::estimator_report::{
    delay_63, depth_step_scenario, report, run_up_scenario, EstimateKind, DEPTH_LEVELS,
};
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};
use tooltouch_plant::drive::{DepthProfile, DriveParams, Plant, ProcessParams};

/// The plant of `tooltouch control` at 800 rpm, 1 kHz, with a process whose force follows
/// the feed within a millisecond (τ_p at its floor): a force step at engagement.
fn fast_plant(seed: u64) -> Plant {
    let process = ProcessParams {
        tau_p: 0.001,
        ks_drift: 0.0,
        ripple: 0.0,
        ..ProcessParams::default()
    };
    let depth = DepthProfile {
        before: 1.0,
        after: 1.0,
        step_at: f64::INFINITY,
    };
    Plant::new(
        DriveParams::default(),
        process,
        depth,
        &AdcScales::default(),
        1000.0,
        800.0 * 2.0 * PI / 60.0,
        seed,
    )
}

/// Index of the first value at or above 63 % of the way from `x[0]` to `last`.
fn first_63(x: &[f64], last: f64) -> usize {
    let target = x[0] + 0.63 * (last - x[0]);
    x.iter().position(|v| *v >= target).expect("reaches 63 %")
}

#[test]
fn dynamometer_follows_a_force_step_within_a_sample_and_carries_the_adc_noise() {
    let mut p = fast_plant(3);
    // No cut: the channel reads mid-scale with the ADC noise (1.5 LSB rms = 1.5 N).
    let idle: Vec<f64> = (0..2000)
        .map(|_| f64::from(p.sample().force) - f64::from(ADC_MID))
        .collect();
    let mean = idle.iter().sum::<f64>() / idle.len() as f64;
    let sd = (idle.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / idle.len() as f64).sqrt();
    assert!(mean.abs() < 0.2, "idle mean {mean} N");
    assert!((1.3..1.7).contains(&sd), "idle noise {sd} N rms");
    // Engage: the force steps to K_s·a·f = 600 N in ~1 ms; the sensor (2 kHz) and the
    // sampling add at most one sample to the force's own 63 % time.
    p.engaged = true;
    let (mut force, mut reading) = (Vec::new(), Vec::new());
    for _ in 0..50 {
        let codes = p.sample();
        force.push(p.state().force);
        reading.push(p.state().dynamometer);
        let _ = codes;
    }
    let last = *force.last().unwrap();
    assert!((last - 600.0).abs() < 1.0, "{last} N");
    let (t_force, t_dyn) = (first_63(&force, last), first_63(&reading, last));
    assert!(
        t_dyn <= t_force + 1,
        "force {t_force} ms, sensor {t_dyn} ms"
    );
    // Through the model's 100 Hz low-pass and the period average, the first full period
    // after the step reads the new force within the noise.
    let mut s = Sampler::new(1);
    for _ in 0..50 {
        s.on_sample(&p.sample());
    }
    let avg = s.on_tick().force as f64 / 256.0;
    assert!((avg - 600.0).abs() < 2.0, "period average {avg} N");
}

#[test]
fn measured_power_lags_the_shaft_power_by_its_time_constant() {
    let mut p = fast_plant(4);
    for _ in 0..200 {
        p.sample();
    }
    p.engaged = true;
    let (mut shaft, mut p_o) = (Vec::new(), Vec::new());
    for _ in 0..3000 {
        p.sample();
        let s = p.state();
        shaft.push(s.t_e * s.omega);
        p_o.push(s.p_o);
    }
    let last = *shaft.last().unwrap();
    let lag_ms = first_63(&p_o, last) as f64 - first_63(&shaft, last) as f64;
    let tau_ms = 1000.0 * p.drive.power_lag;
    assert!(
        (lag_ms - tau_ms).abs() < 0.1 * tau_ms,
        "P_o lags {lag_ms} ms, the drive's lag is {tau_ms} ms"
    );
}

#[test]
fn phase_signals_give_the_air_gap_power_and_the_line_voltage() {
    let mut p = fast_plant(5);
    p.engaged = true;
    let scales = AdcScales::default();
    let mut s = Sampler::new(1);
    for _ in 0..500 {
        s.on_sample(&p.sample());
        s.on_tick();
    }
    let mut p_g_true = 0.0;
    for _ in 0..50 {
        s.on_sample(&p.sample());
        p_g_true += p.state().p_g / 50.0;
    }
    let sig = scales.convert(&s.on_tick());
    let f = |x: tooltouch_model::units::Fx| x.to_num::<f64>();
    // V_line = √(Σv²/3) is the drive's 200 V; F2–F3: 1.5·I·V − R_s·Σi² = P_g.
    assert!((f(sig.v_line) - 200.0).abs() < 1.0, "V = {}", sig.v_line);
    let p_g = 1.5 * f(sig.i_line) * f(sig.v_line) - p.drive.stator_resistance * f(sig.amps_sq);
    assert!(
        (p_g - p_g_true).abs() < 0.01 * p_g_true,
        "P_g {p_g} W from the phases, {p_g_true} W in the plant"
    );
}

/// Case count: `PROPTEST_CASES`, else `TOOLTOUCH_CASES`, else `default`.
fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| tooltouch_model::testing::cases(default))
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: cases(4),
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x00e5_7a7e),
        ..ProptestConfig::default()
    }
}

/// The depth-step scenario (force control off) at a random operating point: force before
/// the step `force_before` N (feed chosen for it), depth ratio `ratio`, cutting speed
/// `rpm` (run-up from 200 rpm below), noise `seed`. The largest force stays inside the
/// current channel's range.
fn operating_point(
    seed: u64,
    ks: f64,
    before: f64,
    force_before: f64,
    ratio: f64,
    rpm: f64,
) -> ControlScenario {
    let mut sc = depth_step_scenario(seed);
    sc.process.ks = ks;
    sc.process.feed_mm_per_rev = force_before / (ks * before);
    sc.depth.before = before;
    sc.depth.after = before * ratio;
    sc.rpm_cut = rpm;
    sc.rpm_start = rpm - 200.0;
    sc
}

fn mean_error_pct(sc: &ControlScenario, kind: EstimateKind) -> (f64, f64, Option<f64>) {
    let r = run(sc, Engine::Model, false);
    let tr = &r.trace;
    let x = kind.series(tr);
    let (mut err, mut dyn_sum) = (0.0, 0.0);
    for (i, t) in tr.t.iter().enumerate() {
        if (*t > 5.0 && *t <= 8.0) || *t > 10.0 {
            err += x[i] - tr.force_meas[i];
            dyn_sum += tr.force_meas[i];
        }
    }
    let power_only_delay = delay_63(tr, &tr.force_power_only, sc.depth.step_at, DEPTH_LEVELS);
    let synthesized_delay = delay_63(tr, &tr.force_est, sc.depth.step_at, DEPTH_LEVELS);
    (
        100.0 * err / dyn_sum,
        power_only_delay.unwrap_or(f64::INFINITY) - synthesized_delay.unwrap_or(f64::INFINITY),
        synthesized_delay,
    )
}

proptest! {
    #![proptest_config(config())]

    /// F9's point: on a depth step the synthesized estimate reaches 63 % of the step at
    /// least 0.15 s before the power-only one (P_o lags 0.3 s), and in steady cutting it
    /// is within 1.5 % of the dynamometer on average.
    #[test]
    fn synthesized_estimate_is_faster_and_within_its_steady_bound(
        seed in any::<u64>(),
        ks in 1500.0..2500.0f64,
        before in 0.8..1.2f64,
        force_before in 300.0..550.0f64,
        ratio in 1.3..1.6f64,
        rpm in 700.0..900.0f64,
    ) {
        let sc = operating_point(seed, ks, before, force_before, ratio, rpm);
        let (err_pct, lead, delay) = mean_error_pct(&sc, EstimateKind::Synthesized);
        prop_assert!(delay.is_some(), "the synthesized estimate never reached 63 %");
        prop_assert!(lead > 0.15, "synthesized leads power-only by only {lead} s");
        prop_assert!(err_pct.abs() < 1.5, "steady mean error {err_pct} %");
    }

    /// The no-load identification over the run-up converges: B within 10 % and T_fco
    /// within 5 % of the plant's, for any noise and a cutting speed of 700–900 rpm.
    #[test]
    fn identification_converges_over_the_run_up(seed in any::<u64>(), rpm in 700.0..900.0f64) {
        let mut sc = run_up_scenario(seed);
        sc.rpm_cut = rpm;
        sc.rpm_start = rpm - 200.0;
        let (b, t_fco) = run(&sc, Engine::Model, false).identified;
        prop_assert!((b / sc.drive.viscous - 1.0).abs() < 0.10, "B = {b}");
        prop_assert!((t_fco / sc.drive.coulomb - 1.0).abs() < 0.05, "T_fco = {t_fco}");
    }
}

#[test]
fn report_of_the_default_plant_has_every_figure() {
    let r = report(1);
    assert_eq!(r.rows.len(), 6);
    let row = |scenario: &str, estimate: EstimateKind| {
        r.rows
            .iter()
            .find(|x| x.scenario == scenario && x.estimate == estimate.name())
            .expect("row")
    };
    let power = row("depth-step", EstimateKind::PowerOnly);
    let fast = row("depth-step", EstimateKind::Electrical);
    let synth = row("depth-step", EstimateKind::Synthesized);
    // the paper's picture: P_o lags ~0.3 s behind, the electrical estimate does not,
    // and is noisier; the synthesis takes the speed of one and the smoothness of the other
    let lag = power.lag_behind_dynamometer_s.expect("delay");
    assert!((0.2..0.45).contains(&lag), "power-only lag {lag} s");
    assert!(fast.lag_behind_dynamometer_s.expect("delay") < 0.1);
    assert!(synth.lag_behind_dynamometer_s.expect("delay") < 0.1);
    assert!(fast.sd_error_n > 2.0 * synth.sd_error_n);
    assert!(synth.peak_error_n < 0.5 * power.peak_error_n);
    assert!(synth.switches.expect("switches") >= 1);
    assert!(synth.fast_share_pct.expect("share") < 10.0);
    // the run-up reads no force in steady state once B and T_fco are identified
    let idle = row("run-up", EstimateKind::Synthesized);
    assert!(idle.mean_error_n.abs() < 2.0, "{} N", idle.mean_error_n);
    assert!(idle.mean_error_pct.is_none() && idle.delay_s.is_none());
    // files: CSV header and six rows; JSON with the identified parameters
    let csv = r.csv().expect("csv");
    assert_eq!(csv.lines().count(), 7);
    assert!(csv.starts_with("scenario,estimate,mean_error_n,"));
    let json: serde_json::Value = serde_json::from_str(&r.json().expect("json")).expect("parses");
    assert!(json["identified_viscous"].as_f64().is_some());
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(6));
}
