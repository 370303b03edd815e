//! Float (f64) references of the force path, one per model kernel and with the same
//! structure — sampling chain, estimator F1–F9 with no-load identification, PI, adaptive
//! F11, fuzzy PI, wear monitor — for tuning experiments and as the yardstick the
//! fixed-point kernels of `tooltouch-model` are measured against. They read the very same
//! validated [`ForceSettings`] (converted from fixed point once), so a difference between
//! the two is the fixed-point arithmetic, nothing else. Differences on purpose: the float
//! 1/b uses the true exponential, and nothing is rounded or quantized except the final
//! override (integer percent, as the CNC needs it).
//!
//! [`design`] holds the controller design on the nominal process F10 (Ziegler–Nichols).

pub mod design;

use tooltouch_model::force::config::{ForceSettings, ForceSource};
use tooltouch_model::force::control::fuzzy::{NO_RULE, SETS};
use tooltouch_model::force::control::{Controller, ControllerSettings};
use tooltouch_model::force::sampling::{AdcCodes, ADC_MAX, ADC_MID};
use tooltouch_model::force::wear::{Threshold, WearSettings, GUARD_SHIFT};
use tooltouch_model::units::Fx;

/// I32F32 → f64.
pub fn f(x: Fx) -> f64 {
    x.to_num::<f64>()
}

/// Float sampling chain: same low-pass and boxcar as `tooltouch_model::force::sampling`, in codes.
#[derive(Clone, Debug, Default)]
pub struct SamplerF {
    alpha: f64,
    filtered: [f64; 5],
    sums: [f64; 5],
    count: u32,
    primed: bool,
    last: [f64; 5],
}

impl SamplerF {
    /// Low-pass coefficient `2^-shift`.
    pub fn new(shift: u8) -> SamplerF {
        SamplerF {
            alpha: 0.5f64.powi(i32::from(shift.clamp(1, 8))),
            ..Default::default()
        }
    }

    /// One sample.
    pub fn on_sample(&mut self, adc: &AdcCodes) {
        let c = |v: u16| f64::from(v.min(ADC_MAX));
        let m = |v: u16| c(v) - f64::from(ADC_MID);
        let (vu, vv, vw) = (m(adc.volts[0]), m(adc.volts[1]), m(adc.volts[2]));
        let (iu, iv) = (m(adc.amps[0]), m(adc.amps[1]));
        let iw = -(iu + iv);
        let x = [
            c(adc.speed),
            c(adc.power),
            m(adc.force),
            vu * vu + vv * vv + vw * vw,
            iu * iu + iv * iv + iw * iw,
        ];
        for ((y, s), x) in self.filtered.iter_mut().zip(self.sums.iter_mut()).zip(x) {
            if self.primed {
                *y += self.alpha * (x - *y);
            } else {
                *y = x;
            }
            *s += *y;
        }
        self.primed = true;
        self.count += 1;
    }

    /// Period averages `[speed, power, force, Σv², Σi²]` in codes.
    pub fn on_tick(&mut self) -> [f64; 5] {
        if self.count > 0 {
            let n = f64::from(self.count);
            for (l, s) in self.last.iter_mut().zip(self.sums) {
                *l = s / n;
            }
        }
        self.sums = [0.0; 5];
        self.count = 0;
        self.last
    }
}

/// One period's float estimate.
#[derive(Clone, Copy, Debug, Default)]
pub struct EstimateF {
    /// Motor speed, rad/s.
    pub omega: f64,
    /// Measured power, W.
    pub p_o: f64,
    /// Air-gap power, W.
    pub p_g: f64,
    /// F9 chose the fast estimate.
    pub fast: bool,
    /// Cutting torque, N·m.
    pub t_c: f64,
    /// Cutting force, N.
    pub force: f64,
    /// Dynamometer force, N.
    pub force_measured: f64,
}

/// Float estimator (F1–F9, identification), mirroring `tooltouch_model::force::estimator`.
#[derive(Clone, Debug)]
pub struct EstimatorF {
    s: ForceSettings,
    h: f64,
    /// Viscous friction B in use, N·m·s/rad.
    pub viscous: f64,
    /// Coulomb friction T_fco in use, N·m.
    pub coulomb: f64,
    inv_b: f64,
    omega_prev: Option<f64>,
    hold: u32,
    identifying: bool,
    steady_prev: bool,
    sums: [f64; 5],
}

