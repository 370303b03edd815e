//! The HAL component's generated parts, from the model's tables: `host/linuxcnc/hal/tooltouch_hal.h`
//! whole, and in `host/linuxcnc/hal/tooltouch.comp` the `adc-*` input pins
//! ([`AdcChannel::ALL`]), the measurement output pins ([`MeasureOutputs::fields`] order,
//! HAL names, types and descriptions from [`measure_pin`], with `latched_position` and the
//! alarm bit `fault` beside), the sample's pin array and the output pins' assignments. Both files are committed; the drift test below fails when they
//! differ from what this module writes, and `TOOLTOUCH_BLESS=1 cargo test -p tooltouch-linuxcnc
//! --lib component` rewrites them.

use tooltouch_model::force::sampling::{AdcChannel, ADC_MAX, ADC_MID};
use tooltouch_model::MeasureOutputs;

/// A HAL pin's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HalType {
    /// `bit`: 0/1.
    Bit,
    /// `s32`.
    S32,
    /// `u32`.
    U32,
}

impl HalType {
    /// The type as halcompile writes it.
    pub fn name(self) -> &'static str {
        match self {
            HalType::Bit => "bit",
            HalType::S32 => "s32",
            HalType::U32 => "u32",
        }
    }

    /// The type's letter in a `sampler`/`streamer` `cfg=` string.
    pub fn cfg(self) -> char {
        match self {
            HalType::Bit => 'b',
            HalType::S32 => 's',
            HalType::U32 => 'u',
        }
    }
}

/// The output pin of one measurement output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeasurePin {
    /// The pin's name in the `.comp` (halcompile drops a trailing `_` and turns `_` into
    /// `-` for the HAL name: `count_` is `tooltouch.0.count`).
    pub comp_name: &'static str,
    /// The pin's type.
    pub hal_type: HalType,
    /// The pin's description.
    pub doc: &'static str,
}

impl MeasurePin {
    /// The HAL pin name (`contact-filtered`).
    pub fn hal_name(&self) -> String {
        self.comp_name.trim_end_matches('_').replace('_', "-")
    }
}

/// The pin of the measurement output `field` (a [`MeasureOutputs::fields`] name); `None`
/// for a field the component has no pin for yet (the tests fail then).
pub fn measure_pin(field: &str) -> Option<MeasurePin> {
    use HalType::{Bit, S32, U32};
    let (comp_name, hal_type, doc) = match field {
        "armed" => ("armed", Bit, "a measurement cycle is running"),
        "contact" => ("contact_filtered", Bit, "the filtered contact level"),
        "register_now" => (
            "register_now",
            Bit,
            "position reached, register now (to motion.probe-input); held until the next arm",
        ),
        "decision_position" => (
            "decision_position",
            S32,
            "scale position latched at the decision, counts",
        ),
        "first_contact" => (
            "first_contact",
            Bit,
            "a contact edge has been seen since arm",
        ),
        "first_contact_position" => (
            "first_contact_position",
            S32,
            "scale position latched at the first contact, counts",
        ),
        "position" => (
            "position",
            S32,
            "live scale position in the model, counts (scale_bits, sign-extended)",
        ),
        "scale_errors" => (
            "scale_errors",
            U32,
            "illegal scale transitions, saturating at 255",
        ),
        "count" => ("count_", U32, "contact pulses in the current window"),
        "last_window_count" => (
            "last_window_count",
            U32,
            "contact pulses in the previous window",
        ),
        "charge" => ("charge", U32, "density detector charge, LSBs"),
        "density_armed" => ("density_armed", Bit, "the density detector is armed"),
        "density_fired" => (
            "density_fired",
            Bit,
            "the density detector has fired since arm",
        ),
        "revolutions" => (
            "revolutions",
            U32,
            "index pulses since arm, saturating at 65535",
        ),
        "pulses" => ("pulses", U32, "FES pulses since arm, wrapping at 2^32"),
        "confirmed" => (
            "confirmed",
            Bit,
            "the decision was confirmed by the contact pattern after it; accept a reading only with confirmed high and fault low",
        ),
        "faults" => (
            "faults",
            U32,
            "fault conditions latched since arm, one bit each: 1 contact_at_arm, 2 pulses_lost, 4 index_missing, 8 scale_error, 16 no_decision, 32 fes_timeout, 64 unconfirmed",
        ),
        _ => return None,
    };
    Some(MeasurePin {
        comp_name,
        hal_type,
        doc,
    })
}

/// The measurement output after which the component adds `latched_position` (the
/// decision position in machine units).
const LATCHED_AFTER: &str = "decision_position";

