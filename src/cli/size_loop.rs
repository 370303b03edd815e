//! `tooltouch size-loop`: the measure-then-correct size loop on the simulated lathe
//! (docs/size_loop.md): N parts turned, each measured in process by the component's period
//! semantics and the tool offset corrected under the loop's rules (re-measure, upper
//! tolerance limit, maximum correction, dead zone, feedback %), with faulted touches drawn
//! per touch; today's loop (no re-measure, no limits) over the same parts beside it.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tooltouch_linuxcnc::size_loop::{
    self, counts, golden_readings, LoopCounts, LoopRules, PartRow, SizeLoopSettings,
    TouchFaultRates,
};
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::measure::checks::MeasureChecks;
use tooltouch_model::MeasureSettings;

/// Arguments of `tooltouch size-loop`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file: a `[size_loop]` table (parts, seed, nominal and tolerance, feedback,
    /// dead zone, the rules) and `[size_loop.faults]` (rates per touch); docs/size_loop.md.
    /// Without it: 20 clean parts, the safe rules.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Also write the parts, the settings and the counts as JSON to this file.
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub json: Option<PathBuf>,
    /// Also draw the parts' diameters against the tolerance band into this SVG file.
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub plot: Option<PathBuf>,
}

/// The `[size_loop]` table: every key optional, the defaults of docs/size_loop.md.
#[derive(serde::Deserialize, serde::Serialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct Table {
    parts: Option<usize>,
    seed: Option<u64>,
    nominal_mm: Option<f64>,
    tolerance_mm: Option<f64>,
    feedback_pct: Option<f64>,
    dead_zone_mm: Option<f64>,
    wear_um_per_part: Option<f64>,
    thermal_um: Option<f64>,
    remeasure: Option<bool>,
    upper_tolerance_mm: Option<f64>,
    max_correction_mm: Option<f64>,
    faults: Option<Faults>,
}

/// `[size_loop.faults]`: probabilities per touch, and the thickest trapped chip.
#[derive(serde::Deserialize, serde::Serialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct Faults {
    coolant_bridge: Option<f64>,
    chip_burst: Option<f64>,
    trapped_chip: Option<f64>,
    trapped_chip_um: Option<f64>,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    size_loop: Option<Table>,
}

/// The most parts a run turns (each part is two touches of 260 servo periods).
const MAX_PARTS: usize = 5_000;

/// Checks `value` of `key` against `ok`, naming both and what is allowed.
fn check(key: &str, value: f64, ok: bool, allowed: &str) -> Result<()> {
    if !value.is_finite() || !ok {
        bail!("size_loop.{key} = {value}: must be {allowed}");
    }
    Ok(())
}

