//! The HAL component's period semantics (`host/linuxcnc/hal/tooltouch.comp`) over the golden
//! model: what one call of `tooltouch.0.update` does with the pins it reads, as events in the
//! model's canonical order. The component is the device; this is the golden side the HAL
//! test checks it against, field by field and period by period.
//!
//! The measurement's clock ticks once per period: every event of period n (from 0) is
//! applied at time n (the model's `apply_at`), and the outputs are read at n, so the FES
//! watchdog's `fes_timeout_cycles` counts servo periods in the component.

use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::{ForceKernel, ForceOutputs};
use tooltouch_model::force::sampling::{AdcChannel, AdcCodes};
use tooltouch_model::{MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};

/// The largest ADC code the component passes on (12-bit converters); larger pin values
/// are clamped to it.
pub const ADC_MAX: u32 = 4095;

/// The component's default `max-events` parameter: index, FES and scale events applied per
/// period at most.
pub const DEFAULT_MAX_EVENTS: u32 = 4096;

/// Every input pin of the component, as one servo period reads it (the streamer's columns,
/// in this order: [`PeriodInputs::STREAMER_CFG`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PeriodInputs {
    /// `arm`: the CNC's measurement-cycle line.
    pub arm: bool,
    /// `contact`: the tool–workpiece contact level.
    pub contact: bool,
    /// `index`: the index pulse level (a rising edge is one event).
    pub index: bool,
    /// `fes`: the FES pulse level (a rising edge is one event).
    pub fes: bool,
    /// `index-counts`: index pulses counted in hardware.
    pub index_counts: i32,
    /// `fes-counts`: FES pulses counted in hardware.
    pub fes_counts: i32,
    /// `scale-counts`: the linear scale's position, x4 counts.
    pub scale_counts: i32,
    /// `adc-speed`, `adc-power`, `adc-force`, `adc-volts-u/v/w`, `adc-amps-u/v`: 12-bit codes
    /// in [`AdcChannel::ALL`] order.
    pub adc: [u32; AdcChannel::COUNT],
    /// `force-control`.
    pub force_control: bool,
    /// `identify`.
    pub identify: bool,
    /// `tool-changed` (a rising edge is one event).
    pub tool_changed: bool,
    /// `conditions`: the wear monitor's condition set.
    pub conditions: u32,
}

impl PeriodInputs {
    /// The component pins the streamer drives, in column order.
    pub const PINS: [&'static str; 19] = [
        "arm",
        "contact",
        "index",
        "fes",
        "index-counts",
        "fes-counts",
        "scale-counts",
        "adc-speed",
        "adc-power",
        "adc-force",
        "adc-volts-u",
        "adc-volts-v",
        "adc-volts-w",
        "adc-amps-u",
        "adc-amps-v",
        "force-control",
        "identify",
        "tool-changed",
        "conditions",
    ];

    /// The streamer's `cfg=` string for [`PeriodInputs::PINS`] (b bit, s s32, u u32).
    pub const STREAMER_CFG: &'static str = "bbbbsssuuuuuuuubbbu";

    /// One line of the streamer's text input: every column, space-separated.
    pub fn streamer_line(&self) -> String {
        let b = |v: bool| if v { "1" } else { "0" };
        let mut cols: Vec<String> = vec![
            b(self.arm).into(),
            b(self.contact).into(),
            b(self.index).into(),
            b(self.fes).into(),
            self.index_counts.to_string(),
            self.fes_counts.to_string(),
            self.scale_counts.to_string(),
        ];
        cols.extend(self.adc.iter().map(u32::to_string));
        cols.extend([
            b(self.force_control).into(),
            b(self.identify).into(),
            b(self.tool_changed).into(),
            self.conditions.to_string(),
        ]);
        cols.join(" ")
    }
}

/// What one period left besides the outputs: the component's health pins.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PeriodHealth {
    /// Events carried over to the next period (`backlog`).
    pub backlog: u32,
    /// Periods that ran out of events budget so far (the budget half of `overruns`).
    pub overruns: u32,
    /// Times a counts pin went down from one period to the next (`count-errors`).
    pub count_errors: u32,
}

/// The component's state and kernels: the golden twin of one `tooltouch` instance.
#[derive(Clone, Debug)]
pub struct PeriodKernel {
    measurement: Measurement,
    force: ForceKernel,
    samples_per_tick: u32,
    /// Index, FES and scale events per period at most (the `max-events` parameter).
    pub max_events: u32,
    started: bool,
    last: PeriodInputs,
    pending_index: u32,
    pending_fes: u32,
    pending_scale: i64,
    /// The scale lines driven into the model, phase 0..4 = (A,B) 00 10 11 01.
    phase: u8,
    samples: u32,
    health: PeriodHealth,
    /// The measurement's clock: periods stepped so far.
    now: u64,
}

