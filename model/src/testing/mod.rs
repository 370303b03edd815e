//! The test kit: the one place random configurations are drawn (feature `testing`).
//!
//! Every test, co-simulation scenario and random HDL configuration of the workspace draws
//! its [`MeasureSettings`] from [`measure_settings`] (a proptest [`Strategy`]) or
//! [`draw_measure`] (the same strategy driven by a `u64` seed, for code that counts seeds
//! rather than running proptest). The strategy builds the settings as a full struct literal,
//! so a new field does not compile until it is drawn here; users differ only in a
//! [`MeasureProfile`] of numbers (ranges and biases), never in which fields are drawn.
//! Each numeric field is drawn edge-biased: its profile's ends come up often, because the
//! ends are where kernels overflow, wrap or never fire. [`cases`] reads `TOOLTOUCH_CASES`.
//!
//! This module needs `std` (proptest); the rest of the crate stays `no_std`.

use proptest::prelude::*;
use proptest::strategy::{Union, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::vec;

use crate::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use crate::{MeasureChecks, MeasureConfig, MeasureSettings};

pub mod force;
#[cfg(test)]
mod tests;

/// Ranges and biases of a [`measure_settings`] draw. Ranges are inclusive; fields that
/// depend on another (thresholds on the charge register's full scale, `i_def` on the window)
/// are drawn as a fraction of their valid range, in per-mille.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeasureProfile {
    /// FES pulses per revolution (valid `16..=16384`).
    pub pulses_per_rev: (u16, u16),
    /// Revolutions per counting window (valid `1..=16`).
    pub window_revs: (u8, u8),
    /// `i_def` as per-mille of the window's last pulse (`window - 1`).
    pub i_def_permille: (u32, u32),
    /// Upper bound on `i_def`, pulses (a low bound decides within a short stimulus).
    pub i_def_cap: (u32, u32),
    /// Charge register width, bits (valid `4..=24`).
    pub charge_bits: (u8, u8),
    /// Linear charge and discharge steps as per-mille of full scale (at least 1 LSB).
    pub step_permille: (u32, u32),
    /// Exponential charge and discharge shifts (capped at `charge_bits`).
    pub shift: (u8, u8),
    /// Fire threshold as per-mille of `1..=full scale`.
    pub fire_permille: (u32, u32),
    /// Re-arm threshold as per-mille of `0..=fire_threshold - 1`.
    pub rearm_permille: (u32, u32),
    /// Glitch filter, clocks (valid `0..=255`).
    pub glitch_cycles: (u8, u8),
    /// Scale counter width, bits (valid `8..=32`).
    pub scale_bits: (u8, u8),
    /// Chance, percent, that a numeric field is drawn over its whole valid range instead of
    /// the profile's (an occasional large value where the profile keeps values small).
    pub wide_percent: u32,
}

