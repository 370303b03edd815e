//! The force path for Python: `ForceSettings` (validated `tooltouch_model` force
//! configurations, built as the CLI builds them), `ForceEvent`, `ForceOutputs` and the
//! event-level `ForceKernel`, plus `drive_scenario`, the depth-step scenario of
//! `tooltouch control` as stimuli. Each wraps the model type by value; nothing is
//! recomputed here.
//!
//! Shaped for the force path's one per-sample loop: `ForceKernel.run` takes a numpy array
//! of ADC codes (one row per 1 kHz sample), applies the control tick after every
//! `samples_per_period`-th sample and the CNC commands at their sample, all in Rust, and
//! returns one numpy column per output after every non-sample event — the records of the
//! CLI's `<controller>_<force>.outputs.ttv`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;
use tooltouch_model::force::config::{
    ForceConfig, ForceSettings as ModelForceSettings, ForceSource,
};
use tooltouch_model::force::control::ControllerSettings;
use tooltouch_model::force::events::ForceEvent as ModelForceEvent;
use tooltouch_model::force::kernel::{
    ForceKernel as ModelForceKernel, ForceOutputs as ModelOutputs,
};
use tooltouch_model::force::sampling::{AdcChannel, AdcCodes};
use tooltouch_model::units::Fx;
use tooltouch_model::wire::force_config::decode_force_settings;
use tooltouch_plant::drive::scenario::{self, scenario_settings, ControlScenario, ControllerKind};
use tooltouch_settings::firmware_config::{FirmwareConfig, ForceDesign};

/// ADC channels of one sample, in the model's order ([`AdcChannel::ALL`], the wire order):
/// speed, power, force, v_u, v_v, v_w, i_u, i_v.
pub(crate) const CHANNELS: usize = AdcChannel::COUNT;

/// A sample's codes in the model's channel order.
pub(crate) fn codes_row(c: &AdcCodes) -> [u16; CHANNELS] {
    c.to_array()
}

/// Codes from a row in the model's channel order.
pub(crate) fn codes_from(row: [u16; CHANNELS]) -> AdcCodes {
    AdcCodes::from_array(row)
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn source_name(s: ForceSource) -> &'static str {
    match s {
        ForceSource::Estimated => "estimated",
        ForceSource::Measured => "measured",
    }
}

/// A validated force-path configuration.
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct ForceSettings {
    pub(crate) config: ForceConfig,
}

impl ForceSettings {
    pub(crate) fn validated(s: ModelForceSettings) -> PyResult<ForceSettings> {
        Ok(ForceSettings {
            config: s.validate().map_err(value_error)?,
        })
    }
}

#[pymethods]
impl ForceSettings {
    /// The model's default force path (what a firmware image built without a `[force]`
    /// table runs): 1 kHz, 50 samples per period, 500 N reference, the default PI.
    #[new]
    fn new() -> PyResult<ForceSettings> {
        ForceSettings::validated(ModelForceSettings::default())
    }

    /// A force design as a settings file's `[force]` table names it (and `tooltouch tune`
    /// sweeps it): `controller` `pi`/`adaptive`/`fuzzy`, gains in percent of the
    /// Ziegler–Nichols design (`1..=1000`), `force_source` `estimated`/`measured`.
    #[staticmethod]
    #[pyo3(signature = (controller="pi", kp_percent=100, ki_percent=100, force_source="estimated"))]
    fn design(
        controller: &str,
        kp_percent: u32,
        ki_percent: u32,
        force_source: &str,
    ) -> PyResult<ForceSettings> {
        let design = ForceDesign {
            controller: controller.into(),
            kp_percent,
            ki_percent,
            force_source: force_source.into(),
        };
        let s = design
            .settings()
            .map_err(|e| value_error(format!("{e:#}")))?;
        ForceSettings::validated(s)
    }

