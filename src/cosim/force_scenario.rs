//! A compact, physically shaped force-path stream for the co-simulation (until the drive
//! simulator's streams are wired in): a spindle at about 100 rad/s, no-load
//! identification first (SPEC 3: B identified just before the tool touches), then a cut
//! whose force follows the feed override the golden model commands (a first-order
//! process, F10) with a depth-of-cut step (1 mm → 1.5 mm, the paper F experiment),
//! three-phase voltages and currents (F2, F3), measured power (W9), noise, CNC commands
//! (conditions, some out of range; tool changes) — and, as a fault, ADC saturation
//! (codes clipped at 0 and 4095).
//!
//! Floats here are the plant only; everything the firmware sees is 12-bit codes.

use rand::Rng;
use rand_distr::{Distribution, Normal};
use tooltouch_model::force::{ForceConfig, ForceEvent, ForceKernel};
use tooltouch_model::sampling::AdcCodes;

/// Largest ADC code (12 bits).
const ADC_MAX: f64 = 4095.0;

fn code(x: f64) -> u16 {
    x.round().clamp(0.0, ADC_MAX) as u16
}

/// Force events from `start` for `periods` control periods at `tick_hz` ticks per second;
/// `saturate` drives the ADC into its rails for part of the cut.
pub fn force_events(
    rng: &mut impl Rng,
    config: &ForceConfig,
    tick_hz: u32,
    start: u64,
    periods: u32,
    saturate: bool,
) -> Vec<(u64, ForceEvent)> {
    let s = config.settings();
    let sample_ticks = u64::from(tick_hz) / u64::from(s.sample_hz.max(1));
    let per_period = u32::from(s.samples_per_period.max(1));
    let scales = s.scales;
    let lsb = |v: tooltouch_model::force::Fx| v.to_num::<f64>().max(1e-9);
    let noise = Normal::new(0.0, rng.gen_range(0.5..4.0)).unwrap_or(Normal::new(0.0, 1.0).unwrap());
    // Process: F = K·a·u/100 with a first-order lag (F10); K·a chosen so the reference
    // force needs an override near 100 %.
    let k_nominal = rng.gen_range(3.0..8.0); // N per % at 1 mm depth
    let tau = rng.gen_range(0.03..0.15); // s
    let omega0 = rng.gen_range(80.0..120.0); // rad/s
    let v_amp = rng.gen_range(250.0..330.0); // V peak
    let r = 0.02; // workpiece radius, m
    let identify_on = 1;
    let identify_off = rng.gen_range(4..8);
    let cut_start = identify_off + rng.gen_range(1..4);
    let depth_step = cut_start + (periods.saturating_sub(cut_start)) / 2;
    let cut_end = periods.saturating_sub(rng.gen_range(1..4));
    let saturate_from = depth_step.saturating_sub(3);
    let saturate_to = depth_step + 3;
    let mut kernel = ForceKernel::new(config);
    let mut out = Vec::new();
    let mut force = 0.0f64;
    let dt = 1.0 / f64::from(s.sample_hz.max(1));
    let mut t = start;
    let mut phase = rng.gen_range(0.0..std::f64::consts::TAU);
    for period in 0..periods {
        // CNC commands at the start of the period.
        let mut commands = Vec::new();
        if period == identify_on {
            commands.push(ForceEvent::Identify(true));
        }
        if period == identify_off {
            commands.push(ForceEvent::Identify(false));
            commands.push(ForceEvent::Conditions(0));
        }
        if period == cut_start {
            commands.push(ForceEvent::Control(true));
        }
        if period == cut_end {
            commands.push(ForceEvent::Control(false));
        }
        if period > cut_start && rng.gen_bool(0.03) {
            commands.push(ForceEvent::Conditions(rng.gen_range(0..10)));
        }
        if period > cut_start && rng.gen_bool(0.02) {
            commands.push(ForceEvent::ToolChanged);
        }
        for c in commands {
            t += 1;
            out.push((t, c));
            kernel.apply(c);
        }
        let cutting = period >= cut_start && period < cut_end;
        let depth = if period >= depth_step { 1.5 } else { 1.0 };
        let u = f64::from(kernel.outputs().override_pct);
        let gain = if saturate && (saturate_from..saturate_to).contains(&period) {
            4.0
        } else {
            1.0
        };
        for k in 0..per_period {
            let target = if cutting { k_nominal * depth * u } else { 0.0 };
            force += (target - force) * (dt / tau).min(1.0);
            let omega = omega0 - 0.01 * force + noise.sample(rng) * 0.05;
            let p_cut = force * omega * r;
            let p_idle = 0.005 * omega * omega + 1.0 * omega;
            let p = p_idle + p_cut;
            let i_amp = 2.0 * p / (3.0 * v_amp * (std::f64::consts::PI / 6.0).cos());
            phase += std::f64::consts::TAU * 50.0 * dt;
            let ph = |shift: f64| (phase - shift).sin();
            let third = std::f64::consts::TAU / 3.0;
            let codes = AdcCodes {
                speed: code(omega / lsb(scales.speed_per_lsb) + noise.sample(rng)),
                power: code(gain * p / lsb(scales.power_per_lsb) + noise.sample(rng)),
                force: code(2048.0 + gain * force / lsb(scales.force_per_lsb) + noise.sample(rng)),
                volts: [
                    code(2048.0 + gain * v_amp * ph(0.0) / lsb(scales.volts_per_lsb)),
                    code(2048.0 + gain * v_amp * ph(third) / lsb(scales.volts_per_lsb)),
                    code(2048.0 + gain * v_amp * ph(2.0 * third) / lsb(scales.volts_per_lsb)),
                ],
                amps: [
                    code(
                        2048.0
                            + gain * i_amp * ph(0.5) / lsb(scales.amps_per_lsb)
                            + noise.sample(rng),
                    ),
                    code(2048.0 + gain * i_amp * ph(0.5 + third) / lsb(scales.amps_per_lsb)),
                ],
            };
            t += sample_ticks.max(1);
            out.push((t, ForceEvent::Sample(codes)));
            kernel.apply(ForceEvent::Sample(codes));
            if k + 1 == per_period {
                // The tick closes the period at the last sample's time (sample first).
                out.push((t, ForceEvent::Tick));
                kernel.apply(ForceEvent::Tick);
            }
        }
    }
    out
}
