//! The board's four timers, one function each (RM0390 "General-purpose timers (TIM2 to
//! TIM5)" and "Basic timers (TIM6 and TIM7)"):
//!
//! - TIM6: the 1 kHz ADC sample tick (update interrupt);
//! - TIM3: the 20 Hz control period (update interrupt);
//! - TIM4: the feed-override PWM on PB6 (TIM4_CH1, AF2), 15.625 kHz, duty = CCR1 / 256;
//! - TIM2: the FES pulse counter on PB3 (TIM2_CH2, AF1) and its channel-1 compare
//!   interrupt, the fold's (`handlers::MeasureDomain`);
//! - TIM5: the measurement's clock, 32 bits at [`CLOCK_HZ`], and its channel-1 compare
//!   interrupt, the FES watchdog's alarm.
//!
//! Prescalers and reloads come from [`TimerSettings`], derived from a
//! [`ClockTree`](crate::nucleo::clocks::ClockTree) at compile time (84 MHz or, on the reset
//! clocks, 16 MHz timer clock). Each start loads them with an update event (UG) rather
//! than after a first period at prescaler 1, and clears the update flag that event sets
//! before its interrupt is enabled. The registers the tasks use afterwards (the FES count
//! and compare, the duty, the flags to clear) have accessors here too.

use crate::nucleo::clocks::{ClockTree, PLL_168_MHZ, RESET_CLOCKS};
use stm32f4::stm32f446 as pac;

/// The ADC sample tick (Hz), TIM6: the baked force configuration's sample rate (1 kHz by
/// default).
pub const SAMPLE_HZ: u32 = crate::baked::SAMPLE_HZ as u32;
/// TIM6's count rate (Hz): 1 µs per count (TIM6 is 16-bit).
const TIM6_COUNT_HZ: u32 = 1_000_000;
/// The control period (Hz), TIM3: the baked configuration's samples per period (20 Hz,
/// 50 samples, by default). A configuration whose rates these timers cannot divide
/// exactly fails the build ([`exact_div`]).
pub const CONTROL_HZ: u32 = exact_div(SAMPLE_HZ, crate::baked::SAMPLES_PER_PERIOD as u32);
/// TIM3's count rate (Hz): 100 µs per count (TIM3 is 16-bit).
const TIM3_COUNT_HZ: u32 = 10_000;
/// The measurement's clock (Hz), TIM5: the unit of `fes_timeout_cycles` on this board,
/// 1 µs per tick (the demo lathe's stream clock, `firmware/demo-lathe.toml`), an exact
/// division of both timer clocks.
pub const CLOCK_HZ: u32 = 1_000_000;
/// Duty steps of the feed-override PWM: TIM4 ARR = 255, duty = CCR1 / 256 (CCR1 = %).
const FEED_PWM_STEPS: u32 = 256;
/// Feed-override PWM frequency (Hz): 15.625 kHz, an exact division of both the PLL's
/// 84 MHz and the fallback's 16 MHz timer clock, so it is the same whichever runs.
pub const FEED_PWM_HZ: u32 = 15_625;

const _: () = assert!(FEED_PWM_STEPS - 1 <= 0xffff && FEED_PWM_STEPS > u8::MAX as u32);
const _: () = assert!(SAMPLE_HZ.is_multiple_of(CONTROL_HZ));

/// `clock_hz / out_hz`, which must be exact (build error otherwise).
const fn exact_div(clock_hz: u32, out_hz: u32) -> u32 {
    assert!(
        out_hz > 0 && clock_hz.is_multiple_of(out_hz),
        "clock not an exact multiple"
    );
    clock_hz / out_hz
}

/// A 16-bit timer prescaler PSC for counting at `count_hz` from `clock_hz`.
const fn prescaler(clock_hz: u32, count_hz: u32) -> u16 {
    let div = exact_div(clock_hz, count_hz);
    assert!(div >= 1 && div <= 0x1_0000, "prescaler out of 16 bits");
    (div - 1) as u16
}

