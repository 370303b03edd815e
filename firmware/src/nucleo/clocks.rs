//! The clock tree: SYSCLK = HCLK = 168 MHz from the main PLL fed by the 16 MHz HSI, and
//! the reset tree the board falls back to should the PLL not come up.
//!
//! After RM0390, "Reset and clock control (RCC)" (the PLL, the bus prescalers, the timer
//! clocks), "Embedded Flash memory interface" (table "Number of wait states according to
//! CPU clock (HCLK) frequency") and "Power controller (PWR)" (voltage scaling); the
//! STM32F446 datasheet for the limits. HSE is not used: on a Nucleo-64 it is the
//! ST-LINK's 8 MHz MCO on PH0, connected by default only from board revision MB1136 C-02
//! on (UM1724), while the HSI is on every board.
//!
//! A [`ClockTree`] holds a tree as numbers (and the PAC's prescaler codes); every
//! clock-dependent setting of the board (the flash latency here, the timer prescalers in
//! `timers`, the ADC prescaler in `adc`) is derived from it at compile time, and the
//! `const` assertions below check RM0390's and the datasheet's limits, so a wrong number
//! stops the build, not the firmware.

use stm32f4::stm32f446 as pac;

use pac::flash::acr::LATENCY;
use pac::rcc::cfgr::{HPRE, PPRE1};
use pac::rcc::pllcfgr::PLLP;

/// HSI RC oscillator: the reset clock and the PLL input (Hz).
pub const HSI_HZ: u32 = 16_000_000;

/// The main PLL's dividers (RCC_PLLCFGR), fed by the HSI.
#[derive(Clone, Copy)]
pub struct Pll {
    /// PLLM, the input divider (bits 5:0; 2–63).
    pub m: u8,
    /// PLLN, the VCO multiplier (bits 14:6; 50–432).
    pub n: u16,
    /// PLLP, the SYSCLK divider (bits 17:16: 2, 4, 6 or 8).
    pub p: PLLP,
    /// PLLQ, the 48 MHz-domain divider (bits 27:24; 2–15; USB/SDIO/RNG, unused here).
    pub q: u8,
}

impl Pll {
    /// VCO input = HSI / M (Hz).
    pub const fn vco_in_hz(&self) -> u32 {
        HSI_HZ / self.m as u32
    }

    /// VCO output = VCO input × N (Hz).
    pub const fn vco_hz(&self) -> u32 {
        self.vco_in_hz() * self.n as u32
    }

    /// PLLP as a divisor.
    pub const fn p_div(&self) -> u32 {
        match self.p {
            PLLP::Div2 => 2,
            PLLP::Div4 => 4,
            PLLP::Div6 => 6,
            PLLP::Div8 => 8,
        }
    }

    /// The PLL's SYSCLK output = VCO / P (Hz).
    pub const fn sysclk_hz(&self) -> u32 {
        self.vco_hz() / self.p_div()
    }

    /// PLL48CLK = VCO / Q (Hz).
    pub const fn pll48_hz(&self) -> u32 {
        self.vco_hz() / self.q as u32
    }
}

/// A clock tree: SYSCLK from the PLL (or the HSI itself), then the AHB and APB prescalers
/// (RCC_CFGR).
#[derive(Clone, Copy)]
pub struct ClockTree {
    /// The main PLL, or `None` for SYSCLK = HSI.
    pub pll: Option<Pll>,
    /// AHB prescaler (HPRE): HCLK = SYSCLK / this.
    pub ahb: HPRE,
    /// APB1 prescaler (PPRE1): PCLK1 = HCLK / this.
    pub apb1: PPRE1,
    /// APB2 prescaler (PPRE2, the PAC types it with PPRE1's codes): PCLK2 = HCLK / this.
    pub apb2: PPRE1,
}

/// The PLL of [`PLL_168_MHZ`]: M 8 gives a 2 MHz VCO input, the value RM0390 recommends
/// to limit jitter (1–2 MHz); N 168 a 336 MHz VCO (100–432 MHz); P 2 gives SYSCLK
/// 168 MHz, the most voltage scale 1 allows without over-drive; Q 7 gives exactly 48 MHz
/// (unused). PLLR keeps its reset value 2 (it feeds nothing here).
pub const PLL: Pll = Pll {
    m: 8,
    n: 168,
    p: PLLP::Div2,
    q: 7,
};

/// The tree this firmware sets up: SYSCLK = HCLK = 168 MHz; APB1 /4 = 42 MHz (its timers
/// TIM2–TIM7 at 84 MHz), APB2 /2 = 84 MHz (ADC1, SYSCFG); 5 flash wait states.
pub const PLL_168_MHZ: ClockTree = ClockTree {
    pll: Some(PLL),
    ahb: HPRE::Div1,
    apb1: PPRE1::Div4,
    apb2: PPRE1::Div2,
};

