//! `.ttv` binary vector streams for Python, over `tooltouch_vectors::binary`'s framing:
//! `TtvReader` reads a file record by record through a small buffer (a stream of any
//! length costs constant memory) with `RecordReader`'s checks (header, record framing,
//! time never going backwards) and its own (one END record closing the stream, nothing
//! after it), any record kind typed by its `tooltouch_model::wire` decoder; `TtvWriter`
//! writes one through `RecordWriter`, the framing the CLI uses, so a stream read and
//! written back is byte-identical.

use crate::force::{ForceEvent, ForceOutputs, ForceSettings};
use crate::model::{Event, Outputs};
use crate::settings::Settings;
use pyo3::exceptions::{PyOSError, PyOverflowError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::fs::File;
use std::io::{BufReader, BufWriter};
use std::path::PathBuf;
use tooltouch_model::wire::firmware_status::{encode_status_fields, status_fields, STATUS_FIELDS};
use tooltouch_model::wire::force_chunks::{force_config_chunks, ForceConfigAssembler};
use tooltouch_model::wire::force_event::{decode_force_event, encode_force_event};
use tooltouch_model::wire::force_outputs::{decode_force_outputs, outputs_record};
use tooltouch_model::wire::measure_config::{decode_config, encode_config};
use tooltouch_model::wire::measure_event::{decode_event, encode_event};
use tooltouch_model::wire::measure_outputs::{decode_outputs, encode_outputs};
use tooltouch_model::wire::{
    kind, Header, Record as WireRecord, StreamKind, WireError, MAX_PAYLOAD,
};
use tooltouch_settings::Settings as HostSettings;
use tooltouch_vectors::binary::{BinaryError, RecordReader, RecordWriter};
use tooltouch_vectors::firmware_error::{describe_firmware_error, FirmwareError};

/// A stream's error as Python's: an I/O failure is an `OSError`, anything wrong with the
/// stream (or a record written out of order) a `ValueError`; both name the file.
fn py_error(e: BinaryError) -> PyErr {
    match e {
        BinaryError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// The name of a record kind, as in `tooltouch_model::wire::kind` in snake case.
fn kind_name(k: u8) -> &'static str {
    match k {
        kind::MEASURE_CONFIG => "measure_config",
        kind::ARM => "arm",
        kind::CONTACT => "contact",
        kind::INDEX => "index",
        kind::FES => "fes",
        kind::SCALE => "scale",
        kind::PRESET_PULSES => "preset_pulses",
        kind::SAMPLE => "sample",
        kind::TICK => "tick",
        kind::IDENTIFY => "identify",
        kind::CONTROL => "control",
        kind::CONDITIONS => "conditions",
        kind::TOOL_CHANGED => "tool_changed",
        kind::FORCE_CONFIG_CHUNK => "force_config_chunk",
        kind::MEASURE_OUTPUTS => "measure_outputs",
        kind::FORCE_OUTPUTS => "force_outputs",
        kind::FIRMWARE_DECISION => "firmware_decision",
        kind::FIRMWARE_OBSERVE => "firmware_observe",
        kind::FIRMWARE_FORCE_PROFILE => "firmware_force_profile",
        kind::FIRMWARE_ERROR => "firmware_error",
        kind::FIRMWARE_PROFILE => "firmware_profile",
        kind::FIRMWARE_STATUS => "firmware_status",
        kind::END => "end",
        _ => "unknown",
    }
}

fn stream_name(s: StreamKind) -> &'static str {
    match s {
        StreamKind::Events => "events",
        StreamKind::Outputs => "outputs",
    }
}

/// One record of a stream.
#[pyclass(module = "tooltouch", frozen)]
pub struct Record {
    /// Kind byte (`tooltouch_model::wire::kind`).
    #[pyo3(get)]
    kind: u8,
    /// Time, ticks of the header's `tick_hz` (FPGA clocks for cycle-level streams).
    #[pyo3(get)]
    time: u64,
    payload: Vec<u8>,
    /// Decoded payload: `Event`, `Outputs`, `Settings` (a measurement configuration
    /// record, `[lathe]` at its defaults), `ForceEvent`, `ForceOutputs`, a
    /// `(total, offset, data)` tuple for a `force_config_chunk` (the reader's
    /// `force_settings` once the last chunk is read), a dict for a firmware record (see
    /// `firmware_fields`), `None` for an unknown kind.
    #[pyo3(get)]
    value: Option<Py<PyAny>>,
}

#[pymethods]
impl Record {
    /// Kind name: `measure_config`, `arm`, `contact`, `index`, `fes`, `scale`,
    /// `preset_pulses`, `measure_outputs`, a force or firmware kind, or `unknown`.
    #[getter]
    fn name(&self) -> &'static str {
        kind_name(self.kind)
    }

    /// The payload bytes as stored.
    #[getter]
    fn payload<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.payload)
    }

    fn __repr__(&self) -> String {
        format!("Record({} at {})", kind_name(self.kind), self.time)
    }
}

