//! Stress stimuli: directed plus constrained-random pin sequences for one configuration,
//! aimed at the behaviours a one-off mistake in an implementation hides behind (see
//! docs/vectors.md, "Stress stimuli"):
//!
//! - windows whose count ends one below, at and one above `i_def`, a decision on the last
//!   pulse of a window (and on the first, when `i_def = 0`), a count saturating at
//!   `pulses_per_rev × window_revs`;
//! - the sticky bit set between pulses, and reloaded by an FES pulse while disarmed;
//! - latches held and then cleared by an arm rising edge; arm falling and rising
//!   mid-window;
//! - pulses of `glitch_cycles` clocks (one short of the filter: rejected) and of
//!   `glitch_cycles + 1` (just passing) on every pin;
//! - edges in the same clock for each pair of the canonical order (arm, contact, index,
//!   FES, scale);
//! - the charge steered onto `fire_threshold − 1`, `fire_threshold` (armed) and
//!   `rearm_threshold`, `rearm_threshold − 1` (fired), and ± 1 around them, saturated at
//!   full scale and at 0 (which reaches the exponential law's one-LSB steps at both ends);
//! - the measurement status at each threshold (`tooltouch_model::measure::checks`): the
//!   contact closed at arm; revolutions of `pulses_per_rev − pulse_tolerance` FES pulses
//!   and one fewer, `pulses_per_rev + pulse_tolerance` and one more without an index;
//!   `probe_revs` revolutions without a decision; no FES pulse for `fes_timeout_cycles`
//!   clocks (when at most [`WATCHDOG_STRESS_MAX`]); a decision confirmed by its windows
//!   and one the contact does not confirm;
//! - scale moves both ways, double changes (errors) until the error count saturates, and a
//!   position wrap when `2^scale_bits` steps fit the budget;
//! - then a constrained-random tail ([`crate::random::random_stimulus`]) from the seed.
//!
//! Every level of the directed part is held at least `glitch_cycles + 1` clocks (but for
//! the deliberate glitches), so it makes exactly the kernel events the generator applies to
//! its own event-level copy of the model, at the clocks the cycle level applies them
//! (which steers it, e.g. towards a charge value, and times the FES watchdog); `tests`
//! checks that the cycle level ends in the same state.

use crate::random::random_stimulus;
use crate::stimulus::Stimulus;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tooltouch_model::measure::config::{ChargeLaw, ContactRule};
use tooltouch_model::measure::frontend::{pin, Edges, Pins};
use tooltouch_model::{MeasureConfig, Measurement};

/// How long a stress stimulus is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StressSize {
    /// Clocks of the constrained-random tail after the directed part.
    pub random_cycles: u64,
    /// At most this many FES pulses to steer the charge onto each target.
    pub steer_pulses: u32,
    /// A position wrap is driven only when it takes at most this many scale steps.
    pub wrap_steps: u64,
}

impl Default for StressSize {
    /// A short stimulus: 20 000 random clocks, at most 4 096 pulses per charge target,
    /// wraps of at most 4 096 steps.
    fn default() -> Self {
        StressSize {
            random_cycles: 20_000,
            steer_pulses: 4_096,
            wrap_steps: 4_096,
        }
    }
}

/// Phase order of the scale lines for positive motion (A leads B).
const SCALE_PHASES: [u8; 4] = [0, pin::SCALE_A, pin::SCALE_A | pin::SCALE_B, pin::SCALE_B];

/// The generator: the stimulus so far, the pins now, and the kernel as the events so far
/// left it.
struct Gen<'a> {
    config: &'a MeasureConfig,
    s: Stimulus,
    pins: u8,
    phase: usize,
    kernel: Measurement,
    rng: ChaCha8Rng,
    /// Clocks a level must be held to pass the glitch filter.
    pass: u64,
    /// Clocks of the stimulus so far: the clock the next segment starts at.
    clock: u64,
    /// Clocks from a pin change to the kernel's event ([`MeasureConfig::latency_cycles`]).
    latency: u64,
}

