//! Face-milling spindle power with flank wear (docs/domain.md §4, paper W: W1–W7), the
//! precomputation of the wear monitor's condition sets (W8–W9), and the wear scenario of
//! `tooltouch wear`.
//!
//! Units: lengths in mm except the cutter diameter in the power formulas (m), C and H in
//! N/mm², forces in N, speed n in rev/s inside the formulas, powers in W. The papers'
//! constants are the defaults: C = 1.54 (paper: "MN/m"; read here as 1.54 kN/mm² = 1540
//! N/mm² so that `b·C·a^(−x)·s_z` is a force in N with b, a, s_z in mm — our reading),
//! x = 0.23, μ = 0.1, H = 1680 N/mm² (cast iron), D = 100 mm, Z = 5, t = 70 mm.

use crate::milling_transients::{ToothTransients, TransientMeter};
use crate::reference::f;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;
use tooltouch_model::force::config::{ForceConfig, ForceSettings};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::{AdcCodes, ADC_MAX, ADC_MID};
use tooltouch_model::force::wear::{ConditionSet, Threshold, WearSettings, MAX_CONDITION_SETS};
use tooltouch_model::units::Fx;

/// Cutter, workpiece and machine data (strategy step 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MillingParams {
    /// Cutting-force constant C, N/mm².
    pub c: f64,
    /// Chip-thickness exponent x.
    pub x: f64,
    /// Flank friction coefficient μ.
    pub mu: f64,
    /// Workpiece hardness H, N/mm².
    pub hardness: f64,
    /// Cutter diameter D, mm.
    pub diameter_mm: f64,
    /// Teeth Z.
    pub teeth: u32,
    /// Width of cut t, mm.
    pub width_mm: f64,
    /// Offset δ of the cutter axis from the middle of the cut, mm.
    pub offset_mm: f64,
    /// Idle spindle power p_i, W.
    pub idle_power: f64,
    /// Machine efficiency η.
    pub efficiency: f64,
}

impl Default for MillingParams {
    fn default() -> Self {
        MillingParams {
            c: 1540.0,
            x: 0.23,
            mu: 0.1,
            hardness: 1680.0,
            diameter_mm: 100.0,
            teeth: 5,
            width_mm: 70.0,
            offset_mm: 0.0,
            idle_power: 300.0,
            efficiency: 0.8,
        }
    }
}

/// Current cutting conditions (strategy step 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    /// Depth of cut b (= cutting-edge length l), mm.
    pub depth_mm: f64,
    /// Feed per tooth s_z, mm.
    pub feed_per_tooth_mm: f64,
    /// Spindle speed, rpm.
    pub rpm: f64,
}

/// Engagement angles: ψ_1, ψ_2, ψ, φ_v (entry), φ_r (exit), rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angles {
    /// ψ_1 = arcsin((t + 2δ)/D).
    pub psi1: f64,
    /// ψ_2 = arcsin((t − 2δ)/D).
    pub psi2: f64,
    /// ψ = ψ_1 + ψ_2.
    pub psi: f64,
    /// Entry angle φ_v = π/2 − ψ_1.
    pub entry: f64,
    /// Exit angle φ_r = π/2 + ψ_2.
    pub exit: f64,
}

impl MillingParams {
    /// The engagement angles (docs/domain.md §4, below W1).
    pub fn angles(&self) -> Angles {
        let psi1 = ((self.width_mm + 2.0 * self.offset_mm) / self.diameter_mm)
            .clamp(-1.0, 1.0)
            .asin();
        let psi2 = ((self.width_mm - 2.0 * self.offset_mm) / self.diameter_mm)
            .clamp(-1.0, 1.0)
            .asin();
        Angles {
            psi1,
            psi2,
            psi: psi1 + psi2,
            entry: PI / 2.0 - psi1,
            exit: PI / 2.0 + psi2,
        }
    }

    /// Mean chip thickness a = (s_z/ψ)(sin ψ_1 + sin ψ_2), mm.
    pub fn mean_chip_thickness(&self, c: &Conditions) -> f64 {
        let an = self.angles();
        c.feed_per_tooth_mm / an.psi * (an.psi1.sin() + an.psi2.sin())
    }

