//! Functional coverage of a pin stimulus: which of the front end's behaviours it makes the
//! golden model go through, counted in bins named in the domain's words (docs/vectors.md,
//! "Coverage").
//!
//! The cycle-level model runs over the stimulus (settled clocks skipped, as for the golden
//! files); in every clock with edges, the kernel's events are replayed one by one on a copy
//! of its state, so each bin sees the state just before and after the event that hit it.
//! The measurement status's bins count each fault's latching and the decision's
//! confirmation, seen after every event and at the FES watchdog's expiry.
//! The glitch bins look at the raw pins: a pin held for exactly `glitch_cycles` clocks (one
//! short of the filter: rejected) or `glitch_cycles + 1` (just passing) between two
//! changes. A bin that cannot be hit at this configuration says why instead of a count.

use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod, MeasureSettings};
use tooltouch_model::measure::events::MeasureEvent;
use tooltouch_model::measure::frontend::{pin, Edges, Pins};
use tooltouch_model::measure::outputs::MeasureOutputs as Outputs;
use tooltouch_model::{fault, MeasureConfig, Measurement};
use tooltouch_plant::stimulus::Stimulus;

/// One coverage bin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bin {
    /// Its group (`pulse counter`, `density detector`, …).
    pub group: &'static str,
    /// What it counts, in the domain's words.
    pub name: String,
    /// How many times the stimulus hit it.
    pub hits: u64,
    /// Why it cannot be hit at this configuration (`None`: it can).
    pub not_applicable: Option<String>,
}

/// The bins of one run, in report order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coverage {
    /// Every bin.
    pub bins: Vec<Bin>,
    /// Clocks of the stimulus.
    pub cycles: u64,
}

impl Coverage {
    /// Applicable bins hit at least once, and applicable bins.
    pub fn reached(&self) -> (usize, usize) {
        let applicable = self.bins.iter().filter(|b| b.not_applicable.is_none());
        let total = applicable.clone().count();
        (applicable.filter(|b| b.hits > 0).count(), total)
    }

    /// The table: one line per bin (`hits` or `n/a: why`), grouped.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let mut group = "";
        let wide = self
            .bins
            .iter()
            .map(|b| b.name.chars().count())
            .max()
            .unwrap_or(0);
        for b in &self.bins {
            if b.group != group {
                out.push_str(&format!("{}:\n", b.group));
                group = b.group;
            }
            let value = match &b.not_applicable {
                Some(why) => format!("n/a: {why}"),
                None if b.hits == 0 => "0  MISSED".to_string(),
                None => b.hits.to_string(),
            };
            let pad = wide - b.name.chars().count();
            out.push_str(&format!("  {}{}  {value}\n", b.name, " ".repeat(pad)));
        }
        let (hit, total) = self.reached();
        out.push_str(&format!(
            "{hit} of {total} applicable bins hit over {} clocks\n",
            self.cycles
        ));
        out
    }

    /// The JSON form: `{"cycles", "reached", "applicable", "bins": [{"group", "name",
    /// "hits", "not_applicable"}]}`.
    pub fn json(&self) -> serde_json::Value {
        let (hit, total) = self.reached();
        serde_json::json!({
            "cycles": self.cycles,
            "reached": hit,
            "applicable": total,
            "bins": self.bins.iter().map(|b| serde_json::json!({
                "group": b.group,
                "name": b.name,
                "hits": b.hits,
                "not_applicable": b.not_applicable,
            })).collect::<Vec<_>>(),
        })
    }
}

/// The figures of a configuration that bins are named and judged by.
struct Figures {
    /// The settings.
    s: MeasureSettings,
    /// Pulses per counting window.
    window: u32,
    /// Full-scale charge, LSBs.
    full: u32,
    /// Density fire threshold, LSBs.
    fire: u32,
    /// Density re-arm threshold, LSBs.
    rearm: u32,
    /// Glitch filter length, clocks.
    g: u64,
    /// The sticky contact rule.
    sticky: bool,
    /// The exponential charge law.
    exp: bool,
    /// Contact pulses a confirming window must count.
    confirm: u32,
}

