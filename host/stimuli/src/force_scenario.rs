//! The co-simulation's force path: a random spindle drive and turning process
//! ([`tooltouch_plant::drive`]: V/f induction motor with its speed loop, lagging measured power, F10
//! with drifting K_s and τ_p, a depth-of-cut step) closed around the golden model's
//! [`ForceKernel`] ([`ClosedLoop`]), under a random force configuration
//! ([`random_force_settings`]: the test kit's draw with the gains, scales, reference,
//! estimator constants and wear powers fitted to that plant) — and a CNC timeline: no-load identification first
//! (docs/domain.md §3: B identified just before the tool touches), condition set 0, the cut under
//! force control with the depth step, retract; random condition changes (some out of
//! range) and tool changes. As a fault, ADC saturation: the front end's gain is 4× for a
//! few periods around the depth step, so every channel clips at 0 or 4095.
//!
//! The recorded events are exactly what the plant produces when the device's overrides
//! equal the model's, so a firmware that agrees bit for bit has been tested in the loop.
//! Floats here are the plant only; everything the firmware sees is 12-bit codes.

use rand::{Rng, RngExt};
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::control::{
    AdaptiveSettings, ControllerSettings, FuzzySettings, PiSettings,
};
use tooltouch_model::force::estimator::settings::EstimatorSettings;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::sampling::AdcScales;
use tooltouch_model::force::sampling::{AdcChannel, AdcCodes, ADC_MAX, ADC_MID};
use tooltouch_model::force::wear::{ConditionSet, Threshold, WearSettings};
use tooltouch_model::testing::force::draw_force;
use tooltouch_model::units::Fx;
use tooltouch_plant::drive::scenario::ClosedLoop;
use tooltouch_plant::drive::{DepthProfile, DriveParams, Plant, ProcessParams};
use tooltouch_plant::reference::design::{
    adaptive_settings, fuzzy_from_pi, pi_settings, NominalProcess,
};

/// ADC sample rates drawn, Hz (each divides the 50 MHz tick rate).
pub const SAMPLE_RATES: [u16; 4] = [500, 1000, 1250, 2000];

/// A random plant: drive, process, depth step and spindle speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantSetup {
    /// Spindle drive.
    pub drive: DriveParams,
    /// Turning process F10.
    pub process: ProcessParams,
    /// Depth of cut before and after the step, mm (`step_at` is set by the timeline).
    pub depth: DepthProfile,
    /// Spindle speed, rad/s.
    pub speed: f64,
}

/// Draws a plant around `tooltouch control`'s default one.
pub fn random_plant(rng: &mut impl Rng) -> PlantSetup {
    let drive = DriveParams {
        inertia: rng.random_range(0.02..0.1),
        viscous: rng.random_range(0.002..0.01),
        coulomb: rng.random_range(0.5..2.0),
        friction_f0: rng.random_range(0.0..0.1),
        friction_g0: rng.random_range(0.0..0.004),
        slip_stiffness: rng.random_range(3.0..8.0),
        speed_ki: rng.random_range(3.0..8.0),
        stator_resistance: rng.random_range(0.2..1.0),
        line_voltage: rng.random_range(180.0..240.0),
        pole_pairs: f64::from(rng.random_range(1u8..=3)),
        power_lag: rng.random_range(0.1..0.5),
        adc_noise: rng.random_range(0.5..3.0),
    };
    let process = ProcessParams {
        ks: rng.random_range(1500.0..2500.0),
        ks_drift: rng.random_range(-0.02..0.02),
        tau_p: rng.random_range(0.04..0.15),
        tau_drift: rng.random_range(-0.02..0.02),
        feed_mm_per_rev: rng.random_range(0.2..0.4),
        radius: rng.random_range(0.01..0.04),
        ripple: rng.random_range(0.0..0.03),
    };
    let before = rng.random_range(0.8..1.2);
    PlantSetup {
        drive,
        process,
        depth: DepthProfile {
            before,
            after: before * rng.random_range(1.2..1.6),
            step_at: f64::INFINITY,
        },
        speed: rng.random_range(400.0..1000.0) * std::f64::consts::TAU / 60.0,
    }
}