    /// Tangential force on one tooth at angle φ with flank wear VB (W4), N; 0 outside the
    /// engagement `φ_v ≤ φ ≤ φ_r`.
    pub fn tooth_force(&self, phi: f64, vb_mm: f64, c: &Conditions) -> f64 {
        let an = self.angles();
        let phi = phi.rem_euclid(2.0 * PI);
        if phi < an.entry || phi > an.exit {
            return 0.0;
        }
        let a = self.mean_chip_thickness(c);
        c.depth_mm
            * (self.c * a.powf(-self.x) * c.feed_per_tooth_mm * phi.sin()
                + self.mu * self.hardness * vb_mm)
    }

    /// Cutting power of the whole cutter at rotation angle θ (W5–W6): the sum over the Z
    /// teeth at θ + kΦ, Φ = 2π/Z (the m or m−1 engaged ones contribute), W.
    pub fn cutting_power(&self, theta: f64, vb_mm: f64, c: &Conditions) -> f64 {
        let pitch = 2.0 * PI / f64::from(self.teeth);
        let v = PI * self.diameter_mm / 1000.0 * c.rpm / 60.0;
        (0..self.teeth)
            .map(|k| v * self.tooth_force(theta + f64::from(k) * pitch, vb_mm, c))
            .sum()
    }

    /// Mean cutting power P̄ (W7), W.
    pub fn mean_power(&self, vb_mm: f64, c: &Conditions) -> f64 {
        let an = self.angles();
        let a = self.mean_chip_thickness(c);
        let n = c.rpm / 60.0;
        f64::from(self.teeth) * n * self.diameter_mm / 1000.0
            * c.depth_mm
            * (self.c * a.powf(-self.x) * c.feed_per_tooth_mm * (an.entry.cos() - an.exit.cos())
                + self.mu * self.hardness * vb_mm * an.psi)
            / 2.0
    }

    /// Spindle motor power for a cutting power: p_i + P/η, W.
    pub fn motor_power(&self, cutting: f64) -> f64 {
        self.idle_power + cutting / self.efficiency
    }

    /// The wear monitor's constants for `c` with wear limit `[VB]` (W8): `[P̄]` and p_i,
    /// converted to I32F32 once, here, outside the hot path.
    pub fn condition_set(&self, c: &Conditions, vb_limit_mm: f64) -> ConditionSet {
        ConditionSet {
            mean_power_limit: Fx::from_num(self.mean_power(vb_limit_mm, c)),
            idle_power: Fx::from_num(self.idle_power),
        }
    }
}

/// Which tool the scenario mills with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tool {
    /// Name for tables and files.
    pub name: &'static str,
    /// Flank wear at the start, mm.
    pub vb_start: f64,
    /// Flank wear growth, mm/s of cutting.
    pub vb_rate: f64,
}

/// A new tool: VB 0.05 mm growing 1 µm/s.
pub const NEW_TOOL: Tool = Tool {
    name: "new",
    vb_start: 0.05,
    vb_rate: 0.001,
};
/// A worn tool: VB 0.42 mm growing 1 µm/s (past the 0.3 mm limit).
pub const WORN_TOOL: Tool = Tool {
    name: "worn",
    vb_start: 0.42,
    vb_rate: 0.001,
};

/// One cut of the part program: its conditions for `seconds`, the spindle's idle power at its
/// speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    /// Depth b, feed per tooth s_z and speed.
    pub conditions: Conditions,
    /// Length of the cut, s.
    pub seconds: f64,
    /// Idle spindle power p_i at this cut's speed, W.
    pub idle_power: f64,
}

/// Tolerance of the settling hold: the monitored power is settled when it is within this
/// fraction of a step's size from its final value.
pub const SETTLE_TOLERANCE: f64 = 0.01;

