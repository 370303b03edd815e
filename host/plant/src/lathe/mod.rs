//! The lathe simulator (docs/domain.md §2.6): a turning workpiece, a spindle with its encoder, a
//! cross slide with its linear scale, and the tool–workpiece contact circuit, producing the
//! front end's six input pins as a run-length [`Stimulus`].
//!
//! Floats are fine here: this is the plant, not the golden model. Everything is seeded
//! ([`LatheScenario::seed`]) and reproducible: the same scenario and configuration give the
//! same stimulus, bit for bit.
//!
//! The physics, in the modules named after it:
//! - [`surface`]: `R(φ) = R0 + profile(φ) + roughness(φ)` plus the per-revolution spindle
//!   errors, which also shaped the surface and therefore cancel;
//! - [`spindle`]: angle versus clock, FES (`pulses_per_rev`, 50 % duty) and index (one FES
//!   period wide, rising with FES pulse 0 of each revolution), and the axis errors with a
//!   period longer than one revolution (the 50 % method's scatter, eq. S10, docs/domain.md);
//! - [`scale`]: the cross slide's quadrature lines at `scale_resolution_um` per count;
//! - [`electrics`]: bounce at first touch, non-conduction after it, noise spikes shorter
//!   than the glitch filter.
//!
//! Contact exists at clock `t` when the tool's radial position `x(t) ≤ R(φ(t), t)`
//! (docs/domain.md §2.6). [`Lathe`] turns a span of clocks with a given slide motion into pin
//! segments; the closed-loop measurement cycle that decides the motion from the model's
//! outputs is [`crate::measurement_cycle`]. For an open-loop stimulus (one approach, no
//! model in the loop) use [`open_loop_stimulus`].

pub mod electrics;
pub mod faults;
pub mod scale;
pub mod spindle;
pub mod spindle_path;
pub mod surface;

pub use electrics::{ContactElectrics, Intervals};
pub use faults::LatheFaults;
pub use scale::Motion;
pub use spindle::{SlowHarmonic, Spindle};
pub use spindle_path::{PathDifference, SpindlePath};
pub use surface::{Harmonic, Surface};

use crate::stimulus::{Segment, Stimulus};
use serde::{Deserialize, Serialize};
use spindle::SlowErrors;
use std::fmt;
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::MeasureConfig;

/// When the CNC retracts after "register now".
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RetractAt {
    /// `cnc_reaction_us` after "register now" rises (the production handshake).
    Decision,
    /// Keep feeding after the decision until contact has been permanent for one whole
    /// revolution, then retract: what the papers' experiments record (revolutions to
    /// permanent contact, the density growing to 1). The latched position is unaffected.
    /// Spelled `permanent-contact`; the old `permanent_contact` is read for one release.
    #[serde(alias = "permanent_contact")]
    PermanentContact,
}

/// The measurement cycle's motions and timing (docs/domain.md §2.5).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CycleSettings {
    /// Measurements, each at a new Z position, `1..=1000`.
    pub repeats: u32,
    /// Start of each approach above the nominal radius, µm, `0..=10000`.
    pub clearance_um: f64,
    /// Cross-slide speed of the retract back to the start point, mm/s (bounded so the
    /// scale's lines change at most once per `4·(glitch_cycles + 2)` clocks).
    pub retract_mm_per_s: f64,
    /// Axial step between measurements, mm; must exceed the nose radius (docs/domain.md §2.4).
    pub z_step_mm: f64,
    /// Tool nose radius r_ε, mm, `0..=10`.
    pub nose_radius_mm: f64,
    /// Time of the Z step (arm low, slide at the start point), ms, `0..=10000`.
    pub z_dwell_ms: f64,
    /// CNC reaction time from "register now" to the feed stop, µs, `0..=1e6`.
    pub cnc_reaction_us: f64,
    /// When to retract.
    pub retract_at: RetractAt,
    /// Give up an approach (no decision) after this many revolutions, `1..=100000`.
    pub max_approach_revs: u32,
    /// Measurements at each Z position before the Z step, `1..=1000` (S8 averaging: `m`
    /// approaches on the same surface; `repeats` counts them all). Written to a settings
    /// file only when not 1.
    #[serde(skip_serializing_if = "is_one")]
    pub averages_per_z: u32,
}

fn is_one(v: &u32) -> bool {
    *v == 1
}

