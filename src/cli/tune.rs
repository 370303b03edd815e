//! `tooltouch tune`: Fixed-point tuning sweeps. (Being built: issue 6.)

/// Arguments of `tooltouch tune`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch tune`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch tune` is not built yet (issue 6)")
}