impl MeasureProfile {
    /// Every valid value of every field (the ranges `MeasureSettings::validate` checks):
    /// round trips of the configuration's encoding; also the range a profile's wide draws
    /// span.
    pub const FULL: Self = Self {
        pulses_per_rev: (16, 16384),
        window_revs: (1, 16),
        i_def_permille: (0, 1000),
        i_def_cap: (u32::MAX, u32::MAX),
        charge_bits: (4, 24),
        step_permille: (0, 1000),
        shift: (0, 24),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 255),
        scale_bits: (8, 32),
        wide_percent: 0,
    };

    /// The kernel's own property tests: a 32-pulse window (16 ppr × 2) and charge registers
    /// of 4–9 bits, so runs of a few hundred pulses cross every threshold.
    pub const KERNEL: Self = Self {
        pulses_per_rev: (16, 16),
        window_revs: (2, 2),
        i_def_permille: (0, 1000),
        i_def_cap: (u32::MAX, u32::MAX),
        charge_bits: (4, 9),
        step_permille: (0, 1000),
        shift: (0, 9),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 255),
        scale_bits: (8, 32),
        wide_percent: 0,
    };

    /// HDL co-simulation (Verilator, Icarus) and lint: few pulses per window, `i_def` below
    /// 24, coarse charge steps and short glitch filters, so a 30 000-clock stimulus decides
    /// many times; one field in seven spans its whole valid range (wide registers, long
    /// filters).
    pub const HDL_COSIM: Self = Self {
        pulses_per_rev: (16, 48),
        window_revs: (1, 3),
        i_def_permille: (0, 1000),
        i_def_cap: (23, 23),
        charge_bits: (4, 24),
        step_permille: (62, 500),
        shift: (0, 4),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 6),
        scale_bits: (8, 32),
        wide_percent: 15,
    };

    /// The lathe's event-level co-simulation (firmware on QEMU): realistic encoders of
    /// 16–1024 pulses per revolution, 1–3-revolution windows, `i_def` at 20–80 % of the
    /// window (the papers use 50 %), charge steps up to a quarter of full scale.
    pub const LATHE_COSIM: Self = Self {
        pulses_per_rev: (16, 1024),
        window_revs: (1, 3),
        i_def_permille: (200, 800),
        i_def_cap: (u32::MAX, u32::MAX),
        charge_bits: (4, 24),
        step_permille: (0, 250),
        shift: (0, 9),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 255),
        scale_bits: (8, 32),
        wide_percent: 0,
    };

    /// Cycle level against event level on a simulated lathe: 16–128 ppr, 4–16-bit charge
    /// registers, glitch filters of at most 6 clocks (the lathe's low clock rates make
    /// longer ones swallow whole pulses).
    pub const LEVELS: Self = Self {
        pulses_per_rev: (16, 128),
        window_revs: (1, 3),
        i_def_permille: (0, 1000),
        i_def_cap: (u32::MAX, u32::MAX),
        charge_bits: (4, 16),
        step_permille: (15, 1000),
        shift: (0, 6),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 6),
        scale_bits: (8, 32),
        wide_percent: 0,
    };

    /// The firmware's host tests of its handlers: short windows, `i_def` below 24 and small
    /// charge registers, so a burst or two of contact pulses decides; no glitch filter (the
    /// firmware's event stream is already filtered).
    pub const FIRMWARE_HANDLERS: Self = Self {
        pulses_per_rev: (16, 40),
        window_revs: (1, 3),
        i_def_permille: (0, 1000),
        i_def_cap: (23, 23),
        charge_bits: (4, 8),
        step_permille: (0, 1000),
        shift: (0, 8),
        fire_permille: (0, 1000),
        rearm_permille: (0, 1000),
        glitch_cycles: (0, 0),
        scale_bits: (8, 32),
        wide_percent: 0,
    };

    /// Every profile, for tests that check them all.
    pub const ALL: [(&'static str, Self); 6] = [
        ("FULL", Self::FULL),
        ("KERNEL", Self::KERNEL),
        ("HDL_COSIM", Self::HDL_COSIM),
        ("LATHE_COSIM", Self::LATHE_COSIM),
        ("LEVELS", Self::LEVELS),
        ("FIRMWARE_HANDLERS", Self::FIRMWARE_HANDLERS),
    ];
}

/// `value` per-mille of the way from `lo` to `hi` (rounded down).
pub fn per_mille(value: u32, lo: u32, hi: u32) -> u32 {
    lo + (u64::from(hi - lo) * u64::from(value) / 1000) as u32
}

/// A number in `span`, edge-biased (each end one draw in eight), or with `wide_percent`
/// chance one in `valid` (edge-biased the same way).
fn field(span: (u32, u32), valid: (u32, u32), wide_percent: u32) -> BoxedStrategy<u32> {
    fn edged(span: (u32, u32)) -> BoxedStrategy<u32> {
        let (lo, hi) = span;
        prop_oneof![1 => Just(lo), 1 => Just(hi), 6 => lo..=hi].boxed()
    }
    let mut arms = vec![(100 - wide_percent.min(100), edged(span))];
    if wide_percent > 0 {
        arms.push((wide_percent.min(100), edged(valid)));
    }
    arms.retain(|(w, _)| *w > 0);
    Union::new_weighted(arms).boxed()
}

fn field_u8(span: (u8, u8), valid: (u8, u8), wide_percent: u32) -> BoxedStrategy<u8> {
    let widen = |(lo, hi): (u8, u8)| (u32::from(lo), u32::from(hi));
    field(widen(span), widen(valid), wide_percent)
        .prop_map(|v| v as u8)
        .boxed()
}

fn field_u16(span: (u16, u16), valid: (u16, u16), wide_percent: u32) -> BoxedStrategy<u16> {
    let widen = |(lo, hi): (u16, u16)| (u32::from(lo), u32::from(hi));
    field(widen(span), widen(valid), wide_percent)
        .prop_map(|v| v as u16)
        .boxed()
}

/// Every variant of the decision method.
pub const METHODS: [DecisionMethod; 3] = [
    DecisionMethod::SinglePulse,
    DecisionMethod::Counter,
    DecisionMethod::Density,
];

/// Every variant of the contact rule.
pub const CONTACT_RULES: [ContactRule; 2] = [ContactRule::Sampled, ContactRule::Sticky];

