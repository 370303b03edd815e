//! The measurement model for Python: `Outputs`, `Event`, the cycle-level `FrontEnd` (one
//! clock, a batched run over a numpy array, the exact fast-forward `advance`) and the
//! event-level `Measurement` (each event at its time, the model's `apply_at`). Each wraps
//! the `tooltouch-model` type by value; nothing is recomputed here.
//!
//! Time: the FES watchdog makes `faults` change with time alone while armed (the model
//! evaluates it lazily at the time the outputs are read), so the batched runs read the
//! outputs at every clock while armed, and `run_segments` finds the clock a settled span
//! times out at.

use crate::settings::Settings;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tooltouch_model::measure::checks::Faults;
use tooltouch_model::measure::frontend::{pin, FrontEnd as ModelFrontEnd, Pins};
use tooltouch_model::measure::mcu_registers::{mcu_word, MCU_ADDR_BITS};
use tooltouch_model::{
    MeasureConfig, MeasureEvent, MeasureOutputs, Measurement as ModelMeasurement,
};

/// Every output of the front end after one clock or event.
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Outputs {
    pub(crate) inner: MeasureOutputs,
}

#[pymethods]
impl Outputs {
    /// A measurement cycle is running (arm is high).
    #[getter]
    fn armed(&self) -> bool {
        self.inner.armed
    }
    /// Filtered contact level.
    #[getter]
    fn contact(&self) -> bool {
        self.inner.contact
    }
    /// "Position reached, register now"; held until the next arm.
    #[getter]
    fn register_now(&self) -> bool {
        self.inner.register_now
    }
    /// Scale position latched at the decision, counts (0 until decided).
    #[getter]
    fn decision_position(&self) -> i32 {
        self.inner.decision_position
    }
    /// A contact edge has been seen since arm.
    #[getter]
    fn first_contact(&self) -> bool {
        self.inner.first_contact
    }
    /// Scale position latched at the first contact edge, counts.
    #[getter]
    fn first_contact_position(&self) -> i32 {
        self.inner.first_contact_position
    }
    /// Live scale position, counts (`scale_bits` two's complement, sign-extended).
    #[getter]
    fn position(&self) -> i32 {
        self.inner.position
    }
    /// Illegal scale transitions since power-on, saturating at 255.
    #[getter]
    fn scale_errors(&self) -> u8 {
        self.inner.scale_errors
    }
    /// Contact pulses in the current window.
    #[getter]
    fn count(&self) -> u32 {
        self.inner.count
    }
    /// Contact pulses in the previous window.
    #[getter]
    fn last_window_count(&self) -> u32 {
        self.inner.last_window_count
    }
    /// Capacitor charge, LSBs (UQ0.`charge_bits` of full scale).
    #[getter]
    fn charge(&self) -> u32 {
        self.inner.charge
    }
    /// The density detector is armed.
    #[getter]
    fn density_armed(&self) -> bool {
        self.inner.density_armed
    }
    /// The density detector has fired since arm.
    #[getter]
    fn density_fired(&self) -> bool {
        self.inner.density_fired
    }
    /// Index pulses since arm, saturating at 65535.
    #[getter]
    fn revolutions(&self) -> u16 {
        self.inner.revolutions
    }
    /// FES pulses since arm, wrapping at 2^32.
    #[getter]
    fn pulses(&self) -> u32 {
        self.inner.pulses
    }
    /// The decision was confirmed by the contact pattern after it.
    #[getter]
    fn confirmed(&self) -> bool {
        self.inner.confirmed
    }
    /// Fault conditions latched since arm, one bit each (`FAULT_*`, named by
    /// `FAULT_NAMES` from bit 0). Accept a measurement only when `confirmed` and no fault.
    #[getter]
    fn faults(&self) -> u8 {
        self.inner.faults
    }
    /// The names of the latched faults, in bit order (`["pulses_lost", "no_decision"]`;
    /// empty when none).
    #[getter]
    fn fault_names(&self) -> Vec<&'static str> {
        Faults(self.inner.faults).names().collect()
    }

    /// Every output as `{name: int}` in `OUTPUT_NAMES` order (flags 0/1).
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in self.inner.fields() {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// Every output as the unsigned bits of its register under `settings` (positions
    /// truncated to `scale_bits`), as the Verilog ports carry them.
    fn register_bits(&self, settings: &Settings) -> Vec<u64> {
        self.inner.register_bits(&settings.config).to_vec()
    }

    fn __repr__(&self) -> String {
        let fields: Vec<String> = self
            .inner
            .fields()
            .iter()
            .map(|(n, v)| format!("{n}={v}"))
            .collect();
        format!("Outputs({})", fields.join(", "))
    }
}

