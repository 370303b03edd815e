//! The real board: a Nucleo-F446RE (STM32F446RE, Cortex-M4F). The pins' edges raise EXTI
//! interrupts bound to the same shared handlers as the QEMU board, and TIM2 counts the FES
//! pulses; defmt logs over RTT (probe-rs prints them).
//!
//! Pin map (Arduino / Morpho header names in brackets; README has the wiring):
//!
//! | pin  | header   | signal                         | interrupt        | edges   |
//! |------|----------|--------------------------------|------------------|---------|
//! | PA0  | A0       | CNC arm / abort (in)           | EXTI0, prio 15   | both    |
//! | PA1  | A1       | tool–workpiece contact (in)    | EXTI1, prio 15   | both    |
//! | PB2  | CN10-22  | index pulse (in)               | EXTI2, prio 15   | rising  |
//! | PB3  | D3       | FES encoder pulse (in; AF1 = TIM2_CH2, counted by TIM2) | TIM2 compare, prio 15 | rising |
//! | PB8  | D15      | linear scale A (in)            | EXTI9_5, prio 15 | both    |
//! | PB9  | D14      | linear scale B (in)            | EXTI9_5, prio 15 | both    |
//! | —    | —        | observe (idle's output snapshot)| TIM7, prio 15   | —       |
//! | PC11 | CN7-2    | CNC force control on (in)      | EXTI15_10, pr 12 | both    |
//! | PC12 | CN7-3    | CNC no-load identification (in)| EXTI15_10, pr 12 | both    |
//! | PC13 | B1 button| tool changed (in, active low)  | EXTI15_10, pr 12 | falling |
//! | PC0–PC5, PB0, PB1 | A5, A4, CN7-35, CN7-37, CN10-34, CN10-6, A3, CN10-24 | ADC1 IN10–IN15, IN8, IN9: speed, power, force, v_u, v_v, v_w, i_u, i_v | TIM6 1 kHz, pr 8 | — |
//! | —    | —        | 20 Hz control period           | TIM3, prio 4     | —       |
//! | PA5  | D13, LD2 | "register now" to the CNC (out)| —                | —       |
//! | PA6  | D12      | wear alarm (out)               | —                | —       |
//! | PB6  | D10      | feed override, PWM 15.625 kHz, duty = % / 256 (TIM4_CH1) | — | — |
//!
//! The measurement tasks share the highest priority, so none preempts another and the
//! measurement domain needs no lock. Their IRQ numbers (EXTI0 = 6, EXTI1 = 7, EXTI2 = 8,
//! EXTI9_5 = 23, TIM2 = 28, TIM7 = 55) decide the order of simultaneous edges (Cortex-M
//! takes same-priority pending interrupts lowest number first): arm, contact, index as
//! the model's canonical same-clock order has them; the FES compare comes after the scale
//! here, so the scale task first folds the counted pulses whenever the counter has
//! reached its compare value (`handlers::scale`), and a deciding pulse counted before a
//! scale edge latches the position from before it, as in the model. The pins are chosen
//! for their EXTI lines (line n is pin n of any one port) and, for the FES line, its
//! timer channel: PB3 leaves its reset function (JTDO/SWO; probe-rs needs only SWD) for
//! alternate function 1, TIM2_CH2 (STM32F446 datasheet, alternate-function table).
//!
//! FES pulses raise no interrupt. TIM2 counts every rising edge of PB3 (external clock
//! mode 1 on TI2FP2, 32 bits, wrapping like the kernel's pulse count), and its channel 1
//! compare interrupt fires on the pulse that would decide or at most
//! `handlers::FES_FOLD_LIMIT` pulses after the last fold (`handlers::MeasureDomain`).
//! The timer's input filter (IC2F = 0011) counts a level that holds for 8 of its 84 MHz
//! clocks, so it rejects spikes under 95 ns and counts FES rates up to about 5 MHz, no
//! longer bounded by an interrupt per pulse; the README gives the cycle budget. The channel is an input
//! (CC2S = 01), so the pin is never driven; channel 1 is an output compare in frozen
//! mode (OC1M = 000, CC1E = 0) that drives no pin either.
//!
//! Clocks, set up first in `init` register by register after RM0390 (the constants below
//! hold every number, checked by `const` assertions): SYSCLK = HCLK = 168 MHz from the main
//! PLL fed by the 16 MHz HSI (M 8: 2 MHz VCO input; N 168: 336 MHz VCO; P 2; Q 7 gives
//! 48 MHz, unused); voltage scale 1 without over-drive; flash 5 wait states with prefetch
//! and the ART instruction and data caches; APB1 /4 = 42 MHz (its timers TIM2–TIM7 at
//! 84 MHz), APB2 /2 = 84 MHz (ADC clock /4 = 21 MHz, 56-cycle sampling). HSE is not used:
//! on a Nucleo-64 it is the ST-LINK's 8 MHz MCO, connected by default only from board
//! revision MB1136 C-02 on (UM1724), while the HSI is on every board. Every wait of the
//! setup is bounded; should one run out, the board logs the step with defmt and stays on
//! the reset clocks (HSI 16 MHz, every bus /1) with timer and ADC settings derived for
//! those, so the 1 kHz and 20 Hz periods and the 15.625 kHz PWM stay exact and only the
//! FES-rate budget shrinks (10.5 times fewer cycles; TIM2's input filter then needs levels
//! of 500 ns, FES rates up to about 1 MHz). The handlers' cost is counted in
//! instructions and cycles, see README for the rates 168 MHz allows. The
//! cutting-conditions command has no pin: condition set 0 is used on this board.
#![no_std]
#![no_main]

#[cfg(not(feature = "panic-check"))]
use defmt_rtt as _;

/// The `panic-check` build's defmt logger: discards every frame. defmt-rtt's logger
/// panics when it is taken re-entrantly (a misuse this firmware cannot commit: it logs
/// only from `idle`), which would keep a panic path in the image; everything else in the
/// check build is the shipped firmware.
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
use core::sync::atomic::{AtomicU32, Ordering};
use stm32f4::stm32f446 as pac;
use tooltouch_firmware::board::Board;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::sampling::AdcCodes;

