//! The one registry of record kinds: every kind byte of the vector format, measurement,
//! force and firmware alike, so a new kind is added where all the others are visible and
//! a test proves no two share a byte.
//!
//! Ranges: `0x01..=0x1f` measurement inputs, `0x20..=0x3f` force-path inputs, `0x40`
//! measurement outputs, `0x41..=0x5f` other output traces (the force outputs from the
//! bottom, the firmware co-simulation's records from the top), `0x7f` end of stream. Each
//! payload's layout is documented by its encoder in the `wire` module named in the kind's
//! doc.

// ---- measurement inputs (`wire::measure_config`, `wire::measure_event`) ----

/// The measurement configuration's canonical bytes (starts an event stream).
pub const MEASURE_CONFIG: u8 = 0x01;
/// Arm line changed; payload: level (1 byte).
pub const ARM: u8 = 0x02;
/// Contact line changed; payload: level (1 byte).
pub const CONTACT: u8 = 0x03;
/// Index pulse; no payload.
pub const INDEX: u8 = 0x04;
/// FES pulse; no payload.
pub const FES: u8 = 0x05;
/// Scale lines changed; payload: bit 0 = A, bit 1 = B.
pub const SCALE: u8 = 0x06;
/// Test event: preset the FES pulse count; payload: the count (u32).
pub const PRESET_PULSES: u8 = 0x07;

// ---- force-path inputs (`wire::force_event`, `wire::force_chunks`) ----

/// First kind reserved for the force path.
pub const FORCE_FIRST: u8 = 0x20;
/// [`crate::force::events::ForceEvent::Sample`]; payload: speed, power, force, v_u, v_v,
/// v_w, i_u, i_v as u16 LE (16 bytes).
pub const SAMPLE: u8 = 0x20;
/// [`crate::force::events::ForceEvent::Tick`]; no payload.
pub const TICK: u8 = 0x21;
/// [`crate::force::events::ForceEvent::Identify`]; payload: level (1 byte).
pub const IDENTIFY: u8 = 0x22;
/// [`crate::force::events::ForceEvent::Control`]; payload: level (1 byte).
pub const CONTROL: u8 = 0x23;
/// [`crate::force::events::ForceEvent::Conditions`]; payload: index (1 byte).
pub const CONDITIONS: u8 = 0x24;
/// [`crate::force::events::ForceEvent::ToolChanged`]; no payload.
pub const TOOL_CHANGED: u8 = 0x25;
/// One piece of the force configuration's canonical encoding
/// ([`crate::force::config::ForceConfig::canonical_bytes`]); payload: total length u16 LE,
/// byte offset u16 LE, then 1..=44 bytes of the encoding from that offset. An events
/// stream whose header has a non-zero `force_hash` carries the chunks right after its
/// `MEASURE_CONFIG` record, in order, starting at offset 0, without gaps or overlaps.
pub const FORCE_CONFIG_CHUNK: u8 = 0x26;
/// Last kind reserved for the force path.
pub const FORCE_LAST: u8 = 0x3f;

// ---- output traces (`wire::measure_outputs`, `wire::force_outputs`) ----

/// Measurement outputs after an event (32 bytes, see `wire::measure_outputs`).
pub const MEASURE_OUTPUTS: u8 = 0x40;
/// First kind reserved for other output traces.
pub const OUTPUT_FIRST: u8 = 0x41;
/// [`crate::force::kernel::ForceOutputs`] (43 bytes, see `wire::force_outputs`).
pub const FORCE_OUTPUTS: u8 = 0x41;

// ---- the firmware co-simulation (firmware/src/cosim.rs writes and reads them, the host's
// `tooltouch::cosim` reads and writes them), counted down from the top of the output range
// so the force path can take its bottom ----