/// One measurement input event (event level, firmware semantics).
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Event {
    pub(crate) inner: MeasureEvent,
}

#[pymethods]
impl Event {
    /// The arm line changed to `level`.
    #[staticmethod]
    fn arm(level: bool) -> Event {
        Event {
            inner: MeasureEvent::Arm(level),
        }
    }
    /// The contact line changed to `level`.
    #[staticmethod]
    fn contact(level: bool) -> Event {
        Event {
            inner: MeasureEvent::Contact(level),
        }
    }
    /// Rising edge of the index pulse.
    #[staticmethod]
    fn index() -> Event {
        Event {
            inner: MeasureEvent::Index,
        }
    }
    /// Rising edge of an FES pulse.
    #[staticmethod]
    fn fes() -> Event {
        Event {
            inner: MeasureEvent::Fes,
        }
    }
    /// Scale lines A and B changed to these levels.
    #[staticmethod]
    fn scale(a: bool, b: bool) -> Event {
        Event {
            inner: MeasureEvent::Scale { a, b },
        }
    }
    /// Test event: sets the FES pulse count since arm to `pulses`.
    #[staticmethod]
    fn preset_pulses(pulses: u32) -> Event {
        Event {
            inner: MeasureEvent::PresetPulses(pulses),
        }
    }

    /// `arm`, `contact`, `index`, `fes`, `scale` or `preset_pulses`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner {
            MeasureEvent::Arm(_) => "arm",
            MeasureEvent::Contact(_) => "contact",
            MeasureEvent::Index => "index",
            MeasureEvent::Fes => "fes",
            MeasureEvent::Scale { .. } => "scale",
            MeasureEvent::PresetPulses(_) => "preset_pulses",
        }
    }
    /// The new level of an `arm` or `contact` event, else `None`.
    #[getter]
    fn level(&self) -> Option<bool> {
        match self.inner {
            MeasureEvent::Arm(l) | MeasureEvent::Contact(l) => Some(l),
            _ => None,
        }
    }
    /// The new `(a, b)` levels of a `scale` event, else `None`.
    #[getter]
    fn lines(&self) -> Option<(bool, bool)> {
        match self.inner {
            MeasureEvent::Scale { a, b } => Some((a, b)),
            _ => None,
        }
    }
    /// The pulse count of a `preset_pulses` event, else `None`.
    #[getter]
    fn pulses(&self) -> Option<u32> {
        match self.inner {
            MeasureEvent::PresetPulses(n) => Some(n),
            _ => None,
        }
    }

    fn __repr__(&self) -> String {
        match self.inner {
            MeasureEvent::Arm(l) => format!("Event.arm({})", py_bool(l)),
            MeasureEvent::Contact(l) => format!("Event.contact({})", py_bool(l)),
            MeasureEvent::Index => "Event.index()".into(),
            MeasureEvent::Fes => "Event.fes()".into(),
            MeasureEvent::Scale { a, b } => format!("Event.scale({}, {})", py_bool(a), py_bool(b)),
            MeasureEvent::PresetPulses(n) => format!("Event.preset_pulses({n})"),
        }
    }
}

fn py_bool(b: bool) -> &'static str {
    if b {
        "True"
    } else {
        "False"
    }
}

/// The pins byte `pins`, refusing bits above the six pins.
/// `addr` checked as the MCU addresses of `clocks` clocks: as long as the pins, each 4 bits.
fn checked_mcu_addr(addr: &[u8], clocks: usize) -> PyResult<&[u8]> {
    if addr.len() != clocks {
        return Err(PyValueError::new_err(format!(
            "mcu_addr has {} elements and pins {clocks}: one address per clock",
            addr.len()
        )));
    }
    if let Some(k) = addr
        .iter()
        .position(|&a| u32::from(a) >= 1 << MCU_ADDR_BITS)
    {
        return Err(PyValueError::new_err(format!(
            "mcu_addr[{k}] = {}: mcu_addr is {MCU_ADDR_BITS} bits, 0..=15",
            addr[k]
        )));
    }
    Ok(addr)
}

fn checked_pins(pins: u8) -> PyResult<Pins> {
    if pins & !pin::ALL != 0 {
        return Err(PyValueError::new_err(format!(
            "pins 0x{pins:02x}: only bits 0..=5 (arm, contact, index, fes, scale_a, scale_b) exist"
        )));
    }
    Ok(Pins(pins))
}

