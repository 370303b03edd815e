//! The Nucleo-F446RE's board code tested on the chip (defmt-test: every test in one image,
//! run in order, each announced as `(i/n) running `name`...`, the run ended by a
//! semihosting exit, status 0 when all passed; a failed assertion logs its message over
//! defmt and ends the run with a panic).
//!
//! On a board (`cd firmware && cargo nucleo-test`: probe-rs flashes the image, prints the
//! defmt log and exits with the image's status) every test runs. It needs one jumper: D2
//! (PA10, driven by the tests) to D3 (PB3, TIM2_CH2, the FES input TIM2 counts); nothing
//! else may drive PA0, PA1, PA10 or PB3 during the run (the handler test pulls PA0 and PA1
//! up to arm and make contact).
//!
//! Under QEMU's `netduinoplus2` (the `emulated` build; tests/firmware/on_target.rs at the
//! repository root runs it in `cargo xtask test`) only what that machine emulates runs:
//! the clock tree's setup (RCC reads 0 there, so it must fall back to the HSI) and TIM3's
//! count rate (QEMU's timers count virtual time at 1 GHz / (PSC + 1), SysTick at its
//! fixed 168 MHz). Every other test logs `skipped under QEMU netduinoplus2: <reason>` and
//! returns: there only, never on a board.
#![no_std]
#![no_main]

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{DWT, SYST};
use stm32f4::stm32f446 as pac;
use tooltouch_firmware::nucleo::{self as board, BusTiming};

#[cfg(not(feature = "emulated"))]
use defmt_rtt as _;

/// What the tests share: the board set up as `init` sets it up, and the clocks it runs.
pub struct Board {
    dp: pac::Peripherals,
    timing: BusTiming,
}

/// SysTick: started once, on the core clock, counting down from 2^24 − 1.
fn start_systick(syst: &mut SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00ff_ffff);
    syst.clear_current();
    syst.enable_counter();
}

/// SysTick's count now (it counts down, 24 bits).
fn systick() -> u32 {
    SYST::get_current()
}

/// SysTick ticks from `start` to `now` (both read with [`systick`]; under 2^24 apart).
fn ticks_since(start: u32, now: u32) -> u32 {
    start.wrapping_sub(now) & 0x00ff_ffff
}

/// Why a test cannot run under QEMU's netduinoplus2; logged in place of running it.
#[cfg(feature = "emulated")]
fn skip(reason: &str) {
    defmt::println!("skipped under QEMU netduinoplus2: {=str}", reason);
}

/// Waits until `flag()` holds, at most `ticks` SysTick ticks (below 2^24, SysTick's
/// range); the ticks it took, or `None` on a timeout.
#[cfg(not(feature = "emulated"))]
fn wait_flag(ticks: u32, mut flag: impl FnMut() -> bool) -> Option<u32> {
    let start = systick();
    loop {
        let waited = ticks_since(start, systick());
        if flag() {
            return Some(waited);
        }
        if waited > ticks {
            return None;
        }
    }
}

/// SysTick ticks over `periods` update events of a timer whose flag `uif()` reads and
/// `clear()` clears, from one update to the `periods`-th after it; `None` if an update
/// does not come within `max_period` ticks.
#[cfg(not(feature = "emulated"))]
fn update_periods(
    periods: u32,
    max_period: u32,
    uif: impl Fn() -> bool,
    clear: impl Fn(),
) -> Option<u32> {
    clear();
    wait_flag(max_period, &uif)?;
    clear();
    let start = systick();
    for _ in 0..periods {
        wait_flag(max_period, &uif)?;
        clear();
    }
    Some(ticks_since(start, systick()))
}

/// The FES jumper's driving end: PA10 (D2), wired to PB3 (D3).
#[cfg(not(feature = "emulated"))]
mod fes_jumper {
    use stm32f4::stm32f446 as pac;

