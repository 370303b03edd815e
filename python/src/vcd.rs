//! VCD files for Python: `VcdReader`, the host crate's streaming reader
//! (`tooltouch_vectors::vcd::VcdReader`, the one `tooltouch check` uses) handing the
//! value changes to Python in numpy chunks, so a dump of any length (the golden VCD,
//! a simulator's `dump.vcd`) is read in constant memory and without a Python call per
//! change. Writing the golden VCD is `Stimulus.write_vcd`.

use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::fs::File;
use std::io::BufReader;
use std::path::PathBuf;
use tooltouch_vectors::vcd::{golden_end, Item, VcdReader as HostReader};

/// Reads a VCD's declarations at once and its body chunk by chunk.
#[pyclass(module = "tooltouch", unsendable)]
pub struct VcdReader {
    inner: HostReader<BufReader<File>>,
    time_fs: u64,
    done: bool,
}

#[pymethods]
impl VcdReader {
    /// Opens `path` and reads its declarations (up to `$enddefinitions`).
    #[new]
    fn new(path: PathBuf) -> PyResult<VcdReader> {
        let file = path.display().to_string();
        let f = File::open(&path).map_err(|e| PyOSError::new_err(format!("{file}: {e}")))?;
        let inner = HostReader::new(BufReader::with_capacity(1 << 20, f), &file)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(VcdReader {
            inner,
            time_fs: 0,
            done: false,
        })
    }

    /// Every `$var` in file order: `(scope, name, width, code)`, scope the dotted path
    /// (`tooltouch.outputs`), width in bits, code the dense index of its identifier code
    /// (the `code` column of `read`; variables of one net share it).
    #[getter]
    fn signals(&self) -> Vec<(String, String, u32, usize)> {
        let d = self.inner.declarations();
        d.signals
            .iter()
            .map(|s| {
                (
                    s.scope.join("."),
                    s.name.clone(),
                    s.width,
                    d.code_index(&s.id).unwrap_or(usize::MAX),
                )
            })
            .collect()
    }

    /// The code of the signal `name` in a scope whose path ends with `scope` (any scope
    /// when None: the shallowest, outputs before inputs, as `tooltouch check` matches);
    /// `KeyError` if there is none.
    #[pyo3(signature = (name, scope=None))]
    fn code(&self, name: &str, scope: Option<&str>) -> PyResult<usize> {
        let d = self.inner.declarations();
        let s = match scope {
            Some(scope) => d.find_in_scope(scope, name),
            None => d.find_shallowest(name),
        };
        s.and_then(|s| d.code_index(&s.id)).ok_or_else(|| {
            pyo3::exceptions::PyKeyError::new_err(format!(
                "{}: no signal {name:?}{}",
                self.inner.file(),
                scope
                    .map(|s| format!(" in scope {s:?}"))
                    .unwrap_or_default()
            ))
        })
    }

    /// Femtoseconds per unit of the file's `$timescale`.
    #[getter]
    fn timescale_fs(&self) -> u64 {
        self.inner.declarations().timescale_fs
    }

    /// `(measure_hash, clock_hz)` of a golden VCD's stamp comment, else None.
    #[getter]
    fn golden_stamp(&self) -> Option<(u64, u32)> {
        self.inner.declarations().golden_stamp()
    }

    /// The clocks a golden VCD covers (its closing `tooltouch end cycles=<n>` comment),
    /// known once the body is read to its end; None before, or for another tool's dump.
    #[getter]
    fn end_cycles(&self) -> Option<u64> {
        golden_end(self.inner.late_comments())
    }

    /// The time of the last `#` read, fs (the file's last time once read to the end).
    #[getter]
    fn time_fs(&self) -> u64 {
        self.time_fs
    }

    /// The next at most `max_changes` value changes as `{"time_fs": uint64, "code":
    /// uint32, "bits": uint64, "unknown": bool}` arrays (x/z bits read 0 and set
    /// `unknown`); None once the file is read to its end. Errors (times going backwards,
    /// an unknown code, a value wider than its signal) name the file and line.
    #[pyo3(signature = (max_changes=65536))]
    fn read<'py>(
        &mut self,
        py: Python<'py>,
        max_changes: usize,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        if self.done {
            return Ok(None);
        }
        let max = max_changes.max(1);
        let (mut times, mut codes, mut bits, mut unknown) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        while codes.len() < max {
            match self
                .inner
                .next_item()
                .map_err(|e| PyValueError::new_err(e.to_string()))?
            {
                None => {
                    self.done = true;
                    break;
                }
                Some(Item::Time(t)) => self.time_fs = t,
                Some(Item::Change(code, value)) => {
                    let Some(number) = value.to_u64() else {
                        return Err(PyValueError::new_err(format!(
                            "{}: line {}: a value wider than 64 bits",
                            self.inner.file(),
                            self.inner.line()
                        )));
                    };
                    times.push(self.time_fs);
                    codes.push(u32::try_from(code).unwrap_or(u32::MAX));
                    bits.push(number);
                    unknown.push(value.unknown);
                }
            }
        }
        if codes.is_empty() && self.done {
            return Ok(None);
        }
        let d = PyDict::new(py);
        d.set_item("time_fs", PyArray1::from_vec(py, times))?;
        d.set_item("code", PyArray1::from_vec(py, codes))?;
        d.set_item("bits", PyArray1::from_vec(py, bits))?;
        d.set_item("unknown", PyArray1::from_vec(py, unknown))?;
        Ok(Some(d))
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    /// `read()` with the default chunk size: `for chunk in VcdReader(path): ...`.
    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.read(py, 65536)
    }
}