impl Default for CycleSettings {
    /// 10 measurements, 14 µm clearance (above the form, the spindle errors and the
    /// default spindle path's offset and orbit, about 9 µm at most), 5 mm/s retract, 1 mm Z steps (nose radius
    /// 0.8 mm), 50 ms Z dwell, 0.5 ms CNC reaction, feed on to permanent contact, 200
    /// revolutions at most.
    fn default() -> Self {
        CycleSettings {
            repeats: 10,
            clearance_um: 14.0,
            retract_mm_per_s: 5.0,
            z_step_mm: 1.0,
            nose_radius_mm: 0.8,
            z_dwell_ms: 50.0,
            cnc_reaction_us: 500.0,
            retract_at: RetractAt::PermanentContact,
            max_approach_revs: 200,
            averages_per_z: 1,
        }
    }
}

/// Every parameter of a simulated lathe and measurement cycle. `Default` is the papers'
/// set-up (docs/domain.md §1): D = 40 mm, 800 rpm, f_r = 0.001 mm/rev, 0.1 µm scale, 50 MHz clock.
/// The encoder's pulses per revolution are the configuration's
/// ([`MeasureConfig::pulses_per_rev`]): the configuration describes the encoder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LatheScenario {
    /// FPGA clock, Hz, `1000..=1e9`, dividing 1e9 (VCD contract).
    pub clock_hz: u32,
    /// Spindle speed, rpm, `1..=1e6` and at least 8 clocks per FES period (fast, coarse
    /// scenarios are for tests).
    pub rpm: f64,
    /// Nominal machined diameter D_M, mm, `0.1..=2000`.
    pub diameter_mm: f64,
    /// Radial feed of the approach f_r, mm/rev, `1e-6..=1`.
    pub feed_mm_per_rev: f64,
    /// Linear scale resolution (one count), µm, `0.001..=100`.
    pub scale_resolution_um: f64,
    /// Polyharmonic form error left by machining (radius, µm).
    pub profile: Vec<Harmonic>,
    /// Spindle errors repeating every revolution (radius, µm); they shaped the surface too.
    pub repeating: Vec<Harmonic>,
    /// Fraction of the repeating errors that does not cancel, `0..=1` (0: machining and
    /// measuring trajectories coincide).
    pub repeating_mismatch: f64,
    /// The spindle's supports and loads, from which its path while measuring differs from
    /// its path while machining ([`SpindlePath`]); the default is a plausible small CNC
    /// lathe ([`SpindlePath::typical`]), [`SpindlePath::none`] has no loads.
    #[serde(skip_serializing_if = "SpindlePath::is_default")]
    pub spindle_path: SpindlePath,
    /// Spindle errors with a period longer than one revolution (radius, µm).
    pub slow: Vec<SlowHarmonic>,
    /// Standard deviation of the random radius error (hardness scatter, cutting-force
    /// variation), µm, `0..=1000`; drawn anew at every Z position.
    pub random_um: f64,
    /// Contact-circuit effects.
    pub electrics: ContactElectrics,
    /// The measurement cycle.
    pub cycle: CycleSettings,
    /// Machine faults on the pins (none by default; written to a settings file only when
    /// there are some).
    #[serde(skip_serializing_if = "LatheFaults::is_none")]
    pub faults: LatheFaults,
    /// Seed of every random stream.
    pub seed: u64,
}

impl Default for LatheScenario {
    fn default() -> Self {
        let h = |order, amplitude_um, phase_rad| Harmonic {
            order,
            amplitude_um,
            phase_rad,
        };
        LatheScenario {
            clock_hz: 50_000_000,
            rpm: 800.0,
            diameter_mm: 40.0,
            feed_mm_per_rev: 0.001,
            scale_resolution_um: 0.1,
            profile: vec![h(2, 2.0, 0.4), h(3, 1.0, 1.9), h(5, 0.4, 4.0)],
            repeating: vec![h(1, 0.8, 0.0), h(4, 0.3, 2.5)],
            repeating_mismatch: 0.0,
            spindle_path: SpindlePath::default(),
            slow: vec![
                SlowHarmonic {
                    amplitude_um: 0.4,
                    period_revs: 2.7,
                    phase_rad: 0.0,
                    amplitude_jitter: 0.3,
                },
                SlowHarmonic {
                    amplitude_um: 0.25,
                    period_revs: 5.3,
                    phase_rad: 1.0,
                    amplitude_jitter: 0.3,
                },
            ],
            random_um: 0.15,
            electrics: ContactElectrics::default(),
            cycle: CycleSettings::default(),
            faults: LatheFaults::default(),
            seed: 1,
        }
    }
}

