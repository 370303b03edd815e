//! `tooltouch measure`: simulate in-process diameter measurements on a lathe with the
//! golden model (docs/domain.md §2), print a table, and write plots, vectors and a JSON
//! summary into an output folder that always holds one whole run ([`OutputFolder`]).
//!
//! Exit codes (as every subcommand, docs/cli.md): 0 every measurement decided; 1 the run
//! completed and its files were written, but some measurement did not decide
//! ([`UNDECIDED`]); 2 bad input (a bad setting, named by its flag or its key in the
//! settings file, a run too large to hold, a folder that cannot be written).
//!
//! A run is sized before it starts ([`check_run_size`]): its event vectors are held in
//! memory, so settings that would make more than [`MAX_EVENTS`] events (a tiny feed over
//! a large clearance with many revolutions allowed) are refused with the estimate.

use anyhow::Context;
use clap::ValueEnum;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_metrology::averaging::{per_z_means, ZMean};
use tooltouch_metrology::calibration::{corrected_mm, Calibration, CalibrationEntry};
use tooltouch_model::measure::config::{ChargeLaw, ContactRule, DecisionMethod};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::lathe::{LatheScenario, RetractAt};
use tooltouch_plant::measurement_cycle::{self, check_run_size, CycleRun, Spread};
use tooltouch_settings::{Settings, SettingsError};
use tooltouch_vectors::output::OutputFolder;
use tooltouch_vectors::{self as vectors, binary, vcd};

/// Decision method (the values are the settings file's, docs/cli.md).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Method {
    /// First contact (measures near the largest diameter).
    SinglePulse,
    /// The old spelling of `single-pulse`: accepted for one release, with a warning.
    #[value(hide = true)]
    Single,
    /// Pulse counter: count > i_def (50 % → the mean diameter).
    Counter,
    /// Contact-density detector (digital capacitor).
    Density,
}

/// Contact bit rule.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Rule {
    /// Contact level at the FES edge.
    Sampled,
    /// Contact at any time since the previous FES pulse.
    Sticky,
}

/// Capacitor law.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Law {
    /// Linear steps.
    Linear,
    /// RC-like, by shifts.
    Exponential,
}

/// When to retract.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Retract {
    /// CNC reaction time after "register now".
    Decision,
    /// After a whole revolution of permanent contact (records the full burst pattern).
    PermanentContact,
}

/// Which part of the run goes into the VCD.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum VcdSpan {
    /// The first measurement only (power-on to its Z step; a few MB).
    First,
    /// Every measurement (tens of MB at the defaults).
    All,
    /// No VCD.
    None,
}

/// Exit code of a run in which some measurement did not decide (its files are written).
pub const UNDECIDED: u8 = super::NOT_PASSED;

/// Every file `measure` can write into its output folder.
pub const OUTPUTS: [&str; 7] = [
    "contact_density.svg",
    "diameters.svg",
    "measure.vcd",
    "measure.fst",
    "events.ttv",
    "expected_outputs.ttv",
    "summary.json",
];

/// Arguments of `tooltouch measure`. Every setting has a flag; flags override `--config`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Exit codes: 0 every measurement decided; 1 the run completed and wrote its files, but some \
measurement did not decide; 2 bad input (a setting out of range, named by its flag or key; a \
run too large; an unreadable settings file; an unwritable output folder).")]
pub struct Args {
    /// Output folder (created): plots, VCD, binary vectors, summary.json. A run replaces
    /// this command's files in the folder (and removes those it did not write this time,
    /// e.g. measure.vcd with `--vcd none`); other files are left alone; a failed run leaves
    /// the folder as it was.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Settings file (TOML: [measure] and [lathe] tables; see docs/measure.md).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Part of the run written as VCD.
    #[arg(long, value_enum, default_value = "first")]
    pub vcd: VcdSpan,
    /// Format of that golden trace: `vcd` writes measure.vcd, `fst` measure.fst (the same
    /// signals and times; `tooltouch check` reads either).
    #[arg(long, value_enum, default_value = "vcd")]
    pub golden_format: super::vectors::GoldenFormatArg,
    /// No progress bar.
    #[arg(long)]
    pub no_progress: bool,
    /// Calibration file (`tooltouch calibrate`): subtract its offset for this method,
    /// contact rule and feed from the decided diameters; refused when made with another
    /// configuration or feed.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
    /// The settings' flags.
    #[command(flatten)]
    pub flags: Box<SettingFlags>,
}

