//! The force path as one event-level kernel (SPEC 3 and 4): sampling chain → estimator →
//! controller → feed override, and the wear monitor beside it; its configuration, its
//! events and outputs, and their wire encodings.
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
//! stream holds one [`kind::OUTPUTS`] record (`0x41`) after every event *except*
//! [`ForceEvent::Sample`] (a sample changes no output), at the event's time. The header's
//! `force_hash` is [`ForceConfig::hash`].
//!
//! ## Numbers
//! Physical quantities are I32F32 ([`Fx`]: 32 integer bits, 32 fractional bits) in SI units;
//! each alias below names its unit. Every operation on them saturates.

use crate::config::fnv1a;
use crate::control::{AdaptiveSettings, PiSettings};
use crate::control::{Controller, ControllerSettings, ForceController, FuzzySettings};
use crate::estimator::{check_range, positive, AdcScales, Estimate, Estimator, EstimatorSettings};
use crate::sampling::{AdcCodes, Sampler};
use crate::wear::{ConditionSet, Threshold, WearMonitor, WearSettings, MAX_CONDITION_SETS};
use crate::wire::{Record, WireError};
use core::fmt;
use fixed::types::I32F32;

/// Generic fixed-point quantity, I32F32 (range ±2^31, resolution 2^−32).
pub type Fx = I32F32;
/// Force, newtons, I32F32.
pub type Newtons = I32F32;
/// Torque, newton-metres, I32F32.
pub type NewtonMetres = I32F32;
/// Power, watts, I32F32.
pub type Watts = I32F32;
/// Angular speed, rad/s, I32F32.
pub type RadPerSec = I32F32;
/// Voltage, volts, I32F32.
pub type Volts = I32F32;
/// Current, amperes, I32F32.
pub type Amps = I32F32;
/// Resistance, ohms, I32F32.
pub type Ohms = I32F32;
/// Time, seconds, I32F32.
pub type Seconds = I32F32;
/// Length, metres, I32F32.
pub type Metres = I32F32;

/// A force-path configuration field outside its allowed range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceConfigError {
    /// The field's path, e.g. `pi.kp`, `wear.efficiency`, `fuzzy.rules`.
    pub field: &'static str,
    /// The rejected value (a count for `fuzzy.rules`' emptiness).
    pub value: Fx,
    /// Smallest allowed value.
    pub min: Fx,
    /// Largest allowed value.
    pub max: Fx,
}

impl fmt::Display for ForceConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "force configuration field `{}` = {} is out of range: allowed {}..={}",
            self.field, self.value, self.min, self.max
        )
    }
}

/// Which force the controller regulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceSource {
    /// The estimator's F̂_c (SPEC F1–F9): no dynamometer needed.
    Estimated,
    /// The dynamometer channel of the ADC (for comparison).
    Measured,
}

/// Version of the force configuration's canonical encoding; part of [`ForceConfig::hash`].
pub const FORCE_CONFIG_FORMAT_VERSION: u16 = 1;

/// Unvalidated force-path settings; [`ForceSettings::validate`] makes a [`ForceConfig`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceSettings {
    /// ADC sample rate, Hz, `100..=10000` (SPEC: 1000).
    pub sample_hz: u16,
    /// Samples per control period, `1..=1000` (SPEC: 50, h = 0.05 s).
    pub samples_per_period: u16,
    /// Low-pass coefficient `2^-lowpass_shift`, `1..=8` (1 ≈ 110 Hz at 1 kHz).
    pub lowpass_shift: u8,
    /// ADC scales.
    pub scales: AdcScales,
    /// Estimator parameters.
    pub estimator: EstimatorSettings,
    /// Estimated or measured force feedback.
    pub force_source: ForceSource,
    /// Reference force F_r, N, `(0, 100000]` (SPEC: 500).
    pub reference: Newtons,
    /// Override while force control is off, %, `0..=255`.
    pub manual_override: u8,
    /// The controller.
    pub controller: ControllerSettings,
    /// The wear monitor.
    pub wear: WearSettings,
}

