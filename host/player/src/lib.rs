//! The lathe player's schedule: a measurement event stream (model::wire, as `tooltouch
//! vectors` and the co-simulation write it) turned into GPIO writes at the lathe's timing,
//! for a second board that drives the controller's measurement inputs (docs/firmware.md,
//! "The bench").
//!
//! Every step is one write of a GPIO port's BSRR word at a time counted in the player's
//! timer ticks: an event at stream time `t` (ticks of the header's `tick_hz`) is played at
//! `round(t * timer_hz / tick_hz)`, so each step is within half a timer tick of its event
//! (the resolution is one tick: 11.9 ns with TIM2 at 84 MHz). Levels (arm, contact, scale
//! A / B) set or reset their pins; an index or FES event is a pulse: its pin rises at the
//! event and falls `width` ticks later, `width` being half the shortest gap between two
//! pulses of that kind in the stream (at most [`MAX_PULSE_TICKS`]), so that the pulses
//! form a square wave at the fastest rate and every pulse is high and low for at least one
//! tick. Steps come in time order; steps of the same tick in the stream's order (a fall
//! before an event of its tick).
//!
//! Only the measurement path is played: the configuration records and the co-simulation's
//! input option are skipped, force-path records are skipped and counted (the force inputs
//! are analog and command lines the bench does not drive), and a record with no pin (the
//! `PRESET_PULSES` test event) is an error. [`Schedule::new`] checks the whole stream before
//! the first step, so a bad stream is refused before any pin moves.
//!
//! Board-independent and allocation-free: the host tests (firmware/tests/handlers/player.rs)
//! check it, the `player` image plays it (as `tooltouch_firmware::player`), and the host
//! reads the emulated image's recording with the same definitions (`tooltouch-firmware-runner`).
//!
//! `no_std`; depends on the golden model only (firmware and host workspaces both use it by
//! path); must not depend on any board crate or host library.

#![no_std]

use tooltouch_model::wire::measure_event::decode_event;
use tooltouch_model::wire::{kind, Header, Records, StreamKind, WireError};
use tooltouch_model::MeasureEvent;

/// The player's output pins: bit numbers on one GPIO port, so that every step is one BSRR
/// write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PinMap {
    /// Arm (to the controller's PA0).
    pub arm: u8,
    /// Contact (to PA1).
    pub contact: u8,
    /// Index (to PB2).
    pub index: u8,
    /// FES (to PB3, TIM2's external clock).
    pub fes: u8,
    /// Scale A (to PB8).
    pub scale_a: u8,
    /// Scale B (to PB9).
    pub scale_b: u8,
}

/// The Nucleo player's pins, all on GPIOC: PC0 arm, PC1 contact, PC2 index, PC3 FES,
/// PC8 scale A, PC9 scale B (the wiring table is in docs/firmware.md).
pub const NUCLEO_PINS: PinMap = PinMap {
    arm: 0,
    contact: 1,
    index: 2,
    fes: 3,
    scale_a: 8,
    scale_b: 9,
};

/// The player timer's clock on the Nucleo: TIM2 on APB1 (42 MHz) times 2 at SYSCLK 168 MHz.
pub const NUCLEO_TIMER_HZ: u32 = 84_000_000;

/// Longest pulse, in timer ticks of 84 MHz: 1 ms (pulses this far apart need no wider).
pub const MAX_PULSE_TICKS: u64 = 84_000;

/// The player timer's count at the start of a run: this many ticks before its 32-bit wrap
/// (6 ms at 84 MHz, 1 ms at the emulated 500 MHz), so every run crosses the wrap of the
/// 64-bit extension early.
pub const WRAP_AHEAD_TICKS: u32 = 500_000;