/// One flag per setting (boxed in [`Args`]: forty options are a large value).
#[derive(clap::Args, Debug, Default)]
pub struct SettingFlags {
    // [measure]
    /// Decision method.
    #[arg(long, value_enum, help_heading = "Golden model [measure]")]
    pub method: Option<Method>,
    /// Decide when the window's contact-pulse count exceeds this (50 % of 1024 = 512).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub i_def: Option<u32>,
    /// FES pulses per revolution (16..=16384).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub pulses_per_rev: Option<u16>,
    /// Revolutions per counting window (1..=16).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub window_revs: Option<u8>,
    /// Contact bit rule.
    #[arg(long, value_enum, help_heading = "Golden model [measure]")]
    pub contact_rule: Option<Rule>,
    /// Capacitor charge register width, bits (4..=24).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub charge_bits: Option<u8>,
    /// Capacitor law. The default configuration is linear with steps 64/64; switching the
    /// law from the file's takes 2048/1024 (linear) or shifts 5/6 (exponential) unless the
    /// steps or shifts are given.
    #[arg(long, value_enum, help_heading = "Golden model [measure]")]
    pub charge_law: Option<Law>,
    /// Linear law: charge per contact pulse, LSBs.
    #[arg(long, help_heading = "Golden model [measure]")]
    pub charge_step: Option<u32>,
    /// Linear law: discharge per pulse without contact, LSBs.
    #[arg(long, help_heading = "Golden model [measure]")]
    pub discharge_step: Option<u32>,
    /// Exponential law: charging time constant, pulses, as a power of two.
    #[arg(long, help_heading = "Golden model [measure]")]
    pub charge_shift: Option<u8>,
    /// Exponential law: discharging time constant, pulses, as a power of two.
    #[arg(long, help_heading = "Golden model [measure]")]
    pub discharge_shift: Option<u8>,
    /// Density detector fire threshold, LSBs.
    #[arg(long, help_heading = "Golden model [measure]")]
    pub fire_threshold: Option<u32>,
    /// Density detector re-arm threshold, LSBs (< fire threshold).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub rearm_threshold: Option<u32>,
    /// Glitch filter length, clocks (0..=255).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub glitch_cycles: Option<u8>,
    /// Scale position counter width, bits (8..=32).
    #[arg(long, help_heading = "Golden model [measure]")]
    pub scale_bits: Option<u8>,

    // [lathe]
    /// FPGA clock, Hz (divides 1e9).
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub clock_hz: Option<u32>,
    /// Spindle speed, rpm.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub rpm: Option<f64>,
    /// Nominal diameter, mm.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub diameter_mm: Option<f64>,
    /// Radial approach feed f_r, mm/rev.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub feed_mm_per_rev: Option<f64>,
    /// Linear scale resolution, µm per count.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub scale_resolution_um: Option<f64>,
    /// Multiply every profile (form error) amplitude by this.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub profile_gain: Option<f64>,
    /// Multiply every slow (period > 1 rev) spindle error amplitude by this (0: none).
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub slow_gain: Option<f64>,
    /// Random radius error (roughness), µm standard deviation.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub random_um: Option<f64>,
    /// Fraction of the per-revolution spindle errors that does not cancel (0..=1).
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub repeating_mismatch: Option<f64>,
    /// Seed of every random stream.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub seed: Option<u64>,
    /// Bounce pulses at first touch.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub bounce_pulses: Option<u32>,
    /// Non-conduction after first touch, µs.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub non_conduction_us: Option<f64>,
    /// Noise spikes on the contact line, per second.
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub spike_rate_hz: Option<f64>,
    /// Longest noise spike, clocks (capped at glitch_cycles).
    #[arg(long, help_heading = "Lathe [lathe]")]
    pub spike_max_cycles: Option<u32>,