    /// Core cycles each level is held: TIM2's input filter needs 8 of its 84 MHz clocks
    /// (16 core cycles at 168 MHz); this is over ten times that.
    const HOLD_CYCLES: u32 = 200;

    /// PA10 a push-pull output, low.
    pub fn configure(gpioa: &pac::GPIOA) {
        gpioa.bsrr().write(|w| w.br10().set_bit());
        gpioa.moder().modify(|_, w| w.moder10().output());
    }

    /// `n` rising edges on PA10, each level held [`HOLD_CYCLES`]; returns once TIM2 has
    /// had the time to count the last one.
    pub fn pulses(gpioa: &pac::GPIOA, n: u32) {
        for _ in 0..n {
            gpioa.bsrr().write(|w| w.bs10().set_bit());
            cortex_m::asm::delay(HOLD_CYCLES);
            gpioa.bsrr().write(|w| w.br10().set_bit());
            cortex_m::asm::delay(HOLD_CYCLES);
        }
    }
}

/// netduinoplus2's timers count virtual time at this rate before their prescaler
/// (QEMU's stm32f2xx_timer: `clock-frequency`, 1 GHz, which the machine does not set).
#[cfg(feature = "emulated")]
const QEMU_TIMER_HZ: u64 = 1_000_000_000;
/// netduinoplus2's SysTick clock: the machine's fixed SYSCLK, 168 MHz of virtual time,
/// whatever RCC (not emulated) is set to.
#[cfg(feature = "emulated")]
const QEMU_SYSTICK_HZ: u64 = 168_000_000;

#[defmt_test::tests]
mod tests {
    use super::*;
    use tooltouch_firmware::nucleo::clocks;
    #[cfg(not(feature = "emulated"))]
    use tooltouch_firmware::nucleo::{adc, timers};

    /// The board as the application's `init` sets it up, in its order (the RTIC app is
    /// not linked: no interrupt is enabled in the NVIC, the tests poll the flags).
    #[init]
    fn init() -> Board {
        let mut cp = cortex_m::Peripherals::take().unwrap();
        let dp = pac::Peripherals::take().unwrap();
        start_systick(&mut cp.SYST);
        board::cpu_load::start_cycle_counter(&mut cp.DCB, &mut cp.DWT);
        let timing = board::bring_up(&dp);
        defmt::println!("SYSCLK {=u32} Hz", timing.sysclk_hz);
        Board { dp, timing }
    }

    /// On a board the PLL comes up: SYSCLK 168 MHz and RCC, FLASH read back as
    /// `clocks::PLL_168_MHZ` says. Under QEMU RCC reads 0: the bounded wait for the PLL
    /// runs out and the board falls back to the reset clocks (the log says `PllLock`).
    #[test]
    fn the_clock_tree_comes_up_as_init_reports(b: &mut Board) {
        let rcc = &b.dp.RCC;
        #[cfg(not(feature = "emulated"))]
        {
            let tree = clocks::PLL_168_MHZ;
            defmt::assert_eq!(b.timing.sysclk_hz, 168_000_000, "the PLL did not come up");
            defmt::assert!(rcc.cr().read().pllrdy().bit_is_set(), "PLLRDY");
            defmt::assert!(rcc.cfgr().read().sws().is_pll(), "SYSCLK is not the PLL");
            let pll = rcc.pllcfgr().read();
            defmt::assert!(pll.pllsrc().is_hsi(), "the PLL's input is not the HSI");
            defmt::assert_eq!(pll.pllm().bits(), clocks::PLL.m, "PLLM");
            defmt::assert_eq!(pll.plln().bits(), clocks::PLL.n, "PLLN");
            defmt::assert_eq!(pll.pllp().bits(), clocks::PLL.p as u8, "PLLP");
            defmt::assert_eq!(pll.pllq().bits(), clocks::PLL.q, "PLLQ");
            let cfgr = rcc.cfgr().read();
            defmt::assert_eq!(cfgr.hpre().bits(), tree.ahb as u8, "HPRE");
            defmt::assert_eq!(cfgr.ppre1().bits(), tree.apb1 as u8, "PPRE1");
            defmt::assert_eq!(cfgr.ppre2().bits(), tree.apb2 as u8, "PPRE2");
            let acr = b.dp.FLASH.acr().read();
            defmt::assert_eq!(
                acr.latency().bits(),
                tree.flash_wait_states() as u8,
                "LATENCY"
            );
            defmt::assert!(
                acr.prften().bit_is_set() && acr.icen().bit_is_set() && acr.dcen().bit_is_set()
            );
        }
        #[cfg(feature = "emulated")]
        {
            defmt::assert_eq!(
                b.timing.sysclk_hz,
                clocks::HSI_HZ,
                "expected the HSI fallback"
            );
            defmt::assert_eq!(
                b.timing.timers.control_psc,
                board::RESET_TIMING.timers.control_psc
            );
            // The fallback switched the PLL off again (RCC_CR reads 0 here anyway).
            defmt::assert!(rcc.cr().read().pllon().bit_is_clear());
        }
        defmt::println!("clock tree: SYSCLK {=u32} Hz", b.timing.sysclk_hz);
    }

