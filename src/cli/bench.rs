//! `tooltouch bench`: the two-board bench from the command line (docs/firmware.md, "The
//! bench"). The lathe player board replays an event stream on its pins; the controller
//! board logs a decision line at each change of "register now"; these commands compare
//! those lines with the golden model's for the same stream ([`tooltouch_firmware_runner::bench`]).
//!
//! - `bench expect` writes the decision lines the controller must log for a stream.
//! - `bench check` compares a log saved earlier (probe-rs's output) with them.
//! - `bench collect` attaches probe-rs to the running controller, collects its log until
//!   every expected decision arrived or the timeout passed, and compares.
//!
//! The controller's configuration is the one its image was built with (`--config`, and
//! `--calibration` when one was baked, as `cosim config` and `cargo xtask firmware` take
//! them): a stream made with another measurement configuration is refused, since the
//! controller decides with its own baked configuration, not the stream's.
//!
//! Exit codes: 0 every decision line equal; 1 a line differs, is missing or is extra (a
//! timeout counts as missing lines); 2 bad input (a stream that is not a playable event
//! stream or was made with another configuration, an unreadable file, an ELF that is not
//! the controller's image, a missing probe-rs).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;
use tooltouch_firmware_runner::bench;
use tooltouch_model::wire::Header;
use tooltouch_settings::firmware_config::FirmwareConfig;

/// Arguments of `tooltouch bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    /// Write the decision lines the controller must log while the player replays a stream
    /// (the golden model's, one per line).
    Expect(ExpectArgs),
    /// Compare a controller log saved earlier (`probe-rs attach --log-format {s}`'s
    /// output) with the golden decision lines (exit 0 equal, 1 different, 2 bad input).
    #[command(after_help = EXIT_CODES)]
    Check(CheckArgs),
    /// Attach probe-rs to the running controller, collect its log while the player plays,
    /// and compare its decision lines with the golden model's (exit 0 equal, 1 different
    /// or missing, 2 bad input).
    #[command(after_help = EXIT_CODES)]
    Collect(CollectArgs),
}

const EXIT_CODES: &str = "Exit codes: 0 every decision line equal to the golden model's; 1 a \
line differs, is missing (a controller quiet until the timeout) or is extra; 2 bad input (a \
stream that is not a playable event stream or was made with another configuration, an \
unreadable or empty file, an ELF that is not the controller's image, a missing probe-rs).";

/// The stream and the controller's configuration, common to every `bench` command.
#[derive(clap::Args, Debug)]
struct StreamArgs {
    /// The event stream the player plays (.ttv: `tooltouch measure`'s events.ttv, a
    /// `tooltouch vectors` stream, the demo firmware/tooltouch-events.bin): the file the
    /// player image was built with (`TOOLTOUCH_PLAYER_STREAM`).
    #[arg(long)]
    stream: PathBuf,
    /// Settings TOML the controller image was built with (`cargo xtask firmware
    /// --config`; default: the defaults). The stream must carry its measurement
    /// configuration.
    #[arg(long)]
    config: Option<PathBuf>,
    /// The calibration file baked into the controller image (`cargo xtask firmware
    /// --calibration`): the expected lines carry its offset.
    #[arg(long, value_name = "FILE")]
    calibration: Option<PathBuf>,
}

/// Arguments of `tooltouch bench expect`.
#[derive(clap::Args, Debug)]
struct ExpectArgs {
    #[command(flatten)]
    stream: StreamArgs,
    /// The file to write the lines to (whole or not at all: a failed run leaves an
    /// existing file as it was).
    // `FilePath`: a file this command writes (the hostile-input test reads the hint).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    out: PathBuf,
}

/// Arguments of `tooltouch bench check`.
#[derive(clap::Args, Debug)]
struct CheckArgs {
    #[command(flatten)]
    stream: StreamArgs,
    /// The controller's log: one decoded defmt message per line, as `probe-rs attach
    /// --log-format {s}` prints it (or `bench collect --out` saved it).
    #[arg(long)]
    log: PathBuf,
}

/// Arguments of `tooltouch bench collect`.
#[derive(clap::Args, Debug)]
struct CollectArgs {
    #[command(flatten)]
    stream: StreamArgs,
    /// The controller's image as flashed (the Nucleo ELF, `cargo nucleo-build`): probe-rs
    /// decodes the defmt log with its table.
    #[arg(long)]
    elf: PathBuf,
    /// The controller's probe when two are plugged in (`probe-rs list`: VID:PID:SERIAL).
    #[arg(long, value_name = "SELECTOR")]
    probe: Option<String>,
    /// The probe-rs program (a name on PATH or a path).
    #[arg(long, value_name = "PROGRAM", default_value = "probe-rs")]
    probe_rs: String,
    /// Seconds to wait for every expected decision line (press B1 on the player in that
    /// time), 1..=86400.
    #[arg(long, value_name = "SECONDS", default_value_t = 120,
          value_parser = clap::value_parser!(u32).range(1..=86_400))]
    timeout_s: u32,
    /// Also write the whole collected log here (for `bench check` later). Its folder is
    /// checked before probe-rs starts; a run that fails before collecting leaves an
    /// existing file as it was.
    // `FilePath`: a file this command writes (the hostile-input test reads the hint).
    #[arg(long, value_hint = clap::ValueHint::FilePath)]
    out: Option<PathBuf>,
}

