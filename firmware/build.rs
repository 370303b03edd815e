//! Puts the board's memory map on the linker's search path, and bakes the image's
//! configuration in.
//!
//! Memory map: the QEMU board's `memory.x` comes with the `lm3s6965` device crate; the
//! Nucleo's is `memory-nucleo.x` here.
//!
//! Configuration: with `TOOLTOUCH_FIRMWARE_CONFIG` set to a configuration file that
//! `tooltouch cosim config` wrote (`cargo xtask firmware --config settings.toml` does
//! both), the image runs that measurement and force configuration; without it, the
//! defaults. The file's canonical bytes are decoded and validated here with the golden
//! model, so a bad configuration fails the build, never the boot; `$OUT_DIR/baked_config.rs`
//! then holds the bytes (decoded again at init, by the same decoder) and their hashes.
//! A third part of the file, when present, is a reference-part calibration record
//! (model::measure::calibration): checked against the measurement configuration here (made
//! with it, its offset within the scale position), so an image never applies a
//! calibration of another configuration.

use std::fmt::Write as _;
use std::path::PathBuf;
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_model::wire::force_config::decode_force_settings;
use tooltouch_model::wire::measure_config::decode_config;
use tooltouch_model::MeasureConfig;

/// The variable that names the event stream the Nucleo's `player` image embeds.
const PLAYER_STREAM_VAR: &str = "TOOLTOUCH_PLAYER_STREAM";

/// The player's stream: `$TOOLTOUCH_PLAYER_STREAM` or the demo stream, passed to the image
/// as the absolute path `TOOLTOUCH_PLAYER_STREAM_FILE` (`include_bytes!`). Its size is
/// checked here: the image must fit in the 512 KiB flash with room for the code.
fn player_stream() {
    println!("cargo:rerun-if-env-changed={PLAYER_STREAM_VAR}");
    let path = match std::env::var_os(PLAYER_STREAM_VAR) {
        Some(p) if !p.is_empty() => PathBuf::from(p),
        _ => PathBuf::from("tooltouch-events.bin"),
    };
    let path = std::path::absolute(&path)
        .unwrap_or_else(|e| stream_fail(&format!("{PLAYER_STREAM_VAR}={}: {e}", path.display())));
    println!("cargo:rerun-if-changed={}", path.display());
    const MAX_STREAM: u64 = 448 * 1024;
    match std::fs::metadata(&path) {
        Ok(m) if m.len() > MAX_STREAM => stream_fail(&format!(
            "{PLAYER_STREAM_VAR}={}: {} bytes, more than the {MAX_STREAM} the player's flash holds",
            path.display(),
            m.len()
        )),
        Ok(_) => {}
        Err(e) => stream_fail(&format!("{PLAYER_STREAM_VAR}={}: {e}", path.display())),
    }
    println!(
        "cargo:rustc-env=TOOLTOUCH_PLAYER_STREAM_FILE={}",
        path.display()
    );
}

/// Ends the build with an error about the player's stream.
fn stream_fail(message: &str) -> ! {
    eprintln!("error: the player's event stream: {message}");
    std::process::exit(1);
}

