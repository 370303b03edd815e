//! The configuration baked into the image: the measurement and force configuration the
//! image starts with (the Nucleo runs it; the QEMU image boots with it and reports it in
//! every trace, while each replayed stream still configures the kernels from its own
//! configuration record), and their hashes, reported at boot.
//!
//! build.rs writes the canonical bytes (model::wire) from the file
//! `TOOLTOUCH_FIRMWARE_CONFIG` names, or from the defaults, after decoding and validating
//! them with the model: a bad configuration fails the build. That file, as
//! `tooltouch cosim config` writes it: `TTFWCFG1`, then the measurement configuration's
//! canonical bytes and the force configuration's, each after its length (u16,
//! little-endian), then, when a calibration is baked (`tooltouch cosim config
//! --calibration`), the calibration record's (model::measure::calibration), after its
//! length: the offset the firmware subtracts from the decision position it reports.

use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_model::wire::force_config::decode_force_settings;
use tooltouch_model::wire::measure_config::decode_config;
use tooltouch_model::MeasureConfig;

/// The constants build.rs writes.
mod generated {
    include!(concat!(env!("OUT_DIR"), "/baked_config.rs"));
}

pub use generated::{FORCE_HASH, MEASURE_HASH, SAMPLES_PER_PERIOD, SAMPLE_HZ, SOURCE};

/// The baked configuration does not decode. build.rs decodes the same bytes with the
/// same decoder, so an image that builds never returns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Undecodable;

/// The baked measurement configuration.
pub fn measure() -> Result<MeasureConfig, Undecodable> {
    decode_config(&generated::MEASURE).map_err(|_| Undecodable)
}

/// The baked force configuration.
pub fn force() -> Result<ForceConfig, Undecodable> {
    decode_force_settings(&generated::FORCE)
        .ok()
        .and_then(|s| s.validate().ok())
        .ok_or(Undecodable)
}

/// The baked calibration (`None`: none baked, the decision is reported raw).
pub fn calibration() -> Result<Option<CalibrationRecord>, Undecodable> {
    if generated::CALIBRATION.is_empty() {
        return Ok(None);
    }
    CalibrationRecord::decode(&generated::CALIBRATION)
        .map(Some)
        .map_err(|_| Undecodable)
}

/// How runs in `config` report their decision with the baked calibration (the raw
/// position when none is baked, or for another configuration). The build checks the
/// record, so it always decodes; if it did not, the decision would be reported raw.
pub fn reported_decision(config: &MeasureConfig) -> crate::handlers::ReportedDecision {
    crate::handlers::ReportedDecision::new(calibration().ok().flatten().as_ref(), config)
}

/// Length of [`boot_line`].
pub const BOOT_LINE_LEN: usize = 92;

/// `configuration measure_hash=<16 hex> force_hash=<16 hex>` and a newline, the line the
/// boards report at boot (formatted without `core::fmt`, which links panic paths).
pub fn boot_line() -> [u8; BOOT_LINE_LEN] {
    let mut line = [0u8; BOOT_LINE_LEN];
    let mut at = 0usize;
    let mut put = |bytes: &[u8]| {
        for &b in bytes {
            if let Some(slot) = line.get_mut(at) {
                *slot = b;
            }
            at = at.saturating_add(1);
        }
    };
    put(b"tooltouch firmware: configuration measure_hash=");
    put(&hex16(MEASURE_HASH));
    put(b" force_hash=");
    put(&hex16(FORCE_HASH));
    put(b"\n");
    line
}

/// `value` as 16 lower-case hex digits.
pub fn hex16(value: u64) -> [u8; 16] {
    let mut out = [0u8; 16];
    for (i, d) in out.iter_mut().enumerate() {
        let shift = 60u32.wrapping_sub(4u32.wrapping_mul(i as u32));
        let nibble = value.wrapping_shr(shift) & 0xf;
        *d = b"0123456789abcdef"
            .get(nibble as usize)
            .copied()
            .unwrap_or(b'?');
    }
    out
}