impl Figures {
    fn of(config: &MeasureConfig) -> Figures {
        let s = *config.settings();
        Figures {
            s,
            window: config.window_pulses(),
            full: config.full_charge(),
            fire: s.fire_threshold,
            rearm: s.rearm_threshold,
            g: u64::from(s.glitch_cycles),
            sticky: s.contact_rule == ContactRule::Sticky,
            exp: matches!(s.charge_law, ChargeLaw::Exponential { .. }),
            confirm: config.confirm_count(),
        }
    }
}

/// A bin's applicability: applicable when `cond` holds, else not, for the reason `why`.
fn needs(cond: bool, why: &'static str) -> Option<&'static str> {
    (!cond).then_some(why)
}

/// One event bin, declared once: its group, its name and why it may not apply.
struct BinSpec {
    /// Its group.
    group: &'static str,
    /// Its name at a configuration.
    name: fn(&Figures) -> String,
    /// Why it cannot be hit at a configuration (`None`: it can).
    not_applicable: fn(&Figures) -> Option<&'static str>,
}

/// Declares the event bins: the index enum `B` and the table [`EVENT_BINS`] in one order.
macro_rules! event_bins {
    ($($(#[$attr:meta])* $bin:ident: $group:expr, $name:expr, $na:expr;)*) => {
        /// Event bin indexes, in report order (that of [`EVENT_BINS`]).
        #[derive(Clone, Copy)]
        enum B {
            $($(#[$attr])* $bin,)*
        }
        /// The bins hit by the model's events, in report order.
        const EVENT_BINS: &[BinSpec] = &[$(BinSpec {
            group: $group,
            name: $name,
            not_applicable: $na,
        },)*];
    };
}

const PC: &str = "pulse counter";
const CT: &str = "contact rule";
const DD: &str = "density detector";
const DE: &str = "decision";
const AR: &str = "arm";
const SC: &str = "scale and counters";
const ST: &str = "measurement status";

event_bins! {
    FirstPulseDecision: PC,
        |_| "count exceeds i_def on the first pulse of a window".into(),
        |f| needs(f.s.i_def == 0, "needs i_def = 0");
    LastPulseDecision: PC,
        |_| "count exceeds i_def on the last pulse of a window".into(),
        |_| None;
    EndBelow: PC,
        |f| format!("window ends with count i_def - 1 = {}", f.s.i_def.wrapping_sub(1)),
        |f| needs(f.s.i_def > 0, "i_def = 0");
    EndAt: PC,
        |f| format!("window ends with count i_def = {}", f.s.i_def),
        |_| None;
    EndAbove: PC,
        |f| format!("window ends with count i_def + 1 = {}", f.s.i_def + 1),
        |_| None;
    CountSaturated: PC,
        |f| format!("contact pulse with the count saturated at {}", f.window),
        |_| None;
    StickyBetween: CT,
        |_| "pulse counts a contact seen only between pulses".into(),
        |f| needs(f.sticky, "sampled rule");
    StickyReloadDisarmed: CT,
        |_| "sticky bit reloaded by a pulse while disarmed".into(),
        |f| needs(f.sticky, "sampled rule");
    FesDisarmed: CT, |_| "FES pulse while disarmed".into(), |_| None;
    FireMinus: DD,
        |f| format!("charge fire_threshold - 1 = {} while armed", f.fire - 1),
        |f| needs(f.fire > 1 && f.fire - 1 > f.rearm, "fire_threshold - 1 is the re-arm level");
    FireAt: DD,
        |f| format!("charge reaches fire_threshold = {} while armed (fires)", f.fire),
        |_| None;
    FirePlus: DD,
        |f| format!("charge fire_threshold + 1 = {}", f.fire + 1),
        |f| needs(f.fire < f.full, "fire_threshold is full scale");
    RearmMinus: DD,
        |f| format!(
            "charge rearm_threshold - 1 = {} while fired (re-arms)",
            f.rearm.wrapping_sub(1)
        ),
        |f| needs(f.rearm > 0, "rearm_threshold = 0");
    RearmAt: DD,
        |f| format!("charge rearm_threshold = {} while fired (stays fired)", f.rearm),
        |_| None;
    RearmPlus: DD,
        |f| format!("charge rearm_threshold + 1 = {}", f.rearm + 1),
        |_| None;
    ChargeFull: DD,
        |f| format!("contact pulse with the charge at full scale {}", f.full),
        |_| None;
    ChargeEmpty: DD, |_| "pulse without contact with the charge at 0".into(), |_| None;
    ExpStepFull: DD,
        |_| "exponential charge step of 1 LSB near full scale".into(),
        |f| needs(f.exp, "linear law");
    ExpStepEmpty: DD,
        |_| "exponential discharge step of 1 LSB near 0".into(),
        |f| needs(f.exp, "linear law");
    DensityDecision: DE,
        |_| "decision when the charge fires".into(),
        |f| needs(f.s.method == DecisionMethod::Density, "not the density method");
    SinglePulseDecision: DE,
        |_| "decision at the first contact".into(),
        |f| needs(f.s.method == DecisionMethod::SinglePulse, "not the single-pulse method");
    FirstContact: DE, |_| "first contact latched".into(), |_| None;
    ArmClearsLatches: AR, |_| "arm rising edge clears held latches".into(), |_| None;
    ArmRiseMidWindow: AR, |_| "arm rises mid-window (counts to clear)".into(), |_| None;
    ArmFallMidWindow: AR, |_| "arm falls mid-window (retract)".into(), |_| None;
    ScaleError: SC, |_| "scale error (double change)".into(), |_| None;
    ScaleErrorsSaturated: SC,
        |_| "scale error with the error count saturated at 255".into(),
        |_| None;
    PositionWrap: SC, |f| format!("position wraps at {} bits", f.s.scale_bits), |_| None;
    PulsesWrap: SC, |_| "FES pulse count wraps past 2^32 - 1".into(), |_| None;
    RevolutionsSaturated: SC, |_| "revolutions held at 65535".into(), |_| None;
    #[allow(dead_code)] // never hit: its bin is always n/a
    Reset: SC,
        |_| "reset mid-measurement".into(),
        |_| Some("a pin stimulus has no reset: it is the testbench's `rst`");
    FaultContactAtArm: ST,
        |_| "contact_at_arm: contact closed when the arm rises".into(),
        |f| needs(f.s.checks.contact_at_arm, "checks.contact_at_arm = false");
    FaultPulsesLost: ST,
        |f| format!(
            "pulses_lost: a revolution of fewer than pulses_per_rev - pulse_tolerance = {} FES pulses",
            f.s.pulses_per_rev - f.s.checks.pulse_tolerance
        ),
        |f| needs(f.s.checks.revolutions, "checks.revolutions = false");
    FaultIndexMissing: ST,
        |f| format!(
            "index_missing: more than pulses_per_rev + pulse_tolerance = {} FES pulses without an index",
            u32::from(f.s.pulses_per_rev) + u32::from(f.s.checks.pulse_tolerance)
        ),
        |f| needs(f.s.checks.revolutions, "checks.revolutions = false");
    FaultScaleError: ST,
        |_| "scale_error: an illegal scale transition while armed".into(),
        |f| needs(f.s.checks.scale_errors, "checks.scale_errors = false");
    FaultNoDecision: ST,
        |f| format!("no_decision: probe_revs = {} revolutions without a decision", f.s.checks.probe_revs),
        |f| needs(f.s.checks.probe_revs != 0, "checks.probe_revs = 0");
    FaultFesTimeout: ST,
        |f| format!(
            "fes_timeout: fes_timeout_cycles = {} clocks without an FES pulse",
            f.s.checks.fes_timeout_cycles
        ),
        |f| needs(f.s.checks.fes_timeout_cycles != 0, "checks.fes_timeout_cycles = 0");
    FaultUnconfirmed: ST,
        |f| format!("unconfirmed: a window after the decision below {} contact pulses", f.confirm),
        |f| match (f.s.checks.confirm_windows, f.confirm) {
            (0, _) => Some("checks.confirm_windows = 0"),
            (_, 0) => Some("a confirmation level of 0 contact pulses"),
            _ => None,
        };
    Confirmed: ST,
        |f| format!("decision confirmed ({} windows)", f.s.checks.confirm_windows),
        |_| None;
}

/// The fault bins, by fault bit position ([`fault::NAMES`] order).
const FAULT_BINS: [B; fault::COUNT] = [
    B::FaultContactAtArm,
    B::FaultPulsesLost,
    B::FaultIndexMissing,
    B::FaultScaleError,
    B::FaultNoDecision,
    B::FaultFesTimeout,
    B::FaultUnconfirmed,
];

const PAIR_NAMES: [&str; 5] = ["arm", "contact", "index", "FES", "scale"];

/// Same-clock edge bins, one per pair of [`PAIR_NAMES`].
const PAIRS: usize = PAIR_NAMES.len() * (PAIR_NAMES.len() - 1) / 2;

/// Every bin of `f` with no hits, in report order: the event bins ([`EVENT_BINS`]), the
/// same-clock pairs, then two glitch bins per pin.
fn bins_of(f: &Figures) -> Vec<Bin> {
    let bin = |group: &'static str, name: String, why: Option<&str>| Bin {
        group,
        name,
        hits: 0,
        not_applicable: why.map(str::to_string),
    };
    let mut bins: Vec<Bin> = EVENT_BINS
        .iter()
        .map(|b| bin(b.group, (b.name)(f), (b.not_applicable)(f)))
        .collect();
    for (i, first) in PAIR_NAMES.iter().enumerate() {
        for second in &PAIR_NAMES[i + 1..] {
            bins.push(bin("same-clock edges", format!("{first} + {second}"), None));
        }
    }
    let g = f.g;
    for name in pin::NAMES {
        bins.push(bin(
            "glitch filter",
            format!("{name}: pulse of glitch_cycles = {g} clocks (rejected)"),
            needs(g > 0, "glitch_cycles = 0"),
        ));
        bins.push(bin(
            "glitch filter",
            format!(
                "{name}: pulse of glitch_cycles + 1 = {} clocks (passes)",
                g + 1
            ),
            None,
        ));
    }
    bins
}

/// The coverage of `stimulus` at `config`.
pub fn coverage(stimulus: &Stimulus, config: &MeasureConfig) -> Coverage {
    let f = Figures::of(config);
    let mut walk = Walk::new(&f);
    let mut glitches = GlitchRuns::new(f.g);
    let mut k = 0u64;
    for seg in &stimulus.segments {
        glitches.pins_from(seg.pins, k);
        k += u64::from(seg.cycles);
    }
    // The kernel before each clocked clock: settled and edgeless clocks change it not.
    let mut before: Option<Measurement> = None;
    let (fe, _) = crate::clock_through_to_end(stimulus, config, |k, _, fe, edges| {
        let pre = before.unwrap_or_else(|| Measurement::new(config));
        if !edges.is_empty() {
            walk.clock(k, pre, &edges);
        } else if crate::watchdog_expires_at(fe, k) {
            walk.status(&fe.outputs());
        }
        before = Some(*fe.measurement());
    });
    walk.status(&fe.outputs());
    let mut bins = bins_of(&f);
    let hits = walk
        .hits
        .iter()
        .chain(&walk.pair_hits)
        .chain(&glitches.hits);
    for (b, h) in bins.iter_mut().zip(hits) {
        b.hits = *h;
    }
    Coverage {
        bins,
        cycles: stimulus.total_cycles(),
    }
}

/// The glitch bins' bookkeeping over the raw pins: how long each pin held its level.
struct GlitchRuns {
    /// Glitch filter length, clocks.
    g: u64,
    /// The pins of the previous segment.
    last: Option<Pins>,
    /// The clock each pin's level began at.
    level_since: [u64; pin::COUNT],
    /// Whether each pin has changed once (its run has a start).
    have_run: [bool; pin::COUNT],
    /// Per pin: runs of exactly `g` clocks, then runs of `g + 1`.
    hits: [u64; 2 * pin::COUNT],
}

impl GlitchRuns {
    fn new(g: u64) -> GlitchRuns {
        GlitchRuns {
            g,
            last: None,
            level_since: [0; pin::COUNT],
            have_run: [false; pin::COUNT],
            hits: [0; 2 * pin::COUNT],
        }
    }

    /// The pins become `pins` at clock `k`.
    fn pins_from(&mut self, pins: Pins, k: u64) {
        let g = self.g;
        if let Some(before) = self.last {
            let changed = before.0 ^ pins.0;
            for p in 0..pin::COUNT {
                if changed & (1 << p) != 0 {
                    let run = k - self.level_since[p];
                    if self.have_run[p] && g > 0 && run == g {
                        self.hits[2 * p] += 1;
                    }
                    if self.have_run[p] && run == g + 1 {
                        self.hits[2 * p + 1] += 1;
                    }
                    self.level_since[p] = k;
                    self.have_run[p] = true;
                }
            }
        }
        self.last = Some(pins);
    }
}

/// The event and same-clock bins' hits, and the bookkeeping they need.
struct Walk<'a> {
    f: &'a Figures,
    /// Hits of each [`EVENT_BINS`] bin.
    hits: Vec<u64>,
    /// Hits of each same-clock pair.
    pair_hits: [u64; PAIRS],
    /// Armed pulses since the window began.
    pulses_in_window: u64,
    /// The last pulse of the window decided.
    decided_on_last: bool,
    /// The `faults` word and `confirmed` last seen (a bin counts their rises).
    status: (u8, bool),
}

/// One event of a clock: the measurement just before it (`pre`, with its outputs `po`)
/// and just after (`m`, outputs `qo`).
struct Step<'m> {
    pre: &'m Measurement,
    m: &'m Measurement,
    po: Outputs,
    qo: Outputs,
}

impl<'a> Walk<'a> {
    fn new(f: &'a Figures) -> Walk<'a> {
        Walk {
            f,
            hits: vec![0; EVENT_BINS.len()],
            pair_hits: [0; PAIRS],
            pulses_in_window: 0,
            decided_on_last: false,
            status: (0, false),
        }
    }

    /// The measurement status seen in `o`: a hit for each fault newly latched and for the
    /// decision's confirmation.
    fn status(&mut self, o: &Outputs) {
        let (faults, confirmed) = self.status;
        let risen = o.faults & !faults;
        for (bit, bin) in FAULT_BINS.iter().enumerate() {
            if risen & (1 << bit) != 0 {
                self.hit(*bin);
            }
        }
        if o.confirmed && !confirmed {
            self.hit(B::Confirmed);
        }
        self.status = (o.faults, o.confirmed);
    }

    fn hit(&mut self, b: B) {
        self.hits[b as usize] += 1;
    }

    /// One clock `k` with edges: its events replayed one by one on a copy of the state `m`
    /// before the clock, at time `k` (the FES watchdog's verdict first).
    fn clock(&mut self, k: u64, mut m: Measurement, edges: &Edges) {
        let mut kinds = [false; 5];
        let mut events = Vec::with_capacity(5);
        edges.for_each_event(|e| events.push(e));
        let double = edges.changed & (pin::SCALE_A | pin::SCALE_B) == pin::SCALE_A | pin::SCALE_B;
        m.observe(k);
        self.status(&m.outputs());
        for e in events {
            let pre = m;
            m.apply_at(k, e);
            let step = Step {
                pre: &pre,
                m: &m,
                po: pre.outputs(),
                qo: m.outputs(),
            };
            match e {
                MeasureEvent::Arm(level) => {
                    kinds[0] = true;
                    self.arm(level, &step);
                }
                MeasureEvent::Contact(level) => {
                    kinds[1] = true;
                    self.contact(level, &step);
                }
                MeasureEvent::Index => {
                    kinds[2] = true;
                    self.index(&step);
                }
                MeasureEvent::Fes => {
                    kinds[3] = true;
                    self.fes(&step);
                }
                MeasureEvent::Scale { .. } => {
                    kinds[4] = true;
                    self.scale(double, &step);
                }
                MeasureEvent::PresetPulses(_) => {}
            }
            self.status(&step.qo);
        }
        let mut n = 0;
        for i in 0..5 {
            for j in i + 1..5 {
                if kinds[i] && kinds[j] {
                    self.pair_hits[n] += 1;
                }
                n += 1;
            }
        }
    }

    fn arm(&mut self, level: bool, st: &Step) {
        let (pre, po) = (st.pre, &st.po);
        let mid = pre.counter().count() > 0 || pre.counter().revs_in_window() > 0;
        if level && !po.armed {
            if po.first_contact || po.register_now {
                self.hit(B::ArmClearsLatches);
            }
            if mid {
                self.hit(B::ArmRiseMidWindow);
            }
            self.pulses_in_window = 0;
            self.decided_on_last = false;
        } else if !level && po.armed && mid {
            self.hit(B::ArmFallMidWindow);
        }
    }

    fn contact(&mut self, level: bool, st: &Step) {
        let (po, qo) = (&st.po, &st.qo);
        if level && po.armed && !po.first_contact && qo.first_contact {
            self.hit(B::FirstContact);
        }
        if !po.register_now && qo.register_now {
            self.hit(B::SinglePulseDecision);
        }
    }

    fn index(&mut self, st: &Step) {
        let (pre, m, po) = (st.pre, st.m, &st.po);
        if !po.armed {
            return;
        }
        if po.revolutions == u16::MAX {
            self.hit(B::RevolutionsSaturated);
        }
        if m.counter().revs_in_window() != 0 {
            return;
        }
        let i_def = self.f.s.i_def;
        let c = pre.counter().count();
        if i_def > 0 && c == i_def - 1 {
            self.hit(B::EndBelow);
        }
        if c == i_def {
            self.hit(B::EndAt);
        }
        if c == i_def + 1 {
            self.hit(B::EndAbove);
        }
        if self.decided_on_last {
            self.hit(B::LastPulseDecision);
        }
        self.pulses_in_window = 0;
        self.decided_on_last = false;
    }

    fn fes(&mut self, st: &Step) {
        let f = self.f;
        let (pre, m, po, qo) = (st.pre, st.m, &st.po, &st.qo);
        let bit = if f.sticky { pre.sticky() } else { po.contact };
        if !po.armed {
            self.hit(B::FesDisarmed);
            if f.sticky && pre.sticky() && !po.contact {
                self.hit(B::StickyReloadDisarmed);
            }
            return;
        }
        self.pulses_in_window += 1;
        if f.sticky && pre.sticky() && !po.contact {
            self.hit(B::StickyBetween);
        }
        let decided = !pre.counter().reached() && m.counter().reached();
        if decided && self.pulses_in_window == 1 {
            self.hit(B::FirstPulseDecision);
        }
        self.decided_on_last = decided;
        if bit && po.count == f.window {
            self.hit(B::CountSaturated);
        }
        if po.pulses == u32::MAX {
            self.hit(B::PulsesWrap);
        }
        self.density(bit, st);
        if f.s.method == DecisionMethod::Density && !po.register_now && qo.register_now {
            self.hit(B::DensityDecision);
        }
    }

    /// The density detector's bins at an armed FES pulse that saw contact `bit`.
    fn density(&mut self, bit: bool, st: &Step) {
        let f = self.f;
        let (fire, rearm, full) = (f.fire, f.rearm, f.full);
        let (d0, d1) = (st.pre.density(), st.m.density());
        let c = d1.charge();
        if fire > 1 && c == fire - 1 && d0.armed() {
            self.hit(B::FireMinus);
        }
        if c == fire && d0.armed() {
            self.hit(B::FireAt);
        }
        if c == fire + 1 {
            self.hit(B::FirePlus);
        }
        if rearm > 0 && c == rearm - 1 && !d0.armed() {
            self.hit(B::RearmMinus);
        }
        if c == rearm && !d0.armed() {
            self.hit(B::RearmAt);
        }
        if c == rearm + 1 {
            self.hit(B::RearmPlus);
        }
        if bit && d0.charge() == full {
            self.hit(B::ChargeFull);
        }
        if !bit && d0.charge() == 0 {
            self.hit(B::ChargeEmpty);
        }
        if let ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } = f.s.charge_law
        {
            let q = d0.charge();
            if bit && q < full && (full - q) >> charge_shift == 0 {
                self.hit(B::ExpStepFull);
            }
            if !bit && q > 0 && q >> discharge_shift == 0 {
                self.hit(B::ExpStepEmpty);
            }
        }
    }

    fn scale(&mut self, double: bool, st: &Step) {
        let (po, qo) = (&st.po, &st.qo);
        if double {
            self.hit(B::ScaleError);
            if po.scale_errors == u8::MAX {
                self.hit(B::ScaleErrorsSaturated);
            }
        }
        let half = 1i64 << (self.f.s.scale_bits - 1);
        let (a, b) = (i64::from(po.position), i64::from(qo.position));
        if (a == half - 1 && b == -half) || (a == -half && b == half - 1) {
            self.hit(B::PositionWrap);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::config::DecisionMethod;
    use tooltouch_model::MeasureSettings;
    use tooltouch_plant::stress::{stress_stimulus, StressSize};

    /// The default stress run (`vectors --stress 1`) reaches every fault condition and a
    /// confirmed decision, at the default configuration and at a density-method,
    /// exponential-law, single-pulse one with other thresholds.
    #[test]
    fn the_default_stress_run_reaches_every_measurement_status_bin() {
        let density = MeasureSettings {
            method: DecisionMethod::Density,
            charge_law: ChargeLaw::Exponential {
                charge_shift: 3,
                discharge_shift: 4,
            },
            ..MeasureSettings::default()
        };
        let mut single = MeasureSettings {
            pulses_per_rev: 64,
            window_revs: 2,
            i_def: 10,
            glitch_cycles: 0,
            method: DecisionMethod::SinglePulse,
            contact_rule: ContactRule::Sampled,
            ..MeasureSettings::default()
        };
        single.checks.pulse_tolerance = 5;
        single.checks.probe_revs = 7;
        single.checks.fes_timeout_cycles = 300;
        single.checks.confirm_windows = 2;
        for settings in [MeasureSettings::default(), density, single] {
            let config = settings.validate().unwrap();
            let s = stress_stimulus(&config, 1, 50_000_000, &StressSize::default());
            let cov = coverage(&s, &config);
            let status: Vec<&Bin> = cov.bins.iter().filter(|b| b.group == ST).collect();
            assert_eq!(status.len(), fault::COUNT + 1, "{}", cov.table());
            for (bin, name) in status.iter().zip(fault::NAMES) {
                assert!(bin.name.starts_with(name), "{}", bin.name);
            }
            for bin in status {
                assert!(
                    bin.not_applicable.is_none() && bin.hits > 0,
                    "{settings:?}: `{}` not reached:\n{}",
                    bin.name,
                    cov.table()
                );
            }
        }
    }

    /// A check turned off makes its bin not applicable, with the setting named.
    #[test]
    fn a_check_turned_off_has_no_bin_to_reach() {
        let config = MeasureSettings {
            checks: tooltouch_model::MeasureChecks::OFF,
            ..MeasureSettings::default()
        }
        .validate()
        .unwrap();
        let cov = coverage(&Stimulus::new(50_000_000), &config);
        let why: Vec<Option<&str>> = cov
            .bins
            .iter()
            .filter(|b| b.group == ST)
            .map(|b| b.not_applicable.as_deref())
            .collect();
        assert_eq!(
            why,
            [
                Some("checks.contact_at_arm = false"),
                Some("checks.revolutions = false"),
                Some("checks.revolutions = false"),
                Some("checks.scale_errors = false"),
                Some("checks.probe_revs = 0"),
                Some("checks.fes_timeout_cycles = 0"),
                Some("checks.confirm_windows = 0"),
                None,
            ]
        );
    }
}