/// Reads a `.ttv` stream record by record: `for record in TtvReader(path): ...`.
#[pyclass(module = "tooltouch")]
pub struct TtvReader {
    file: String,
    records: RecordReader<BufReader<File>>,
    /// After the END record or an error.
    finished: bool,
    chunks: ForceConfigAssembler,
    force: Option<ForceSettings>,
}

impl TtvReader {
    fn header(&self) -> Header {
        self.records.header()
    }

    fn next_record(&mut self, py: Python<'_>) -> PyResult<Option<Record>> {
        if self.finished {
            return Ok(None);
        }
        let next = self.records.next_record().map_err(|e| {
            self.finished = true;
            py_error(e)
        })?;
        let Some((record, offset)) = next else {
            self.finished = true;
            return Err(PyValueError::new_err(format!(
                "{}: ends at byte {} without its END record (cut short?)",
                self.file,
                self.records.offset()
            )));
        };
        if record.kind == kind::END {
            self.finished = true;
            return match self.records.nothing_after_end() {
                Ok(()) => Ok(None),
                Err(BinaryError::AfterEnd { .. }) => Err(PyValueError::new_err(format!(
                    "{}: bytes after the END record at byte {offset} (two streams glued together?)",
                    self.file
                ))),
                Err(e) => Err(py_error(e)),
            };
        }
        let value = self.decode_value(py, &record, offset)?;
        Ok(Some(Record {
            kind: record.kind,
            time: record.time,
            payload: record.payload().to_vec(),
            value,
        }))
    }

