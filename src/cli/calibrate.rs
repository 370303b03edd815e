//! `tooltouch calibrate`: the calibration cycle on a reference part of known diameter
//! (docs/accuracy.md "Calibration on a reference part"): measures it `--repeats` times with
//! each method and contact rule on the machine of the settings, writes the offsets (per
//! method, contact rule and feed, with the configuration's hash) as a calibration file, and
//! prints the residual bias on the settings' own workpiece at the calibrated conditions and
//! at other feeds and speeds. `measure --calibration FILE` applies it. Parsing and printing
//! only: the work is `tooltouch_metrology::calibration`.

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tooltouch_metrology::calibration::{calibrate, residuals, CalibrationError, ReferencePart};
use tooltouch_metrology::Variant;
use tooltouch_plant::lathe::{CycleSettings, LatheScenario};
use tooltouch_plant::measurement_cycle::check_run_size;
use tooltouch_settings::Settings;
use tooltouch_vectors::output::write_file;

/// Arguments of `tooltouch calibrate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Settings file (the same TOML as `measure --config`): the machine and the cycle.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The reference part's known diameter, mm.
    #[arg(long, value_name = "MM")]
    pub reference_mm: f64,
    /// The reference part's roughness, µm 1σ (a ground ring).
    #[arg(long, value_name = "UM", default_value_t = 0.05)]
    pub reference_roughness_um: f64,
    /// The reference was cut in this set-up and measured off the machine (it carries the
    /// workpiece's form error); without it the reference is round (a ring or ground
    /// cylinder).
    #[arg(long)]
    pub reference_as_cut: bool,
    /// Measurements of the reference per method and contact rule (m).
    #[arg(long, value_name = "M", default_value_t = 20,
          value_parser = clap::value_parser!(u32).range(2..=1000))]
    pub repeats: u32,
    /// The calibration file to write (JSON), whole or not at all.
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub out: PathBuf,
    /// Also print the residual bias on the settings' workpiece (at the calibrated
    /// conditions, at half and twice the feed, at 600 and 1000 rpm), from this many
    /// simulated measurements each (0: not).
    #[arg(long, value_name = "N", default_value_t = 0,
          value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub residuals: u32,
    /// The settings' flags (as `measure`).
    #[command(flatten)]
    pub flags: super::setting_flags::SettingFlags,
}

/// Runs `tooltouch calibrate`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let settings: Settings = args.flags.settings(args.config.as_deref())?;
    let (config, machine) = settings
        .resolve()
        .map_err(|e| args.flags.explain(e, args.config.as_deref()))?;
    for n in [args.repeats, args.residuals] {
        check_run_size(
            &LatheScenario {
                cycle: CycleSettings {
                    repeats: n.max(1),
                    ..machine.cycle
                },
                ..machine.clone()
            },
            &config,
        )?;
    }
    let reference = ReferencePart {
        diameter_mm: args.reference_mm,
        roughness_um: args.reference_roughness_um,
        as_cut: args.reference_as_cut,
    };
    let calibration =
        calibrate(&settings.measure, &machine, &reference, args.repeats).map_err(|e| match e {
            CalibrationError::Reference { field, .. } => {
                let flag = if field == "diameter_mm" {
                    "--reference-mm"
                } else {
                    "--reference-roughness-um"
                };
                anyhow::anyhow!("{flag}: {e}")
            }
            e => e.into(),
        })?;
    outln!(
        "calibration on {} reference of {} mm (roughness {} µm), {} measurements per variant, \
         f_r = {} mm/rev, {} rpm",
        if reference.as_cut {
            "an as-cut"
        } else {
            "a round"
        },
        reference.diameter_mm,
        reference.roughness_um,
        args.repeats,
        machine.feed_mm_per_rev,
        machine.rpm
    );
    outln!(
        "  variant            offset µm (Ø)   ± standard error   1σ of one   counts   measure hash"
    );
    for e in &calibration.entries {
        outln!(
            "  {:<18} {:>+10.2}      ± {:.2}             {:.2}     {:>+6}   {}",
            Variant {
                method: e.method,
                rule: e.contact_rule
            }
            .name(),
            e.offset_um,
            e.standard_error_um,
            e.sigma_um,
            e.offset_counts,
            e.measure_hash
        );
    }
    let json = serde_json::to_vec_pretty(&calibration).context("encoding the calibration")?;
    write_file(&args.out, &json)?;
    outln!("wrote {}", args.out.display());
    if args.residuals > 0 {
        let f = machine.feed_mm_per_rev;
        let rows = residuals(
            &settings.measure,
            &machine,
            &calibration,
            args.residuals,
            &[f / 2.0, f * 2.0],
            &[600.0, 1000.0],
        )?;
        outln!(
            "residual bias on the workpiece after calibration (µm on the diameter; raw and \
             residual vs the true mean, and the residual vs the true largest diameter):"
        );
        outln!(
            "  variant            condition              raw      offset   residual ± s.e.   vs largest"
        );
        for r in &rows {
            outln!(
                "  {:<18} {:<20} {:>+7.2}   {:>+7.2}   {:>+7.2} ± {:.2}      {:>+7.2}",
                r.variant,
                r.condition,
                r.raw_bias_um,
                r.offset_um,
                r.residual_um,
                r.standard_error_um,
                r.raw_bias_vs_largest_um - r.offset_um
            );
        }
    }
    outln!("calibrated in {:.2} s", started.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}
