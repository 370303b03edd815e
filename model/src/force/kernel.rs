//! The force path as one event-level kernel (docs/domain.md §3 and §4): sampling chain → estimator
//! → controller → feed override, and the wear monitor beside it, with every output.
//!
//! ## Firmware API
//! ```text
//! let config = ForceSettings::default().validate()?;   // once, at start-up
//! let mut kernel = ForceKernel::new(&config);
//! // ADC DMA complete, 1 kHz:      kernel.apply(ForceEvent::Sample(codes));
//! // control timer, 20 Hz:         kernel.apply(ForceEvent::Tick);
//! //                               write kernel.outputs().override_pct to the CNC
//! // CNC commands:                 ForceEvent::Identify(bool) / Control(bool) /
//! //                               Conditions(index) / ToolChanged
//! ```
//! Every method is `no_std`, allocation-free and panic-free (no unwrap, no panicking index,
//! every division checked). When a sample and a tick carry the same time, the sample comes
//! first (it belongs to the period the tick closes): [`ForceEvent::CANONICAL_ORDER`].
//!
//! ## Vectors
//! An Events stream holds [`ForceEvent`] records (kinds [`kind::SAMPLE`]..=
//! [`kind::TOOL_CHANGED`], inside the force range `0x20..=0x3f`); the matching Outputs
//! stream holds one [`kind::FORCE_OUTPUTS`] record (`0x41`) after every event *except*
//! [`ForceEvent::Sample`] (a sample changes no output), at the event's time. The header's
//! `force_hash` is [`ForceConfig::hash`]. Encoders and decoders: [`crate::wire`].
//!
//! [`kind::SAMPLE`]: crate::wire::kind::SAMPLE
//! [`kind::TOOL_CHANGED`]: crate::wire::kind::TOOL_CHANGED
//! [`kind::FORCE_OUTPUTS`]: crate::wire::kind::FORCE_OUTPUTS

use crate::force::config::{ForceConfig, ForceSource};
use crate::force::control::{Controller, ForceController};
use crate::force::estimator::{Estimate, Estimator};
use crate::force::events::ForceEvent;
use crate::force::sampling::{AdcScales, Sampler};
use crate::force::wear::WearMonitor;
use crate::units::{NewtonMetres, Newtons, Watts};

/// Every output of the force path, compared bit for bit between model and firmware.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ForceOutputs {
    /// Feed override to the CNC, %, `0..=255`.
    pub override_pct: u8,
    /// The controller's demand was outside `0..=255` in the last period.
    pub saturated: bool,
    /// F9 selected the fast electrical estimate in the last period.
    pub fast_estimate: bool,
    /// Force control is on.
    pub control_enabled: bool,
    /// No-load identification is running.
    pub identifying: bool,
    /// B and T_fco come from an identification.
    pub identified: bool,
    /// The wear monitor's power is at or above its threshold.
    pub wear_over: bool,
    /// Wear alarm latched (change the tool).
    pub wear_alarm: bool,
    /// The wear monitor cannot judge: its threshold is still above the selected
    /// conditions' `[P]` (after a lighter cut was selected; `WearStatus::blind`).
    pub wear_blind: bool,
    /// Bad CNC commands (condition index out of range), saturating at 255.
    pub bad_events: u8,
    /// Estimated cutting force F̂_c, N.
    pub force_estimate: Newtons,
    /// Dynamometer force (period average), N.
    pub force_measured: Newtons,
    /// Low-passed mean spindle power p̄, W.
    pub wear_power: Watts,
    /// Allowed power \[P\] the next period compares with (during a settling hold after a
    /// lowering condition change, the held one), W.
    pub wear_allowed: Watts,
    /// Coulomb friction T_fco in use, N·m.
    pub coulomb: NewtonMetres,
}

/// The force path's kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceKernel {
    reference: Newtons,
    source: ForceSource,
    manual: u8,
    scales: AdcScales,
    sampler: Sampler,
    estimator: Estimator,
    controller: Controller,
    wear: WearMonitor,
    estimate: Estimate,
    out: ForceOutputs,
}