    /// SysTick (core clock) against the DWT cycle counter (HCLK): both count the core
    /// clock, so SysTick is the core clock the timer tests below compare against.
    #[test]
    fn systick_counts_the_core_clock_like_the_dwt_cycle_counter(_b: &mut Board) {
        #[cfg(feature = "emulated")]
        {
            // The reason, checked: CYCCNT reads 0 there, enabled or not.
            let c0 = DWT::cycle_count();
            cortex_m::asm::delay(10_000);
            defmt::assert_eq!(c0, DWT::cycle_count(), "QEMU's DWT counts: run this test");
            skip("QEMU's DWT cycle counter does not count (CYCCNT reads 0)");
        }
        #[cfg(not(feature = "emulated"))]
        {
            let (s0, c0) = (systick(), DWT::cycle_count());
            cortex_m::asm::delay(1_000_000);
            let (s1, c1) = (systick(), DWT::cycle_count());
            let ticks = ticks_since(s0, s1);
            let cycles = c1.wrapping_sub(c0);
            defmt::println!("SysTick {=u32} ticks, DWT {=u32} cycles", ticks, cycles);
            defmt::assert!(ticks.abs_diff(cycles) <= 16, "SysTick and DWT disagree");
            defmt::assert!(cycles >= 1_000_000, "the delay loop was shorter than asked");
        }
    }

    /// TIM6, the 1 kHz ADC sample tick: 50 update periods last 50 ms of the core clock.
    #[test]
    fn tim6_updates_at_the_sample_rate_against_systick(b: &mut Board) {
        #[cfg(feature = "emulated")]
        {
            let _ = b;
            skip("TIM6 is not emulated (its registers read 0, it never counts)");
        }
        #[cfg(not(feature = "emulated"))]
        {
            let tim6 = &b.dp.TIM6;
            let period = b.timing.sysclk_hz / timers::SAMPLE_HZ;
            // 50 periods: 8.4 M ticks at 168 MHz, within SysTick's 24 bits.
            let ticks = update_periods(
                50,
                2 * period,
                || tim6.sr().read().uif().bit_is_set(),
                || tim6.sr().reset(),
            );
            let ticks = defmt::unwrap!(ticks, "TIM6 raised no update within two periods");
            defmt::println!("TIM6: 50 updates in {=u32} SysTick ticks", ticks);
            // Both clocks come from SYSCLK: exact but for the polling loop's jitter.
            defmt::assert!(ticks.abs_diff(50 * period) <= 200, "TIM6's period is off");
        }
    }

