//! Speed of the golden model against the HDL simulators (`cargo xtask bench`,
//! `benches/speed.rs`): one realistic measurement stimulus run through
//!
//! - the cycle-level model **plain**: [`FrontEnd::clock`] once per clock ([`run_plain`]);
//! - the cycle-level model **fast-forward**: [`FrontEnd::advance`] per stimulus segment,
//!   which skips the clocks where the front end is settled, exactly ([`run_fast_forward`]);
//! - the **event level**: the events the cycle level's kernel acted on, replayed with
//!   [`Measurement::apply`] ([`run_events`]);
//! - the **Verilator** and **Icarus** models of the generated Verilog, through the
//!   co-simulation runner of [`crate`] ([`hdl`]: its self-checking testbench), and
//!   Verilator once more as a bare C++ clock loop without a testbench ([`verilator`]).
//!
//! Every model run returns a [`Trace`] (a digest of every clock's detected edges and the
//! final state) so the harness can check that the runs it times did the same work.
//! Speeds are reported by the bench, never asserted by tests.

pub mod hdl;
pub mod verilator;

use std::time::Instant;
use tooltouch_model::fnv::{fnv1a_continue, FNV_OFFSET};
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::control::adaptive::DEFAULT_ADAPTIVE;
use tooltouch_model::force::control::fuzzy::DEFAULT_FUZZY;
use tooltouch_model::force::control::pi::DEFAULT_PI;
use tooltouch_model::force::control::{Controller, ControllerSettings, ForceController};
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::measure::frontend::Edges;
use tooltouch_model::units::Fx;
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureOutputs, Measurement, TimedEvent};
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_plant::stimulus::Stimulus;

/// What a model run did: enough to prove two runs equal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Trace {
    /// Clocks covered.
    pub cycles: u64,
    /// Clocks at which the kernel acted on edges.
    pub edge_clocks: u64,
    /// FNV-1a digest of `(clock, changed, levels)` of every clock with edges.
    pub digest: u64,
    /// Outputs after the last clock.
    pub outputs: MeasureOutputs,
}

/// Continues the digest `h` over one clock with edges: `k` (little-endian), then the edges'
/// `changed` and `levels` bytes (the model's FNV-1a, the same hash as the contract hashes).
#[inline]
fn fold(h: u64, k: u64, e: Edges) -> u64 {
    fnv1a_continue(fnv1a_continue(h, &k.to_le_bytes()), &[e.changed, e.levels])
}

/// Cycle level, one [`FrontEnd::clock`] per clock of `stimulus`.
pub fn run_plain(stimulus: &Stimulus, config: &MeasureConfig) -> Trace {
    let mut fe = FrontEnd::new(config);
    let (mut k, mut n, mut h) = (0u64, 0u64, FNV_OFFSET);
    for seg in &stimulus.segments {
        for _ in 0..seg.cycles {
            let e = fe.clock(seg.pins);
            if !e.is_empty() {
                n += 1;
                h = fold(h, k, e);
            }
            k += 1;
        }
    }
    Trace {
        cycles: k,
        edge_clocks: n,
        digest: h,
        outputs: fe.outputs(),
    }
}

/// Cycle level with exact fast-forward: [`FrontEnd::advance`] per segment.
pub fn run_fast_forward(stimulus: &Stimulus, config: &MeasureConfig) -> Trace {
    run_fast_forward_counted(stimulus, config).0
}

/// [`run_fast_forward`], also returning the clocks actually simulated one by one.
pub fn run_fast_forward_counted(stimulus: &Stimulus, config: &MeasureConfig) -> (Trace, u64) {
    let mut fe = FrontEnd::new(config);
    let (mut k, mut n, mut h, mut clocked) = (0u64, 0u64, FNV_OFFSET, 0u64);
    for seg in &stimulus.segments {
        clocked += fe.advance(seg.pins, u64::from(seg.cycles), |j, e| {
            n += 1;
            h = fold(h, k + j, e);
        });
        k += u64::from(seg.cycles);
    }
    let trace = Trace {
        cycles: k,
        edge_clocks: n,
        digest: h,
        outputs: fe.outputs(),
    };
    (trace, clocked)
}

/// The events of `stimulus` at event level (what the firmware receives).
pub fn events(stimulus: &Stimulus, config: &MeasureConfig) -> Vec<TimedEvent> {
    tooltouch_vectors::events_from_stimulus(stimulus, config)
}

/// Event level: replays `events` from reset; returns the outputs after the last one.
pub fn run_events(events: &[TimedEvent], config: &MeasureConfig) -> MeasureOutputs {
    let mut m = Measurement::new(config);
    for e in events {
        m.apply(e.event);
    }
    m.outputs()
}