/// The loop's settings from the table, validated.
fn settings(t: Option<Table>) -> Result<SizeLoopSettings> {
    let mut s = SizeLoopSettings {
        rules: LoopRules::SAFE,
        ..SizeLoopSettings::default()
    };
    let Some(t) = t else { return Ok(s) };
    if let Some(parts) = t.parts {
        if parts == 0 || parts > MAX_PARTS {
            bail!("size_loop.parts = {parts}: must be 1 to {MAX_PARTS}");
        }
        s.parts = parts;
    }
    s.seed = t.seed.unwrap_or(s.seed);
    let mm = |v: Option<f64>, d: f64| v.unwrap_or(d);
    s.nominal_mm = mm(t.nominal_mm, s.nominal_mm);
    check(
        "nominal_mm",
        s.nominal_mm,
        s.nominal_mm > 0.0 && s.nominal_mm <= 2_000.0,
        "in (0, 2000] mm",
    )?;
    s.master_mm = s.nominal_mm;
    s.tolerance_mm = mm(t.tolerance_mm, s.tolerance_mm);
    check(
        "tolerance_mm",
        s.tolerance_mm,
        s.tolerance_mm > 0.0 && s.tolerance_mm <= 1.0,
        "in (0, 1] mm",
    )?;
    s.feedback_pct = mm(t.feedback_pct, s.feedback_pct);
    check(
        "feedback_pct",
        s.feedback_pct,
        (0.0..=100.0).contains(&s.feedback_pct),
        "0 to 100 %",
    )?;
    s.dead_zone_mm = mm(t.dead_zone_mm, s.dead_zone_mm);
    check(
        "dead_zone_mm",
        s.dead_zone_mm,
        (0.0..=1.0).contains(&s.dead_zone_mm),
        "0 to 1 mm",
    )?;
    s.wear_um_per_part = mm(t.wear_um_per_part, s.wear_um_per_part);
    check(
        "wear_um_per_part",
        s.wear_um_per_part,
        (0.0..=100.0).contains(&s.wear_um_per_part),
        "0 to 100 µm",
    )?;
    s.thermal_um = mm(t.thermal_um, s.thermal_um);
    check(
        "thermal_um",
        s.thermal_um,
        s.thermal_um.abs() <= 1_000.0,
        "-1000 to 1000 µm",
    )?;
    s.rules.remeasure = t.remeasure.unwrap_or(s.rules.remeasure);
    if let Some(v) = t.upper_tolerance_mm {
        check(
            "upper_tolerance_mm",
            v,
            v > 0.0 && v <= 10.0,
            "in (0, 10] mm (leave it out for no limit)",
        )?;
        s.rules.upper_tolerance_mm = Some(v);
    }
    if let Some(v) = t.max_correction_mm {
        check(
            "max_correction_mm",
            v,
            v > 0.0 && v <= 10.0,
            "in (0, 10] mm (leave it out for no limit)",
        )?;
        s.rules.max_correction_mm = Some(v);
    }
    if let Some(f) = t.faults {
        let rate = |key: &str, v: Option<f64>| -> Result<f64> {
            let v = v.unwrap_or(0.0);
            check(
                &format!("faults.{key}"),
                v,
                (0.0..=1.0).contains(&v),
                "a probability per touch, 0 to 1",
            )?;
            Ok(v)
        };
        s.faults = TouchFaultRates {
            coolant_bridge: rate("coolant_bridge", f.coolant_bridge)?,
            chip_burst: rate("chip_burst", f.chip_burst)?,
            trapped_chip: rate("trapped_chip", f.trapped_chip)?,
            trapped_chip_um: f
                .trapped_chip_um
                .unwrap_or(TouchFaultRates::CAMPAIGN.trapped_chip_um),
        };
        let sum = s.faults.coolant_bridge + s.faults.chip_burst + s.faults.trapped_chip;
        check(
            "faults (coolant_bridge + chip_burst + trapped_chip)",
            sum,
            sum <= 1.0,
            "at most 1",
        )?;
        let um = s.faults.trapped_chip_um;
        check(
            "faults.trapped_chip_um",
            um,
            (1.0..=100.0).contains(&um),
            "1 to 100 µm",
        )?;
    }
    Ok(s)
}

/// Reads the settings file.
fn load(path: Option<&Path>) -> Result<SizeLoopSettings> {
    let Some(p) = path else { return settings(None) };
    let text =
        std::fs::read_to_string(p).with_context(|| format!("settings file {}", p.display()))?;
    if text.trim().is_empty() {
        anyhow::bail!(
            "settings file {}: empty (write a [size_loop] table, docs/size_loop.md)",
            p.display()
        );
    }
    let file: File =
        toml::from_str(&text).map_err(|e| anyhow::anyhow!("settings file {}: {e}", p.display()))?;
    settings(file.size_loop).map_err(|e| anyhow::anyhow!("settings file {}: {e}", p.display()))
}

/// A scratch file, removed when dropped.
struct ScratchFile(PathBuf);

