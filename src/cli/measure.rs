//! `tooltouch measure`: Simulate in-process diameter measurements on a lathe with the golden model. (Being built: issue 2.)

/// Arguments of `tooltouch measure`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch measure`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch measure` is not built yet (issue 2)")
}
