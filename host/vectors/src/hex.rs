//! `$readmemh` vectors for the generated testbench: the run-length stimulus and the
//! golden cycle model's response, both run-length encoded so a long, mostly quiet
//! scenario stays a small file (formats: `tooltouch_hdl_gen::testbench`).

use bitvec::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;
use tooltouch_hdl_gen::{output_fields, output_values, outputs_width, MAX_CYCLES, STIM_WORD_BITS};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureOutputs};
use tooltouch_plant::stimulus::{Segment, Stimulus};

use crate::{clock_through_to_end, watchdog_expires_at};

/// Why a stimulus could not be written as testbench vectors.
#[derive(Debug, thiserror::Error)]
pub enum HexError {
    /// The stimulus cannot be written as testbench vectors.
    #[error("stimulus: {0}")]
    Stimulus(String),
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

/// Result alias of this module.
pub type Result<T> = std::result::Result<T, HexError>;

fn io_err(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> HexError {
    let path = path.into();
    move |source| HexError::Io { path, source }
}

/// Testbench memory depth when neither a depth nor `--vectors` is given, words.
pub const DEFAULT_DEPTH: usize = 1 << 16;

/// The testbench vectors of one scenario.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Vectors {
    /// Text of `stim.hex`.
    pub stim_hex: String,
    /// Text of `expect.hex`.
    pub expect_hex: String,
    /// Words in `stim.hex`, header included.
    pub stim_words: usize,
    /// Words in `expect.hex`, header included.
    pub expect_words: usize,
    /// Clock cycles of the scenario.
    pub cycles: u64,
    /// The model's outputs after the last clock.
    pub final_outputs: MeasureOutputs,
}

/// A `$readmemh` word built field by field, most significant bit first (the order of the
/// testbench's `{cycle, fields…}` concatenation), printed as hex digits.
struct Word {
    bits: BitVec<u8, Msb0>,
}

impl Word {
    fn with_capacity(n: u32) -> Self {
        Word {
            bits: BitVec::with_capacity(n as usize),
        }
    }
    /// Appends the `width` low bits of `value` (`width <= 64`).
    fn push(&mut self, value: u64, width: u32) {
        let start = self.bits.len();
        self.bits.resize(start + width as usize, false);
        if width > 0 {
            self.bits[start..].store_be(value);
        }
    }
    /// Appends `width` zero bits.
    fn zeros(&mut self, width: u32) {
        let len = self.bits.len() + width as usize;
        self.bits.resize(len, false);
    }
    /// Hex digits, zeros on the left up to a whole digit, then a newline.
    fn write_hex(&self, out: &mut String) {
        let pad = (4 - self.bits.len() % 4) % 4;
        let mut padded: BitVec<u8, Msb0> = BitVec::repeat(false, pad);
        padded.extend_from_bitslice(&self.bits);
        for digit in padded.chunks(4) {
            out.push(char::from_digit(digit.load_be::<u32>(), 16).unwrap_or('0'));
        }
        out.push('\n');
    }
}

/// Output values of every field, in [`output_fields`] order.
type OutputValues = [u64; MeasureOutputs::FIELD_COUNT];

/// The expected response of a run: one `(cycle, outputs)` entry for clock 0 and for every
/// later clock after which an output changed, and the front end after the last clock.
type Response = (Vec<(u64, OutputValues)>, FrontEnd);

/// Runs the golden cycle model over `stimulus` and writes both vector files.
///
/// The model is clocked only where it can change: within a segment, once the front end
/// [is settled](FrontEnd::is_settled) (the pins have passed the synchronizers and the
/// glitch filter) no later clock of the segment changes a register, so the rest of the
/// segment is skipped; and the outputs are read only after a clock whose edges the kernel
/// acted on (nothing else changes them). The files are byte for byte those of clocking
/// every cycle ([`FrontEnd::clock`] once per clock), which the tests keep as reference.
///
/// Errors: an empty stimulus, or one longer than [`MAX_CYCLES`] clocks (the testbench's
/// cycle field and loop counter are 32-bit signed integers).
pub fn golden_vectors(config: &MeasureConfig, stimulus: &Stimulus) -> Result<Vectors> {
    golden_vectors_with(config, stimulus, settled_response)
}

/// [`golden_vectors`] with the expected response computed by `response`.
fn golden_vectors_with(
    config: &MeasureConfig,
    stimulus: &Stimulus,
    response: fn(&MeasureConfig, &[&Segment]) -> Response,
) -> Result<Vectors> {
    let cycles = stimulus.total_cycles();
    if cycles == 0 {
        return Err(HexError::Stimulus(
            "the stimulus has no clock cycles".into(),
        ));
    }
    if cycles > MAX_CYCLES {
        return Err(HexError::Stimulus(format!(
            "{cycles} clock cycles is more than the testbench's limit of {MAX_CYCLES}"
        )));
    }
    // Stimulus: one word per segment.
    let segments: Vec<&Segment> = stimulus.segments.iter().filter(|s| s.cycles > 0).collect();
    let mut stim_hex = String::with_capacity((segments.len() + 1) * 11);
    let mut word = Word::with_capacity(STIM_WORD_BITS);
    word.push(0, STIM_WORD_BITS - 32);
    word.push(segments.len() as u64, 32);
    word.write_hex(&mut stim_hex);
    for s in &segments {
        let mut word = Word::with_capacity(STIM_WORD_BITS);
        word.push(u64::from(s.pins.0), STIM_WORD_BITS - 32);
        word.push(u64::from(s.cycles), 32);
        word.write_hex(&mut stim_hex);
    }

    // Expected response: one word per clock after which an output changed.
    let fields = output_fields(config);
    let width = outputs_width(config);
    let (entries, fe) = response(config, &segments);
    let mut expect_hex = String::with_capacity((entries.len() + 1) * (width as usize / 4 + 10));
    let mut header = Word::with_capacity(width + 32);
    header.push(entries.len() as u64, 32);
    header.zeros(width);
    header.write_hex(&mut expect_hex);
    for (cycle, values) in &entries {
        let mut word = Word::with_capacity(width + 32);
        word.push(*cycle, 32);
        for (v, f) in values.iter().zip(fields.iter()) {
            word.push(*v, f.width);
        }
        word.write_hex(&mut expect_hex);
    }
    Ok(Vectors {
        stim_hex,
        expect_hex,
        stim_words: segments.len() + 1,
        expect_words: entries.len() + 1,
        cycles,
        final_outputs: fe.outputs(),
    })
}

/// The expected response, clocking the model only until it settles in each segment, and
/// at the FES watchdog's expiry (see [`golden_vectors`]).
fn settled_response(config: &MeasureConfig, segments: &[&Segment]) -> Response {
    let mut entries: Vec<(u64, OutputValues)> = Vec::new();
    // Clock 0 always gives an entry: the reset outputs, which are those after clock 0 (no
    // edge can be detected there), whether clock 0 is clocked or skipped as settled.
    let reset = output_values(config, &FrontEnd::new(config).outputs());
    entries.push((0, reset));
    let mut last = reset;
    let mut stimulus = Stimulus::new(1);
    for s in segments {
        stimulus.push(s.pins, u64::from(s.cycles));
    }
    let (fe, _) = clock_through_to_end(&stimulus, config, |k, _, fe, edges| {
        if !edges.is_empty() || watchdog_expires_at(fe, k) {
            let values = output_values(config, &fe.outputs());
            if values != last {
                entries.push((k, values));
                last = values;
            }
        }
    });
    (entries, fe)
}

/// Writes `stim.hex` and `expect.hex` into `dir`.
pub fn write_vectors(dir: &std::path::Path, v: &Vectors) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    for (name, text) in [
        (tooltouch_hdl_gen::STIM_HEX, &v.stim_hex),
        (tooltouch_hdl_gen::EXPECT_HEX, &v.expect_hex),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io_err(&p))?;
    }
    Ok(())
}