    // [lathe.cycle]
    /// Measurements (each at a new Z).
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub repeats: Option<u32>,
    /// Approach start above the nominal radius, µm.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub clearance_um: Option<f64>,
    /// Retract speed, mm/s.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub retract_mm_per_s: Option<f64>,
    /// Z step between measurements, mm (> nose radius).
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub z_step_mm: Option<f64>,
    /// Tool nose radius, mm.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub nose_radius_mm: Option<f64>,
    /// Z step time, ms.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub z_dwell_ms: Option<f64>,
    /// CNC reaction from "register now" to feed stop, µs.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub cnc_reaction_us: Option<f64>,
    /// When to retract.
    #[arg(long, value_enum, help_heading = "Measurement cycle [lathe.cycle]")]
    pub retract_at: Option<Retract>,
    /// Give up an approach after this many revolutions.
    #[arg(long, help_heading = "Measurement cycle [lathe.cycle]")]
    pub max_approach_revs: Option<u32>,
}

/// Multiplies each amplitude of the `[lathe] list` by `gain` (the flag `flag`), naming the
/// flag when the gain or a scaled amplitude is out of range (`0..=1000` µm).
fn scale_amplitudes<'a>(
    flag: &str,
    gain: f64,
    list: &str,
    amplitudes: impl Iterator<Item = &'a mut f64>,
) -> Result<(), SettingsError> {
    if !(gain.is_finite() && gain >= 0.0) {
        return Err(SettingsError::Conflict(format!(
            "{flag} {gain} is out of range: allowed 0 or more (a factor on every [lathe] {list} amplitude)"
        )));
    }
    for (i, a) in amplitudes.enumerate() {
        let scaled = *a * gain;
        if scaled > 1000.0 {
            return Err(SettingsError::Conflict(format!(
                "{flag} {gain} makes [lathe] {list}[{i}].amplitude_um {} × {gain} = {scaled} µm, \
                 out of range: allowed 0..=1000 µm",
                *a
            )));
        }
        *a = scaled;
    }
    Ok(())
}

fn set<T: Copy>(target: &mut T, flag: Option<T>) {
    if let Some(v) = flag {
        *target = v;
    }
}

impl Args {
    /// The settings: defaults, then the `--config` file, then the flags.
    pub fn settings(&self) -> Result<Settings, SettingsError> {
        self.flags.settings(self.config.as_deref())
    }
}