/// A 16-bit auto-reload ARR for an update every `count_hz / out_hz` counts.
const fn reload16(count_hz: u32, out_hz: u32) -> u16 {
    let div = exact_div(count_hz, out_hz);
    assert!(div >= 1 && div <= 0x1_0000, "reload out of 16 bits");
    (div - 1) as u16
}

/// Prescalers and reloads of the APB1 timers for one clock tree.
#[derive(Clone, Copy)]
pub struct TimerSettings {
    /// TIM6 PSC (1 µs count) and ARR (1 kHz update).
    pub sample_psc: u16,
    /// TIM6 ARR.
    pub sample_arr: u16,
    /// TIM3 PSC (100 µs count) and ARR (20 Hz update).
    pub control_psc: u16,
    /// TIM3 ARR.
    pub control_arr: u16,
    /// TIM4 PSC for [`FEED_PWM_HZ`] with ARR = [`FEED_PWM_STEPS`] − 1.
    pub feed_pwm_psc: u16,
    /// TIM5 PSC for [`CLOCK_HZ`].
    pub clock_psc: u16,
}

impl TimerSettings {
    /// The settings for the APB1 timer clock of `tree`.
    pub const fn for_clocks(tree: &ClockTree) -> Self {
        let tim_hz = tree.apb1_timer_hz();
        TimerSettings {
            sample_psc: prescaler(tim_hz, TIM6_COUNT_HZ),
            sample_arr: reload16(TIM6_COUNT_HZ, SAMPLE_HZ),
            control_psc: prescaler(tim_hz, TIM3_COUNT_HZ),
            control_arr: reload16(TIM3_COUNT_HZ, CONTROL_HZ),
            feed_pwm_psc: prescaler(tim_hz, FEED_PWM_HZ * FEED_PWM_STEPS),
            clock_psc: prescaler(tim_hz, CLOCK_HZ),
        }
    }
}

const _: () = {
    let pll = TimerSettings::for_clocks(&PLL_168_MHZ);
    assert!(pll.sample_psc == 83 && pll.sample_arr == 999);
    assert!(pll.control_psc == 8_399 && pll.control_arr == 499);
    let reset = TimerSettings::for_clocks(&RESET_CLOCKS);
    assert!(reset.sample_psc == 15 && reset.sample_arr == 999);
    assert!(pll.feed_pwm_psc == 20 && reset.feed_pwm_psc == 3);
    assert!(pll.clock_psc == 83 && reset.clock_psc == 15);
};

/// TIM6: the 1 kHz sample tick's update interrupt.
pub fn start_sample_tick(tim6: &pac::TIM6, settings: &TimerSettings) {
    tim6.psc().write(|w| w.psc().set(settings.sample_psc));
    tim6.arr().write(|w| w.arr().set(settings.sample_arr));
    tim6.egr().write(|w| w.ug().set_bit());
    // SR's reset value clears every flag (rc_w0).
    tim6.sr().reset();
    tim6.dier().write(|w| w.uie().set_bit());
    tim6.cr1().write(|w| w.cen().set_bit());
}

/// TIM3: the 20 Hz control period's update interrupt.
pub fn start_control_period(tim3: &pac::TIM3, settings: &TimerSettings) {
    tim3.psc().write(|w| w.psc().set(settings.control_psc));
    tim3.arr().write(|w| w.arr().set(settings.control_arr));
    tim3.egr().write(|w| w.ug().set_bit());
    tim3.sr().reset();
    // Emulated: QEMU's TIM3 would raise its update every period of virtual time; the
    // stream's control ticks pend the interrupt instead, so its update stays disabled.
    #[cfg(not(feature = "emulated"))]
    tim3.dier().write(|w| w.uie().enabled());
    tim3.cr1().write(|w| w.cen().enabled());
}