/// The decision as the firmware reports it, after the `MEASURE_OUTPUTS` record of the
/// event whose outputs first show "register now" since the previous outputs record:
/// the corrected position i32 (`decision_position − offset`, wrapped to `scale_bits`,
/// [`crate::measure::calibration::corrected_position`]) and the offset applied i32
/// (scale counts, 0 without a calibration for the stream's configuration), 8 bytes.
pub const FIRMWARE_DECISION: u8 = 0x5a;
/// Input, before the first event of a stream: which measurement events get an outputs
/// record. Payload u8: 1 = every event (the default), 0 = every event but FES pulses,
/// whose runs the firmware then folds into the kernel many at a time, as on a board.
pub const FIRMWARE_OBSERVE: u8 = 0x5b;
/// Per force event kind (sample, tick, command): events u32 and SysTick ticks u32,
/// 24 bytes. A tick's ticks include applying the period's queued samples.
pub const FIRMWARE_FORCE_PROFILE: u8 = 0x5c;
/// The input was rejected; payload: code u8, wire error u8, byte offset u64, detail u64,
/// then for a force configuration field out of range the field's name (UTF-8, up to
/// 30 bytes).
pub const FIRMWARE_ERROR: u8 = 0x5d;
/// Per event kind (arm, contact, index, FES, scale): interrupts u32 and SysTick ticks
/// u32 spent in them (pend to return), 40 bytes. FES: the counter's compare
/// interrupts (most FES events raise none).
pub const FIRMWARE_PROFILE: u8 = 0x5e;
/// The firmware's status after a stream (`wire::firmware_status`): events u32, lost u32,
/// overflowed u32, stack bytes used u32, calibration instructions u32, calibration ticks
/// u32 (24 bytes), then the measure and force hashes (u64 each) of the configuration baked
/// into the image: 40 bytes.
pub const FIRMWARE_STATUS: u8 = 0x5f;
/// Last kind reserved for other output traces.
pub const OUTPUT_LAST: u8 = 0x5f;

// ---- framing ----

/// End of stream; no payload.
pub const END: u8 = 0x7f;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind that names a record (range markers excluded), with its name.
    const KINDS: [(u8, &str); 22] = [
        (MEASURE_CONFIG, "MEASURE_CONFIG"),
        (ARM, "ARM"),
        (CONTACT, "CONTACT"),
        (INDEX, "INDEX"),
        (FES, "FES"),
        (SCALE, "SCALE"),
        (PRESET_PULSES, "PRESET_PULSES"),
        (SAMPLE, "SAMPLE"),
        (TICK, "TICK"),
        (IDENTIFY, "IDENTIFY"),
        (CONTROL, "CONTROL"),
        (CONDITIONS, "CONDITIONS"),
        (TOOL_CHANGED, "TOOL_CHANGED"),
        (FORCE_CONFIG_CHUNK, "FORCE_CONFIG_CHUNK"),
        (MEASURE_OUTPUTS, "MEASURE_OUTPUTS"),
        (FORCE_OUTPUTS, "FORCE_OUTPUTS"),
        (FIRMWARE_DECISION, "FIRMWARE_DECISION"),
        (FIRMWARE_OBSERVE, "FIRMWARE_OBSERVE"),
        (FIRMWARE_FORCE_PROFILE, "FIRMWARE_FORCE_PROFILE"),
        (FIRMWARE_ERROR, "FIRMWARE_ERROR"),
        (FIRMWARE_PROFILE, "FIRMWARE_PROFILE"),
        (FIRMWARE_STATUS, "FIRMWARE_STATUS"),
    ];

    #[test]
    fn every_kind_is_distinct() {
        for (i, (k, name)) in KINDS.iter().enumerate() {
            for (other, other_name) in &KINDS[..i] {
                assert_ne!(k, other, "{name} and {other_name} share {k:#04x}");
            }
            assert_ne!(*k, END, "{name} is END");
            assert_ne!(*k, 0, "{name} is 0");
        }
    }

    #[test]
    fn force_inputs_are_inside_the_force_range() {
        for k in [
            SAMPLE,
            TICK,
            IDENTIFY,
            CONTROL,
            CONDITIONS,
            TOOL_CHANGED,
            FORCE_CONFIG_CHUNK,
        ] {
            assert!((FORCE_FIRST..=FORCE_LAST).contains(&k), "{k:#x}");
        }
        for k in [
            MEASURE_CONFIG,
            ARM,
            CONTACT,
            INDEX,
            FES,
            SCALE,
            PRESET_PULSES,
        ] {
            assert!(k < FORCE_FIRST, "{k:#x}");
        }
    }

    #[test]
    fn firmware_kinds_are_distinct_and_inside_the_output_trace_range() {
        let kinds = [
            FIRMWARE_DECISION,
            FIRMWARE_OBSERVE,
            FIRMWARE_FORCE_PROFILE,
            FIRMWARE_ERROR,
            FIRMWARE_PROFILE,
            FIRMWARE_STATUS,
        ];
        for (i, k) in kinds.iter().enumerate() {
            assert!((OUTPUT_FIRST..=OUTPUT_LAST).contains(k), "{k:#x}");
            assert!(!kinds[..i].contains(k), "{k:#x} twice");
        }
        assert!((OUTPUT_FIRST..=OUTPUT_LAST).contains(&FORCE_OUTPUTS));
    }
}
