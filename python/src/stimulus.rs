//! Cycle-level stimuli for Python: `Stimulus` (run-length pins, the host crate's
//! `tooltouch_plant::stimulus::Stimulus`), the lathe scenario that makes one (`lathe_stimulus`,
//! what `tooltouch measure` simulates), the stimulus files the CLI reads (`read_stimulus`:
//! a VCD or a `stim.hex`) and the files it writes from one (the golden VCD, the
//! `$readmemh` vectors, the event list). Every file is written by the CLI's own code, so
//! it is byte-identical to the CLI's.
//!
//! Shaped as run-length segments because a lathe run is millions of clocks but a few
//! thousand pin changes; `per_clock()` expands it only when asked.

use crate::model::Event;
use crate::settings::Settings;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use tooltouch_model::measure::frontend::{pin, Pins};
use tooltouch_plant::stimulus::Stimulus as HostStimulus;
use tooltouch_vectors::hex::golden_vectors;
use tooltouch_vectors::stimulus_file::{self, StatedClock, StimulusFile};
use tooltouch_vectors::{events_from_stimulus, vcd};

/// Run-length pins at a clock rate: segment `i` holds `pins[i]` for `cycles[i]` clocks.
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, PartialEq, Eq)]
pub struct Stimulus {
    pub(crate) inner: HostStimulus,
}

#[pymethods]
impl Stimulus {
    /// A stimulus from `pins` (uint8 pin bytes, bit 0 arm … bit 5 scale_b) and `cycles`
    /// (uint32 clocks per segment, each at least 1) at `clock_hz` (Hz; 1e9 / clock_hz
    /// must be whole nanoseconds for a VCD). Equal neighbours are merged into one segment,
    /// as the CLI merges them reading any stimulus file.
    #[new]
    fn new(
        pins: PyReadonlyArray1<'_, u8>,
        cycles: PyReadonlyArray1<'_, u32>,
        clock_hz: u32,
    ) -> PyResult<Stimulus> {
        let (pins, cycles) = (pins.as_slice()?, cycles.as_slice()?);
        if pins.len() != cycles.len() {
            return Err(PyValueError::new_err(format!(
                "{} pin bytes but {} cycle counts: one of each per segment",
                pins.len(),
                cycles.len()
            )));
        }
        if clock_hz == 0 {
            return Err(PyValueError::new_err("clock_hz 0: the clock must run"));
        }
        let mut stimulus = HostStimulus::new(clock_hz);
        for (i, (&p, &c)) in pins.iter().zip(cycles).enumerate() {
            if p & !pin::ALL != 0 {
                return Err(PyValueError::new_err(format!(
                    "pins[{i}] = 0x{p:02x}: only bits 0..=5 (arm, contact, index, fes, scale_a, scale_b) exist"
                )));
            }
            if c == 0 {
                return Err(PyValueError::new_err(format!(
                    "cycles[{i}] = 0: a segment lasts at least one clock"
                )));
            }
            stimulus.push(Pins(p), u64::from(c));
        }
        Ok(Stimulus { inner: stimulus })
    }

    /// Pin byte of every segment (uint8).
    #[getter]
    fn pins<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        PyArray1::from_iter(py, self.inner.segments.iter().map(|s| s.pins.0))
    }

    /// Clocks of every segment (uint32).
    #[getter]
    fn cycles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        PyArray1::from_iter(py, self.inner.segments.iter().map(|s| s.cycles))
    }

    /// FPGA clock, Hz.
    #[getter]
    fn clock_hz(&self) -> u32 {
        self.inner.clock_hz
    }

    /// Clocks in all segments.
    #[getter]
    fn total_cycles(&self) -> u64 {
        self.inner.total_cycles()
    }

    /// Segments.
    fn __len__(&self) -> usize {
        self.inner.segments.len()
    }

    /// Every clock's pin byte (uint8, `total_cycles` long): what `FrontEnd.run` takes.
    fn per_clock<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        let v: Vec<u8> = self.inner.cycles().map(|p| p.0).collect();
        PyArray1::from_vec(py, v)
    }

    /// The measurement events the cycle-level kernel acts on under `settings`, as
    /// `[(clock, Event)]` in canonical order: what `tooltouch measure` writes to
    /// `events.ttv` (after the configuration record).
    fn events(&self, settings: &Settings) -> Vec<(u64, Event)> {
        events_from_stimulus(&self.inner, &settings.config)
            .into_iter()
            .map(|e| (e.time, Event { inner: e.event }))
            .collect()
    }

    /// Writes the golden VCD of clocks `[0, end)` (all when `end` is None) under
    /// `settings`: the file `tooltouch measure --vcd` / `tooltouch vectors` write, byte
    /// for byte. Returns the clocks covered.
    #[pyo3(signature = (path, settings, end=None))]
    fn write_vcd(&self, path: PathBuf, settings: &Settings, end: Option<u64>) -> PyResult<u64> {
        let file = path.display().to_string();
        let io = |e: std::io::Error| PyOSError::new_err(format!("{file}: {e}"));
        let f = std::fs::File::create(&path).map_err(io)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, f);
        let n = vcd::write_golden(&mut w, &self.inner, &settings.config, end).map_err(io)?;
        w.flush().map_err(io)?;
        Ok(n)
    }

    /// The generated testbench's `$readmemh` vectors under `settings`: `(stim_hex,
    /// expect_hex)` texts, those of `tooltouch hdl --vectors` / `tooltouch vectors`.
    /// `stim.hex`: a header word `{8'd0, segments}`, then `{pins[7:0], cycles[31:0]}`
    /// per segment; `expect.hex`: run-length `{cycle, outputs}` words (see docs/hdl.md).
    fn hex_vectors(&self, settings: &Settings) -> PyResult<(String, String)> {
        let v = golden_vectors(&settings.config, &self.inner)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok((v.stim_hex, v.expect_hex))
    }

    fn __repr__(&self) -> String {
        format!(
            "Stimulus({} segments, {} clocks at {} Hz)",
            self.inner.segments.len(),
            self.inner.total_cycles(),
            self.inner.clock_hz
        )
    }
}

