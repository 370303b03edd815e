//! The measure-then-correct size loop of an in-process measuring lathe, with every
//! measurement made by the HAL component's period semantics ([`PeriodKernel`], the
//! component under `halrun` bit for bit).
//!
//! N parts are turned to a nominal diameter. Between parts the tool wears (its edge
//! recedes, the diameter grows by twice the radial wear) and the machine warms up (a
//! radial thermal drift approaching its end value exponentially). After each part the
//! cutting tool measures it in process, comparatively: it touches a master of known
//! diameter, then the part, with the same feed and spindle speed, and the diameter is the
//! master's plus twice the difference of the two latched scale positions — wear and drift
//! shift both touches alike and cancel, the touches' decision depths leave the
//! measurement's own scatter. The tool offset is then corrected by a feedback percentage of
//! the measured error, unless the error is inside a dead zone (as industrial probing
//! macros do); the same parts without correction are the reference.
//!
//! The rule of the correction: a touch is a reading only when the component decided,
//! `confirmed` is high and `faults` is zero at the read ([`reading`]). Anything else is an
//! alarm ([`Alarm`]: the faults named, a decision not confirmed, no decision): the part is
//! reported with it and the tool offset is left unchanged — never corrected from a reading
//! the measurement itself does not trust.
//!
//! The safety rules ([`LoopRules`], [`LoopRules::SAFE`]): a flagged touch is made once more
//! and a second flagged touch alarms and stops the machine; a measured error beyond the
//! upper tolerance limit updates nothing, alarms and stops; a correction is clipped to the
//! maximum per part. [`LoopRules::TODAY`], the default, is the loop without them. Faulted
//! touches ([`TouchFault`]: a coolant bridge, a chip burst, a chip trapped on the surface —
//! the last a silent wrong reading) are drawn per touch ([`TouchFaultRates`]) or forced
//! ([`ForcedFault`]); every touch's chatter and every part's turning scatter have their own
//! random stream of the seed, so faults and re-measures change no other draw.
//!
//! Every touch is a servo-rate stream of the component's pins (arm, contact chattering
//! over the surface's roughness, FES and index counts, the scale): the stream of all
//! touches is what the HAL test feeds `halrun`, and the loop's table is recomputed from
//! the positions the component latched there.

use super::period::{PeriodInputs, PeriodKernel};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::measure::checks::Faults;
use tooltouch_model::{MeasureConfig, MeasureOutputs};

/// The loop's set-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeLoopSettings {
    /// Parts machined.
    pub parts: usize,
    /// Nominal diameter, mm.
    pub nominal_mm: f64,
    /// Tolerance, ± mm around the nominal.
    pub tolerance_mm: f64,
    /// Offset correction: this percentage of the measured error.
    pub feedback_pct: f64,
    /// No correction while |measured error| ≤ this, mm (diameter).
    pub dead_zone_mm: f64,
    /// Radial tool wear per part, µm.
    pub wear_um_per_part: f64,
    /// Radial thermal drift at the end of the warm-up, µm.
    pub thermal_um: f64,
    /// Warm-up time constant, parts.
    pub thermal_parts: f64,
    /// Scatter of the turned diameter (1σ), µm.
    pub cut_sigma_um: f64,
    /// The master's diameter, mm.
    pub master_mm: f64,
    /// Scale resolution, µm per count.
    pub scale_um: f64,
    /// Spindle speed while measuring, rpm.
    pub rpm: f64,
    /// Measuring feed, µm per revolution.
    pub feed_um_per_rev: f64,
    /// Surface roughness the contact chatters over (Rz), µm.
    pub roughness_um: f64,
    /// Seed of every random draw.
    pub seed: u64,
    /// A touch (0-based, in stream order: master and part of each part in turn) made with
    /// the contact already closed when the arm rises (a coolant bridge): its reading alarms
    /// `contact_at_arm`. `None` for a clean machine.
    pub bridged_touch: Option<usize>,
    /// Faulted touches drawn at random ([`TouchFaultRates`]); all rates 0 for a clean machine.
    pub faults: TouchFaultRates,
    /// One fault made on purpose, besides the drawn ones: `fault` in the first `attempts`
    /// touches (1: the first, 2: the re-measure too) of `role` of `part` (from 1).
    pub forced: Option<ForcedFault>,
    /// What the loop does with a reading ([`LoopRules`]); [`LoopRules::TODAY`] by default.
    pub rules: LoopRules,
}

/// A fault made on purpose ([`SizeLoopSettings::forced`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForcedFault {
    /// The part, from 1.
    pub part: usize,
    /// Its master or part touch.
    pub role: Role,
    /// Touches faulted: 1 the first, 2 the re-measure too.
    pub attempts: usize,
    /// The fault.
    pub fault: TouchFault,
}

/// How often a touch is faulted, each a probability per touch (0–1), drawn from the seed,
/// the part, the touch (master or part) and the attempt alone — so two loops over the same
/// parts meet the same faults on their first touches, whatever each did before.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TouchFaultRates {
    /// A coolant bridge ([`TouchFault::CoolantBridge`]): flagged `contact_at_arm`.
    pub coolant_bridge: f64,
    /// A chip flying through the gap during the approach ([`TouchFault::ChipBurst`]): an
    /// early contact, flagged `unconfirmed` when the contact falls back.
    pub chip_burst: f64,
    /// A chip lying on the surface ([`TouchFault::TrappedChip`]): a real, steady contact
    /// early by the chip's thickness, unflagged — a silent wrong reading.
    pub trapped_chip: f64,
    /// The thickest trapped chip, µm (each drawn uniformly from half this to this). A chip
    /// thicker than the approach gap (6 µm) less the roughness (Rz) closes the contact at
    /// the arm and is flagged; a thinner one reads the surface early by its thickness.
    pub trapped_chip_um: f64,
}

/// The rules that turn a part's measurement into a tool-offset update (beside the feedback
/// percentage and the dead zone of [`SizeLoopSettings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopRules {
    /// A flagged touch (faults, not confirmed, no decision) is made once more; a second
    /// flagged touch alarms and stops the machine. `false`: the first one alarms.
    pub remeasure: bool,
    /// The upper tolerance limit, mm (diameter): a measured error |d − nominal| beyond it
    /// updates nothing, alarms and stops the machine (a reading that far off is taken for a
    /// measuring or machining failure, not for drift). `None`: no limit.
    pub upper_tolerance_mm: Option<f64>,
    /// The largest offset change after one part, mm (diameter): a larger correction is
    /// clipped to it. `None`: no limit.
    pub max_correction_mm: Option<f64>,
}

