//! `tooltouch vectors`: the golden response to the user's own stimulus — a VCD of the six
//! input pins (a bench recording, a simulation), an input event stream, or run-length pins
//! — as every file a device under test is checked with ([`GoldenSet`](tooltouch_vectors::golden_set::GoldenSet)).
//!
//! The settings file is the one `tooltouch measure` and `tooltouch hdl` take
//! ([`load_settings`]).

use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_settings::load::{golden_set_of, load_settings};
use tooltouch_vectors::golden_set;
use tooltouch_vectors::output::OutputFolder;

/// The clock rule, shown in `--help` of `vectors` and `hdl`.
pub const CLOCK_RULE: &str = "\
Clock: the period P = 1e9 / clock_hz ns comes from --clock-hz, else the settings file's \
[lathe] clock_hz, else the stimulus file's own clock (a golden VCD's `clock_hz` comment, an \
event stream's tick rate), else 50 MHz; a stated clock that differs from the file's own is \
an error. A VCD's clock k takes the pins' values at time k*P (the last change at or \
before it); its clocks run from time 0 to its last time.";

/// Arguments of `tooltouch vectors`.
#[derive(clap::Args, Debug)]
#[command(after_help = CLOCK_RULE)]
pub struct Args {
    /// The stimulus: a VCD holding the six input pins (arm contact index fes scale_a
    /// scale_b: in a scope `inputs`, or named `pin_<name>`, or the shallowest outside a
    /// scope `outputs`), an input event stream (.ttv: measurement and/or force events), or
    /// run-length pins (the testbench's stim.hex).
    #[arg(long, required_unless_present = "stress", conflicts_with = "stress")]
    pub stimulus: Option<PathBuf>,
    /// Instead of a stimulus file: the stress stimulus of the configuration for this seed,
    /// directed plus constrained-random pins aimed at the behaviours `tooltouch coverage`
    /// lists (docs/vectors.md, "Stress stimuli"). Check a design with its golden.vcd
    /// (`hdl --vectors golden.vcd`): glitches shorter than the filter have no event in
    /// events.ttv.
    #[arg(long, value_name = "SEED")]
    pub stress: Option<u64>,
    /// Clocks of the stress stimulus's constrained-random tail.
    #[arg(
        long,
        value_name = "CLOCKS",
        default_value_t = 20_000,
        requires = "stress"
    )]
    pub stress_random: u64,
    /// Settings TOML, as `tooltouch measure` takes it: the golden model's `[measure]`
    /// table (or its fields at top level) and `[lathe] clock_hz`; other tables are errors.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// FPGA clock, Hz (see the clock rule below).
    #[arg(long)]
    pub clock_hz: Option<u32>,
    /// Output folder (created): golden.vcd, stim.hex, expect.hex, events.ttv,
    /// expected_outputs.ttv, summary.json. A run replaces this command's files in the
    /// folder (and removes those it did not write this time, e.g. golden.vcd for a
    /// force-only stream); other files are left alone; a failed run leaves the folder as it
    /// was.
    #[arg(long)]
    pub out: PathBuf,
    /// Format of the golden trace: `vcd` writes golden.vcd, `fst` golden.fst (the same
    /// signals and times; `tooltouch check` reads either).
    #[arg(long, value_enum, default_value = "vcd")]
    pub golden_format: GoldenFormatArg,
}

/// The golden trace's format (`--golden-format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GoldenFormatArg {
    /// Value change dump (text).
    Vcd,
    /// GTKWave's FST (compressed blocks; Verilator's `--trace-fst` format).
    Fst,
}

impl From<GoldenFormatArg> for golden_set::GoldenFormat {
    fn from(f: GoldenFormatArg) -> Self {
        match f {
            GoldenFormatArg::Vcd => golden_set::GoldenFormat::Vcd,
            GoldenFormatArg::Fst => golden_set::GoldenFormat::Fst,
        }
    }
}

/// Runs `tooltouch vectors`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let settings = load_settings(args.config.as_deref(), args.clock_hz)?;
    let (set, format, file) = match (&args.stimulus, args.stress) {
        (Some(path), _) => {
            let (set, format) = golden_set_of(path, &settings, args.config.is_some())?;
            (set, format, path.display().to_string())
        }
        (None, Some(seed)) => {
            let size = tooltouch_plant::stress::StressSize {
                random_cycles: args.stress_random,
                ..Default::default()
            };
            let clock_hz = settings.clock.as_ref().map_or(50_000_000, |c| c.hz);
            let stimulus =
                tooltouch_plant::stress::stress_stimulus(&settings.config, seed, clock_hz, &size);
            (
                golden_set::GoldenSet::from_pins(&settings.config, stimulus),
                "stress",
                format!("stress seed {seed}"),
            )
        }
        (None, None) => anyhow::bail!("give --stimulus FILE or --stress SEED"),
    };
    let out = OutputFolder::create(&args.out, golden_set::FILES)?;
    let source = serde_json::json!({
        "file": file,
        "format": format,
        "settings": args.config.as_ref().map(|p| p.display().to_string()),
    });
    let summary = set.write_as(&out, source, args.golden_format.into())?;
    let dir = out.dir().to_path_buf();
    let files = out.commit()?;
    let hashes = [
        ("measure_hash", "configuration"),
        ("force_hash", "force configuration"),
    ]
    .iter()
    .filter_map(|(k, what)| summary[k].as_str().map(|h| format!("{what} {h}")))
    .collect::<Vec<_>>()
    .join(", ");
    outln!(
        "{hashes}: {} events, {} force events, decisions: {}; wrote {}",
        summary["events"],
        summary["force_events"],
        summary["decisions"].as_array().map_or(0, Vec::len),
        dir.display()
    );
    if let Some(why) = &set.no_cycle_level {
        outln!("  no golden VCD nor testbench vectors: {why}");
    }
    if let Some(c) = &set.cycle {
        outln!(
            "  {} clocks at {} Hz in {} segments",
            c.stimulus.total_cycles(),
            c.stimulus.clock_hz,
            c.stimulus.segments.len()
        );
        match &c.hex {
            Ok(v) => {
                outln!(
                    "  testbench vectors: {} stim.hex words, {} expect.hex words",
                    v.stim_words,
                    v.expect_words
                );
                if v.stim_words.max(v.expect_words) > tooltouch_vectors::hex::DEFAULT_DEPTH {
                    outln!(
                        "  (more than a default testbench holds: `tooltouch hdl --vectors {}` sizes it, \
                         or give `--stim-depth {} --expect-depth {}`)",
                        file,
                        v.stim_words,
                        v.expect_words
                    );
                }
            }
            Err(why) => outln!("  no testbench vectors: {why}"),
        }
    }
    for f in files {
        outln!("  {}", f.display());
    }
    Ok(ExitCode::SUCCESS)
}
