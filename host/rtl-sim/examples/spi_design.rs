//! Writes the SPI design (`tooltouch_hdl_gen::generate_spi`: the kernel with run-time
//! thresholds, `tt_spi`, the board top `tt_fpga_spi`) of a settings file's configuration,
//! or of the default one, into a folder, one file per module, and prints the file names in
//! compile order (what `cargo xtask hdl-report --boards` synthesizes):
//! `cargo run -p tooltouch-rtl-sim --example spi_design -- DIR [--config settings.toml]`.

use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_hdl_gen::{generate_spi, Options};
use tooltouch_settings::load::load_settings;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("spi_design: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let mut dir: Option<PathBuf> = None;
    let mut config: Option<PathBuf> = None;
    while let Some(a) = args.next() {
        if a == "--config" {
            let path = args
                .next()
                .ok_or_else(|| anyhow::anyhow!("--config needs a settings file"))?;
            config = Some(path.into());
        } else if dir.is_none() {
            dir = Some(a.into());
        } else {
            anyhow::bail!("usage: spi_design DIR [--config settings.toml]");
        }
    }
    let dir =
        dir.ok_or_else(|| anyhow::anyhow!("usage: spi_design DIR [--config settings.toml]"))?;
    let settings = load_settings(config.as_deref(), None)?;
    std::fs::create_dir_all(&dir)?;
    let design = generate_spi(&settings.config, &Options::default());
    for f in &design.files {
        let path = dir.join(&f.name);
        std::fs::write(&path, &f.text)?;
        println!("{}", path.display());
    }
    eprintln!(
        "configuration hash {:016x}: {} files",
        design.config_hash,
        design.files.len()
    );
    Ok(())
}