/// The pins of `tooltouch measure`'s simulated lathe run for `settings` (its `[lathe]`
/// table: spindle, surface, scale, measurement cycle), the model in the loop deciding
/// each retract; `seed` replaces `[lathe] seed`. The same stimulus the CLI writes as
/// `measure.vcd` and turns into `events.ttv`.
#[pyfunction]
#[pyo3(signature = (settings, seed=None))]
pub fn lathe_stimulus(
    py: Python<'_>,
    settings: &Settings,
    seed: Option<u64>,
) -> PyResult<Stimulus> {
    let mut scenario = settings.host.lathe.clone();
    if let Some(seed) = seed {
        scenario.seed = seed;
    }
    let config = settings.config;
    tooltouch_plant::measurement_cycle::check_run_size(&scenario, &config)
        .map_err(|e| PyValueError::new_err(format!("{e:#}")))?;
    let run = py
        .detach(|| tooltouch_plant::measurement_cycle::run(&scenario, &config, &mut |_| {}))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(Stimulus {
        inner: run.stimulus,
    })
}

/// Reads a pin stimulus as `tooltouch vectors --stimulus` does: a VCD (any tool's dump
/// holding the six pins; the golden VCD's `inputs` scope, `pin_*` ports, or bare names)
/// or a `stim.hex`. `clock_hz` states the clock (a VCD's own stamp must agree); else the
/// file's own, else 50 MHz. An event stream (`.ttv`) is refused: read it with `TtvReader`.
#[pyfunction]
#[pyo3(signature = (path, clock_hz=None))]
pub fn read_stimulus(path: PathBuf, clock_hz: Option<u32>) -> PyResult<Stimulus> {
    let stated = clock_hz.map(|hz| StatedClock {
        hz,
        source: "clock_hz=".into(),
    });
    match stimulus_file::read(&path, stated.as_ref())
        .map_err(|e| PyValueError::new_err(e.to_string()))?
    {
        StimulusFile::Pins { stimulus, .. } => Ok(Stimulus { inner: stimulus }),
        StimulusFile::Events(_) => Err(PyValueError::new_err(format!(
            "{}: an event stream, not pins: read it with TtvReader",
            path.display()
        ))),
    }
}

/// Bits `[lsb, lsb + width)` (counted from the right end) of a word given as hex digit
/// values, most significant first.
fn word_field(digits: &[u8], lsb: u32, width: u32) -> u64 {
    let mut v = 0u64;
    for bit in (lsb..lsb + width).rev() {
        let (digit, within) = ((bit / 4) as usize, bit % 4);
        let d = digits
            .len()
            .checked_sub(1 + digit)
            .and_then(|i| digits.get(i))
            .copied()
            .unwrap_or(0);
        v = (v << 1) | u64::from((d >> within) & 1);
    }
    v
}

/// Reads the generated testbench's `expect.hex` (the `$readmemh` response `tooltouch hdl
/// --vectors` / `tooltouch vectors` write) for `settings`: a header word holding the
/// entry count, then one `{cycle[31:0], outputs}` word per clock after which an output
/// changed (clock 0 always). Returns the change list as `{"clock": uint64, <output>:
/// uint64 register bits}` — what `FrontEnd.run_segments` gives, positions as port bits.
#[pyfunction]
pub fn read_expect_hex<'py>(
    py: Python<'py>,
    path: PathBuf,
    settings: &Settings,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let file = path.display().to_string();
    let text =
        std::fs::read_to_string(&path).map_err(|e| PyOSError::new_err(format!("{file}: {e}")))?;
    let widths = tooltouch_model::MeasureOutputs::widths(&settings.config);
    let total: u32 = widths.iter().map(|(_, w)| *w).sum();
    let mut words = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let digits = |n: usize, line: &str| -> PyResult<Vec<u8>> {
        line.chars()
            .map(|c| c.to_digit(16).map(|d| d as u8))
            .collect::<Option<Vec<u8>>>()
            .filter(|d| d.len() * 4 <= (total + 32 + 3) as usize)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "{file}: line {n}: `{line}` is not an expect.hex word of {} bits under these settings",
                    total + 32
                ))
            })
    };
    let (n, header) = words
        .next()
        .ok_or_else(|| PyValueError::new_err(format!("{file}: empty, no header word")))?;
    let entries = word_field(&digits(n, header)?, total, 32) as usize;
    let mut clocks = Vec::with_capacity(entries);
    let mut columns: Vec<Vec<u64>> = vec![Vec::with_capacity(entries); widths.len()];
    for (n, line) in words.by_ref().take(entries) {
        let d = digits(n, line)?;
        clocks.push(word_field(&d, total, 32));
        let mut lsb = total;
        for (col, (_, w)) in columns.iter_mut().zip(widths.iter()) {
            lsb -= w;
            col.push(word_field(&d, lsb, *w));
        }
    }
    if clocks.len() != entries {
        return Err(PyValueError::new_err(format!(
            "{file}: the header announces {entries} entries, the file holds {}",
            clocks.len()
        )));
    }
    let d = pyo3::types::PyDict::new(py);
    d.set_item("clock", PyArray1::from_vec(py, clocks))?;
    for (col, (name, _)) in columns.into_iter().zip(widths.iter()) {
        d.set_item(*name, PyArray1::from_vec(py, col))?;
    }
    Ok(d)
}
