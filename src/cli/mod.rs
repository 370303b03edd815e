//! Command-line interface: one module per subcommand.

pub mod check;
pub mod control;
pub mod hdl;
pub mod measure;
pub mod tune;
pub mod vectors;
pub mod wear;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Simulate in-process measurement and force control on a CNC lathe with the golden
/// fixed-point model; write and check test vectors.
#[derive(Parser, Debug)]
#[command(name = "tooltouch", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Simulate in-process diameter measurements on a lathe with the golden model.
    Measure(measure::Args),
    /// Compare a device-under-test trace with the golden expected trace.
    Check(check::Args),
    /// Compute the golden response to your own stimulus (VCD of the pins, event stream,
    /// run-length pins) as VCD, testbench vectors and firmware streams.
    Vectors(vectors::Args),
    /// Run the force-control depth-step scenario.
    Control(control::Args),
    /// Run the tool-wear monitoring scenario.
    Wear(wear::Args),
    /// Write the Verilog of the FPGA front end.
    Hdl(hdl::Args),
    /// Fixed-point tuning sweeps.
    Tune(tune::Args),
}

/// Parses the arguments, runs the subcommand, and reports an error with its context.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Measure(args) => measure::run(args),
        Command::Check(args) => check::run(args),
        Command::Vectors(args) => vectors::run(args),
        Command::Control(args) => control::run(args),
        Command::Wear(args) => wear::run(args),
        Command::Hdl(args) => hdl::run(args),
        Command::Tune(args) => tune::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