/// The reset tree (HSI 16 MHz, every bus /1), where the board stays if the PLL setup
/// fails: the timer and ADC settings derived for it keep the 1 kHz and 20 Hz periods and
/// the 15.625 kHz PWM exact, and only the FES-rate budget shrinks (10.5 times fewer
/// cycles; TIM2's input filter then needs levels of 500 ns, FES rates up to about 1 MHz).
pub const RESET_CLOCKS: ClockTree = ClockTree {
    pll: None,
    ahb: HPRE::Div1,
    apb1: PPRE1::Div1,
    apb2: PPRE1::Div1,
};

impl ClockTree {
    /// SYSCLK (Hz).
    pub const fn sysclk_hz(&self) -> u32 {
        match self.pll {
            Some(pll) => pll.sysclk_hz(),
            None => HSI_HZ,
        }
    }

    /// HCLK, the core, AHB and flash clock (Hz).
    pub const fn hclk_hz(&self) -> u32 {
        self.sysclk_hz() / ahb_div(self.ahb)
    }

    /// PCLK1, the APB1 bus clock (Hz).
    pub const fn pclk1_hz(&self) -> u32 {
        self.hclk_hz() / apb_div(self.apb1)
    }

    /// PCLK2, the APB2 bus clock (Hz): clocks ADC1 and SYSCFG.
    pub const fn pclk2_hz(&self) -> u32 {
        self.hclk_hz() / apb_div(self.apb2)
    }

    /// Kernel clock of the APB1 timers TIM2–TIM7 (Hz).
    pub const fn apb1_timer_hz(&self) -> u32 {
        timer_clock(self.pclk1_hz(), self.apb1)
    }

    /// Kernel clock of the APB2 timers (Hz; none is used).
    pub const fn apb2_timer_hz(&self) -> u32 {
        timer_clock(self.pclk2_hz(), self.apb2)
    }

    /// Flash wait states at this HCLK for VDD 2.7–3.6 V: one per started 30 MHz (RM0390
    /// table "Number of wait states according to CPU clock (HCLK) frequency").
    pub const fn flash_wait_states(&self) -> u32 {
        (self.hclk_hz() - 1) / 30_000_000
    }

    /// [`ClockTree::flash_wait_states`] as the FLASH_ACR LATENCY code.
    pub const fn flash_latency(&self) -> LATENCY {
        match self.flash_wait_states() {
            0 => LATENCY::Ws0,
            1 => LATENCY::Ws1,
            2 => LATENCY::Ws2,
            3 => LATENCY::Ws3,
            4 => LATENCY::Ws4,
            5 => LATENCY::Ws5,
            _ => panic!("HCLK above the STM32F446's 180 MHz"),
        }
    }
}

/// HPRE as a divisor.
const fn ahb_div(p: HPRE) -> u32 {
    match p {
        HPRE::Div1 => 1,
        HPRE::Div2 => 2,
        HPRE::Div4 => 4,
        HPRE::Div8 => 8,
        HPRE::Div16 => 16,
        HPRE::Div64 => 64,
        HPRE::Div128 => 128,
        HPRE::Div256 => 256,
        HPRE::Div512 => 512,
    }
}

/// PPRE1 / PPRE2 as a divisor.
const fn apb_div(p: PPRE1) -> u32 {
    match p {
        PPRE1::Div1 => 1,
        PPRE1::Div2 => 2,
        PPRE1::Div4 => 4,
        PPRE1::Div8 => 8,
        PPRE1::Div16 => 16,
    }
}

/// The APB timers' kernel clock (Hz): PCLK when its prescaler is 1, else twice PCLK
/// (RCC_DCKCFGR TIMPRE = 0, its reset value).
const fn timer_clock(pclk_hz: u32, apb: PPRE1) -> u32 {
    if apb_div(apb) == 1 {
        pclk_hz
    } else {
        pclk_hz * 2
    }
}

// RM0390 / datasheet limits, checked when the firmware is built.
const _: () = assert!(PLL.m >= 2 && PLL.m <= 63 && HSI_HZ.is_multiple_of(PLL.m as u32));
const _: () = assert!(PLL.n >= 50 && PLL.n <= 432);
const _: () = assert!(PLL.q >= 2 && PLL.q <= 15);
const _: () = assert!(PLL.vco_in_hz() >= 1_000_000 && PLL.vco_in_hz() <= 2_000_000);
const _: () = assert!(PLL.vco_hz() >= 100_000_000 && PLL.vco_hz() <= 432_000_000);
const _: () = assert!(PLL.sysclk_hz() == 168_000_000 && PLL.vco_hz().is_multiple_of(PLL.p_div()));
const _: () = assert!(PLL.pll48_hz() == 48_000_000 && PLL.vco_hz().is_multiple_of(PLL.q as u32));
const _: () = assert!(PLL_168_MHZ.hclk_hz() == PLL_168_MHZ.sysclk_hz());
const _: () = assert!(PLL_168_MHZ.hclk_hz() <= 168_000_000);
const _: () = assert!(PLL_168_MHZ.pclk1_hz() == 42_000_000 && PLL_168_MHZ.pclk1_hz() <= 45_000_000);
const _: () = assert!(PLL_168_MHZ.pclk2_hz() == 84_000_000 && PLL_168_MHZ.pclk2_hz() <= 90_000_000);
const _: () = assert!(PLL_168_MHZ.apb1_timer_hz() == 84_000_000);
const _: () = assert!(PLL_168_MHZ.apb2_timer_hz() == 168_000_000);
const _: () = assert!(PLL_168_MHZ.flash_wait_states() == 5);
const _: () = assert!(RESET_CLOCKS.flash_wait_states() == 0);
const _: () = assert!(RESET_CLOCKS.apb1_timer_hz() == HSI_HZ && RESET_CLOCKS.pclk2_hz() == HSI_HZ);