/// The player image under QEMU's `netduinoplus2` (its `emulated` build) and the host that
/// reads its recording (`tooltouch_firmware_runner::player`): one definition of the rate, the
/// recording's format and the exit statuses.
pub mod emulated {
    /// TIM2's prescaler: QEMU's timers count at 1 GHz/(PSC+1) whatever RCC says.
    pub const PRESCALER: u32 = 1;
    /// TIM2's rate, Hz: 2 instructions per tick under `-icount shift=0`, as the board has
    /// 2 CPU cycles per tick.
    pub const TIMER_HZ: u32 = 500_000_000;
    /// Bytes of one recorded BSRR write: the tick the loop saw (u64, from the run's
    /// start), then the word (u32), little-endian.
    pub const WRITE_BYTES: usize = 12;

    /// One recorded write's bytes.
    pub fn encode_write(seen_at: u64, bsrr: u32) -> [u8; WRITE_BYTES] {
        let (t, w) = (seen_at.to_le_bytes(), bsrr.to_le_bytes());
        [
            t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], w[0], w[1], w[2], w[3],
        ]
    }

    /// The (tick, word) of one recorded write.
    pub fn decode_write(b: &[u8; WRITE_BYTES]) -> (u64, u32) {
        (
            u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
            u32::from_le_bytes([b[8], b[9], b[10], b[11]]),
        )
    }

    /// The run's semihosting exit status.
    pub mod exit_code {
        /// Played once, the whole recording written.
        pub const PLAYED: u8 = 0;
        /// The embedded stream was refused (the log says why).
        pub const STREAM_REFUSED: u8 = 3;
        /// The recording could not be created or written.
        pub const RECORDING_FAILED: u8 = 4;
    }
}

impl PinMap {
    /// Every output pin as a BSRR reset word (all low).
    pub const fn all_low(&self) -> u32 {
        let pins = 1u32 << self.arm
            | 1 << self.contact
            | 1 << self.index
            | 1 << self.fes
            | 1 << self.scale_a
            | 1 << self.scale_b;
        pins << 16
    }

    /// The pins' mask on the port (for MODER / ODR).
    pub const fn mask(&self) -> u32 {
        self.all_low() >> 16
    }
}

/// The BSRR bit that drives pin `pin` to `level`.
const fn drive(pin: u8, level: bool) -> u32 {
    let bit = 1u32 << (pin & 15);
    if level {
        bit
    } else {
        bit << 16
    }
}

/// One GPIO write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Step {
    /// When, in timer ticks from the start of the run.
    pub at: u64,
    /// The BSRR word (bits 0..16 set pins, 16..32 reset them).
    pub bsrr: u32,
    /// What the step plays.
    pub what: StepKind,
}

/// What a [`Step`] plays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepKind {
    /// A measurement event of the stream (index and FES: the pulse's rising edge).
    Event(MeasureEvent),
    /// The falling edge of the index pulse.
    IndexFall,
    /// The falling edge of an FES pulse.
    FesFall,
}

/// Why a stream cannot be played.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlayerError {
    /// A malformed stream.
    Wire(WireError),
    /// The header is not an event stream's.
    NotEvents,
    /// The header's `tick_hz` or the timer's rate is 0.
    ZeroRate,
    /// A record the player cannot play (`kind` at byte `offset`).
    Unplayable {
        /// The record's kind.
        kind: u8,
        /// Its byte offset.
        offset: usize,
    },
    /// An event's time in timer ticks does not fit in 64 bits (its stream time).
    TimeOverflow(u64),
    /// Two pulses of one kind less than 2 timer ticks apart (the second one's time in
    /// timer ticks): they cannot be played as separate pulses.
    PulsesTooClose(u64),
    /// The stream has no `END` record.
    MissingEnd,
    /// Bytes follow the stream's `END` (another stream: the player plays one).
    TrailingBytes(usize),
}

/// What a stream holds, from [`Schedule::new`]'s check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    /// Measurement events played.
    pub events: u32,
    /// FES pulses.
    pub fes_pulses: u32,
    /// Index pulses.
    pub index_pulses: u32,
    /// Force-path records skipped.
    pub force_skipped: u32,
    /// Width of an FES pulse, timer ticks.
    pub fes_width: u64,
    /// Width of an index pulse, timer ticks.
    pub index_width: u64,
    /// Time of the last step, timer ticks.
    pub end: u64,
}