impl SettingFlags {
    /// The flag that set the settings field `field` (as a [`ScenarioError`] or
    /// `ConfigError` names it: `rpm`, `cycle.repeats`, `i_def`) and its value as given.
    ///
    /// [`ScenarioError`]: tooltouch_plant::lathe::ScenarioError
    pub fn flag_of(&self, field: &str) -> Option<(String, String)> {
        fn v<T: std::fmt::Display>(x: Option<T>) -> Option<String> {
            x.map(|x| x.to_string())
        }
        let leaf = field.rsplit('.').next().unwrap_or(field);
        let value = match leaf {
            "i_def" => v(self.i_def),
            "pulses_per_rev" => v(self.pulses_per_rev),
            "window_revs" => v(self.window_revs),
            "charge_bits" => v(self.charge_bits),
            "charge_step" => v(self.charge_step),
            "discharge_step" => v(self.discharge_step),
            "charge_shift" => v(self.charge_shift),
            "discharge_shift" => v(self.discharge_shift),
            "fire_threshold" => v(self.fire_threshold),
            "rearm_threshold" => v(self.rearm_threshold),
            "glitch_cycles" => v(self.glitch_cycles),
            "scale_bits" => v(self.scale_bits),
            "clock_hz" => v(self.clock_hz),
            "rpm" => v(self.rpm),
            "diameter_mm" => v(self.diameter_mm),
            "feed_mm_per_rev" => v(self.feed_mm_per_rev),
            "scale_resolution_um" => v(self.scale_resolution_um),
            "random_um" => v(self.random_um),
            "repeating_mismatch" => v(self.repeating_mismatch),
            "seed" => v(self.seed),
            "bounce_pulses" => v(self.bounce_pulses),
            "non_conduction_us" => v(self.non_conduction_us),
            "spike_rate_hz" => v(self.spike_rate_hz),
            "spike_max_cycles" => v(self.spike_max_cycles),
            "repeats" => v(self.repeats),
            "clearance_um" => v(self.clearance_um),
            "retract_mm_per_s" => v(self.retract_mm_per_s),
            "z_step_mm" => v(self.z_step_mm),
            "nose_radius_mm" => v(self.nose_radius_mm),
            "z_dwell_ms" => v(self.z_dwell_ms),
            "cnc_reaction_us" => v(self.cnc_reaction_us),
            "max_approach_revs" => v(self.max_approach_revs),
            _ => None,
        }?;
        Some((format!("--{}", leaf.replace('_', "-")), value))
    }

    /// The flag of a settings field whether given or not (`cycle.retract_mm_per_s` →
    /// `--retract-mm-per-s`), or its key for a field without a flag.
    fn flag_of_name(&self, field: &str) -> String {
        let leaf = field.rsplit('.').next().unwrap_or(field);
        let flag = format!("--{}", leaf.replace('_', "-"));
        let known = crate::cli::Cli::command_has_flag("measure", &flag[2..]);
        if known {
            flag
        } else {
            format!("`{field}` in --config")
        }
    }

    /// A settings error told as the user spelled the culprit: the flag and its value when
    /// a flag set the field, else the settings file (when the field is in it), else a
    /// default the user did not set. `config` is the `--config` file.
    pub fn explain(&self, e: SettingsError, config: Option<&std::path::Path>) -> anyhow::Error {
        let field = match &e {
            SettingsError::Measure(c) => c.field.to_string(),
            SettingsError::Lathe(l) => l.field.clone(),
            _ => return e.into(),
        };
        if let Some((flag, value)) = self.flag_of(&field) {
            return anyhow::anyhow!("{flag} {value}: {e}");
        }
        match config {
            Some(path) if file_sets(path, &e, &field) => {
                anyhow::anyhow!("settings file {}: {e}", path.display())
            }
            _ => anyhow::anyhow!(
                "{e}; this value is the default (not set by a flag or the settings file) and does not fit the other settings: set {} or change those",
                self.flag_of_name(&field)
            ),
        }
    }

