//! The lathe player: a second Nucleo-F446RE that replays a golden event stream on its pins
//! at the lathe's timing, wired to the controller board's measurement inputs
//! (docs/firmware.md, "The bench": pin map, wiring and the run step by step).
//!
//! The stream is embedded in the image: `TOOLTOUCH_PLAYER_STREAM` at build time names
//! the file, the demo stream `tooltouch-events.bin` by default (build.rs). At boot the
//! player sets the clocks up (SYSCLK 168 MHz, TIM2 at 84 MHz), checks the whole stream
//! (`tooltouch_firmware::player::Schedule::new`), drives its outputs low and logs the
//! stream's summary over defmt; each press of the B1 button (PC13) plays the stream once.
//!
//! Timing: TIM2 counts at 84 MHz (one tick 11.9 ns, the schedule's resolution), free
//! running over 32 bits and extended to 64 in software; for each step the main loop
//! spins until TIM2 reaches the step's tick, then writes the step's word to GPIOC_BSRR
//! (every output is on GPIOC, so each step is one store). No interrupt is enabled, so
//! nothing delays a write but the loop itself: the worst lateness (ticks between a step's
//! time and the spin seeing it) is measured and logged after each run.

#![no_std]
#![no_main]

#[cfg(not(any(feature = "panic-check", feature = "emulated")))]
use defmt_rtt as _;

/// The `panic-check` build's defmt logger: discards every frame (defmt-rtt keeps a panic
/// path for re-entrant use, as in the controller's image).
#[cfg(feature = "panic-check")]
mod null_logger {
    #[defmt::global_logger]
    struct Null;

    // SAFETY: stateless; every method is a no-op, so any call order is sound.
    unsafe impl defmt::Logger for Null {
        fn acquire() {}
        unsafe fn flush() {}
        unsafe fn release() {}
        unsafe fn write(_bytes: &[u8]) {}
    }
}

use stm32f4::stm32f446 as pac;
use tooltouch_firmware::nucleo::{clocks, configure_clocks, PLL_TIMING};
use tooltouch_firmware::player::{PlayerError, Schedule, NUCLEO_PINS};

/// The stream to play (build.rs names the file).
static STREAM: &[u8] = include_bytes!(env!("TOOLTOUCH_PLAYER_STREAM_FILE"));

/// The B1 button, PC13 (active low).
const BUTTON: u32 = 1 << 13;

/// TIM2's count extended to 64 bits; read more often than every 2^32 ticks (51 s).
struct Clock {
    high: u64,
    last: u32,
}

impl Clock {
    fn now(&mut self, tim2: &pac::TIM2) -> u64 {
        let c = tim2.cnt().read().bits();
        if c < self.last {
            self.high = self.high.wrapping_add(1 << 32);
        }
        self.last = c;
        self.high | u64::from(c)
    }
}

/// A stream error as a message and its figure, for defmt.
fn describe(e: PlayerError) -> (&'static str, u64) {
    match e {
        PlayerError::Wire(_) => ("malformed stream", 0),
        PlayerError::NotEvents => ("not an event stream", 0),
        PlayerError::ZeroRate => ("a tick rate of 0", 0),
        PlayerError::Unplayable { kind, offset } => (
            "a record with no pin (kind << 32 | offset)",
            u64::from(kind) << 32 | offset as u64,
        ),
        PlayerError::TimeOverflow(t) => ("an event time too large for the timer", t),
        PlayerError::PulsesTooClose(at) => ("two pulses less than 2 ticks apart, at tick", at),
        PlayerError::MissingEnd => ("no END record", 0),
        PlayerError::TrailingBytes(at) => ("bytes after END (one stream only), at byte", at as u64),
    }
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else {
        // Taken only here; never happens.
        loop {
            cortex_m::asm::wfi();
        }
    };
    let timing = configure_clocks(&dp.RCC, &dp.PWR, &dp.FLASH);
    let timer_hz = if timing.sysclk_hz == PLL_TIMING.sysclk_hz {
        clocks::PLL_168_MHZ.apb1_timer_hz()
    } else {
        clocks::RESET_CLOCKS.apb1_timer_hz()
    };
    clocks::enable_peripheral_clocks(&dp.RCC);
    let gpioc = &dp.GPIOC;
    let pins = NUCLEO_PINS;
    // SAFETY (every `bits` write): BSRR takes any word; MODER / OSPEEDR get 0b01 (output)
    // / 0b11 (very high speed) for the player's pins only, PSC / ARR any value.
    gpioc.bsrr().write(|w| unsafe { w.bits(pins.all_low()) });
    let mut moder = 0;
    let mut speed = 0;
    for pin in 0..16 {
        if pins.mask() & 1 << pin != 0 {
            moder |= 0b01 << (2 * pin);
            speed |= 0b11 << (2 * pin);
        }
    }
    let two_bits = |word: u32| word | word << 1;
    gpioc
        .moder()
        .modify(|r, w| unsafe { w.bits(r.bits() & !two_bits(moder) | moder) });
    gpioc
        .ospeedr()
        .modify(|r, w| unsafe { w.bits(r.bits() | speed) });
    let tim2 = &dp.TIM2;
    tim2.psc().write(|w| unsafe { w.bits(0) });
    tim2.arr().write(|w| unsafe { w.bits(u32::MAX) });
    tim2.egr().write(|w| w.ug().set_bit());
    tim2.cr1().modify(|_, w| w.cen().set_bit());

    let summary = match Schedule::new(STREAM, timer_hz, pins) {
        Ok((header, summary, _)) => {
            defmt::info!(
                "player: {} events ({} FES pulses {} ticks wide, {} index pulses {} ticks wide, {} force records skipped), {} ticks at {} Hz; stream ticks at {} Hz, measure hash {=u64:x}; press B1 to play",
                summary.events,
                summary.fes_pulses,
                summary.fes_width,
                summary.index_pulses,
                summary.index_width,
                summary.force_skipped,
                summary.end,
                timer_hz,
                header.tick_hz,
                header.measure_hash
            );
            summary
        }
        Err(e) => {
            let (what, figure) = describe(e);
            defmt::error!("player: the stream cannot be played: {} {}", what, figure);
            loop {
                cortex_m::asm::wfi();
            }
        }
    };
    let mut clock = Clock { high: 0, last: 0 };
    loop {
        // Wait for a press of B1 (low), then for its release.
        while gpioc.idr().read().bits() & BUTTON != 0 {}
        while gpioc.idr().read().bits() & BUTTON == 0 {}
        let Ok((_, _, schedule)) = Schedule::new(STREAM, timer_hz, pins) else {
            continue;
        };
        let start = clock.now(tim2);
        let (mut steps, mut late, mut worst) = (0u32, 0u32, 0u64);
        for step in schedule {
            let due = start.wrapping_add(step.at);
            let mut now = clock.now(tim2);
            while now < due {
                now = clock.now(tim2);
            }
            gpioc.bsrr().write(|w| unsafe { w.bits(step.bsrr) });
            let lateness = now - due;
            if lateness > 0 && step.at > 0 {
                late = late.saturating_add(1);
            }
            worst = worst.max(lateness);
            steps = steps.saturating_add(1);
        }
        gpioc.bsrr().write(|w| unsafe { w.bits(pins.all_low()) });
        defmt::info!(
            "player: played {} steps in {} ticks; {} steps seen late, the worst by {} ticks",
            steps,
            summary.end,
            late,
            worst
        );
    }
}