impl EstimatorF {
    /// From validated settings.
    pub fn new(s: &ForceSettings) -> EstimatorF {
        let h = f64::from(s.samples_per_period) / f64::from(s.sample_hz);
        let mut e = EstimatorF {
            s: *s,
            h,
            viscous: f(s.estimator.viscous_nominal),
            coulomb: f(s.estimator.coulomb_nominal),
            inv_b: 0.0,
            omega_prev: None,
            hold: 0,
            identifying: false,
            steady_prev: false,
            sums: [0.0; 5],
        };
        e.inv_b = e.inverse_b();
        e
    }

    fn inverse_b(&self) -> f64 {
        let j = f(self.s.estimator.inertia);
        let b = self.viscous;
        if b <= 0.0 {
            j / self.h
        } else {
            b / (1.0 - (-b * self.h / j).exp())
        }
    }

    /// Starts the no-load identification.
    pub fn start_identification(&mut self) {
        self.identifying = true;
        self.sums = [0.0; 5];
    }

    /// Ends it and solves B and T_fco.
    pub fn finish_identification(&mut self) {
        if !self.identifying {
            return;
        }
        self.identifying = false;
        let [n, sw, sww, sy, swy] = self.sums;
        if n == 0.0 {
            return;
        }
        let det = n * sww - sw * sw;
        let j = f(self.s.estimator.inertia);
        if det >= n * n {
            self.viscous = ((n * swy - sw * sy) / det).clamp(0.0, j / (2.0 * self.h));
        }
        self.coulomb = ((sy - self.viscous * sw) / n).clamp(0.0, 1000.0);
        self.inv_b = self.inverse_b();
    }

    fn torque(&self, p: f64, omega: f64) -> f64 {
        if omega < f(self.s.estimator.min_speed) {
            0.0
        } else {
            p / omega
        }
    }

    /// One period from the sampler's averages.
    pub fn step(&mut self, avg: &[f64; 5]) -> EstimateF {
        let sc = &self.s.scales;
        let es = &self.s.estimator;
        let omega = avg[0] * f(sc.speed_per_lsb);
        let p_o = avg[1] * f(sc.power_per_lsb);
        let force_measured = avg[2] * f(sc.force_per_lsb);
        let v = (avg[3] / 3.0).sqrt() * f(sc.volts_per_lsb);
        let i = (avg[4] / 3.0).sqrt() * f(sc.amps_per_lsb);
        let amps_sq = avg[4] * f(sc.amps_per_lsb).powi(2);
        let p_g = 1.5 * i * v - f(es.stator_resistance) * amps_sq;
        if (p_g - p_o).abs() > f(es.switch_threshold) * p_o.abs() {
            self.hold = u32::from(es.slip_hold_periods);
        }
        let fast_power = f(es.slip_gain) * p_g;
        let fast = self.hold > 0;
        self.hold = self.hold.saturating_sub(1);
        let t_e = self.torque(if fast { fast_power } else { p_o }, omega);
        let d_omega = omega - self.omega_prev.unwrap_or(omega);
        self.omega_prev = Some(omega);
        // identification on steady periods, without the slip gain (as the model)
        let t_g = self.torque(p_g, omega);
        let inertia_torque = f(es.inertia) / self.h * d_omega;
        let steady = inertia_torque.abs()
            * f64::from(1u32 << tooltouch_model::force::estimator::STEADY_SHIFT)
            <= t_g.abs();
        if self.identifying && steady && self.steady_prev {
            let y = t_g - inertia_torque;
            let s = &mut self.sums;
            s[0] += 1.0;
            s[1] += omega;
            s[2] += omega * omega;
            s[3] += y;
            s[4] += omega * y;
        }
        self.steady_prev = steady;
        let t_t = t_e - self.inv_b * d_omega - self.viscous * omega;
        let c = t_t - self.coulomb;
        let ff = f(es.friction_f[0]) + f(es.friction_f[1]) * omega;
        let g = f(es.friction_g[0]) + f(es.friction_g[1]) * omega;
        let one_f = (1.0 + ff).max(0.5);
        let disc = (one_f * one_f + 4.0 * g * c).max(0.0);
        let t_c = 2.0 * c / (one_f + disc.sqrt());
        EstimateF {
            omega,
            p_o,
            p_g,
            fast,
            t_c,
            force: t_c / f(es.workpiece_radius),
            force_measured,
        }
    }
}

