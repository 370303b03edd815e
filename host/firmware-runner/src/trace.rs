//! Reading the firmware's output trace: per input stream, an `Outputs` header, one
//! `MEASURE_OUTPUTS` record per event, the firmware's profile and status records, `END`;
//! or an error record that says why the firmware rejected its input.

use super::error::CosimError;
use tooltouch_model::force::kernel::ForceOutputs;
use tooltouch_model::wire::firmware_status::FirmwareStatus;
use tooltouch_model::wire::force_outputs::decode_force_outputs;
use tooltouch_model::wire::measure_outputs::decode_outputs;
use tooltouch_model::wire::{self, Header, Record, StreamKind, HEADER_LEN};
use tooltouch_model::MeasureOutputs;
use tooltouch_vectors::firmware_error::describe_firmware_error;

/// Record kinds the firmware adds, and its input option (model::wire, shared with the
/// firmware).
pub use tooltouch_model::wire::kind;

/// Names of the event kinds in [`Profile::per_kind`]'s order.
pub const EVENT_KIND_NAMES: [&str; 8] = [
    "arm",
    "contact",
    "index",
    "fes compare",
    "scale",
    "adc sample",
    "control period",
    "force command",
];

/// What the firmware measured about itself during one stream.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Profile {
    /// Per event kind (arm, contact, index, FES, scale, ADC sample, control period, force
    /// command): interrupts taken and SysTick ticks spent from the pend to the return
    /// (interrupt entry, handler, exit; a control period includes applying its samples).
    /// FES pulses are counted, not interrupts: their slot holds the counter's compare
    /// interrupts.
    pub per_kind: [(u32, u32); 8],
    /// Events replayed.
    pub events: u32,
    /// Edges lost (interrupt still pending at the next edge).
    pub lost: u32,
    /// Samples dropped by a full queue.
    pub overflowed: u32,
    /// Stack bytes used (watermark since boot).
    pub stack_bytes: u32,
    /// Instructions of the calibration loop.
    pub calibration_instructions: u32,
    /// SysTick ticks of the calibration loop.
    pub calibration_ticks: u32,
    /// The hashes of the configuration baked into the image (measurement, force), from
    /// the end of its status record; `None` for an image that does not report them.
    pub image_hashes: Option<(u64, u64)>,
}

impl Profile {
    /// Instructions per SysTick tick (QEMU `-icount shift=0`: a fixed virtual time per
    /// instruction), from the calibration loop.
    pub fn instructions_per_tick(&self) -> f64 {
        f64::from(self.calibration_instructions) / f64::from(self.calibration_ticks.max(1))
    }

    /// Takes the firmware's status record's fields (its counters, the image's hashes).
    pub fn set_status(&mut self, status: FirmwareStatus) {
        let FirmwareStatus {
            events,
            lost,
            overflowed,
            stack_bytes,
            calibration_instructions,
            calibration_ticks,
            image_hashes,
        } = status;
        *self = Profile {
            per_kind: self.per_kind,
            events,
            lost,
            overflowed,
            stack_bytes,
            calibration_instructions,
            calibration_ticks,
            image_hashes,
        };
    }

    /// Mean instructions per interrupt of kind `k` (index into [`EVENT_KIND_NAMES`]), pend
    /// to return.
    pub fn instructions_per_event(&self, k: usize) -> Option<f64> {
        let (n, ticks) = *self.per_kind.get(k)?;
        (n > 0).then(|| f64::from(ticks) * self.instructions_per_tick() / f64::from(n))
    }
}

/// One stream of the firmware's trace.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StreamTrace {
    /// The header's configuration hash.
    pub measure_hash: u64,
    /// Measurement outputs after each measurement event, with the event's time.
    pub outputs: Vec<(u64, MeasureOutputs)>,
    /// Force outputs after each force event except samples, with the event's time.
    pub force_outputs: Vec<(u64, ForceOutputs)>,
    /// The decisions the firmware reported ([`kind::FIRMWARE_DECISION`]), with their time:
    /// the corrected position and the offset applied, scale counts.
    pub decisions: Vec<(u64, ReportedDecision)>,
    /// The firmware's profile and status.
    pub profile: Profile,
}

/// A decision as the firmware reports it: the latched position corrected by the baked
/// calibration (model::measure::calibration).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReportedDecision {
    /// `decision_position − offset`, wrapped to `scale_bits`, counts.
    pub position: i32,
    /// The offset applied, counts (0 without a calibration for the configuration).
    pub offset: i32,
}

fn u32_at(p: &[u8], i: usize) -> u32 {
    p.get(i..i + 4)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
        .unwrap_or(0)
}

/// Parses the whole trace file `bytes` into its streams.
pub fn parse(bytes: &[u8]) -> Result<Vec<StreamTrace>, CosimError> {
    let bad = |offset: usize, why: String| CosimError::Trace { offset, why };
    let mut streams = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        let rest = &bytes[at..];
        // An error record may follow the last complete stream directly.
        if rest.first() == Some(&kind::FIRMWARE_ERROR) {
            let (record, _) = Record::decode(rest, at).map_err(|e| bad(at, e.to_string()))?;
            return Err(CosimError::Firmware(describe_firmware_error(
                record.payload(),
            )));
        }
        let header = Header::decode(rest).map_err(|e| bad(at, e.to_string()))?;
        if header.stream != StreamKind::Outputs {
            return Err(bad(at, "header is not an output trace".into()));
        }
        at += HEADER_LEN;
        let mut stream = StreamTrace {
            measure_hash: header.measure_hash,
            ..Default::default()
        };
        loop {
            let (record, n) = Record::decode(bytes.get(at..).unwrap_or(&[]), at)
                .map_err(|e| bad(at, e.to_string()))?;
            let p = record.payload();
            match record.kind {
                wire::kind::MEASURE_OUTPUTS => {
                    let o = decode_outputs(p)
                        .ok_or_else(|| bad(at, format!("outputs record of {} bytes", p.len())))?;
                    stream.outputs.push((record.time, o));
                }
                wire::kind::FORCE_OUTPUTS => {
                    let o = decode_force_outputs(p).ok_or_else(|| {
                        bad(at, format!("force outputs record of {} bytes", p.len()))
                    })?;
                    stream.force_outputs.push((record.time, o));
                }
                kind::FIRMWARE_DECISION => {
                    if p.len() != 8 {
                        return Err(bad(at, format!("decision record of {} bytes", p.len())));
                    }
                    stream.decisions.push((
                        record.time,
                        ReportedDecision {
                            position: u32_at(p, 0) as i32,
                            offset: u32_at(p, 4) as i32,
                        },
                    ));
                }
                kind::FIRMWARE_PROFILE => {
                    for (k, slot) in stream.profile.per_kind.iter_mut().take(5).enumerate() {
                        *slot = (u32_at(p, 8 * k), u32_at(p, 8 * k + 4));
                    }
                }
                kind::FIRMWARE_FORCE_PROFILE => {
                    for (k, slot) in stream.profile.per_kind.iter_mut().skip(5).enumerate() {
                        *slot = (u32_at(p, 8 * k), u32_at(p, 8 * k + 4));
                    }
                }
                kind::FIRMWARE_STATUS => stream.profile.set_status(FirmwareStatus::decode(p)),
                kind::FIRMWARE_ERROR => {
                    return Err(CosimError::Firmware(describe_firmware_error(p)));
                }
                wire::kind::END => {
                    at += n;
                    break;
                }
                other => return Err(bad(at, format!("unexpected record kind {other:#04x}"))),
            }
            at += n;
        }
        streams.push(stream);
    }
    Ok(streams)
}
