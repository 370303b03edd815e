//! The seams of the emulated Nucleo: the registers `netduinoplus2` does not emulate,
//! held in memory. The co-simulation driver sets the inputs before it pends an event's
//! interrupt, as an edge on the pin would; the board code reads and drives them through
//! the same functions that touch the hardware registers in the flashable image
//! (`pins`, `timers`, `adc` pick these with `#[cfg(feature = "emulated")]`).

use crate::model::MeasureConfig;
use core::cell::Cell;
use core::sync::atomic::{AtomicU16, AtomicU32, Ordering};
use cortex_m::interrupt::Mutex;

/// GPIOA_IDR (QEMU: GPIO not emulated, reads 0): PA0 arm, PA1 contact.
static IDR_A: AtomicU32 = AtomicU32::new(0);
/// GPIOB_IDR: PB8, PB9 scale A, B.
static IDR_B: AtomicU32 = AtomicU32::new(0);
/// GPIOC_IDR: PC11 control on, PC12 identification, PC13 the B1 button (active low).
static IDR_C: AtomicU32 = AtomicU32::new(1 << 13);
/// GPIOA_ODR as the BSRR writes set it: PA5 register now, PA6 wear alarm.
static ODR_A: AtomicU32 = AtomicU32::new(0);
/// EXTI_PR bits of the command lines 11–13 (QEMU's EXTI sets PR only from its GPIO
/// inputs, which nothing drives there).
static EXTI_PR: AtomicU32 = AtomicU32::new(0);
/// TIM2_CNT in external clock mode 1: FES rising edges (QEMU's TIM2 counts virtual time).
static FES_COUNT: AtomicU32 = AtomicU32::new(0);
/// TIM2_CCR1, the compare value (QEMU keeps 16 bits of it and never matches).
static FES_COMPARE: AtomicU32 = AtomicU32::new(0);
/// TIM5_CNT, the measurement's clock (QEMU's TIM5 counts its own virtual time): the
/// stream's time, set by the driver.
static TIME: AtomicU32 = AtomicU32::new(0);
/// TIM5_CCR1 and CC1IE, the clock's alarm (QEMU's TIM5 never compares).
static TIME_ALARM: Mutex<Cell<Option<u32>>> = Mutex::new(Cell::new(None));
/// ADC1_DR per channel (QEMU's ADC never sets EOC): the 12-bit code a conversion gives.
static ADC_RESULTS: [AtomicU16; 16] = [const { AtomicU16::new(0) }; 16];
/// The configuration of a fresh measurement kernel for `observe` to install (the driver's reset of the
/// measurement domain, which only the measurement tasks may touch).
static RESET: Mutex<Cell<Option<MeasureConfig>>> = Mutex::new(Cell::new(None));

/// GPIOA_IDR.
pub fn idr_a() -> u32 {
    IDR_A.load(Ordering::Relaxed)
}
/// GPIOB_IDR.
pub fn idr_b() -> u32 {
    IDR_B.load(Ordering::Relaxed)
}
/// GPIOC_IDR.
pub fn idr_c() -> u32 {
    IDR_C.load(Ordering::Relaxed)
}
/// GPIOA_ODR.
pub fn odr_a() -> u32 {
    ODR_A.load(Ordering::Relaxed)
}
/// A GPIOA_BSRR write: bits 0–15 set, 16–31 reset (set wins, as on the chip).
pub fn bsrr_a(bits: u32) {
    let odr = ODR_A.load(Ordering::Relaxed);
    ODR_A.store((odr & !(bits >> 16)) | (bits & 0xffff), Ordering::Relaxed);
}
/// EXTI_PR (command lines).
pub fn exti_pr() -> u32 {
    EXTI_PR.load(Ordering::Relaxed)
}
/// An EXTI_PR write: 1 clears (QEMU's EXTI_PR gets the write too).
pub fn exti_clear(bits: u32) {
    EXTI_PR.fetch_and(!bits, Ordering::Relaxed);
    // SAFETY: a write-1-to-clear of the command lines' pending bits.
    unsafe {
        (*stm32f4::stm32f446::EXTI::ptr())
            .pr()
            .write(|w| w.bits(bits));
    }
}
/// TIM2_CNT.
pub fn fes_count() -> u32 {
    FES_COUNT.load(Ordering::Relaxed)
}
/// TIM2_CCR1 write.
pub fn set_fes_compare(at: u32) {
    FES_COMPARE.store(at, Ordering::Relaxed);
}
/// TIM5_CNT.
pub fn time() -> u32 {
    TIME.load(Ordering::Relaxed)
}
/// TIM5_CCR1 write with CC1IE set (`Some`), or CC1IE cleared.
pub fn set_time_alarm(at: Option<u32>) {
    cortex_m::interrupt::free(|cs| TIME_ALARM.borrow(cs).set(at));
}
/// ADC1_DR after a conversion of `channel`.
pub fn adc_result(channel: u8) -> u16 {
    ADC_RESULTS
        .get(usize::from(channel))
        .map_or(0, |r| r.load(Ordering::Relaxed))
}
/// The configuration the driver queued, if any (taken by `observe`).
pub fn take_reset() -> Option<MeasureConfig> {
    cortex_m::interrupt::free(|cs| RESET.borrow(cs).replace(None))
}

