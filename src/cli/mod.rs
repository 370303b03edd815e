//! Command-line interface: one module per subcommand.
//!
//! Every subcommand exits alike (docs/cli.md): 0 success; 1 a verdict that is not a pass
//! (a `check` mismatch, a `measure` run in which some measurement did not decide or faulted); 2 bad
//! input (a usage error, a bad value or file, refused work, an output folder that cannot be
//! written), each message naming the file, the flag or key, the value and what is allowed;
//! 130 stopped by a signal (no partial output left). Standard output goes through
//! [`outln!`]: a reader that went away (`tooltouch control | head -1`) ends the printing
//! quietly instead of panicking.

/// Writes one formatted piece to standard output. After a write error (the reader closed
/// the pipe) the rest of the run's printing is dropped; the run itself goes on, so its
/// files are still written.
pub fn write_stdout(args: std::fmt::Arguments) {
    use std::io::Write;
    use std::sync::atomic::{AtomicBool, Ordering};
    static CLOSED: AtomicBool = AtomicBool::new(false);
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("warning: standard output: {e}; printing stops here");
        }
    }
}

/// `println!` through [`write_stdout`].
macro_rules! outln {
    () => {
        $crate::cli::write_stdout(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` through [`write_stdout`].
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::write_stdout(format_args!($($arg)*))
    };
}

pub mod bench;
pub mod budget;
pub mod calibrate;
pub mod check;
pub mod control;
pub mod cosim;
pub mod coverage;
pub mod faults;
pub mod formal;
pub mod hdl;
pub mod measure;
pub mod ranges;
pub mod run_settings;
pub mod run_tables;
pub mod setting_flags;
pub mod size_loop;
pub mod tune;
pub mod vectors;
pub mod wear;

use tooltouch_vectors::output;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Exit code of a verdict that is not a pass: a mismatch, an undecided measurement.
pub const NOT_PASSED: u8 = 1;
/// Exit code of bad input: usage, values, files, refused work, unwritable output.
pub const BAD_INPUT: u8 = 2;

/// Simulate in-process measurement and force control on a CNC lathe with the golden
/// fixed-point model; write and check test vectors.
#[derive(Parser, Debug)]
#[command(
    name = "tooltouch",
    version,
    about,
    after_help = "Exit codes (every subcommand): 0 success; 1 a check mismatch or an undecided \
measurement; 2 bad input (usage, values, files, refused work, unwritable output); 130 \
interrupted (no partial output left). See docs/cli.md."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Simulate in-process diameter measurements on a lathe with the golden model.
    Measure(measure::Args),
    /// Predict the decided diameter's bias and scatter from the settings (the error
    /// budget), optionally beside a simulation.
    Budget(budget::Args),
    /// The fault campaign: how often a faulted lathe gets a wrong diameter through as a
    /// good one (fault kind × level × method, each measurement classified).
    Faults(faults::Args),
    /// Measure a reference part of known diameter with each method and contact rule and
    /// write the offsets as a calibration file (`measure --calibration` applies it).
    Calibrate(calibrate::Args),
    /// Compare a device-under-test trace with the golden expected trace.
    Check(check::Args),
    /// Compute the golden response to your own stimulus (VCD of the pins, event stream,
    /// run-length pins) as VCD, testbench vectors and firmware streams.
    Vectors(vectors::Args),
    /// Report which of the front end's behaviours a stimulus exercises (functional
    /// coverage, bins in the domain's words).
    Coverage(coverage::Args),
    /// Run the force-control depth-step scenario.
    Control(control::Args),
    /// Run the tool-wear monitoring scenario.
    Wear(wear::Args),
    /// Run the measure-then-correct size loop with faulted touches.
    SizeLoop(size_loop::Args),
    /// Write the Verilog of the FPGA front end.
    Hdl(hdl::Args),
    /// Fixed-point tuning sweeps.
    Tune(tune::Args),
    /// Observed ranges, saturations, wraps and headroom of every fixed-point register.
    Ranges(ranges::Args),
    /// Run the QEMU firmware image on a stimulus and check its trace; write the
    /// configuration file a firmware build bakes in.
    Cosim(cosim::Args),
    /// The two-board bench: the decision lines the controller board must log while the
    /// lathe player board replays a stream, collected over probe-rs and checked.
    Bench(bench::Args),
    /// Prove your own `tt_frontend` RTL equal to the reference derived from the golden
    /// model, for every input sequence (exit 0 proven, 1 not equal, 2 bad input, 3
    /// undecided).
    Formal(formal::Args),
}

/// Lets a value that starts with `-` reach the flag's own parser (`--rpm -inf`, `--seed
/// -1`, `--glitch-cycles -5..=5`), so the error names the flag instead of an "unexpected
/// argument `-i`". Every argument that takes a value other than a path or a named choice.
fn hyphen_values(c: clap::Command) -> clap::Command {
    c.mut_args(|a| {
        let path = a.get_value_parser().type_id() == std::any::TypeId::of::<std::path::PathBuf>();
        if a.get_action().takes_values() && !path && a.get_possible_values().is_empty() {
            a.allow_hyphen_values(true)
        } else {
            a
        }
    })
    .mut_subcommands(hyphen_values)
}

impl Cli {
    /// The command line's definition as parsed: the derived one with
    /// [`hyphen_values`] applied.
    pub fn definition() -> clap::Command {
        use clap::CommandFactory;
        hyphen_values(Cli::command())
    }

    /// Whether the subcommand `sub` has the long flag `--long`.
    pub fn command_has_flag(sub: &str, long: &str) -> bool {
        use clap::CommandFactory;
        Cli::command()
            .find_subcommand(sub)
            .is_some_and(|c| c.get_arguments().any(|a| a.get_long() == Some(long)))
    }
}

/// Installs the handler of Ctrl-C, SIGTERM and SIGHUP: it removes every staging folder
/// still open (the output folders are then as they were) and exits with
/// [`output::INTERRUPTED`]. A second call changes nothing.
fn remove_staging_on_signal() {
    // An error here means a handler is already installed (tests call `cli::main` twice).
    let _ = ctrlc::set_handler(|| {
        output::remove_open_staging();
        eprintln!("interrupted: no output written");
        std::process::exit(output::INTERRUPTED);
    });
}

/// Parses the arguments, runs the subcommand, and reports an error with its context.
pub fn main() -> ExitCode {
    use clap::FromArgMatches;
    let cli = Cli::from_arg_matches(&Cli::definition().get_matches()).unwrap_or_else(|e| e.exit());
    remove_staging_on_signal();
    let result = match cli.command {
        Command::Measure(args) => measure::run(args),
        Command::Budget(args) => budget::run(args),
        Command::Calibrate(args) => calibrate::run(args),
        Command::Faults(args) => faults::run(args),
        Command::Check(args) => check::run(args),
        Command::Vectors(args) => vectors::run(args),
        Command::Coverage(args) => coverage::run(args),
        Command::Control(args) => control::run(args),
        Command::Wear(args) => wear::run(args),
        Command::SizeLoop(args) => size_loop::run(args),
        Command::Hdl(args) => hdl::run(args),
        Command::Tune(args) => tune::run(args),
        Command::Ranges(args) => ranges::run(args),
        Command::Cosim(args) => cosim::run(args),
        Command::Formal(args) => formal::run(args),
        Command::Bench(args) => bench::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(BAD_INPUT)
        }
    }
}