impl LoopRules {
    /// The loop as it was before the safety rules: no re-measure, no upper tolerance
    /// limit, no maximum correction.
    pub const TODAY: LoopRules = LoopRules {
        remeasure: false,
        upper_tolerance_mm: None,
        max_correction_mm: None,
    };
    /// The safe loop for the default Ø40 ± 0.010 mm parts: re-measure once, an upper
    /// tolerance limit of 0.020 mm (twice the tolerance), at most 0.004 mm of correction
    /// per part (above the 3.8 µm a part grows at the start of the warm-up, a silent
    /// wrong reading of up to 11 µm moves the size by at most that).
    pub const SAFE: LoopRules = LoopRules {
        remeasure: true,
        upper_tolerance_mm: Some(0.020),
        max_correction_mm: Some(0.004),
    };
}

impl Default for LoopRules {
    /// [`LoopRules::TODAY`].
    fn default() -> Self {
        LoopRules::TODAY
    }
}

/// A fault made in one touch's stream: what the machine did, and so what the component saw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TouchFault {
    /// Coolant bridges edge and surface: the contact is closed from before the arm rises
    /// until it has risen.
    CoolantBridge,
    /// A chip swept through the gap during the approach closes the contact for `periods`
    /// servo periods from `after_arm` periods after the arm rises, in the air.
    ChipBurst {
        /// Periods after the arm's rise, while the edge is still in the air.
        after_arm: u32,
        /// Length of the burst, periods.
        periods: u32,
    },
    /// A chip `thickness_um` thick lying on the surface: the edge meets it that much early,
    /// with a real contact the checks cannot tell from the surface's.
    TrappedChip {
        /// µm.
        thickness_um: f64,
    },
}

impl std::fmt::Display for TouchFault {
    /// `coolant bridge`, `chip burst 12 ms at 40 ms`, `trapped chip 3.2 µm`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TouchFault::CoolantBridge => f.write_str("coolant bridge"),
            TouchFault::ChipBurst { after_arm, periods } => {
                write!(f, "chip burst {periods} periods at {after_arm}")
            }
            TouchFault::TrappedChip { thickness_um } => {
                write!(f, "trapped chip {thickness_um:.1} µm")
            }
        }
    }
}

/// The random stream of one draw of the loop: a touch's (`Some((role, attempt))`) or the
/// turning scatter of a part (`None`), from the seed and the part (from 1) alone.
fn keyed_rng(seed: u64, part: usize, touch: Option<(Role, usize)>) -> ChaCha8Rng {
    let which = match touch {
        None => 0,
        Some((role, attempt)) => 1 + (role as u64) * 2 + attempt as u64,
    };
    let key = (part as u64) << 3 | which;
    ChaCha8Rng::seed_from_u64(seed ^ key.wrapping_mul(0x9e37_79b9_7f4a_7c15))
}

/// The touch in a part's measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// The master ring.
    Master,
    /// The part.
    Part,
}

impl std::fmt::Display for Role {
    /// `master`, `part`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Role::Master => "master",
            Role::Part => "part",
        })
    }
}

impl TouchFaultRates {
    /// The campaign's faults: per touch, 2 % coolant bridges, 2 % chip bursts, 1 % chips
    /// trapped on the surface up to 5.5 µm thick.
    pub const CAMPAIGN: TouchFaultRates = TouchFaultRates {
        coolant_bridge: 0.02,
        chip_burst: 0.02,
        trapped_chip: 0.01,
        trapped_chip_um: 5.5,
    };

    /// The fault of touch `attempt` (0: the first, 1: the re-measure) of `role` of `part`
    /// (from 1), drawn from `seed`.
    pub fn draw(&self, seed: u64, part: usize, role: Role, attempt: usize) -> Option<TouchFault> {
        let mut rng = keyed_rng(seed ^ 0x5a5a_0000_0000_0000, part, Some((role, attempt)));
        let u: f64 = rng.random();
        let (bridge, burst) = (self.coolant_bridge, self.coolant_bridge + self.chip_burst);
        if u < bridge {
            Some(TouchFault::CoolantBridge)
        } else if u < burst {
            Some(TouchFault::ChipBurst {
                after_arm: rng.random_range(10..80),
                periods: rng.random_range(2..=20),
            })
        } else if u < burst + self.trapped_chip {
            Some(TouchFault::TrappedChip {
                thickness_um: self.trapped_chip_um * rng.random_range(0.5..=1.0),
            })
        } else {
            None
        }
    }
}

impl Default for SizeLoopSettings {
    /// 20 parts of Ø40 ± 0.010 mm; 70 % feedback, 2 µm dead zone; 0.8 µm wear per part,
    /// 6 µm warm-up over 5 parts, 1.5 µm turning scatter; 0.5 µm scale, 3000 rpm, 1 µm/rev
    /// measuring feed, Rz 1.5 µm.
    fn default() -> Self {
        SizeLoopSettings {
            parts: 20,
            nominal_mm: 40.0,
            tolerance_mm: 0.010,
            feedback_pct: 70.0,
            dead_zone_mm: 0.002,
            wear_um_per_part: 0.8,
            thermal_um: 6.0,
            thermal_parts: 5.0,
            cut_sigma_um: 1.5,
            master_mm: 40.0,
            scale_um: 0.5,
            rpm: 3000.0,
            feed_um_per_rev: 1.0,
            roughness_um: 1.5,
            seed: 31,
            bridged_touch: None,
            faults: TouchFaultRates::default(),
            forced: None,
            rules: LoopRules::TODAY,
        }
    }
}

/// Periods of one touch: arm from period 5 to 220, retract after.
pub const TOUCH_PERIODS: u32 = 260;
/// The arm rises at this period of a touch.
const ARM_START: u32 = 5;
/// The arm falls at this period of a touch.
const ARM_END: u32 = 220;
/// Approach gap before the surface, µm.
const GAP_UM: f64 = 6.0;