/// The cycle-level front end (RTL semantics), from reset.
#[pyclass(module = "tooltouch")]
pub struct FrontEnd {
    /// The model's front end; it counts its clocks (the time of its FES watchdog).
    inner: ModelFrontEnd,
    /// Its configuration (the MCU words' widths and hash).
    config: MeasureConfig,
}

/// One growing array per output, filled clock by clock and handed to numpy at the end.
#[derive(Default)]
struct OutputColumns {
    armed: Vec<bool>,
    contact: Vec<bool>,
    register_now: Vec<bool>,
    decision_position: Vec<i32>,
    first_contact: Vec<bool>,
    first_contact_position: Vec<i32>,
    position: Vec<i32>,
    scale_errors: Vec<u8>,
    count: Vec<u32>,
    last_window_count: Vec<u32>,
    charge: Vec<u32>,
    density_armed: Vec<bool>,
    density_fired: Vec<bool>,
    revolutions: Vec<u16>,
    pulses: Vec<u32>,
    confirmed: Vec<bool>,
    faults: Vec<u8>,
}

/// `Vec::with_capacity(n)` for every column.
macro_rules! columns_with_capacity {
    ($n:expr; $($f:ident),*) => {
        OutputColumns { $($f: Vec::with_capacity($n)),* }
    };
}

impl OutputColumns {
    fn with_capacity(n: usize) -> Self {
        columns_with_capacity!(n; armed, contact, register_now, decision_position,
            first_contact, first_contact_position, position, scale_errors, count,
            last_window_count, charge, density_armed, density_fired, revolutions, pulses,
            confirmed, faults)
    }

    #[inline]
    fn push(&mut self, o: &MeasureOutputs) {
        self.armed.push(o.armed);
        self.contact.push(o.contact);
        self.register_now.push(o.register_now);
        self.decision_position.push(o.decision_position);
        self.first_contact.push(o.first_contact);
        self.first_contact_position.push(o.first_contact_position);
        self.position.push(o.position);
        self.scale_errors.push(o.scale_errors);
        self.count.push(o.count);
        self.last_window_count.push(o.last_window_count);
        self.charge.push(o.charge);
        self.density_armed.push(o.density_armed);
        self.density_fired.push(o.density_fired);
        self.revolutions.push(o.revolutions);
        self.pulses.push(o.pulses);
        self.confirmed.push(o.confirmed);
        self.faults.push(o.faults);
    }

    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("armed", PyArray1::from_vec(py, self.armed))?;
        d.set_item("contact", PyArray1::from_vec(py, self.contact))?;
        d.set_item("register_now", PyArray1::from_vec(py, self.register_now))?;
        d.set_item(
            "decision_position",
            PyArray1::from_vec(py, self.decision_position),
        )?;
        d.set_item("first_contact", PyArray1::from_vec(py, self.first_contact))?;
        d.set_item(
            "first_contact_position",
            PyArray1::from_vec(py, self.first_contact_position),
        )?;
        d.set_item("position", PyArray1::from_vec(py, self.position))?;
        d.set_item("scale_errors", PyArray1::from_vec(py, self.scale_errors))?;
        d.set_item("count", PyArray1::from_vec(py, self.count))?;
        d.set_item(
            "last_window_count",
            PyArray1::from_vec(py, self.last_window_count),
        )?;
        d.set_item("charge", PyArray1::from_vec(py, self.charge))?;
        d.set_item("density_armed", PyArray1::from_vec(py, self.density_armed))?;
        d.set_item("density_fired", PyArray1::from_vec(py, self.density_fired))?;
        d.set_item("revolutions", PyArray1::from_vec(py, self.revolutions))?;
        d.set_item("pulses", PyArray1::from_vec(py, self.pulses))?;
        d.set_item("confirmed", PyArray1::from_vec(py, self.confirmed))?;
        d.set_item("faults", PyArray1::from_vec(py, self.faults))?;
        Ok(d)
    }
}

#[pymethods]
impl FrontEnd {
    /// A front end in its reset state (every register 0) for `settings`.
    #[new]
    fn new(settings: &Settings) -> FrontEnd {
        FrontEnd {
            inner: ModelFrontEnd::new(&settings.config),
            config: settings.config,
        }
    }

    /// One rising clock edge with the pin byte `pins` (bit 0 arm, 1 contact, 2 index,
    /// 3 fes, 4 scale_a, 5 scale_b); returns the outputs registered by it.
    fn step(&mut self, pins: u8) -> PyResult<Outputs> {
        self.inner.clock(checked_pins(pins)?);
        Ok(Outputs {
            inner: self.inner.outputs(),
        })
    }

