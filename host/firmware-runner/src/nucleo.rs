//! The Nucleo-F446RE image executed: its `emulated` build (the driver in firmware/src/bin/
//! nucleo/emulated/, the seams in firmware/src/nucleo/emulated/) booted on QEMU's `netduinoplus2` (STM32F405, Cortex-M4F), driven over
//! semihosting like the lm3s6965 image, its trace checked against the golden model by
//! [`crate::check_batch`], and its defmt log decoded with defmt's own decoder
//! (`defmt-decoder`) from the frames the image writes to `tooltouch-defmt.bin`.
//!
//! The image's measurement tasks run on the Nucleo's interrupts in the Nucleo's order
//! (EXTI0, EXTI1, EXTI2, EXTI9_5, TIM2, TIM7 at one priority): the driver pends them as
//! the pins' edges and TIM2's compare match would. The board has no input for the
//! cutting-conditions command nor for the pulse-count preset test event: [`for_nucleo`]
//! drops the first from a case, and a stream holding either is reported as lost events.

use super::error::CosimError;
use super::qemu::{self, Artifact, MachineRun};
use super::{check_calibrated_batch, encode_batch, Case, Observe, Report};
use std::path::{Path, PathBuf};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::measure::calibration::CalibrationRecord;
use tooltouch_settings::firmware_config::FirmwareConfig;

/// The Nucleo's target triple.
pub const TARGET: &str = "thumbv7em-none-eabihf";
/// The cargo arguments of the emulated build (from inside firmware/).
pub const EMULATED_BUILD: [&str; 5] = [
    "--target",
    TARGET,
    "--no-default-features",
    "--features",
    "emulated",
];
/// QEMU arguments before the image: the STM32F405 machine, semihosting to the host's files,
/// `-icount shift=0` (1 ns of virtual time per instruction, as for the lm3s6965 image).
pub const MACHINE_ARGS: [&str; 11] = [
    "-machine",
    "netduinoplus2",
    "-nographic",
    "-monitor",
    "none",
    "-serial",
    "none",
    "-semihosting-config",
    "enable=on,target=native",
    "-icount",
    "shift=0",
];

/// Builds the emulated Nucleo image with the default configuration and returns its path
/// (copied to `firmware/target/images/nucleo-emulated`, under the images' build lock).
pub fn build_emulated() -> Result<PathBuf, CosimError> {
    build_emulated_image(None)
}

/// Builds the emulated Nucleo image with `config` baked in and returns its path
/// (`firmware/target/images/nucleo-emulated-<configuration's image name>`).
pub fn build_configured_emulated(config: &FirmwareConfig) -> Result<PathBuf, CosimError> {
    build_emulated_image(Some(config))
}

fn build_emulated_image(config: Option<&FirmwareConfig>) -> Result<PathBuf, CosimError> {
    qemu::check_tools_for(TARGET)?;
    let name = match config {
        Some(c) => format!("nucleo-emulated-{}", c.image_name()),
        None => "nucleo-emulated".to_string(),
    };
    let baked = config.map(FirmwareConfig::baked_bytes);
    qemu::build_into_images(
        &EMULATED_BUILD,
        Artifact::Bin("nucleo"),
        &name,
        baked.as_deref(),
    )
}

/// `case` as the Nucleo can receive it: without the cutting-conditions commands (no pin
/// on this board: it runs condition set 0). The golden model is run on the same events.
pub fn for_nucleo(case: &Case) -> Case {
    let mut c = case.clone();
    c.force_events
        .retain(|(_, e)| !matches!(e, ForceEvent::Conditions(_)));
    c
}

/// One batch on the emulated Nucleo: the checked report and the decoded defmt log.
#[derive(Clone, Debug)]
pub struct NucleoRun {
    /// The batch's report, every case checked.
    pub report: Report,
    /// The defmt log, one decoded message per frame.
    pub log: Vec<String>,
}

/// Runs every case in one `netduinoplus2` boot of `image`, checks each against the golden
/// model (every output after every event `observe` names) and decodes the defmt log.
pub fn run_batch(image: &Path, cases: &[Case], observe: Observe) -> Result<NucleoRun, CosimError> {
    run_calibrated_batch(image, cases, observe, None)
}

/// [`run_batch`] on an image built with `calibration` baked in: its reported decisions
/// are checked against [`crate::golden_decisions`] of that calibration.
pub fn run_calibrated_batch(
    image: &Path,
    cases: &[Case],
    observe: Observe,
    calibration: Option<&CalibrationRecord>,
) -> Result<NucleoRun, CosimError> {
    let MachineRun {
        trace,
        elapsed,
        defmt,
    } = qemu::run_machine(&MACHINE_ARGS, image, &encode_batch(cases, observe))?;
    let report = check_calibrated_batch(cases, observe, calibration, &trace, elapsed)?;
    let elf = std::fs::read(image)
        .map_err(|e| CosimError::Io(format!("reading {}: {e}", image.display())))?;
    Ok(NucleoRun {
        report,
        log: decode_defmt(&elf, &defmt)?,
    })
}

/// Decodes the defmt `frames` an image wrote with the `.defmt` table of its `elf`; a
/// malformed frame, or bytes left after the last whole frame, is an error.
pub fn decode_defmt(elf: &[u8], frames: &[u8]) -> Result<Vec<String>, CosimError> {
    use defmt_decoder::{DecodeError, Table};
    let bad = |why: String| CosimError::Trace { offset: 0, why };
    let table = Table::parse(elf)
        .map_err(|e| bad(format!("the image's defmt table: {e}")))?
        .ok_or_else(|| bad("the image has no defmt table".into()))?;
    let mut decoder = table.new_stream_decoder();
    decoder.received(frames);
    let mut log = Vec::new();
    loop {
        match decoder.decode() {
            Ok(frame) => log.push(frame.display_message().to_string()),
            Err(DecodeError::UnexpectedEof) => break,
            Err(DecodeError::Malformed) => {
                return Err(bad(format!(
                    "defmt frame {} is malformed (after: {:?})",
                    log.len(),
                    log.last()
                )))
            }
        }
    }
    Ok(log)
}
