//! The Nucleo-F446RE as the handlers see it ([`Board`]): pins read and driven through
//! `pins`, the FES count and compare in TIM2, the clock and its alarm in TIM5, the feed override in TIM4's duty, the drive
//! signals from ADC1.

use super::{adc, pins, timers};
use crate::board::Board;
use crate::model::force::events::ForceEvent;
use crate::model::force::sampling::AdcCodes;
use stm32f4::stm32f446 as pac;

/// The Nucleo-F446RE.
pub struct Nucleo;

impl Board for Nucleo {
    fn arm() -> bool {
        pins::arm()
    }
    fn contact() -> bool {
        pins::contact()
    }
    fn scale() -> (bool, bool) {
        pins::scale()
    }
    fn fes_count() -> u32 {
        timers::fes_count()
    }
    fn set_fes_compare(at: u32) {
        timers::set_fes_compare(at);
    }
    fn pend_fes_compare() {
        rtic::pend(pac::Interrupt::TIM2);
    }
    fn time() -> u32 {
        timers::time()
    }
    fn set_time_alarm(at: Option<u32>) {
        timers::set_time_alarm(at);
    }
    fn pend_time_alarm() {
        rtic::pend(pac::Interrupt::TIM5);
    }
    fn set_register_now(on: bool) {
        pins::set_register_now(on);
    }
    fn set_status(faults: u8, confirmed: bool) {
        pins::set_status(faults, confirmed);
    }
    fn adc() -> AdcCodes {
        adc::convert_all()
    }
    fn force_command() -> Option<ForceEvent> {
        pins::next_command()
    }
    fn set_feed_override(percent: u8) {
        timers::set_feed_override(percent);
    }
    fn set_wear_alarm(on: bool) {
        pins::set_wear_alarm(on);
    }
}