/// One part of the loop.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PartRow {
    /// Part number, from 1.
    pub part: usize,
    /// Diameter turned without correction, mm.
    pub uncorrected_mm: f64,
    /// Diameter turned with the loop's correction, mm.
    pub corrected_mm: f64,
    /// The in-process measurement of the corrected part, mm (NaN: an alarm, no reading).
    pub measured_mm: f64,
    /// Why the part has no reading (`master: contact_at_arm`, `part: not confirmed`, …);
    /// empty when it has one. The offset is not corrected after an alarm.
    pub alarm: String,
    /// Tool offset the part was turned with, µm (radial).
    pub offset_um: f64,
    /// Touches made again after a flagged one ([`LoopRules::remeasure`]).
    pub remeasures: usize,
    /// The alarm stopped the machine (a second flagged touch, the upper tolerance limit):
    /// the operator clears it and the loop goes on with the offset unchanged.
    pub stopped: bool,
    /// The faults the stream made in this part's touches (`part: trapped chip 3.2 µm`, …);
    /// empty for clean touches.
    pub injected: String,
    /// Verdict of the uncorrected part.
    pub uncorrected_ok: bool,
    /// Verdict of the corrected part.
    pub corrected_ok: bool,
}

/// A capability summary over the parts.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Capability {
    /// Mean, mm.
    pub mean_mm: f64,
    /// Repeatability: twice the sample standard deviation, µm.
    pub two_sigma_um: f64,
    /// Range, max − min, µm.
    pub range_um: f64,
    /// Cp = tolerance width / 6σ.
    pub cp: f64,
    /// Cpk = distance of the mean to the nearer limit / 3σ.
    pub cpk: f64,
    /// Parts inside the tolerance.
    pub in_tolerance: usize,
}

/// Mean, 2σ, range, Cp and Cpk of `values` (mm) against `nominal ± tol`.
pub fn capability(values: &[f64], nominal: f64, tol: f64) -> Capability {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    let sigma = var.sqrt();
    let max = values.iter().copied().fold(f64::MIN, f64::max);
    let min = values.iter().copied().fold(f64::MAX, f64::min);
    let (usl, lsl) = (nominal + tol, nominal - tol);
    Capability {
        mean_mm: mean,
        two_sigma_um: 2.0 * sigma * 1e3,
        range_um: (max - min) * 1e3,
        cp: (usl - lsl) / (6.0 * sigma),
        cpk: (usl - mean).min(mean - lsl) / (3.0 * sigma),
        in_tolerance: values
            .iter()
            .filter(|v| (**v - nominal).abs() <= tol)
            .count(),
    }
}

/// Where one touch's decision is in the stream, and what the touch was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// The stream's period at which the arm falls (the latched position is read there).
    pub read_at: usize,
    /// The part measured, from 1.
    pub part: usize,
    /// Master or part.
    pub role: Role,
    /// 0: the first touch, 1: the re-measure.
    pub attempt: usize,
    /// The fault the stream made in it.
    pub fault: Option<TouchFault>,
}

/// The loop's result.
#[derive(Clone, Debug, PartialEq)]
pub struct SizeLoopReport {
    /// One row per part.
    pub rows: Vec<PartRow>,
    /// Without correction.
    pub uncorrected: Capability,
    /// With correction.
    pub corrected: Capability,
    /// The measurement's own error (measured − turned diameter), 2σ and range, µm.
    pub measurement_two_sigma_um: f64,
    /// Its range, µm.
    pub measurement_range_um: f64,
    /// The component's input pins, every touch in order (master, part, master, part, …).
    pub stream: Vec<PeriodInputs>,
    /// The touches in `stream`.
    pub touches: Vec<Touch>,
}

/// The streams' spindle and slide state, continuous over the touches.
struct Machine {
    rng: ChaCha8Rng,
    row: PeriodInputs,
    spindle: f64,
    ppr: f64,
    settings: SizeLoopSettings,
}

impl Machine {
    /// Appends one touch of a surface at slide reading `surface_um` (µm, the scale's
    /// reading when the edge meets the surface's top), made with `fault`, returning where
    /// its decision is read.
    fn touch(
        &mut self,
        stream: &mut Vec<PeriodInputs>,
        surface_um: f64,
        sample_hz: f64,
        fault: Option<TouchFault>,
    ) -> usize {
        let s = self.settings;
        let feed = s.feed_um_per_rev * s.rpm / 60.0 / sample_hz; // µm per period
        let mut q = surface_um - GAP_UM;
        // A trapped chip is met that much before the surface (the scale reads smaller).
        let met_um = match fault {
            Some(TouchFault::TrappedChip { thickness_um }) => surface_um - thickness_um,
            _ => surface_um,
        };
        let start = stream.len();
        for k in 0..TOUCH_PERIODS {
            self.spindle += self.ppr * s.rpm / 60.0 / sample_hz;
            let pulses = self.spindle.floor() as i64;
            self.row.fes_counts = pulses as i32;
            self.row.index_counts = (pulses / self.ppr as i64) as i32;
            if k < ARM_END {
                q += feed;
            } else {
                q -= GAP_UM / f64::from(TOUCH_PERIODS - ARM_END);
            }
            self.row.scale_counts = (q / s.scale_um).floor() as i32;
            self.row.arm = (ARM_START..ARM_END).contains(&k);
            // The edge touches the roughness peaks first: P(contact) rises over Rz.
            let p = ((q - met_um) / s.roughness_um + 1.0).clamp(0.0, 1.0);
            self.row.contact = k < ARM_END && self.rng.random_bool(p);
            match fault {
                Some(TouchFault::CoolantBridge) if k <= ARM_START => self.row.contact = true,
                Some(TouchFault::ChipBurst { after_arm, periods })
                    if (ARM_START + after_arm..ARM_START + after_arm + periods).contains(&k) =>
                {
                    self.row.contact = true
                }
                _ => {}
            }
            stream.push(self.row);
        }
        start + ARM_END as usize - 1
    }
}