/// The measurement output after which the component adds `fault`, the bit `faults != 0`
/// for the CNC's alarm input.
const FAULT_AFTER: &str = "faults";

/// The `fault` pin's declaration.
const FAULT_PIN: &str = "pin out bit fault \"a fault is latched (faults != 0): to the CNC's alarm input; retract and re-measure\";\n";

/// The model's measurement output names, in order.
fn measure_fields() -> [&'static str; MeasureOutputs::FIELD_COUNT] {
    MeasureOutputs::default().fields().map(|(name, _)| name)
}

/// Every measurement output with its pin, in the model's order; an error names a field
/// without a pin.
pub fn measure_pins() -> Result<Vec<(&'static str, MeasurePin)>, String> {
    measure_fields()
        .into_iter()
        .map(|f| {
            measure_pin(f)
                .map(|p| (f, p))
                .ok_or_else(|| format!("the measurement output `{f}` has no HAL pin"))
        })
        .collect()
}

/// The `.comp` name of channel `ch`'s input pin (`adc_volts_u`).
pub fn adc_pin(ch: AdcChannel) -> String {
    format!("adc_{}", ch.name())
}

/// Words separated by spaces, wrapped into C comment lines of at most 90 columns: the
/// first line starts with `first`, the others with ` * `.
fn comment(first: &str, words: &str) -> String {
    let mut out = String::new();
    let mut line = first.to_string();
    for w in words.split(' ') {
        if line.len() + 1 + w.len() > 90 && line.len() > 3 {
            out.push_str(line.trim_end());
            out.push('\n');
            line = " *".to_string();
        }
        line.push(' ');
        line.push_str(w);
    }
    out.push_str(&line);
    out.push('\n');
    out
}

/// The whole `tooltouch_hal.h`.
pub fn hal_header() -> Result<String, String> {
    let pins = measure_pins()?;
    let mut h = String::from(
        "/* tooltouch_hal.h: the C ABI's output structures as plain words, for tooltouch.comp.\n \
         * halcompile defines a macro for every pin name, and many pins are named as the model's\n \
         * fields (armed, position, wear_alarm, ...); these helpers read the fields before those\n \
         * macros exist (the component includes this header first). */\n\
         #ifndef TOOLTOUCH_HAL_H\n#define TOOLTOUCH_HAL_H\n\n#include \"tooltouch.h\"\n\n",
    );
    let names: Vec<&str> = pins.iter().map(|(f, _)| *f).collect();
    h.push_str(&comment(
        &format!(
            "/* The {} measurement outputs in the model's order (TT_OUTPUT_COUNT):",
            names.len()
        ),
        &format!(
            "{}; flags 0/1, positions sign-extended. */",
            names.join(" ")
        ),
    ));
    h.push_str(
        "static inline void tt_hal_measure_words(const TtMeasureOutputs *m, int64_t w[TT_OUTPUT_COUNT]) {\n",
    );
    for (i, f) in names.iter().enumerate() {
        h.push_str(&format!("    w[{i}] = m->{f};\n"));
    }
    h.push_str("}\n\n");
    h.push_str(FORCE_WORDS);
    let n = AdcChannel::COUNT;
    let channel_names: Vec<&str> = AdcChannel::ALL.iter().map(|c| c.name()).collect();
    h.push_str(&comment(
        "/* A force event of `kind` with `on` and the condition set `set`; for a sample the",
        &format!(
            "{} codes `adc` in the model's channel order ({}), each clamped to {ADC_MAX}. */",
            number(n),
            channel_names.join(" ")
        ),
    ));
    h.push_str(&format!(
        "static inline TtForceEvent tt_hal_force_event(uint8_t kind, uint8_t on, uint8_t set, const uint32_t adc[{n}]) {{\n\
         \x20   TtForceEvent e;\n\
         \x20   uint16_t c[{n}];\n\
         \x20   int i;\n\
         \x20   for (i = 0; i < {n}; i++) c[i] = (uint16_t)(adc[i] > {ADC_MAX} ? {ADC_MAX} : adc[i]);\n\
         \x20   e.kind = kind;\n\
         \x20   e.on = on;\n\
         \x20   e.conditions = set;\n"
    ));
    for (i, ch) in AdcChannel::ALL.iter().enumerate() {
        h.push_str(&format!("    e.adc.{} = c[{i}];\n", ch.field()));
    }
    h.push_str("    return e;\n}\n\n");
    h.push_str(MEASURE_EVENT);
    Ok(h)
}