impl PeriodKernel {
    /// A fresh component for the two configurations (the one file `loadrt` reads).
    pub fn new(measure: &MeasureConfig, force: &ForceConfig) -> PeriodKernel {
        PeriodKernel {
            measurement: Measurement::new(measure),
            force: ForceKernel::new(force),
            samples_per_tick: u32::from(force.settings().samples_per_period.max(1)),
            max_events: DEFAULT_MAX_EVENTS,
            started: false,
            last: PeriodInputs::default(),
            pending_index: 0,
            pending_fes: 0,
            pending_scale: 0,
            phase: 0,
            samples: 0,
            health: PeriodHealth::default(),
            now: 0,
        }
    }

    /// The increase of a counts pin (a decrease counts an error and gives 0).
    fn rise(&mut self, now: i32, last: i32) -> u32 {
        let d = now.wrapping_sub(last);
        if d < 0 {
            self.health.count_errors += 1;
            0
        } else {
            d as u32
        }
    }

    /// One period: the events the pins give, in the component's order, then the outputs.
    pub fn step(&mut self, p: &PeriodInputs) -> (MeasureOutputs, ForceOutputs) {
        if !self.started {
            self.started = true;
            self.last.index_counts = p.index_counts;
            self.last.fes_counts = p.fes_counts;
            self.last.scale_counts = p.scale_counts;
        }
        let last = self.last;
        let now = self.now;
        self.measurement.observe(now);
        if p.arm != last.arm {
            self.measurement.apply_at(now, MeasureEvent::Arm(p.arm));
        }
        if p.contact != last.contact {
            self.measurement
                .apply_at(now, MeasureEvent::Contact(p.contact));
        }
        let index =
            u32::from(p.index && !last.index) + self.rise(p.index_counts, last.index_counts);
        self.pending_index = self.pending_index.wrapping_add(index);
        let fes = u32::from(p.fes && !last.fes) + self.rise(p.fes_counts, last.fes_counts);
        self.pending_fes = self.pending_fes.wrapping_add(fes);
        self.pending_scale += i64::from(p.scale_counts.wrapping_sub(last.scale_counts));
        let mut budget = self.max_events;
        while self.pending_index > 0 && budget > 0 {
            self.measurement.apply_at(now, MeasureEvent::Index);
            self.pending_index -= 1;
            budget -= 1;
        }
        while self.pending_fes > 0 && budget > 0 {
            self.measurement.apply_at(now, MeasureEvent::Fes);
            self.pending_fes -= 1;
            budget -= 1;
        }
        while self.pending_scale != 0 && budget > 0 {
            let up = self.pending_scale > 0;
            self.phase = (self.phase + if up { 1 } else { 3 }) & 3;
            self.pending_scale += if up { -1 } else { 1 };
            let (a, b) = [(false, false), (true, false), (true, true), (false, true)]
                [usize::from(self.phase)];
            self.measurement.apply_at(now, MeasureEvent::Scale { a, b });
            budget -= 1;
        }
        let backlog = self
            .pending_index
            .wrapping_add(self.pending_fes)
            .wrapping_add(self.pending_scale.unsigned_abs() as u32);
        self.health.backlog = backlog;
        if backlog > 0 {
            self.health.overruns += 1;
        }
        if p.identify != last.identify {
            self.force.apply(ForceEvent::Identify(p.identify));
        }
        if p.force_control != last.force_control {
            self.force.apply(ForceEvent::Control(p.force_control));
        }
        if p.conditions != last.conditions {
            self.force
                .apply(ForceEvent::Conditions(p.conditions.min(255) as u8));
        }
        if p.tool_changed && !last.tool_changed {
            self.force.apply(ForceEvent::ToolChanged);
        }
        self.force.apply(ForceEvent::Sample(adc_codes(&p.adc)));
        self.samples += 1;
        if self.samples >= self.samples_per_tick {
            self.samples = 0;
            self.force.apply(ForceEvent::Tick);
        }
        self.last = *p;
        self.now += 1;
        (self.measurement.outputs_at(now), self.force.outputs())
    }

    /// The health pins after the last period.
    pub fn health(&self) -> PeriodHealth {
        self.health
    }
}