    /// The settings `tooltouch control --controller C --force S --process P` runs: the model
    /// defaults with the controller designed on the process (`"kienzle"`, the default: its
    /// linearization; `"linear"`: the nominal F10).
    #[staticmethod]
    #[pyo3(signature = (controller="pi", force_source="estimated", process="kienzle"))]
    fn control_scenario(
        controller: &str,
        force_source: &str,
        process: &str,
    ) -> PyResult<ForceSettings> {
        let kienzle = kienzle_process(process)?;
        let kind = ControllerKind::ALL
            .into_iter()
            .find(|k| k.name() == controller)
            .ok_or_else(|| {
                value_error(format!(
                    "controller {controller:?}: expected \"pi\", \"adaptive\" or \"fuzzy\""
                ))
            })?;
        let source = match force_source {
            "estimated" => ForceSource::Estimated,
            "measured" => ForceSource::Measured,
            other => {
                return Err(value_error(format!(
                    "force_source {other:?}: expected \"estimated\" or \"measured\""
                )))
            }
        };
        ForceSettings::validated(match kienzle {
            Some(k) => scenario::kienzle_settings(kind, source, &k),
            None => scenario_settings(kind, source),
        })
    }

    /// The force configuration of a settings file, as `tooltouch cosim` and the firmware
    /// build read it (its `[force]` table; the model defaults without one).
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<ForceSettings> {
        if !path.is_file() {
            return Err(PyOSError::new_err(format!(
                "{}: no such settings file",
                path.display()
            )));
        }
        let c = FirmwareConfig::load(Some(&path)).map_err(|e| value_error(format!("{e:#}")))?;
        Ok(ForceSettings { config: c.force })
    }

    /// Settings from their canonical bytes (`canonical_bytes`, the payload the
    /// `force_config_chunk` records carry), validated.
    #[staticmethod]
    fn from_canonical_bytes(data: &[u8]) -> PyResult<ForceSettings> {
        let s = decode_force_settings(data).map_err(|e| {
            value_error(format!(
                "force configuration bytes do not decode at byte {} (format version, an enum \
                 value, too few bytes or bytes left over)",
                e.at
            ))
        })?;
        ForceSettings::validated(s)
    }

    /// The canonical bytes of the configuration (hashed into `force_hash`).
    #[getter]
    fn canonical_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let (bytes, n) = self.config.canonical_bytes();
        PyBytes::new(py, &bytes[..n])
    }

    /// 64-bit FNV-1a hash of the canonical bytes: the `force_hash` of `.ttv` headers.
    #[getter]
    fn force_hash(&self) -> u64 {
        self.config.hash()
    }

    /// ADC sample rate, Hz (the tick rate of force streams).
    #[getter]
    fn sample_hz(&self) -> u16 {
        self.config.settings().sample_hz
    }

    /// ADC samples per control period.
    #[getter]
    fn samples_per_period(&self) -> u16 {
        self.config.settings().samples_per_period
    }

    /// Control period h = samples_per_period / sample_hz, s (I32F32 converted to float).
    #[getter]
    fn period_s(&self) -> f64 {
        self.config.period().to_num()
    }

    /// Reference force F_r, N (I32F32 converted to float).
    #[getter]
    fn reference_n(&self) -> f64 {
        self.config.settings().reference.to_num()
    }

    /// Feed override while force control is off, %.
    #[getter]
    fn manual_override(&self) -> u8 {
        self.config.settings().manual_override
    }

    /// Low-pass coefficient exponent k (coefficient 2^-k).
    #[getter]
    fn lowpass_shift(&self) -> u8 {
        self.config.settings().lowpass_shift
    }

    /// `estimated` or `measured`: which force the controller regulates.
    #[getter]
    fn force_source(&self) -> &'static str {
        source_name(self.config.settings().force_source)
    }

    /// `pi`, `adaptive` or `fuzzy`.
    #[getter]
    fn controller(&self) -> &'static str {
        match self.config.settings().controller {
            ControllerSettings::Pi(_) => "pi",
            ControllerSettings::Adaptive(_) => "adaptive",
            ControllerSettings::Fuzzy(_) => "fuzzy",
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "ForceSettings(controller={:?}, force_source={:?}, force_hash=0x{:016x})",
            self.controller(),
            self.force_source(),
            self.config.hash()
        )
    }
}

/// One input event of the force path.
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct ForceEvent {
    pub(crate) inner: ModelForceEvent,
}