/// The driver's side: the inputs it drives and the outputs it reads.
pub mod drive {
    use super::*;

    /// Sets or clears `mask` in the input data register `idr`.
    fn set(idr: &AtomicU32, mask: u32, on: bool) {
        if on {
            idr.fetch_or(mask, Ordering::Relaxed);
        } else {
            idr.fetch_and(!mask, Ordering::Relaxed);
        }
    }
    /// PA0, the arm line.
    pub fn arm(on: bool) {
        set(&IDR_A, 1 << 0, on);
    }
    /// PA1, the contact line.
    pub fn contact(on: bool) {
        set(&IDR_A, 1 << 1, on);
    }
    /// PB8, PB9, the scale's A and B.
    pub fn scale(a: bool, b: bool) {
        set(&IDR_B, 1 << 8, a);
        set(&IDR_B, 1 << 9, b);
    }
    /// An edge of command line `line` (11–13) to `level`: the pin's level and its EXTI
    /// pending bit.
    pub fn command_edge(line: u32, level: bool) {
        set(&IDR_C, 1 << line, level);
        EXTI_PR.fetch_or(1 << line, Ordering::Relaxed);
    }
    /// Every input at its idle level (pull-downs; the button released).
    pub fn release_all() {
        IDR_A.store(0, Ordering::Relaxed);
        IDR_B.store(0, Ordering::Relaxed);
        IDR_C.store(1 << 13, Ordering::Relaxed);
        EXTI_PR.store(0, Ordering::Relaxed);
    }
    /// One FES rising edge on PB3: true if the count now matches TIM2_CCR1 (CC1IF: the
    /// TIM2 interrupt).
    pub fn fes_edge() -> bool {
        let count = FES_COUNT.load(Ordering::Relaxed).wrapping_add(1);
        FES_COUNT.store(count, Ordering::Relaxed);
        count == FES_COMPARE.load(Ordering::Relaxed)
    }
    /// The codes the next conversion of each channel gives.
    pub fn adc(channel: u8, code: u16) {
        if let Some(r) = ADC_RESULTS.get(usize::from(channel)) {
            r.store(code, Ordering::Relaxed);
        }
    }
    /// Queues a fresh kernel's configuration for `observe` to install.
    pub fn reset(config: MeasureConfig) {
        cortex_m::interrupt::free(|cs| RESET.borrow(cs).set(Some(config)));
    }
    /// Sets the clock (TIM5_CNT) to `now`.
    pub fn set_time(now: u32) {
        TIME.store(now, Ordering::Relaxed);
    }
    /// The alarm's compare value while its interrupt is enabled.
    pub fn time_alarm() -> Option<u32> {
        cortex_m::interrupt::free(|cs| TIME_ALARM.borrow(cs).get())
    }
}