/// The wear monitor's settling hold for `s` with a measured-power lag of `power_lag_s`
/// seconds (docs/wear.md, "Settling hold"): the unit step response of the chain the power
/// goes through — the first-order lag (exact per sample), the sampling low-pass `2^−k` per
/// sample, the period's average and the wear low-pass `2^−w` per period — is stepped from
/// a change at a period's start; the hold is one less than the first period whose monitored
/// power is within [`SETTLE_TOLERANCE`] of the step, so the first period compared with the
/// new threshold is settled. Err names the limit if that is more than 255 periods.
pub fn settle_periods(power_lag_s: f64, s: &ForceSettings) -> Result<u8, String> {
    if !(power_lag_s.is_finite() && power_lag_s >= 0.0) {
        return Err(format!("power lag {power_lag_s} s: must be 0 or more"));
    }
    let fs = f64::from(s.sample_hz.max(1));
    let decay = if power_lag_s > 0.0 {
        (-1.0 / (fs * power_lag_s)).exp()
    } else {
        0.0
    };
    let k_s = 0.5f64.powi(i32::from(s.lowpass_shift));
    let k_w = 0.5f64.powi(i32::from(s.wear.lowpass_shift));
    let spp = u32::from(s.samples_per_period.max(1));
    let (mut lag, mut sampled, mut monitored) = (0.0f64, 0.0f64, 0.0f64);
    for period in 1..=256u32 {
        let mut sum = 0.0;
        for _ in 0..spp {
            lag = 1.0 - (1.0 - lag) * decay;
            sampled += (lag - sampled) * k_s;
            sum += sampled;
        }
        monitored += (sum / f64::from(spp) - monitored) * k_w;
        if 1.0 - monitored <= SETTLE_TOLERANCE {
            return Ok(u8::try_from(period - 1).unwrap_or(u8::MAX));
        }
    }
    Err(format!(
        "the monitored power takes more than 255 control periods to settle within {} % (power lag {power_lag_s} s, wear low-pass 2^-{}): the hold is at most 255 periods",
        SETTLE_TOLERANCE * 100.0,
        s.wear.lowpass_shift
    ))
}

/// The scatter of measured power about the model, a fraction of the allowed motor power
/// `[P]`: the milling paper's Fig. 5 points lie within about 5 % of its model lines, and
/// what it measured is the spindle's motor-side power with its idle part (docs/wear.md,
/// "Fig. 6"). A threshold separates a new tool from a worn one only if the new tool's
/// motor power sits below `[P]` by more than this.
pub const MODEL_SCATTER: f64 = 0.05;

impl WearScenario {
    /// Refuses a new tool whose motor power `p_i + P̄/η` (W7, W9) comes within
    /// [`MODEL_SCATTER`] of `[P]` in some cut: the model's own scatter could lift it over the
    /// threshold. Err names the cut, both powers and the margin.
    pub fn check_new_tool_margin(&self, new_vb_mm: f64) -> Result<(), String> {
        let eta = self.milling.efficiency;
        for (i, c) in self.cuts.iter().enumerate() {
            let allowed =
                c.idle_power + self.milling.mean_power(self.vb_limit_mm, &c.conditions) / eta;
            let new = c.idle_power + self.milling.mean_power(new_vb_mm, &c.conditions) / eta;
            let margin = allowed - new;
            if margin <= MODEL_SCATTER * allowed {
                return Err(format!(
                    "cut {} (depth {} mm): the new tool (VB {new_vb_mm} mm) draws {new:.0} W of motor power against [P] = {allowed:.0} W at [VB] = {} mm, {margin:.0} W ({:.1} %) below it: within the model's {:.0} % scatter, so the threshold cannot tell it from a worn tool (raise vb_limit_mm or lower new_vb_mm)",
                    i + 1,
                    c.conditions.depth_mm,
                    self.vb_limit_mm,
                    100.0 * margin / allowed,
                    100.0 * MODEL_SCATTER
                ));
            }
        }
        Ok(())
    }
}

/// The tracking's per-sample gain for a measured-power lag of `power_lag_s` seconds sampled
/// at `sample_hz` (docs/wear.md, "Cuts shorter than the hold"): `1 − e^(−1/(f_s·τ))`, the
/// step of a first-order lag from one sample to the next; 1 for no lag. Err for a negative
/// or non-finite lag.
pub fn power_lag_gain(power_lag_s: f64, sample_hz: u16) -> Result<Fx, String> {
    if !(power_lag_s.is_finite() && power_lag_s >= 0.0) {
        return Err(format!("power lag {power_lag_s} s: must be 0 or more"));
    }
    let fs = f64::from(sample_hz.max(1));
    let gain = if power_lag_s > 0.0 {
        1.0 - (-1.0 / (fs * power_lag_s)).exp()
    } else {
        1.0
    };
    // At least one LSB: a lag so long that the gain rounds to 0 would never track.
    Ok(Fx::from_num(gain).max(Fx::DELTA))
}