/// GPIO bits (= EXTI lines) of the inputs: arm PA0, contact PA1, index PB2, scale PB8 /
/// PB9, force commands PC11–PC13; outputs PA5, PA6. (FES, PB3, is TIM2's clock input.)
const ARM: u32 = 1 << 0;
const CONTACT: u32 = 1 << 1;
const INDEX: u32 = 1 << 2;
const SCALE_A: u32 = 1 << 8;
const SCALE_B: u32 = 1 << 9;
const REGISTER_NOW: u32 = 1 << 5;
const WEAR_ALARM: u32 = 1 << 6;
const CONTROL: u32 = 1 << 11;
const IDENTIFY: u32 = 1 << 12;
const TOOL_CHANGED: u32 = 1 << 13;
const FORCE_LINES: u32 = CONTROL | IDENTIFY | TOOL_CHANGED;
/// ADC1 channels in [`AdcCodes`] order: speed, power, force, v_u, v_v, v_w, i_u, i_v.
const ADC_CHANNELS: [u32; 8] = [10, 11, 12, 13, 14, 15, 8, 9];

// Clock tree (RM0390: RCC clocks and registers, the flash wait-state table, PWR voltage
// scaling; the STM32F446 datasheet for the limits). SYSCLK 168 MHz from the PLL
// fed by the 16 MHz HSI: HSE on this board needs the ST-LINK's 8 MHz MCO on PH0, fitted by
// default only from board revision MB1136 C-02 on (UM1724), so the HSI is the one input
// every Nucleo-F446RE has. Everything clock-dependent below is derived from these numbers
// at compile time; a `const` assertion that fails stops the build, not the firmware.

/// HSI RC oscillator: the reset clock and the PLL input (Hz).
const HSI_HZ: u32 = 16_000_000;
/// PLLM, the PLL input divider (RCC_PLLCFGR bits 5:0; 2–63).
const PLL_M: u32 = 8;
/// PLLN, the VCO multiplier (RCC_PLLCFGR bits 14:6; 50–432).
const PLL_N: u32 = 168;
/// PLLP, the SYSCLK divider (RCC_PLLCFGR bits 17:16: 2, 4, 6 or 8).
const PLL_P: u32 = 2;
/// PLLQ, the 48 MHz-domain divider (RCC_PLLCFGR bits 27:24; 2–15; USB/SDIO/RNG, unused).
const PLL_Q: u32 = 7;
/// VCO input = HSI / M (Hz): 2 MHz, the value RM0390 recommends to limit jitter (1–2 MHz).
const PLL_VCO_IN_HZ: u32 = HSI_HZ / PLL_M;
/// VCO output = VCO input × N (Hz): 336 MHz (100–432 MHz).
const PLL_VCO_HZ: u32 = PLL_VCO_IN_HZ * PLL_N;
/// SYSCLK = VCO / P (Hz): 168 MHz, the most voltage scale 1 allows without over-drive.
const SYSCLK_HZ: u32 = PLL_VCO_HZ / PLL_P;
/// PLL48CLK = VCO / Q (Hz): exactly 48 MHz.
const PLL48_HZ: u32 = PLL_VCO_HZ / PLL_Q;
/// AHB prescaler (RCC_CFGR HPRE): HCLK = SYSCLK.
const AHB_DIV: u32 = 1;
/// HCLK, the core, AHB and flash clock (Hz): 168 MHz.
const HCLK_HZ: u32 = SYSCLK_HZ / AHB_DIV;
/// APB1 prescaler (RCC_CFGR PPRE1 = 0b101).
const APB1_DIV: u32 = 4;
/// PCLK1 (Hz): 42 MHz (at most 45 MHz).
const PCLK1_HZ: u32 = HCLK_HZ / APB1_DIV;
/// APB2 prescaler (RCC_CFGR PPRE2 = 0b100).
const APB2_DIV: u32 = 2;
/// PCLK2 (Hz): 84 MHz (at most 90 MHz); clocks ADC1, SYSCFG.
const PCLK2_HZ: u32 = HCLK_HZ / APB2_DIV;
/// Kernel clock of the APB1 timers TIM2–TIM7 (Hz): 84 MHz, twice PCLK1 because the APB1
/// prescaler is not 1 (RCC_DCKCFGR TIMPRE = 0, its reset value).
const TIM_CLK_APB1_HZ: u32 = timer_clock(PCLK1_HZ, APB1_DIV);
/// Kernel clock of the APB2 timers (Hz): 168 MHz (none is used).
const TIM_CLK_APB2_HZ: u32 = timer_clock(PCLK2_HZ, APB2_DIV);
/// Flash wait states at HCLK (FLASH_ACR LATENCY): 5 at 168 MHz.
const FLASH_WAIT_STATES: u32 = flash_wait_states(HCLK_HZ);

/// The 1 kHz ADC sample tick (Hz), TIM6: the model's sample rate.
const SAMPLE_HZ: u32 = 1_000;
/// TIM6's count rate (Hz): 1 µs per count (TIM6 is 16-bit).
const TIM6_COUNT_HZ: u32 = 1_000_000;
/// The 20 Hz control period (Hz), TIM3: 50 samples per period.
const CONTROL_HZ: u32 = 20;
/// TIM3's count rate (Hz): 100 µs per count (TIM3 is 16-bit).
const TIM3_COUNT_HZ: u32 = 10_000;
/// Duty steps of the feed-override PWM: TIM4 ARR = 255, duty = CCR1 / 256 (CCR1 = %).
const FEED_PWM_STEPS: u32 = 256;
/// Feed-override PWM frequency (Hz): 15.625 kHz, an exact division of both the PLL's
/// 84 MHz and the fallback's 16 MHz timer clock, so it is the same whichever runs.
const FEED_PWM_HZ: u32 = 15_625;
/// Highest ADC clock (Hz) for VDDA 2.4–3.6 V (STM32F446 datasheet; 18 MHz below 2.4 V).
const ADC_CLK_MAX_HZ: u32 = 36_000_000;
/// ADC sampling time per channel (ADC clocks; ADC_SMPRx code 0b011). With the datasheet's
/// R_AIN formula (C_ADC 7 pF max, R_ADC 6 kΩ, 12 bit) at 21 MHz this tolerates a source
/// impedance of about 30 kΩ; the reset value, 3 clocks, tolerates none at this clock.
const ADC_SAMPLE_CYCLES: u32 = 56;
/// ADC conversion time (ADC clocks): sampling + 12 for the 12-bit approximation.
const ADC_CONVERSION_CYCLES: u32 = ADC_SAMPLE_CYCLES + 12;
/// Longest wait for a PLL lock, a voltage-scale or a clock-switch flag (polls). Every poll
/// takes at least one cycle of the 16 MHz HSI: at least 4 ms, over ten times the PLL's
/// worst-case lock time (datasheet t_LOCK 300 µs).
const CLOCK_READY_POLLS: u32 = HSI_HZ / 250;