/// Default PI: Ziegler–Nichols (reaction curve) on the default nominal process of
/// `tooltouch::drive` (K = 6 N/%, τ_p = 0.08 s, dead time 0.075 s):
/// `K_p = 0.9τ/(K·L) = 0.16 %/N`, `T_i = 3.33·L = 0.25 s`, `K_i = K_p/T_i = 0.64 %/(N·s)`.
pub const DEFAULT_PI: PiSettings = PiSettings {
    kp: Fx::lit("0.16"),
    ki: Fx::lit("0.64"),
    integrator_min: Fx::ZERO,
    integrator_max: Fx::const_from_int(255),
};

/// Default adaptive controller: open-loop gain 4 /s (K·h = 0.2), K̂ in 0.5..=100 N/%.
pub const DEFAULT_ADAPTIVE: AdaptiveSettings = AdaptiveSettings {
    open_loop_gain: Fx::const_from_int(4),
    gain_min: Fx::lit("0.5"),
    gain_max: Fx::const_from_int(100),
    initial_gain: Fx::const_from_int(6),
    gain_filter_shift: 2,
    min_override: Fx::const_from_int(5),
    min_force: Fx::const_from_int(50),
};

/// Default fuzzy PI: e saturates the universe at ±300 N (GE = 3072/300), and GΔU, GΔE
/// reproduce [`DEFAULT_PI`] in the linear region (`K_i·h = GΔU·GE`, `K_p = GΔU·GΔE`).
pub const DEFAULT_FUZZY: FuzzySettings = FuzzySettings {
    ge: Fx::lit("10.24"),
    gde: Fx::lit("51.2"),
    gdu: Fx::lit("0.003125"),
    rules: crate::control::fuzzy::STANDARD_RULES,
};

impl Default for ForceSettings {
    /// The set-up of `tooltouch control`'s default plant: 1 kHz, 50 samples per period,
    /// 12-bit channels, a 0.05 kg·m² spindle, 20 mm workpiece radius, 500 N reference, PI.
    fn default() -> Self {
        let mut sets = [ConditionSet::default(); MAX_CONDITION_SETS];
        sets[0] = ConditionSet {
            mean_power_limit: Fx::const_from_int(1800),
            idle_power: Fx::const_from_int(300),
        };
        ForceSettings {
            sample_hz: 1000,
            samples_per_period: 50,
            lowpass_shift: 1,
            scales: AdcScales {
                speed_per_lsb: const { Fx::lit("0.05") },
                power_per_lsb: const { Fx::lit("2.5") },
                force_per_lsb: Fx::ONE,
                volts_per_lsb: const { Fx::lit("0.25") },
                amps_per_lsb: const { Fx::lit("0.005") },
            },
            estimator: EstimatorSettings {
                stator_resistance: const { Fx::lit("0.5") },
                inertia: const { Fx::lit("0.05") },
                viscous_nominal: const { Fx::lit("0.005") },
                coulomb_nominal: Fx::ONE,
                friction_f: [const { Fx::lit("0.05") }, Fx::ZERO],
                friction_g: [const { Fx::lit("0.002") }, Fx::ZERO],
                min_speed: Fx::const_from_int(5),
                switch_threshold: const { Fx::lit("0.1") },
                slip_gain: const { Fx::lit("0.97") },
                slip_hold_periods: 4,
                workpiece_radius: const { Fx::lit("0.02") },
            },
            force_source: ForceSource::Estimated,
            reference: Fx::const_from_int(500),
            manual_override: 100,
            controller: ControllerSettings::Pi(DEFAULT_PI),
            wear: WearSettings {
                sets,
                set_count: 1,
                efficiency: const { Fx::lit("0.8") },
                lowpass_shift: 3,
                debounce_periods: 10,
                threshold: Threshold::Updating,
            },
        }
    }
}

