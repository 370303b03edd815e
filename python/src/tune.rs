//! The tuning loop for Python: a sweep (`tooltouch tune`), the optimizer (`tune optimize`)
//! and the range instrumentation (`tooltouch ranges`), each run by the host crate's code and
//! returned as the CLI's JSON, parsed into Python dicts and lists (`results.json`, the
//! optimizer's log lines and answer, `ranges.json`).

use crate::force::ForceSettings;
use crate::settings::Settings;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tooltouch_tune::optimize::{self, OptimizeSpec};
use tooltouch_tune::scenario::ApproachSettings;
use tooltouch_tune::{ranges as tune_ranges, SweepSpec};

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Python objects of a JSON text (through the standard library's `json`).
fn from_json<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// Runs the sweep of a spec (TOML text, `tune --spec`'s format; `""`: the default sweep)
/// on all cores and returns `results.json` as a dict (`rows`, `force`, `spec`, …).
#[pyfunction]
#[pyo3(signature = (spec_toml=""))]
pub fn tune_sweep<'py>(py: Python<'py>, spec_toml: &str) -> PyResult<Bound<'py, PyAny>> {
    let spec = SweepSpec::from_toml(spec_toml).map_err(value_error)?;
    let results = py
        .detach(|| tooltouch_tune::run(&spec, None, &|| {}))
        .map_err(value_error)?;
    let text = serde_json::to_string(&results).map_err(value_error)?;
    from_json(py, &text)
}

/// Runs the optimizer on a spec (TOML text, `tune optimize --spec`'s format) and returns a
/// dict: `evaluations` (the log's lines), `best` (the answer's index into them, or None),
/// `stopped`, `grid_points`, `settings_toml` (the answer as `tune point`'s settings file),
/// `unmet` (without an answer: `constraint`, `tolerance`, `best`), `seconds`. A malformed
/// spec is a `ValueError` naming the key.
#[pyfunction]
pub fn tune_optimize<'py>(py: Python<'py>, spec_toml: &str) -> PyResult<Bound<'py, PyAny>> {
    let spec = OptimizeSpec::from_toml(spec_toml)
        .map_err(|e| value_error(format!("key `{}`: {}", e.parameter, e.message)))?;
    let o = py
        .detach(|| optimize::optimize(&spec, &|_| {}))
        .map_err(value_error)?;
    let text = serde_json::to_string(&o).map_err(value_error)?;
    from_json(py, &text)
}

/// The observed ranges of every register of the measurement path over the tuning
/// scenarios (seeds `1..=scenarios`) and of the force path over the control scenario — the
/// kernels' outputs and their internal registers — as `tooltouch ranges` writes them in
/// `ranges.json` (`tooltouch-ranges-2`): a dict with `registers`, each a dict (`path`,
/// `kind` — `output` or `internal` —, `name`, `format`, `bits`, `signed`, `overflow`,
/// `limits`, `min`, `max`, `saturations`, `wraps`, `headroom_bits`, `samples`).
#[pyfunction]
#[pyo3(signature = (settings=None, force=None, scenarios=8))]
pub fn ranges<'py>(
    py: Python<'py>,
    settings: Option<&Settings>,
    force: Option<&ForceSettings>,
    scenarios: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let measure = settings.map_or_else(Default::default, |s| s.config);
    let force = match force {
        Some(f) => f.config,
        None => tooltouch_model::force::config::ForceSettings::default()
            .validate()
            .map_err(value_error)?,
    };
    let r = py
        .detach(|| tune_ranges::ranges(&measure, &force, &ApproachSettings::default(), scenarios))
        .map_err(value_error)?;
    let text = serde_json::to_string(&r).map_err(value_error)?;
    from_json(py, &text)
}
