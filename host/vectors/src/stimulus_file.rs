//! A user's stimulus read from a file, for `tooltouch vectors` and `tooltouch hdl
//! --vectors`: the six input pins clock by clock, or an input event stream.
//!
//! Three formats, told apart by their content:
//! - **VCD** (first token `$…`): any tool's dump holding the six pins, any `$timescale`, any
//!   hierarchy. Pin `p` is the signal named `p` in a scope named `inputs` (the golden
//!   VCD), else `pin_p` (the ports of the generated `tt_frontend`, as in the testbench's
//!   `dut.vcd`), else `p` outside a scope named `outputs` (the shallowest). Clock `k`
//!   takes the pins' values at time `k·P` (the last change at or before it, the golden
//!   VCD's convention); the clocks run from 0 to the file's last time.
//! - **Events** (magic `TTVX`): an input stream ([`binary::read_event_stream`], record by record): the
//!   measurement events, the force events, or both. Measurement events are turned back
//!   into pins ([`pins_from_events`]) so the cycle-level files can be written too.
//! - **Run-length pins** (`stim.hex`, hex words): the testbench's stimulus format
//!   (`tooltouch_hdl_gen::testbench`): a header word `{8'd0, segments}`, then one word
//!   `{pins[7:0], cycles[31:0]}` per segment.
//!
//! The clock period `P`: `--clock-hz`, else the settings file's `[lathe] clock_hz`, else
//! the file's own clock (a golden VCD's `clock_hz` comment, an event stream's tick rate),
//! else [`DEFAULT_CLOCK_HZ`]. A stated clock that differs from the file's own is an error.
//! Every error names the file, the line (text) or byte (binary), and the signal.

use super::binary::{self, InputStream};
use super::vcd::{Declarations, Item, Signal, VcdReader};
use bitvec::prelude::*;
use std::io::{BufRead, BufReader};
use std::path::Path;
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_model::{MeasureConfig, MeasureEvent, TimedEvent};
use tooltouch_plant::stimulus::Stimulus;

/// The FPGA clock when nothing states one: the lathe simulator's default, Hz.
pub const DEFAULT_CLOCK_HZ: u32 = 50_000_000;

/// A stimulus that cannot be read or used; the message names the file and the place.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct StimulusError(pub String);

/// A clock stated by the user, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StatedClock {
    /// Hz.
    pub hz: u32,
    /// Where it was stated, for messages (`--clock-hz`, `[lathe] clock_hz of FILE`).
    pub source: String,
}

/// What a stimulus file holds.
#[derive(Clone, Debug, PartialEq)]
pub enum StimulusFile {
    /// Pins clock by clock (a VCD or a `stim.hex`).
    Pins {
        /// The pins, at the settled clock.
        stimulus: Stimulus,
        /// `"vcd"` or `"stim.hex"`.
        format: &'static str,
    },
    /// An input event stream (boxed: it holds two configurations).
    Events(Box<InputStream>),
}

/// The clock to use: the stated one, else the file's own, else [`DEFAULT_CLOCK_HZ`]; a
/// stated clock that differs from the file's own is an error.
pub fn settle_clock(
    stated: Option<&StatedClock>,
    own: Option<(u32, &str)>,
    file: &str,
) -> Result<u32, StimulusError> {
    let hz = match (stated, own) {
        (Some(s), Some((hz, what))) if s.hz != hz => {
            return Err(StimulusError(format!(
                "{file}: {what} says {hz} Hz, {} says {} Hz",
                s.source, s.hz
            )))
        }
        (Some(s), _) => s.hz,
        (None, Some((hz, _))) => hz,
        (None, None) => DEFAULT_CLOCK_HZ,
    };
    if hz == 0 || 1_000_000_000 % hz != 0 {
        return Err(StimulusError(format!(
            "{file}: clock {hz} Hz: the period 1e9 / clock_hz ns must be a whole number"
        )));
    }
    Ok(hz)
}