/// The smallest `[measure.checks] pulse_tolerance` that never raises `pulses_lost` or
/// `index_missing` on a clean spindle at `rpm` in the component: its index events of a
/// period are applied before the period's FES pulses, so a revolution counts up to one
/// period's pulses (`ppr · rpm / 60 / sample_hz`, rounded up) more or fewer than `ppr`;
/// the model's default margin of 2 on top.
pub fn servo_pulse_tolerance(ppr: u16, rpm: f64, sample_hz: f64) -> u16 {
    let per_period = (f64::from(ppr) * rpm / 60.0 / sample_hz).ceil();
    (per_period as u16).saturating_add(2)
}

/// Why a touch gave no reading: the CNC alarms (retract, re-measure) and the loop does not
/// correct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Alarm {
    /// Fault conditions latched (the component's `fault` pin high).
    Faults(Faults),
    /// A decision, no fault, but not (yet) confirmed by the contact pattern.
    NotConfirmed,
    /// No decision and no fault: the touch ended without one.
    NoDecision,
}

impl std::fmt::Display for Alarm {
    /// The faults' names (`contact_at_arm+unconfirmed`), `not confirmed` or `no decision`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Alarm::Faults(faults) => write!(f, "{faults}"),
            Alarm::NotConfirmed => f.write_str("not confirmed"),
            Alarm::NoDecision => f.write_str("no decision"),
        }
    }
}

/// What a touch left in the component's outputs at its read period: the latched position
/// (µm) when it decided, is confirmed and has no fault; the alarm otherwise.
pub fn reading(o: &MeasureOutputs, scale_um: f64) -> Result<f64, Alarm> {
    if o.faults != 0 {
        Err(Alarm::Faults(Faults(o.faults)))
    } else if !o.register_now {
        Err(Alarm::NoDecision)
    } else if !o.confirmed {
        Err(Alarm::NotConfirmed)
    } else {
        Ok(f64::from(o.decision_position) * scale_um)
    }
}

/// The part's diameter from its two readings (master, part), mm, or the alarm that stops
/// the correction (`master: …`, `part: …`).
fn measured(
    s: &SizeLoopSettings,
    master: Result<f64, String>,
    part: Result<f64, String>,
) -> Result<f64, String> {
    match (master, part) {
        // Readings grow inward: a larger part is touched at a smaller reading.
        (Ok(m), Ok(p)) => Ok(s.master_mm + 2.0 * (m - p) / 1e3),
        (Err(a), _) | (_, Err(a)) => Err(a),
    }
}

/// One part's measurement under the rules.
struct Measurement {
    /// The diameter, mm, or why there is none.
    diameter: Result<f64, String>,
    /// Touches made again.
    remeasures: usize,
    /// A touch was flagged twice: the machine stops.
    stopped: bool,
}

/// Measures one part: the master, then the part, each made by `touch(role, attempt)` and
/// made once more after a flagged reading when the rules re-measure.
fn measure_part(
    s: &SizeLoopSettings,
    mut touch: impl FnMut(Role, usize) -> Result<f64, Alarm>,
) -> Measurement {
    let mut remeasures = 0;
    let mut stopped = false;
    let mut take = |role: Role| match touch(role, 0) {
        Ok(v) => Ok(v),
        Err(first) if s.rules.remeasure => {
            remeasures += 1;
            touch(role, 1).map_err(|again| {
                stopped = true;
                format!("{role}: {first}, re-measured: {again}")
            })
        }
        Err(first) => Err(format!("{role}: {first}")),
    };
    let master = take(Role::Master);
    let part = take(Role::Part);
    Measurement {
        diameter: measured(s, master, part),
        remeasures,
        stopped,
    }
}

/// The offset after a part's measurement, µm, and the alarm that stopped the machine:
/// corrected by the feedback share of an error outside the dead zone, clipped to the
/// maximum correction; unchanged after an alarm and beyond the upper tolerance limit.
fn corrected_offset(
    s: &SizeLoopSettings,
    offset_um: f64,
    measured: &Result<f64, String>,
) -> (f64, Option<String>) {
    match measured {
        Ok(mm) => {
            let error_mm = mm - s.nominal_mm;
            if let Some(limit) = s.rules.upper_tolerance_mm {
                if error_mm.abs() > limit {
                    return (
                        offset_um,
                        Some(format!("upper tolerance limit: error {error_mm:+.4} mm")),
                    );
                }
            }
            if error_mm.abs() <= s.dead_zone_mm {
                return (offset_um, None);
            }
            let mut correction_mm = s.feedback_pct / 100.0 * error_mm;
            if let Some(max) = s.rules.max_correction_mm {
                correction_mm = correction_mm.clamp(-max, max);
            }
            (offset_um - correction_mm * 1e3 / 2.0, None)
        }
        Err(_) => (offset_um, None),
    }
}

/// A part's row from its turned diameters, the offset it was turned with and its
/// measurement; and the offset for the next part.
fn part_row(
    s: &SizeLoopSettings,
    (part, uncorrected, corrected, offset_um): (usize, f64, f64, f64),
    m: Measurement,
    injected: String,
) -> (PartRow, f64) {
    let (next, limit_alarm) = corrected_offset(s, offset_um, &m.diameter);
    let alarm = match (&m.diameter, limit_alarm.as_ref()) {
        (Err(a), _) => a.clone(),
        (Ok(_), Some(a)) => a.clone(),
        (Ok(_), None) => String::new(),
    };
    let row = PartRow {
        part,
        uncorrected_mm: uncorrected,
        corrected_mm: corrected,
        measured_mm: *m.diameter.as_ref().unwrap_or(&f64::NAN),
        alarm,
        offset_um,
        remeasures: m.remeasures,
        stopped: m.stopped || limit_alarm.is_some(),
        injected,
        uncorrected_ok: (uncorrected - s.nominal_mm).abs() <= s.tolerance_mm,
        corrected_ok: (corrected - s.nominal_mm).abs() <= s.tolerance_mm,
    };
    (row, next)
}