/// The wear scenario: idle at the first cut's speed for `idle_s`, then the cuts in order;
/// the CNC selects each cut's condition set at its start.
#[derive(Clone, Debug, PartialEq)]
pub struct WearScenario {
    /// Cutter and machine.
    pub milling: MillingParams,
    /// The part program.
    pub cuts: Vec<Cut>,
    /// Wear limit [VB], mm.
    pub vb_limit_mm: f64,
    /// Idle time before the first cut, s.
    pub idle_s: f64,
    /// Lag of the measured power, s.
    pub power_lag: f64,
    /// ADC noise, LSB rms.
    pub adc_noise: f64,
    /// Noise seed.
    pub seed: u64,
    /// The CNC sends the tool-changed command at every cut's start (clears a latched alarm,
    /// so each cut's detection time is seen; tests).
    pub clear_alarm_each_cut: bool,
    /// The wear monitor's low-pass `2^−shift` per period, `0..=8`.
    pub monitor_lowpass_shift: u8,
    /// The wear monitor's debounce, periods, `1..=255`.
    pub debounce_periods: u8,
    /// The per-tooth transient plant ([`crate::milling_transients`]) before the power lag;
    /// `None`: W6 as it is.
    pub transients: Option<ToothTransients>,
}

impl Default for WearScenario {
    /// Depth 2 mm then 3 mm, s_z = 0.2 mm, 300 rpm, [VB] = 0.3 mm, 20 s per cut.
    fn default() -> Self {
        let m = MillingParams::default();
        let cut = |depth_mm| Cut {
            conditions: Conditions {
                depth_mm,
                feed_per_tooth_mm: 0.2,
                rpm: 300.0,
            },
            seconds: 20.0,
            idle_power: m.idle_power,
        };
        WearScenario {
            milling: m,
            cuts: vec![cut(2.0), cut(3.0)],
            vb_limit_mm: 0.3,
            idle_s: 1.0,
            power_lag: 0.3,
            adc_noise: 1.5,
            seed: 7,
            clear_alarm_each_cut: false,
            monitor_lowpass_shift: WearSettings::default().lowpass_shift,
            debounce_periods: WearSettings::default().debounce_periods,
            transients: None,
        }
    }
}

/// Per-period wear traces.
#[derive(Clone, Debug, Default)]
pub struct WearRun {
    /// Time, s.
    pub t: Vec<f64>,
    /// True motor power (period mean), W.
    pub power_true: Vec<f64>,
    /// Monitor's low-passed power p̄, W.
    pub power: Vec<f64>,
    /// Allowed power [P], W.
    pub allowed: Vec<f64>,
    /// Alarm latched.
    pub alarm: Vec<bool>,
    /// The monitor could not judge (`wear_blind`).
    pub blind: Vec<bool>,
    /// Flank wear, mm.
    pub vb: Vec<f64>,
    /// First alarm time, s.
    pub alarm_at: Option<f64>,
    /// Per cut, the first period end in it with the alarm raised, s.
    pub cut_alarms: Vec<Option<f64>>,
    /// Input events (time in samples).
    pub events: Vec<(u64, ForceEvent)>,
}

impl WearScenario {
    /// Start time of cut `i`, s.
    pub fn cut_start(&self, i: usize) -> f64 {
        self.idle_s + self.cuts.iter().take(i).map(|c| c.seconds).sum::<f64>()
    }

    /// The cut running at time `t` (s), `None` before the first.
    pub fn cut_at(&self, t: f64) -> Option<usize> {
        (0..self.cuts.len()).rev().find(|&i| t >= self.cut_start(i))
    }

    /// The distinct condition sets of the cuts, in order of first use (conditions and
    /// idle power), and each cut's set index.
    pub fn condition_sets(&self) -> (Vec<(Conditions, f64)>, Vec<u8>) {
        let mut sets: Vec<(Conditions, f64)> = Vec::new();
        let mut index = Vec::with_capacity(self.cuts.len());
        for c in &self.cuts {
            let key = (c.conditions, c.idle_power);
            let i = sets.iter().position(|s| *s == key).unwrap_or_else(|| {
                sets.push(key);
                sets.len() - 1
            });
            index.push(u8::try_from(i).unwrap_or(u8::MAX));
        }
        (sets, index)
    }

