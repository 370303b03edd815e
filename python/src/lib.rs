//! `tooltouch._tooltouch`: the golden model for Python (cocotb scoreboards, notebooks),
//! a thin PyO3 layer over `tooltouch-model` and the host crate's settings, so every value
//! is computed by the same Rust code as the CLI's and is bit-identical to it.
//!
//! Shaped for a scoreboard that must not pay Python per clock: [`FrontEnd::run`] takes a
//! numpy array of pin bytes and returns one numpy array per output, the loop staying in
//! Rust. Settings come from the CLI's own TOML files or an equal dict and are validated
//! by the CLI's code, each error a `ValueError` naming the field, its value and its allowed
//! range. `.ttv` streams are read record by record from a buffered file, never whole, and
//! VCDs change by change in numpy chunks. The force path (`ForceKernel.run`), the lathe
//! and drive scenarios and every file writer reuse the host crate's code, so the files
//! are the CLI's byte for byte.
//! The pure-Python package `tooltouch` (python/tooltouch/) re-exports these names; its
//! stubs (`_tooltouch.pyi`) document units and fixed-point formats.

mod force;
mod model;
mod settings;
mod stimulus;
mod ttv;
mod tune;
mod vcd;

use pyo3::prelude::*;
use tooltouch_model::measure::checks::fault;
use tooltouch_model::measure::frontend::pin;
use tooltouch_model::MeasureOutputs;

/// Output names, in the order of the VCD, the Verilog ports and [`MeasureOutputs::fields`].
fn output_names() -> Vec<&'static str> {
    MeasureOutputs::default().fields().map(|(n, _)| n).to_vec()
}

#[pymodule]
fn _tooltouch(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<settings::Settings>()?;
    m.add_class::<model::Outputs>()?;
    m.add_class::<model::Event>()?;
    m.add_class::<model::FrontEnd>()?;
    m.add_class::<model::Measurement>()?;
    m.add_class::<ttv::Record>()?;
    m.add_class::<ttv::TtvReader>()?;
    m.add_class::<ttv::TtvWriter>()?;
    m.add_class::<force::ForceSettings>()?;
    m.add_class::<force::ForceEvent>()?;
    m.add_class::<force::ForceOutputs>()?;
    m.add_class::<force::ForceKernel>()?;
    m.add_function(wrap_pyfunction!(force::drive_scenario, m)?)?;
    m.add_class::<stimulus::Stimulus>()?;
    m.add_function(wrap_pyfunction!(stimulus::lathe_stimulus, m)?)?;
    m.add_function(wrap_pyfunction!(stimulus::read_stimulus, m)?)?;
    m.add_function(wrap_pyfunction!(stimulus::read_expect_hex, m)?)?;
    m.add_class::<vcd::VcdReader>()?;
    m.add_function(wrap_pyfunction!(tune::tune_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(tune::tune_optimize, m)?)?;
    m.add_function(wrap_pyfunction!(tune::ranges, m)?)?;
    m.add("PIN_ARM", pin::ARM)?;
    m.add("PIN_CONTACT", pin::CONTACT)?;
    m.add("PIN_INDEX", pin::INDEX)?;
    m.add("PIN_FES", pin::FES)?;
    m.add("PIN_SCALE_A", pin::SCALE_A)?;
    m.add("PIN_SCALE_B", pin::SCALE_B)?;
    m.add("PIN_NAMES", pin::NAMES.to_vec())?;
    m.add("OUTPUT_NAMES", output_names())?;
    m.add("FAULT_NAMES", fault::NAMES.to_vec())?;
    m.add("FAULT_CONTACT_AT_ARM", fault::CONTACT_AT_ARM)?;
    m.add("FAULT_PULSES_LOST", fault::PULSES_LOST)?;
    m.add("FAULT_INDEX_MISSING", fault::INDEX_MISSING)?;
    m.add("FAULT_SCALE_ERROR", fault::SCALE_ERROR)?;
    m.add("FAULT_NO_DECISION", fault::NO_DECISION)?;
    m.add("FAULT_FES_TIMEOUT", fault::FES_TIMEOUT)?;
    m.add("FAULT_UNCONFIRMED", fault::UNCONFIRMED)?;
    Ok(())
}
