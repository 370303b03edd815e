//! The test kit reaches what it promises: over many seeded draws, every profile's strategy
//! validates, reaches every enum variant, and reaches both ends of every field's range (the
//! profile's, and the valid range's where the profile draws wide), so a field left at one
//! value by a forgotten generator range fails here.

use super::*;
use std::collections::BTreeSet;
use std::format;
use std::string::String;
use std::vec::Vec;

const DRAWS: u64 = 3000;

/// What the draws reached: for each named quantity, the set of values seen (coarse).
#[derive(Default)]
struct Seen {
    hits: BTreeSet<String>,
}

impl Seen {
    fn hit(&mut self, what: &str, value: impl core::fmt::Debug) {
        self.hits.insert(format!("{what}={value:?}"));
    }

    /// Records which end of `span` (per-mille of `lo..=hi`, at least `floor`) `value` is.
    fn ends(&mut self, what: &str, value: u32, span: (u32, u32), range: (u32, u32), floor: u32) {
        for permille in [span.0, span.1] {
            if value == per_mille(permille, range.0, range.1).max(floor) {
                self.hit(&format!("{what}_permille"), permille);
            }
        }
    }
}

/// The names of the outcomes `profile` must reach.
fn expected(p: &MeasureProfile) -> Vec<String> {
    let mut e = Vec::new();
    let mut ends = |what: &str, span: (u32, u32), valid: (u32, u32)| {
        for v in [span.0, span.1] {
            e.push(format!("{what}={v:?}"));
        }
        if p.wide_percent > 0 {
            for v in [valid.0, valid.1] {
                e.push(format!("{what}={v:?}"));
            }
        }
    };
    let w8 = |s: (u8, u8)| (u32::from(s.0), u32::from(s.1));
    let w16 = |s: (u16, u16)| (u32::from(s.0), u32::from(s.1));
    let v = &MeasureProfile::FULL;
    ends(
        "pulses_per_rev",
        w16(p.pulses_per_rev),
        w16(v.pulses_per_rev),
    );
    ends("window_revs", w8(p.window_revs), w8(v.window_revs));
    ends("charge_bits", w8(p.charge_bits), w8(v.charge_bits));
    ends("glitch_cycles", w8(p.glitch_cycles), w8(v.glitch_cycles));
    ends("scale_bits", w8(p.scale_bits), w8(v.scale_bits));
    // Derived fields: their per-mille ends, seen through the quantity they scale.
    for what in ["i_def", "charge_step", "discharge_step", "fire", "rearm"] {
        let span = match what {
            "i_def" => p.i_def_permille,
            "charge_step" | "discharge_step" => p.step_permille,
            "fire" => p.fire_permille,
            _ => p.rearm_permille,
        };
        e.push(format!("{what}_permille={:?}", span.0));
        e.push(format!("{what}_permille={:?}", span.1));
    }
    if p.i_def_cap.0 < u32::MAX {
        e.push(String::from("i_def_capped=true"));
    }
    for shift in ["charge_shift", "discharge_shift"] {
        e.push(format!("{shift}={:?}", p.shift.0));
        e.push(format!("{shift}={:?}", p.shift.1.min(p.charge_bits.1)));
    }
    for m in METHODS {
        e.push(format!("method={m:?}"));
    }
    for r in CONTACT_RULES {
        e.push(format!("contact_rule={r:?}"));
    }
    e.push(String::from("law=Linear"));
    e.push(String::from("law=Exponential"));
    e
}

fn record(seen: &mut Seen, p: &MeasureProfile, s: &MeasureSettings) {
    seen.hit("pulses_per_rev", u32::from(s.pulses_per_rev));
    seen.hit("window_revs", u32::from(s.window_revs));
    seen.hit("charge_bits", u32::from(s.charge_bits));
    seen.hit("glitch_cycles", u32::from(s.glitch_cycles));
    seen.hit("scale_bits", u32::from(s.scale_bits));
    seen.hit("method", s.method);
    seen.hit("contact_rule", s.contact_rule);
    let window = u32::from(s.pulses_per_rev) * u32::from(s.window_revs);
    let full = (1u32 << s.charge_bits) - 1;
    seen.ends("i_def", s.i_def, p.i_def_permille, (0, window - 1), 0);
    if s.i_def == p.i_def_cap.0 {
        seen.hit("i_def_capped", true);
    }
    seen.ends("fire", s.fire_threshold, p.fire_permille, (1, full), 0);
    seen.ends(
        "rearm",
        s.rearm_threshold,
        p.rearm_permille,
        (0, s.fire_threshold - 1),
        0,
    );
    match s.charge_law {
        ChargeLaw::Linear {
            charge_step,
            discharge_step,
        } => {
            seen.hits.insert(String::from("law=Linear"));
            seen.ends("charge_step", charge_step, p.step_permille, (0, full), 1);
            seen.ends(
                "discharge_step",
                discharge_step,
                p.step_permille,
                (0, full),
                1,
            );
        }
        ChargeLaw::Exponential {
            charge_shift,
            discharge_shift,
        } => {
            seen.hits.insert(String::from("law=Exponential"));
            seen.hit("charge_shift", charge_shift);
            seen.hit("discharge_shift", discharge_shift);
        }
    }
}

#[test]
fn every_profile_validates_and_reaches_every_variant_and_range_end() {
    for (name, profile) in MeasureProfile::ALL {
        let strategy = measure_settings(&profile);
        let mut runner = seeded_runner(0x7e57_c0de);
        let mut seen = Seen::default();
        for _ in 0..DRAWS {
            let s = strategy.new_tree(&mut runner).unwrap().current();
            if let Err(e) = s.validate() {
                panic!("{name}: invalid draw {s:?}: {e}");
            }
            record(&mut seen, &profile, &s);
        }
        let missing: Vec<String> = expected(&profile)
            .into_iter()
            .filter(|e| !seen.hits.contains(e))
            .collect();
        assert!(missing.is_empty(), "{name} never drew {missing:?}");
    }
}

#[test]
fn seeded_draws_are_reproducible_and_differ_between_seeds() {
    let p = MeasureProfile::HDL_COSIM;
    assert_eq!(draw_measure(&p, 5), draw_measure(&p, 5));
    let distinct: BTreeSet<String> = (0..32)
        .map(|seed| format!("{:?}", draw_measure(&p, seed)))
        .collect();
    assert!(distinct.len() > 24, "{} distinct of 32", distinct.len());
}

#[test]
fn cases_reads_the_default_without_the_variable() {
    if std::env::var("TOOLTOUCH_CASES").is_err() {
        assert_eq!(cases(17), 17);
    }
}