    /// The settings: defaults, then the file `config`, then these flags.
    pub fn settings(&self, config: Option<&std::path::Path>) -> Result<Settings, SettingsError> {
        let mut s = match config {
            Some(path) => Settings::load(path)?,
            None => Settings::default(),
        };
        let m = &mut s.measure;
        if let Some(method) = self.method {
            m.method = match method {
                Method::SinglePulse => DecisionMethod::SinglePulse,
                Method::Single => {
                    eprintln!(
                        "{}",
                        tooltouch_settings::old_spelling_warning(
                            "--method",
                            "single",
                            "single-pulse"
                        )
                    );
                    DecisionMethod::SinglePulse
                }
                Method::Counter => DecisionMethod::Counter,
                Method::Density => DecisionMethod::Density,
            };
        }
        if let Some(rule) = self.contact_rule {
            m.contact_rule = match rule {
                Rule::Sampled => ContactRule::Sampled,
                Rule::Sticky => ContactRule::Sticky,
            };
        }
        set(&mut m.i_def, self.i_def);
        set(&mut m.pulses_per_rev, self.pulses_per_rev);
        set(&mut m.window_revs, self.window_revs);
        set(&mut m.charge_bits, self.charge_bits);
        set(&mut m.fire_threshold, self.fire_threshold);
        set(&mut m.rearm_threshold, self.rearm_threshold);
        set(&mut m.glitch_cycles, self.glitch_cycles);
        set(&mut m.scale_bits, self.scale_bits);
        match self.charge_law {
            Some(Law::Linear) if !matches!(m.charge_law, ChargeLaw::Linear { .. }) => {
                m.charge_law = ChargeLaw::Linear {
                    charge_step: 2048,
                    discharge_step: 1024,
                }
            }
            Some(Law::Exponential) if !matches!(m.charge_law, ChargeLaw::Exponential { .. }) => {
                m.charge_law = ChargeLaw::Exponential {
                    charge_shift: 5,
                    discharge_shift: 6,
                }
            }
            _ => {}
        }
        match &mut m.charge_law {
            ChargeLaw::Linear {
                charge_step,
                discharge_step,
            } => {
                if self.charge_shift.is_some() || self.discharge_shift.is_some() {
                    return Err(SettingsError::Conflict(
                        "--charge-shift/--discharge-shift need --charge-law exponential".into(),
                    ));
                }
                set(charge_step, self.charge_step);
                set(discharge_step, self.discharge_step);
            }
            ChargeLaw::Exponential {
                charge_shift,
                discharge_shift,
            } => {
                if self.charge_step.is_some() || self.discharge_step.is_some() {
                    return Err(SettingsError::Conflict(
                        "--charge-step/--discharge-step need --charge-law linear".into(),
                    ));
                }
                set(charge_shift, self.charge_shift);
                set(discharge_shift, self.discharge_shift);
            }
        }
        let l = &mut s.lathe;
        set(&mut l.clock_hz, self.clock_hz);
        set(&mut l.rpm, self.rpm);
        set(&mut l.diameter_mm, self.diameter_mm);
        set(&mut l.feed_mm_per_rev, self.feed_mm_per_rev);
        set(&mut l.scale_resolution_um, self.scale_resolution_um);
        set(&mut l.random_um, self.random_um);
        set(&mut l.repeating_mismatch, self.repeating_mismatch);
        set(&mut l.seed, self.seed);
        if let Some(g) = self.profile_gain {
            scale_amplitudes(
                "--profile-gain",
                g,
                "profile",
                l.profile.iter_mut().map(|h| &mut h.amplitude_um),
            )?;
        }
        if let Some(g) = self.slow_gain {
            scale_amplitudes(
                "--slow-gain",
                g,
                "slow",
                l.slow.iter_mut().map(|h| &mut h.amplitude_um),
            )?;
        }
        let e = &mut l.electrics;
        set(&mut e.bounce_pulses, self.bounce_pulses);
        set(&mut e.non_conduction_us, self.non_conduction_us);
        set(&mut e.spike_rate_hz, self.spike_rate_hz);
        set(&mut e.spike_max_cycles, self.spike_max_cycles);
        let c = &mut l.cycle;
        set(&mut c.repeats, self.repeats);
        set(&mut c.clearance_um, self.clearance_um);
        set(&mut c.retract_mm_per_s, self.retract_mm_per_s);
        set(&mut c.z_step_mm, self.z_step_mm);
        set(&mut c.nose_radius_mm, self.nose_radius_mm);
        set(&mut c.z_dwell_ms, self.z_dwell_ms);
        set(&mut c.cnc_reaction_us, self.cnc_reaction_us);
        set(&mut c.max_approach_revs, self.max_approach_revs);
        if let Some(r) = self.retract_at {
            c.retract_at = match r {
                Retract::Decision => RetractAt::Decision,
                Retract::PermanentContact => RetractAt::PermanentContact,
            };
        }
        Ok(s)
    }
}