/// The APB timers' kernel clock (Hz): PCLK when its prescaler is 1, else twice PCLK.
const fn timer_clock(pclk_hz: u32, apb_div: u32) -> u32 {
    if apb_div == 1 {
        pclk_hz
    } else {
        pclk_hz * 2
    }
}

/// Flash wait states for `hclk_hz` at VDD 2.7–3.6 V: one per started 30 MHz (RM0390
/// table "Number of wait states according to CPU clock (HCLK) frequency").
const fn flash_wait_states(hclk_hz: u32) -> u32 {
    (hclk_hz - 1) / 30_000_000
}

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

/// The ADC_CCR ADCPRE code of the smallest ADC prescaler (2, 4, 6, 8) that keeps the ADC
/// clock within [`ADC_CLK_MAX_HZ`] at `pclk2_hz`, and the ADC clock (Hz) it gives.
const fn adc_prescaler(pclk2_hz: u32) -> (u8, u32) {
    let mut code = 0u8;
    while code < 4 {
        let adc_hz = pclk2_hz / (2 * (code as u32 + 1));
        if adc_hz <= ADC_CLK_MAX_HZ {
            return (code, adc_hz);
        }
        code += 1;
    }
    panic!("PCLK2 too fast for the ADC")
}

/// The ADC_SMPRx code of a sampling time of `cycles` ADC clocks.
const fn sample_time_code(cycles: u32) -> u8 {
    match cycles {
        3 => 0,
        15 => 1,
        28 => 2,
        56 => 3,
        84 => 4,
        112 => 5,
        144 => 6,
        480 => 7,
        _ => panic!("not an ADC sampling time"),
    }
}

/// Every setting that depends on the bus clocks, for one clock tree; built at compile time.
#[derive(Clone, Copy)]
struct BusTiming {
    /// SYSCLK = HCLK (Hz).
    sysclk_hz: u32,
    /// TIM6 PSC (1 µs count) and ARR (1 kHz update).
    tim6_psc: u16,
    tim6_arr: u16,
    /// TIM3 PSC (100 µs count) and ARR (20 Hz update).
    tim3_psc: u16,
    tim3_arr: u16,
    /// TIM4 PSC for [`FEED_PWM_HZ`] with ARR = [`FEED_PWM_STEPS`] − 1.
    tim4_psc: u16,
    /// ADC_CCR ADCPRE code and the ADC clock it gives (Hz).
    adcpre: u8,
    adc_hz: u32,
}

impl BusTiming {
    /// The settings for core clock `sysclk_hz`, ADC bus clock `pclk2_hz` and APB1 timer
    /// clock `tim_hz` (all Hz).
    const fn new(sysclk_hz: u32, pclk2_hz: u32, tim_hz: u32) -> Self {
        let (adcpre, adc_hz) = adc_prescaler(pclk2_hz);
        BusTiming {
            sysclk_hz,
            tim6_psc: prescaler(tim_hz, TIM6_COUNT_HZ),
            tim6_arr: reload16(TIM6_COUNT_HZ, SAMPLE_HZ),
            tim3_psc: prescaler(tim_hz, TIM3_COUNT_HZ),
            tim3_arr: reload16(TIM3_COUNT_HZ, CONTROL_HZ),
            tim4_psc: prescaler(tim_hz, FEED_PWM_HZ * FEED_PWM_STEPS),
            adcpre,
            adc_hz,
        }
    }

    /// Core cycles one ADC conversion lasts.
    const fn conversion_cycles(&self) -> u32 {
        ADC_CONVERSION_CYCLES * self.sysclk_hz.div_ceil(self.adc_hz)
    }
}

/// The clock tree this firmware sets up: PLL, SYSCLK 168 MHz.
const PLL_TIMING: BusTiming = BusTiming::new(SYSCLK_HZ, PCLK2_HZ, TIM_CLK_APB1_HZ);
/// The fallback if the PLL does not come up: the reset clocks (HSI 16 MHz, every bus /1).
const HSI_TIMING: BusTiming = BusTiming::new(HSI_HZ, HSI_HZ, HSI_HZ);
/// ADC_SMPR1/2 code of [`ADC_SAMPLE_CYCLES`].
const ADC_SMP: u8 = sample_time_code(ADC_SAMPLE_CYCLES);
/// Longest wait for an ADC end of conversion (polls): each poll takes at least one core
/// cycle, so twice the conversion's length in core cycles on either clock tree.
const ADC_EOC_POLLS: u32 = 2 * max(
    PLL_TIMING.conversion_cycles(),
    HSI_TIMING.conversion_cycles(),
);

const fn max(a: u32, b: u32) -> u32 {
    if a > b {
        a
    } else {
        b
    }
}

// RM0390 / datasheet limits, checked when the firmware is built.
const _: () = assert!(PLL_M >= 2 && PLL_M <= 63 && HSI_HZ.is_multiple_of(PLL_M));
const _: () = assert!(PLL_N >= 50 && PLL_N <= 432);
const _: () = assert!(PLL_P == 2 || PLL_P == 4 || PLL_P == 6 || PLL_P == 8);
const _: () = assert!(PLL_Q >= 2 && PLL_Q <= 15);
const _: () = assert!(PLL_VCO_IN_HZ >= 1_000_000 && PLL_VCO_IN_HZ <= 2_000_000);
const _: () = assert!(PLL_VCO_HZ >= 100_000_000 && PLL_VCO_HZ <= 432_000_000);
const _: () = assert!(SYSCLK_HZ == 168_000_000 && PLL_VCO_HZ.is_multiple_of(PLL_P));
const _: () = assert!(PLL48_HZ == 48_000_000 && PLL_VCO_HZ.is_multiple_of(PLL_Q));
const _: () = assert!(AHB_DIV == 1 && HCLK_HZ <= 168_000_000);
const _: () = assert!(PCLK1_HZ == 42_000_000 && PCLK1_HZ <= 45_000_000);
const _: () = assert!(PCLK2_HZ == 84_000_000 && PCLK2_HZ <= 90_000_000);
const _: () = assert!(TIM_CLK_APB1_HZ == 84_000_000 && TIM_CLK_APB2_HZ == 168_000_000);
const _: () = assert!(FLASH_WAIT_STATES == 5 && flash_wait_states(HSI_HZ) == 0);
const _: () = assert!(PLL_TIMING.tim6_psc == 83 && PLL_TIMING.tim6_arr == 999);
const _: () = assert!(HSI_TIMING.tim6_psc == 15 && HSI_TIMING.tim6_arr == 999);
const _: () = assert!(PLL_TIMING.tim3_psc == 8_399 && PLL_TIMING.tim3_arr == 499);
const _: () = assert!(PLL_TIMING.tim4_psc == 20 && HSI_TIMING.tim4_psc == 3);
const _: () = assert!(PLL_TIMING.adc_hz == 21_000_000 && PLL_TIMING.adcpre == 1);
const _: () = assert!(HSI_TIMING.adc_hz == 8_000_000 && HSI_TIMING.adcpre == 0);
const _: () = assert!(FEED_PWM_STEPS - 1 <= 0xffff && FEED_PWM_STEPS > u8::MAX as u32);