impl ForceSettings {
    /// Checks every field; the error names the first bad field and its allowed range.
    pub fn validate(&self) -> Result<ForceConfig, ForceConfigError> {
        check_range(
            "sample_hz",
            Fx::from_num(self.sample_hz),
            Fx::const_from_int(100),
            Fx::const_from_int(10_000),
        )?;
        check_range(
            "samples_per_period",
            Fx::from_num(self.samples_per_period),
            Fx::ONE,
            Fx::const_from_int(1000),
        )?;
        check_range(
            "lowpass_shift",
            Fx::from_num(self.lowpass_shift),
            Fx::ONE,
            Fx::const_from_int(8),
        )?;
        let h = Fx::from_num(self.samples_per_period)
            .checked_div(Fx::from_num(self.sample_hz))
            .unwrap_or(Fx::ZERO);
        let s = &self.scales;
        positive("scales.speed_per_lsb", s.speed_per_lsb, Fx::ONE)?;
        positive(
            "scales.power_per_lsb",
            s.power_per_lsb,
            Fx::const_from_int(100),
        )?;
        positive(
            "scales.force_per_lsb",
            s.force_per_lsb,
            Fx::const_from_int(100),
        )?;
        positive(
            "scales.volts_per_lsb",
            s.volts_per_lsb,
            Fx::const_from_int(10),
        )?;
        positive("scales.amps_per_lsb", s.amps_per_lsb, Fx::ONE)?;
        self.estimator.validate(h)?;
        positive("reference", self.reference, Fx::const_from_int(100_000))?;
        match &self.controller {
            ControllerSettings::Pi(p) => p.validate()?,
            ControllerSettings::Adaptive(a) => a.validate(h)?,
            ControllerSettings::Fuzzy(f) => f.validate()?,
        }
        self.wear.validate()?;
        Ok(ForceConfig { settings: *self, h })
    }
}

/// A validated force-path configuration. Only [`ForceSettings::validate`] makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceConfig {
    settings: ForceSettings,
    h: Seconds,
}

impl ForceConfig {
    /// The settings this configuration was validated from.
    pub fn settings(&self) -> &ForceSettings {
        &self.settings
    }

    /// Control period h = samples_per_period / sample_hz, s.
    pub fn period(&self) -> Seconds {
        self.h
    }

    /// Canonical little-endian encoding of every setting (fixed-point values as their raw
    /// bits), fed to [`Self::hash`]. Returns the buffer and the bytes used.
    pub fn canonical_bytes(&self) -> ([u8; 512], usize) {
        let mut w = Writer {
            buf: [0; 512],
            n: 0,
        };
        let s = &self.settings;
        w.put(&FORCE_CONFIG_FORMAT_VERSION.to_le_bytes());
        w.put(&s.sample_hz.to_le_bytes());
        w.put(&s.samples_per_period.to_le_bytes());
        w.put(&[s.lowpass_shift]);
        let c = &s.scales;
        for v in [
            c.speed_per_lsb,
            c.power_per_lsb,
            c.force_per_lsb,
            c.volts_per_lsb,
            c.amps_per_lsb,
        ] {
            w.fx(v);
        }
        let e = &s.estimator;
        for v in [
            e.stator_resistance,
            e.inertia,
            e.viscous_nominal,
            e.coulomb_nominal,
            e.friction_f[0],
            e.friction_f[1],
            e.friction_g[0],
            e.friction_g[1],
            e.min_speed,
            e.switch_threshold,
            e.slip_gain,
            e.workpiece_radius,
        ] {
            w.fx(v);
        }
        w.put(&[e.slip_hold_periods, s.force_source as u8, s.manual_override]);
        w.fx(s.reference);
        match &s.controller {
            ControllerSettings::Pi(p) => {
                w.put(&[0]);
                for v in [p.kp, p.ki, p.integrator_min, p.integrator_max] {
                    w.fx(v);
                }
            }
            ControllerSettings::Adaptive(a) => {
                w.put(&[1]);
                for v in [
                    a.open_loop_gain,
                    a.gain_min,
                    a.gain_max,
                    a.initial_gain,
                    a.min_override,
                    a.min_force,
                ] {
                    w.fx(v);
                }
                w.put(&[a.gain_filter_shift]);
            }
            ControllerSettings::Fuzzy(f) => {
                w.put(&[2]);
                for v in [f.ge, f.gde, f.gdu] {
                    w.fx(v);
                }
                for row in &f.rules {
                    for &r in row {
                        w.put(&r.to_le_bytes());
                    }
                }
            }
        }
        let wr = &s.wear;
        w.put(&[wr.set_count, wr.lowpass_shift, wr.debounce_periods]);
        w.fx(wr.efficiency);
        for set in wr.sets.iter().take(usize::from(wr.set_count)) {
            w.fx(set.mean_power_limit);
            w.fx(set.idle_power);
        }
        match wr.threshold {
            Threshold::Updating => w.put(&[0]),
            Threshold::Constant(p) => {
                w.put(&[1]);
                w.fx(p);
            }
        }
        (w.buf, w.n)
    }