    fn decode_value(
        &mut self,
        py: Python<'_>,
        record: &WireRecord,
        offset: usize,
    ) -> PyResult<Option<Py<PyAny>>> {
        let fail = |e: WireError| PyValueError::new_err(format!("{}: {e}", self.file));
        Ok(match record.kind {
            kind::MEASURE_CONFIG => {
                let config = decode_config(record.payload()).map_err(fail)?;
                let host = HostSettings {
                    measure: *config.settings(),
                    ..HostSettings::default()
                };
                Some(Py::new(py, Settings::validated(host)?)?.into_any())
            }
            kind::MEASURE_OUTPUTS => {
                let outputs = decode_outputs(record.payload()).ok_or_else(|| {
                    fail(WireError::BadLength {
                        kind: record.kind,
                        len: u8::try_from(record.payload().len()).unwrap_or(u8::MAX),
                        offset,
                    })
                })?;
                Some(Py::new(py, Outputs { inner: outputs })?.into_any())
            }
            kind::FORCE_OUTPUTS => {
                let outputs = decode_force_outputs(record.payload()).ok_or_else(|| {
                    fail(WireError::BadLength {
                        kind: record.kind,
                        len: u8::try_from(record.payload().len()).unwrap_or(u8::MAX),
                        offset,
                    })
                })?;
                Some(Py::new(py, ForceOutputs { inner: outputs })?.into_any())
            }
            kind::FORCE_CONFIG_CHUNK => {
                let p = record.payload();
                let complete = self.chunks.push(p).map_err(|e| {
                    PyValueError::new_err(format!("{}: byte {offset}: {e}", self.file))
                })?;
                if complete {
                    let config = self.chunks.finish(self.header().force_hash).map_err(|e| {
                        PyValueError::new_err(format!("{}: byte {offset}: {e}", self.file))
                    })?;
                    self.force = Some(ForceSettings { config });
                }
                let total = u16::from_le_bytes([p[0], p[1]]);
                let at = u16::from_le_bytes([p[2], p[3]]);
                let data = PyBytes::new(py, &p[4..]);
                Some((total, at, data).into_pyobject(py)?.into_any().unbind())
            }
            kind::FIRMWARE_OBSERVE
            | kind::FIRMWARE_DECISION
            | kind::FIRMWARE_FORCE_PROFILE
            | kind::FIRMWARE_ERROR
            | kind::FIRMWARE_PROFILE
            | kind::FIRMWARE_STATUS => Some(
                firmware_dict(py, record.kind, record.payload())?
                    .into_any()
                    .unbind(),
            ),
            k if (kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&k) => {
                match decode_force_event(record, offset).map_err(fail)? {
                    Some(event) => Some(Py::new(py, ForceEvent { inner: event })?.into_any()),
                    None => None,
                }
            }
            _ => match decode_event(record, offset).map_err(fail)? {
                Some(event) => Some(Py::new(py, Event { inner: event })?.into_any()),
                None => None,
            },
        })
    }
}

#[pymethods]
impl TtvReader {
    /// Opens `path` and reads its 28-byte header.
    #[new]
    fn new(path: PathBuf) -> PyResult<TtvReader> {
        let file = path.display().to_string();
        let f = File::open(&path).map_err(|e| PyOSError::new_err(format!("{file}: {e}")))?;
        let records =
            RecordReader::new(BufReader::with_capacity(1 << 16, f), &file).map_err(py_error)?;
        Ok(TtvReader {
            file,
            records,
            finished: false,
            chunks: ForceConfigAssembler::new(),
            force: None,
        })
    }

    /// `events` or `outputs`.
    #[getter]
    fn stream(&self) -> &'static str {
        stream_name(self.header().stream)
    }
    /// Ticks per second of the record times, Hz.
    #[getter]
    fn tick_hz(&self) -> u32 {
        self.header().tick_hz
    }
    /// Configuration hash of the measurement settings the stream was made with.
    #[getter]
    fn measure_hash(&self) -> u64 {
        self.header().measure_hash
    }
    /// Hash of the force configuration (0 when none).
    #[getter]
    fn force_hash(&self) -> u64 {
        self.header().force_hash
    }

    /// The force configuration reassembled from the `force_config_chunk` records read so
    /// far (its hash checked against the header's `force_hash`), None before the last.
    #[getter]
    fn force_settings(&self) -> Option<ForceSettings> {
        self.force
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&mut self, py: Python<'_>) -> PyResult<Option<Record>> {
        self.next_record(py)
    }
}

/// Writes a `.ttv` stream: the header at once, records in time order, END on `close()`
/// (or leaving a `with` block) at the last record's time.
#[pyclass(module = "tooltouch")]
pub struct TtvWriter {
    file: String,
    /// `None` once closed.
    sink: Option<RecordWriter<BufWriter<File>>>,
}

impl TtvWriter {
    fn put(&mut self, record: &WireRecord) -> PyResult<()> {
        let file = &self.file;
        self.sink
            .as_mut()
            .ok_or_else(|| PyValueError::new_err(format!("{file}: already closed")))?
            .write(record)
            .map_err(py_error)
    }
}