impl Gen<'_> {
    /// Holds the current pins for `pass` clocks, one time in four up to 2 more.
    fn hold(&mut self) {
        let extra = if self.rng.random_bool(0.25) {
            self.rng.random_range(1..=2)
        } else {
            0
        };
        let n = self.pass + extra;
        self.push(self.pins, n);
    }

    /// Appends `n` clocks of `pins`.
    fn push(&mut self, pins: u8, n: u64) {
        self.s.push(Pins(pins), n);
        self.clock += n;
    }

    /// Makes the last segment `clocks` clocks long.
    fn set_last_len(&mut self, clocks: u64) {
        let last = self.s.segments.len() - 1;
        let len = u32::try_from(clocks).unwrap_or(u32::MAX);
        self.clock = self.clock - u64::from(self.s.segments[last].cycles) + u64::from(len);
        self.s.segments[last].cycles = len;
    }

    /// Changes the pins to `new` (in one clock) and holds them: the kernel sees the edges
    /// in canonical order, `latency` clocks after the change (the time it is told, as the
    /// cycle level tells it at every clock with edges).
    fn set(&mut self, new: u8) {
        let edges = Edges {
            changed: self.pins ^ new,
            levels: new,
        };
        let kernel = &mut self.kernel;
        let time = self.clock + self.latency;
        if edges.changed != 0 {
            kernel.observe(time);
        }
        edges.for_each_event(|e| kernel.apply_at(time, e));
        self.pins = new;
        self.hold();
    }

    fn level(&mut self, bit: u8, on: bool) {
        let new = if on {
            self.pins | bit
        } else {
            self.pins & !bit
        };
        if new != self.pins {
            self.set(new);
        }
    }

    fn arm(&mut self, on: bool) {
        self.level(pin::ARM, on);
    }

    /// Arm low then high: a new measurement cycle (counts, charge, latches cleared).
    fn rearm(&mut self) {
        self.arm(false);
        self.arm(true);
    }

    fn contact(&mut self, on: bool) {
        self.level(pin::CONTACT, on);
    }

    /// One FES pulse at the current contact level.
    fn fes(&mut self) {
        self.level(pin::FES, true);
        self.level(pin::FES, false);
    }

    /// `n` FES pulses with contact at `on`.
    fn pulses(&mut self, n: u32, on: bool) {
        self.contact(on);
        for _ in 0..n {
            self.fes();
        }
    }

    fn index(&mut self) {
        self.level(pin::INDEX, true);
        self.level(pin::INDEX, false);
    }

    /// The scale phase bits for a step `up` or down from the current phase.
    fn scale_bits_after(&mut self, up: bool) -> u8 {
        self.phase = if up {
            (self.phase + 1) % 4
        } else {
            (self.phase + 3) % 4
        };
        (self.pins & !(pin::SCALE_A | pin::SCALE_B)) | SCALE_PHASES[self.phase]
    }

    fn scale_step(&mut self, up: bool) {
        let new = self.scale_bits_after(up);
        self.set(new);
    }

    /// A double change of the scale lines (an error; the position does not move).
    fn scale_error(&mut self) {
        self.phase = (self.phase + 2) % 4;
        let new = (self.pins & !(pin::SCALE_A | pin::SCALE_B)) | SCALE_PHASES[self.phase];
        self.set(new);
    }

    /// Pin `bit` inverted for `clocks` clocks and back, with no kernel event when it is
    /// shorter than the filter; the surrounding levels are held long enough.
    fn glitch(&mut self, bit: u8, clocks: u64) {
        if clocks >= self.pass {
            let back = self.pins;
            self.set(self.pins ^ bit);
            // `set` held it `pass..=pass + 2` clocks; a pulse of exactly `clocks` clocks:
            self.set_last_len(clocks);
            self.set(back);
        } else if clocks > 0 {
            self.push(self.pins ^ bit, clocks);
            self.hold();
        }
    }

    /// Steers the charge with FES pulses (with or without contact) until a pulse brings it
    /// to `target` from a state armed (`armed`) or fired, by the shortest sequence of at
    /// most `budget` pulses ([`density_path`]); leaves contact low. Returns whether it got
    /// there.
    fn steer(&mut self, target: u32, armed: bool, budget: u32) -> bool {
        let d = self.kernel.density();
        let sticky =
            self.config.settings().contact_rule == ContactRule::Sticky && self.kernel.sticky();
        let from = (d.charge(), d.armed(), sticky);
        let Some(path) = density_path(self.config, from, (target, armed), budget) else {
            return false;
        };
        for contact in path {
            self.pulses(1, contact);
        }
        self.contact(false);
        self.kernel.density().charge() == target
    }
}