    /// TIM3, the control period. Board: its counter runs at 10 kHz and one update period
    /// lasts 1 / CONTROL_HZ s of the core clock. QEMU: the counter runs at QEMU's timer
    /// clock over the prescaler the board code wrote, against SysTick's 168 MHz.
    #[test]
    fn tim3_counts_at_its_rate_against_systick(b: &mut Board) {
        let tim3 = &b.dp.TIM3;
        let psc = u32::from(tim3.psc().read().psc().bits());
        defmt::assert_eq!(psc, u32::from(b.timing.timers.control_psc), "TIM3 PSC");
        defmt::assert!(tim3.cr1().read().cen().bit_is_set(), "TIM3 is not counting");
        #[cfg(feature = "emulated")]
        {
            let (s0, n0) = (systick(), tim3.cnt().read().bits());
            cortex_m::asm::delay(2_000_000);
            let (s1, n1) = (systick(), tim3.cnt().read().bits());
            let ticks = u64::from(ticks_since(s0, s1));
            let counts = u64::from(n1.wrapping_sub(n0));
            let want = ticks * QEMU_TIMER_HZ / (u64::from(psc) + 1) / QEMU_SYSTICK_HZ;
            defmt::println!(
                "TIM3: {=u64} counts in {=u64} SysTick ticks (QEMU's 1 GHz / (PSC {=u32} + 1): {=u64})",
                counts,
                ticks,
                psc,
                want
            );
            defmt::assert!(counts.abs_diff(want) <= 2, "TIM3's count rate is off");
        }
        #[cfg(not(feature = "emulated"))]
        {
            // The counter: 10 kHz, so 1 ms of SysTick sees 10 counts (±1 for the phase).
            let n0 = tim3.cnt().read().cnt().bits();
            let s0 = systick();
            while ticks_since(s0, systick()) < b.timing.sysclk_hz / 1000 {}
            let n1 = tim3.cnt().read().cnt().bits();
            let arr = u32::from(b.timing.timers.control_arr) + 1;
            let counts = (u32::from(n1) + arr - u32::from(n0)) % arr;
            defmt::println!("TIM3: {=u32} counts in 1 ms", counts);
            defmt::assert!(counts.abs_diff(10) <= 1, "TIM3 does not count at 10 kHz");
            // One period: 8.4 M ticks at 168 MHz; waits of 1.5 periods stay within
            // SysTick's 24 bits.
            let period = b.timing.sysclk_hz / timers::CONTROL_HZ;
            let ticks = update_periods(
                1,
                period + period / 2,
                || tim3.sr().read().uif().bit_is_set(),
                || tim3.sr().reset(),
            );
            let ticks = defmt::unwrap!(ticks, "TIM3 raised no update within 1.5 periods");
            defmt::println!("TIM3: a control period in {=u32} SysTick ticks", ticks);
            defmt::assert!(ticks.abs_diff(period) <= 200, "TIM3's period is off");
        }
    }