/// A scenario field outside its allowed range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("lathe field `{field}` = {value} is out of range: allowed {range}")]
pub struct ScenarioError {
    /// The field, as in [`LatheScenario`] (dotted for nested fields).
    pub field: String,
    /// The rejected value.
    pub value: f64,
    /// The allowed range, in words.
    pub range: String,
}

/// Most harmonics a `profile`, `repeating` or `slow` list may hold.
pub const MAX_HARMONICS: usize = 256;

impl ScenarioError {
    /// The error with the reason of a range that other fields set appended to its range.
    fn because(mut self, reason: String) -> ScenarioError {
        self.range = format!("{} ({reason})", self.range);
        self
    }
}

fn check(field: &str, value: f64, min: f64, max: f64) -> Result<(), ScenarioError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err(ScenarioError {
            field: field.to_string(),
            value,
            range: format!("{min}..={max}"),
        })
    }
}

impl LatheScenario {
    /// Checks every field against its range and against `config` (the glitch filter
    /// bounds the retract speed; the encoder bounds the spindle speed).
    pub fn validate(&self, config: &MeasureConfig) -> Result<(), ScenarioError> {
        check("clock_hz", self.clock_hz.into(), 1000.0, 1e9)?;
        if 1_000_000_000 % self.clock_hz != 0 {
            return Err(ScenarioError {
                field: "clock_hz".into(),
                value: self.clock_hz.into(),
                range: "a divisor of 1e9 (whole ns clock period, VCD contract)".into(),
            });
        }
        let ppr = f64::from(config.pulses_per_rev());
        let max_rpm = (f64::from(self.clock_hz) * 60.0 / (ppr * 8.0)).min(1e6);
        check("rpm", self.rpm, 1.0, max_rpm).map_err(|e| {
            e.because(format!(
                "at least 8 clocks per FES pulse: clock_hz {} × 60 / (8 × pulses_per_rev {ppr}), at most 1e6",
                self.clock_hz
            ))
        })?;
        check("diameter_mm", self.diameter_mm, 0.1, 2000.0)?;
        check("feed_mm_per_rev", self.feed_mm_per_rev, 1e-6, 1.0)?;
        check(
            "scale_resolution_um",
            self.scale_resolution_um,
            0.001,
            100.0,
        )?;
        for (name, len) in [
            ("profile", self.profile.len()),
            ("repeating", self.repeating.len()),
            ("slow", self.slow.len()),
        ] {
            if len > MAX_HARMONICS {
                return Err(ScenarioError {
                    field: name.into(),
                    value: len as f64,
                    range: format!(
                        "at most {MAX_HARMONICS} harmonics (the value is the list's length; \
                         every harmonic is summed at every surface sample)"
                    ),
                });
            }
        }
        for (name, list) in [("profile", &self.profile), ("repeating", &self.repeating)] {
            for (i, h) in list.iter().enumerate() {
                check(&format!("{name}[{i}].order"), h.order.into(), 1.0, 512.0)?;
                check(
                    &format!("{name}[{i}].amplitude_um"),
                    h.amplitude_um,
                    0.0,
                    1000.0,
                )?;
                check(&format!("{name}[{i}].phase_rad"), h.phase_rad, -1e3, 1e3)?;
            }
        }
        check("repeating_mismatch", self.repeating_mismatch, 0.0, 1.0)?;
        if let Some((field, value, lo, hi)) = self.spindle_path.out_of_range() {
            check(field, value, lo, hi)?;
        }
        for (i, h) in self.slow.iter().enumerate() {
            check(
                &format!("slow[{i}].amplitude_um"),
                h.amplitude_um,
                0.0,
                1000.0,
            )?;
            check(
                &format!("slow[{i}].period_revs"),
                h.period_revs,
                1.0001,
                1000.0,
            )?;
            check(&format!("slow[{i}].phase_rad"), h.phase_rad, -1e3, 1e3)?;
            check(
                &format!("slow[{i}].amplitude_jitter"),
                h.amplitude_jitter,
                0.0,
                1.0,
            )?;
        }
        check("random_um", self.random_um, 0.0, 1000.0)?;
        let e = &self.electrics;
        check(
            "electrics.bounce_pulses",
            e.bounce_pulses.into(),
            0.0,
            100.0,
        )?;
        check("electrics.bounce_on_us", e.bounce_on_us, 0.0, 10_000.0)?;
        check("electrics.bounce_off_us", e.bounce_off_us, 0.0, 10_000.0)?;
        check(
            "electrics.non_conduction_us",
            e.non_conduction_us,
            0.0,
            100_000.0,
        )?;
        check("electrics.spike_rate_hz", e.spike_rate_hz, 0.0, 1e6)?;
        check(
            "electrics.spike_max_cycles",
            e.spike_max_cycles.into(),
            0.0,
            255.0,
        )?;
        let c = &self.cycle;
        check("cycle.repeats", c.repeats.into(), 1.0, 1000.0)?;
        check("cycle.clearance_um", c.clearance_um, 0.0, 10_000.0)?;
        // Scale counts per clock at the retract speed: at most one per 4·(glitch + 2)
        // clocks, so each line change passes the glitch filter on its own.
        let min_cycles_per_count = 4.0 * (f64::from(config.settings().glitch_cycles) + 2.0);
        let max_retract =
            self.scale_resolution_um * 1e-3 * f64::from(self.clock_hz) / min_cycles_per_count;
        check(
            "cycle.retract_mm_per_s",
            c.retract_mm_per_s,
            0.001,
            max_retract.min(1000.0),
        )
        .map_err(|e| {
            e.because(format!(
                "one scale count per 4·(glitch_cycles + 2) clocks: scale_resolution_um {} × 1e-3 × clock_hz {} / (4·({} + 2)), at most 1000",
                self.scale_resolution_um,
                self.clock_hz,
                config.settings().glitch_cycles
            ))
        })?;
        check("cycle.nose_radius_mm", c.nose_radius_mm, 0.0, 10.0)?;
        if !(c.z_step_mm.is_finite() && c.z_step_mm > c.nose_radius_mm && c.z_step_mm <= 100.0) {
            return Err(ScenarioError {
                field: "cycle.z_step_mm".into(),
                value: c.z_step_mm,
                range: format!(
                    "above the nose radius {} mm, at most 100 (docs/domain.md §2.4)",
                    c.nose_radius_mm
                ),
            });
        }
        check("cycle.z_dwell_ms", c.z_dwell_ms, 0.0, 10_000.0)?;
        check("cycle.cnc_reaction_us", c.cnc_reaction_us, 0.0, 1e6)?;
        check("cycle.averages_per_z", c.averages_per_z.into(), 1.0, 1000.0)?;
        check(
            "cycle.max_approach_revs",
            c.max_approach_revs.into(),
            1.0,
            100_000.0,
        )?;
        self.faults.validate()?;
        Ok(())
    }