/// Stream-time to timer-tick conversion, reduced by the rates' greatest common divisor.
#[derive(Clone, Copy, Debug)]
struct Rate {
    num: u64,
    den: u64,
}

impl Rate {
    fn new(tick_hz: u32, timer_hz: u32) -> Result<Rate, PlayerError> {
        if tick_hz == 0 || timer_hz == 0 {
            return Err(PlayerError::ZeroRate);
        }
        let (mut a, mut b) = (u64::from(tick_hz), u64::from(timer_hz));
        while b != 0 {
            let r = a % b;
            a = b;
            b = r;
        }
        Ok(Rate {
            num: u64::from(timer_hz) / a,
            den: u64::from(tick_hz) / a,
        })
    }

    /// `round(t * num / den)`.
    fn ticks(&self, t: u64) -> Result<u64, PlayerError> {
        let scaled = t
            .checked_mul(self.num)
            .and_then(|x| x.checked_add(self.den / 2))
            .ok_or(PlayerError::TimeOverflow(t))?;
        Ok(scaled / self.den.max(1))
    }
}

/// A pin event of a record, `Ok(None)` for a record the player skips.
fn playable(
    record: &tooltouch_model::wire::Record,
    offset: usize,
) -> Result<Option<MeasureEvent>, PlayerError> {
    match record.kind {
        kind::MEASURE_CONFIG | kind::FIRMWARE_OBSERVE | kind::END => return Ok(None),
        k if (kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&k) => return Ok(None),
        _ => {}
    }
    match decode_event(record, offset).map_err(PlayerError::Wire)? {
        Some(MeasureEvent::PresetPulses(_)) | None => Err(PlayerError::Unplayable {
            kind: record.kind,
            offset,
        }),
        Some(e) => Ok(Some(e)),
    }
}

/// The steps of one stream, in time order (an iterator; see the module doc).
pub struct Schedule<'a> {
    records: Records<'a>,
    offset: usize,
    rate: Rate,
    pins: PinMap,
    summary: Summary,
    /// The next event's step, read ahead of pending falls.
    next: Option<Step>,
    index_fall: Option<u64>,
    fes_fall: Option<u64>,
}

impl<'a> Schedule<'a> {
    /// Checks the whole stream `bytes` (one event stream) for a timer of `timer_hz` and
    /// pins `pins`; returns the stream's header and summary and the schedule.
    pub fn new(
        bytes: &'a [u8],
        timer_hz: u32,
        pins: PinMap,
    ) -> Result<(Header, Summary, Schedule<'a>), PlayerError> {
        let (header, records) = Records::new(bytes).map_err(PlayerError::Wire)?;
        if header.stream != StreamKind::Events {
            return Err(PlayerError::NotEvents);
        }
        let rate = Rate::new(header.tick_hz, timer_hz)?;
        // Check pass: every record, the pulses' shortest gaps, the end.
        let mut summary = Summary::default();
        let (mut last_index, mut last_fes) = (None::<u64>, None::<u64>);
        let (mut gap_index, mut gap_fes) = (u64::MAX, u64::MAX);
        let mut ended = false;
        let mut last_event = 0;
        let mut offset = tooltouch_model::wire::HEADER_LEN;
        for item in records {
            let record = item.map_err(PlayerError::Wire)?;
            let at_offset = offset;
            offset = offset.saturating_add(record.encoded_len());
            if record.kind == kind::END {
                ended = true;
                rate.ticks(record.time)?;
                break;
            }
            if (kind::FORCE_FIRST..=kind::FORCE_LAST).contains(&record.kind) {
                summary.force_skipped = summary.force_skipped.saturating_add(1);
            }
            let Some(event) = playable(&record, at_offset)? else {
                continue;
            };
            let at = rate.ticks(record.time)?;
            last_event = at;
            summary.events = summary.events.saturating_add(1);
            let (last, gap, count) = match event {
                MeasureEvent::Index => (&mut last_index, &mut gap_index, &mut summary.index_pulses),
                MeasureEvent::Fes => (&mut last_fes, &mut gap_fes, &mut summary.fes_pulses),
                _ => continue,
            };
            if let Some(prev) = *last {
                let d = at.saturating_sub(prev);
                if d < 2 {
                    return Err(PlayerError::PulsesTooClose(at));
                }
                *gap = (*gap).min(d);
            }
            *last = Some(at);
            *count = count.saturating_add(1);
        }
        if !ended {
            return Err(PlayerError::MissingEnd);
        }
        if offset < bytes.len() {
            return Err(PlayerError::TrailingBytes(offset));
        }
        let width = |gap: u64| (gap / 2).clamp(1, MAX_PULSE_TICKS);
        summary.index_width = width(gap_index);
        summary.fes_width = width(gap_fes);
        // The last step: the last event or the fall of a pulse before it.
        let fall = |last: Option<u64>, w: u64| last.map_or(0, |t| t.saturating_add(w));
        summary.end = last_event
            .max(fall(last_index, summary.index_width))
            .max(fall(last_fes, summary.fes_width));
        let (_, replay) = Records::new(bytes).map_err(PlayerError::Wire)?;
        let schedule = Schedule {
            records: replay,
            offset: tooltouch_model::wire::HEADER_LEN,
            rate,
            pins,
            summary,
            next: None,
            index_fall: None,
            fes_fall: None,
        };
        Ok((header, summary, schedule))
    }