/// Valid measurement settings drawn with `profile`: every field, every variant of every
/// enum (method, contact rule, linear or exponential charge law).
pub fn measure_settings(profile: &MeasureProfile) -> impl Strategy<Value = MeasureSettings> {
    let p = profile;
    let w = p.wide_percent;
    let v = &MeasureProfile::FULL;
    let layout = (
        field_u16(p.pulses_per_rev, v.pulses_per_rev, w),
        field_u8(p.window_revs, v.window_revs, w),
        field(p.i_def_permille, v.i_def_permille, w),
        field(p.i_def_cap, (0, u32::MAX), w),
        field_u8(p.charge_bits, v.charge_bits, w),
    );
    let law = (
        any::<bool>(),
        field(p.step_permille, v.step_permille, w),
        field(p.step_permille, v.step_permille, w),
        field_u8(p.shift, v.shift, w),
        field_u8(p.shift, v.shift, w),
    );
    let rest = (
        field(p.fire_permille, v.fire_permille, w),
        field(p.rearm_permille, v.rearm_permille, w),
        field_u8(p.glitch_cycles, v.glitch_cycles, w),
        field_u8(p.scale_bits, v.scale_bits, w),
        proptest::sample::select(&CONTACT_RULES[..]),
        proptest::sample::select(&METHODS[..]),
    );
    (layout, law, rest, measure_checks()).prop_map(
        |(
            (pulses_per_rev, window_revs, i_def_permille, i_def_cap, charge_bits),
            (linear, charge_step, discharge_step, charge_shift, discharge_shift),
            (fire, rearm, glitch_cycles, scale_bits, contact_rule, method),
            checks,
        )| {
            let window = u32::from(pulses_per_rev) * u32::from(window_revs);
            let full = (1u32 << charge_bits) - 1;
            let fire_threshold = per_mille(fire, 1, full);
            // A struct literal without `..Default::default()`: a new field must be drawn.
            MeasureSettings {
                pulses_per_rev,
                i_def: per_mille(i_def_permille, 0, window - 1).min(i_def_cap),
                window_revs,
                contact_rule,
                charge_bits,
                charge_law: if linear {
                    ChargeLaw::Linear {
                        charge_step: per_mille(charge_step, 0, full).max(1),
                        discharge_step: per_mille(discharge_step, 0, full).max(1),
                    }
                } else {
                    ChargeLaw::Exponential {
                        charge_shift: charge_shift.min(charge_bits),
                        discharge_shift: discharge_shift.min(charge_bits),
                    }
                },
                fire_threshold,
                rearm_threshold: per_mille(rearm, 0, fire_threshold - 1),
                glitch_cycles,
                scale_bits,
                method,
                checks: MeasureChecks {
                    pulse_tolerance: checks.pulse_tolerance.min(pulses_per_rev / 4),
                    ..checks
                },
            }
        },
    )
}

/// The measurement status's checks, drawn so that short random streams reach every
/// condition: each check on or off, a tolerance of 0–4 pulses (clamped to the
/// configuration's quarter revolution by the caller), a probe fail after 0–16 revolutions,
/// an FES watchdog off or of 1–4096 ticks, 0–4 confirmation windows at 1–100 %.
pub fn measure_checks() -> impl Strategy<Value = MeasureChecks> {
    (
        any::<[bool; 3]>(),
        0u16..=4,
        0u16..=16,
        prop_oneof![Just(0u32), 1u32..=4096],
        0u8..=4,
        1u8..=100,
    )
        .prop_map(
            |(
                [contact_at_arm, revolutions, scale_errors],
                pulse_tolerance,
                probe_revs,
                fes_timeout_cycles,
                confirm_windows,
                confirm_percent,
            )| MeasureChecks {
                contact_at_arm,
                revolutions,
                pulse_tolerance,
                scale_errors,
                probe_revs,
                fes_timeout_cycles,
                confirm_windows,
                confirm_percent,
            },
        )
}

/// [`measure_settings`], validated.
pub fn measure_configs(profile: &MeasureProfile) -> impl Strategy<Value = MeasureConfig> {
    measure_settings(profile).prop_map(|s| {
        s.validate()
            .unwrap_or_else(|e| panic!("the test kit drew an invalid field: {e}"))
    })
}

/// A runner whose random stream is fixed by `seed` (ChaCha, so draws are stable across
/// platforms and proptest releases that keep the algorithm).
pub fn seeded_runner(seed: u64) -> TestRunner {
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &bytes),
    )
}

/// One draw of `strategy` fixed by `seed`.
pub fn draw<S: Strategy>(strategy: &S, seed: u64) -> S::Value {
    strategy
        .new_tree(&mut seeded_runner(seed))
        .unwrap_or_else(|e| panic!("the test kit's strategy rejected every draw: {e}"))
        .current()
}

/// The validated measurement configuration that `seed` draws with `profile`.
pub fn draw_measure(profile: &MeasureProfile, seed: u64) -> MeasureConfig {
    draw(&measure_configs(profile), seed)
}

/// Case count of a property test: `TOOLTOUCH_CASES` if set to a number, else `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("TOOLTOUCH_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}