#[pymethods]
impl ForceEvent {
    /// One ADC sample: eight 12-bit codes in wire order (speed, power, force, v_u, v_v,
    /// v_w, i_u, i_v); codes above 4095 are clamped to 4095 by the sampler.
    #[staticmethod]
    fn sample(codes: [u16; CHANNELS]) -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::Sample(codes_from(codes)),
        }
    }
    /// The control period's tick.
    #[staticmethod]
    fn tick() -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::Tick,
        }
    }
    /// CNC: no-load identification on / off.
    #[staticmethod]
    fn identify(on: bool) -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::Identify(on),
        }
    }
    /// CNC: force control on / off.
    #[staticmethod]
    fn control(on: bool) -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::Control(on),
        }
    }
    /// CNC: cutting conditions changed to condition set `index`.
    #[staticmethod]
    fn conditions(index: u8) -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::Conditions(index),
        }
    }
    /// CNC: a new tool was put in.
    #[staticmethod]
    fn tool_changed() -> ForceEvent {
        ForceEvent {
            inner: ModelForceEvent::ToolChanged,
        }
    }

    /// `sample`, `tick`, `identify`, `control`, `conditions` or `tool_changed`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner {
            ModelForceEvent::Sample(_) => "sample",
            ModelForceEvent::Tick => "tick",
            ModelForceEvent::Identify(_) => "identify",
            ModelForceEvent::Control(_) => "control",
            ModelForceEvent::Conditions(_) => "conditions",
            ModelForceEvent::ToolChanged => "tool_changed",
        }
    }
    /// A sample's eight codes in wire order, else `None`.
    #[getter]
    fn codes(&self) -> Option<[u16; CHANNELS]> {
        match self.inner {
            ModelForceEvent::Sample(c) => Some(codes_row(&c)),
            _ => None,
        }
    }
    /// The level of an `identify` or `control` event, else `None`.
    #[getter]
    fn level(&self) -> Option<bool> {
        match self.inner {
            ModelForceEvent::Identify(on) | ModelForceEvent::Control(on) => Some(on),
            _ => None,
        }
    }
    /// The condition set of a `conditions` event, else `None`.
    #[getter]
    fn index(&self) -> Option<u8> {
        match self.inner {
            ModelForceEvent::Conditions(i) => Some(i),
            _ => None,
        }
    }

    fn __repr__(&self) -> String {
        let b = |on: bool| if on { "True" } else { "False" };
        match self.inner {
            ModelForceEvent::Sample(c) => format!("ForceEvent.sample({:?})", codes_row(&c)),
            ModelForceEvent::Tick => "ForceEvent.tick()".into(),
            ModelForceEvent::Identify(on) => format!("ForceEvent.identify({})", b(on)),
            ModelForceEvent::Control(on) => format!("ForceEvent.control({})", b(on)),
            ModelForceEvent::Conditions(i) => format!("ForceEvent.conditions({i})"),
            ModelForceEvent::ToolChanged => "ForceEvent.tool_changed()".into(),
        }
    }
}

