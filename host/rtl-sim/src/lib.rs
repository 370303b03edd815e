//! Host side of the FPGA co-simulation: `$readmemh` vectors from a [`Stimulus`] and the
//! golden cycle model (`tooltouch_vectors::hex`), the Verilator and Icarus runners and the lint gates
//! ([`runner`]), the cosim comparison of both simulators with the model ([`cosim`]), the random stimuli of its property
//! tests being `tooltouch_plant::random`.
//!
//! The Verilog itself comes from `tooltouch-hdl-gen`. Their speed is timed in [`speed`].
//! The SPI design (board top `tt_fpga_spi`) is driven bit by bit under Icarus by [`spi`],
//! which also proves it equal to the constant design with its thresholds tied.
//! Beside the code, the simulator glue over the C ABI (`tooltouch-abi`): `c/tooltouch_dpi.c`
//! with `sv/` (the DPI-C package and scoreboard), `c/tooltouch_vpi.c` with `verilog/` (the
//! VPI scoreboard for Icarus, the stimulus-only bench).
//!
//! Depends on the golden model, hdl-gen, the plants and the vector formats; must not depend
//! on the firmware runners, the formal proof, LinuxCNC, tuning, plots or the command line.
//!
//! [`Stimulus`]: tooltouch_plant::stimulus::Stimulus

pub mod cosim;
pub mod runner;
pub mod speed;
pub mod spi;

use std::path::PathBuf;

/// Errors of the HDL tools.
#[derive(Debug, thiserror::Error)]
pub enum HdlError {
    /// An external tool is not installed.
    #[error("`{tool}` was not found on PATH: run `cargo xtask setup` to install it")]
    ToolMissing {
        /// The program name.
        tool: String,
    },
    /// An external tool failed.
    #[error("`{command}` failed ({status}):\n{output}")]
    ToolFailed {
        /// The command line.
        command: String,
        /// Exit status text.
        status: String,
        /// Its stdout and stderr (tail).
        output: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The stimulus cannot be written as testbench vectors.
    #[error("stimulus: {0}")]
    Stimulus(String),
    /// A lint or synthesis check found a problem.
    #[error("{check}: {details}")]
    Check {
        /// Which check.
        check: String,
        /// What it found.
        details: String,
    },
}

impl From<tooltouch_vectors::hex::HexError> for HdlError {
    fn from(e: tooltouch_vectors::hex::HexError) -> Self {
        use tooltouch_vectors::hex::HexError;
        match e {
            HexError::Stimulus(s) => HdlError::Stimulus(s),
            HexError::Io { path, source } => HdlError::Io { path, source },
        }
    }
}

/// Result alias of this module.
pub type Result<T> = std::result::Result<T, HdlError>;

/// Wraps an I/O error with its path.
pub fn io_err(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> HdlError {
    let path = path.into();
    move |source| HdlError::Io { path, source }
}

/// Writes every file of `design` (and the optional testbench) into `dir`, creating it.
/// Returns the paths in compile order.
pub fn write_design(
    dir: &std::path::Path,
    design: &tooltouch_hdl_gen::Design,
    testbench: Option<&tooltouch_hdl_gen::VerilogFile>,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    let mut paths = Vec::new();
    for f in design.files.iter().chain(testbench) {
        let p = dir.join(&f.name);
        std::fs::write(&p, &f.text).map_err(io_err(&p))?;
        paths.push(p);
    }
    Ok(paths)
}