/// TIM4 channel 1 on PB6 (alternate function 2): PWM mode 1 with preload, ARR = 255, so
/// [`FEED_PWM_HZ`] with duty = CCR1 / 256; CCR1 starts at 0 (output low).
pub fn start_feed_pwm(tim4: &pac::TIM4, gpiob: &pac::GPIOB, settings: &TimerSettings) {
    gpiob.moder().modify(|_, w| w.moder6().alternate());
    gpiob.afrl().modify(|_, w| w.afrl6().af2());
    tim4.psc().write(|w| w.psc().set(settings.feed_pwm_psc));
    tim4.arr()
        .write(|w| w.arr().set((FEED_PWM_STEPS - 1) as u16));
    tim4.ccmr1_output()
        .write(|w| w.oc1m().pwm_mode1().oc1pe().enabled());
    tim4.ccer().write(|w| w.cc1e().set_bit());
    tim4.egr().write(|w| w.ug().set_bit());
    tim4.cr1().write(|w| w.arpe().enabled().cen().enabled());
}

/// TIM2 counts FES rising edges on PB3 (TIM2_CH2, alternate function 1), RM0390 "External
/// clock source mode 1", its procedure for TI2: CC2S = 01 (channel 2 an input, IC2 on TI2),
/// IC2F = 0011 (a level must hold for 8 timer clocks, 95 ns at 84 MHz, to count: rejects
/// spikes on the encoder line and still counts up to about 5 MHz, 25 times the 204.8 kHz of
/// 1024 pulses per revolution at 12 000 rpm; the TI2 input is resynchronised to the timer
/// clock either way), CC2P = CC2NP = 0 (rising edge), SMS = 111 (external clock mode 1), TS
/// = 110 (TI2FP2), then CEN. PSC 0 counts every edge; ARR at its 32-bit maximum wraps the
/// count at 2^32 like the kernel's. Channel 1 is the fold's compare: CC1S = 00 and OC1M =
/// 000 (the same CCMR1 write: output compare, frozen, no preload, so a CCR1 write takes
/// effect at once), CC1E = 0 (no pin); CC1IE raises the TIM2 interrupt when the count
/// reaches CCR1. The update interrupt stays off. The pin is switched to the timer once the
/// channel is an input, so it is never driven.
pub fn start_fes_counter(tim2: &pac::TIM2, gpiob: &pac::GPIOB) {
    tim2.ccmr1_input()
        .write(|w| w.cc2s().ti2().ic2f().fck_int_n8());
    tim2.ccer()
        .write(|w| w.cc2p().clear_bit().cc2np().clear_bit());
    // TS before SMS: RM0390 asks for TS to change only while SMS = 000.
    tim2.smcr().write(|w| w.ts().ti2fp2());
    tim2.smcr().modify(|_, w| w.sms().ext_clock_mode());
    tim2.psc().write(|w| w.psc().set(0));
    tim2.arr().write(|w| w.arr().set(u32::MAX));
    gpiob.afrl().modify(|_, w| w.afrl3().af1());
    gpiob.moder().modify(|_, w| w.moder3().alternate());
    tim2.egr().write(|w| w.ug().set_bit());
    tim2.sr().reset();
    tim2.dier().write(|w| w.cc1ie().set_bit());
    tim2.cr1().write(|w| w.cen().set_bit());
}

/// TIM5: the measurement's clock, counting up at [`CLOCK_HZ`] over its whole 32 bits
/// (ARR = 2^32 − 1, wrapping like [`crate::board::Board::time`]); channel 1 an output
/// compare in frozen mode with no pin and no preload (the alarm, CC1IE: the TIM5
/// interrupt), enabled by [`set_time_alarm`].
pub fn start_clock(tim5: &pac::TIM5, settings: &TimerSettings) {
    tim5.psc().write(|w| w.psc().set(settings.clock_psc));
    tim5.arr().write(|w| w.arr().set(u32::MAX));
    tim5.ccmr1_output().write(|w| w.oc1m().frozen());
    tim5.egr().write(|w| w.ug().set_bit());
    tim5.sr().reset();
    tim5.cr1().write(|w| w.cen().set_bit());
}

/// TIM5's count: the measurement's clock, ticks of [`CLOCK_HZ`].
#[inline(always)]
pub fn time() -> u32 {
    #[cfg(feature = "emulated")]
    let now = crate::nucleo::emulated::registers::time();
    // SAFETY: a read of TIM5's counter, free-running since `init`.
    #[cfg(not(feature = "emulated"))]
    let now = unsafe { (*pac::TIM5::ptr()).cnt().read().cnt().bits() };
    now
}