/// The variable that names the configuration file.
const CONFIG_VAR: &str = "TOOLTOUCH_FIRMWARE_CONFIG";
/// The configuration file's first bytes (the file layout is in src/baked.rs).
const MAGIC: &[u8; 8] = b"TTFWCFG1";

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory-nucleo.x");
    println!("cargo:rerun-if-env-changed={CONFIG_VAR}");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if std::env::var_os("CARGO_FEATURE_NUCLEO").is_some() {
        std::fs::copy("memory-nucleo.x", out.join("memory.x")).expect("copying memory-nucleo.x");
        println!("cargo:rustc-link-search={}", out.display());
        player_stream();
    }
    let (measure, force, calibration, source) = match std::env::var_os(CONFIG_VAR) {
        Some(path) if !path.is_empty() => {
            let path = PathBuf::from(path);
            println!("cargo:rerun-if-changed={}", path.display());
            match read_config(&path) {
                Ok((m, f, c)) => (m, f, c, path.display().to_string()),
                Err(why) => fail(&format!("{CONFIG_VAR}={}: {why}", path.display())),
            }
        }
        _ => {
            let (m, n) = MeasureConfig::default().canonical_bytes();
            let force = ForceSettings::default()
                .validate()
                .unwrap_or_else(|e| fail(&format!("the default force configuration: {e}")));
            let (f, k) = force.canonical_bytes();
            (
                m[..n].to_vec(),
                f[..k].to_vec(),
                Vec::new(),
                "defaults".to_string(),
            )
        }
    };
    let measure_config = decode_config(&measure)
        .unwrap_or_else(|e| fail(&format!("measurement configuration: {e}")));
    let measure_hash = measure_config.hash();
    if !calibration.is_empty() {
        CalibrationRecord::decode(&calibration)
            .and_then(|c| c.check_for(&measure_config))
            .unwrap_or_else(|e| fail(&format!("calibration: {e}")));
    }
    let force_config = decode_force_settings(&force)
        .map_err(|e| format!("does not decode at byte {}", e.at))
        .and_then(|s| s.validate().map_err(|e| e.to_string()))
        .unwrap_or_else(|e| fail(&format!("force configuration: {e}")));
    let force_hash = force_config.hash();
    let rates = force_config.settings();
    let mut rs = String::new();
    let _ = writeln!(rs, "// Written by build.rs from {source}.");
    let _ = writeln!(
        rs,
        "/// Where the configuration came from: `defaults` or the file {CONFIG_VAR} named."
    );
    let _ = writeln!(rs, "pub const SOURCE: &str = {source:?};");
    let _ = writeln!(
        rs,
        "/// The measurement configuration's canonical bytes (model::wire::measure_config)."
    );
    let _ = writeln!(
        rs,
        "pub const MEASURE: [u8; {}] = {measure:?};",
        measure.len()
    );
    let _ = writeln!(
        rs,
        "/// The force configuration's canonical bytes (model::wire::force_config)."
    );
    let _ = writeln!(rs, "pub const FORCE: [u8; {}] = {force:?};", force.len());
    let _ = writeln!(
        rs,
        "/// The calibration record's canonical bytes (model::measure::calibration), empty \
         without a calibration."
    );
    let _ = writeln!(
        rs,
        "pub const CALIBRATION: [u8; {}] = {calibration:?};",
        calibration.len()
    );
    let _ = writeln!(rs, "/// `MeasureConfig::hash` of [`MEASURE`].");
    let _ = writeln!(rs, "pub const MEASURE_HASH: u64 = {measure_hash:#018x};");
    let _ = writeln!(rs, "/// `ForceConfig::hash` of [`FORCE`].");
    let _ = writeln!(rs, "pub const FORCE_HASH: u64 = {force_hash:#018x};");
    let _ = writeln!(rs, "/// The force configuration's ADC sample rate, Hz.");
    let _ = writeln!(rs, "pub const SAMPLE_HZ: u16 = {};", rates.sample_hz);
    let _ = writeln!(
        rs,
        "/// The force configuration's samples per control period."
    );
    let _ = writeln!(
        rs,
        "pub const SAMPLES_PER_PERIOD: u16 = {};",
        rates.samples_per_period
    );
    std::fs::write(out.join("baked_config.rs"), rs).expect("writing baked_config.rs");
}

/// The parts of a configuration file: measurement, force, calibration (empty when absent).
type Parts = (Vec<u8>, Vec<u8>, Vec<u8>);

/// Splits a configuration file into its measurement and force canonical bytes and the
/// optional calibration record.
fn read_config(path: &std::path::Path) -> Result<Parts, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let rest = bytes
        .strip_prefix(MAGIC.as_slice())
        .ok_or("not a firmware configuration file (write one with `tooltouch cosim config`)")?;
    let (measure, rest) = take_sized(rest).ok_or("cut short in the measurement configuration")?;
    let (force, rest) = take_sized(rest).ok_or("cut short in the force configuration")?;
    let (calibration, rest) = if rest.is_empty() {
        (&[][..], rest)
    } else {
        take_sized(rest).ok_or("cut short in the calibration record")?
    };
    if !rest.is_empty() {
        return Err(format!("{} bytes after the calibration record", rest.len()));
    }
    Ok((measure.to_vec(), force.to_vec(), calibration.to_vec()))
}

/// A u16 little-endian length, then that many bytes.
fn take_sized(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let (len, rest) = bytes.split_first_chunk::<2>()?;
    let n = usize::from(u16::from_le_bytes(*len));
    (rest.len() >= n).then(|| rest.split_at(n))
}

fn fail(message: &str) -> ! {
    eprintln!("error: baked firmware configuration: {message}");
    std::process::exit(1);
}