/// Reads the stimulus file `path` (see the module documentation).
pub fn read(path: &Path, stated: Option<&StatedClock>) -> Result<StimulusFile, StimulusError> {
    let file = path.display().to_string();
    let f = std::fs::File::open(path).map_err(|e| StimulusError(format!("{file}: {e}")))?;
    read_from(BufReader::with_capacity(1 << 20, f), &file, stated)
}

/// Reads a stimulus from `r` (see the module documentation); `file` names it in errors.
pub fn read_from<R: BufRead>(
    mut r: R,
    file: &str,
    stated: Option<&StatedClock>,
) -> Result<StimulusFile, StimulusError> {
    let file = file.to_string();
    let head = r
        .fill_buf()
        .map_err(|e| StimulusError(format!("{file}: {e}")))?;
    if head.starts_with(&tooltouch_model::wire::MAGIC) {
        let stream =
            binary::read_event_stream(r, &file).map_err(|e| StimulusError(e.to_string()))?;
        settle_clock(
            stated,
            Some((stream.header.tick_hz, "its header's tick rate")),
            &file,
        )?;
        return Ok(StimulusFile::Events(Box::new(stream)));
    }
    let first = head
        .iter()
        .copied()
        .find(|b| !b.is_ascii_whitespace())
        .unwrap_or(b'\n');
    if first == b'$' {
        let reader = VcdReader::new(r, &file).map_err(|e| StimulusError(e.to_string()))?;
        Ok(StimulusFile::Pins {
            stimulus: read_vcd_pins(reader, stated)?,
            format: "vcd",
        })
    } else {
        Ok(StimulusFile::Pins {
            stimulus: read_hex_pins(r, &file, stated)?,
            format: "stim.hex",
        })
    }
}

/// The signal that drives pin `name` (see the module documentation).
pub fn find_pin<'a>(d: &'a Declarations, name: &str) -> Option<&'a Signal> {
    let in_scope = |s: &Signal, scope: &str| s.scope.last().is_some_and(|l| l == scope);
    let port = format!("pin_{name}");
    d.find_in_scope("inputs", name)
        .or_else(|| {
            d.signals
                .iter()
                .filter(|s| s.name == port)
                .min_by_key(|s| s.scope.len())
        })
        .or_else(|| {
            d.signals
                .iter()
                .filter(|s| s.name == name && !in_scope(s, "outputs"))
                .min_by_key(|s| s.scope.len())
        })
}

/// The six pins as a bit array, bit `i` = pin `i` of `pin::NAMES`: the layout of the model's
/// [`Pins`] byte, which stays a plain `u8` in the `no_std` model (the FPGA's pin register).
type PinBundle = BitArr!(for pin::COUNT, in u8, Lsb0);

/// One pin's level while reading a VCD: value, whether x/z, the line of its last change.
#[derive(Clone, Copy, Debug, Default)]
struct Level {
    high: bool,
    unknown: bool,
    known: bool,
    line: usize,
}