/// Whether the settings file `path` sets the field of `e` (`field`, dotted, with list
/// indices `profile[0].amplitude_um`).
fn file_sets(path: &std::path::Path, e: &SettingsError, field: &str) -> bool {
    let Ok(text) = tooltouch_settings::read_text_file(path, "settings file") else {
        return false;
    };
    let Ok(table) = toml::from_str::<toml::Table>(&text) else {
        return false;
    };
    let (root, alt) = match e {
        SettingsError::Measure(_) => ("measure", Some("charge_law")),
        _ => ("lathe", None),
    };
    let lookup = |prefix: Option<&str>| {
        let mut at = table.get(root);
        for part in prefix.into_iter().chain(field.split('.')) {
            let (key, index) = match part.split_once('[') {
                Some((k, i)) => (k, i.trim_end_matches(']').parse::<usize>().ok()),
                None => (part, None),
            };
            at = at.and_then(|t| t.get(key));
            if let Some(i) = index {
                at = at.and_then(|t| t.get(i));
            }
        }
        at.is_some()
    };
    lookup(None) || alt.is_some_and(|a| lookup(Some(a)))
}

fn opt(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "—".to_string(), |x| format!("{x:.decimals$}"))
}

/// The readable table of a run.
pub fn table(run: &CycleRun, config: &MeasureConfig) -> String {
    let mut s = String::new();
    let method = match config.settings().method {
        DecisionMethod::SinglePulse => "single pulse (first contact)".to_string(),
        DecisionMethod::Counter => format!(
            "pulse counter, count > i_def = {} of {} pulses",
            config.settings().i_def,
            config.window_pulses()
        ),
        DecisionMethod::Density => "contact-density detector".to_string(),
    };
    s.push_str(&format!("method: {method}\n"));
    s.push_str(
        "  #   first-contact Ø   decided Ø       vs mean   vs largest   revs to     revs to\n\
         \x20     mm                mm              µm        µm           decision    permanent\n",
    );
    for m in &run.measurements {
        s.push_str(&format!(
            "{:>3}   {:>14}   {:>13}   {:>8}   {:>10}   {:>8}   {:>9}\n",
            m.index + 1,
            opt(m.first_contact_diameter_mm, 4),
            opt(m.diameter_mm, 4),
            opt(m.error_vs_mean_um, 2),
            opt(m.error_vs_largest_um, 2),
            opt(m.revs_to_decision, 2),
            opt(m.revs_to_permanent, 2),
        ));
    }
    let t = &run.summary;
    if t.decided == 0 {
        s.push_str(&format!(
            "decided 0/{}: no measurement decided, so no diameter (one count = {:.2} µm)\n",
            t.measurements, t.diameter_quantum_um
        ));
        return s;
    }
    s.push_str(&format!(
        "decided {}/{}; diameter {:.4} mm ± {:.2} µm (1σ, range {:.2} µm, one count = {:.2} µm)\n",
        t.decided,
        t.measurements,
        t.diameter_mm.mean,
        t.diameter_mm.std * 1000.0,
        (t.diameter_mm.max - t.diameter_mm.min) * 1000.0,
        t.diameter_quantum_um
    ));
    s.push_str(&format!(
        "error vs true mean {:+.2} ± {:.2} µm; vs true largest {:+.2} ± {:.2} µm\n",
        t.error_vs_mean_um.mean,
        t.error_vs_mean_um.std,
        t.error_vs_largest_um.mean,
        t.error_vs_largest_um.std
    ));
    let pm = |x: &tooltouch_plant::measurement_cycle::Spread| {
        if x.n == 0 {
            "—".to_string()
        } else {
            format!("{:.2} ± {:.2}", x.mean, x.std)
        }
    };
    s.push_str(&format!(
        "revolutions from first contact: to decision {}, to permanent contact {}\n",
        pm(&t.revs_to_decision),
        pm(&t.revs_to_permanent)
    ));
    s
}

