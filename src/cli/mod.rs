//! Command-line interface: one module per subcommand.

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
enum Command {}

/// Parses the arguments, runs the subcommand, and reports an error with its context.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {};
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