/// The realistic measurement stimulus of the bench: the lathe simulator's closed-loop
/// measurement cycle (docs/domain.md §2.5) with the papers' set-up (`LatheScenario::default()`:
/// 40 mm, 800 rpm, f_r = 1 µm/rev, 50 MHz) and `repeats` measurements — approach to
/// permanent contact, decision, retract, Z step — on the default configuration.
pub fn realistic_stimulus(config: &MeasureConfig, repeats: u32) -> anyhow::Result<Stimulus> {
    let mut scenario = LatheScenario::default();
    scenario.cycle.repeats = repeats;
    Ok(tooltouch_plant::measurement_cycle::closed_loop_stimulus(
        &scenario, config,
    )?)
}

/// The first `cycles` clocks of `stimulus`.
pub fn prefix(stimulus: &Stimulus, cycles: u64) -> Stimulus {
    Stimulus {
        clock_hz: stimulus.clock_hz,
        segments: tooltouch_plant::measurement_cycle::slice(stimulus, 0, cycles),
    }
}

/// State of the golden model, bytes (`size_of`), per measurement channel and per force
/// channel.
pub fn state_bytes() -> Vec<(&'static str, usize)> {
    use core::mem::size_of;
    vec![
        ("FrontEnd (cycle level, one channel)", size_of::<FrontEnd>()),
        (
            "Measurement (event level, one channel)",
            size_of::<Measurement>(),
        ),
        (
            "ForceKernel (force path, one spindle)",
            size_of::<ForceKernel>(),
        ),
        ("Controller (any of the three)", size_of::<Controller>()),
    ]
}

/// The three controllers with their default settings.
pub fn controllers() -> [ControllerSettings; 3] {
    [
        ControllerSettings::Pi(DEFAULT_PI),
        ControllerSettings::Adaptive(DEFAULT_ADAPTIVE),
        ControllerSettings::Fuzzy(DEFAULT_FUZZY),
    ]
}

/// A force feedback sequence for timing the controllers: 500 N ± a sawtooth of ±200 N,
/// `n` control periods.
pub fn force_sequence(n: usize) -> Vec<Fx> {
    (0..n)
        .map(|i| Fx::from_num(300 + (i * 37 % 400) as i32))
        .collect()
}

/// Runs `settings`' controller over `forces` against a 500 N reference; returns the sum
/// of the overrides (so the work cannot be optimised away).
pub fn run_controller(settings: &ControllerSettings, forces: &[Fx]) -> u64 {
    let h = Fx::lit("0.05");
    let mut c = Controller::new(settings, h, 100);
    let r = Fx::const_from_int(500);
    forces
        .iter()
        .map(|&f| u64::from(c.step(r, f).override_pct))
        .sum()
}

/// The force path's events for `periods` control periods with force control on: per
/// period `samples_per_period` ADC samples and one tick.
pub fn force_events(settings: &ForceSettings, periods: usize) -> Vec<ForceEvent> {
    let mut v = vec![ForceEvent::Control(true)];
    for p in 0..periods {
        for s in 0..settings.samples_per_period {
            let w = ((p * 13 + usize::from(s) * 7) % 64) as u16;
            v.push(ForceEvent::Sample(AdcCodes {
                speed: 1600 + w,
                power: 600 + w,
                force: 2048 + 480 + w,
                volts: [2048 + 800 + w, 2048 - 400, 2048 - 400 - w],
                amps: [2048 + 300 + w, 2048 - 150],
            }));
        }
        v.push(ForceEvent::Tick);
    }
    v
}

/// Runs the force kernel over `events`; returns the last override.
pub fn run_force_kernel(settings: &ForceSettings, events: &[ForceEvent]) -> u8 {
    let config = match settings.validate() {
        Ok(c) => c,
        Err(_) => return 0,
    };
    let mut k = ForceKernel::new(&config);
    for &e in events {
        k.apply(e);
    }
    k.outputs().override_pct
}

/// Repeats `f` until at least `min_seconds` have passed (and at least once); returns the
/// last result and the mean seconds per call.
pub fn time<T>(min_seconds: f64, mut f: impl FnMut() -> T) -> (T, f64) {
    let t = Instant::now();
    let mut n = 0u32;
    loop {
        let r = std::hint::black_box(f());
        n += 1;
        let s = t.elapsed().as_secs_f64();
        if s >= min_seconds {
            return (r, s / f64::from(n));
        }
    }
}