/// The calibration entry for this run from the file at `path`.
fn load_calibration(
    path: &std::path::Path,
    config: &MeasureConfig,
    scenario: &LatheScenario,
) -> anyhow::Result<CalibrationEntry> {
    let text =
        tooltouch_settings::read_text_file(path, "calibration file").map_err(anyhow::Error::msg)?;
    let file: Calibration = serde_json::from_str(&text)
        .with_context(|| format!("reading the calibration file {}", path.display()))?;
    let entry = file
        .entry_for(config, scenario.feed_mm_per_rev, scenario.rpm)
        .with_context(|| format!("--calibration {}", path.display()))?;
    Ok(entry.clone())
}

/// The calibrated figures: a line to print and the JSON for summary.json.
struct Calibrated {
    line: String,
    json: serde_json::Value,
}

/// The run's decided diameters with the calibration's offset subtracted.
fn calibrated_summary(run: &CycleRun, entry: &CalibrationEntry) -> Calibrated {
    let corrected: Vec<Option<f64>> = run
        .measurements
        .iter()
        .map(|m| m.diameter_mm.map(|d| corrected_mm(d, entry)))
        .collect();
    let d = Spread::of(corrected.iter().copied());
    let e = Spread::of(
        run.measurements
            .iter()
            .map(|m| m.error_vs_mean_um.map(|x| x - entry.offset_um)),
    );
    let line = format!(
        "calibrated (offset {:+.2} µm subtracted): diameter {:.4} mm ± {:.2} µm (1σ); \
         error vs true mean {:+.2} ± {:.2} µm\n",
        entry.offset_um,
        d.mean,
        d.std * 1000.0,
        e.mean,
        e.std
    );
    let json = serde_json::json!({
        "entry": entry,
        "diameter_mm": corrected,
        "error_vs_mean_um": e,
    });
    Calibrated { line, json }
}

/// S8: the mean of each Z's measurements and its 1σ `σ/√m` (with `averages_per_z` > 1).
fn per_z_table(means: &[ZMean]) -> String {
    let mut s = String::from(
        "S8 means at one Z:\n  Z mm    m   mean Ø mm    σ µm   σ/√m µm   error vs true mean µm\n",
    );
    for z in means {
        s.push_str(&format!(
            "{:>6.3} {:>4}   {:>9.4}   {:>5.2}   {:>7.2}   {:>+8.2}\n",
            z.z_mm, z.m, z.diameter_mm, z.sigma_um, z.sigma_of_mean_um, z.error_vs_mean_um
        ));
    }
    let spread = Spread::of(means.iter().map(|z| Some(z.diameter_mm)));
    if spread.n > 1 {
        s.push_str(&format!(
            "the {} means: 1σ {:.2} µm between Z positions (each Z's roughness stays in its mean)\n",
            spread.n,
            spread.std * 1000.0
        ));
    }
    s
}