/// The I32F32 outputs: name and accessor.
type FxField = (&'static str, fn(&ModelOutputs) -> Fx);
const FX_FIELDS: [FxField; 5] = [
    ("force_estimate", |o| o.force_estimate),
    ("force_measured", |o| o.force_measured),
    ("wear_power", |o| o.wear_power),
    ("wear_allowed", |o| o.wear_allowed),
    ("coulomb", |o| o.coulomb),
];
/// The flag outputs: name and accessor.
type FlagField = (&'static str, fn(&ModelOutputs) -> bool);
const FLAG_FIELDS: [FlagField; 8] = [
    ("saturated", |o| o.saturated),
    ("fast_estimate", |o| o.fast_estimate),
    ("control_enabled", |o| o.control_enabled),
    ("identifying", |o| o.identifying),
    ("identified", |o| o.identified),
    ("wear_over", |o| o.wear_over),
    ("wear_alarm", |o| o.wear_alarm),
    ("wear_blind", |o| o.wear_blind),
];

/// Every output of the force path after one event.
#[pyclass(module = "tooltouch", frozen, eq)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct ForceOutputs {
    pub(crate) inner: ModelOutputs,
}

#[pymethods]
impl ForceOutputs {
    /// Feed override to the CNC, %, 0..=255.
    #[getter]
    fn override_pct(&self) -> u8 {
        self.inner.override_pct
    }
    /// The controller's demand was outside 0..=255 in the last period.
    #[getter]
    fn saturated(&self) -> bool {
        self.inner.saturated
    }
    /// The fast electrical estimate was selected in the last period.
    #[getter]
    fn fast_estimate(&self) -> bool {
        self.inner.fast_estimate
    }
    /// Force control is on.
    #[getter]
    fn control_enabled(&self) -> bool {
        self.inner.control_enabled
    }
    /// No-load identification is running.
    #[getter]
    fn identifying(&self) -> bool {
        self.inner.identifying
    }
    /// B and T_fco come from an identification.
    #[getter]
    fn identified(&self) -> bool {
        self.inner.identified
    }
    /// The wear monitor's power is at or above its threshold.
    #[getter]
    fn wear_over(&self) -> bool {
        self.inner.wear_over
    }
    /// Wear alarm latched.
    #[getter]
    fn wear_alarm(&self) -> bool {
        self.inner.wear_alarm
    }
    /// The wear monitor cannot judge: its threshold is still above the conditions' own.
    #[getter]
    fn wear_blind(&self) -> bool {
        self.inner.wear_blind
    }
    /// Bad CNC commands, saturating at 255.
    #[getter]
    fn bad_events(&self) -> u8 {
        self.inner.bad_events
    }
    /// Estimated cutting force, N (I32F32 as float; `force_estimate_bits` is exact).
    #[getter]
    fn force_estimate(&self) -> f64 {
        self.inner.force_estimate.to_num()
    }
    /// Dynamometer force, period average, N.
    #[getter]
    fn force_measured(&self) -> f64 {
        self.inner.force_measured.to_num()
    }
    /// Low-passed mean spindle power, W.
    #[getter]
    fn wear_power(&self) -> f64 {
        self.inner.wear_power.to_num()
    }
    /// Allowed power, W.
    #[getter]
    fn wear_allowed(&self) -> f64 {
        self.inner.wear_allowed.to_num()
    }
    /// Coulomb friction torque in use, N·m.
    #[getter]
    fn coulomb(&self) -> f64 {
        self.inner.coulomb.to_num()
    }
    /// `force_estimate` as its I32F32 bits (value × 2^32, int64).
    #[getter]
    fn force_estimate_bits(&self) -> i64 {
        self.inner.force_estimate.to_bits()
    }
    /// `force_measured` as its I32F32 bits.
    #[getter]
    fn force_measured_bits(&self) -> i64 {
        self.inner.force_measured.to_bits()
    }
    /// `wear_power` as its I32F32 bits.
    #[getter]
    fn wear_power_bits(&self) -> i64 {
        self.inner.wear_power.to_bits()
    }
    /// `wear_allowed` as its I32F32 bits.
    #[getter]
    fn wear_allowed_bits(&self) -> i64 {
        self.inner.wear_allowed.to_bits()
    }
    /// `coulomb` as its I32F32 bits.
    #[getter]
    fn coulomb_bits(&self) -> i64 {
        self.inner.coulomb.to_bits()
    }

    /// Every output as `{name: value}`: integers and flags as int/bool, the I32F32 values
    /// as their exact bits under `<name>_bits` and as float under `<name>`.
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let o = &self.inner;
        d.set_item("override_pct", o.override_pct)?;
        for (name, get) in FLAG_FIELDS {
            d.set_item(name, get(o))?;
        }
        d.set_item("bad_events", o.bad_events)?;
        for (name, get) in FX_FIELDS {
            d.set_item(name, get(o).to_num::<f64>())?;
            d.set_item(format!("{name}_bits"), get(o).to_bits())?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let o = &self.inner;
        format!(
            "ForceOutputs(override_pct={}, control_enabled={}, force_estimate={}, wear_alarm={})",
            o.override_pct, o.control_enabled, o.force_estimate, o.wear_alarm
        )
    }
}

/// Columns of force outputs, one row per non-sample event.
#[derive(Default)]
struct ForceColumns {
    time: Vec<u64>,
    kind: Vec<u8>,
    override_pct: Vec<u8>,
    bad_events: Vec<u8>,
    flags: [Vec<bool>; FLAG_FIELDS.len()],
    bits: [Vec<i64>; FX_FIELDS.len()],
}

impl ForceColumns {
    fn push(&mut self, time: u64, event: &ModelForceEvent, o: &ModelOutputs) {
        self.time.push(time);
        self.kind.push(event.kind());
        self.override_pct.push(o.override_pct);
        self.bad_events.push(o.bad_events);
        for (col, (_, get)) in self.flags.iter_mut().zip(FLAG_FIELDS) {
            col.push(get(o));
        }
        for (col, (_, get)) in self.bits.iter_mut().zip(FX_FIELDS) {
            col.push(get(o).to_bits());
        }
    }

    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_vec(py, self.time))?;
        d.set_item("kind", PyArray1::from_vec(py, self.kind))?;
        d.set_item("override_pct", PyArray1::from_vec(py, self.override_pct))?;
        d.set_item("bad_events", PyArray1::from_vec(py, self.bad_events))?;
        for (col, (name, _)) in self.flags.into_iter().zip(FLAG_FIELDS) {
            d.set_item(name, PyArray1::from_vec(py, col))?;
        }
        for (col, (name, _)) in self.bits.into_iter().zip(FX_FIELDS) {
            let float: Vec<f64> = col
                .iter()
                .map(|&b| Fx::from_bits(b).to_num::<f64>())
                .collect();
            d.set_item(name, PyArray1::from_vec(py, float))?;
            d.set_item(format!("{name}_bits"), PyArray1::from_vec(py, col))?;
        }
        Ok(d)
    }
}

