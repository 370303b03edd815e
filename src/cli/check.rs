//! `tooltouch check`: Compare a device-under-test trace with the golden expected trace. (Being built: issue 2.)

/// Arguments of `tooltouch check`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch check`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch check` is not built yet (issue 2)")
}
