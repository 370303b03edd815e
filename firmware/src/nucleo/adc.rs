//! ADC1 and the eight spindle-drive inputs (RM0390 "Analog-to-digital converter (ADC)"):
//! one software-started conversion per channel, from the 1 kHz sample task, which owns
//! the ADC.
//!
//! The ADC clock is PCLK2 divided by the smallest prescaler that keeps it within the
//! datasheet's limit (21 MHz on the PLL tree, 8 MHz on the reset clocks), derived per
//! clock tree at compile time ([`AdcClock`]); every channel is sampled for
//! [`ADC_SAMPLE_CYCLES`].

use crate::model::force::sampling::{AdcChannel, AdcCodes};
use crate::nucleo::clocks::{ClockTree, PLL_168_MHZ, RESET_CLOCKS};
use stm32f4::stm32f446 as pac;

use pac::adc1::smpr1::SMP10;
use pac::adc_common::ccr::ADCPRE;

/// The ADC1 input each spindle-drive channel is wired to: speed, power, force and the
/// phase voltages on PC0–PC5 (IN10–IN15), the phase currents i_u and i_v on PB0 and PB1
/// (IN8 and IN9).
pub const fn adc_input(channel: AdcChannel) -> u8 {
    match channel {
        AdcChannel::Speed => 10,
        AdcChannel::Power => 11,
        AdcChannel::Force => 12,
        AdcChannel::VoltsU => 13,
        AdcChannel::VoltsV => 14,
        AdcChannel::VoltsW => 15,
        AdcChannel::AmpsU => 8,
        AdcChannel::AmpsV => 9,
    }
}

/// ADC1 inputs in conversion order, the model's channel order ([`AdcChannel::ALL`]).
pub const ADC_CHANNELS: [u8; AdcChannel::COUNT] = {
    let mut inputs = [0; AdcChannel::COUNT];
    let mut i = 0;
    while i < AdcChannel::COUNT {
        inputs[i] = adc_input(AdcChannel::ALL[i]);
        i += 1;
    }
    inputs
};
// The board's wiring, by physical meaning: the sample's i_u (word 6 of the model's order)
// is converted from PB0 = IN8, its speed (word 0) from PC0 = IN10. A change of the model's
// channel order fails the build here.
const _: () = assert!(matches!(ADC_CHANNELS, [10, 11, 12, 13, 14, 15, 8, 9]));
const _: () = assert!(ADC_CHANNELS[AdcChannel::AmpsU.index()] == 8);

/// Highest ADC clock (Hz) for VDDA 2.4–3.6 V (STM32F446 datasheet; 18 MHz below 2.4 V).
const ADC_CLK_MAX_HZ: u32 = 36_000_000;
/// ADC sampling time per channel (ADC clocks). With the datasheet's R_AIN formula
/// (C_ADC 7 pF max, R_ADC 6 kΩ, 12 bit) at 21 MHz this tolerates a source impedance of
/// about 30 kΩ; the reset value, 3 clocks, tolerates none at this clock.
pub const ADC_SAMPLE_CYCLES: u32 = 56;
/// ADC conversion time (ADC clocks): sampling + 12 for the 12-bit approximation.
const ADC_CONVERSION_CYCLES: u32 = ADC_SAMPLE_CYCLES + 12;
/// ADC_SMPRx code of [`ADC_SAMPLE_CYCLES`].
const SAMPLE_TIME: SMP10 = sample_time(ADC_SAMPLE_CYCLES);

/// The ADC_SMPRx code of a sampling time of `cycles` ADC clocks.
const fn sample_time(cycles: u32) -> SMP10 {
    match cycles {
        3 => SMP10::Cycles3,
        15 => SMP10::Cycles15,
        28 => SMP10::Cycles28,
        56 => SMP10::Cycles56,
        84 => SMP10::Cycles84,
        112 => SMP10::Cycles112,
        144 => SMP10::Cycles144,
        480 => SMP10::Cycles480,
        _ => panic!("not an ADC sampling time"),
    }
}

/// The ADC clock of one clock tree.
#[derive(Clone, Copy)]
pub struct AdcClock {
    /// ADC_CCR ADCPRE: PCLK2 / 2, 4, 6 or 8.
    pub prescaler: ADCPRE,
    /// The ADC clock it gives (Hz).
    pub hz: u32,
    /// Core cycles one conversion lasts.
    pub conversion_cycles: u32,
}

impl AdcClock {
    /// The smallest ADC prescaler that keeps the ADC clock within [`ADC_CLK_MAX_HZ`] at
    /// `tree`'s PCLK2.
    pub const fn for_clocks(tree: &ClockTree) -> Self {
        let pclk2_hz = tree.pclk2_hz();
        let prescalers = [
            (ADCPRE::Div2, 2),
            (ADCPRE::Div4, 4),
            (ADCPRE::Div6, 6),
            (ADCPRE::Div8, 8),
        ];
        let mut i = 0;
        while i < prescalers.len() {
            let (prescaler, div) = prescalers[i];
            let hz = pclk2_hz / div;
            if hz <= ADC_CLK_MAX_HZ {
                return AdcClock {
                    prescaler,
                    hz,
                    conversion_cycles: ADC_CONVERSION_CYCLES * tree.sysclk_hz().div_ceil(hz),
                };
            }
            i += 1;
        }
        panic!("PCLK2 too fast for the ADC")
    }
}