    /// Nominal radius R0, µm.
    pub fn radius_um(&self) -> f64 {
        self.diameter_mm * 500.0
    }
}

/// The pins of a span of clocks, with what the simulator knows about them.
#[derive(Clone, Debug)]
pub struct Chunk {
    /// First clock.
    pub start: u64,
    /// One past the last clock.
    pub end: u64,
    /// The pins, run-length encoded, covering `start..end`.
    pub segments: Vec<Segment>,
    /// The electric contact without noise spikes (what a clean line would show).
    pub contact: Intervals,
    /// Scale count changes `(clock, new count)`.
    pub count_changes: Vec<(u64, i64)>,
    /// First touch of the approach, if it happened in this span.
    pub touch: Option<u64>,
    /// The arm line's level over the span.
    pub arm: bool,
}

impl Chunk {
    /// The segments of the first `cycles` clocks.
    pub fn truncated_segments(&self, cycles: u64) -> Vec<Segment> {
        let mut out = Vec::new();
        let mut left = cycles;
        for s in &self.segments {
            if left == 0 {
                break;
            }
            let n = u64::from(s.cycles).min(left);
            out.push(Segment {
                pins: s.pins,
                cycles: n as u32,
            });
            left -= n;
        }
        out
    }
}

/// The simulated lathe's state between spans of clocks: the spindle, the current Z
/// position's surface, the scale count, the contact circuit's first-touch state.
#[derive(Clone, Debug)]
pub struct Lathe {
    scenario: LatheScenario,
    spindle: Spindle,
    slow: SlowErrors,
    surface: Surface,
    spike_max_cycles: u32,
    cycles_per_us: f64,
    count: i64,
    home_count: i64,
    first_touch: Option<u64>,
    /// The clock at which the arm rose, while it is high.
    arm_rise: Option<u64>,
}