/// The largest charge register [`density_path`] searches, bits (2^22 states).
const SEARCHED_CHARGE_BITS: u8 = 20;

/// The density detector's state after one pulse with contact bit `bit` from charge `q`,
/// `armed` (the model's law: linear steps, or `max(1, distance >> shift)`, saturating at 0
/// and full scale; fire at `>= fire_threshold` while armed, re-arm below
/// `rearm_threshold`).
fn density_step(config: &MeasureConfig, (q, armed): (u32, bool), bit: bool) -> (u32, bool) {
    let s = config.settings();
    let full = config.full_charge();
    let exp = |d: u32, sh: u8| if d == 0 { 0 } else { (d >> sh.min(31)).max(1) };
    let next = match (s.charge_law, bit) {
        (ChargeLaw::Linear { charge_step, .. }, true) => q.saturating_add(charge_step).min(full),
        (ChargeLaw::Linear { discharge_step, .. }, false) => q.saturating_sub(discharge_step),
        (ChargeLaw::Exponential { charge_shift, .. }, true) => q + exp(full - q, charge_shift),
        (
            ChargeLaw::Exponential {
                discharge_shift, ..
            },
            false,
        ) => q - exp(q, discharge_shift),
    };
    let armed = if armed {
        next < s.fire_threshold
    } else {
        next < s.rearm_threshold
    };
    (next, armed)
}

/// The shortest sequence of pulses (their contact levels) of at most `budget` whose last
/// pulse brings the density detector's charge to `to.0` from a state whose armed flag is
/// `to.1`, starting from `from` (charge, armed, sticky bit), by breadth-first search over
/// its states. Under the sticky rule a pulse's bit is its contact level or the sticky bit
/// (the previous pulse's level), so a pulse without contact right after one with counts as
/// contact. `None` when there is none (or the register is wider than
/// [`SEARCHED_CHARGE_BITS`]).
fn density_path(
    config: &MeasureConfig,
    from: (u32, bool, bool),
    to: (u32, bool),
    budget: u32,
) -> Option<Vec<bool>> {
    if config.settings().charge_bits > SEARCHED_CHARGE_BITS {
        return None;
    }
    let sticky_rule = config.settings().contact_rule == ContactRule::Sticky;
    let index =
        |(q, a, st): (u32, bool, bool)| (q as usize) * 4 + usize::from(a) * 2 + usize::from(st);
    let states = (config.full_charge() as usize + 1) * 4;
    // Per state: the state it was reached from and the contact level of that pulse.
    let mut parent = vec![u32::MAX; states];
    let mut level = vec![false; states];
    let mut queue = std::collections::VecDeque::new();
    parent[index(from)] = index(from) as u32;
    queue.push_back((from, 0u32));
    while let Some((state, depth)) = queue.pop_front() {
        if depth >= budget {
            continue;
        }
        for contact in [true, false] {
            let bit = contact || (sticky_rule && state.2);
            let (q, a) = density_step(config, (state.0, state.1), bit);
            let next = (q, a, sticky_rule && contact);
            if q == to.0 && state.1 == to.1 {
                let mut path = vec![contact];
                let mut i = index(state);
                while i != index(from) {
                    path.push(level[i]);
                    i = parent[i] as usize;
                }
                path.reverse();
                return Some(path);
            }
            let j = index(next);
            if parent[j] == u32::MAX {
                parent[j] = index(state) as u32;
                level[j] = contact;
                queue.push_back((next, depth + 1));
            }
        }
    }
    None
}

/// The stress stimulus of `config` for `seed` at `clock_hz` (see the module documentation).
pub fn stress_stimulus(
    config: &MeasureConfig,
    seed: u64,
    clock_hz: u32,
    size: &StressSize,
) -> Stimulus {
    generate(config, seed, clock_hz, size).0
}