fn read_vcd_pins<R: BufRead>(
    mut reader: VcdReader<R>,
    stated: Option<&StatedClock>,
) -> Result<Stimulus, StimulusError> {
    let file = reader.file().to_string();
    let d = reader.declarations().clone();
    let own = d
        .golden_stamp()
        .map(|(_, hz)| (hz, "its `tooltouch … clock_hz` comment"));
    let clock_hz = settle_clock(stated, own, &file)?;
    let period_fs = 1_000_000_000_000_000 / u64::from(clock_hz);
    // Pin bits per code index.
    // The pins each identifier code drives (a bundle: bit i is pin i of `pin::NAMES`).
    let mut bits_of: Vec<PinBundle> = vec![PinBundle::ZERO; d.codes().len()];
    let mut signals: Vec<&Signal> = Vec::with_capacity(pin::COUNT);
    for (i, name) in pin::NAMES.iter().enumerate() {
        let s = find_pin(&d, name).ok_or_else(|| {
            StimulusError(format!(
                "{file}: no signal for pin `{name}` (looked for `{name}` in a scope `inputs`, \
                 `pin_{name}`, and `{name}` outside a scope `outputs`)"
            ))
        })?;
        if s.width != 1 {
            return Err(StimulusError(format!(
                "{file}: line {}: pin `{name}` is signal `{}` of {} bits; a pin is 1 bit",
                s.line,
                s.scope
                    .iter()
                    .chain([&s.name])
                    .cloned()
                    .collect::<Vec<_>>()
                    .join("."),
                s.width
            )));
        }
        if let Some(c) = d.code_index(&s.id) {
            bits_of[c].set(i, true);
        }
        signals.push(s);
    }
    let mut levels = [Level::default(); pin::COUNT];
    let mut stimulus = Stimulus::new(clock_hz);
    let mut next_k = 0u64;
    // Emits clocks `next_k..end` with the current levels.
    let mut emit = |end: u64, levels: &[Level; pin::COUNT], stimulus: &mut Stimulus| {
        if end <= next_k {
            return Ok(());
        }
        let mut bundle = PinBundle::ZERO;
        for (i, l) in levels.iter().enumerate() {
            let name = pin::NAMES[i];
            let time_ns = next_k * period_fs / 1_000_000;
            if !l.known {
                return Err(StimulusError(format!(
                    "{file}: line {}: pin `{name}` has no value at clock {next_k} (time {time_ns} ns): \
                     every pin needs a value from time 0",
                    signals[i].line
                )));
            }
            if l.unknown {
                return Err(StimulusError(format!(
                    "{file}: line {}: pin `{name}` is x or z at clock {next_k} (time {time_ns} ns)",
                    l.line
                )));
            }
            bundle.set(i, l.high);
        }
        stimulus.push(Pins(bundle.into_inner()[0]), end - next_k);
        next_k = end;
        Ok(())
    };
    loop {
        let item = reader
            .next_item()
            .map_err(|e| StimulusError(e.to_string()))?;
        match item {
            None => break,
            Some(Item::Time(t)) => {
                // Clocks whose sampling time k·P is before t see the current levels.
                emit(t.div_ceil(period_fs), &levels, &mut stimulus)?;
            }
            Some(Item::Change(code, v)) => {
                for i in bits_of[code].iter_ones() {
                    levels[i] = Level {
                        high: v.bit(0),
                        unknown: v.unknown,
                        known: true,
                        line: reader.line(),
                    };
                }
            }
        }
    }
    emit(reader.time_fs() / period_fs + 1, &levels, &mut stimulus)?;
    Ok(stimulus)
}