impl ForceKernel {
    /// A kernel for `config`: control off at the manual override, nominal friction,
    /// condition set 0.
    pub fn new(config: &ForceConfig) -> ForceKernel {
        let s = config.settings();
        let estimator = Estimator::new(&s.estimator, config.period());
        let wear = WearMonitor::new(&s.wear, s.lowpass_shift);
        let status = wear.status();
        ForceKernel {
            reference: s.reference,
            source: s.force_source,
            manual: s.manual_override,
            scales: s.scales,
            sampler: Sampler::new(s.lowpass_shift),
            estimator,
            controller: Controller::new(&s.controller, config.period(), s.manual_override),
            wear,
            estimate: Estimate::default(),
            out: ForceOutputs {
                override_pct: s.manual_override,
                coulomb: estimator.coulomb(),
                wear_allowed: status.allowed,
                ..ForceOutputs::default()
            },
        }
    }

    /// Applies one event (see [`ForceEvent`]).
    pub fn apply(&mut self, event: ForceEvent) {
        match event {
            ForceEvent::Sample(codes) => {
                self.sampler.on_sample(&codes);
                self.wear.on_sample();
            }
            ForceEvent::Tick => self.on_tick(),
            ForceEvent::Identify(true) => self.estimator.start_identification(),
            ForceEvent::Identify(false) => self.estimator.finish_identification(),
            ForceEvent::Control(on) => {
                if on && !self.out.control_enabled {
                    self.controller.reset(self.out.override_pct);
                }
                if !on {
                    self.out.override_pct = self.manual;
                    self.out.saturated = false;
                }
                self.out.control_enabled = on;
            }
            ForceEvent::Conditions(index) => {
                if !self.wear.select(index) {
                    self.out.bad_events = self.out.bad_events.saturating_add(1);
                }
            }
            ForceEvent::ToolChanged => self.wear.tool_changed(),
        }
        let st = self.wear.status();
        self.out.wear_allowed = st.allowed;
        self.out.wear_alarm = st.alarm;
        self.out.wear_blind = st.blind;
        self.out.identifying = self.estimator.identifying();
        self.out.identified = self.estimator.identified();
        self.out.coulomb = self.estimator.coulomb();
    }

    fn on_tick(&mut self) {
        let avg = self.sampler.on_tick();
        let sig = self.scales.convert(&avg);
        self.estimate = self.estimator.step(&sig);
        let feedback = match self.source {
            ForceSource::Estimated => self.estimate.force,
            ForceSource::Measured => sig.force_measured,
        };
        if self.out.control_enabled {
            let c = self.controller.step(self.reference, feedback);
            self.out.override_pct = c.override_pct;
            self.out.saturated = c.saturated;
        }
        let st = self.wear.step(sig.p_o);
        self.out.fast_estimate = self.estimate.fast;
        self.out.force_estimate = self.estimate.force;
        self.out.force_measured = sig.force_measured;
        self.out.wear_power = st.power;
        self.out.wear_over = st.over;
        self.out.wear_blind = st.blind;
    }

    /// Every output after the last event.
    pub fn outputs(&self) -> ForceOutputs {
        self.out
    }

    /// The last period's estimator internals (powers, torques) for plots and tests.
    pub fn estimate(&self) -> &Estimate {
        &self.estimate
    }

    /// The estimator (identified B and T_fco).
    pub fn estimator(&self) -> &Estimator {
        &self.estimator
    }

    /// The controller.
    pub fn controller(&self) -> &Controller {
        &self.controller
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for ForceKernel {
    /// The sampler's, then the last period's estimate (I32F32: `estimate.omega`,
    /// `.p_o`, `.v_line`, `.i_line`, `.amps_sq` — the period's signals but the dynamometer
    /// force, an output —, `.p_i`, `.p_g`, `.p_used`, `.d_omega`, `.t_e`, `.t_t`, `.t_c` —
    /// F̂_c is the `force_estimate` output), then the estimator's, the controller's and the
    /// wear monitor's.
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        self.sampler.internals(f);
        let e = &self.estimate;
        let sig = &e.signals;
        for (name, v) in [
            ("estimate.omega", sig.omega),
            ("estimate.p_o", sig.p_o),
            ("estimate.v_line", sig.v_line),
            ("estimate.i_line", sig.i_line),
            ("estimate.amps_sq", sig.amps_sq),
            ("estimate.p_i", e.p_i),
            ("estimate.p_g", e.p_g),
            ("estimate.p_used", e.p_used),
            ("estimate.d_omega", e.d_omega),
            ("estimate.t_e", e.t_e),
            ("estimate.t_t", e.t_t),
            ("estimate.t_c", e.t_c),
        ] {
            f(Register::fx(name, Format::I32F32, v));
        }
        self.estimator.internals(f);
        self.controller.internals(f);
        self.wear.internals(f);
    }
}

#[cfg(test)]
mod worked_examples;