    /// The monitor's constants of one condition set: `[P̄]` at `[VB]` and p_i.
    pub fn condition_set(&self, c: &Conditions, idle_power: f64) -> ConditionSet {
        ConditionSet {
            mean_power_limit: Fx::from_num(self.milling.mean_power(self.vb_limit_mm, c)),
            idle_power: Fx::from_num(idle_power),
        }
    }

    /// The force-path configuration with the cuts' condition sets precomputed (updating
    /// threshold) or the constant threshold of the first cut's conditions, and the settling
    /// hold derived from the power lag ([`settle_periods`]). Err names the culprit: more
    /// condition sets than [`MAX_CONDITION_SETS`] (the firmware's capacity), no cut, a hold
    /// that does not fit, or a value the model refuses.
    pub fn config(&self, constant: bool) -> Result<ForceConfig, String> {
        let mut s = ForceSettings::default();
        s.wear = self.wear_settings(&s, constant)?;
        s.validate().map_err(|e| e.to_string())
    }

    /// The wear monitor's settings for the force path `base` (its sampling and wear
    /// filters set the hold): as [`Self::config`], the rest of `base.wear` kept.
    pub fn wear_settings(
        &self,
        base: &ForceSettings,
        constant: bool,
    ) -> Result<WearSettings, String> {
        let mut s = *base;
        let (distinct, _) = self.condition_sets();
        if distinct.is_empty() {
            return Err("no cut: at least one is needed".into());
        }
        if distinct.len() > MAX_CONDITION_SETS {
            return Err(format!(
                "{} condition sets: the firmware holds at most {MAX_CONDITION_SETS} (MAX_CONDITION_SETS)",
                distinct.len()
            ));
        }
        let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
        for (slot, (c, idle)) in sets.iter_mut().zip(&distinct) {
            *slot = self.condition_set(c, *idle);
        }
        s.wear.sets = sets;
        s.wear.set_count = distinct.len() as u8;
        s.wear.lowpass_shift = self.monitor_lowpass_shift;
        s.wear.debounce_periods = self.debounce_periods;
        s.wear.efficiency = Fx::from_num(self.milling.efficiency);
        s.wear.threshold = if constant {
            let p = tooltouch_model::force::wear::allowed_power(&sets[0], s.wear.efficiency);
            Threshold::Constant(p)
        } else {
            Threshold::Updating
        };
        // The ringing's envelope adds to the lag it comes before (conservative).
        let lag = self.power_lag + self.transients.map_or(0.0, |t| t.envelope_s());
        s.wear.settle_periods = settle_periods(lag, &s)?;
        // Tracking replicates the lag alone: the ringing has a mean delay of 2ζ/ω_n (a few
        // ms), which the guard covers.
        s.wear.power_lag_gain = Some(power_lag_gain(self.power_lag, s.sample_hz)?);
        s.wear.validate().map_err(|e| e.to_string())?;
        Ok(s.wear)
    }