/// The faults of `touches` that belong to `part`, as text (`part: trapped chip 3.2 µm`).
fn injected(touches: &[Touch], part: usize) -> String {
    touches
        .iter()
        .filter(|t| t.part == part)
        .filter_map(|t| t.fault.map(|f| format!("{}: {f}", t.role)))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Runs the loop: every touch through [`PeriodKernel`] as it is made (closed loop: part
/// i's correction comes from its measurement), the stream of all touches kept.
pub fn run(s: &SizeLoopSettings, measure: &MeasureConfig, force: &ForceConfig) -> SizeLoopReport {
    let sample_hz = f64::from(force.settings().sample_hz.max(1));
    let mut machine = Machine {
        rng: ChaCha8Rng::seed_from_u64(s.seed),
        row: PeriodInputs::default(),
        spindle: 0.0,
        ppr: f64::from(measure.settings().pulses_per_rev),
        settings: *s,
    };
    let cut = Normal::new(0.0, s.cut_sigma_um).unwrap_or_else(|_| Normal::new(0.0, 0.0).unwrap());
    let mut kernel = PeriodKernel::new(measure, force);
    let mut stream = Vec::new();
    let mut touches: Vec<Touch> = Vec::new();
    let mut rows = Vec::with_capacity(s.parts);
    let mut offset_um = 0.0;
    // Slide readings: the scale reads `FAR − edge radius`, FAR a reference radius.
    const FAR_UM: f64 = 100_000.0;
    for part in 1..=s.parts {
        let i = (part - 1) as f64;
        let wear = s.wear_um_per_part * i;
        let thermal = s.thermal_um * (1.0 - (-i / s.thermal_parts).exp());
        let noise = cut.sample(&mut keyed_rng(s.seed, part, None));
        let radius_nominal_um = s.nominal_mm * 500.0;
        let uncorrected = (2.0 * (radius_nominal_um + wear + thermal) + noise) / 1e3;
        let corrected = (2.0 * (radius_nominal_um + offset_um + wear + thermal) + noise) / 1e3;
        // Measure: the master, then the part; the edge sits `wear + thermal` outward.
        let edge = wear + thermal;
        let m = measure_part(s, |role, attempt| {
            let radius_um = match role {
                Role::Master => s.master_mm * 500.0,
                Role::Part => corrected * 500.0,
            };
            let forced = s
                .forced
                .filter(|f| f.part == part && f.role == role && attempt < f.attempts);
            let fault = if s.bridged_touch == Some(touches.len()) {
                Some(TouchFault::CoolantBridge)
            } else if let Some(f) = forced {
                Some(f.fault)
            } else {
                s.faults.draw(s.seed, part, role, attempt)
            };
            let from = stream.len();
            // Every touch chatters from its own seed: a fault or a re-measure changes
            // nothing in the other touches, and two loops over these parts see the same.
            machine.rng = keyed_rng(s.seed, part, Some((role, attempt)));
            let read_at = machine.touch(&mut stream, FAR_UM - radius_um + edge, sample_hz, fault);
            touches.push(Touch {
                read_at,
                part,
                role,
                attempt,
                fault,
            });
            let mut out = Err(Alarm::NoDecision);
            for (k, row) in stream.iter().enumerate().skip(from) {
                let (o, _) = kernel.step(row);
                if k == read_at {
                    out = reading(&o, s.scale_um);
                }
            }
            out
        });
        let (row, next) = part_row(
            s,
            (part, uncorrected, corrected, offset_um),
            m,
            injected(&touches, part),
        );
        rows.push(row);
        offset_um = next;
    }
    report(s, rows, stream, touches)
}

/// The report of `rows` (capabilities, the measurement's scatter).
pub fn report(
    s: &SizeLoopSettings,
    rows: Vec<PartRow>,
    stream: Vec<PeriodInputs>,
    touches: Vec<Touch>,
) -> SizeLoopReport {
    let unc: Vec<f64> = rows.iter().map(|r| r.uncorrected_mm).collect();
    let cor: Vec<f64> = rows.iter().map(|r| r.corrected_mm).collect();
    let err: Vec<f64> = rows
        .iter()
        .filter(|r| r.measured_mm.is_finite())
        .map(|r| r.measured_mm - r.corrected_mm)
        .collect();
    let e = capability(&err, 0.0, 1.0);
    SizeLoopReport {
        uncorrected: capability(&unc, s.nominal_mm, s.tolerance_mm),
        corrected: capability(&cor, s.nominal_mm, s.tolerance_mm),
        measurement_two_sigma_um: e.two_sigma_um,
        measurement_range_um: e.range_um,
        rows,
        stream,
        touches,
    }
}

/// The same rows with the measurements replaced by another device's readings
/// (`readings[j]` for touch j of `golden.touches`, [`reading`] of its outputs at the
/// touch's read period; a missing one is no decision), and the corrections they imply:
/// equal to the golden rows exactly when the device latched the same positions and raised
/// the same alarms.
pub fn replay_with(
    s: &SizeLoopSettings,
    golden: &SizeLoopReport,
    readings: &[Result<f64, Alarm>],
) -> Vec<PartRow> {
    let mut offset_um = 0.0;
    let mut out = Vec::with_capacity(golden.rows.len());
    let mut next_touch = 0;
    for g in &golden.rows {
        let m = measure_part(s, |_, _| {
            next_touch += 1;
            readings
                .get(next_touch - 1)
                .copied()
                .unwrap_or(Err(Alarm::NoDecision))
        });
        let shift = (offset_um - g.offset_um) * 2.0 / 1e3;
        let corrected = g.corrected_mm + shift;
        let (row, next) = part_row(
            s,
            (g.part, g.uncorrected_mm, corrected, offset_um),
            m,
            g.injected.clone(),
        );
        out.push(row);
        offset_um = next;
    }
    out
}

/// The parts that alarmed (part number, alarm): reported, their offset not corrected.
pub fn alarms(r: &SizeLoopReport) -> Vec<(usize, &str)> {
    r.rows
        .iter()
        .filter(|p| !p.alarm.is_empty())
        .map(|p| (p.part, p.alarm.as_str()))
        .collect()
}

/// The counts of a run: what the campaign of faulted touches is judged by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct LoopCounts {
    /// Parts turned.
    pub parts: usize,
    /// Corrected parts out of tolerance.
    pub out_of_tolerance: usize,
    /// Uncorrected parts out of tolerance.
    pub uncorrected_out_of_tolerance: usize,
    /// Parts with an alarm (offset not corrected).
    pub alarms: usize,
    /// Alarms that stopped the machine.
    pub stops: usize,
    /// Touches made again after a flagged one.
    pub remeasures: usize,
    /// Touches the stream faulted.
    pub faulted_touches: usize,
    /// Of those, touches whose reading came through unflagged (silent wrong readings:
    /// trapped chips, and any chip burst the checks did not flag).
    pub unflagged_faulted_touches: usize,
}

/// The counts of `r` (`readings`: [`reading`] of each touch, as the loop saw them).
pub fn counts(r: &SizeLoopReport, readings: &[Result<f64, Alarm>]) -> LoopCounts {
    let faulted = || {
        r.touches
            .iter()
            .zip(readings)
            .filter(|(t, _)| t.fault.is_some())
    };
    LoopCounts {
        parts: r.rows.len(),
        out_of_tolerance: r.rows.iter().filter(|p| !p.corrected_ok).count(),
        uncorrected_out_of_tolerance: r.rows.iter().filter(|p| !p.uncorrected_ok).count(),
        alarms: r.rows.iter().filter(|p| !p.alarm.is_empty()).count(),
        stops: r.rows.iter().filter(|p| p.stopped).count(),
        remeasures: r.rows.iter().map(|p| p.remeasures).sum(),
        faulted_touches: faulted().count(),
        unflagged_faulted_touches: faulted().filter(|(_, v)| v.is_ok()).count(),
    }
}

/// The readings of `r`'s touches by the golden model (the component's period semantics).
pub fn golden_readings(
    s: &SizeLoopSettings,
    r: &SizeLoopReport,
    measure: &MeasureConfig,
    force: &ForceConfig,
) -> Vec<Result<f64, Alarm>> {
    let mut kernel = PeriodKernel::new(measure, force);
    let mut touches = r.touches.iter().peekable();
    let mut out = Vec::with_capacity(r.touches.len());
    for (k, row) in r.stream.iter().enumerate() {
        let (o, _) = kernel.step(row);
        while touches.next_if(|t| t.read_at == k).is_some() {
            out.push(reading(&o, s.scale_um));
        }
    }
    out
}

/// The table as text: one line per part, then the capabilities.
pub fn table(s: &SizeLoopSettings, r: &SizeLoopReport) -> Vec<String> {
    let verdict = |ok: bool| if ok { "ok" } else { "OUT" };
    let mut lines = vec![
        format!(
            "part | without correction, mm | verdict | offset, µm | with correction, mm | verdict | measured in process, mm   (Ø{} ± {} mm)",
            s.nominal_mm, s.tolerance_mm
        ),
    ];
    for p in &r.rows {
        let measured = match (p.alarm.is_empty(), p.stopped) {
            (true, _) => format!("{:.4}", p.measured_mm),
            (false, false) => format!("ALARM {} (offset not corrected)", p.alarm),
            (false, true) => format!("ALARM {} (offset not corrected, machine stopped)", p.alarm),
        };
        lines.push(format!(
            "{:4} | {:21.4} | {:7} | {:10.2} | {:19.4} | {:7} | {measured}",
            p.part,
            p.uncorrected_mm,
            verdict(p.uncorrected_ok),
            p.offset_um,
            p.corrected_mm,
            verdict(p.corrected_ok),
        ));
    }
    for (name, c) in [
        ("without correction", r.uncorrected),
        ("with correction", r.corrected),
    ] {
        lines.push(format!(
            "{name}: mean {:.4} mm, 2σ {:.2} µm, range {:.2} µm, Cp {:.2}, Cpk {:.2}, {}/{} in tolerance",
            c.mean_mm, c.two_sigma_um, c.range_um, c.cp, c.cpk, c.in_tolerance, r.rows.len()
        ));
    }
    lines.push(format!(
        "in-process measurement (measured − turned): 2σ {:.2} µm, range {:.2} µm",
        r.measurement_two_sigma_um, r.measurement_range_um
    ));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::force::config::ForceSettings;
    use tooltouch_model::measure::checks::MeasureChecks;
    use tooltouch_model::MeasureSettings;

    #[test]
    fn capability_of_a_known_sample() {
        // Mean 10, σ = 1 (n − 1), tolerance ±3: Cp = 6 / 6 = 1, Cpk = 1.
        let c = capability(&[9.0, 11.0, 9.0, 11.0, 10.0 + 2f64.sqrt() * 0.0], 10.0, 3.0);
        assert!((c.mean_mm - 10.0).abs() < 1e-12);
        let sigma = (4.0f64 / 4.0).sqrt();
        assert!((c.two_sigma_um - 2e3 * sigma).abs() < 1e-9);
        assert!((c.cp - 6.0 / (6.0 * sigma)).abs() < 1e-12);
        assert_eq!(c.range_um, 2e3);
        assert_eq!(c.in_tolerance, 5);
    }

    /// The default measurement settings with the revolution check's tolerance set for the
    /// servo rate ([`servo_pulse_tolerance`]).
    fn servo_settings(s: &SizeLoopSettings, f: &ForceConfig) -> MeasureConfig {
        let d = MeasureSettings::default();
        let tolerance =
            servo_pulse_tolerance(d.pulses_per_rev, s.rpm, f64::from(f.settings().sample_hz));
        assert_eq!(
            tolerance, 54,
            "1024 ppr at 3000 rpm: 51.2 pulses per 1 ms period"
        );
        MeasureSettings {
            checks: MeasureChecks {
                pulse_tolerance: tolerance,
                ..MeasureChecks::default()
            },
            ..d
        }
        .validate()
        .unwrap()
    }

    /// At the servo rate the default tolerance of 2 pulses raises false revolution faults;
    /// [`servo_pulse_tolerance`] none.
    #[test]
    fn the_default_pulse_tolerance_is_too_tight_at_the_servo_rate() {
        let s = SizeLoopSettings::default();
        let m = MeasureSettings::default().validate().unwrap();
        let f = ForceSettings::default().validate().unwrap();
        let tight = run(&s, &m, &f);
        assert!(
            alarms(&tight)
                .iter()
                .any(|(_, a)| a.contains("pulses_lost")),
            "{:?}",
            alarms(&tight)
        );
        assert_eq!(alarms(&run(&s, &servo_settings(&s, &f), &f)), []);
    }

    #[test]
    fn the_loop_holds_the_size_the_uncorrected_parts_drift_out() {
        let s = SizeLoopSettings::default();
        let f = ForceSettings::default().validate().unwrap();
        let m = servo_settings(&s, &f);
        let f = ForceSettings::default().validate().unwrap();
        let r = run(&s, &m, &f);
        for line in table(&s, &r) {
            println!("{line}");
        }
        assert!(
            r.rows.iter().all(|p| p.measured_mm.is_finite()),
            "a touch did not decide"
        );
        assert_eq!(alarms(&r), [], "a clean machine alarms");
        // Wear 0.8 µm/part and 6 µm of drift: the last uncorrected parts are 2·(15.2 + 5.9) µm
        // over, out of ±10 µm; the corrected ones stay inside.
        assert!(r.uncorrected.in_tolerance < s.parts);
        assert_eq!(r.corrected.in_tolerance, s.parts);
        assert!(r.corrected.cpk > r.uncorrected.cpk);
        // The comparative measurement is unbiased to a few scale counts.
        assert!(r.measurement_range_um < 4.0, "{}", r.measurement_range_um);
        // Replaying the golden latches gives the golden rows.
        let mut k = PeriodKernel::new(&m, &f);
        let outs: Vec<_> = r.stream.iter().map(|row| k.step(row).0).collect();
        let readings: Vec<_> = r
            .touches
            .iter()
            .map(|t| reading(&outs[t.read_at], s.scale_um))
            .collect();
        assert_eq!(replay_with(&s, &r, &readings), r.rows);
    }

    /// A coolant bridge closes the contact at the arm of part 6's measuring touch: the
    /// reading alarms `contact_at_arm`, is reported, and the offset stays as it was; the
    /// other parts are measured and corrected as before.
    #[test]
    fn a_faulted_reading_alarms_and_leaves_the_offset_unchanged() {
        let f = ForceSettings::default().validate().unwrap();
        let m = servo_settings(&SizeLoopSettings::default(), &f);
        let clean = run(&SizeLoopSettings::default(), &m, &f);
        let s = SizeLoopSettings {
            bridged_touch: Some(2 * 5 + 1),
            ..SizeLoopSettings::default()
        };
        let r = run(&s, &m, &f);
        for line in table(&s, &r) {
            println!("{line}");
        }
        assert_eq!(alarms(&r), [(6, "part: contact_at_arm")]);
        let (p6, p7) = (&r.rows[5], &r.rows[6]);
        assert!(p6.measured_mm.is_nan());
        assert_eq!(p7.offset_um, p6.offset_um, "corrected after an alarm");
        // Without the bridge, part 6's measurement would have moved the offset.
        assert_ne!(clean.rows[6].offset_um, clean.rows[5].offset_um);
        assert_eq!(r.rows[..5], clean.rows[..5]);
        assert_eq!(p6.offset_um, clean.rows[5].offset_um);
        assert!(table(&s, &r)[6].ends_with("| ALARM part: contact_at_arm (offset not corrected)"));
        // A reading with a fault, or not confirmed, is never a position.
        let o = MeasureOutputs {
            register_now: true,
            confirmed: true,
            decision_position: 10,
            ..Default::default()
        };
        assert_eq!(reading(&o, 0.5), Ok(5.0));
        use tooltouch_model::measure::checks::fault;
        let faulted = MeasureOutputs {
            faults: fault::PULSES_LOST,
            ..o
        };
        assert_eq!(
            reading(&faulted, 0.5),
            Err(Alarm::Faults(Faults(fault::PULSES_LOST)))
        );
        let unconfirmed = MeasureOutputs {
            confirmed: false,
            ..o
        };
        assert_eq!(reading(&unconfirmed, 0.5), Err(Alarm::NotConfirmed));
        let undecided = MeasureOutputs {
            register_now: false,
            ..o
        };
        assert_eq!(reading(&undecided, 0.5), Err(Alarm::NoDecision));
    }

    fn setup() -> (MeasureConfig, ForceConfig) {
        let f = ForceSettings::default().validate().unwrap();
        (servo_settings(&SizeLoopSettings::default(), &f), f)
    }

    /// A flagged touch is made again: a bridge on the first touch only costs a re-measure,
    /// the part is corrected from the second; a bridge on both alarms, stops the machine and
    /// leaves the offset. Today's loop alarms at the first.
    #[test]
    fn a_flagged_touch_is_made_again_and_a_second_alarms_and_stops() {
        let (m, f) = setup();
        let base = SizeLoopSettings {
            rules: LoopRules::SAFE,
            ..SizeLoopSettings::default()
        };
        let clean = run(&base, &m, &f);
        let forced = |attempts, rules| SizeLoopSettings {
            forced: Some(ForcedFault {
                part: 8,
                role: Role::Part,
                attempts,
                fault: TouchFault::CoolantBridge,
            }),
            rules,
            ..base
        };
        let once = run(&forced(1, LoopRules::SAFE), &m, &f);
        assert_eq!(alarms(&once), []);
        assert_eq!(once.rows[7].remeasures, 1);
        assert_eq!(once.rows[7].injected, "part: coolant bridge");
        assert_eq!(once.touches.len(), clean.touches.len() + 1);
        // The re-measure chatters from its own seed: the reading may differ by a count.
        assert!((once.rows[7].measured_mm - clean.rows[7].measured_mm).abs() <= 0.0011);
        let twice = run(&forced(2, LoopRules::SAFE), &m, &f);
        assert_eq!(
            alarms(&twice),
            [(8, "part: contact_at_arm, re-measured: contact_at_arm")]
        );
        assert!(twice.rows[7].stopped && twice.rows[7].measured_mm.is_nan());
        assert_eq!(twice.rows[8].offset_um, twice.rows[7].offset_um);
        assert!(table(&base, &twice)[8].ends_with("(offset not corrected, machine stopped)"));
        let today = run(&forced(1, LoopRules::TODAY), &m, &f);
        assert_eq!(alarms(&today), [(8, "part: contact_at_arm")]);
        assert!(!today.rows[7].stopped && today.rows[7].remeasures == 0);
        // The golden readings replay to the same rows, re-measures and all.
        for r in [&once, &twice] {
            let s = if r == &once {
                forced(1, LoopRules::SAFE)
            } else {
                forced(2, LoopRules::SAFE)
            };
            let replayed = replay_with(&s, r, &golden_readings(&s, r, &m, &f));
            // Debug text: NaN (no reading) compares equal there.
            assert_eq!(format!("{replayed:?}"), format!("{:?}", r.rows));
        }
    }

    /// A chip trapped on the master (4.4 µm: with the roughness's 1.5 µm just under the
    /// 6 µm approach gap) reads the part 8.8 µm small, unflagged: a silent wrong reading.
    /// Today's loop moves the offset by 70 % of it, the safe loop by at most the maximum
    /// correction (2 µm radial). Either may still turn a part out: a wrong reading inside
    /// the upper tolerance limit is a reading like any other (the counts printed).
    #[test]
    fn a_silent_wrong_reading_moves_the_offset_by_at_most_the_maximum_correction() {
        let (m, f) = setup();
        let mut out = [0, 0];
        let mut largest_step = [0.0f64, 0.0];
        for part in 4..=19 {
            for (k, rules) in [LoopRules::TODAY, LoopRules::SAFE].into_iter().enumerate() {
                let s = SizeLoopSettings {
                    forced: Some(ForcedFault {
                        part,
                        role: Role::Master,
                        attempts: 1,
                        fault: TouchFault::TrappedChip { thickness_um: 4.4 },
                    }),
                    rules,
                    ..SizeLoopSettings::default()
                };
                let r = run(&s, &m, &f);
                assert_eq!(alarms(&r), [], "the trapped chip is flagged");
                let bias = r.rows[part - 1].measured_mm - r.rows[part - 1].corrected_mm;
                assert!((-0.0105..-0.0070).contains(&bias), "{bias}");
                out[k] += r.rows.iter().filter(|p| !p.corrected_ok).count();
                let step = r.rows[part].offset_um - r.rows[part - 1].offset_um;
                largest_step[k] = largest_step[k].max(step.abs());
            }
        }
        println!(
            "after a 4.4 µm chip on the master (16 runs of 20 parts): parts out of tolerance today {}, safe {}; largest offset step today {:.2} µm, safe {:.2} µm",
            out[0], out[1], largest_step[0], largest_step[1]
        );
        assert!(largest_step[0] > 2.5, "{}", largest_step[0]);
        assert!(largest_step[1] <= 2.0 + 1e-9, "{}", largest_step[1]);
    }

    /// Beyond the upper tolerance limit the offset stays and the machine stops; the
    /// correction is clipped to the maximum; the dead zone and the feedback as before.
    #[test]
    fn the_upper_tolerance_limit_and_the_maximum_correction() {
        let s = SizeLoopSettings {
            rules: LoopRules::SAFE,
            ..SizeLoopSettings::default()
        };
        let at = |error_mm: f64| corrected_offset(&s, -1.0, &Ok(s.nominal_mm + error_mm));
        assert_eq!(
            at(0.0205),
            (-1.0, Some("upper tolerance limit: error +0.0205 mm".into()))
        );
        assert_eq!(
            at(-0.0205).1.as_deref(),
            Some("upper tolerance limit: error -0.0205 mm")
        );
        assert_eq!(at(0.0015), (-1.0, None), "inside the dead zone");
        let (o, alarm) = at(0.004);
        assert!(
            alarm.is_none() && (o - (-1.0 - 0.7 * 4.0 / 2.0)).abs() < 1e-9,
            "{o}"
        );
        let (o, alarm) = at(0.019);
        assert!(
            alarm.is_none() && (o - (-1.0 - 4.0 / 2.0)).abs() < 1e-9,
            "clipped: {o}"
        );
        let (o, _) = at(-0.019);
        assert!((o - (-1.0 + 2.0)).abs() < 1e-9, "{o}");
        let today = SizeLoopSettings::default();
        let (o, alarm) = corrected_offset(&today, -1.0, &Ok(today.nominal_mm + 0.0205));
        assert!(alarm.is_none() && (o - (-1.0 - 0.7 * 20.5 / 2.0)).abs() < 1e-9);
    }

    /// The goal on the simulated loop: 4 × 200 parts with faulted touches (2 %
    /// coolant bridges, 2 % chip bursts, 1 % trapped chips per touch): no corrected part
    /// out of tolerance with the safe rules; the clean runs have none either.
    #[test]
    fn over_800_parts_with_faulted_touches_the_safe_loop_turns_none_out() {
        let (m, f) = setup();
        let mut totals = [LoopCounts::default(); 3];
        for seed in 31..35 {
            for (k, (rules, faults)) in [
                (LoopRules::SAFE, TouchFaultRates::default()),
                (LoopRules::TODAY, TouchFaultRates::CAMPAIGN),
                (LoopRules::SAFE, TouchFaultRates::CAMPAIGN),
            ]
            .into_iter()
            .enumerate()
            {
                let s = SizeLoopSettings {
                    parts: 200,
                    seed,
                    rules,
                    faults,
                    ..SizeLoopSettings::default()
                };
                let r = run(&s, &m, &f);
                let c = counts(&r, &golden_readings(&s, &r, &m, &f));
                let t = &mut totals[k];
                t.parts += c.parts;
                t.out_of_tolerance += c.out_of_tolerance;
                t.uncorrected_out_of_tolerance += c.uncorrected_out_of_tolerance;
                t.alarms += c.alarms;
                t.stops += c.stops;
                t.remeasures += c.remeasures;
                t.faulted_touches += c.faulted_touches;
                t.unflagged_faulted_touches += c.unflagged_faulted_touches;
            }
        }
        println!(
            "safe, clean:   {:?}\ntoday, faults: {:?}\nsafe, faults:  {:?}",
            totals[0], totals[1], totals[2]
        );
        assert_eq!(totals[0].out_of_tolerance, 0);
        assert_eq!(totals[2].out_of_tolerance, 0);
        assert!(totals[2].faulted_touches > 40 && totals[2].unflagged_faulted_touches > 10);
        assert!(totals[2].remeasures > 20);
        assert!(totals[1].out_of_tolerance > 0, "the faults do not matter");
        assert!(totals[1].uncorrected_out_of_tolerance > 700);
    }
}