/// A clock-setup step that did not complete within its bounded wait.
#[derive(Clone, Copy, defmt::Format)]
enum ClockFault {
    /// PLLRDY did not rise.
    PllLock,
    /// PWR_CSR VOSRDY did not rise.
    VoltageScale,
    /// FLASH_ACR did not read back 5 wait states.
    FlashLatency,
    /// RCC_CFGR SWS did not report the PLL.
    Switch,
}

/// Polls `ready` at most `polls` times; true as soon as it holds.
fn wait_for(polls: u32, mut ready: impl FnMut() -> bool) -> bool {
    (0..polls).any(|_| ready())
}

/// Raises SYSCLK from the reset clock (HSI 16 MHz, PLL off) to 168 MHz: PLL from HSI,
/// voltage scale 1, 5 flash wait states with prefetch and the ART caches, AHB /1, APB1 /4,
/// APB2 /2, then the switch. Each wait is bounded; on a fault the clocks are put back to
/// the reset tree (HSI, every bus /1) so [`HSI_TIMING`] holds, and the fault is returned.
fn start_pll(rcc: &pac::RCC, pwr: &pac::PWR, flash: &pac::FLASH) -> Result<(), ClockFault> {
    // PWR's bus clock, then a read back so the write has reached RCC before PWR is used
    // (the delay the STM32F4 errata ask for after an RCC peripheral clock enable).
    rcc.apb1enr().modify(|_, w| w.pwren().set_bit());
    let _ = rcc.apb1enr().read();
    // Voltage scale 1 (also the reset value); it is written while the PLL is off and
    // takes effect when the PLL starts.
    pwr.cr().modify(|_, w| w.vos().scale1());
    // SAFETY: M, N, Q are within their fields (checked by the `const` assertions above);
    // PLLR keeps its reset value 2 (it feeds nothing here).
    rcc.pllcfgr().modify(|_, w| unsafe {
        w.pllsrc()
            .hsi()
            .pllm()
            .bits(PLL_M as u8)
            .plln()
            .bits(PLL_N as u16)
            .pllp()
            .div2()
            .pllq()
            .bits(PLL_Q as u8)
    });
    rcc.cr().modify(|_, w| w.pllon().set_bit());
    let pll_off = || rcc.cr().modify(|_, w| w.pllon().clear_bit());
    if !wait_for(CLOCK_READY_POLLS, || rcc.cr().read().pllrdy().bit_is_set()) {
        pll_off();
        return Err(ClockFault::PllLock);
    }
    if !wait_for(CLOCK_READY_POLLS, || pwr.csr().read().vosrdy().bit_is_set()) {
        pll_off();
        return Err(ClockFault::VoltageScale);
    }
    // Flash: reset the (still disabled) caches, then wait states, prefetch and caches on,
    // and read the latency back before the clock rises (RM0390's order for increasing
    // the CPU frequency: LATENCY, check it, then SW, then check SWS).
    flash.acr().modify(|_, w| w.icrst().reset().dcrst().reset());
    flash
        .acr()
        .modify(|_, w| w.icrst().no_reset().dcrst().no_reset());
    // SAFETY: LATENCY is a 4-bit field; 5 fits (checked above).
    flash.acr().modify(|_, w| unsafe {
        w.latency()
            .bits(FLASH_WAIT_STATES as u8)
            .prften()
            .enabled()
            .icen()
            .enabled()
            .dcen()
            .enabled()
    });
    if u32::from(flash.acr().read().latency().bits()) != FLASH_WAIT_STATES {
        pll_off();
        return Err(ClockFault::FlashLatency);
    }
    // Bus prescalers first (harmless at 16 MHz), then SYSCLK = PLL.
    rcc.cfgr()
        .modify(|_, w| w.hpre().div1().ppre1().div4().ppre2().div2());
    rcc.cfgr().modify(|_, w| w.sw().pll());
    if !wait_for(CLOCK_READY_POLLS, || rcc.cfgr().read().sws().is_pll()) {
        rcc.cfgr()
            .modify(|_, w| w.sw().hsi().ppre1().div1().ppre2().div1());
        let _ = wait_for(CLOCK_READY_POLLS, || rcc.cfgr().read().sws().is_hsi());
        pll_off();
        return Err(ClockFault::Switch);
    }
    Ok(())
}

/// EXTI lines of force-path commands not yet handled (set by the EXTI15_10 handler).
static PENDING_COMMANDS: AtomicU32 = AtomicU32::new(0);

/// The Nucleo-F446RE.
pub struct Nucleo;

fn idr_a() -> u32 {
    // SAFETY: a read of the input data register; no side effect.
    unsafe { (*pac::GPIOA::ptr()).idr().read().bits() }
}
fn idr_b() -> u32 {
    // SAFETY: as above.
    unsafe { (*pac::GPIOB::ptr()).idr().read().bits() }
}
fn idr_c() -> u32 {
    // SAFETY: as above.
    unsafe { (*pac::GPIOC::ptr()).idr().read().bits() }
}