fn fx(x: f64) -> Fx {
    Fx::from_num(x)
}

/// Draws force-path settings fitted to `plant`: the test kit's draw
/// ([`tooltouch_model::testing::force::draw_force`], every field inside its validated
/// range) with what the plant dictates overridden — a sample rate that divides the tick rate
/// and a period of 20–100 ms; ADC scales that keep the plant's signals inside 12 bits; a
/// sampling low-pass no slower than half a control period (the kit's shift, capped); a
/// reference of 200–800 N and a manual override of 60–140 % (so the cut before force
/// control stays inside the ADC range too); the estimator's drive constants near the
/// plant's (misestimated by up to ±50 %), its speed floor below the spindle speed and its
/// slip gain near 1; the controller's gains designed on the plant's nominal process and
/// detuned by up to 2× (PI integrator clamps, the adaptive controller's re-estimation
/// guards and the fuzzy scalings with them); the wear monitor's powers and efficiency from
/// the plant's idle and cutting power. Everything else — controller kind, force source,
/// the adaptive gain filter, the fuzzy rule table, the F9 switch threshold and hold, the
/// number of condition sets, the wear filter, debounce and threshold kind — is the kit's.
pub fn random_force_settings(rng: &mut impl Rng, plant: &PlantSetup) -> ForceSettings {
    let kit = draw_force(rng.random());
    let d = &plant.drive;
    let p = &plant.process;
    let sample_hz = SAMPLE_RATES[rng.random_range(0..SAMPLE_RATES.len())];
    let h_target = rng.random_range(0.02..0.1);
    let samples_per_period = ((h_target * f64::from(sample_hz)).round() as u16).clamp(1, 1000);
    let h = f64::from(samples_per_period) / f64::from(sample_hz);
    let reference = rng.random_range(200.0..800.0);
    let omega = plant.speed;
    let idle = d.coulomb * omega + d.viscous * omega * omega;
    let cut = reference * p.radius * omega;
    // Signals at most ~1.5× their expected peaks stay inside 0..=4095 (2048 ± 2047 for
    // the bipolar channels).
    let p_peak = idle + 2.5 * cut;
    let v_peak = std::f64::consts::SQRT_2 * d.line_voltage;
    let i_peak = std::f64::consts::SQRT_2 * p_peak / (1.5 * d.line_voltage);
    let scales = AdcScales {
        speed_per_lsb: fx(1.3 * omega / rng.random_range(2000.0..3500.0)),
        power_per_lsb: fx(p_peak / rng.random_range(2000.0..3500.0)),
        force_per_lsb: fx(2.5 * reference / rng.random_range(1200.0..1900.0)),
        volts_per_lsb: fx(v_peak / rng.random_range(1200.0..1900.0)),
        amps_per_lsb: fx(i_peak / rng.random_range(1000.0..1800.0)),
    };
    let estimator = EstimatorSettings {
        stator_resistance: fx(d.stator_resistance * rng.random_range(0.8..1.2)),
        inertia: fx(d.inertia * rng.random_range(0.9..1.1)),
        // B ≤ J/(2h) (validate); the plant's B is far below.
        viscous_nominal: fx(
            (d.viscous * rng.random_range(0.5..1.5)).min(d.inertia * 0.9 / (2.0 * h))
        ),
        coulomb_nominal: fx(d.coulomb * rng.random_range(0.5..1.5)),
        friction_f: [
            fx(d.friction_f0 * rng.random_range(0.5..1.5)),
            fx(rng.random_range(-0.001..0.001)),
        ],
        friction_g: [
            fx(d.friction_g0 * rng.random_range(0.5..1.5)),
            fx(rng.random_range(-1e-4..1e-4)),
        ],
        min_speed: fx(rng.random_range(1.0..20.0)),
        slip_gain: fx(rng.random_range(0.8..1.2)),
        workpiece_radius: fx(p.radius),
        ..kit.estimator
    };
    let nominal = NominalProcess {
        ks: p.ks,
        depth_mm: plant.depth.before,
        feed_mm_per_rev: p.feed_mm_per_rev,
        tau_p: p.tau_p,
        period: h,
    };
    let (kp, ki) = nominal.ziegler_nichols_pi();
    let (kp, ki) = (
        kp * rng.random_range(0.5..2.0),
        ki * rng.random_range(0.5..2.0),
    );
    let k = nominal.gain();
    let controller = match kit.controller {
        ControllerSettings::Pi(_) => ControllerSettings::Pi(PiSettings {
            integrator_min: fx(f64::from(rng.random_range(0..=40))),
            integrator_max: fx(f64::from(rng.random_range(180..=255))),
            ..pi_settings(kp, ki)
        }),
        ControllerSettings::Adaptive(drawn) => ControllerSettings::Adaptive(AdaptiveSettings {
            gain_min: fx(k / rng.random_range(5.0..20.0)),
            gain_max: fx(k * rng.random_range(5.0..30.0)),
            initial_gain: fx(k * rng.random_range(0.5..2.0)),
            gain_filter_shift: drawn.gain_filter_shift,
            min_override: fx(rng.random_range(1.0..20.0)),
            min_force: fx(rng.random_range(10.0..100.0)),
            ..adaptive_settings(rng.random_range(0.1..0.6) / h, k)
        }),
        ControllerSettings::Fuzzy(drawn) => ControllerSettings::Fuzzy(FuzzySettings {
            rules: drawn.rules,
            ..fuzzy_from_pi(kp, ki, h, rng.random_range(150.0..500.0))
        }),
    };
    let mut sets = kit.wear.sets;
    for set in sets.iter_mut().take(usize::from(kit.wear.set_count)) {
        *set = ConditionSet {
            mean_power_limit: fx(cut * rng.random_range(0.6..1.5)),
            idle_power: fx(idle * rng.random_range(0.7..1.3)),
        };
    }
    let wear = WearSettings {
        sets,
        efficiency: fx(rng.random_range(0.6..1.0)),
        threshold: match kit.wear.threshold {
            Threshold::Updating => Threshold::Updating,
            Threshold::Constant(_) => {
                Threshold::Constant(fx(idle + cut * rng.random_range(0.8..1.5)))
            }
        },
        ..kit.wear
    };
    // The sampling low-pass's time constant, 2^k samples, at most half a control period:
    // a slower filter lags the loop into oscillation and the plant's force off the ADC.
    let slowest_lowpass = (u16::BITS - 1 - (samples_per_period / 2).max(2).leading_zeros()) as u8;
    ForceSettings {
        sample_hz,
        samples_per_period,
        lowpass_shift: kit.lowpass_shift.min(slowest_lowpass),
        scales,
        estimator,
        reference: fx(reference),
        manual_override: rng.random_range(60..=140),
        controller,
        wear,
        ..kit
    }
}