/// Longest wait for an ADC end of conversion (polls): each poll takes at least one core
/// cycle, so twice the conversion's length in core cycles on either clock tree.
#[cfg_attr(feature = "emulated", allow(dead_code))]
const ADC_EOC_POLLS: u32 = 2 * max(
    AdcClock::for_clocks(&PLL_168_MHZ).conversion_cycles,
    AdcClock::for_clocks(&RESET_CLOCKS).conversion_cycles,
);

const fn max(a: u32, b: u32) -> u32 {
    if a > b {
        a
    } else {
        b
    }
}

const _: () = {
    let pll = AdcClock::for_clocks(&PLL_168_MHZ);
    assert!(pll.hz == 21_000_000 && matches!(pll.prescaler, ADCPRE::Div4));
    let reset = AdcClock::for_clocks(&RESET_CLOCKS);
    assert!(reset.hz == 8_000_000 && matches!(reset.prescaler, ADCPRE::Div2));
};

/// The ADC inputs analog (PC0–PC5, PB0, PB1); the ADC clock `clock`; every channel
/// sampled for [`ADC_SAMPLE_CYCLES`]; then ADC1 on (ADON). t_STAB = 3 µs must pass before
/// the first conversion, which the first TIM6 tick, 1 ms later, leaves.
pub fn configure_adc(
    gpiob: &pac::GPIOB,
    gpioc: &pac::GPIOC,
    common: &pac::ADC_COMMON,
    adc1: &pac::ADC1,
    clock: &AdcClock,
) {
    gpioc.moder().modify(|_, w| {
        w.moder0()
            .analog()
            .moder1()
            .analog()
            .moder2()
            .analog()
            .moder3()
            .analog()
            .moder4()
            .analog()
            .moder5()
            .analog()
    });
    gpiob
        .moder()
        .modify(|_, w| w.moder0().analog().moder1().analog());
    common
        .ccr()
        .modify(|_, w| w.adcpre().variant(clock.prescaler));
    adc1.smpr1().write(|w| {
        w.smp10()
            .variant(SAMPLE_TIME)
            .smp11()
            .variant(SAMPLE_TIME)
            .smp12()
            .variant(SAMPLE_TIME)
            .smp13()
            .variant(SAMPLE_TIME)
            .smp14()
            .variant(SAMPLE_TIME)
            .smp15()
            .variant(SAMPLE_TIME)
    });
    adc1.smpr2()
        .write(|w| w.smp8().variant(SAMPLE_TIME).smp9().variant(SAMPLE_TIME));
    adc1.cr2().modify(|_, w| w.adon().enabled());
}

/// One conversion of every channel, in [`AdcCodes`] order.
pub fn convert_all() -> AdcCodes {
    AdcCodes::from_array(ADC_CHANNELS.map(convert))
}

/// One software-started ADC1 conversion of `channel` ([`ADC_CONVERSION_CYCLES`] ADC
/// clocks: 3.2 µs at the PLL tree's 21 MHz, 8.5 µs at the fallback's 8 MHz); 0 if it
/// does not complete within [`ADC_EOC_POLLS`] polls (never blocks forever). The sample
/// task converts [`ADC_CHANNELS`]; the on-target tests the internal reference (17).
pub fn convert(channel: u8) -> u16 {
    // SAFETY: ADC1 is owned by the 1 kHz sample task alone (the on-target tests run
    // without it). SQ1 has no named values in the PAC; the field writer keeps its 5
    // bits, so any `channel` selects an input (the board's are below 19). EOC is cleared
    // by reading DR.
    unsafe {
        let adc = &*pac::ADC1::ptr();
        adc.sqr3().write(|w| w.sq1().bits(channel));
        adc.cr2().modify(|_, w| w.swstart().start());
        result(adc, channel)
    }
}

/// The conversion's 12-bit result, once EOC is set.
#[cfg(not(feature = "emulated"))]
fn result(adc: &pac::adc1::RegisterBlock, _channel: u8) -> u16 {
    for _ in 0..ADC_EOC_POLLS {
        if adc.sr().read().eoc().is_complete() {
            return adc.dr().read().data().bits() & 0x0fff;
        }
    }
    0
}

/// Emulated: QEMU's ADC never sets EOC; the seam holds the code the driver put there.
#[cfg(feature = "emulated")]
fn result(_adc: &pac::adc1::RegisterBlock, channel: u8) -> u16 {
    crate::nucleo::emulated::registers::adc_result(channel) & 0x0fff
}
