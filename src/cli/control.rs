//! `tooltouch control`: Run the force-control depth-step scenario. (Being built: issue 3.)

/// Arguments of `tooltouch control`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `tooltouch control`.
pub fn run(_args: Args) -> anyhow::Result<std::process::ExitCode> {
    anyhow::bail!("`tooltouch control` is not built yet (issue 3)")
}
