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
//! time and the spin seeing it) is measured and logged after each run. Before each run
//! TIM2 is set `player::WRAP_AHEAD_TICKS` before its 32-bit wrap, so that every run crosses the
//! wrap of the 64-bit extension early.
//!
//! The `emulated` build runs under QEMU's `netduinoplus2` (docs/firmware.md lists the
//! seams): that machine has no GPIO, so B1 reads pressed and BSRR writes go nowhere. It
//! plays the stream once at boot, without B1; every BSRR write is also recorded, with the
//! tick the loop saw, to the host file `tooltouch-outputs.bin` over semihosting; TIM2
//! counts at QEMU's 1 GHz/(PSC+1) whatever RCC says, so PSC is 1 and the schedule is made
//! for `player::emulated::TIMER_HZ` (2 instructions per tick under `-icount shift=0`, as the
//! board has 2 CPU cycles per tick); the run ends with a semihosting exit (0 played, 3 a
//! stream refused, 4 the recording could not be written).

#![no_std]
#![no_main]

#[cfg(not(any(feature = "panic-check", feature = "emulated")))]
use defmt_rtt as _;

// The `panic-check` build's defmt logger is the library's (`nucleo::null_logger`).

use stm32f4::stm32f446 as pac;
#[cfg(not(feature = "emulated"))]
use tooltouch_firmware::nucleo::PLL_TIMING;
use tooltouch_firmware::nucleo::{clocks, configure_clocks};
#[cfg(feature = "emulated")]
use tooltouch_firmware::player::emulated;
use tooltouch_firmware::player::{PlayerError, Schedule, NUCLEO_PINS, WRAP_AHEAD_TICKS};

/// The stream to play (build.rs names the file).
static STREAM: &[u8] = include_bytes!(env!("TOOLTOUCH_PLAYER_STREAM_FILE"));

/// The B1 button, PC13 (active low).
#[cfg(not(feature = "emulated"))]
const BUTTON: u32 = 1 << 13;

/// The emulated build's record of every BSRR write, sent to the host file
/// `tooltouch-outputs.bin` in blocks (`player::emulated::encode_write`'s format).
#[cfg(feature = "emulated")]
mod recording {
    use tooltouch_firmware::player::emulated::{encode_write, WRITE_BYTES as STEP_BYTES};
    use tooltouch_firmware::semihosting::{create, write_all, OUTPUTS_FILE};

    /// Writes held before a block goes to the host.
    const BLOCK_STEPS: usize = 256;

    /// The open file and the block being filled.
    pub struct Recording {
        file: semihosting::fd::OwnedFd,
        block: [[u8; STEP_BYTES]; BLOCK_STEPS],
        count: usize,
        /// A write to the host failed: the recording is incomplete.
        pub failed: bool,
    }

    impl Recording {
        /// Creates (truncates) the host file; `None` if the host refuses.
        pub fn create() -> Option<Recording> {
            Some(Recording {
                file: create(OUTPUTS_FILE)?,
                block: [[0; STEP_BYTES]; BLOCK_STEPS],
                count: 0,
                failed: false,
            })
        }

        /// Records the write of `bsrr` seen at tick `at`.
        pub fn push(&mut self, at: u64, bsrr: u32) {
            if let Some(slot) = self.block.get_mut(self.count) {
                *slot = encode_write(at, bsrr);
                self.count += 1;
            }
            if self.count >= BLOCK_STEPS {
                self.flush();
            }
        }

        /// Sends the block to the host.
        pub fn flush(&mut self) {
            let bytes = self.block.get(..self.count).unwrap_or(&[]).as_flattened();
            if !bytes.is_empty() && !write_all(&self.file, bytes) {
                self.failed = true;
            }
            self.count = 0;
        }
    }
}

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
    // TIM2's rate and prescaler. Emulated: QEMU's TIM2 ignores RCC and counts at
    // 1 GHz/(PSC+1); the clock tree above still runs and falls back as on a board.
    #[cfg(not(feature = "emulated"))]
    let (timer_hz, prescaler) = if timing.sysclk_hz == PLL_TIMING.sysclk_hz {
        (clocks::PLL_168_MHZ.apb1_timer_hz(), 0)
    } else {
        (clocks::RESET_CLOCKS.apb1_timer_hz(), 0)
    };
    #[cfg(feature = "emulated")]
    let (timer_hz, prescaler) = {
        let _ = timing;
        (emulated::TIMER_HZ, emulated::PRESCALER)
    };
    clocks::enable_peripheral_clocks(&dp.RCC);
    let gpioc = &dp.GPIOC;
    let pins = NUCLEO_PINS;
    // SAFETY (every `bits` write): BSRR takes any word; MODER / OSPEEDR get 0b01 (output)
    // / 0b11 (very high speed) for the player's pins only, PSC / ARR / CNT any value.
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
    tim2.psc().write(|w| unsafe { w.bits(prescaler) });
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
            #[cfg(feature = "emulated")]
            tooltouch_firmware::semihosting::exit(emulated::exit_code::STREAM_REFUSED);
            #[cfg(not(feature = "emulated"))]
            loop {
                cortex_m::asm::wfi();
            }
        }
    };
    let mut clock = Clock { high: 0, last: 0 };
    #[cfg(feature = "emulated")]
    let Some(mut recording) = recording::Recording::create() else {
        defmt::error!("player: the recording file could not be created");
        tooltouch_firmware::semihosting::exit(emulated::exit_code::RECORDING_FAILED);
    };
    loop {
        // Wait for a press of B1 (low), then for its release (emulated: play at once).
        #[cfg(not(feature = "emulated"))]
        {
            while gpioc.idr().read().bits() & BUTTON != 0 {}
            while gpioc.idr().read().bits() & BUTTON == 0 {}
        }
        let Ok((_, _, schedule)) = Schedule::new(STREAM, timer_hz, pins) else {
            continue;
        };
        tim2.cnt()
            .write(|w| unsafe { w.bits(WRAP_AHEAD_TICKS.wrapping_neg()) });
        let start = clock.now(tim2);
        let (mut steps, mut late, mut worst) = (0u32, 0u32, 0u64);
        for step in schedule {
            let due = start.wrapping_add(step.at);
            let mut now = clock.now(tim2);
            while now < due {
                now = clock.now(tim2);
            }
            gpioc.bsrr().write(|w| unsafe { w.bits(step.bsrr) });
            #[cfg(feature = "emulated")]
            recording.push(now - start, step.bsrr);
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
        #[cfg(feature = "emulated")]
        {
            recording.flush();
            tooltouch_firmware::semihosting::exit(if recording.failed {
                emulated::exit_code::RECORDING_FAILED
            } else {
                emulated::exit_code::PLAYED
            });
        }
    }
}