    /// The step of `event` at `at`.
    fn event_step(&self, event: MeasureEvent, at: u64) -> Step {
        let p = &self.pins;
        let bsrr = match event {
            MeasureEvent::Arm(level) => drive(p.arm, level),
            MeasureEvent::Contact(level) => drive(p.contact, level),
            MeasureEvent::Index => drive(p.index, true),
            MeasureEvent::Fes => drive(p.fes, true),
            MeasureEvent::Scale { a, b } => drive(p.scale_a, a) | drive(p.scale_b, b),
            // Refused by the check pass.
            MeasureEvent::PresetPulses(_) => 0,
        };
        Step {
            at,
            bsrr,
            what: StepKind::Event(event),
        }
    }

    /// Reads the next playable event into `self.next` (checked by [`Schedule::new`], so
    /// errors cannot occur here; one would end the schedule).
    fn read_ahead(&mut self) {
        while self.next.is_none() {
            let Some(Ok(record)) = self.records.next() else {
                return;
            };
            let at_offset = self.offset;
            self.offset = self.offset.saturating_add(record.encoded_len());
            if record.kind == kind::END {
                return;
            }
            if let (Ok(Some(event)), Ok(at)) =
                (playable(&record, at_offset), self.rate.ticks(record.time))
            {
                self.next = Some(self.event_step(event, at));
            }
        }
    }
}

impl Iterator for Schedule<'_> {
    type Item = Step;

    fn next(&mut self) -> Option<Step> {
        self.read_ahead();
        // The earliest of the pending falls and the next event; a fall first on a tie.
        let event_at = self.next.map_or(u64::MAX, |s| s.at);
        let index_at = self.index_fall.unwrap_or(u64::MAX);
        let fes_at = self.fes_fall.unwrap_or(u64::MAX);
        if self.index_fall.is_some() && index_at <= event_at && index_at <= fes_at {
            self.index_fall = None;
            return Some(Step {
                at: index_at,
                bsrr: drive(self.pins.index, false),
                what: StepKind::IndexFall,
            });
        }
        if self.fes_fall.is_some() && fes_at <= event_at {
            self.fes_fall = None;
            return Some(Step {
                at: fes_at,
                bsrr: drive(self.pins.fes, false),
                what: StepKind::FesFall,
            });
        }
        let step = self.next.take()?;
        match step.what {
            StepKind::Event(MeasureEvent::Index) => {
                self.index_fall = Some(step.at.saturating_add(self.summary.index_width));
            }
            StepKind::Event(MeasureEvent::Fes) => {
                self.fes_fall = Some(step.at.saturating_add(self.summary.fes_width));
            }
            _ => {}
        }
        Some(step)
    }
}
