//! `tooltouch coverage`: which of the front end's behaviours a stimulus makes the golden
//! model go through, as a table of bins in the domain's words, as JSON
//! ([`tooltouch_vectors::coverage`]) and as cocotb-coverage's YAML
//! ([`tooltouch_vectors::cocotb_coverage`]; docs/vectors.md, "Coverage").

use std::path::PathBuf;
use std::process::ExitCode;
use tooltouch_settings::load::{golden_set_of, load_settings};

/// Arguments of `tooltouch coverage`.
#[derive(clap::Args, Debug)]
#[command(after_help = super::vectors::CLOCK_RULE)]
pub struct Args {
    /// The stimulus, any input `tooltouch vectors` reads: a VCD of the six pins (a golden
    /// VCD), an input event stream (.ttv), run-length pins (stim.hex).
    #[arg(long)]
    pub stimulus: PathBuf,
    /// Settings TOML, as `tooltouch vectors` takes it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// FPGA clock, Hz (see the clock rule below).
    #[arg(long)]
    pub clock_hz: Option<u32>,
    /// Also write the bins as JSON to FILE.
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub json: Option<PathBuf>,
    /// Also write the bins as cocotb-coverage's YAML export to FILE, for its
    /// `merge_coverage` with a bench's own covergroups (docs/vectors.md).
    #[arg(long, value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub cocotb_coverage: Option<PathBuf>,
}

/// Runs `tooltouch coverage`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    for path in args.json.iter().chain(&args.cocotb_coverage) {
        tooltouch_vectors::output::check_output_file(path)?;
    }
    let settings = load_settings(args.config.as_deref(), args.clock_hz)?;
    let (set, _) = golden_set_of(&args.stimulus, &settings, args.config.is_some())?;
    let Some(cycle) = &set.cycle else {
        anyhow::bail!(
            "{}: no pins to cover: {}",
            args.stimulus.display(),
            set.no_cycle_level
                .as_deref()
                .unwrap_or("no measurement events")
        );
    };
    let cov = tooltouch_vectors::coverage::coverage(&cycle.stimulus, &cycle.config);
    let s = cycle.config.settings();
    outln!(
        "coverage of {}: method {:?}, {:?} contact rule, {:?}",
        args.stimulus.display(),
        s.method,
        s.contact_rule,
        s.charge_law
    );
    print!("{}", cov.table());
    if let Some(path) = &args.json {
        let mut text = serde_json::to_string_pretty(&cov.json())?;
        text.push('\n');
        tooltouch_vectors::output::write_file(path, text.as_bytes())?;
    }
    if let Some(path) = &args.cocotb_coverage {
        let text = tooltouch_vectors::cocotb_coverage::yaml(&cov, cycle.config.hash());
        tooltouch_vectors::output::write_file(path, text.as_bytes())?;
    }
    Ok(ExitCode::SUCCESS)
}