/// A float controller: one period → (continuous override %, integer override, saturated).
pub trait ControllerF {
    /// One period.
    fn step(&mut self, reference: f64, force: f64) -> (f64, u8, bool);
    /// Restart at an override.
    fn reset(&mut self, override_pct: u8);
    /// The unclamped demand, %, that [`ControllerF::step`] would clamp and round for these
    /// inputs (N) from the present state; the state is left as it is.
    fn demand(&self, reference: f64, force: f64) -> f64;
    /// The state.
    fn state(&self) -> ControllerStateF;
    /// Re-synchronizes the state, e.g. to a fixed-point kernel's ([`state_of`]), so the two
    /// can be compared one period at a time; a state of another kind of controller is
    /// refused and the state left as it is.
    fn set_state(&mut self, state: &ControllerStateF) -> Result<(), WrongController>;
}

/// The state of a controller, as f64s: what a float reference and a fixed-point kernel
/// carry from one period to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControllerStateF {
    /// PI.
    Pi {
        /// Integrator, %.
        integral: f64,
    },
    /// Adaptive F11.
    Adaptive {
        /// Override state f (the clamped demand before rounding), %.
        feed: f64,
        /// Process-gain estimate K̂, N/%.
        gain_estimate: f64,
        /// Controller gain K̄_c for the next period, %/(N·s).
        controller_gain: f64,
    },
    /// Fuzzy PI.
    Fuzzy {
        /// Override state (the clamped demand before rounding), %.
        override_state: f64,
        /// The previous period's error, N; `None` before the first period.
        previous_error: Option<f64>,
    },
}

/// [`ControllerF::set_state`] was given the state of another kind of controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WrongController;

/// The state of a fixed-point kernel, converted exactly (every I32F32 value is an f64).
pub fn state_of(c: &Controller) -> ControllerStateF {
    match c {
        Controller::Pi(p) => ControllerStateF::Pi {
            integral: f(p.integral()),
        },
        Controller::Adaptive(a) => ControllerStateF::Adaptive {
            feed: f(a.override_state()),
            gain_estimate: f(a.gain_estimate()),
            controller_gain: f(a.controller_gain()),
        },
        Controller::Fuzzy(z) => ControllerStateF::Fuzzy {
            override_state: f(z.override_state()),
            previous_error: z.previous_error().map(f),
        },
    }
}

fn out(demand: f64) -> (f64, u8, bool) {
    let u = demand.clamp(0.0, 255.0);
    (u, u.round() as u8, !(0.0..=255.0).contains(&demand))
}

/// Float PI with the same anti-windup.
#[derive(Clone, Debug)]
pub struct PiF {
    kp: f64,
    ki_h: f64,
    lo: f64,
    hi: f64,
    /// Integrator, %.
    pub integral: f64,
}

impl ControllerF for PiF {
    fn step(&mut self, r: f64, force: f64) -> (f64, u8, bool) {
        let e = r - force;
        let demand = self.demand(r, force);
        if !((demand > 255.0 && e > 0.0) || (demand < 0.0 && e < 0.0)) {
            self.integral = (self.integral + self.ki_h * e).clamp(self.lo, self.hi);
        }
        out(demand)
    }
    fn reset(&mut self, o: u8) {
        self.integral = f64::from(o).clamp(self.lo, self.hi);
    }
    fn demand(&self, r: f64, force: f64) -> f64 {
        self.kp * (r - force) + self.integral
    }
    fn state(&self) -> ControllerStateF {
        ControllerStateF::Pi {
            integral: self.integral,
        }
    }
    fn set_state(&mut self, state: &ControllerStateF) -> Result<(), WrongController> {
        let ControllerStateF::Pi { integral } = *state else {
            return Err(WrongController);
        };
        self.integral = integral;
        Ok(())
    }
}

/// Float adaptive F11.
#[derive(Clone, Debug)]
pub struct AdaptiveF {
    s: tooltouch_model::force::control::AdaptiveSettings,
    h: f64,
    feed: f64,
    /// Process-gain estimate, N/%.
    pub gain_estimate: f64,
    gain: f64,
}