impl Board for Nucleo {
    fn arm() -> bool {
        idr_a() & ARM != 0
    }
    fn contact() -> bool {
        idr_a() & CONTACT != 0
    }
    fn scale() -> (bool, bool) {
        let b = idr_b();
        (b & SCALE_A != 0, b & SCALE_B != 0)
    }
    fn fes_count() -> u32 {
        // SAFETY: a read of TIM2's counter; TIM2 counts FES edges (set up once in `init`).
        unsafe { (*pac::TIM2::ptr()).cnt().read().bits() }
    }
    fn set_fes_compare(at: u32) {
        // SAFETY: CCR1 of TIM2 (32 bits, no preload: takes effect at once) is the FES
        // compare value and written only by the measurement tasks.
        unsafe { (*pac::TIM2::ptr()).ccr1().write(|w| w.bits(at)) };
    }
    fn pend_fes_compare() {
        rtic::pend(pac::Interrupt::TIM2);
    }
    fn set_register_now(on: bool) {
        let bits = if on { REGISTER_NOW } else { REGISTER_NOW << 16 };
        // SAFETY: BSRR is write-only and atomic per bit: sets or resets PA5 alone.
        unsafe { (*pac::GPIOA::ptr()).bsrr().write(|w| w.bits(bits)) };
    }
    fn adc() -> AdcCodes {
        let mut c = [0u16; 8];
        for (code, channel) in c.iter_mut().zip(ADC_CHANNELS) {
            *code = convert(channel);
        }
        AdcCodes {
            speed: c[0],
            power: c[1],
            force: c[2],
            volts: [c[3], c[4], c[5]],
            amps: [c[6], c[7]],
        }
    }
    fn force_command() -> Option<ForceEvent> {
        // One command per call, lowest line first; the task calls again while any remain.
        let pending = PENDING_COMMANDS.load(Ordering::Relaxed);
        let line = pending & pending.wrapping_neg();
        PENDING_COMMANDS.fetch_and(!line, Ordering::Relaxed);
        match line {
            CONTROL => Some(ForceEvent::Control(idr_c() & CONTROL != 0)),
            IDENTIFY => Some(ForceEvent::Identify(idr_c() & IDENTIFY != 0)),
            TOOL_CHANGED => Some(ForceEvent::ToolChanged),
            _ => None,
        }
    }
    fn set_feed_override(percent: u8) {
        // SAFETY: CCR1 of TIM4 takes any 16-bit compare value; ARR = 255.
        unsafe {
            (*pac::TIM4::ptr())
                .ccr1()
                .write(|w| w.bits(u32::from(percent)))
        };
    }
    fn set_wear_alarm(on: bool) {
        let bits = if on { WEAR_ALARM } else { WEAR_ALARM << 16 };
        // SAFETY: as for "register now" (PA6).
        unsafe { (*pac::GPIOA::ptr()).bsrr().write(|w| w.bits(bits)) };
    }
}

/// One software-started ADC1 conversion of `channel` ([`ADC_CONVERSION_CYCLES`] ADC
/// clocks: 3.2 µs at the PLL tree's 21 MHz, 8.5 µs at the fallback's 8 MHz); 0 if it
/// does not complete within [`ADC_EOC_POLLS`] polls (never blocks forever).
fn convert(channel: u32) -> u16 {
    // SAFETY: ADC1 is owned by the 1 kHz sample task alone; SQR3 selects one channel,
    // CR2 bit 30 starts it, SR bit 1 (EOC) is cleared by reading DR.
    unsafe {
        let adc = &*pac::ADC1::ptr();
        adc.sqr3().write(|w| w.bits(channel & 0x1f));
        adc.cr2().modify(|r, w| w.bits(r.bits() | 1 << 30));
        for _ in 0..ADC_EOC_POLLS {
            if adc.sr().read().bits() & 1 << 1 != 0 {
                return (adc.dr().read().bits() & 0x0fff) as u16;
            }
        }
    }
    0
}

/// Interrupt load measured from `idle` (feature `cpu-load`), for checking the FES budget on
/// a board: idle spins instead of sleeping and reads the DWT cycle counter once per turn.
/// A turn longer than the shortest one seen was preempted, and its excess is time spent in
/// interrupts; once per `period` cycles the busy share is reported, in ‰.
#[cfg(feature = "cpu-load")]
struct CpuLoad {
    /// Cycle count at the previous turn.
    last: u32,
    /// Shortest turn seen, cycles: idle's own loop.
    shortest: u32,
    /// Cycles taken by interrupts in this window.
    busy: u64,
    /// Cycles in this window.
    window: u64,
    /// Window length, cycles (one second of SYSCLK).
    period: u64,
}

#[cfg(feature = "cpu-load")]
impl CpuLoad {
    fn new(now: u32, period: u32) -> Self {
        CpuLoad {
            last: now,
            shortest: u32::MAX,
            busy: 0,
            window: 0,
            period: u64::from(period).max(1),
        }
    }

    /// One idle turn at cycle count `now`; the window's load in ‰ when it is complete.
    fn turn(&mut self, now: u32) -> Option<u32> {
        let turn = now.wrapping_sub(self.last);
        self.last = now;
        self.shortest = self.shortest.min(turn);
        self.busy = self
            .busy
            .saturating_add(u64::from(turn.saturating_sub(self.shortest)));
        self.window = self.window.saturating_add(u64::from(turn));
        if self.window < self.period {
            return None;
        }
        let permille = self
            .busy
            .saturating_mul(1000)
            .checked_div(self.window)
            .unwrap_or(0);
        self.busy = 0;
        self.window = 0;
        Some(u32::try_from(permille).unwrap_or(u32::MAX))
    }
}

/// Acknowledges EXTI lines `mask` (write 1 to clear).
fn ack(mask: u32) {
    // SAFETY: PR is write-1-to-clear; other lines are unaffected.
    unsafe { (*pac::EXTI::ptr()).pr().write(|w| w.bits(mask)) };
}

#[rtic::app(device = stm32f4::stm32f446, peripherals = true)]
mod app {
    use super::{
        ack, pac, start_pll, Nucleo, ADC_SMP, ARM, CONTACT, FEED_PWM_HZ, FEED_PWM_STEPS,
        FORCE_LINES, HSI_TIMING, INDEX, PENDING_COMMANDS, PLL_TIMING, REGISTER_NOW, SCALE_A,
        SCALE_B, WEAR_ALARM,
    };
    use core::sync::atomic::Ordering;
    use tooltouch_firmware::board::Board;
    use tooltouch_firmware::handlers::{
        self, Counters, MeasureDomain, SampleConsumer, SampleProducer, SampleQueue,
    };
    use tooltouch_firmware::model::force::config::ForceSettings;
    use tooltouch_firmware::model::force::kernel::ForceKernel;
    use tooltouch_firmware::model::{MeasureConfig, MeasureOutputs, Measurement};

