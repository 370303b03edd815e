//! Writes the Verilog of the default configuration and its testbench into a folder:
//! `cargo run -p tooltouch-hdl-gen --example dump -- DIR`.

use tooltouch_hdl_gen::{generate, testbench, Options, TestbenchSpec};
use tooltouch_model::MeasureConfig;

fn main() -> std::io::Result<()> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "hdl-out".into());
    std::fs::create_dir_all(&dir)?;
    let c = MeasureConfig::default();
    let d = generate(&c, &Options::default());
    let spec = TestbenchSpec {
        clock_hz: 50_000_000,
        stim_depth: 1 << 16,
        expect_depth: 1 << 16,
        mcu_diagnostics: false,
    };
    let tb = testbench(&c, &spec).into_iter();
    for f in d.files.iter().cloned().chain(tb) {
        std::fs::write(format!("{dir}/{}", f.name), f.text)?;
        println!("{dir}/{}", f.name);
    }
    Ok(())
}