impl AdaptiveF {
    fn gain_for(&self, k: f64) -> f64 {
        f(self.s.open_loop_gain) / k.clamp(f(self.s.gain_min), f(self.s.gain_max))
    }
}

impl ControllerF for AdaptiveF {
    fn step(&mut self, r: f64, force: f64) -> (f64, u8, bool) {
        let (u, q, sat) = out(self.demand(r, force));
        if self.feed >= f(self.s.min_override) && force >= f(self.s.min_force) {
            let (lo, hi) = (f(self.s.gain_min), f(self.s.gain_max));
            let raw = (force / self.feed).clamp(lo, hi);
            let k = 0.5f64.powi(i32::from(self.s.gain_filter_shift));
            self.gain_estimate =
                (self.gain_estimate + k * (raw - self.gain_estimate)).clamp(lo, hi);
        }
        self.gain = self.gain_for(self.gain_estimate);
        self.feed = u;
        (u, q, sat)
    }
    fn reset(&mut self, o: u8) {
        self.feed = f64::from(o);
    }
    fn demand(&self, r: f64, force: f64) -> f64 {
        self.feed + self.gain * self.h * (r - force)
    }
    fn state(&self) -> ControllerStateF {
        ControllerStateF::Adaptive {
            feed: self.feed,
            gain_estimate: self.gain_estimate,
            controller_gain: self.gain,
        }
    }
    fn set_state(&mut self, state: &ControllerStateF) -> Result<(), WrongController> {
        let ControllerStateF::Adaptive {
            feed,
            gain_estimate,
            controller_gain,
        } = *state
        else {
            return Err(WrongController);
        };
        self.feed = feed;
        self.gain_estimate = gain_estimate;
        self.gain = controller_gain;
        Ok(())
    }
}

/// Float fuzzy PI: continuous inputs and memberships, the same rule table and the same
/// discretized output universe.
#[derive(Clone, Debug)]
pub struct FuzzyF {
    ge: f64,
    gde: f64,
    gdu: f64,
    rules: [[i8; SETS]; SETS],
    e_prev: Option<f64>,
    u: f64,
}

fn memberships_f(x: f64) -> [f64; SETS] {
    let x = x.clamp(-3.0, 3.0);
    let mut mu = [0.0; SETS];
    for (k, m) in mu.iter_mut().enumerate() {
        *m = (1.0 - (x - (k as f64 - 3.0)).abs()).max(0.0);
    }
    mu
}

