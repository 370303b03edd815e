//! `Settings`: the CLI's settings file (`[measure]` and `[lathe]`), read and validated by
//! the host crate's own `tooltouch_settings`, so a file the CLI refuses is refused here
//! with the same message. A dict is turned into the same TOML value first, so dict and
//! file take one path.

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::path::PathBuf;
use tooltouch_model::{MeasureConfig, MeasureOutputs};
use tooltouch_settings::{Settings as HostSettings, SettingsError};

/// Validated settings: the model's configuration and the simulated lathe.
#[pyclass(module = "tooltouch", frozen)]
#[derive(Clone)]
pub struct Settings {
    pub(crate) host: HostSettings,
    pub(crate) config: MeasureConfig,
}

/// A settings error as the Python exception a user expects: a file that cannot be read is
/// an `OSError`, everything else (TOML syntax, unknown or out-of-range field) a `ValueError`.
fn to_py_err(e: SettingsError) -> PyErr {
    match e {
        SettingsError::Io(m) => PyOSError::new_err(m),
        other => PyValueError::new_err(other.to_string()),
    }
}

impl Settings {
    /// Validates `host` (both tables) into settings.
    pub(crate) fn validated(host: HostSettings) -> PyResult<Settings> {
        let (config, _) = host.resolve().map_err(to_py_err)?;
        Ok(Settings { host, config })
    }
}

/// A Python value as TOML: bool, int, float, str, dict (str keys), list or tuple.
fn to_toml(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    if let Ok(b) = value.extract::<bool>() {
        return Ok(toml::Value::Boolean(b));
    }
    if let Ok(i) = value.extract::<i64>() {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(f) = value.extract::<f64>() {
        return Ok(toml::Value::Float(f));
    }
    if let Ok(s) = value.extract::<String>() {
        return Ok(toml::Value::String(s));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyValueError::new_err(format!("settings {path}: keys must be strings"))
            })?;
            let inner = format!("{path}.{key}");
            table.insert(key, to_toml(&v, inner.trim_start_matches('.'))?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, v) in value.try_iter()?.enumerate() {
            items.push(to_toml(&v?, &format!("{path}[{i}]"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    Err(PyValueError::new_err(format!(
        "settings {path}: a {} is not a settings value (bool, int, float, str, dict or list)",
        value.get_type().name()?
    )))
}

#[pymethods]
impl Settings {
    /// Settings from a dict shaped like the TOML file (`{"measure": {...}, "lathe":
    /// {...}}`); `None` or `{}` gives the defaults.
    #[new]
    #[pyo3(signature = (table=None))]
    fn new(table: Option<&Bound<'_, PyDict>>) -> PyResult<Settings> {
        let value = match table {
            Some(t) => to_toml(t.as_any(), "")?,
            None => toml::Value::Table(toml::Table::new()),
        };
        let host: HostSettings = value
            .try_into()
            .map_err(|e: toml::de::Error| PyValueError::new_err(format!("settings: {e}")))?;
        Settings::validated(host)
    }

    /// Reads a settings file, as `tooltouch measure --config PATH` does.
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<Settings> {
        Settings::validated(HostSettings::load(&path).map_err(to_py_err)?)
    }

    /// Parses settings from TOML text.
    #[staticmethod]
    fn from_toml_str(text: &str) -> PyResult<Settings> {
        Settings::validated(HostSettings::parse(text, "<string>").map_err(to_py_err)?)
    }

    /// The settings as TOML text, every field written (a file the CLI reads back).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.host).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// 64-bit FNV-1a hash of the model configuration's canonical bytes: the hash stamped
    /// in `.ttv` headers, golden VCDs and the generated Verilog.
    #[getter]
    fn config_hash(&self) -> u64 {
        self.config.hash()
    }

    /// FPGA clock, Hz (`[lathe] clock_hz`).
    #[getter]
    fn clock_hz(&self) -> u32 {
        self.host.lathe.clock_hz
    }

    /// Glitch filter length, clocks (`[measure] glitch_cycles`).
    #[getter]
    fn glitch_cycles(&self) -> u8 {
        self.config.settings().glitch_cycles
    }

    /// Clocks from a pin change to the outputs that react to it: `3 + glitch_cycles`.
    #[getter]
    fn latency_cycles(&self) -> u32 {
        self.config.latency_cycles()
    }

    /// Every output's `(name, register width in bits)`, in `OUTPUT_NAMES` order.
    #[getter]
    fn output_widths(&self) -> Vec<(&'static str, u32)> {
        MeasureOutputs::widths(&self.config).to_vec()
    }

    fn __eq__(&self, other: &Settings) -> bool {
        self.host == other.host
    }

    fn __repr__(&self) -> String {
        format!("Settings(config_hash=0x{:016x})", self.config.hash())
    }
}