/// The force path's event-level kernel (firmware semantics), from reset.
#[pyclass(module = "tooltouch")]
pub struct ForceKernel {
    inner: ModelForceKernel,
    samples_per_period: u64,
    samples: u64,
}

/// A command list `[(sample index, ForceEvent)]` as checked pairs.
fn commands_from(
    commands: Option<Vec<(u64, ForceEvent)>>,
    first: u64,
    end: u64,
) -> PyResult<Vec<(u64, ModelForceEvent)>> {
    let commands = commands.unwrap_or_default();
    let mut previous = first;
    let mut out = Vec::with_capacity(commands.len());
    for (i, (k, e)) in commands.into_iter().enumerate() {
        if matches!(e.inner, ModelForceEvent::Sample(_) | ModelForceEvent::Tick) {
            return Err(value_error(format!(
                "commands[{i}] is a {}: samples come from `codes`, ticks from the sample count",
                e.kind()
            )));
        }
        if k < previous || k >= end {
            return Err(value_error(format!(
                "commands[{i}] at sample {k}: the commands must be in order, at samples \
                 {first}..{end} of this call"
            )));
        }
        previous = k;
        out.push((k, e.inner));
    }
    Ok(out)
}

#[pymethods]
impl ForceKernel {
    /// A kernel for `settings`: control off at the manual override, nominal friction,
    /// condition set 0, no sample taken.
    #[new]
    fn new(settings: &ForceSettings) -> ForceKernel {
        ForceKernel {
            inner: ModelForceKernel::new(&settings.config),
            samples_per_period: u64::from(settings.config.settings().samples_per_period.max(1)),
            samples: 0,
        }
    }

    /// Applies one event; returns the outputs after it. A sample applied here counts
    /// toward `samples` (the index `run` continues from) but never ticks by itself.
    fn apply(&mut self, event: &ForceEvent) -> ForceOutputs {
        if matches!(event.inner, ModelForceEvent::Sample(_)) {
            self.samples += 1;
        }
        self.inner.apply(event.inner);
        ForceOutputs {
            inner: self.inner.outputs(),
        }
    }