impl Drop for ScratchFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// One line of counts.
fn counts_line(name: &str, c: &LoopCounts) -> String {
    format!(
        "{name}: {}/{} out of tolerance, {} alarms, {} stops, {} re-measures, {} faulted touches ({} read unflagged)",
        c.out_of_tolerance, c.parts, c.alarms, c.stops, c.remeasures, c.faulted_touches, c.unflagged_faulted_touches
    )
}

/// The JSON file's content.
#[derive(serde::Serialize)]
struct Json<'a> {
    parts: usize,
    seed: u64,
    nominal_mm: f64,
    tolerance_mm: f64,
    feedback_pct: f64,
    dead_zone_mm: f64,
    remeasure: bool,
    upper_tolerance_mm: Option<f64>,
    max_correction_mm: Option<f64>,
    counts: LoopCounts,
    today: LoopCounts,
    rows: &'a [PartRow],
}

/// Runs `tooltouch size-loop`.
pub fn run(args: Args) -> Result<ExitCode> {
    let s = load(args.config.as_deref())?;
    let force = ForceSettings::default()
        .validate()
        .map_err(anyhow::Error::msg)?;
    let d = MeasureSettings::default();
    let measure = MeasureSettings {
        checks: MeasureChecks {
            pulse_tolerance: size_loop::servo_pulse_tolerance(
                d.pulses_per_rev,
                s.rpm,
                f64::from(force.settings().sample_hz),
            ),
            ..MeasureChecks::default()
        },
        ..d
    }
    .validate()
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    let r = size_loop::run(&s, &measure, &force);
    let c = counts(&r, &golden_readings(&s, &r, &measure, &force));
    let today_settings = SizeLoopSettings {
        rules: LoopRules::TODAY,
        ..s
    };
    let today = size_loop::run(&today_settings, &measure, &force);
    let t = counts(
        &today,
        &golden_readings(&today_settings, &today, &measure, &force),
    );
    for line in size_loop::table(&s, &r) {
        outln!("{line}");
    }
    outln!("{}", counts_line("this loop", &c));
    outln!(
        "{}",
        counts_line("today's loop (no re-measure, no limits), same parts", &t)
    );
    outln!(
        "uncorrected: {}/{} out of tolerance",
        c.uncorrected_out_of_tolerance,
        c.parts
    );
    if let Some(path) = &args.json {
        let json = Json {
            parts: s.parts,
            seed: s.seed,
            nominal_mm: s.nominal_mm,
            tolerance_mm: s.tolerance_mm,
            feedback_pct: s.feedback_pct,
            dead_zone_mm: s.dead_zone_mm,
            remeasure: s.rules.remeasure,
            upper_tolerance_mm: s.rules.upper_tolerance_mm,
            max_correction_mm: s.rules.max_correction_mm,
            counts: c,
            today: t,
            rows: &r.rows,
        };
        let mut text = serde_json::to_string_pretty(&json)?;
        text.push('\n');
        tooltouch_vectors::output::write_file(path, text.as_bytes())
            .with_context(|| format!("--json {}", path.display()))?;
    }
    if let Some(path) = &args.plot {
        // Drawn into a scratch file, then written whole (the SVG backend writes as it goes
        // and would not report a folder it cannot write to).
        let scratch = ScratchFile(
            std::env::temp_dir().join(format!("tooltouch-size-loop-{}.svg", std::process::id())),
        );
        let col = |f: fn(&PartRow) -> f64| r.rows.iter().map(f).collect::<Vec<_>>();
        tooltouch_plot::size_loop::size_loop(
            &scratch.0,
            s.nominal_mm,
            s.tolerance_mm,
            &col(|p| p.uncorrected_mm),
            &col(|p| p.corrected_mm),
            &col(|p| p.measured_mm),
        )
        .with_context(|| format!("--plot {}", path.display()))?;
        let svg = std::fs::read(&scratch.0).context("reading the drawn plot back")?;
        tooltouch_vectors::output::write_file(path, &svg)
            .with_context(|| format!("--plot {}", path.display()))?;
    }
    Ok(ExitCode::SUCCESS)
}
