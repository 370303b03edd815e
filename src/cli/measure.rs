//! `tooltouch measure`: simulate in-process diameter measurements on a lathe with the
//! golden model (docs/domain.md §2), print a table, and write plots, vectors and a JSON
//! summary into an output folder that always holds one whole run ([`OutputFolder`]).
//!
//! Exit codes (as every subcommand, docs/cli.md): 0 every measurement decided and was
//! accepted (confirmed, no fault); 1 the run completed and its files were written, but some
//! measurement did not decide, faulted or was not confirmed ([`UNDECIDED`]); 2 bad input
//! (a bad setting, named by its flag or its key in the settings file, a run too large to
//! hold, a folder that cannot be written).
//!
//! The table gives each measurement's status as the CNC reads it (docs/CONTRACT.md):
//! `confirmed`, `FAULT <names>` (e.g. `FAULT pulses_lost+no_decision`: no diameter is
//! shown for it) or `not confirmed`; the status line counts them, and the statistics are
//! those of the confirmed measurements only.
//!
//! A run is sized before it starts ([`check_run_size`]): its event vectors are held in
//! memory, so settings that would make more than [`MAX_EVENTS`] events (a tiny feed over
//! a large clearance with many revolutions allowed) are refused with the estimate.

pub use super::setting_flags::SettingFlags;
use anyhow::Context;
use clap::ValueEnum;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_metrology::averaging::{per_z_means, ZMean};
use tooltouch_metrology::calibration::{corrected_mm, Calibration, CalibrationEntry};
use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_model::Faults;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::lathe::LatheScenario;
use tooltouch_plant::measurement_cycle::{
    self, check_run_size, CycleRun, MeasurementReport, Spread,
};
use tooltouch_settings::{Settings, SettingsError};
use tooltouch_vectors::output::OutputFolder;
use tooltouch_vectors::{self as vectors, binary, vcd};

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

/// Exit code of a run in which some measurement did not decide, faulted or was not
/// confirmed (its files are written).
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
Exit codes: 0 every measurement decided and was accepted (confirmed, no fault); 1 the run \
completed and wrote its files, but some measurement did not decide, faulted or was not \
confirmed; 2 bad input (a setting out of range, named by its flag or key; a \
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
    /// The settings' flags ([`tooltouch_settings::flags`]).
    #[command(flatten)]
    pub flags: SettingFlags,
}

impl Args {
    /// The settings: defaults, then the `--config` file, then the flags.
    pub fn settings(&self) -> Result<Settings, SettingsError> {
        self.flags.settings(self.config.as_deref())
    }
}

fn opt(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "—".to_string(), |x| format!("{x:.decimals$}"))
}

/// A measurement's status as the CNC reads it: `confirmed` (accepted), `FAULT <names>`
/// (an alarm: the reading is not trusted), `not confirmed` (decided, no fault, but the
/// CNC retracted before the confirmation) or `no decision`.
fn status(m: &MeasurementReport) -> String {
    if m.faults != 0 {
        format!("FAULT {}", Faults(m.faults))
    } else if m.accepted {
        "confirmed".to_string()
    } else if m.decision_position.is_some() {
        "not confirmed".to_string()
    } else {
        "no decision".to_string()
    }
}

/// The run's status line: how many measurements were confirmed, and which faulted or
/// went unconfirmed (both left out of the statistics).
fn status_line(run: &CycleRun) -> String {
    let t = &run.summary;
    let mut line = format!("status: {}/{} confirmed", t.decided, t.measurements);
    if t.faulted == 0 {
        line.push_str(", no fault");
    } else {
        let list: Vec<String> = run
            .measurements
            .iter()
            .filter(|m| m.faults != 0)
            .map(|m| format!("#{} {}", m.index + 1, Faults(m.faults)))
            .collect();
        line.push_str(&format!(
            "; {} faulted (the CNC alarms; no diameter, left out of the statistics): {}",
            t.faulted,
            list.join(", ")
        ));
    }
    if t.unconfirmed > 0 {
        let list: Vec<String> = run
            .measurements
            .iter()
            .filter(|m| m.faults == 0 && !m.confirmed && m.decision_position.is_some())
            .map(|m| format!("#{}", m.index + 1))
            .collect();
        line.push_str(&format!(
            "; {} decided but not confirmed before the retract (left out): {}",
            t.unconfirmed,
            list.join(", ")
        ));
    }
    line.push('\n');
    line
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
        "  #   first-contact Ø   decided Ø       vs mean   vs largest   revs to     revs to     status\n\
         \x20     mm                mm              µm        µm           decision    permanent\n",
    );
    for m in &run.measurements {
        s.push_str(&format!(
            "{:>3}   {:>14}   {:>13}   {:>8}   {:>10}   {:>8}   {:>9}   {}\n",
            m.index + 1,
            opt(m.first_contact_diameter_mm, 4),
            opt(m.diameter_mm, 4),
            opt(m.error_vs_mean_um, 2),
            opt(m.error_vs_largest_um, 2),
            opt(m.revs_to_decision, 2),
            opt(m.revs_to_permanent, 2),
            status(m),
        ));
    }
    let t = &run.summary;
    s.push_str(&status_line(run));
    if t.decided == 0 {
        s.push_str(&format!(
            "decided 0/{}: no measurement decided and was accepted, so no diameter (one count = {:.2} µm)\n",
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
        .entry_for_machine(config, scenario)
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

/// The mean of each Z's measurements and its 1σ `σ/√m` (with `averages_per_z` > 1; the law
/// of S8).
fn per_z_table(means: &[ZMean]) -> String {
    let mut s = String::from(
        "means at one Z (σ/√m):\n  Z mm    m   mean Ø mm    σ µm   σ/√m µm   error vs true mean µm\n",
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
            "measure: {} of {} measurements did not decide or were not accepted ({} faulted) (exit code {UNDECIDED})",
            t.measurements - t.decided,
            t.measurements,
            t.faulted
        );
        return Ok(ExitCode::from(UNDECIDED));
    }
    Ok(ExitCode::SUCCESS)
}