    /// TIM2 counts the FES edges on PB3 (the jumper from PA10), its channel 1 compare
    /// flag rises on the pulse that reaches CCR1 (and not before), and the count wraps at
    /// 2^32 with the compare still matching after the wrap.
    #[test]
    fn the_fes_counter_counts_compares_and_wraps(b: &mut Board) {
        #[cfg(feature = "emulated")]
        {
            let _ = b;
            skip(
                "GPIO is not emulated (no edge reaches PB3) and QEMU's TIM2 ignores the \
                 external clock (SMCR) and never compares",
            );
        }
        #[cfg(not(feature = "emulated"))]
        {
            let gpioa = &b.dp.GPIOA;
            let tim2 = &b.dp.TIM2;
            let cc1if = || tim2.sr().read().cc1if().bit_is_set();
            fes_jumper::configure(gpioa);
            let c0 = timers::fes_count();
            fes_jumper::pulses(gpioa, 100);
            let counted = timers::fes_count().wrapping_sub(c0);
            defmt::assert_eq!(
                counted,
                100,
                "TIM2 counted {} of 100 edges: is the jumper D2 (PA10) to D3 (PB3) fitted?",
                counted
            );
            // Compare 10 pulses on: no flag after 9, the flag on the 10th.
            let at = timers::fes_count().wrapping_add(10);
            timers::set_fes_compare(at);
            timers::ack_fes_compare();
            fes_jumper::pulses(gpioa, 9);
            defmt::assert!(!cc1if(), "CC1IF before the compare value");
            fes_jumper::pulses(gpioa, 1);
            defmt::assert_eq!(timers::fes_count(), at);
            defmt::assert!(cc1if(), "no CC1IF on the compare value");
            timers::ack_fes_compare();
            defmt::assert!(!cc1if(), "CC1IF not cleared by ack_fes_compare");
            // The wrap: from 2^32 − 3, compare at 1.
            tim2.cnt().write(|w| w.cnt().set(u32::MAX - 2));
            timers::set_fes_compare(1);
            timers::ack_fes_compare();
            fes_jumper::pulses(gpioa, 3);
            defmt::assert_eq!(timers::fes_count(), 0, "TIM2 did not wrap at 2^32");
            defmt::assert!(!cc1if(), "CC1IF before the compare value");
            fes_jumper::pulses(gpioa, 1);
            defmt::assert_eq!(timers::fes_count(), 1);
            defmt::assert!(cc1if(), "no CC1IF on the compare value after the wrap");
            timers::ack_fes_compare();
            defmt::println!("TIM2: 100 edges counted; compare and wrap as expected");
        }
    }

    /// ADC1 on its internal reference (channel 17): the code the board's conversion
    /// gives, at the board's ADC clock, matches the factory calibration VREFINT_CAL
    /// (taken at VDDA = 3.3 V, the Nucleo's) within 3 %, so full scale (the model's
    /// `ADC_MAX` = 4095) is VDDA = 3.3 V as the drive signals' scaling assumes.
    #[test]
    fn the_adc_reads_its_internal_reference_at_the_calibrated_code(b: &mut Board) {
        #[cfg(feature = "emulated")]
        {
            let _ = b;
            skip("QEMU's ADC never sets EOC and converts no input (its DR holds no sample)");
        }
        #[cfg(not(feature = "emulated"))]
        {
            use tooltouch_firmware::model::force::sampling::ADC_MAX;
            /// VREFINT_CAL: VREFINT's code at VDDA = 3.3 V, 30 °C (STM32F446 datasheet).
            const VREFINT_CAL: *const u16 = 0x1fff_7a2a as *const u16;
            b.dp.ADC_COMMON.ccr().modify(|_, w| w.tsvrefe().set_bit());
            // VREFINT needs over 10 µs of sampling: 480 ADC clocks are 22.9 µs at 21 MHz.
            b.dp.ADC1.smpr1().modify(|_, w| w.smp17().cycles480());
            // Its start-up time (t_START, 10 µs).
            cortex_m::asm::delay(b.timing.sysclk_hz / 10_000);
            // SAFETY: a read of the factory calibration in the system memory (read only).
            let cal = u32::from(unsafe { core::ptr::read_volatile(VREFINT_CAL) });
            let mut sum = 0;
            for _ in 0..16 {
                let code = adc::convert(17);
                defmt::assert!(code > 0 && code <= ADC_MAX, "VREFINT code {}", code);
                sum += u32::from(code);
            }
            let code = sum / 16;
            let vdda_mv = 3300 * cal / code.max(1);
            defmt::println!(
                "ADC: VREFINT {=u32} (calibration {=u32}), VDDA {=u32} mV",
                code,
                cal,
                vdda_mv
            );
            defmt::assert!(code.abs_diff(cal) * 100 <= 3 * cal, "VREFINT's code is off");
        }
    }