#[pymethods]
impl TtvWriter {
    /// Creates `path` and writes the header. `stream`: `events` or `outputs`; `tick_hz`:
    /// ticks per second of the record times; `settings`: whose configuration hash the
    /// header carries (`measure_hash` instead, for a stream made elsewhere).
    #[new]
    #[pyo3(signature = (path, stream, tick_hz, settings=None, measure_hash=None, force_hash=0))]
    fn new(
        path: PathBuf,
        stream: &str,
        tick_hz: u32,
        settings: Option<&Settings>,
        measure_hash: Option<u64>,
        force_hash: u64,
    ) -> PyResult<TtvWriter> {
        let file = path.display().to_string();
        let stream = match stream {
            "events" => StreamKind::Events,
            "outputs" => StreamKind::Outputs,
            other => {
                return Err(PyValueError::new_err(format!(
                    "stream {other:?}: expected \"events\" or \"outputs\""
                )))
            }
        };
        let measure_hash = match (settings, measure_hash) {
            (Some(s), None) => s.config.hash(),
            (None, Some(h)) => h,
            _ => {
                return Err(PyValueError::new_err(
                    "give exactly one of settings= and measure_hash=",
                ))
            }
        };
        let header = Header {
            stream,
            tick_hz,
            measure_hash,
            force_hash,
        };
        let f = File::create(&path).map_err(|e| PyOSError::new_err(format!("{file}: {e}")))?;
        let sink = RecordWriter::new(BufWriter::with_capacity(1 << 16, f), header, &file)
            .map_err(py_error)?;
        Ok(TtvWriter {
            file,
            sink: Some(sink),
        })
    }

    /// Writes a record of any kind with its payload (at most 48 bytes) as given.
    fn write_record(&mut self, kind: u8, time: u64, payload: &[u8]) -> PyResult<()> {
        if payload.len() > MAX_PAYLOAD {
            return Err(PyValueError::new_err(format!(
                "{}: a payload of {} bytes, at most {MAX_PAYLOAD} fit a record",
                self.file,
                payload.len()
            )));
        }
        if kind == kind::END {
            return Err(PyValueError::new_err(format!(
                "{}: END is written by close()",
                self.file
            )));
        }
        self.put(&WireRecord::new(kind, time, payload))
    }

    /// Writes the configuration record of `settings` (an events stream starts with it at
    /// time 0).
    fn write_config(&mut self, time: u64, settings: &Settings) -> PyResult<()> {
        let mut r = encode_config(&settings.config);
        r.time = time;
        self.put(&r)
    }

    /// Writes one measurement event at `time`.
    fn write_event(&mut self, time: u64, event: &Event) -> PyResult<()> {
        self.put(&encode_event(time, event.inner))
    }

    /// Writes one outputs record at `time`.
    fn write_outputs(&mut self, time: u64, outputs: &Outputs) -> PyResult<()> {
        self.put(&WireRecord::new(
            kind::MEASURE_OUTPUTS,
            time,
            &encode_outputs(&outputs.inner),
        ))
    }

    /// Writes one force-path event at `time` (ADC samples, ticks and CNC commands; the
    /// force streams of `tooltouch control` count time in ADC samples).
    fn write_force_event(&mut self, time: u64, event: &ForceEvent) -> PyResult<()> {
        self.put(&encode_force_event(time, &event.inner))
    }

    /// Writes one force outputs record at `time`.
    fn write_force_outputs(&mut self, time: u64, outputs: &ForceOutputs) -> PyResult<()> {
        self.put(&outputs_record(time, &outputs.inner))
    }

    /// Writes the force configuration of `settings` as `force_config_chunk` records at
    /// `time` (a force events stream starts with them at time 0; the header's
    /// `force_hash` must be `settings.force_hash`).
    fn write_force_config(&mut self, time: u64, settings: &ForceSettings) -> PyResult<()> {
        for r in force_config_chunks(&settings.config, time) {
            self.put(&r)?;
        }
        Ok(())
    }