/// The clocks of every peripheral the board uses: GPIOA–GPIOC (AHB1); SYSCFG and ADC1
/// (APB2); TIM2, TIM3, TIM4 and TIM6 (APB1). Each bus is read back so the writes have
/// reached RCC before the peripherals are used (the delay the STM32F4 errata ask for
/// after an RCC peripheral clock enable).
pub fn enable_peripheral_clocks(rcc: &pac::RCC) {
    rcc.ahb1enr().modify(|_, w| {
        w.gpioaen()
            .enabled()
            .gpioben()
            .enabled()
            .gpiocen()
            .enabled()
    });
    rcc.apb2enr()
        .modify(|_, w| w.syscfgen().enabled().adc1en().enabled());
    rcc.apb1enr().modify(|_, w| {
        w.tim2en()
            .enabled()
            .tim3en()
            .enabled()
            .tim4en()
            .enabled()
            .tim5en()
            .enabled()
            .tim6en()
            .enabled()
    });
    let _ = rcc.ahb1enr().read();
    let _ = rcc.apb2enr().read();
    let _ = rcc.apb1enr().read();
}

/// Longest wait for a PLL lock, a voltage-scale or a clock-switch flag (polls). Every poll
/// takes at least one cycle of the 16 MHz HSI: at least 4 ms, over ten times the PLL's
/// worst-case lock time (datasheet t_LOCK 300 µs).
const CLOCK_READY_POLLS: u32 = HSI_HZ / 250;

/// A clock-setup step that did not complete within its bounded wait.
#[derive(Clone, Copy, defmt::Format)]
pub enum ClockFault {
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

/// Raises SYSCLK from the reset clock (HSI 16 MHz, PLL off) to [`PLL_168_MHZ`]: PLL from
/// HSI, voltage scale 1, 5 flash wait states with prefetch and the ART caches, AHB /1,
/// APB1 /4, APB2 /2, then the switch. Each wait is bounded; on a fault the clocks are put
/// back to [`RESET_CLOCKS`] and the fault is returned.
pub fn start_pll(rcc: &pac::RCC, pwr: &pac::PWR, flash: &pac::FLASH) -> Result<(), ClockFault> {
    // PWR's bus clock, then a read back so the write has reached RCC before PWR is used
    // (the delay the STM32F4 errata ask for after an RCC peripheral clock enable).
    rcc.apb1enr().modify(|_, w| w.pwren().set_bit());
    let _ = rcc.apb1enr().read();
    // Voltage scale 1 (also the reset value); it is written while the PLL is off and
    // takes effect when the PLL starts.
    pwr.cr().modify(|_, w| w.vos().scale1());
    // SAFETY: PLLM, PLLN and PLLQ have no named values in the PAC; M, N, Q are within
    // their fields (checked by the `const` assertions above).
    rcc.pllcfgr().modify(|_, w| unsafe {
        w.pllsrc()
            .hsi()
            .pllm()
            .bits(PLL.m)
            .plln()
            .bits(PLL.n)
            .pllp()
            .variant(PLL.p)
            .pllq()
            .bits(PLL.q)
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
    let latency = PLL_168_MHZ.flash_latency();
    flash.acr().modify(|_, w| {
        w.latency()
            .variant(latency)
            .prften()
            .enabled()
            .icen()
            .enabled()
            .dcen()
            .enabled()
    });
    if flash.acr().read().latency().bits() != latency as u8 {
        pll_off();
        return Err(ClockFault::FlashLatency);
    }
    // Bus prescalers first (harmless at 16 MHz), then SYSCLK = PLL.
    rcc.cfgr().modify(|_, w| {
        w.hpre()
            .variant(PLL_168_MHZ.ahb)
            .ppre1()
            .variant(PLL_168_MHZ.apb1)
            .ppre2()
            .variant(PLL_168_MHZ.apb2)
    });
    rcc.cfgr().modify(|_, w| w.sw().pll());
    if !wait_for(CLOCK_READY_POLLS, || rcc.cfgr().read().sws().is_pll()) {
        rcc.cfgr().modify(|_, w| {
            w.sw()
                .hsi()
                .ppre1()
                .variant(RESET_CLOCKS.apb1)
                .ppre2()
                .variant(RESET_CLOCKS.apb2)
        });
        let _ = wait_for(CLOCK_READY_POLLS, || rcc.cfgr().read().sws().is_hsi());
        pll_off();
        return Err(ClockFault::Switch);
    }
    Ok(())
}
