//! Writes the SPI design of the default configuration (`tooltouch_hdl_gen::generate_spi`:
//! the kernel with run-time thresholds, `tt_spi`, the board top `tt_fpga_spi`) into a
//! folder, one file per module, and prints the file names in compile order:
//! `cargo run -p tooltouch-hdl-gen --example spi_design -- DIR`.

use tooltouch_hdl_gen::{generate_spi, Options};
use tooltouch_model::MeasureConfig;

fn main() -> std::io::Result<()> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "hdl-spi".into());
    std::fs::create_dir_all(&dir)?;
    let d = generate_spi(&MeasureConfig::default(), &Options::default());
    let tied = std::env::args().nth(2).as_deref() == Some("--tied");
    let extra = tied.then(|| tooltouch_hdl_gen::spi::tied_frontend(&MeasureConfig::default()));
    for f in d.files.iter().chain(extra.as_ref()) {
        std::fs::write(format!("{dir}/{}", f.name), &f.text)?;
        println!("{dir}/{}", f.name);
    }
    Ok(())
}