fn read_hex_pins<R: BufRead>(
    r: R,
    file: &str,
    stated: Option<&StatedClock>,
) -> Result<Stimulus, StimulusError> {
    let clock_hz = settle_clock(stated, None, file)?;
    let mut stimulus = Stimulus::new(clock_hz);
    let mut segments: Option<(u64, usize)> = None;
    let mut seen = 0u64;
    for (i, line) in r.lines().enumerate() {
        let n = i + 1;
        let line = line.map_err(|e| StimulusError(format!("{file}: line {n}: {e}")))?;
        let text = line.split("//").next().unwrap_or("").trim();
        if text.is_empty() {
            continue;
        }
        let word = (text.len() <= 10)
            .then(|| u64::from_str_radix(text, 16).ok())
            .flatten()
            .ok_or_else(|| {
                StimulusError(format!(
                    "{file}: line {n}: `{text}` is not a stim.hex word (up to 10 hex digits: \
                     pins[7:0], cycles[31:0]); not a VCD (no `$` keyword) nor an event stream \
                     (no TTVX magic) either"
                ))
            })?;
        // The word's fields, as the testbench slices them: {pins[7:0], cycles[31:0]}.
        let fields = word.view_bits::<Lsb0>();
        let (pins, cycles): (u8, u64) = (fields[32..40].load_le(), fields[..32].load_le());
        match segments {
            None => {
                if pins != 0 {
                    return Err(StimulusError(format!(
                        "{file}: line {n}: the header word `{text}` must be {{8'd0, segments}}"
                    )));
                }
                segments = Some((cycles, n));
            }
            Some((count, header_line)) => {
                seen += 1;
                if seen > count {
                    return Err(StimulusError(format!(
                        "{file}: line {n}: more segments than the {count} of the header (line {header_line})"
                    )));
                }
                if pins.view_bits::<Lsb0>()[pin::COUNT..].any() {
                    return Err(StimulusError(format!(
                        "{file}: line {n}: pins 0x{pins:02x} set bits beyond the six pins ({})",
                        pin::NAMES.join(", ")
                    )));
                }
                if cycles == 0 {
                    return Err(StimulusError(format!(
                        "{file}: line {n}: a segment of 0 cycles"
                    )));
                }
                stimulus.push(Pins(pins), cycles);
            }
        }
    }
    match segments {
        None => Err(StimulusError(format!("{file}: empty: no header word"))),
        Some((count, line)) if seen != count => Err(StimulusError(format!(
            "{file}: line {line}: the header announces {count} segments, the file holds {seen}"
        ))),
        Some(_) => Ok(stimulus),
    }
}