/// Sets TIM5's alarm at `at` (CCR1, no preload, then CC1IE), or turns it off.
#[inline(always)]
pub fn set_time_alarm(at: Option<u32>) {
    // SAFETY: CCR1 and DIER of TIM5 are the alarm's, written only by the measurement
    // tasks (one priority, so one at a time).
    unsafe {
        let tim5 = &*pac::TIM5::ptr();
        match at {
            Some(at) => {
                tim5.ccr1().write(|w| w.ccr().set(at));
                tim5.sr().write(|w| w.cc1if().clear());
                tim5.dier().write(|w| w.cc1ie().set_bit());
            }
            None => {
                tim5.dier().write(|w| w.cc1ie().clear_bit());
            }
        }
    }
    // QEMU's TIM5 counts virtual time and never compares: the seam holds the alarm.
    #[cfg(feature = "emulated")]
    crate::nucleo::emulated::registers::set_time_alarm(at);
}

/// Clears TIM5's compare flag CC1IF.
#[inline(always)]
pub fn ack_time_alarm() {
    // SAFETY: TIM5_SR's flags clear on a written 0 (rc_w0), the others are written 1.
    unsafe { (*pac::TIM5::ptr()).sr().write(|w| w.cc1if().clear()) };
}

/// TIM2's count of FES rising edges, wrapping at 2^32.
#[inline(always)]
pub fn fes_count() -> u32 {
    #[cfg(feature = "emulated")]
    let count = crate::nucleo::emulated::registers::fes_count();
    // SAFETY: a read of TIM2's counter; TIM2 counts FES edges (set up once in `init`).
    #[cfg(not(feature = "emulated"))]
    let count = unsafe { (*pac::TIM2::ptr()).cnt().read().cnt().bits() };
    count
}

/// Sets TIM2's compare value: CCR1, 32 bits, no preload, so it takes effect at once.
#[inline(always)]
pub fn set_fes_compare(at: u32) {
    // SAFETY: CCR1 of TIM2 is the FES compare value, written only by the measurement
    // tasks (one priority, so one at a time).
    unsafe { (*pac::TIM2::ptr()).ccr1().write(|w| w.ccr().set(at)) };
    // QEMU's TIM2 keeps the write but never compares: the seam's count matches it.
    #[cfg(feature = "emulated")]
    crate::nucleo::emulated::registers::set_fes_compare(at);
}

/// Clears TIM2's compare flag CC1IF, so a match after the next compare value raises the
/// interrupt again.
#[inline(always)]
pub fn ack_fes_compare() {
    // SAFETY: TIM2_SR's flags clear on a written 0 (rc_w0); the PAC's `clear` writes 0
    // to CC1IF and 1 to every other flag, which leaves them as they are.
    unsafe { (*pac::TIM2::ptr()).sr().write(|w| w.cc1if().clear()) };
}

/// Clears TIM6's update flag (its only flag).
#[inline(always)]
pub fn ack_sample_tick() {
    // SAFETY: SR's reset value, 0, clears the flag (rc_w0); only the sample task writes it.
    unsafe { (*pac::TIM6::ptr()).sr().reset() };
}

/// Clears TIM3's flags (the update flag is the only one whose interrupt is enabled).
#[inline(always)]
pub fn ack_control_period() {
    // SAFETY: SR's reset value, 0, clears every flag (rc_w0); only the control task
    // writes it.
    unsafe { (*pac::TIM3::ptr()).sr().reset() };
}

/// Sets the feed-override PWM's duty: `percent` / 256 (TIM4 CCR1, preloaded: takes
/// effect at the next period).
#[inline(always)]
pub fn set_feed_override(percent: u8) {
    // SAFETY: CCR1 of TIM4 takes any 16-bit compare value (ARR = 255); only the force
    // tasks write it, under the force kernel's lock.
    unsafe {
        (*pac::TIM4::ptr())
            .ccr1()
            .write(|w| w.ccr().set(u16::from(percent)))
    };
}