/// The directed sections of the stress stimulus, in order.
impl Gen<'_> {
    /// The pulse counter: windows ending one below, at and one above `i_def`, decisions
    /// on a window's last and first pulse, a saturating count.
    fn counter_windows(&mut self) {
        let s = *self.config.settings();
        let window = self.config.window_pulses();
        // Windows ending one below, at and one above i_def (the last decides).
        for target in [s.i_def.checked_sub(1), Some(s.i_def), Some(s.i_def + 1)]
            .into_iter()
            .flatten()
            .filter(|&t| t <= window)
        {
            self.rearm();
            self.scale_step(true);
            self.pulses(target, true);
            self.contact(false);
            for _ in 0..s.window_revs {
                self.index();
            }
        }
        // A decision on the last pulse of a full window, then on the first pulse of the next
        // (reached only when i_def = 0).
        self.rearm();
        self.pulses(window - (s.i_def + 1), false);
        self.pulses(s.i_def + 1, true);
        self.contact(false);
        for _ in 0..s.window_revs {
            self.index();
        }
        self.rearm();
        self.pulses(1, true);
        self.contact(false);
        // A count saturating: more contact pulses than a window holds, no index.
        self.rearm();
        self.pulses(window + 2, true);
        self.contact(false);
    }

    /// The sticky bit set between pulses and reloaded while disarmed; the arm falling and
    /// rising mid-window.
    fn contact_rule_and_arm(&mut self) {
        // The sticky bit: set by a contact between pulses, reloaded by a pulse while disarmed.
        self.rearm();
        self.glitch(pin::CONTACT, self.pass);
        self.fes();
        self.arm(false);
        self.glitch(pin::CONTACT, self.pass);
        self.fes(); // disarmed: reloads the sticky bit with contact 0
        self.arm(true);
        self.fes(); // counts only if the sticky bit was not reloaded
        self.index();
        // Arm falling and rising mid-window, with latches held.
        self.scale_step(false);
        self.pulses(2, true);
        self.arm(false);
        self.pulses(2, true);
        self.scale_step(true);
        self.arm(true);
        self.pulses(1, true);
        self.contact(false);
    }

    /// Glitches one clock short of the filter and just long enough, on every pin.
    fn glitches(&mut self) {
        // Glitches one clock short of the filter and just long enough, on every pin.
        for bit in [pin::ARM, pin::CONTACT, pin::INDEX, pin::FES] {
            for clocks in [self.pass - 1, self.pass] {
                self.glitch(bit, clocks);
                self.glitch(bit, clocks);
            }
        }
        for clocks in [self.pass - 1, self.pass] {
            for bit in [pin::SCALE_A, pin::SCALE_B] {
                // A glitch on one scale line is a step and its reverse when it passes.
                if clocks >= self.pass {
                    let back = self.pins;
                    let phase = self.phase;
                    let new = self.pins ^ bit;
                    self.phase = SCALE_PHASES
                        .iter()
                        .position(|&p| p == new & (pin::SCALE_A | pin::SCALE_B))
                        .unwrap_or(phase);
                    self.set(new);
                    self.set_last_len(clocks);
                    self.phase = phase;
                    self.set(back);
                } else {
                    self.glitch(bit, clocks);
                }
            }
        }
    }

    /// Edges in the same clock for each pair of the canonical order.
    fn same_clock_pairs(&mut self) {
        // Edges in the same clock, for each pair of the canonical order (rising edges; the
        // scale a step), twice each, with the other lines at random levels.
        let kinds: [u8; 5] = [pin::ARM, pin::CONTACT, pin::INDEX, pin::FES, 0];
        for i in 0..kinds.len() {
            for j in i + 1..kinds.len() {
                for _ in 0..2 {
                    let pair = [kinds[i], kinds[j]];
                    self.level(pin::INDEX, false);
                    self.level(pin::FES, false);
                    let arm_on = !pair.contains(&pin::ARM);
                    self.arm(arm_on);
                    let contact_on = !pair.contains(&pin::CONTACT) && self.rng.random_bool(0.5);
                    self.contact(contact_on);
                    let mut new = self.pins;
                    for k in pair {
                        new = if k == 0 {
                            let stepped = self.scale_bits_after(true);
                            (new & !(pin::SCALE_A | pin::SCALE_B))
                                | (stepped & (pin::SCALE_A | pin::SCALE_B))
                        } else {
                            new | k
                        };
                    }
                    self.set(new);
                }
            }
        }
        self.level(pin::INDEX, false);
        self.level(pin::FES, false);
        self.arm(true);
        self.contact(false);
    }

    /// The density detector's thresholds and full scale (`steer_pulses`: the most pulses
    /// spent steering the charge onto one).
    fn density_thresholds(&mut self, steer_pulses: u32) {
        let s = *self.config.settings();
        let config = self.config;
        // The density detector: the charge steered onto each threshold and one LSB around
        // it, in the armed state where a threshold one off would act differently, chained from
        // one measurement cycle; then held at full scale and at 0.
        let (fire, rearm, full) = (s.fire_threshold, s.rearm_threshold, config.full_charge());
        self.rearm();
        // (charge, armed before the pulse that brings it there)
        let mut targets: Vec<(u32, bool)> = vec![(fire, true), (rearm, false)];
        if rearm > 0 {
            targets.push((rearm - 1, false));
        }
        if fire - 1 > rearm {
            targets.push((fire - 1, true));
        }
        if fire < full {
            targets.push((fire + 1, false));
        }
        targets.push((rearm + 1, false));
        for (target, armed) in targets {
            self.steer(target, armed, steer_pulses);
        }
        while self.kernel.density().charge() < full {
            self.pulses(1, true);
        }
        self.pulses(2, true);
        while self.kernel.density().charge() > 0 {
            self.pulses(1, false);
        }
        self.pulses(2, false);
    }

    /// The scale both ways, errors to saturation, a wrap within `wrap_steps` steps.
    fn scale_and_wrap(&mut self, wrap_steps: u64) {
        let s = *self.config.settings();
        // The scale: both ways, errors until their count saturates, a wrap if it fits.
        for _ in 0..6 {
            self.scale_step(false);
        }
        for _ in 0..=u32::from(u8::MAX) {
            self.scale_error();
        }
        let half = 1u64 << (s.scale_bits - 1);
        let position = i64::from(self.kernel.scale().position());
        let to_wrap = (half as i64 - position).unsigned_abs();
        if to_wrap <= wrap_steps {
            for _ in 0..=to_wrap {
                self.scale_step(true);
            }
        }
        self.arm(false);
        self.contact(false);
        self.level(pin::FES, false);
        self.level(pin::INDEX, false);
        self.hold();
    }
}

