//! `tooltouch hdl`: Write the Verilog of the FPGA front end. (Being built: issue 5.)

/// Arguments of `tooltouch hdl`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch hdl`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch hdl` is not built yet (issue 5)")
}