/// Runs `tooltouch bench`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.command {
        Command::Expect(a) => {
            let want = expected(&a.stream)?;
            tooltouch_vectors::output::write_file(&a.out, lines_text(&want).as_bytes())?;
            outln!(
                "{}: {} decision lines expected; wrote {}",
                a.stream.stream.display(),
                want.len(),
                a.out.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Check(a) => {
            let want = expected(&a.stream)?;
            let bytes = read_bounded(&a.log, "--log", MAX_LOG_BYTES, "a controller log may have")?;
            let text = String::from_utf8(bytes).map_err(|e| {
                anyhow::anyhow!(
                    "--log {}: byte {} is not UTF-8 text; a controller log is probe-rs's \
                     `--log-format {{s}}` output",
                    a.log.display(),
                    e.utf8_error().valid_up_to()
                )
            })?;
            if text.trim().is_empty() {
                anyhow::bail!(
                    "controller log {}: holds no line (probe-rs printed nothing?)",
                    a.log.display()
                );
            }
            let log: Vec<String> = text.lines().map(str::to_string).collect();
            Ok(verdict(&want, &log, &a.log.display().to_string()))
        }
        Command::Collect(a) => collect(&a),
    }
}

fn collect(a: &CollectArgs) -> anyhow::Result<ExitCode> {
    let want = expected(&a.stream)?;
    if let Some(path) = &a.out {
        tooltouch_vectors::output::check_output_file(path)?;
    }
    check_controller_elf(&a.elf)?;
    outln!(
        "attaching {} to the controller ({}); press B1 on the player within {} s",
        a.probe_rs,
        a.elf.display(),
        a.timeout_s
    );
    let log = bench::collect(
        &a.probe_rs,
        &a.elf,
        a.probe.as_deref(),
        want.len(),
        Duration::from_secs(u64::from(a.timeout_s)),
    )?;
    if let Some(path) = &a.out {
        tooltouch_vectors::output::write_file(path, lines_text(&log).as_bytes())?;
    }
    Ok(verdict(&want, &log, "the controller's log"))
}

/// The golden decision lines for the stream, for the controller's configuration.
fn expected(a: &StreamArgs) -> anyhow::Result<Vec<String>> {
    let mut config = FirmwareConfig::load(a.config.as_deref())?;
    if let Some(path) = &a.calibration {
        config = super::cosim::with_calibration(config, a.config.as_deref(), path)?;
    }
    let stream = read_stream(&a.stream)?;
    let name = a.stream.display();
    let header = Header::decode(&stream).map_err(|e| anyhow::anyhow!("--stream {name}: {e}"))?;
    let controller = config.measure.hash();
    if header.measure_hash != controller {
        anyhow::bail!(
            "--stream {name}: made with measure_hash={:016x}, the controller's configuration \
             ({}) has measure_hash={controller:016x}: the controller decides with its own \
             baked configuration, so build it with the stream's settings (`cargo xtask \
             firmware --config SETTINGS`) and give the same `--config`",
            header.measure_hash,
            a.config.as_ref().map_or_else(
                || "the defaults".to_string(),
                |p| format!("--config {}", p.display())
            ),
        );
    }
    bench::expected_lines(&stream, config.calibration.as_ref())
        .map_err(|e| anyhow::anyhow!("--stream {name}: {e}"))
}

/// The largest controller log `bench check` reads: 64 MiB (a day of decisions).
const MAX_LOG_BYTES: u64 = 64 << 20;
/// The largest controller image `bench collect` reads: 64 MiB (the Nucleo's ELF with its
/// debug information is under 2 MiB).
const MAX_ELF_BYTES: u64 = 64 << 20;

/// The bytes of the file `path` given to `flag`, refused over `limit` bytes (`limit_is`:
/// what the limit is; checked before it is read, and bounded while reading), or when it
/// is a folder.
fn read_bounded(path: &Path, flag: &str, limit: u64, limit_is: &str) -> anyhow::Result<Vec<u8>> {
    use std::io::Read;
    let name = path.display();
    let file = std::fs::File::open(path).map_err(|e| anyhow::anyhow!("{flag} {name}: {e}"))?;
    let meta = file
        .metadata()
        .map_err(|e| anyhow::anyhow!("{flag} {name}: {e}"))?;
    if meta.is_dir() {
        anyhow::bail!("{flag} {name}: is a folder, not a file");
    }
    let too_large =
        |len: u64| anyhow::anyhow!("{flag} {name}: {len} bytes, more than the {limit} {limit_is}");
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| anyhow::anyhow!("{flag} {name}: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// The stream's bytes, refused past what the player's flash holds.
fn read_stream(path: &Path) -> anyhow::Result<Vec<u8>> {
    read_bounded(
        path,
        "--stream",
        bench::MAX_PLAYER_STREAM_BYTES,
        "the player's flash holds",
    )
}

/// Refuses a file that is not an ELF or has no defmt table (probe-rs could not decode
/// the controller's log with it).
fn check_controller_elf(path: &Path) -> anyhow::Result<()> {
    let name = path.display();
    let bytes = read_bounded(path, "--elf", MAX_ELF_BYTES, "a controller image may have")?;
    if !bytes.starts_with(b"\x7fELF") {
        anyhow::bail!("{name}: not an ELF image");
    }
    bench::check_defmt_table(&bytes).map_err(|e| anyhow::anyhow!("--elf {name}: {e}"))
}

/// Prints the comparison of `log`'s decision lines with `want` and returns its exit code.
fn verdict(want: &[String], log: &[String], name: &str) -> ExitCode {
    let got = bench::decision_lines(log);
    match bench::first_difference(want, &got) {
        None => {
            outln!(
                "{} decision lines in {name}, every one equal to the golden model's",
                got.len()
            );
            ExitCode::SUCCESS
        }
        Some(d) => {
            outln!("MISMATCH: {name}: {d}");
            ExitCode::from(super::NOT_PASSED)
        }
    }
}

/// `lines`, one per line.
fn lines_text(lines: &[String]) -> String {
    lines.iter().map(|l| format!("{l}\n")).collect()
}