    /// The measurement handlers on the board's own registers (TIM2 counting the jumper's
    /// edges, PA0 / PA1 pulled up for arm and contact), timed with the DWT cycle counter
    /// on the paths docs/firmware.md estimates; the FES compare with its 64 folded pulses
    /// must stay within the FES budget (82 cycles per pulse, entry and exit included).
    #[test]
    fn the_handlers_worst_case_cycles_fit_the_fes_budget(b: &mut Board) {
        #[cfg(feature = "emulated")]
        {
            let _ = b;
            skip("QEMU's DWT cycle counter does not count, and GPIO is not emulated");
        }
        #[cfg(not(feature = "emulated"))]
        {
            use tooltouch_firmware::baked;
            use tooltouch_firmware::handlers::{self, MeasureDomain, FES_FOLD_LIMIT};
            use tooltouch_firmware::nucleo::board::Nucleo;
            /// The FES budget: 10 % of 168 MHz at 204 800 pulses/s.
            const BUDGET_PER_PULSE: u32 = 82;
            /// Exception entry and exit, which the handler's call does not include.
            const ENTRY_EXIT: u32 = 22;
            let gpioa = &b.dp.GPIOA;
            let time = |f: &mut dyn FnMut()| {
                let c0 = DWT::cycle_count();
                f();
                DWT::cycle_count().wrapping_sub(c0)
            };
            let config = defmt::unwrap!(baked::measure().ok(), "the baked configuration");
            fes_jumper::configure(gpioa);
            let mut d = MeasureDomain::start::<Nucleo>(&config);
            gpioa
                .pupdr()
                .modify(|_, w| w.pupdr0().pull_up().pupdr1().pull_down());
            cortex_m::asm::delay(1000);
            let arm = time(&mut || handlers::cnc_command::<Nucleo>(&mut d));
            fes_jumper::pulses(gpioa, 10);
            gpioa.pupdr().modify(|_, w| w.pupdr1().pull_up());
            cortex_m::asm::delay(1000);
            let contact = time(&mut || handlers::contact::<Nucleo>(&mut d));
            let mut compare = 0;
            for _ in 0..3 {
                fes_jumper::pulses(gpioa, FES_FOLD_LIMIT);
                compare = compare.max(time(&mut || handlers::fes_compare::<Nucleo>(&mut d)));
            }
            fes_jumper::pulses(gpioa, FES_FOLD_LIMIT);
            let index = time(&mut || handlers::index::<Nucleo>(&mut d));
            let scale = time(&mut || handlers::scale::<Nucleo>(&mut d));
            let o = d.kernel().outputs();
            defmt::assert!(
                o.armed && o.contact,
                "the kernel is not armed and in contact"
            );
            defmt::assert_eq!(
                o.pulses,
                10 + 4 * FES_FOLD_LIMIT,
                "pulses folded since the arm"
            );
            gpioa
                .pupdr()
                .modify(|_, w| w.pupdr0().pull_down().pupdr1().pull_down());
            cortex_m::asm::delay(1000);
            let disarm = time(&mut || handlers::cnc_command::<Nucleo>(&mut d));
            defmt::println!(
                "handler cycles (call to return): arm {=u32}, contact + 10 pulses {=u32}, \
                 FES compare + 64 pulses {=u32}, index + 64 pulses {=u32}, scale {=u32}, \
                 disarm {=u32}",
                arm,
                contact,
                compare,
                index,
                scale,
                disarm
            );
            let per_pulse = (compare + ENTRY_EXIT).div_ceil(FES_FOLD_LIMIT);
            defmt::assert!(
                per_pulse <= BUDGET_PER_PULSE,
                "the FES compare costs {} cycles per pulse, over the budget of {}",
                per_pulse,
                BUDGET_PER_PULSE
            );
            for cycles in [arm, contact, index, scale, disarm] {
                defmt::assert!(
                    cycles + ENTRY_EXIT <= BUDGET_PER_PULSE * FES_FOLD_LIMIT,
                    "a measurement task takes longer than its 64 pulses' budget"
                );
            }
        }
    }
}