fn number(n: usize) -> String {
    match n {
        8 => "eight".into(),
        n => n.to_string(),
    }
}

/// The force words: the model has no list of its force outputs (yet); written here once.
const FORCE_WORDS: &str = "/* Number of force output words. */
#define TT_HAL_FORCE_WORDS 15

/* The 15 force outputs: override_pct saturated fast_estimate control_enabled identifying
 * identified wear_over wear_alarm bad_events, then the I32F32 bits of force_estimate
 * force_measured wear_power wear_allowed coulomb, then wear_blind. */
static inline void tt_hal_force_words(const TtForceOutputs *f, int64_t w[TT_HAL_FORCE_WORDS]) {
    w[0] = f->override_pct;
    w[1] = f->saturated;
    w[2] = f->fast_estimate;
    w[3] = f->control_enabled;
    w[4] = f->identifying;
    w[5] = f->identified;
    w[6] = f->wear_over;
    w[7] = f->wear_alarm;
    w[8] = f->bad_events;
    w[9] = f->force_estimate;
    w[10] = f->force_measured;
    w[11] = f->wear_power;
    w[12] = f->wear_allowed;
    w[13] = f->coulomb;
    w[14] = f->wear_blind;
}

";

const MEASURE_EVENT: &str = "/* A measurement event at `time` (the component's clock: one tick per servo period). */
static inline TtMeasureEvent tt_hal_measure_event(uint8_t kind, uint8_t level, uint8_t a, uint8_t b, uint64_t time) {
    TtMeasureEvent e;
    e.kind = kind;
    e.level = level;
    e.scale_a = a;
    e.scale_b = b;
    e.pulses = 0;
    e.time = time;
    return e;
}

#endif /* TOOLTOUCH_HAL_H */
";

/// The `adc_*` pin declarations.
fn adc_pin_lines() -> String {
    AdcChannel::ALL
        .iter()
        .map(|&ch| {
            let polarity = if ch.bipolar() {
                format!("bipolar around {ADC_MID}")
            } else {
                "unipolar".into()
            };
            format!(
                "pin in u32 {} \"{}, 12-bit ADC code ({polarity})\";\n",
                adc_pin(ch),
                ch.quantity()
            )
        })
        .collect()
}

/// The measurement output pin declarations, with their section comment.
fn measure_pin_lines(pins: &[(&str, MeasurePin)]) -> String {
    let mut s = format!(
        "// ---- measurement outputs (the model's {} fields)\n",
        pins.len()
    );
    for (field, p) in pins {
        s.push_str(&format!(
            "pin out {} {} \"{}\";\n",
            p.hal_type.name(),
            p.comp_name,
            p.doc
        ));
        if *field == LATCHED_AFTER {
            s.push_str(
                "pin out float latched_position \"decision-position times position-scale, machine units\";\n",
            );
        }
        if *field == FAULT_AFTER {
            s.push_str(FAULT_PIN);
        }
    }
    s
}

/// The sample's pin array in `force_event`.
fn adc_array_line() -> String {
    let pins: Vec<String> = AdcChannel::ALL.iter().map(|&c| adc_pin(c)).collect();
    format!(
        "    uint32_t adc[{}] = {{{}}};\n",
        AdcChannel::COUNT,
        pins.join(", ")
    )
}

/// The measurement output pins' assignments from the words `w`.
fn measure_assignments(pins: &[(&str, MeasurePin)]) -> String {
    let mut s = String::new();
    for (i, (field, p)) in pins.iter().enumerate() {
        s.push_str(&format!("    {} = w[{i}];\n", p.comp_name));
        if *field == LATCHED_AFTER {
            s.push_str(&format!(
                "    latched_position = w[{i}] * position_scale;\n"
            ));
        }
        if *field == FAULT_AFTER {
            s.push_str(&format!("    fault = w[{i}] != 0;\n"));
        }
    }
    s
}

/// Replaces the text between the end of `start` and the beginning of `end` (both once in
/// `text`, in that order) with `with`.
fn replace_between(text: &str, start: &str, end: &str, with: &str) -> Result<String, String> {
    let a = text
        .find(start)
        .ok_or_else(|| format!("`{}` not found", start.trim_end()))?
        + start.len();
    let b = a + text[a..].find(end).ok_or_else(|| {
        format!(
            "`{}` not found after `{}`",
            end.trim_end(),
            start.trim_end()
        )
    })?;
    Ok(format!("{}{with}{}", &text[..a], &text[b..]))
}