    /// Feeds the ADC samples `codes` (uint16 array of shape (n, 8), a row per sample in
    /// wire order), as the firmware does: sample k (counted from the kernel's first
    /// sample, `samples`) is applied, then the tick when `(k + 1) % samples_per_period ==
    /// 0`, then the `commands` `(k, ForceEvent)` given for sample k, in order (CNC commands
    /// only). Returns `{name: array}` with one element per tick and command, the outputs
    /// after it: `time` (sample index, uint64), `kind` (wire kind, uint8), `override_pct`
    /// and `bad_events` (uint8), the flags (bool), and each I32F32 value as float64
    /// under its name and as int64 bits (value × 2^32) under `<name>_bits`.
    #[pyo3(signature = (codes, commands=None))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        codes: PyReadonlyArray2<'py, u16>,
        commands: Option<Vec<(u64, ForceEvent)>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let codes = codes.as_array();
        if codes.ncols() != CHANNELS {
            return Err(value_error(format!(
                "codes has {} columns: one sample is {CHANNELS} codes (speed, power, force, \
                 v_u, v_v, v_w, i_u, i_v)",
                codes.ncols()
            )));
        }
        let first = self.samples;
        let end = first + codes.nrows() as u64;
        let commands = commands_from(commands, first, end)?;
        let mut next = commands.iter().peekable();
        let spp = self.samples_per_period;
        let mut columns = ForceColumns::default();
        for row in codes.rows() {
            let k = self.samples;
            let mut words = [0u16; CHANNELS];
            for (w, c) in words.iter_mut().zip(row.iter()) {
                *w = *c;
            }
            self.inner.apply(ModelForceEvent::Sample(codes_from(words)));
            self.samples += 1;
            if (k + 1).is_multiple_of(spp) {
                self.inner.apply(ModelForceEvent::Tick);
                columns.push(k, &ModelForceEvent::Tick, &self.inner.outputs());
            }
            while let Some((_, e)) = next.next_if(|(at, _)| *at == k) {
                self.inner.apply(*e);
                columns.push(k, e, &self.inner.outputs());
            }
        }
        columns.into_dict(py)
    }

    /// The outputs after the last event.
    #[getter]
    fn outputs(&self) -> ForceOutputs {
        ForceOutputs {
            inner: self.inner.outputs(),
        }
    }

    /// ADC samples applied so far (the index of the next one).
    #[getter]
    fn samples(&self) -> u64 {
        self.samples
    }
}

/// `process` as `tooltouch control --process` spells it: the Kienzle law or `None` (F10).
fn kienzle_process(
    process: &str,
) -> PyResult<Option<tooltouch_plant::drive::kienzle::KienzleProcess>> {
    match process {
        "kienzle" => Ok(Some(Default::default())),
        "linear" => Ok(None),
        other => Err(value_error(format!(
            "process {other:?}: expected \"kienzle\" or \"linear\""
        ))),
    }
}

/// The ADC samples (a numpy array) and the CNC commands of a scenario.
type ScenarioStimuli<'py> = (Bound<'py, PyAny>, Vec<(u64, ForceEvent)>);

/// `tooltouch control`'s depth-step scenario closed around the model for `settings` with
/// noise `seed`: the plant's ADC samples as a uint16 array (n, 8) and the CNC commands as
/// `[(sample index, ForceEvent)]`. `ForceKernel(settings).run(codes, commands)` replays
/// the run bit for bit (the plant reacted to exactly those outputs); the CLI writes the
/// same events to `<controller>_<force>.events.ttv`. `process` as `control --process`
/// (`"kienzle"`, the default, or `"linear"`).
#[pyfunction]
#[pyo3(signature = (settings, seed=1, process="kienzle"))]
pub fn drive_scenario<'py>(
    py: Python<'py>,
    settings: &ForceSettings,
    seed: u64,
    process: &str,
) -> PyResult<ScenarioStimuli<'py>> {
    let mut sc = ControlScenario::new(settings.config);
    if kienzle_process(process)?.is_some() {
        sc = sc.with_kienzle_process();
    }
    sc.seed = seed;
    let run = py.detach(|| scenario::run(&sc, scenario::Engine::Model, true));
    let mut rows = Vec::new();
    let mut commands = Vec::new();
    for (k, e) in &run.events {
        match e {
            ModelForceEvent::Sample(c) => rows.extend_from_slice(&codes_row(c)),
            ModelForceEvent::Tick => {}
            other => commands.push((*k, ForceEvent { inner: *other })),
        }
    }
    let n = rows.len() / CHANNELS;
    let codes = Array2::from_shape_vec((n, CHANNELS), rows).map_err(value_error)?;
    Ok((codes.into_pyarray(py).into_any(), commands))
}