    /// Writes a firmware record of kind `name` (`firmware_observe`, `firmware_decision`,
    /// `firmware_profile`, `firmware_force_profile`, `firmware_status`, `firmware_error`)
    /// from the dict the reader gives for it (see `firmware_fields`).
    fn write_firmware(
        &mut self,
        time: u64,
        name: &str,
        fields: &Bound<'_, PyDict>,
    ) -> PyResult<()> {
        let (k, payload) = firmware_payload(name, fields)?;
        self.put(&WireRecord::new(k, time, &payload))
    }

    /// Writes the END record at the last record's time and closes the file. Idempotent.
    fn close(&mut self) -> PyResult<()> {
        if let Some(sink) = self.sink.take() {
            sink.finish().map_err(py_error)?;
        }
        Ok(())
    }

    fn __enter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    #[pyo3(signature = (*_exc))]
    fn __exit__(&mut self, _exc: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close()?;
        Ok(false)
    }
}

/// Per-kind slots of the firmware's profile records, in payload order.
const PROFILE_SLOTS: [&str; 5] = ["arm", "contact", "index", "fes", "scale"];
/// Slots of the firmware's force profile record, in payload order.
const FORCE_PROFILE_SLOTS: [&str; 3] = ["sample", "tick", "command"];
/// The fields of a `firmware_decision` payload, each an i32 (little-endian) in turn.
const DECISION_I32: [&str; 2] = ["corrected_position", "offset"];

fn u32_at(p: &[u8], i: usize) -> Option<u32> {
    p.get(i..i + 4)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
}

fn i32_at(p: &[u8], i: usize) -> Option<i32> {
    p.get(i..i + 4)
        .and_then(|b| b.try_into().ok())
        .map(i32::from_le_bytes)
}

/// A firmware record's payload as a dict (layouts: `tooltouch_model::wire::kind`):
/// - `firmware_observe`: `observe_fes` (bool);
/// - `firmware_decision`: `corrected_position`, `offset` (i32), the decision the firmware
///   reported (the fields the payload holds);
/// - `firmware_profile`: `arm` … `scale`, each `(interrupts, systick_ticks)`;
/// - `firmware_force_profile`: `sample`, `tick`, `command`, each `(events, systick_ticks)`;
/// - `firmware_status`: `events`, `lost`, `overflowed`, `stack_bytes`,
///   `calibration_instructions`, `calibration_ticks`, `measure_hash`, `force_hash` (the
///   fields the payload holds);
/// - `firmware_error`: `code`, `wire_error`, `offset`, `detail`, `field` (bytes) and
///   `description` (the CLI's explanation).
fn firmware_dict<'py>(py: Python<'py>, k: u8, p: &[u8]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match k {
        kind::FIRMWARE_OBSERVE => d.set_item("observe_fes", p.first().is_none_or(|&b| b != 0))?,
        kind::FIRMWARE_DECISION => {
            for (i, name) in DECISION_I32.iter().enumerate() {
                if let Some(v) = i32_at(p, 4 * i) {
                    d.set_item(*name, v)?;
                }
            }
        }
        kind::FIRMWARE_PROFILE | kind::FIRMWARE_FORCE_PROFILE => {
            let slots: &[&str] = if k == kind::FIRMWARE_PROFILE {
                &PROFILE_SLOTS
            } else {
                &FORCE_PROFILE_SLOTS
            };
            for (i, name) in slots.iter().enumerate() {
                if let (Some(a), Some(b)) = (u32_at(p, 8 * i), u32_at(p, 8 * i + 4)) {
                    d.set_item(*name, (a, b))?;
                }
            }
        }
        kind::FIRMWARE_STATUS => {
            for (field, value) in status_fields(p) {
                d.set_item(field.name, value)?;
            }
        }
        _ => {
            let e = FirmwareError::decode(p);
            d.set_item("code", e.code)?;
            d.set_item("wire_error", e.wire_error)?;
            d.set_item("offset", e.offset)?;
            d.set_item("detail", e.detail)?;
            d.set_item("field", PyBytes::new(py, e.field))?;
            d.set_item("description", describe_firmware_error(p))?;
        }
    }
    Ok(d)
}

