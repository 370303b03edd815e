//! Functional coverage of a pin stimulus: which of the front end's behaviours it makes the
//! golden model go through, counted in bins named in the domain's words (docs/vectors.md,
//! "Coverage").
//!
//! The cycle-level model runs over the stimulus (settled clocks skipped, as for the golden
//! files); in every clock with edges, the kernel's events are replayed one by one on a copy
//! of its state, so each bin sees the state just before and after the event that hit it.
//! The glitch bins look at the raw pins: a pin held for exactly `glitch_cycles` clocks (one
//! short of the filter: rejected) or `glitch_cycles + 1` (just passing) between two
//! changes. A bin that cannot be hit at this configuration says why instead of a count.

use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::measure::events::MeasureEvent;
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{FrontEnd, MeasureConfig, Measurement};
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

/// Bin indexes, in report order.
#[derive(Clone, Copy)]
enum B {
    FirstPulseDecision,
    LastPulseDecision,
    EndBelow,
    EndAt,
    EndAbove,
    CountSaturated,
    StickyBetween,
    StickyReloadDisarmed,
    FesDisarmed,
    FireMinus,
    FireAt,
    FirePlus,
    RearmMinus,
    RearmAt,
    RearmPlus,
    ChargeFull,
    ChargeEmpty,
    ExpStepFull,
    ExpStepEmpty,
    DensityDecision,
    SinglePulseDecision,
    FirstContact,
    ArmClearsLatches,
    ArmRiseMidWindow,
    ArmFallMidWindow,
    ScaleError,
    ScaleErrorsSaturated,
    PositionWrap,
    PulsesWrap,
    RevolutionsSaturated,
    Reset,
}

const PAIR_NAMES: [&str; 5] = ["arm", "contact", "index", "FES", "scale"];