impl Lathe {
    /// A lathe for `scenario` feeding a front end configured by `config`, at Z position 0,
    /// the slide at the start point. Validates the scenario.
    pub fn new(scenario: &LatheScenario, config: &MeasureConfig) -> Result<Lathe, ScenarioError> {
        scenario.validate(config)?;
        let spindle = Spindle::new(scenario.clock_hz, scenario.rpm, config.pulses_per_rev());
        let res = scenario.scale_resolution_um;
        let start = scenario.radius_um() + scenario.cycle.clearance_um;
        let home_count = ((start / res).floor() as i64).div_euclid(4) * 4;
        let mut lathe = Lathe {
            slow: SlowErrors::new(&scenario.slow, scenario.seed, spindle.cycles_per_rev),
            surface: Surface::new(0.0, &[], &[], 0.0, 0.0, 0, 0),
            spike_max_cycles: scenario
                .electrics
                .spike_max_cycles
                .min(config.settings().glitch_cycles.into()),
            cycles_per_us: f64::from(scenario.clock_hz) * 1e-6,
            count: home_count,
            home_count,
            first_touch: None,
            arm_rise: None,
            spindle,
            scenario: scenario.clone(),
        };
        lathe.set_z(0);
        Ok(lathe)
    }

    /// Moves to axial position number `z_index` (a new surface; the same form error, new
    /// roughness) and clears the first-touch state for the next approach.
    pub fn set_z(&mut self, z_index: u64) {
        let s = &self.scenario;
        self.surface = Surface::new(
            s.radius_um(),
            &s.profile,
            &s.repeating,
            s.repeating_mismatch,
            s.random_um,
            s.seed,
            z_index,
        )
        .with_path_difference(&s.spindle_path.difference(s.rpm));
        self.first_touch = None;
    }

    /// Clears the first-touch state for another approach at the same Z position.
    pub fn clear_first_touch(&mut self) {
        self.first_touch = None;
    }

    /// The scenario.
    pub fn scenario(&self) -> &LatheScenario {
        &self.scenario
    }
    /// The spindle's timing.
    pub fn spindle(&self) -> &Spindle {
        &self.spindle
    }
    /// The current Z position's surface.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }
    /// The approach start point's scale count (≡ 0 mod 4; the count at power-on).
    pub fn home_count(&self) -> i64 {
        self.home_count
    }
    /// The approach start point, µm: the middle of the home count's cell.
    pub fn home_um(&self) -> f64 {
        (self.home_count as f64 + 0.5) * self.scenario.scale_resolution_um
    }
    /// The scale count now.
    pub fn count(&self) -> i64 {
        self.count
    }
    /// FPGA clocks per µs.
    pub fn cycles_per_us(&self) -> f64 {
        self.cycles_per_us
    }

    /// Radial gap between the surface the tool sees and the tool at real clock `t`, µm:
    /// contact when `≥ 0` (docs/domain.md §2.6).
    fn gap(&self, t: f64, motion: &Motion) -> f64 {
        self.surface.seen_at(self.spindle.turns(t)) + self.slow.at(t) - motion.at(t)
    }

    /// Geometric contact in clocks `[k_a, k_b)` with the slide moving by `motion`.
    fn geometric_contact(&self, k_a: u64, k_b: u64, motion: &Motion) -> Intervals {
        let mut out = Intervals::new();
        let lowest = motion.at(k_a as f64).min(motion.at(k_b as f64));
        if lowest > self.surface.largest_seen_um() + self.slow.bound_um() + 1e-6 {
            return out;
        }
        let n = surface::SAMPLES_PER_REV as f64;
        let per_sample = self.spindle.cycles_per_rev / n;
        let first = (k_a as f64 / per_sample).ceil() as u64;
        let last = (k_b as f64 / per_sample).floor() as u64;
        let mut t0 = k_a as f64;
        let mut g0 = self.gap(t0, motion);
        let mut on = g0 >= 0.0;
        let mut start = k_a;
        let mut step = |t1: f64, g1: f64, t0: f64, g0: f64, on: &mut bool, start: &mut u64| {
            if (g1 >= 0.0) != *on {
                let t = t0 + g0 / (g0 - g1) * (t1 - t0);
                let k = (t.ceil().max(k_a as f64) as u64).min(k_b);
                if *on {
                    out.push((*start, k));
                } else {
                    *start = k;
                }
                *on = !*on;
            }
        };
        for i in first..=last {
            let t1 = i as f64 * per_sample;
            if t1 <= t0 {
                continue;
            }
            let g1 = self
                .surface
                .seen_sample((i % surface::SAMPLES_PER_REV as u64) as usize)
                + self.slow.at(t1)
                - motion.at(t1);
            step(t1, g1, t0, g0, &mut on, &mut start);
            t0 = t1;
            g0 = g1;
        }
        let t1 = k_b as f64;
        if t1 > t0 {
            let g1 = self.gap(t1, motion);
            step(t1, g1, t0, g0, &mut on, &mut start);
        }
        if on {
            out.push((start, k_b));
        }
        electrics::normalize(out)
    }

