//! The force path's firmware cost: the instructions the Nucleo image spends on the force
//! path per control period, measured by executing it.
//!
//! A force point's depth-step scenario (the one its IAE comes from,
//! [`tooltouch_plant::drive::scenario`]) is recorded with the golden kernel in the loop and
//! replayed to the Nucleo-F446RE image's emulated build on QEMU's `netduinoplus2`
//! (Cortex-M4F, `-icount shift=0`: one nanosecond of virtual time per instruction, SysTick
//! calibrated against a loop of known length; [`tooltouch_firmware_runner::nucleo`]). The image
//! configures its kernels from the stream's force configuration records, so one image
//! measures every point; its force outputs are checked bit for bit against the golden model
//! on every control period and command (a mismatch is an error, not a cost).
//!
//! The cost is the mean instructions per control period of the ADC-sample interrupts
//! (each queues a sample) and the control-period interrupt (it applies the period's samples,
//! estimates, controls and watches wear), from pend to return: exception entry and exit not
//! included, each interrupt timed in whole SysTick ticks of 5 instructions (so a figure
//! depends slightly on where in the boot a stream runs: within
//! [`ForceFirmwareCost::resolution`]). Instructions, not cycles: QEMU does not model the Cortex-M4's pipeline; the
//! measurement interrupts' paths run at 1.4–1.8 cycles per instruction by the disassembly
//! (docs/firmware.md, "FES cost"), so cycles are about 1.4–1.8 times these figures.

use std::path::{Path, PathBuf};
use tooltouch_firmware_runner::nucleo;
use tooltouch_firmware_runner::{Case, CosimError, Observe, Profile};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::drive::scenario::{run, ControlScenario, Engine};
use tooltouch_stimuli::scenario::TICK_HZ;

/// Index of the ADC-sample interrupts in [`Profile::per_kind`].
const ADC_SAMPLE: usize = 5;
/// Index of the control-period interrupts in [`Profile::per_kind`].
const CONTROL_PERIOD: usize = 6;

/// What the image spent on one force point's scenario.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceFirmwareCost {
    /// Mean instructions per control period: its ADC-sample interrupts and its
    /// control-period interrupt, pend to return.
    pub per_period: f64,
    /// Mean instructions per ADC-sample interrupt.
    pub per_sample: f64,
    /// Mean instructions per control-period interrupt (applying its samples included).
    pub per_control: f64,
    /// Control periods replayed.
    pub periods: u32,
    /// ADC samples replayed.
    pub samples: u32,
    /// How exact `per_period` is: each interrupt is timed in whole SysTick ticks, so a
    /// period's figure is within one tick per interrupt of the true count (instructions;
    /// the mean over many periods is usually much closer).
    pub resolution: f64,
}

impl ForceFirmwareCost {
    /// The cost from one stream's profile; `None` when the stream had no control period.
    pub fn from_profile(p: &Profile) -> Option<ForceFirmwareCost> {
        let (samples, sample_ticks) = p.per_kind[ADC_SAMPLE];
        let (periods, control_ticks) = p.per_kind[CONTROL_PERIOD];
        if periods == 0 {
            return None;
        }
        let per_tick = p.instructions_per_tick();
        let instructions = |ticks: u32| f64::from(ticks) * per_tick;
        Some(ForceFirmwareCost {
            per_period: (instructions(sample_ticks) + instructions(control_ticks))
                / f64::from(periods),
            per_sample: instructions(sample_ticks) / f64::from(samples.max(1)),
            per_control: instructions(control_ticks) / f64::from(periods),
            periods,
            samples,
            resolution: f64::from(samples + periods) / f64::from(periods) * per_tick,
        })
    }
}

/// The depth-step scenario of `config` as a firmware case: its force events (recorded
/// with the golden kernel closing the loop, as `tooltouch control` runs it), at 50 MHz
/// ticks (sample `k` at `(k + 1)·50 MHz / sample rate`; a control period and the commands
/// after a sample carry its time), and no measurement events.
pub fn force_case(config: &ForceConfig) -> Case {
    let recorded = run(&ControlScenario::new(*config), Engine::Model, true);
    let sample_hz = u64::from(config.settings().sample_hz.max(1));
    let ticks = |k: u64| (k + 1) * u64::from(TICK_HZ) / sample_hz;
    let s = config.settings();
    Case {
        name: format!(
            "depth-step scenario, {} controller, {:?} force",
            s.controller.name(),
            s.force_source
        ),
        config: MeasureConfig::default(),
        tick_hz: TICK_HZ,
        events: Vec::new(),
        force: Some(*config),
        force_events: recorded
            .events
            .into_iter()
            .map(|(k, e)| (ticks(k), e))
            .collect(),
    }
}

/// The emulated Nucleo image that measures the cost.
#[derive(Clone, Debug)]
pub struct CostImage {
    image: PathBuf,
}

impl CostImage {
    /// Builds (or reuses) the emulated Nucleo image; fails naming `cargo xtask setup` when
    /// QEMU or the Cortex-M4F target is missing.
    pub fn build() -> Result<CostImage, CosimError> {
        Ok(CostImage {
            image: nucleo::build_emulated()?,
        })
    }

    /// An image built elsewhere.
    pub fn at(image: &Path) -> CostImage {
        CostImage {
            image: image.to_path_buf(),
        }
    }

    /// The cost of each of `configs`, in one boot; every force output checked against the
    /// golden model.
    pub fn measure(&self, configs: &[ForceConfig]) -> Result<Vec<ForceFirmwareCost>, CosimError> {
        let cases: Vec<Case> = configs.iter().map(force_case).collect();
        let run = nucleo::run_batch(&self.image, &cases, Observe::SkipFes)?;
        run.report
            .profiles
            .iter()
            .zip(&cases)
            .map(|(p, c)| {
                ForceFirmwareCost::from_profile(p).ok_or_else(|| CosimError::Trace {
                    offset: 0,
                    why: format!("{}: the image took no control-period interrupt", c.name),
                })
            })
            .collect()
    }
}
