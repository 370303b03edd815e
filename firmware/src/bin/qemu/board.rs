//! The QEMU board's virtual pins and registers, and the handlers' view of them
//! ([`Board`]). The co-simulation driver (`driver`) writes the inputs before it pends an
//! event's interrupt and reads the outputs back; the FES counter is virtual too (QEMU's
//! Stellaris timers have no edge-count mode): the driver counts each FES event in it and,
//! when the count reaches the compare value the handlers set, pends the compare
//! interrupt, as a timer's compare match would. So is the clock ([`TIME`]): the driver sets
//! it to each event's time stamp and pends the alarm interrupt (SSI0) at the alarm's time
//! when it falls before the next event.

use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};
use tooltouch_firmware::board::Board;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::sampling::{AdcChannel, AdcCodes};

/// Virtual pin bits in [`PINS`].
pub const ARM: u8 = 1;
/// Contact line.
pub const CONTACT: u8 = 2;
/// Scale line A.
pub const SCALE_A: u8 = 4;
/// Scale line B.
pub const SCALE_B: u8 = 8;

/// Levels of the virtual input pins, written by the driver before each pend.
pub static PINS: AtomicU8 = AtomicU8::new(0);
/// The virtual FES counter: FES events so far (wrapping).
pub static FES_COUNT: AtomicU32 = AtomicU32::new(0);
/// The virtual FES counter's compare value.
pub static FES_COMPARE: AtomicU32 = AtomicU32::new(0);
/// The "register now" output.
pub static REGISTER_NOW: AtomicBool = AtomicBool::new(false);
/// The fault output.
pub static FAULT: AtomicBool = AtomicBool::new(false);
/// The virtual clock: the stream's time, ticks, wrapping at 2^32 (set by the driver).
pub static TIME: AtomicU32 = AtomicU32::new(0);
/// The virtual clock's alarm (compare) value.
pub static TIME_ALARM: AtomicU32 = AtomicU32::new(0);
/// Whether the alarm is set.
pub static TIME_ALARM_ON: AtomicBool = AtomicBool::new(false);
/// The virtual ADC's result registers: the codes in the model's channel order
/// ([`AdcChannel::ALL`]: speed, power, force, v_u, v_v, v_w, i_u, i_v),
/// two 16-bit codes per word.
static ADC: [AtomicU32; 4] = [
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
];
/// The pending CNC force-path command: 0 none, else [`encode_command`]'s word.
pub static COMMAND: AtomicU32 = AtomicU32::new(0);
/// The value of the pending pulse-count preset (test event).
pub static PRESET: AtomicU32 = AtomicU32::new(0);
/// The feed override output, %.
pub static FEED_OVERRIDE: AtomicU8 = AtomicU8::new(0);
/// The wear alarm output.
pub static WEAR_ALARM: AtomicBool = AtomicBool::new(false);

/// A CNC command as the command register holds it: kind in bits 8..16, argument in 0..8,
/// bit 16 set (so 0 means "none").
pub fn encode_command(event: ForceEvent) -> u32 {
    let (kind, arg) = match event {
        ForceEvent::Identify(on) => (1, u32::from(on)),
        ForceEvent::Control(on) => (2, u32::from(on)),
        ForceEvent::Conditions(i) => (3, u32::from(i)),
        ForceEvent::ToolChanged => (4, 0),
        // Samples and ticks have their own interrupts.
        ForceEvent::Sample(_) | ForceEvent::Tick => (0, 0),
    };
    1 << 16 | kind << 8 | arg
}

fn decode_command(word: u32) -> Option<ForceEvent> {
    if word & 1 << 16 == 0 {
        return None;
    }
    let arg = (word & 0xff) as u8;
    match (word >> 8) & 0xff {
        1 => Some(ForceEvent::Identify(arg != 0)),
        2 => Some(ForceEvent::Control(arg != 0)),
        3 => Some(ForceEvent::Conditions(arg)),
        4 => Some(ForceEvent::ToolChanged),
        _ => None,
    }
}

/// Loads the virtual ADC's result registers with `codes`.
pub fn set_adc(codes: &AdcCodes) {
    for (reg, pair) in ADC.iter().zip(codes.to_array().chunks_exact(2)) {
        reg.store(
            u32::from(pair[0]) | u32::from(pair[1]) << 16,
            Ordering::Relaxed,
        );
    }
}

/// The QEMU board.
pub struct Qemu;

impl Board for Qemu {
    fn arm() -> bool {
        PINS.load(Ordering::Relaxed) & ARM != 0
    }
    fn contact() -> bool {
        PINS.load(Ordering::Relaxed) & CONTACT != 0
    }
    fn scale() -> (bool, bool) {
        let p = PINS.load(Ordering::Relaxed);
        (p & SCALE_A != 0, p & SCALE_B != 0)
    }
    fn fes_count() -> u32 {
        FES_COUNT.load(Ordering::Relaxed)
    }
    fn set_fes_compare(at: u32) {
        FES_COMPARE.store(at, Ordering::Relaxed);
    }
    fn pend_fes_compare() {
        rtic::pend(lm3s6965::Interrupt::GPIOD);
    }
    fn time() -> u32 {
        TIME.load(Ordering::Relaxed)
    }
    fn set_time_alarm(at: Option<u32>) {
        TIME_ALARM.store(at.unwrap_or(0), Ordering::Relaxed);
        TIME_ALARM_ON.store(at.is_some(), Ordering::Relaxed);
    }
    fn pend_time_alarm() {
        rtic::pend(lm3s6965::Interrupt::SSI0);
    }
    fn set_register_now(on: bool) {
        REGISTER_NOW.store(on, Ordering::Relaxed);
    }
    fn set_status(faults: u8, _confirmed: bool) {
        FAULT.store(faults != 0, Ordering::Relaxed);
    }
    fn adc() -> AdcCodes {
        let mut codes = [0u16; AdcChannel::COUNT];
        for (pair, reg) in codes.chunks_exact_mut(2).zip(&ADC) {
            let w = reg.load(Ordering::Relaxed);
            pair[0] = (w & 0xffff) as u16;
            pair[1] = (w >> 16) as u16;
        }
        AdcCodes::from_array(codes)
    }
    fn force_command() -> Option<ForceEvent> {
        decode_command(COMMAND.swap(0, Ordering::Relaxed))
    }
    fn set_feed_override(percent: u8) {
        FEED_OVERRIDE.store(percent, Ordering::Relaxed);
    }
    fn set_wear_alarm(on: bool) {
        WEAR_ALARM.store(on, Ordering::Relaxed);
    }
}