    /// Runs the scenario through the model kernel.
    pub fn run(&self, tool: &Tool, config: &ForceConfig) -> WearRun {
        let s = config.settings();
        let fs = f64::from(s.sample_hz);
        let spp = u64::from(s.samples_per_period);
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let noise = Normal::new(0.0, self.adc_noise.max(1e-12)).expect("positive sigma");
        let mut kernel = ForceKernel::new(config);
        let mut out = WearRun {
            cut_alarms: vec![None; self.cuts.len()],
            ..WearRun::default()
        };
        let (_, set_of_cut) = self.condition_sets();
        let starts: Vec<u64> = (0..self.cuts.len())
            .map(|i| (self.cut_start(i) * fs).round() as u64)
            .collect();
        let total = self.cut_start(self.cuts.len());
        let n = (total * fs).round() as u64;
        let idle_at_start = self
            .cuts
            .first()
            .map_or(self.milling.idle_power, |c| c.idle_power);
        let mut p_meas = idle_at_start;
        let mut meter = self
            .transients
            .map(|t| TransientMeter::new(&t, idle_at_start, self.seed ^ 0x7472_616e_7369_656e));
        let mut theta = 0.0;
        let mut sum = 0.0;
        let dt = 1.0 / fs;
        let power_lsb = f(s.scales.power_per_lsb);
        let apply = |k: &mut ForceKernel, out: &mut WearRun, t: u64, ev: ForceEvent| {
            k.apply(ev);
            out.events.push((t, ev));
        };
        apply(&mut kernel, &mut out, 0, ForceEvent::Conditions(0));
        let mut vb = tool.vb_start;
        let mut cut = 0usize;
        for k in 0..n {
            // The cut whose start this sample has reached; its set is selected at the
            // sample where it begins (the first cut's set is selected at power-up).
            while cut + 1 < self.cuts.len() && k >= starts[cut + 1] {
                cut += 1;
                apply(
                    &mut kernel,
                    &mut out,
                    k,
                    ForceEvent::Conditions(set_of_cut[cut]),
                );
                if self.clear_alarm_each_cut {
                    apply(&mut kernel, &mut out, k, ForceEvent::ToolChanged);
                }
            }
            if self.clear_alarm_each_cut && cut == 0 && k == starts[0] {
                apply(&mut kernel, &mut out, k, ForceEvent::ToolChanged);
            }
            let cutting_now = k >= starts[0];
            let this = &self.cuts[cut];
            if cutting_now {
                vb += tool.vb_rate * dt;
            }
            let theta_before = theta;
            let omega = 2.0 * PI * this.conditions.rpm / 60.0;
            theta += omega * dt;
            let p_cut = if cutting_now {
                self.milling.cutting_power(theta, vb, &this.conditions)
            } else {
                0.0
            };
            let p_motor = this.idle_power + p_cut / self.milling.efficiency;
            sum += p_motor;
            let p_seen = match meter.as_mut() {
                Some(meter) => {
                    let (m, c, eff) = (&self.milling, &this.conditions, self.milling.efficiency);
                    meter.sample(dt, |frac| {
                        let load = if cutting_now {
                            m.cutting_power(theta_before + omega * dt * frac, vb, c)
                        } else {
                            0.0
                        };
                        this.idle_power + load / eff
                    })
                }
                None => p_motor,
            };
            p_meas += (p_seen - p_meas) * dt / self.power_lag;
            let code = (p_meas / power_lsb + noise.sample(&mut rng))
                .round()
                .clamp(0.0, f64::from(ADC_MAX)) as u16;
            let mid = ADC_MID as u16;
            let codes = AdcCodes {
                speed: 0,
                power: code,
                force: mid,
                volts: [mid; 3],
                amps: [mid; 2],
            };
            apply(&mut kernel, &mut out, k, ForceEvent::Sample(codes));
            if (k + 1) % spp == 0 {
                apply(&mut kernel, &mut out, k, ForceEvent::Tick);
                let o = kernel.outputs();
                let tt = (k + 1) as f64 / fs;
                out.t.push(tt);
                out.power_true.push(sum / spp as f64);
                out.power.push(o.wear_power.to_num());
                out.allowed.push(o.wear_allowed.to_num());
                out.alarm.push(o.wear_alarm);
                out.blind.push(o.wear_blind);
                out.vb.push(vb);
                if o.wear_alarm && out.alarm_at.is_none() {
                    out.alarm_at = Some(tt);
                }
                if o.wear_alarm && cutting_now {
                    if let Some(slot) = out.cut_alarms.get_mut(cut) {
                        slot.get_or_insert(tt);
                    }
                }
                sum = 0.0;
            }
        }
        out
    }
}

/// One cut at constant conditions and wear, sampled at `fs` Hz for `seconds`: the W6 power
/// at each sample (the model's instantaneous prediction) and what the transient meter
/// reports (cutting power only, no idle power or efficiency).
pub fn cutting_trace(
    m: &MillingParams,
    c: &Conditions,
    vb_mm: f64,
    t: &ToothTransients,
    fs: f64,
    seconds: f64,
    seed: u64,
) -> (Vec<f64>, Vec<f64>) {
    let n = (seconds * fs).round().max(0.0) as usize;
    let dt = 1.0 / fs;
    let omega = 2.0 * PI * c.rpm / 60.0;
    let mut meter = TransientMeter::new(t, m.cutting_power(0.0, vb_mm, c), seed);
    let mut model = Vec::with_capacity(n);
    let mut measured = Vec::with_capacity(n);
    for k in 0..n {
        let theta0 = omega * k as f64 * dt;
        measured.push(meter.sample(dt, |frac| {
            m.cutting_power(theta0 + omega * dt * frac, vb_mm, c)
        }));
        model.push(m.cutting_power(theta0 + omega * dt, vb_mm, c));
    }
    (model, measured)
}