/// A one-line description of a mismatch position for reports: which output fields of
/// the expected word differ. Used by tests of the encoder.
pub fn describe_word(config: &MeasureConfig, word_hex: &str) -> Option<String> {
    let width = outputs_width(config) + 32;
    let digits = width.div_ceil(4) as usize;
    if word_hex.len() != digits {
        return None;
    }
    let mut bits: BitVec<u8, Msb0> = BitVec::with_capacity(digits * 4);
    for c in word_hex.chars() {
        let at = bits.len();
        bits.resize(at + 4, false);
        bits[at..].store_be(c.to_digit(16)?);
    }
    let bits = &bits[bits.len() - width as usize..];
    let take = |from: usize, w: u32| -> u64 {
        let field = &bits[from..from + w as usize];
        if field.is_empty() {
            0
        } else {
            field.load_be()
        }
    };
    let mut out = format!("cycle {}", take(0, 32));
    let mut at = 32usize;
    for f in output_fields(config) {
        let _ = write!(out, " {}=0x{:x}", f.name, take(at, f.width));
        at += f.width as usize;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::frontend::{pin, Pins};

    #[test]
    fn words_round_trip_through_describe() {
        let c = MeasureConfig::default();
        let mut s = Stimulus::new(50_000_000);
        s.push(Pins(pin::ARM), 20);
        s.push(Pins(pin::ARM | pin::SCALE_B), 20);
        let v = golden_vectors(&c, &s).unwrap();
        assert_eq!(v.stim_hex.lines().next(), Some("0000000002"));
        assert_eq!(v.stim_hex.lines().nth(2), Some("2100000014"));
        // Armed after clock 7 (latency 3 + 4); position -1 after clock 27.
        let lines: Vec<&str> = v.expect_hex.lines().collect();
        assert_eq!(lines.len(), v.expect_words);
        let first = describe_word(&c, lines[1]).unwrap();
        assert!(first.starts_with("cycle 0 armed=0x0"), "{first}");
        let armed = describe_word(&c, lines[2]).unwrap();
        assert!(armed.starts_with("cycle 7 armed=0x1"), "{armed}");
        let moved = describe_word(&c, lines[3]).unwrap();
        assert!(
            moved.contains("cycle 27 ") && moved.contains(" position=0xffffff "),
            "{moved}"
        );
        assert_eq!(v.final_outputs.position, -1);
    }

    /// The reference: the model clocked on every cycle, the outputs compared after each.
    fn per_cycle_response(config: &MeasureConfig, segments: &[&Segment]) -> Response {
        let mut fe = FrontEnd::new(config);
        let mut entries = Vec::new();
        let mut last: Option<OutputValues> = None;
        let mut k: u64 = 0;
        for s in segments {
            for _ in 0..s.cycles {
                fe.clock(s.pins);
                let values = output_values(config, &fe.outputs());
                if last != Some(values) {
                    entries.push((k, values));
                    last = Some(values);
                }
                k += 1;
            }
        }
        (entries, fe)
    }

    #[test]
    fn skipping_settled_clocks_writes_the_per_cycle_files_byte_for_byte() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        let mut configs = vec![MeasureConfig::default()];
        configs.extend((0..4).map(|_| tooltouch_plant::random::random_config(&mut rng)));
        for (i, config) in configs.iter().enumerate() {
            for stretch in [1, 40, 3000] {
                // Random pins with glitches; then some segments held far longer, so that the
                // model settles and the rest of those segments is skipped.
                let short =
                    tooltouch_plant::random::random_stimulus(&mut rng, config, 50_000_000, 4_000);
                let mut s = Stimulus::new(50_000_000);
                if i % 2 == 1 {
                    s.push(Pins(pin::ARM | pin::FES), 1); // not settled at clock 0
                }
                for seg in &short.segments {
                    let hold = if rng.random_bool(0.05) { stretch } else { 1 };
                    s.push(seg.pins, u64::from(seg.cycles) * hold);
                }
                let fast = golden_vectors(config, &s).unwrap();
                let reference = golden_vectors_with(config, &s, per_cycle_response).unwrap();
                assert_eq!(
                    fast, reference,
                    "configuration {i}, stretch {stretch}: the files differ"
                );
            }
        }
    }

    #[test]
    fn skipping_settled_clocks_writes_the_per_cycle_files_of_a_lathe_run() {
        // The closed-loop measurement cycle, fast and coarse (4800 rpm at 1 MHz, one
        // measurement: about 100 000 clocks of long quiet stretches between encoder pulses).
        let mut scenario = tooltouch_plant::lathe::LatheScenario {
            clock_hz: 1_000_000,
            rpm: 4800.0,
            spindle_path: tooltouch_plant::lathe::SpindlePath::none(),
            ..Default::default()
        };
        scenario.cycle.repeats = 1;
        scenario.cycle.clearance_um = 3.0;
        scenario.cycle.z_dwell_ms = 0.2;
        scenario.cycle.retract_mm_per_s = 2.0;
        let config = MeasureConfig::default();
        let s =
            tooltouch_plant::measurement_cycle::closed_loop_stimulus(&scenario, &config).unwrap();
        let fast = golden_vectors(&config, &s).unwrap();
        assert!(
            fast.final_outputs.register_now,
            "no decision in the lathe run"
        );
        assert_eq!(
            fast,
            golden_vectors_with(&config, &s, per_cycle_response).unwrap()
        );
    }

    #[test]
    fn an_empty_stimulus_is_an_error() {
        let c = MeasureConfig::default();
        assert!(golden_vectors(&c, &Stimulus::new(50_000_000)).is_err());
    }
}