    /// The pins of clocks `[k_a, k_b)` with the slide moving by `motion` and the arm line
    /// at `arm`. `detect_touch`: this span belongs to an approach, so its first contact is
    /// the first touch (bounce, non-conduction). Does not advance the lathe's state: call
    /// [`Self::commit`] with the clocks actually used.
    pub fn chunk(
        &self,
        k_a: u64,
        k_b: u64,
        motion: &Motion,
        arm: bool,
        detect_touch: bool,
    ) -> Chunk {
        let s = &self.scenario;
        let geometric = self.geometric_contact(k_a, k_b, motion);
        let mut touch = None;
        let mut contact = geometric;
        let first_touch = match self.first_touch {
            Some(t) => Some(t),
            None if detect_touch => contact.first().map(|&(s, _)| {
                touch = Some(s);
                s
            }),
            None => None,
        };
        if let Some(t) = first_touch {
            contact = s
                .electrics
                .apply_first_touch(&contact, t, self.cycles_per_us);
            contact = electrics::subtract(&contact, &[(0, k_a), (k_b, u64::MAX)]);
        }
        let spikes = s
            .electrics
            .spikes(k_a, k_b, self.spike_max_cycles, s.clock_hz, s.seed);
        let line = electrics::xor(&contact, &spikes);

        let mut changes: Vec<(u64, u8, bool)> = Vec::new();
        self.spindle.transitions(k_a, k_b, &mut changes);
        for &(start, end) in &line {
            if start > k_a {
                changes.push((start, pin::CONTACT, true));
            }
            if end < k_b {
                changes.push((end, pin::CONTACT, false));
            }
        }
        let mut count_changes = Vec::new();
        scale::count_changes(
            motion,
            s.scale_resolution_um,
            self.count,
            k_a,
            k_b,
            1,
            &mut count_changes,
        );
        let mut previous = scale::lines(self.count);
        for &(k, c) in &count_changes {
            let (a, b) = scale::lines(c);
            if a != previous.0 {
                changes.push((k, pin::SCALE_A, a));
            }
            if b != previous.1 {
                changes.push((k, pin::SCALE_B, b));
            }
            previous = (a, b);
        }
        changes.sort_by_key(|c| c.0);

        let (fes, index) = self.spindle.levels_at(k_a);
        let (a, b) = scale::lines(self.count);
        let mut pins = Pins(0)
            .with(pin::ARM, arm)
            .with(pin::CONTACT, line.first().is_some_and(|&(s, _)| s == k_a))
            .with(pin::FES, fes)
            .with(pin::INDEX, index)
            .with(pin::SCALE_A, a)
            .with(pin::SCALE_B, b);
        let mut stimulus = Stimulus::new(s.clock_hz);
        let mut k = k_a;
        for (clock, bit, level) in changes {
            stimulus.push(pins, clock - k);
            k = clock;
            pins = pins.with(bit, level);
        }
        stimulus.push(pins, k_b - k);
        let segments = faults::inject(
            &s.faults,
            &stimulus.segments,
            k_a,
            &faults::Context {
                spindle: &self.spindle,
                clock_hz: s.clock_hz,
                seed: s.seed,
                arm_rise: arm.then_some(self.arm_rise.unwrap_or(k_a)),
            },
        );
        Chunk {
            start: k_a,
            end: k_b,
            segments,
            contact,
            count_changes,
            touch,
            arm,
        }
    }