/// Float Mamdani inference + centroid, universe in set spacings (−3..3).
pub fn infer_f(rules: &[[i8; SETS]; SETS], e: f64, de: f64) -> f64 {
    let (me, md) = (memberships_f(e), memberships_f(de));
    let mut strength = [0.0f64; SETS];
    for i in 0..SETS {
        for j in 0..SETS {
            let r = rules[i][j];
            if r != NO_RULE {
                let o = (r + 3) as usize;
                strength[o] = strength[o].max(me[i].min(md[j]));
            }
        }
    }
    let steps = 3 * tooltouch_model::force::control::fuzzy::OUTPUT_STEPS_PER_SET;
    let (mut num, mut den) = (0.0, 0.0);
    for p in -steps..=steps {
        let u =
            f64::from(p) / f64::from(tooltouch_model::force::control::fuzzy::OUTPUT_STEPS_PER_SET);
        let mu = strength
            .iter()
            .zip(memberships_f(u))
            .map(|(s, m)| s.min(m))
            .fold(0.0, f64::max);
        num += u * mu;
        den += mu;
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

impl ControllerF for FuzzyF {
    fn step(&mut self, r: f64, force: f64) -> (f64, u8, bool) {
        let (u, q, sat) = out(self.demand(r, force));
        self.e_prev = Some(r - force);
        self.u = u;
        (u, q, sat)
    }
    fn reset(&mut self, o: u8) {
        self.u = f64::from(o);
        self.e_prev = None;
    }
    fn demand(&self, r: f64, force: f64) -> f64 {
        let span = f64::from(tooltouch_model::force::control::fuzzy::SPAN);
        let e = r - force;
        let de = e - self.e_prev.unwrap_or(e);
        let du = infer_f(&self.rules, self.ge * e / span, self.gde * de / span) * span;
        self.u + self.gdu * du
    }
    fn state(&self) -> ControllerStateF {
        ControllerStateF::Fuzzy {
            override_state: self.u,
            previous_error: self.e_prev,
        }
    }
    fn set_state(&mut self, state: &ControllerStateF) -> Result<(), WrongController> {
        let ControllerStateF::Fuzzy {
            override_state,
            previous_error,
        } = *state
        else {
            return Err(WrongController);
        };
        self.u = override_state;
        self.e_prev = previous_error;
        Ok(())
    }
}

/// The float controller for `settings`, period `h`, starting at `override_pct`.
pub fn controller_f(settings: &ControllerSettings, h: f64, o: u8) -> Box<dyn ControllerF + Send> {
    let mut c: Box<dyn ControllerF + Send> = match settings {
        ControllerSettings::Pi(p) => Box::new(PiF {
            kp: f(p.kp),
            ki_h: f(p.ki) * h,
            lo: f(p.integrator_min),
            hi: f(p.integrator_max),
            integral: 0.0,
        }),
        ControllerSettings::Adaptive(a) => {
            let mut c = AdaptiveF {
                s: *a,
                h,
                feed: 0.0,
                gain_estimate: f(a.initial_gain),
                gain: 0.0,
            };
            c.gain = c.gain_for(c.gain_estimate);
            Box::new(c)
        }
        ControllerSettings::Fuzzy(z) => Box::new(FuzzyF {
            ge: f(z.ge),
            gde: f(z.gde),
            gdu: f(z.gdu),
            rules: z.rules,
            e_prev: None,
            u: 0.0,
        }),
    };
    c.reset(o);
    c
}

/// Float wear monitor, mirroring `tooltouch_model::force::wear::WearMonitor`: the settling
/// hold, or with `power_lag_gain` the tracked threshold (the selected one through the
/// replica of the power's chain, plus the guard).
#[derive(Clone, Debug)]
pub struct WearF {
    s: WearSettings,
    /// Allowed power compared (during a settling hold the held one, tracking `T̃` + guard), W.
    pub allowed: f64,
    selected: f64,
    held: f64,
    hold_left: u32,
    filtered: Option<f64>,
    count: u32,
    /// Alarm latched.
    pub alarm: bool,
    /// A tool more than 1/64 of the selected threshold over it could pass.
    pub blind: bool,
    sample_k: f64,
    /// Replica: lag, sampled, period sum, samples, tracked T̃.
    track: [f64; 4],
    track_n: u32,
}

impl WearF {
    /// Condition set 0 selected; `sample_shift` is the sampling low-pass's.
    pub fn new(s: &WearSettings, sample_shift: u8) -> WearF {
        let mut w = WearF {
            s: *s,
            allowed: 0.0,
            selected: 0.0,
            held: 0.0,
            hold_left: 0,
            filtered: None,
            count: 0,
            alarm: false,
            blind: false,
            sample_k: 0.5f64.powi(i32::from(sample_shift.clamp(1, 8))),
            track: [0.0; 4],
            track_n: 0,
        };
        w.select(0);
        w.hold_left = 0;
        w.allowed = w.compared();
        w
    }
    /// Selects a condition set; a lower threshold than the one compared starts the
    /// settling hold of `settle_periods` periods (the higher one stays compared).
    pub fn select(&mut self, i: u8) {
        if i < self.s.set_count {
            let set = self.s.sets[usize::from(i)];
            let before = self.allowed;
            self.selected = match self.s.threshold {
                Threshold::Updating => {
                    f(set.idle_power) + f(set.mean_power_limit) / f(self.s.efficiency)
                }
                Threshold::Constant(p) => f(p),
            };
            if self.selected < before {
                self.held = before;
                self.hold_left = u32::from(self.s.settle_periods);
            }
            if self.filtered.is_none() {
                self.track = [self.selected, self.selected, 0.0, self.selected];
                self.track_n = 0;
                self.hold_left = 0;
            }
            self.allowed = self.compared();
            self.blind = self.unseen() > self.selected / 64.0;
        }
    }
    fn compared(&self) -> f64 {
        if self.s.power_lag_gain.is_some() {
            let t = self.track[3];
            t + (self.selected - t).abs() / f64::from(1u32 << GUARD_SHIFT)
        } else if self.hold_left > 0 {
            self.selected.max(self.held)
        } else {
            self.selected
        }
    }
    /// How far over its limit a tool may be and still pass, W (the model's `unseen`).
    fn unseen(&self) -> f64 {
        if self.s.power_lag_gain.is_some() {
            (self.selected - self.track[3]).abs() / f64::from(1u32 << GUARD_SHIFT)
        } else {
            (self.compared() - self.selected).max(0.0)
        }
    }
    /// One ADC sample (tracking only).
    pub fn on_sample(&mut self) {
        if let Some(g) = self.s.power_lag_gain {
            let t = &mut self.track;
            t[0] += (self.selected - t[0]) * f(g);
            t[1] += (t[0] - t[1]) * self.sample_k;
            t[2] += t[1];
            self.track_n += 1;
        }
    }
    /// One period; returns the low-passed power.
    pub fn step(&mut self, p: f64) -> f64 {
        let k = 0.5f64.powi(i32::from(self.s.lowpass_shift));
        let y = match self.filtered {
            None => p,
            Some(y) => y + k * (p - y),
        };
        self.filtered = Some(y);
        if self.s.power_lag_gain.is_some() {
            if self.track_n > 0 {
                let avg = self.track[2] / f64::from(self.track_n);
                self.track[3] += (avg - self.track[3]) * k;
            }
            self.track[2] = 0.0;
            self.track_n = 0;
        }
        let limit = self.compared();
        self.blind = self.unseen() > self.selected / 64.0;
        let over = y >= limit;
        self.hold_left = self.hold_left.saturating_sub(1);
        self.allowed = limit;
        if over {
            self.count += 1;
        } else {
            self.count = 0;
        }
        if self.count >= u32::from(self.s.debounce_periods) {
            self.alarm = true;
        }
        y
    }
}

/// The whole float force path, driven like `tooltouch_model::force::kernel::ForceKernel`.
pub struct ReferenceStack {
    settings: ForceSettings,
    /// Sampling chain.
    pub sampler: SamplerF,
    /// Estimator.
    pub estimator: EstimatorF,
    controller: Box<dyn ControllerF + Send>,
    /// Wear monitor.
    pub wear: WearF,
    /// Force control on.
    pub enabled: bool,
    /// Current override, %.
    pub override_pct: u8,
    /// Continuous override of the last period, %.
    pub override_cont: f64,
    /// Last estimate.
    pub estimate: EstimateF,
}

impl ReferenceStack {
    /// From validated settings.
    pub fn new(s: &ForceSettings) -> ReferenceStack {
        let h = f64::from(s.samples_per_period) / f64::from(s.sample_hz);
        ReferenceStack {
            settings: *s,
            sampler: SamplerF::new(s.lowpass_shift),
            estimator: EstimatorF::new(s),
            controller: controller_f(&s.controller, h, s.manual_override),
            wear: WearF::new(&s.wear, s.lowpass_shift),
            enabled: false,
            override_pct: s.manual_override,
            override_cont: f64::from(s.manual_override),
            estimate: EstimateF::default(),
        }
    }

    /// Applies one event, as `ForceKernel::apply` does.
    pub fn apply(&mut self, ev: tooltouch_model::force::events::ForceEvent) {
        use tooltouch_model::force::events::ForceEvent as E;
        match ev {
            E::Sample(c) => {
                self.sampler.on_sample(&c);
                self.wear.on_sample();
            }
            E::Tick => {
                let avg = self.sampler.on_tick();
                self.estimate = self.estimator.step(&avg);
                let fb = match self.settings.force_source {
                    ForceSource::Estimated => self.estimate.force,
                    ForceSource::Measured => self.estimate.force_measured,
                };
                if self.enabled {
                    let (u, q, _) = self.controller.step(f(self.settings.reference), fb);
                    self.override_cont = u;
                    self.override_pct = q;
                }
                self.wear.step(self.estimate.p_o);
            }
            E::Identify(true) => self.estimator.start_identification(),
            E::Identify(false) => self.estimator.finish_identification(),
            E::Control(on) => {
                if on && !self.enabled {
                    self.controller.reset(self.override_pct);
                }
                if !on {
                    self.override_pct = self.settings.manual_override;
                }
                self.enabled = on;
            }
            E::Conditions(i) => self.wear.select(i),
            E::ToolChanged => {
                self.wear.alarm = false;
                self.wear.count = 0;
            }
        }
    }
}