    /// 64-bit FNV-1a of [`Self::canonical_bytes`]: the `force_hash` of vector headers.
    pub fn hash(&self) -> u64 {
        let (bytes, n) = self.canonical_bytes();
        fnv1a(bytes.get(..n).unwrap_or(&bytes))
    }
}

struct Writer {
    buf: [u8; 512],
    n: usize,
}

impl Writer {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if let Some(slot) = self.buf.get_mut(self.n) {
                *slot = b;
                self.n = self.n.saturating_add(1);
            }
        }
    }
    fn fx(&mut self, v: Fx) {
        self.put(&v.to_bits().to_le_bytes());
    }
}

/// One input event of the force path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceEvent {
    /// One ADC sample of every channel (1 kHz).
    Sample(AdcCodes),
    /// Control period tick (20 Hz): estimate, control, monitor wear.
    Tick,
    /// CNC: no-load identification on (clears its sums) / off (solves B and T_fco).
    Identify(bool),
    /// CNC: force control on (tool in cut; the controller restarts bumplessly from the
    /// current override) / off (override = `manual_override`).
    Control(bool),
    /// CNC: the cutting conditions changed to condition set `index` (wear monitor).
    Conditions(u8),
    /// CNC: a new tool was put in; clears the wear alarm.
    ToolChanged,
}

impl ForceEvent {
    /// Order of events with the same time: samples first (they belong to the period a
    /// tick closes), then the tick, then CNC commands (which act from the next period).
    pub const CANONICAL_ORDER: [u8; 6] = [
        kind::SAMPLE,
        kind::TICK,
        kind::IDENTIFY,
        kind::CONTROL,
        kind::CONDITIONS,
        kind::TOOL_CHANGED,
    ];