    /// Advances the lathe's state over the first clocks of `chunk`, up to (excluding)
    /// clock `end`: the scale count and the first touch.
    pub fn commit(&mut self, chunk: &Chunk, end: u64) {
        if let Some(&(_, c)) = chunk.count_changes.iter().rev().find(|&&(k, _)| k < end) {
            self.count = c;
        }
        if let Some(t) = chunk.touch {
            if t < end {
                self.first_touch = Some(t);
            }
        }
        if !chunk.arm {
            self.arm_rise = None;
        } else if end > chunk.start {
            self.arm_rise.get_or_insert(chunk.start);
        }
    }
}

impl fmt::Display for RetractAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RetractAt::Decision => "decision",
            RetractAt::PermanentContact => "permanent-contact",
        })
    }
}

/// An open-loop stimulus: the slide waits at the start point until the first index pulse
/// after clock 64, the arm rises with that index pulse, and the tool approaches at the
/// feed for `revolutions` revolutions; no retract, no model in the loop. For HDL and
/// firmware tests that want a plain approach of a known length.
pub fn open_loop_stimulus(
    scenario: &LatheScenario,
    config: &MeasureConfig,
    revolutions: u64,
) -> Result<Stimulus, ScenarioError> {
    let mut lathe = Lathe::new(scenario, config)?;
    let mut stimulus = Stimulus::new(scenario.clock_hz);
    let spindle = *lathe.spindle();
    let r0 = spindle.next_revolution(64);
    let k0 = spindle.index_rise(r0);
    let home = lathe.home_um();
    let wait = lathe.chunk(0, k0, &Motion::hold(home), false, false);
    lathe.commit(&wait, k0);
    stimulus.segments.extend(wait.segments);
    let approach = Motion {
        t0: k0 as f64,
        start_um: home,
        speed_um_per_cycle: -scenario.feed_mm_per_rev * 1000.0 / spindle.cycles_per_rev,
    };
    for r in r0..r0 + revolutions {
        let (a, b) = (spindle.index_rise(r), spindle.index_rise(r + 1));
        let chunk = lathe.chunk(a, b, &approach, true, true);
        lathe.commit(&chunk, b);
        for s in chunk.segments {
            stimulus.push(s.pins, s.cycles.into());
        }
    }
    Ok(stimulus)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_loop_stimulus_arms_on_an_index_and_approaches() {
        let config = MeasureConfig::default();
        let s = LatheScenario::default();
        let stim = open_loop_stimulus(&s, &config, 12).unwrap();
        let spindle = Spindle::new(s.clock_hz, s.rpm, 1024);
        assert_eq!(stim.total_cycles(), spindle.index_rise(13));
        // The arm rises with the index pulse of revolution 1, and stays high.
        let mut k = 0u64;
        let mut arm_rise = None;
        let mut contact_clocks = 0u64;
        for seg in &stim.segments {
            if arm_rise.is_none() && seg.pins.get(pin::ARM) {
                arm_rise = Some(k);
                assert!(seg.pins.get(pin::INDEX) && seg.pins.get(pin::FES));
            }
            if arm_rise.is_some() {
                assert!(seg.pins.get(pin::ARM));
            }
            if seg.pins.get(pin::CONTACT) {
                contact_clocks += u64::from(seg.cycles);
            }
            k += u64::from(seg.cycles);
        }
        assert_eq!(arm_rise, Some(spindle.index_rise(1)));
        // 12 µm of feed from 8 µm above R0 reaches into the 3.4 µm form error.
        assert!(contact_clocks > 1_000_000, "{contact_clocks}");
        assert!(stim.segments.len() < 200_000);
    }

    #[test]
    fn bad_scenarios_name_the_field() {
        let config = MeasureConfig::default();
        let s = LatheScenario {
            clock_hz: 48_000_000,
            ..Default::default()
        };
        assert_eq!(s.validate(&config).unwrap_err().field, "clock_hz");
        let mut s = LatheScenario::default();
        s.slow[1].period_revs = 1.0;
        assert_eq!(
            s.validate(&config).unwrap_err().field,
            "slow[1].period_revs"
        );
        let mut s = LatheScenario::default();
        s.cycle.retract_mm_per_s = 500.0;
        let e = s.validate(&config).unwrap_err();
        assert_eq!(e.field, "cycle.retract_mm_per_s");
        assert!(e.to_string().contains("allowed 0.001..=208.3"), "{e}");
    }
}
