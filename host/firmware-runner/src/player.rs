//! The lathe player's image (firmware/src/bin/player) under QEMU's `netduinoplus2`: its
//! `emulated` build plays its embedded stream once at boot (no B1 there), records every
//! GPIOC_BSRR write with the TIM2 tick its loop saw, and exits over semihosting. The
//! recording is the host file `tooltouch-outputs.bin`: per write 12 bytes, the tick (u64,
//! from the run's start) and the BSRR word (u32), little-endian. The defmt log is decoded
//! with defmt's own decoder, as for the controller's emulated image.
//!
//! tests/firmware/player.rs compares the recording with the schedule
//! `tooltouch_firmware::player::Schedule` makes on the host for the same stream and rate.

use super::error::CosimError;
use super::nucleo::{self, EMULATED_BUILD, MACHINE_ARGS, TARGET};
use super::qemu::{self, Artifact};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The firmware's own player module (`tooltouch_firmware::player`: the schedule, the pin
/// map, the emulated build's rate, recording format and exit statuses): the no_std crate
/// `tooltouch-player` both workspaces depend on, so each is defined once.
pub use tooltouch_player as firmware_player;

pub use firmware_player::emulated::{exit_code, TIMER_HZ as EMULATED_TIMER_HZ, WRITE_BYTES};

/// A run that takes longer is killed (the demo stream plays in about 2 s of QEMU).
pub const WATCHDOG: Duration = Duration::from_secs(120);

/// One recorded GPIOC_BSRR write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedWrite {
    /// The TIM2 tick at which the loop saw the step due (ticks from the run's start).
    pub seen_at: u64,
    /// The BSRR word written.
    pub bsrr: u32,
}

/// One QEMU run of the player.
#[derive(Clone, Debug)]
pub struct PlayerRun {
    /// QEMU's exit status ([`exit_code`]; `None` if killed by a signal).
    pub status: Option<i32>,
    /// The decoded defmt log.
    pub log: Vec<String>,
    /// Every BSRR write of the run, in order.
    pub writes: Vec<RecordedWrite>,
    /// QEMU's wall time.
    pub elapsed: Duration,
}

/// Builds the player's emulated image (release, from inside firmware/, with the demo
/// stream embedded) and returns its path, `firmware/target/images/player-emulated`.
pub fn build_emulated() -> Result<PathBuf, CosimError> {
    qemu::check_tools_for(TARGET)?;
    qemu::build_into_images(
        &EMULATED_BUILD,
        Artifact::Bin("player"),
        "player-emulated",
        None,
    )
}

/// Boots the player's emulated `image` on netduinoplus2 and reads its recording and log.
/// A run that refused its stream is no error here (its status and log say so); a QEMU that
/// cannot start or hangs, a malformed recording or log, is.
pub fn run_emulated(image: &Path) -> Result<PlayerRun, CosimError> {
    let boot = qemu::boot(&MACHINE_ARGS, image, &[], WATCHDOG, &|s| {
        format!("the player ran longer than {s} s under QEMU and was killed")
    })?;
    let elf = std::fs::read(image)
        .map_err(|e| CosimError::Io(format!("reading {}: {e}", image.display())))?;
    Ok(PlayerRun {
        status: boot.status.code(),
        log: nucleo::decode_defmt(&elf, &boot.defmt)?,
        writes: parse_recording(&boot.trace)?,
        elapsed: boot.elapsed,
    })
}

/// The writes of a recording; a length that is not a whole number of writes is an error.
pub fn parse_recording(bytes: &[u8]) -> Result<Vec<RecordedWrite>, CosimError> {
    if !bytes.len().is_multiple_of(WRITE_BYTES) {
        return Err(CosimError::Trace {
            offset: bytes.len() / WRITE_BYTES * WRITE_BYTES,
            why: format!(
                "the player's recording is {} bytes, not a whole number of {WRITE_BYTES}-byte \
                 writes",
                bytes.len()
            ),
        });
    }
    Ok(bytes
        .chunks_exact(WRITE_BYTES)
        .filter_map(|w| <&[u8; WRITE_BYTES]>::try_from(w).ok())
        .map(|w| {
            let (seen_at, bsrr) = firmware_player::emulated::decode_write(w);
            RecordedWrite { seen_at, bsrr }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recording_parses_write_by_write_and_a_partial_one_is_refused() {
        let mut bytes = Vec::new();
        for (t, w) in [(0u64, 0x0001_0000u32), (1 << 33, 0x8)] {
            bytes.extend_from_slice(&firmware_player::emulated::encode_write(t, w));
        }
        // The format: the tick, then the word, little-endian.
        assert_eq!(bytes[12..20], (1u64 << 33).to_le_bytes());
        assert_eq!(bytes[20..], 8u32.to_le_bytes());
        let writes = parse_recording(&bytes).unwrap();
        assert_eq!(
            writes,
            [
                RecordedWrite {
                    seen_at: 0,
                    bsrr: 0x0001_0000
                },
                RecordedWrite {
                    seen_at: 1 << 33,
                    bsrr: 8
                }
            ]
        );
        let e = parse_recording(&bytes[..20]).unwrap_err().to_string();
        assert!(e.contains("20 bytes, not a whole number"), "{e}");
    }
}