    /// One clock per element of `pins` (a 1-D uint8 array, pin bytes as for `step`);
    /// returns `{output name: array}`, element `k` the output after clock `k`. dtypes:
    /// flags bool, positions int32, scale_errors uint8, revolutions uint16, the rest
    /// uint32, faults uint8. With `mcu_addr` (a uint8 array as long as `pins`, addresses
    /// 0..=15) the dict also holds `mcu_rdata` (uint32): the word of the MCU register map
    /// at `mcu_addr[k]` after clock `k`, the diagnostic counters 0 unless
    /// `mcu_diagnostics`.
    #[pyo3(signature = (pins, mcu_addr=None, mcu_diagnostics=false))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        pins: PyReadonlyArray1<'py, u8>,
        mcu_addr: Option<PyReadonlyArray1<'py, u8>>,
        mcu_diagnostics: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let pins = pins.as_slice()?;
        if let Some(k) = pins.iter().position(|p| p & !pin::ALL != 0) {
            return Err(PyValueError::new_err(format!(
                "pins[{k}] = 0x{:02x}: only bits 0..=5 (arm, contact, index, fes, scale_a, scale_b) exist",
                pins[k]
            )));
        }
        let mcu_addr = match &mcu_addr {
            Some(a) => Some(checked_mcu_addr(a.as_slice()?, pins.len())?),
            None => None,
        };
        let mut columns = OutputColumns::with_capacity(pins.len());
        let mut mcu_rdata = Vec::with_capacity(mcu_addr.map_or(0, <[u8]>::len));
        let hash = self.config.hash();
        // The outputs are the kernel's registers, and the kernel changes only in a clock
        // with edges, or with time while armed (the FES watchdog): the other clocks repeat
        // the last outputs without recomputing them.
        let mut outputs = self.inner.outputs();
        let mut bits = outputs.register_bits(&self.config);
        for (k, &p) in pins.iter().enumerate() {
            if !self.inner.clock(Pins(p)).is_empty() || outputs.armed {
                outputs = self.inner.outputs();
                if mcu_addr.is_some() {
                    bits = outputs.register_bits(&self.config);
                }
            }
            columns.push(&outputs);
            if let Some(addr) = mcu_addr {
                mcu_rdata.push(mcu_word(
                    &self.config,
                    hash,
                    &bits,
                    u32::from(addr[k]),
                    mcu_diagnostics,
                ));
            }
        }
        let d = columns.into_dict(py)?;
        if mcu_addr.is_some() {
            d.set_item("mcu_rdata", PyArray1::from_vec(py, mcu_rdata))?;
        }
        Ok(d)
    }

    /// `cycles` clocks with `pins` held, skipping exactly the clocks after the front end
    /// has settled; returns the clocks simulated one by one (the rest changed nothing).
    fn advance(&mut self, pins: u8, cycles: u64) -> PyResult<u64> {
        Ok(self.inner.advance(checked_pins(pins)?, cycles, |_, _| {}))
    }

    /// Run-length clocking: segment `i` holds `pins[i]` (uint8) for `cycles[i]` clocks
    /// (uint32, 0 allowed), the settled clocks skipped exactly as `advance` does, so the
    /// cost follows the pin changes, not the clocks. Returns the output change list as
    /// `{"clock": uint64, <output>: array}`: a row for the first clock of the call and one
    /// for every later clock after which an output changed (clock counted from reset,
    /// see `clocks`), each output as `run` types it; the outputs hold each row's values
    /// until the next row — the outputs half of the golden VCD's change list.
    fn run_segments<'py>(
        &mut self,
        py: Python<'py>,
        pins: PyReadonlyArray1<'py, u8>,
        cycles: PyReadonlyArray1<'py, u32>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (pins, cycles) = (pins.as_slice()?, cycles.as_slice()?);
        if pins.len() != cycles.len() {
            return Err(PyValueError::new_err(format!(
                "{} pin bytes but {} cycle counts: one of each per segment",
                pins.len(),
                cycles.len()
            )));
        }
        if let Some(k) = pins.iter().position(|p| p & !pin::ALL != 0) {
            return Err(PyValueError::new_err(format!(
                "pins[{k}] = 0x{:02x}: only bits 0..=5 (arm, contact, index, fes, scale_a, scale_b) exist",
                pins[k]
            )));
        }
        let mut columns = OutputColumns::default();
        let mut at = Vec::new();
        let mut last: Option<MeasureOutputs> = None;
        for (&p, &n) in pins.iter().zip(cycles) {
            let (p, end) = (Pins(p), self.inner.clocks() + u64::from(n));
            while self.inner.clocks() < end {
                let clock = self.inner.clocks();
                if let Some(held) = last.filter(|_| self.inner.is_settled(p)) {
                    // Settled: no register changes, only the watchdog's time may show. It
                    // expires at most once and stays, so the first clock whose outputs
                    // differ is found by bisection.
                    let m = self.inner.measurement();
                    if m.outputs_at(end - 1) != held {
                        let (mut lo, mut hi) = (clock, end - 1);
                        while lo < hi {
                            let mid = lo + (hi - lo) / 2;
                            if m.outputs_at(mid) != held {
                                hi = mid;
                            } else {
                                lo = mid + 1;
                            }
                        }
                        let o = m.outputs_at(lo);
                        at.push(lo);
                        columns.push(&o);
                        last = Some(o);
                    }
                    self.inner.advance(p, end - clock, |_, _| {});
                    break;
                }
                let edges = self.inner.clock(p);
                let armed = last.is_some_and(|o| o.armed);
                if last.is_none() || !edges.is_empty() || armed {
                    let o = self.inner.outputs();
                    if last != Some(o) {
                        at.push(clock);
                        columns.push(&o);
                        last = Some(o);
                    }
                }
            }
        }
        let d = columns.into_dict(py)?;
        d.set_item("clock", PyArray1::from_vec(py, at))?;
        Ok(d)
    }

    /// Clocks since reset (`step`, `run`, `advance` and `run_segments` all count): the
    /// time of the FES watchdog.
    #[getter]
    fn clocks(&self) -> u64 {
        self.inner.clocks()
    }

    /// Whether clocking with `pins` held would change no register.
    fn is_settled(&self, pins: u8) -> PyResult<bool> {
        Ok(self.inner.is_settled(checked_pins(pins)?))
    }

    /// The outputs registered after the last clock.
    #[getter]
    fn outputs(&self) -> Outputs {
        Outputs {
            inner: self.inner.outputs(),
        }
    }

    /// Glitch-filtered pin levels, a pin byte.
    #[getter]
    fn filtered_pins(&self) -> u8 {
        self.inner.filtered().0
    }
}