/// Longest FES watchdog the stress drives to expiry, clocks.
pub const WATCHDOG_STRESS_MAX: u64 = 1 << 17;

/// Most contact pulses the stress spends bringing about a decision.
const DECISION_PULSES_MAX: u32 = 1 << 16;

/// The measurement status's fault conditions (module `tooltouch_model::measure::checks`),
/// each at its threshold: one short of it (no fault) and at it (the fault).
impl Gen<'_> {
    /// Every fault condition the configuration checks, and a confirmed decision.
    fn measurement_status(&mut self) {
        self.contact_at_arm();
        self.revolution_lengths();
        self.probe_fail();
        self.fes_watchdog();
        self.confirmation();
        // Leave a clean measurement cycle running (the scale section errs while armed).
        self.rearm();
    }

    /// The contact closed at the arm's rising edge (`contact_at_arm`).
    fn contact_at_arm(&mut self) {
        self.arm(false);
        self.contact(true);
        self.arm(true);
        self.contact(false);
    }

    /// Revolutions of `pulses_per_rev − pulse_tolerance` FES pulses (no fault), one fewer
    /// (`pulses_lost`), `pulses_per_rev + pulse_tolerance` (no fault) and one more without
    /// an index (`index_missing`).
    fn revolution_lengths(&mut self) {
        let s = self.config.settings();
        let ppr = u32::from(s.pulses_per_rev);
        let tolerance = u32::from(s.checks.pulse_tolerance);
        let (fewest, most) = (ppr - tolerance, ppr + tolerance);
        self.rearm();
        self.index();
        self.pulses(fewest, false);
        self.index();
        self.pulses(fewest - 1, false);
        self.index();
        self.rearm();
        self.index();
        self.pulses(most, false);
        self.index();
        self.pulses(most + 1, false);
        self.index();
    }

    /// `probe_revs − 1` revolutions without a decision (no fault), then one more
    /// (`no_decision`); index pulses only (so the revolutions are short too).
    fn probe_fail(&mut self) {
        let revs = self.config.settings().checks.probe_revs;
        if revs == 0 {
            return;
        }
        self.rearm();
        for _ in 0..revs {
            self.index();
        }
    }

    /// No FES pulse for `fes_timeout_cycles` clocks after one (`fes_timeout`), when that
    /// is at most [`WATCHDOG_STRESS_MAX`]. The golden trace shows the fault from exactly
    /// the clock it expires at, so one long gap checks the threshold both ways: a watchdog
    /// a clock early or late differs there.
    fn fes_watchdog(&mut self) {
        let timeout = u64::from(self.config.settings().checks.fes_timeout_cycles);
        if timeout == 0 || timeout > WATCHDOG_STRESS_MAX {
            return;
        }
        self.rearm();
        self.contact(false);
        self.fes();
        self.push(self.pins, timeout);
        self.fes();
    }

    /// A decision confirmed by every window after it, then one the contact does not
    /// confirm (`unconfirmed`: the contact falls back after the decision, as after a chip).
    fn confirmation(&mut self) {
        let windows = self.config.settings().checks.confirm_windows;
        let level = self.config.confirm_count();
        for confirmed in [true, false] {
            self.rearm();
            if !self.decide() {
                return;
            }
            for _ in 0..windows.max(1) {
                if confirmed {
                    while self.kernel.outputs().count < level {
                        self.pulses(1, true);
                    }
                }
                self.contact(false);
                for _ in 0..self.config.settings().window_revs {
                    self.index();
                }
            }
        }
    }

    /// Contact pulses until the configured method decides (at most
    /// [`DECISION_PULSES_MAX`]); whether it did.
    fn decide(&mut self) -> bool {
        self.contact(true);
        let mut n = 0;
        while !self.kernel.register_now() && n < DECISION_PULSES_MAX {
            self.fes();
            n += 1;
        }
        self.kernel.register_now()
    }
}