/// The front end with 4× gain: every channel clips at its rails.
fn saturate(c: AdcCodes) -> AdcCodes {
    let mut out = c;
    for ch in AdcChannel::ALL {
        let m = if ch.bipolar() { ADC_MID } else { 0 };
        let v = m + 4 * (i32::from(c[ch]) - m);
        out[ch] = v.clamp(0, i32::from(ADC_MAX)) as u16;
    }
    out
}

/// Runs `plant` closed around the golden kernel for `config` for about `duration` s and
/// returns the force events with their times in ticks of `tick_hz` (sample k at
/// `(k + 1)·tick_hz/sample_hz`; a tick and the CNC commands after a sample carry its
/// time). `saturate_adc` clips the ADC for a few periods around the depth step.
pub fn force_events(
    rng: &mut impl Rng,
    config: &ForceConfig,
    plant: &PlantSetup,
    tick_hz: u32,
    duration: f64,
    saturate_adc: bool,
) -> Vec<(u64, ForceEvent)> {
    let s = config.settings();
    let fs = f64::from(s.sample_hz.max(1));
    let spp = u64::from(s.samples_per_period.max(1));
    let h = spp as f64 / fs;
    let periods = ((duration / h).round() as u64).max(20);
    let at = |t: f64| ((t * periods as f64).round() as u64).clamp(1, periods - 1);
    let identify_on = at(rng.random_range(0.03..0.1));
    let identify_off = at(rng.random_range(0.25..0.35));
    let cut_start = at(rng.random_range(0.38..0.45));
    let depth_step = at(rng.random_range(0.62..0.72));
    let cut_end = at(rng.random_range(0.9..0.96));
    let mut depth = plant.depth;
    depth.step_at = depth_step as f64 * h;
    let sim = Plant::new(
        plant.drive,
        plant.process,
        depth,
        &s.scales,
        fs,
        plant.speed,
        rng.random(),
    );
    let mut lp = ClosedLoop::new(config, sim);
    let set_count = s.wear.set_count;
    for period in 0..periods {
        // CNC commands at the start of the period (after the previous period's tick).
        if period > 0 {
            if period == identify_on {
                lp.command(ForceEvent::Identify(true));
            }
            if period == identify_off {
                lp.command(ForceEvent::Identify(false));
                lp.command(ForceEvent::Conditions(0));
            }
            if period == cut_start {
                lp.command(ForceEvent::Control(true));
            }
            if period == cut_end {
                lp.command(ForceEvent::Control(false));
            }
            if period > cut_start && rng.random_bool(0.03) {
                // Mostly valid sets, sometimes one out of range (a bad event).
                lp.command(ForceEvent::Conditions(rng.random_range(0..set_count + 2)));
            }
            if period > cut_start && rng.random_bool(0.02) {
                lp.command(ForceEvent::ToolChanged);
            }
        }
        let clip = saturate_adc && period + 3 >= depth_step && period < depth_step + 3;
        for _ in 0..spp {
            if clip {
                lp.step(saturate);
            } else {
                lp.step(|c| c);
            }
        }
    }
    let sample_ticks = u64::from(tick_hz) / u64::from(s.sample_hz.max(1));
    lp.into_events()
        .into_iter()
        .map(|(k, e)| ((k + 1) * sample_ticks.max(1), e))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn random_force_settings_are_valid_and_cover_every_controller() {
        let mut kinds = std::collections::HashMap::new();
        for seed in 0..300 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let plant = random_plant(&mut rng);
            let s = random_force_settings(&mut rng, &plant);
            let c = s
                .validate()
                .unwrap_or_else(|e| panic!("seed {seed}: {e}\n{s:?}"));
            *kinds.entry(c.settings().controller.name()).or_insert(0) += 1;
        }
        assert_eq!(kinds.len(), 3, "{kinds:?}");
        assert!(kinds.values().all(|&n| n > 50), "{kinds:?}");
    }

    #[test]
    fn the_plant_stream_stays_inside_the_adc_range_and_is_controlled() {
        for seed in 0..6 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let plant = random_plant(&mut rng);
            let config = random_force_settings(&mut rng, &plant).validate().unwrap();
            let events = force_events(&mut rng, &config, &plant, 50_000_000, 3.0, false);
            assert!(events.windows(2).all(|w| w[0].0 <= w[1].0), "time order");
            let clipped = events.iter().any(|(_, e)| {
                matches!(e, ForceEvent::Sample(c)
                    if c.to_array()
                        .iter()
                        .any(|&v| v == 0 || v == ADC_MAX))
            });
            assert!(!clipped, "seed {seed}: a clean case clips the ADC");
            assert!(events.iter().any(|(_, e)| *e == ForceEvent::Control(true)));
        }
    }
}