/// The eight ADC pins ([`AdcChannel::ALL`] order) as the model's codes, each clamped to
/// [`ADC_MAX`].
pub fn adc_codes(adc: &[u32; AdcChannel::COUNT]) -> AdcCodes {
    AdcCodes::from_array(adc.map(|v| v.min(ADC_MAX) as u16))
}

/// The eight ADC pins ([`AdcChannel::ALL`] order) of a sample of the model's codes.
pub fn adc_pins(c: &AdcCodes) -> [u32; AdcChannel::COUNT] {
    c.to_array().map(u32::from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::force::config::ForceSettings;
    use tooltouch_model::MeasureSettings;

    fn kernel() -> PeriodKernel {
        let m = MeasureSettings::default().validate().unwrap();
        let f = ForceSettings::default().validate().unwrap();
        PeriodKernel::new(&m, &f)
    }

    #[test]
    fn counts_become_events_and_the_first_period_is_the_baseline() {
        let mut k = kernel();
        let mut p = PeriodInputs {
            fes_counts: 1000,
            scale_counts: -7,
            ..Default::default()
        };
        let (m, _) = k.step(&p);
        assert_eq!((m.pulses, m.position), (0, 0));
        p.arm = true;
        k.step(&p);
        p.fes_counts += 5;
        p.fes = true; // a rising edge adds one
        p.scale_counts += 3;
        let (m, _) = k.step(&p);
        assert_eq!((m.pulses, m.position), (6, 3));
        p.scale_counts -= 10;
        let (m, _) = k.step(&p);
        assert_eq!(m.position, -7);
        assert_eq!(m.scale_errors, 0);
    }

    #[test]
    fn a_budget_overrun_carries_the_events_over() {
        let mut k = kernel();
        k.max_events = 4;
        let mut p = PeriodInputs {
            arm: true,
            ..Default::default()
        };
        k.step(&p);
        p.fes_counts = 10;
        let (m, _) = k.step(&p);
        assert_eq!(m.pulses, 4);
        assert_eq!(k.health().backlog, 6);
        let (m, _) = k.step(&p);
        assert_eq!(m.pulses, 8);
        let (m, _) = k.step(&p);
        assert_eq!(m.pulses, 10);
        assert_eq!(k.health().overruns, 2);
        p.fes_counts = 3; // went down: ignored, counted
        let (m, _) = k.step(&p);
        assert_eq!((m.pulses, k.health().count_errors), (10, 1));
    }

    /// One tick per period: armed at period 1, the last FES at period 2, a watchdog of 3
    /// ticks: clean through period 4, `fes_timeout` from period 5, held after the arm falls.
    #[test]
    fn the_fes_watchdog_counts_servo_periods() {
        use tooltouch_model::measure::checks::{fault, MeasureChecks};
        let m = MeasureSettings {
            checks: MeasureChecks {
                fes_timeout_cycles: 3,
                ..MeasureChecks::OFF
            },
            ..Default::default()
        }
        .validate()
        .unwrap();
        let f = ForceSettings::default().validate().unwrap();
        let mut k = PeriodKernel::new(&m, &f);
        let mut p = PeriodInputs::default();
        assert_eq!(k.step(&p).0.faults, 0); // period 0: the baseline
        p.arm = true;
        assert_eq!(k.step(&p).0.faults, 0); // 1: armed
        p.fes_counts = 1;
        assert_eq!(k.step(&p).0.faults, 0); // 2: the last FES
        assert_eq!(k.step(&p).0.faults, 0); // 3
        assert_eq!(k.step(&p).0.faults, 0); // 4
        assert_eq!(k.step(&p).0.faults, fault::FES_TIMEOUT); // 5
        p.arm = false;
        assert_eq!(k.step(&p).0.faults, fault::FES_TIMEOUT); // 6: held
        p.arm = true;
        assert_eq!(k.step(&p).0.faults, 0, "cleared at the arm");
    }

    #[test]
    fn a_tick_follows_every_samples_per_tick_samples() {
        let mut k = kernel();
        let p = PeriodInputs {
            adc: [2000, 1000, 2048, 2048, 2048, 2048, 2048, 2048],
            ..Default::default()
        };
        // The wear power only moves at a tick: unchanged for 49 periods, then it moves.
        let first = k.step(&p).1.wear_power;
        for _ in 1..49 {
            assert_eq!(k.step(&p).1.wear_power, first);
        }
        assert_ne!(k.step(&p).1.wear_power, first);
    }
}