/// [`stress_stimulus`] and the kernel state its directed part ends in.
fn generate(
    config: &MeasureConfig,
    seed: u64,
    clock_hz: u32,
    size: &StressSize,
) -> (Stimulus, Measurement) {
    let s = config.settings();
    let mut g = Gen {
        config,
        s: Stimulus::new(clock_hz),
        pins: 0,
        phase: 0,
        kernel: Measurement::new(config),
        rng: ChaCha8Rng::seed_from_u64(seed),
        pass: u64::from(s.glitch_cycles) + 1,
        clock: 0,
        latency: config.latency_cycles().into(),
    };
    // Power-on, then a measurement cycle with the scale away from 0 (so a latch that is
    // not cleared shows).
    g.push(0, 4);
    g.arm(true);
    for _ in 0..5 {
        g.scale_step(true);
    }

    g.counter_windows();
    g.contact_rule_and_arm();
    g.glitches();
    g.same_clock_pairs();
    g.density_thresholds(size.steer_pulses);
    g.measurement_status();
    g.scale_and_wrap(size.wrap_steps);
    let directed_end = g.kernel;

    // The constrained-random tail.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x005e_ed0f_7a11);
    if size.random_cycles > 0 {
        let tail = random_stimulus(&mut rng, config, clock_hz, size.random_cycles);
        for seg in tail.segments {
            g.s.push(seg.pins, seg.cycles.into());
        }
    }
    (g.s, directed_end)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::{FrontEnd, MeasureSettings};

    /// The cycle level over the directed part ends in the state the generator's own
    /// event-level copy reached: every level made exactly the events it applied.
    #[test]
    fn the_directed_part_makes_the_events_the_generator_applied() {
        for settings in [
            MeasureSettings::default(),
            MeasureSettings {
                pulses_per_rev: 64,
                i_def: 0,
                glitch_cycles: 0,
                charge_bits: 8,
                charge_law: ChargeLaw::Exponential {
                    charge_shift: 2,
                    discharge_shift: 3,
                },
                fire_threshold: 200,
                rearm_threshold: 40,
                scale_bits: 8,
                method: tooltouch_model::measure::config::DecisionMethod::Density,
                ..MeasureSettings::default()
            },
        ] {
            let config = settings.validate().unwrap();
            let size = StressSize {
                random_cycles: 0,
                ..StressSize::default()
            };
            let (stimulus, kernel) = generate(&config, 1, 50_000_000, &size);
            let mut fe = FrontEnd::new(&config);
            for p in stimulus.cycles() {
                fe.clock(p);
            }
            let last = stimulus.segments.last().unwrap().pins;
            for _ in 0..config.latency_cycles() + 2 {
                fe.clock(last);
            }
            assert_eq!(fe.measurement(), &kernel, "{settings:?}");
        }
    }
}
