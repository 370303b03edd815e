//! The Nucleo-F446RE's board code (feature `nucleo`, thumb targets only): the setup steps
//! its `init` runs and the register accesses its tasks make, one module per peripheral,
//! in the library so that the RTIC application (`src/bin/nucleo/`) and the on-target tests
//! (`tests/on_target.rs`) call the same functions.
//!
//! The steps, in `init`'s order: the clock tree first ([`clocks`]: SYSCLK 168 MHz from the
//! PLL fed by the HSI; every setting below derived from it at compile time and checked by
//! `const` assertions; [`configure_clocks`] falls back to the reset clocks), then the pins
//! and their EXTI lines ([`pins`]), the ADC ([`adc`]) and the timers ([`timers`]).
//! [`board::Nucleo`] is the [`Board`](crate::board::Board) the handlers see; [`cpu_load`]
//! reads the DWT cycle counter. With the `emulated` feature (QEMU's `netduinoplus2`),
//! `emulated` holds the seams that replace what that machine does not emulate
//! (docs/firmware.md lists them) and the defmt logger that writes to a semihosting file.

pub mod adc;
pub mod board;
pub mod clocks;
pub mod cpu_load;
#[cfg(feature = "emulated")]
pub mod emulated;
#[cfg(feature = "panic-check")]
mod null_logger;
pub mod pins;
pub mod timers;

use adc::AdcClock;
use clocks::ClockTree;
use stm32f4::stm32f446 as pac;
use timers::TimerSettings;

/// Every setting that depends on the clock tree, for one tree; built at compile time.
#[derive(Clone, Copy)]
pub struct BusTiming {
    /// SYSCLK = HCLK (Hz).
    pub sysclk_hz: u32,
    /// The APB1 timers' prescalers and reloads.
    pub timers: TimerSettings,
    /// The ADC clock.
    pub adc: AdcClock,
}

impl BusTiming {
    /// The settings of `tree`.
    pub const fn for_clocks(tree: &ClockTree) -> Self {
        BusTiming {
            sysclk_hz: tree.sysclk_hz(),
            timers: TimerSettings::for_clocks(tree),
            adc: AdcClock::for_clocks(tree),
        }
    }
}

/// The settings of the clock tree this firmware sets up: PLL, SYSCLK 168 MHz.
pub const PLL_TIMING: BusTiming = BusTiming::for_clocks(&clocks::PLL_168_MHZ);
/// The fallback if the PLL does not come up: the reset clocks (HSI 16 MHz, every bus /1).
pub const RESET_TIMING: BusTiming = BusTiming::for_clocks(&clocks::RESET_CLOCKS);

/// The clock tree first: every timer and the ADC are set from the bus clocks it gives.
/// Should the PLL not come up, the board runs on the reset clocks with settings derived
/// for them, and says so.
pub fn configure_clocks(rcc: &pac::RCC, pwr: &pac::PWR, flash: &pac::FLASH) -> BusTiming {
    match clocks::start_pll(rcc, pwr, flash) {
        Ok(()) => PLL_TIMING,
        Err(fault) => {
            defmt::error!(
                "clock setup failed ({}): running from the 16 MHz HSI, the measurement \
                 tasks take 10.5 times longer than the 168 MHz budget of docs/firmware.md",
                fault
            );
            RESET_TIMING
        }
    }
}

/// The board set up in `init`'s order: the clock tree ([`configure_clocks`]), the
/// peripheral clocks, the pins and their EXTI lines, the ADC, then the timers (feed PWM,
/// the FES counter, the sample tick, the control period, the measurement's clock). Returns the bus timing the
/// tree gave. The application's `init` and the on-target tests' `#[init]` both run this.
pub fn bring_up(dp: &pac::Peripherals) -> BusTiming {
    let timing = configure_clocks(&dp.RCC, &dp.PWR, &dp.FLASH);
    clocks::enable_peripheral_clocks(&dp.RCC);
    pins::configure_outputs(&dp.GPIOA);
    pins::configure_measurement_inputs(&dp.GPIOA, &dp.GPIOB, &dp.SYSCFG, &dp.EXTI);
    pins::configure_command_inputs(&dp.GPIOC, &dp.SYSCFG, &dp.EXTI);
    adc::configure_adc(&dp.GPIOB, &dp.GPIOC, &dp.ADC_COMMON, &dp.ADC1, &timing.adc);
    timers::start_feed_pwm(&dp.TIM4, &dp.GPIOB, &timing.timers);
    timers::start_fes_counter(&dp.TIM2, &dp.GPIOB);
    timers::start_sample_tick(&dp.TIM6, &timing.timers);
    timers::start_control_period(&dp.TIM3, &timing.timers);
    timers::start_clock(&dp.TIM5, &timing.timers);
    timing
}