/// Runs `tooltouch measure`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let settings = args.settings()?;
    let (config, scenario) = settings
        .resolve()
        .map_err(|e| args.flags.explain(e, args.config.as_deref()))?;
    check_run_size(&scenario, &config)?;
    let calibration = match &args.calibration {
        Some(path) => Some(load_calibration(path, &config, &scenario)?),
        None => None,
    };
    let out = OutputFolder::create(&args.out, OUTPUTS)?;

    let bar = if args.no_progress {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(scenario.cycle.repeats.into())
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("measuring {bar:30} {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let run = measurement_cycle::run(&scenario, &config, &mut |n| bar.set_position(n as u64))?;
    bar.finish_and_clear();
    let simulated = started.elapsed();

    out!("{}", table(&run, &config));
    let calibrated = calibration
        .as_ref()
        .map(|entry| calibrated_summary(&run, entry));
    if let Some(c) = &calibrated {
        out!("{}", c.line);
    }
    let per_z = (scenario.cycle.averages_per_z > 1).then(|| per_z_means(&run.measurements));
    if let Some(means) = &per_z {
        out!("{}", per_z_table(means));
    }

    tooltouch_plot::contact_density(
        &out.path("contact_density.svg"),
        &run.measurements,
        config.window_pulses(),
        config.settings().i_def,
    )?;
    tooltouch_plot::diameters(
        &out.path("diameters.svg"),
        &run.measurements,
        scenario.diameter_mm,
    )?;

    let vcd_end = match args.vcd {
        VcdSpan::None => None,
        VcdSpan::First => Some(run.measurements.first().map_or(0, |m| m.end_cycle)),
        VcdSpan::All => Some(run.stimulus.total_cycles()),
    };
    if let Some(end) = vcd_end {
        let fst = args.golden_format == super::vectors::GoldenFormatArg::Fst;
        let name = if fst { "measure.fst" } else { "measure.vcd" };
        let mut w = out.create_file(name)?;
        if fst {
            vectors::fst::write_golden_fst(&mut w, &run.stimulus, &config, Some(end))
        } else {
            vcd::write_golden(&mut w, &run.stimulus, &config, Some(end))
        }
        .and_then(|_| w.flush())
        .with_context(|| format!("writing {}", out.final_path(name).display()))?;
    }

    let events = vectors::events_from_stimulus(&run.stimulus, &config);
    let outputs = vectors::outputs_after_each_event(&events, &config);
    let write = |name: &str, bytes: Vec<u8>| out.write(name, bytes);
    // The input stream's copy of the events lives only while it is encoded.
    let header = {
        let inputs = binary::InputStream::of_measure_events(&config, scenario.clock_hz, &events);
        write("events.ttv", binary::encode_event_stream(&inputs))?;
        inputs.header
    };
    let expected = outputs
        .iter()
        .map(|&(t, o)| (t, binary::Output::Measure(o)));
    write(
        "expected_outputs.ttv",
        binary::encode_output_stream(header, expected),
    )?;

    let mut summary = serde_json::json!({
        "measure_hash": format!("{:016x}", config.hash()),
        "settings": settings,
        "summary": run.summary,
        "measurements": run.measurements,
        "home_count": run.home_count,
        "simulated_cycles": run.stimulus.total_cycles(),
        "simulated_seconds": run.stimulus.total_cycles() as f64 / f64::from(scenario.clock_hz),
        "clocked_cycles": run.clocked_cycles,
        "stimulus_segments": run.stimulus.segments.len(),
        "events": events.len(),
        "vcd": format!("{:?}", args.vcd).to_lowercase(),
        "wall_seconds_simulation": simulated.as_secs_f64(),
        "wall_seconds_total": started.elapsed().as_secs_f64(),
    });
    if let Some(means) = &per_z {
        summary["per_z_means"] = serde_json::json!(means);
    }
    if let Some(c) = calibrated {
        summary["calibration"] = c.json;
    }
    write(
        "summary.json",
        serde_json::to_vec_pretty(&summary).context("encoding summary.json")?,
    )?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    outln!(
        "simulated {:.2} s of lathe time ({} clocks, {} clocked, {} events) in {:.2} s; wrote {}",
        run.stimulus.total_cycles() as f64 / f64::from(scenario.clock_hz),
        run.stimulus.total_cycles(),
        run.clocked_cycles,
        events.len(),
        started.elapsed().as_secs_f64(),
        dir.display()
    );
    let t = &run.summary;
    if t.decided < t.measurements {
        eprintln!(
            "measure: {} of {} measurements did not decide (exit code {UNDECIDED})",
            t.measurements - t.decided,
            t.measurements
        );
        return Ok(ExitCode::from(UNDECIDED));
    }
    Ok(ExitCode::SUCCESS)
}