    /// The interrupt of [`observe`] (TIM7 stays disabled: only software pends it).
    const OBSERVE: pac::Interrupt = pac::Interrupt::TIM7;

    #[shared]
    struct Shared {
        /// The measurement kernel and TIM2's FES count as of its last fold. Lock-free:
        /// only the measurement tasks touch it, and they all run at one priority, so none
        /// can preempt another.
        #[lock_free]
        meas: MeasureDomain,
        /// The kernel's outputs as of the last [`observe`], for idle's log.
        snapshot: MeasureOutputs,
        force: ForceKernel,
        counters: Counters,
    }

    #[local]
    struct Local {
        samples_in: SampleProducer<'static>,
        samples_out: SampleConsumer<'static>,
        /// The core clock `init` set up, Hz (idle's load window with `cpu-load`).
        sysclk_hz: u32,
    }

    #[init(local = [queue: SampleQueue = SampleQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        // The cycle counter idle's load measurement reads (feature `cpu-load`).
        #[cfg(feature = "cpu-load")]
        {
            let mut core = cx.core;
            core.DCB.enable_trace();
            core.DWT.enable_cycle_counter();
        }
        // The clock tree first: every timer and the ADC below are set from the bus clocks
        // it gives. Should the PLL not come up, the board runs on the reset clocks with
        // settings derived for them, and says so.
        let timing = match start_pll(&dp.RCC, &dp.PWR, &dp.FLASH) {
            Ok(()) => PLL_TIMING,
            Err(fault) => {
                defmt::error!(
                    "clock setup failed ({}): running from the 16 MHz HSI, the measurement \
                     tasks take 10.5 times longer than the README's 168 MHz budget",
                    fault
                );
                HSI_TIMING
            }
        };
        // SAFETY (all `bits` writes below): values built from the reference manual's
        // (RM0390) bit positions; reserved bits are left as read.
        unsafe {
            // Clocks: GPIOA, GPIOB, GPIOC (AHB1), SYSCFG (APB2).
            dp.RCC.ahb1enr().modify(|r, w| w.bits(r.bits() | 0b111));
            dp.RCC.apb2enr().modify(|r, w| w.bits(r.bits() | 1 << 14));
            // PA5 push-pull output, low; the inputs in input mode with pull-downs so an
            // unconnected line reads 0 (PB3 too, then put in AF1 below: the pull-down
            // stays).
            dp.GPIOA.bsrr().write(|w| w.bits(REGISTER_NOW << 16));
            dp.GPIOA
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 10)) | 0b01 << 10));
            dp.GPIOA
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !0b1111) | 0b1010));
            dp.GPIOB
                .moder()
                .modify(|r, w| w.bits(r.bits() & !(0b1111 << 4)));
            dp.GPIOB.pupdr().modify(|r, w| {
                w.bits((r.bits() & !(0b1111 << 4 | 0b1111 << 16)) | 0b1010 << 4 | 0b1010 << 16)
            });
            dp.GPIOC
                .pupdr()
                .modify(|r, w| w.bits((r.bits() & !(0b1111 << 22)) | 0b1010 << 22));
            // EXTI line sources: 0, 1 = port A (reset value); 2, 8, 9 = port B.
            dp.SYSCFG
                .exticr1()
                .modify(|r, w| w.bits((r.bits() & !0x0f00) | 0x1 << 8));
            dp.SYSCFG
                .exticr3()
                .modify(|r, w| w.bits((r.bits() & !0xff) | 0x1 | 0x1 << 4));
            let lines = ARM | CONTACT | INDEX | SCALE_A | SCALE_B;
            dp.EXTI.rtsr().modify(|r, w| w.bits(r.bits() | lines));
            dp.EXTI
                .ftsr()
                .modify(|r, w| w.bits(r.bits() | ARM | CONTACT | SCALE_A | SCALE_B));
            dp.EXTI.pr().write(|w| w.bits(lines));
            dp.EXTI.imr().modify(|r, w| w.bits(r.bits() | lines));
            // Force-path command lines PC11, PC12 (both edges), PC13 (button, falling).
            dp.SYSCFG
                .exticr3()
                .modify(|r, w| w.bits((r.bits() & !(0xf << 12)) | 0x2 << 12));
            dp.SYSCFG
                .exticr4()
                .modify(|r, w| w.bits((r.bits() & !0xff) | 0x2 | 0x2 << 4));
            dp.EXTI
                .rtsr()
                .modify(|r, w| w.bits(r.bits() | super::CONTROL | super::IDENTIFY));
            dp.EXTI.ftsr().modify(|r, w| w.bits(r.bits() | FORCE_LINES));
            dp.EXTI.pr().write(|w| w.bits(FORCE_LINES));
            dp.EXTI.imr().modify(|r, w| w.bits(r.bits() | FORCE_LINES));
            // PA6 wear alarm: output, low.
            dp.GPIOA.bsrr().write(|w| w.bits(WEAR_ALARM << 16));
            dp.GPIOA
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 12)) | 0b01 << 12));
            // ADC inputs analog: PC0–PC5, PB0, PB1. ADC1 clock on; ADC clock PCLK2 / 4 =
            // 21 MHz (PLL) or PCLK2 / 2 = 8 MHz (fallback), at most 36 MHz; every channel
            // sampled for ADC_SAMPLE_CYCLES; then ADC1 on (ADON), t_STAB = 3 µs before the
            // first conversion, which the first TIM6 tick, 1 ms later, leaves.
            dp.GPIOC.moder().modify(|r, w| w.bits(r.bits() | 0xfff));
            dp.GPIOB.moder().modify(|r, w| w.bits(r.bits() | 0xf));
            dp.RCC.apb2enr().modify(|r, w| w.bits(r.bits() | 1 << 8));
            let _ = dp.RCC.apb2enr().read();
            dp.ADC_COMMON
                .ccr()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 16)) | u32::from(timing.adcpre) << 16));
            dp.ADC1.smpr1().write(|w| {
                w.smp10()
                    .set(ADC_SMP)
                    .smp11()
                    .set(ADC_SMP)
                    .smp12()
                    .set(ADC_SMP)
                    .smp13()
                    .set(ADC_SMP)
                    .smp14()
                    .set(ADC_SMP)
                    .smp15()
                    .set(ADC_SMP)
            });
            dp.ADC1
                .smpr2()
                .write(|w| w.smp8().set(ADC_SMP).smp9().set(ADC_SMP));
            dp.ADC1.cr2().modify(|r, w| w.bits(r.bits() | 1));
            // TIM6: 1 kHz sample tick; TIM3: 20 Hz control period; TIM4: override PWM;
            // TIM2: FES edge count. Prescalers from `timing` (84 MHz or 16 MHz timer
            // clock); an update event (UG) loads them now rather than after a first period
            // at prescaler 1, and its flag is cleared before the update interrupts are
            // enabled. RCC_APB1ENR: TIM2EN, TIM3EN, TIM4EN (bits 0–2), TIM6EN (bit 4).
            dp.RCC
                .apb1enr()
                .modify(|r, w| w.bits(r.bits() | 0b111 | 1 << 4));
            let _ = dp.RCC.apb1enr().read();
            dp.TIM6.psc().write(|w| w.psc().set(timing.tim6_psc));
            dp.TIM6.arr().write(|w| w.arr().set(timing.tim6_arr));
            dp.TIM3.psc().write(|w| w.psc().set(timing.tim3_psc));
            dp.TIM3.arr().write(|w| w.arr().set(timing.tim3_arr));
            // PB6 alternate function 2 (TIM4_CH1), PWM mode 1 with preload, ARR = 255:
            // FEED_PWM_HZ (15.625 kHz), duty = CCR1 / 256.
            dp.GPIOB
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 12)) | 0b10 << 12));
            dp.GPIOB
                .afrl()
                .modify(|r, w| w.bits((r.bits() & !(0xf << 24)) | 0x2 << 24));
            dp.TIM4.psc().write(|w| w.psc().set(timing.tim4_psc));
            dp.TIM4
                .arr()
                .write(|w| w.arr().set((FEED_PWM_STEPS - 1) as u16));
            dp.TIM4
                .ccmr1_output()
                .write(|w| w.bits(0b110 << 4 | 1 << 3));
            dp.TIM4.ccer().write(|w| w.bits(1));
            // TIM2 counts FES rising edges on PB3 (TIM2_CH2, AF1), RM0390 "External clock
            // source mode 1", its procedure for TI2: CC2S = 01 (channel 2 an input, IC2 on
            // TI2), IC2F = 0011 (a level must hold for 8 timer clocks, 95 ns at 84 MHz, to
            // count: rejects spikes on the encoder line and still counts up to about 5 MHz,
            // 25 times the SPEC's 204.8 kHz; the TI2 input is resynchronised to the timer
            // clock either way), CC2P = CC2NP = 0 (rising edge), SMS = 111 (external
            // clock mode 1), TS = 110 (TI2FP2), then CEN. PSC 0 counts every edge; ARR at
            // its 32-bit maximum wraps the count at 2^32 like the kernel's. Channel 1 is
            // the fold's compare: CC1S = 00 and OC1M = 000 (the same CCMR1 write: output
            // compare, frozen, no preload, so a CCR1 write takes effect at once), CC1E = 0
            // (no pin); CC1IE raises the TIM2 interrupt when the count reaches CCR1. The
            // update interrupt stays off.
            dp.TIM2
                .ccmr1_input()
                .write(|w| w.cc2s().ti2().ic2f().fck_int_n8());
            dp.TIM2
                .ccer()
                .write(|w| w.cc2p().clear_bit().cc2np().clear_bit());
            // TS before SMS: RM0390 asks for TS to change only while SMS = 000.
            dp.TIM2.smcr().write(|w| w.ts().ti2fp2());
            dp.TIM2.smcr().modify(|_, w| w.sms().ext_clock_mode());
            dp.TIM2.psc().write(|w| w.psc().set(0));
            dp.TIM2.arr().write(|w| w.arr().set(u32::MAX));
            dp.GPIOB
                .afrl()
                .modify(|r, w| w.bits((r.bits() & !(0xf << 12)) | 0x1 << 12));
            dp.GPIOB
                .moder()
                .modify(|r, w| w.bits((r.bits() & !(0b11 << 6)) | 0b10 << 6));
            dp.TIM2.egr().write(|w| w.ug().set_bit());
            dp.TIM6.egr().write(|w| w.ug().set_bit());
            dp.TIM3.egr().write(|w| w.ug().set_bit());
            dp.TIM4.egr().write(|w| w.ug().set_bit());
            dp.TIM2.sr().write(|w| w.bits(0));
            dp.TIM6.sr().write(|w| w.bits(0));
            dp.TIM3.sr().write(|w| w.bits(0));
            dp.TIM4.cr1().write(|w| w.bits(1 << 7 | 1));
            dp.TIM6.dier().write(|w| w.uie().set_bit());
            dp.TIM2.dier().write(|w| w.cc1ie().set_bit());
            dp.TIM3.dier().write(|w| w.bits(1));
            dp.TIM2.cr1().write(|w| w.cen().set_bit());
            dp.TIM6.cr1().write(|w| w.cen().set_bit());
            dp.TIM3.cr1().write(|w| w.bits(1));
        }
        defmt::info!(
            "tooltouch firmware on Nucleo-F446RE, SYSCLK {} Hz, feed-override PWM {} Hz: \
             waiting for the CNC's arm line (PA0)",
            timing.sysclk_hz,
            FEED_PWM_HZ
        );
        let (samples_in, samples_out) = cx.local.queue.split();
        // The default force configuration is valid (model::force tests it); should it
        // ever not be, the board halts here with a log line rather than run unconfigured.
        let force = match ForceSettings::default().validate() {
            Ok(c) => ForceKernel::new(&c),
            Err(_) => {
                defmt::error!("the default force configuration does not validate");
                loop {
                    rtic::export::wfi();
                }
            }
        };
        Nucleo::set_feed_override(force.outputs().override_pct);
        // TIM2 is counting: the domain starts at its count and sets the first compare.
        let meas = MeasureDomain::start::<Nucleo>(Measurement::new(&MeasureConfig::default()));
        (
            Shared {
                meas,
                snapshot: meas.kernel().outputs(),
                force,
                counters: Counters::default(),
            },
            Local {
                samples_in,
                samples_out,
                sysclk_hz: timing.sysclk_hz,
            },
        )
    }

    /// Logs every change of "register now" with the latched position and the ADC samples
    /// dropped; sleeps otherwise. The pin is read from the output data register; the rest
    /// of the outputs, which only the measurement tasks may read, through [`observe`], and
    /// only on a change.
    #[idle(shared = [snapshot, counters], local = [sysclk_hz])]
    fn idle(mut cx: idle::Context) -> ! {
        let mut reported = false;
        #[cfg(feature = "cpu-load")]
        let mut load = super::CpuLoad::new(
            cortex_m::peripheral::DWT::cycle_count(),
            *cx.local.sysclk_hz,
        );
        #[cfg(not(feature = "cpu-load"))]
        let _ = cx.local.sysclk_hz;
        loop {
            // SAFETY: a read of GPIOA's output data register; no side effect.
            let odr = unsafe { (*pac::GPIOA::ptr()).odr().read().bits() };
            let register_now = odr & REGISTER_NOW != 0;
            if register_now != reported {
                reported = register_now;
                rtic::pend(OBSERVE);
                cortex_m::asm::dsb();
                cortex_m::asm::isb();
                let o = cx.shared.snapshot.lock(|s| *s);
                let dropped = cx.shared.counters.lock(|c| c.overflowed);
                if reported {
                    defmt::info!(
                        "register now: position {} counts, first contact at {}, {} revolutions, \
                         {} FES pulses; {} ADC samples dropped",
                        o.decision_position,
                        o.first_contact_position,
                        o.revolutions,
                        o.pulses,
                        dropped
                    );
                } else {
                    defmt::info!("measurement cycle armed; {} ADC samples dropped", dropped);
                }
            }
            #[cfg(feature = "cpu-load")]
            if let Some(permille) = load.turn(cortex_m::peripheral::DWT::cycle_count()) {
                defmt::info!(
                    "CPU load {}.{} % (interrupts; idle turn {} cycles)",
                    permille / 10,
                    permille % 10,
                    load.shortest
                );
            }
            #[cfg(not(feature = "cpu-load"))]
            rtic::export::wfi();
        }
    }

    // The measurement tasks: one priority (15, the highest), so none preempts another:
    // the measurement domain needs no lock (module doc: the order of simultaneous edges).

    /// CNC arm / abort (PA0).
    #[task(binds = EXTI0, priority = 15, shared = [meas])]
    fn cnc_command(cx: cnc_command::Context) {
        ack(ARM);
        handlers::cnc_command::<Nucleo>(cx.shared.meas);
    }

    /// Contact edge (PA1).
    #[task(binds = EXTI1, priority = 15, shared = [meas])]
    fn contact(cx: contact::Context) {
        ack(CONTACT);
        handlers::contact::<Nucleo>(cx.shared.meas);
    }

    /// Index pulse (PB2).
    #[task(binds = EXTI2, priority = 15, shared = [meas])]
    fn index(cx: index::Context) {
        ack(INDEX);
        handlers::index::<Nucleo>(cx.shared.meas);
    }

    /// Scale edge on A or B (PB8, PB9).
    #[task(binds = EXTI9_5, priority = 15, shared = [meas])]
    fn scale(cx: scale::Context) {
        ack(SCALE_A | SCALE_B);
        handlers::scale::<Nucleo>(cx.shared.meas);
    }

    /// TIM2 channel 1: the FES count reached the compare value (the pulse that may
    /// decide, or the fold limit). The flag is cleared first, so a match after the new
    /// compare value is set raises the interrupt again.
    #[task(binds = TIM2, priority = 15, shared = [meas])]
    fn fes_compare(cx: fes_compare::Context) {
        // SAFETY: TIM2_SR's flags clear on a written 0 (rc_w0); the PAC's `clear` writes 0
        // to CC1IF and 1 to every other flag, which leaves them as they are.
        unsafe { (*pac::TIM2::ptr()).sr().write(|w| w.cc1if().clear()) };
        handlers::fes_compare::<Nucleo>(cx.shared.meas);
    }

    /// Idle's snapshot of the outputs (folding the counted FES pulses first); after any
    /// edge pending with it.
    #[task(binds = TIM7, priority = 15, shared = [meas, snapshot])]
    fn observe(cx: observe::Context) {
        let outputs = handlers::observe::<Nucleo>(cx.shared.meas);
        let mut snapshot = cx.shared.snapshot;
        snapshot.lock(|s| *s = outputs);
    }

    /// CNC force-path commands (PC11–PC13).
    #[task(binds = EXTI15_10, priority = 12, shared = [force])]
    fn cnc_force_command(mut cx: cnc_force_command::Context) {
        // SAFETY: a read of the pending register.
        let pr = unsafe { (*pac::EXTI::ptr()).pr().read().bits() };
        ack(pr & FORCE_LINES);
        PENDING_COMMANDS.fetch_or(pr & FORCE_LINES, Ordering::Relaxed);
        while PENDING_COMMANDS.load(Ordering::Relaxed) != 0 {
            cx.shared.force.lock(handlers::force_command::<Nucleo>);
        }
    }
    /// 1 kHz ADC sample (TIM6 update): convert the eight channels, queue them.
    #[task(binds = TIM6_DAC, priority = 8, shared = [counters], local = [samples_in])]
    fn adc_sample(mut cx: adc_sample::Context) {
        // SAFETY: clears TIM6's update flag (write 0 to UIF, its only flag).
        unsafe { (*pac::TIM6::ptr()).sr().write(|w| w.bits(0)) };
        if !handlers::adc_sample::<Nucleo>(cx.local.samples_in) {
            cx.shared
                .counters
                .lock(|c| c.overflowed = c.overflowed.saturating_add(1));
        }
    }

    /// 20 Hz control period (TIM3 update): samples, estimate, control, wear.
    #[task(binds = TIM3, priority = 4, shared = [force], local = [samples_out])]
    fn control_period(mut cx: control_period::Context) {
        // SAFETY: clears TIM3's update flag.
        unsafe { (*pac::TIM3::ptr()).sr().write(|w| w.bits(0)) };
        let queue = cx.local.samples_out;
        cx.shared
            .force
            .lock(|k| handlers::control_period::<Nucleo>(k, queue));
    }
}