/// The pins that make the cycle-level front end act on exactly `events` (times in clocks):
/// each event's pin changes `latency_cycles` clocks before its time, an index or FES pulse
/// held high for `glitch_cycles + 1` clocks (the filter's minimum), until clock `end`
/// (at least one past the last event). The result is checked by running the front end over
/// it; an event no pins can cause is an error naming its byte in `file` (`offsets`).
pub fn pins_from_events(
    events: &[TimedEvent],
    offsets: &[usize],
    config: &MeasureConfig,
    clock_hz: u32,
    end: u64,
    file: &str,
) -> Result<Stimulus, StimulusError> {
    let latency = u64::from(config.latency_cycles());
    let hold = u64::from(config.settings().glitch_cycles) + 1;
    let at = |i: usize| {
        offsets
            .get(i)
            .map_or_else(|| format!("event {i}"), |o| format!("byte {o} (event {i})"))
    };
    // (clock, pin bit, level), in event order.
    let mut changes: Vec<(u64, u8, bool)> = Vec::with_capacity(events.len() * 2);
    let mut level = [false; pin::COUNT];
    let mut last: [Option<u64>; pin::COUNT] = [None; pin::COUNT];
    for (i, e) in events.iter().enumerate() {
        let Some(c) = e.time.checked_sub(latency) else {
            return Err(StimulusError(format!(
                "{file}: {}: {:?} at clock {} is earlier than the {latency}-clock latency from the pins allows",
                at(i),
                e.event,
                e.time
            )));
        };
        // The pin changes this event needs: (pin index, level, clock).
        let wanted: Vec<(usize, bool, u64)> = match e.event {
            MeasureEvent::Arm(l) => vec![(0, l, c)],
            MeasureEvent::Contact(l) => vec![(1, l, c)],
            MeasureEvent::Index => vec![(2, true, c), (2, false, c + hold)],
            MeasureEvent::Fes => vec![(3, true, c), (3, false, c + hold)],
            MeasureEvent::Scale { a, b } => {
                if a == level[4] && b == level[5] {
                    return Err(StimulusError(format!(
                        "{file}: {}: {:?} at clock {}: the scale pins already hold these levels",
                        at(i),
                        e.event,
                        e.time
                    )));
                }
                [(4, a), (5, b)]
                    .into_iter()
                    .filter(|&(bit, to)| level[bit] != to)
                    .map(|(bit, to)| (bit, to, c))
                    .collect()
            }
            MeasureEvent::PresetPulses(_) => {
                return Err(StimulusError(format!(
                    "{file}: {}: PresetPulses is a test-only event that no pin makes",
                    at(i)
                )))
            }
        };
        for (bit, to, clock) in wanted {
            let name = pin::NAMES[bit];
            if level[bit] == to {
                return Err(StimulusError(format!(
                    "{file}: {}: {:?} at clock {}: pin `{name}` is already {}",
                    at(i),
                    e.event,
                    e.time,
                    if to { "high" } else { "low" }
                )));
            }
            if let Some(prev) = last[bit] {
                if clock < prev + hold {
                    return Err(StimulusError(format!(
                        "{file}: {}: {:?} at clock {}: pin `{name}` would change at clock {clock}, \
                         but not before clock {} after its change at clock {prev} (the glitch \
                         filter passes a level held {hold} clocks; a pulse is high {hold} clocks)",
                        at(i),
                        e.event,
                        e.time,
                        prev + hold
                    )));
                }
            }
            level[bit] = to;
            last[bit] = Some(clock);
            changes.push((clock, 1 << bit, to));
        }
    }
    changes.sort_by_key(|c| c.0);
    let total = end.max(events.last().map_or(0, |e| e.time + 1));
    let mut stimulus = Stimulus::new(clock_hz);
    let mut pins = Pins(0);
    let mut k = 0u64;
    for (clock, bit, to) in changes {
        let clock = clock.min(total);
        stimulus.push(pins, clock - k);
        k = clock;
        pins = pins.with(bit, to);
    }
    stimulus.push(pins, total - k);
    // The pins must give back exactly these events.
    let back = super::events_from_stimulus(&stimulus, config);
    if let Some(i) = (0..events.len().max(back.len())).find(|&i| events.get(i) != back.get(i)) {
        let what = match back.get(i) {
            Some(b) => format!("{:?} at clock {}", b.event, b.time),
            None => "no event".to_string(),
        };
        let want = match events.get(i) {
            Some(e) => format!("{:?} at clock {}", e.event, e.time),
            None => "no event".to_string(),
        };
        return Err(StimulusError(format!(
            "{file}: {}: no pins make the front end act on these events: {want} expected, \
             the pins closest to them give {what} (events of one clock must come in canonical order: arm, \
             contact, index, FES, scale)",
            at(i.min(events.len().saturating_sub(1)))
        )));
    }
    Ok(stimulus)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_become_pins_that_give_them_back() {
        let config = MeasureConfig::default();
        let mut s = Stimulus::new(DEFAULT_CLOCK_HZ);
        s.push(Pins(0), 5);
        s.push(Pins(pin::ARM), 30);
        s.push(Pins(pin::ARM | pin::INDEX | pin::SCALE_A), 10);
        s.push(Pins(pin::ARM | pin::SCALE_A), 10);
        s.push(Pins(pin::ARM | pin::FES | pin::CONTACT), 10);
        s.push(Pins(pin::ARM | pin::CONTACT), 10);
        let events = super::super::events_from_stimulus(&s, &config);
        assert!(events.len() >= 6, "{events:?}");
        let pins = pins_from_events(&events, &[], &config, DEFAULT_CLOCK_HZ, 0, "t").unwrap();
        assert_eq!(super::super::events_from_stimulus(&pins, &config), events);
    }

    #[test]
    fn pulses_too_close_for_the_filter_are_named() {
        let config = MeasureConfig::default();
        let l = u64::from(config.latency_cycles());
        let fes = |time| TimedEvent {
            time,
            event: MeasureEvent::Fes,
        };
        let e = pins_from_events(
            &[fes(l + 10), fes(l + 12)],
            &[40, 50],
            &config,
            DEFAULT_CLOCK_HZ,
            0,
            "e.ttv",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("e.ttv: byte 50 (event 1)") && e.contains("`fes`"),
            "{e}"
        );
    }
}