/// `comp` (the text of `tooltouch.comp`) with its generated parts written from the model's
/// tables; the rest is kept as it is.
pub fn hal_component(comp: &str) -> Result<String, String> {
    let pins = measure_pins()?;
    let c = replace_between(
        comp,
        "// ---- force-path inputs: the ADC codes of the period's sample and the CNC's commands\n",
        "pin in bit force_control ",
        &adc_pin_lines(),
    )?;
    let c = replace_between(
        &c,
        "pin in u32 conditions \"cutting-condition set of the wear monitor\";\n\n",
        "// ---- force outputs",
        &measure_pin_lines(&pins),
    )?;
    let c = replace_between(
        &c,
        "static void force_event(struct __comp_state *__comp_inst, uint8_t kind, uint8_t on, uint8_t set) {\n",
        "    TtForceEvent e = ",
        &adc_array_line(),
    )?;
    replace_between(
        &c,
        "    tt_hal_measure_words(&m, w);\n",
        "    tt_hal_force_words(&f, v);\n",
        &measure_assignments(&pins),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn hal_dir() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("hal")
    }

    /// Compares `generated` with the committed `file` (rewriting it first under
    /// `TOOLTOUCH_BLESS`), naming the first line that differs.
    fn check(file: &str, generated: &str) {
        let path = hal_dir().join(file);
        if std::env::var_os("TOOLTOUCH_BLESS").is_some() {
            std::fs::write(&path, generated).expect("writing the generated file");
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        if committed != generated {
            let line = committed
                .lines()
                .zip(generated.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(committed.lines().count().min(generated.lines().count()));
            panic!(
                "{} differs from what hal::component writes from the model, from line {}:\n  \
                 committed: {:?}\n  generated: {:?}\n\
                 rewrite it with TOOLTOUCH_BLESS=1 cargo test -p tooltouch-linuxcnc --lib component",
                path.display(),
                line + 1,
                committed.lines().nth(line).unwrap_or("<end>"),
                generated.lines().nth(line).unwrap_or("<end>")
            );
        }
    }

    #[test]
    fn the_committed_header_is_what_the_model_gives() {
        check("tooltouch_hal.h", &hal_header().unwrap());
    }

    #[test]
    fn the_committed_component_is_what_the_model_gives() {
        let comp = std::fs::read_to_string(hal_dir().join("tooltouch.comp")).unwrap();
        check("tooltouch.comp", &hal_component(&comp).unwrap());
    }

    #[test]
    fn every_measurement_output_has_one_pin_and_the_samplers_follow_them() {
        let pins = measure_pins().unwrap();
        let sampler: Vec<(String, char)> = pins
            .iter()
            .map(|(_, p)| (p.hal_name(), p.hal_type.cfg()))
            .collect();
        let listed: Vec<(String, char)> = super::super::files::MEASURE_PINS
            .iter()
            .map(|&(n, t)| (n.to_string(), t))
            .collect();
        // The model's outputs, then the alarm bit beside them.
        assert_eq!(sampler[..], listed[..sampler.len()]);
        assert_eq!(listed[sampler.len()..], [("fault".to_string(), 'b')]);
        assert!(FAULT_PIN.starts_with("pin out bit fault "));
    }

    #[test]
    fn the_streamer_drives_the_adc_pins_in_the_model_s_order() {
        use super::super::period::PeriodInputs;
        let adc: Vec<String> = AdcChannel::ALL
            .iter()
            .map(|&c| adc_pin(c).replace('_', "-"))
            .collect();
        let at = PeriodInputs::PINS
            .iter()
            .position(|p| p.starts_with("adc-"))
            .unwrap();
        assert_eq!(PeriodInputs::PINS[at..at + AdcChannel::COUNT], adc[..]);
    }

    /// The physical meaning of one channel, in the C the component compiles: the ABI's
    /// field `amps[0]` (the phase current i_u) comes from the pin `adc-amps-u`.
    #[test]
    fn the_phase_current_u_pin_feeds_the_abi_s_amps_0() {
        let header = hal_header().unwrap();
        let i = header
            .lines()
            .find_map(|l| l.strip_prefix("    e.adc.amps[0] = c[")?.strip_suffix("];"))
            .unwrap();
        let array = adc_array_line();
        let pins: Vec<&str> = array
            .split_once('{')
            .unwrap()
            .1
            .trim_end_matches("};\n")
            .split(", ")
            .collect();
        assert_eq!(pins[i.parse::<usize>().unwrap()], "adc_amps_u");
        assert_eq!(i, "6", "i_u is word 6 of a sample (the wire order)");
    }
}