/// The event-level measurement kernel (firmware semantics), from reset.
#[pyclass(module = "tooltouch")]
pub struct Measurement {
    inner: ModelMeasurement,
}

#[pymethods]
impl Measurement {
    /// A kernel in its reset state for `settings`.
    #[new]
    fn new(settings: &Settings) -> Measurement {
        Measurement {
            inner: ModelMeasurement::new(&settings.config),
        }
    }

    /// Applies one event at `time` (ticks of the stream's clock, as a `.ttv` record's;
    /// the model's `apply_at`: the FES watchdog sees the time first); returns the outputs
    /// after it. A time before the last is a `ValueError`.
    fn apply(&mut self, event: &Event, time: u64) -> PyResult<Outputs> {
        self.not_before(time)?;
        self.inner.apply_at(time, event.inner);
        Ok(Outputs {
            inner: self.inner.outputs(),
        })
    }

    /// The stream's clock reads `now` ticks, with no event (the FES watchdog latches if it
    /// expired); returns the outputs then.
    fn observe(&mut self, now: u64) -> PyResult<Outputs> {
        self.not_before(now)?;
        self.inner.observe(now);
        Ok(Outputs {
            inner: self.inner.outputs(),
        })
    }

    /// The outputs at time `now` (not before the last event's or observed time), the FES
    /// watchdog evaluated then; changes nothing.
    fn outputs_at(&self, now: u64) -> PyResult<Outputs> {
        self.not_before(now)?;
        Ok(Outputs {
            inner: self.inner.outputs_at(now),
        })
    }

    /// The outputs at the last event's or observed time.
    #[getter]
    fn outputs(&self) -> Outputs {
        Outputs {
            inner: self.inner.outputs(),
        }
    }

    /// The last event's or observed time, ticks.
    #[getter]
    fn time(&self) -> u64 {
        self.inner.checks().now()
    }
}

impl Measurement {
    /// A `ValueError` when `time` is before the kernel's time.
    fn not_before(&self, time: u64) -> PyResult<()> {
        let now = self.inner.checks().now();
        if time < now {
            return Err(PyValueError::new_err(format!(
                "time {time} is before the time already reached, {now}; time never goes backwards"
            )));
        }
        Ok(())
    }
}