/// The coverage of `stimulus` at `config`.
pub fn coverage(stimulus: &Stimulus, config: &MeasureConfig) -> Coverage {
    let s = *config.settings();
    let window = config.window_pulses();
    let full = config.full_charge();
    let (fire, rearm) = (s.fire_threshold, s.rearm_threshold);
    let g = u64::from(s.glitch_cycles);
    let sticky = s.contact_rule == ContactRule::Sticky;
    let exp = matches!(s.charge_law, ChargeLaw::Exponential { .. });
    let method = s.method;
    let na = |cond: bool, why: &str| (!cond).then(|| why.to_string());
    let mut bins: Vec<Bin> = Vec::new();
    fn add(bins: &mut Vec<Bin>, group: &'static str, name: String, why: Option<String>) {
        bins.push(Bin {
            group,
            name,
            hits: 0,
            not_applicable: why,
        })
    }
    let pc = "pulse counter";
    add(
        &mut bins,
        pc,
        "count exceeds i_def on the first pulse of a window".into(),
        na(s.i_def == 0, "needs i_def = 0"),
    );
    add(
        &mut bins,
        pc,
        "count exceeds i_def on the last pulse of a window".into(),
        None,
    );
    add(
        &mut bins,
        pc,
        format!(
            "window ends with count i_def - 1 = {}",
            s.i_def.wrapping_sub(1)
        ),
        na(s.i_def > 0, "i_def = 0"),
    );
    add(
        &mut bins,
        pc,
        format!("window ends with count i_def = {}", s.i_def),
        None,
    );
    add(
        &mut bins,
        pc,
        format!("window ends with count i_def + 1 = {}", s.i_def + 1),
        None,
    );
    add(
        &mut bins,
        pc,
        format!("contact pulse with the count saturated at {window}"),
        None,
    );
    let ct = "contact rule";
    add(
        &mut bins,
        ct,
        "pulse counts a contact seen only between pulses".into(),
        na(sticky, "sampled rule"),
    );
    add(
        &mut bins,
        ct,
        "sticky bit reloaded by a pulse while disarmed".into(),
        na(sticky, "sampled rule"),
    );
    add(&mut bins, ct, "FES pulse while disarmed".into(), None);
    let dd = "density detector";
    add(
        &mut bins,
        dd,
        format!("charge fire_threshold - 1 = {} while armed", fire - 1),
        na(
            fire > 1 && fire - 1 > rearm,
            "fire_threshold - 1 is the re-arm level",
        ),
    );
    add(
        &mut bins,
        dd,
        format!("charge reaches fire_threshold = {fire} while armed (fires)"),
        None,
    );
    add(
        &mut bins,
        dd,
        format!("charge fire_threshold + 1 = {}", fire + 1),
        na(fire < full, "fire_threshold is full scale"),
    );
    add(
        &mut bins,
        dd,
        format!(
            "charge rearm_threshold - 1 = {} while fired (re-arms)",
            rearm.wrapping_sub(1)
        ),
        na(rearm > 0, "rearm_threshold = 0"),
    );
    add(
        &mut bins,
        dd,
        format!("charge rearm_threshold = {rearm} while fired (stays fired)"),
        None,
    );
    add(
        &mut bins,
        dd,
        format!("charge rearm_threshold + 1 = {}", rearm + 1),
        None,
    );
    add(
        &mut bins,
        dd,
        format!("contact pulse with the charge at full scale {full}"),
        None,
    );
    add(
        &mut bins,
        dd,
        "pulse without contact with the charge at 0".into(),
        None,
    );
    add(
        &mut bins,
        dd,
        "exponential charge step of 1 LSB near full scale".into(),
        na(exp, "linear law"),
    );
    add(
        &mut bins,
        dd,
        "exponential discharge step of 1 LSB near 0".into(),
        na(exp, "linear law"),
    );
    let de = "decision";
    add(
        &mut bins,
        de,
        "decision when the charge fires".into(),
        na(method == DecisionMethod::Density, "not the density method"),
    );
    add(
        &mut bins,
        de,
        "decision at the first contact".into(),
        na(
            method == DecisionMethod::SinglePulse,
            "not the single-pulse method",
        ),
    );
    add(&mut bins, de, "first contact latched".into(), None);
    let ar = "arm";
    add(
        &mut bins,
        ar,
        "arm rising edge clears held latches".into(),
        None,
    );
    add(
        &mut bins,
        ar,
        "arm rises mid-window (counts to clear)".into(),
        None,
    );
    add(&mut bins, ar, "arm falls mid-window (retract)".into(), None);
    let sc = "scale and counters";
    add(&mut bins, sc, "scale error (double change)".into(), None);
    add(
        &mut bins,
        sc,
        "scale error with the error count saturated at 255".into(),
        None,
    );
    add(
        &mut bins,
        sc,
        format!("position wraps at {} bits", s.scale_bits),
        None,
    );
    add(
        &mut bins,
        sc,
        "FES pulse count wraps past 2^32 - 1".into(),
        None,
    );
    add(&mut bins, sc, "revolutions held at 65535".into(), None);
    add(
        &mut bins,
        sc,
        "reset mid-measurement".into(),
        Some("a pin stimulus has no reset: it is the testbench's `rst`".into()),
    );
    let pairs_at = bins.len();
    for (i, first) in PAIR_NAMES.iter().enumerate() {
        for second in &PAIR_NAMES[i + 1..] {
            add(
                &mut bins,
                "same-clock edges",
                format!("{first} + {second}"),
                None,
            );
        }
    }
    let glitch_at = bins.len();
    for name in pin::NAMES {
        add(
            &mut bins,
            "glitch filter",
            format!("{name}: pulse of glitch_cycles = {g} clocks (rejected)"),
            na(g > 0, "glitch_cycles = 0"),
        );
        add(
            &mut bins,
            "glitch filter",
            format!(
                "{name}: pulse of glitch_cycles + 1 = {} clocks (passes)",
                g + 1
            ),
            None,
        );
    }

    let mut hit = |b: B| bins[b as usize].hits += 1;
    let mut pair_hits = [0u64; 10];
    let mut glitch_hits = [0u64; 2 * pin::COUNT];
    // Own bookkeeping: armed pulses since the window began, a decision on the last one.
    let mut pulses_in_window = 0u64;
    let mut decided_on_last = false;
    let mut fe = FrontEnd::new(config);
    let mut k = 0u64;
    let mut last_pins: Option<Pins> = None;
    let mut level_since = [0u64; pin::COUNT];
    let mut have_run = [false; pin::COUNT];
    for seg in &stimulus.segments {
        if let Some(before) = last_pins {
            let changed = before.0 ^ seg.pins.0;
            for p in 0..pin::COUNT {
                if changed & (1 << p) != 0 {
                    let run = k - level_since[p];
                    if have_run[p] && g > 0 && run == g {
                        glitch_hits[2 * p] += 1;
                    }
                    if have_run[p] && run == g + 1 {
                        glitch_hits[2 * p + 1] += 1;
                    }
                    level_since[p] = k;
                    have_run[p] = true;
                }
            }
        }
        last_pins = Some(seg.pins);
        let end = k + u64::from(seg.cycles);
        while k < end {
            if fe.is_settled(seg.pins) {
                k = end;
                break;
            }
            let mut m: Measurement = *fe.measurement();
            let edges = fe.clock(seg.pins);
            k += 1;
            if edges.is_empty() {
                continue;
            }
            let mut kinds = [false; 5];
            let mut events = Vec::with_capacity(5);
            edges.for_each_event(|e| events.push(e));
            let double =
                edges.changed & (pin::SCALE_A | pin::SCALE_B) == pin::SCALE_A | pin::SCALE_B;
            for e in events {
                let pre = m;
                m.apply(e);
                let (po, qo) = (pre.outputs(), m.outputs());
                match e {
                    MeasureEvent::Arm(level) => {
                        kinds[0] = true;
                        let mid = pre.counter().count() > 0 || pre.counter().revs_in_window() > 0;
                        if level && !po.armed {
                            if po.first_contact || po.register_now {
                                hit(B::ArmClearsLatches);
                            }
                            if mid {
                                hit(B::ArmRiseMidWindow);
                            }
                            pulses_in_window = 0;
                            decided_on_last = false;
                        } else if !level && po.armed && mid {
                            hit(B::ArmFallMidWindow);
                        }
                    }
                    MeasureEvent::Contact(level) => {
                        kinds[1] = true;
                        if level && po.armed && !po.first_contact && qo.first_contact {
                            hit(B::FirstContact);
                        }
                        if !po.register_now && qo.register_now {
                            hit(B::SinglePulseDecision);
                        }
                    }
                    MeasureEvent::Index => {
                        kinds[2] = true;
                        if po.armed {
                            if po.revolutions == u16::MAX {
                                hit(B::RevolutionsSaturated);
                            }
                            let ends = m.counter().revs_in_window() == 0;
                            if ends {
                                let c = pre.counter().count();
                                if s.i_def > 0 && c == s.i_def - 1 {
                                    hit(B::EndBelow);
                                }
                                if c == s.i_def {
                                    hit(B::EndAt);
                                }
                                if c == s.i_def + 1 {
                                    hit(B::EndAbove);
                                }
                                if decided_on_last {
                                    hit(B::LastPulseDecision);
                                }
                                pulses_in_window = 0;
                                decided_on_last = false;
                            }
                        }
                    }
                    MeasureEvent::Fes => {
                        kinds[3] = true;
                        let bit = if sticky { pre.sticky() } else { po.contact };
                        if !po.armed {
                            hit(B::FesDisarmed);
                            if sticky && pre.sticky() && !po.contact {
                                hit(B::StickyReloadDisarmed);
                            }
                            continue;
                        }
                        pulses_in_window += 1;
                        if sticky && pre.sticky() && !po.contact {
                            hit(B::StickyBetween);
                        }
                        let decided = !pre.counter().reached() && m.counter().reached();
                        if decided && pulses_in_window == 1 {
                            hit(B::FirstPulseDecision);
                        }
                        decided_on_last = decided;
                        if bit && po.count == window {
                            hit(B::CountSaturated);
                        }
                        if po.pulses == u32::MAX {
                            hit(B::PulsesWrap);
                        }
                        let (d0, d1) = (pre.density(), m.density());
                        let c = d1.charge();
                        if fire > 1 && c == fire - 1 && d0.armed() {
                            hit(B::FireMinus);
                        }
                        if c == fire && d0.armed() {
                            hit(B::FireAt);
                        }
                        if c == fire + 1 {
                            hit(B::FirePlus);
                        }
                        if rearm > 0 && c == rearm - 1 && !d0.armed() {
                            hit(B::RearmMinus);
                        }
                        if c == rearm && !d0.armed() {
                            hit(B::RearmAt);
                        }
                        if c == rearm + 1 {
                            hit(B::RearmPlus);
                        }
                        if bit && d0.charge() == full {
                            hit(B::ChargeFull);
                        }
                        if !bit && d0.charge() == 0 {
                            hit(B::ChargeEmpty);
                        }
                        if let ChargeLaw::Exponential {
                            charge_shift,
                            discharge_shift,
                        } = s.charge_law
                        {
                            let q = d0.charge();
                            if bit && q < full && (full - q) >> charge_shift == 0 {
                                hit(B::ExpStepFull);
                            }
                            if !bit && q > 0 && q >> discharge_shift == 0 {
                                hit(B::ExpStepEmpty);
                            }
                        }
                        if method == DecisionMethod::Density && !po.register_now && qo.register_now
                        {
                            hit(B::DensityDecision);
                        }
                    }
                    MeasureEvent::Scale { .. } => {
                        kinds[4] = true;
                        if double {
                            hit(B::ScaleError);
                            if po.scale_errors == u8::MAX {
                                hit(B::ScaleErrorsSaturated);
                            }
                        }
                        let half = 1i64 << (s.scale_bits - 1);
                        let (a, b) = (i64::from(po.position), i64::from(qo.position));
                        if (a == half - 1 && b == -half) || (a == -half && b == half - 1) {
                            hit(B::PositionWrap);
                        }
                    }
                    MeasureEvent::PresetPulses(_) => {}
                }
            }
            let mut n = 0;
            for i in 0..5 {
                for j in i + 1..5 {
                    if kinds[i] && kinds[j] {
                        pair_hits[n] += 1;
                    }
                    n += 1;
                }
            }
        }
    }
    let _ = B::Reset;
    for (i, h) in pair_hits.iter().enumerate() {
        bins[pairs_at + i].hits = *h;
    }
    for (i, h) in glitch_hits.iter().enumerate() {
        bins[glitch_at + i].hits = *h;
    }
    Coverage {
        bins,
        cycles: stimulus.total_cycles(),
    }
}
