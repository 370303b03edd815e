//! The Nucleo image under QEMU's `netduinoplus2` (STM32F405, Cortex-M4F; the `emulated`
//! feature): the co-simulation driver and the seams it drives.
//!
//! Everything QEMU emulates runs as on the board: the clock setup (RCC reads 0 there, so
//! its bounded waits run out and the board falls back to the 16 MHz HSI, which the boot
//! log says), SYSCFG and EXTI (line sources, edges, masks, the acknowledging writes),
//! TIM2–TIM4's registers, ADC1's register sequence, the NVIC with the Nucleo's interrupt
//! numbers and priorities, the FPU. What it does not is replaced by [`registers`] (in the
//! library's board code, `tooltouch_firmware::nucleo::emulated`), one
//! function per seam (docs/firmware.md lists them with the reason): the GPIO data
//! registers, TIM2's external-clock count and its compare match, TIM5's count and compare (the
//! measurement's clock and its alarm), the ADC's results, the
//! EXTI pending bits of the command lines, TIM3's update interrupt (left disabled: the
//! stream's control ticks pend it), TIM6 (not emulated: the stream's samples pend it),
//! and RTT (the library's `emulated::defmt_log`: the frames go to a semihosting file).
//!
//! [`driver`] replays the stream (`tooltouch_firmware::cosim`) from `idle` as the QEMU
//! image's driver does, pending the Nucleo's interrupts: EXTI0, EXTI1, EXTI2, EXTI9_5,
//! TIM2 (on the virtual count's compare match), TIM7 (observe), EXTI15_10, TIM6_DAC, TIM3.

pub mod driver;
pub use tooltouch_firmware::nucleo::emulated::registers;

use tooltouch_firmware::handlers::Counters;
use tooltouch_firmware::model::force::kernel::ForceKernel;
use tooltouch_firmware::model::MeasureOutputs;
use tooltouch_firmware::semihosting;

/// Idle of the emulated image: replays the event streams through the Nucleo's
/// interrupts, writes the trace, ends the QEMU run with its status.
pub fn run(
    snapshot: impl rtic::Mutex<T = MeasureOutputs>,
    force: impl rtic::Mutex<T = ForceKernel>,
    counters: impl rtic::Mutex<T = Counters>,
) -> ! {
    let mut driver = driver::Driver::new(snapshot, force, counters);
    let code = semihosting::replay(&mut driver);
    defmt::info!("co-simulation ended, QEMU exit status {}", code);
    semihosting::exit(code)
}