    /// The event's wire kind.
    pub fn kind(&self) -> u8 {
        match self {
            ForceEvent::Sample(_) => kind::SAMPLE,
            ForceEvent::Tick => kind::TICK,
            ForceEvent::Identify(_) => kind::IDENTIFY,
            ForceEvent::Control(_) => kind::CONTROL,
            ForceEvent::Conditions(_) => kind::CONDITIONS,
            ForceEvent::ToolChanged => kind::TOOL_CHANGED,
        }
    }
}

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
    /// Bad CNC commands (condition index out of range), saturating at 255.
    pub bad_events: u8,
    /// Estimated cutting force F̂_c, N.
    pub force_estimate: Newtons,
    /// Dynamometer force (period average), N.
    pub force_measured: Newtons,
    /// Low-passed mean spindle power p̄, W.
    pub wear_power: Watts,
    /// Allowed power [P], W.
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
        let s = &config.settings;
        let estimator = Estimator::new(&s.estimator, config.h);
        let wear = WearMonitor::new(&s.wear);
        let status = wear.status();
        ForceKernel {
            reference: s.reference,
            source: s.force_source,
            manual: s.manual_override,
            scales: s.scales,
            sampler: Sampler::new(s.lowpass_shift),
            estimator,
            controller: Controller::new(&s.controller, config.h, s.manual_override),
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
            ForceEvent::Sample(codes) => self.sampler.on_sample(&codes),
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

/// Wire kinds of the force path (inputs in `0x20..=0x3f`, outputs `0x41`).
pub mod kind {
    /// [`super::ForceEvent::Sample`]; payload: speed, power, force, v_u, v_v, v_w, i_u,
    /// i_v as u16 LE (16 bytes).
    pub const SAMPLE: u8 = 0x20;
    /// [`super::ForceEvent::Tick`]; no payload.
    pub const TICK: u8 = 0x21;
    /// [`super::ForceEvent::Identify`]; payload: level (1 byte).
    pub const IDENTIFY: u8 = 0x22;
    /// [`super::ForceEvent::Control`]; payload: level (1 byte).
    pub const CONTROL: u8 = 0x23;
    /// [`super::ForceEvent::Conditions`]; payload: index (1 byte).
    pub const CONDITIONS: u8 = 0x24;
    /// [`super::ForceEvent::ToolChanged`]; no payload.
    pub const TOOL_CHANGED: u8 = 0x25;
    /// [`super::ForceOutputs`] ([`super::FORCE_OUTPUTS_LEN`] bytes).
    pub const OUTPUTS: u8 = 0x41;
}

/// Encodes a force event as a record at `time`.
pub fn encode_force_event(time: u64, event: &ForceEvent) -> Record {
    match event {
        ForceEvent::Sample(c) => {
            let mut p = [0u8; 16];
            let words = [
                c.speed, c.power, c.force, c.volts[0], c.volts[1], c.volts[2], c.amps[0], c.amps[1],
            ];
            for (chunk, w) in p.chunks_exact_mut(2).zip(words) {
                chunk.copy_from_slice(&w.to_le_bytes());
            }
            Record::new(kind::SAMPLE, time, &p)
        }
        ForceEvent::Tick => Record::new(kind::TICK, time, &[]),
        ForceEvent::Identify(on) => Record::new(kind::IDENTIFY, time, &[u8::from(*on)]),
        ForceEvent::Control(on) => Record::new(kind::CONTROL, time, &[u8::from(*on)]),
        ForceEvent::Conditions(i) => Record::new(kind::CONDITIONS, time, &[*i]),
        ForceEvent::ToolChanged => Record::new(kind::TOOL_CHANGED, time, &[]),
    }
}

/// Decodes a force-event record (found at byte `offset`); `Ok(None)` for another kind.
pub fn decode_force_event(record: &Record, offset: usize) -> Result<Option<ForceEvent>, WireError> {
    let p = record.payload();
    let bad = WireError::BadLength {
        kind: record.kind,
        len: u8::try_from(p.len()).unwrap_or(u8::MAX),
        offset,
    };
    let level = || match p {
        [b] if *b <= 1 => Ok(*b == 1),
        _ => Err(bad),
    };
    Ok(Some(match record.kind {
        kind::SAMPLE => {
            if p.len() != 16 {
                return Err(bad);
            }
            let mut w = [0u16; 8];
            for (d, chunk) in w.iter_mut().zip(p.chunks_exact(2)) {
                *d = u16::from_le_bytes([chunk[0], chunk[1]]);
            }
            let [speed, power, force, vu, vv, vw, iu, iv] = w;
            ForceEvent::Sample(AdcCodes {
                speed,
                power,
                force,
                volts: [vu, vv, vw],
                amps: [iu, iv],
            })
        }
        kind::TICK if p.is_empty() => ForceEvent::Tick,
        kind::IDENTIFY => ForceEvent::Identify(level()?),
        kind::CONTROL => ForceEvent::Control(level()?),
        kind::CONDITIONS => match p {
            [i] => ForceEvent::Conditions(*i),
            _ => return Err(bad),
        },
        kind::TOOL_CHANGED if p.is_empty() => ForceEvent::ToolChanged,
        kind::TICK | kind::TOOL_CHANGED => return Err(bad),
        _ => return Ok(None),
    }))
}

/// Encoded length of [`ForceOutputs`], bytes.
pub const FORCE_OUTPUTS_LEN: usize = 43;

/// Encodes every force output: override u8, flags u8 (saturated, fast_estimate,
/// control_enabled, identifying, identified, wear_over, wear_alarm from bit 0), bad_events
/// u8, then the raw I32F32 bits (i64 LE) of force_estimate, force_measured, wear_power,
/// wear_allowed, coulomb.
pub fn encode_force_outputs(o: &ForceOutputs) -> [u8; FORCE_OUTPUTS_LEN] {
    let mut out = [0u8; FORCE_OUTPUTS_LEN];
    out[0] = o.override_pct;
    out[1] = u8::from(o.saturated)
        | u8::from(o.fast_estimate) << 1
        | u8::from(o.control_enabled) << 2
        | u8::from(o.identifying) << 3
        | u8::from(o.identified) << 4
        | u8::from(o.wear_over) << 5
        | u8::from(o.wear_alarm) << 6;
    out[2] = o.bad_events;
    let values = [
        o.force_estimate,
        o.force_measured,
        o.wear_power,
        o.wear_allowed,
        o.coulomb,
    ];
    for (chunk, v) in out[3..].chunks_exact_mut(8).zip(values) {
        chunk.copy_from_slice(&v.to_bits().to_le_bytes());
    }
    out
}

/// Decodes [`encode_force_outputs`]' bytes; `None` if `p` is not [`FORCE_OUTPUTS_LEN`]
/// long or has unknown flag bits.
pub fn decode_force_outputs(p: &[u8]) -> Option<ForceOutputs> {
    if p.len() != FORCE_OUTPUTS_LEN || p[1] & 0x80 != 0 {
        return None;
    }
    let mut v = [Fx::ZERO; 5];
    for (d, chunk) in v.iter_mut().zip(p[3..].chunks_exact(8)) {
        let mut b = [0u8; 8];
        b.copy_from_slice(chunk);
        *d = Fx::from_bits(i64::from_le_bytes(b));
    }
    let f = p[1];
    Some(ForceOutputs {
        override_pct: p[0],
        saturated: f & 1 != 0,
        fast_estimate: f & 2 != 0,
        control_enabled: f & 4 != 0,
        identifying: f & 8 != 0,
        identified: f & 16 != 0,
        wear_over: f & 32 != 0,
        wear_alarm: f & 64 != 0,
        bad_events: p[2],
        force_estimate: v[0],
        force_measured: v[1],
        wear_power: v[2],
        wear_allowed: v[3],
        coulomb: v[4],
    })
}

/// The [`ForceOutputs`] record at `time`.
pub fn outputs_record(time: u64, o: &ForceOutputs) -> Record {
    Record::new(kind::OUTPUTS, time, &encode_force_outputs(o))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_hash_is_stable() {
        let c = ForceSettings::default().validate().unwrap();
        assert!((c.period() - Fx::lit("0.05")).abs() <= Fx::DELTA);
        assert_eq!(c.hash(), c.hash());
        let s = ForceSettings {
            reference: Fx::const_from_int(400),
            ..Default::default()
        };
        assert_ne!(s.validate().unwrap().hash(), c.hash());
    }

    #[test]
    fn bad_fields_are_named() {
        let s = ForceSettings {
            controller: ControllerSettings::Pi(PiSettings {
                kp: Fx::ZERO,
                ..DEFAULT_PI
            }),
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "pi.kp");
        let s = ForceSettings {
            controller: ControllerSettings::Pi(PiSettings {
                ki: Fx::const_from_int(-1),
                ..DEFAULT_PI
            }),
            ..Default::default()
        };
        assert_eq!(s.validate().unwrap_err().field, "pi.ki");
        let mut s = ForceSettings::default();
        s.estimator.workpiece_radius = Fx::ZERO;
        assert_eq!(
            s.validate().unwrap_err().field,
            "estimator.workpiece_radius"
        );
    }

    #[test]
    fn events_and_outputs_round_trip() {
        let events = [
            ForceEvent::Sample(AdcCodes {
                speed: 1,
                power: 2,
                force: 3,
                volts: [4, 5, 6],
                amps: [7, 4095],
            }),
            ForceEvent::Tick,
            ForceEvent::Identify(true),
            ForceEvent::Control(false),
            ForceEvent::Conditions(3),
            ForceEvent::ToolChanged,
        ];
        for e in events {
            let r = encode_force_event(9, &e);
            assert!((0x20..=0x3f).contains(&r.kind));
            assert_eq!(decode_force_event(&r, 0).unwrap(), Some(e));
        }
        let o = ForceOutputs {
            override_pct: 83,
            saturated: true,
            wear_alarm: true,
            bad_events: 2,
            force_estimate: Fx::lit("-12.5"),
            coulomb: Fx::DELTA,
            ..ForceOutputs::default()
        };
        assert_eq!(decode_force_outputs(&encode_force_outputs(&o)), Some(o));
        let bad = Record::new(kind::CONTROL, 0, &[2]);
        assert!(decode_force_event(&bad, 5).is_err());
    }
}