/// The kind and payload of a firmware record from its dict ([`firmware_dict`]'s keys;
/// the status and profile fields up to the first one missing; both decision fields are
/// required).
fn firmware_payload(name: &str, d: &Bound<'_, PyDict>) -> PyResult<(u8, Vec<u8>)> {
    let get = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> { d.get_item(key) };
    let mut p = Vec::new();
    let k = match name {
        "firmware_observe" => {
            let on: bool = get("observe_fes")?
                .ok_or_else(|| PyValueError::new_err("firmware_observe needs observe_fes"))?
                .extract()?;
            p.push(u8::from(on));
            kind::FIRMWARE_OBSERVE
        }
        "firmware_decision" => {
            for key in DECISION_I32 {
                let v = get(key)?.ok_or_else(|| {
                    PyValueError::new_err(format!("firmware_decision needs {key}"))
                })?;
                let v = v.extract::<i32>().map_err(|e: PyErr| {
                    if e.is_instance_of::<PyOverflowError>(d.py()) {
                        PyValueError::new_err(format!(
                            "firmware_decision: {key} must fit an i32 (-2**31 .. 2**31 - 1)"
                        ))
                    } else {
                        e
                    }
                })?;
                p.extend_from_slice(&v.to_le_bytes());
            }
            kind::FIRMWARE_DECISION
        }
        "firmware_profile" | "firmware_force_profile" => {
            let (k, slots): (u8, &[&str]) = if name == "firmware_profile" {
                (kind::FIRMWARE_PROFILE, &PROFILE_SLOTS)
            } else {
                (kind::FIRMWARE_FORCE_PROFILE, &FORCE_PROFILE_SLOTS)
            };
            for slot in slots {
                let Some(v) = get(slot)? else { break };
                let (a, b): (u32, u32) = v.extract()?;
                p.extend_from_slice(&a.to_le_bytes());
                p.extend_from_slice(&b.to_le_bytes());
            }
            k
        }
        "firmware_status" => {
            let mut values = Vec::new();
            for field in &STATUS_FIELDS {
                let Some(v) = get(field.name)? else { break };
                values.push(match field.width {
                    4 => u64::from(v.extract::<u32>()?),
                    _ => v.extract::<u64>()?,
                });
            }
            let (payload, len) = encode_status_fields(&values);
            p.extend_from_slice(&payload[..len]);
            kind::FIRMWARE_STATUS
        }
        "firmware_error" => {
            let num = |key: &str| -> PyResult<u64> {
                Ok(match get(key)? {
                    Some(v) => v.extract()?,
                    None => 0,
                })
            };
            p.push(u8::try_from(num("code")?).map_err(|_| PyValueError::new_err("code: a byte"))?);
            p.push(
                u8::try_from(num("wire_error")?)
                    .map_err(|_| PyValueError::new_err("wire_error: a byte"))?,
            );
            p.extend_from_slice(&num("offset")?.to_le_bytes());
            p.extend_from_slice(&num("detail")?.to_le_bytes());
            if let Some(field) = get("field")? {
                p.extend_from_slice(field.cast::<PyBytes>()?.as_bytes());
            }
            kind::FIRMWARE_ERROR
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "{other:?} is not a firmware record kind (firmware_observe, firmware_decision, \
                 firmware_profile, firmware_force_profile, firmware_status, firmware_error)"
            )))
        }
    };
    if p.len() > MAX_PAYLOAD {
        return Err(PyValueError::new_err(format!(
            "{name}: a payload of {} bytes, at most {MAX_PAYLOAD} fit a record",
            p.len()
        )));
    }
    Ok((k, p))
}
