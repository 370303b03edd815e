//! `tooltouch wear`: Run the tool-wear monitoring scenario. (Being built: issue 3.)

/// Arguments of `tooltouch wear`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch wear`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch wear` is not built yet (issue 3)")
}
