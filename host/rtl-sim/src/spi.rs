//! The SPI design (`tooltouch_hdl_gen::generate_spi`, board top `tt_fpga_spi`) under Icarus,
//! driven bit by bit: the bench `verilog/tooltouch_spi_bench.v` reads a command file
//! ([`SpiCommand`]: hold the pins for some clocks, one SPI frame of any length at any SCK
//! half-period, print the output pins) and prints what the master saw ([`SpiReply`]). The
//! tests (`tests/spi.rs`) write the commands from a stimulus and compare the replies with
//! the golden model.

use super::runner::find_tool;
use super::{io_err, write_design, HdlError, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use tooltouch_hdl_gen::spi::{SPI_FRAME_BITS, SPI_WRITE};
use tooltouch_hdl_gen::{generate_spi, Options};
use tooltouch_model::MeasureConfig;
use tooltouch_plant::stimulus::Stimulus;

/// The bench's source (module `tooltouch_spi_bench`).
pub const SPI_BENCH: &str = include_str!("../verilog/tooltouch_spi_bench.v");

/// One step of the bench.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpiCommand {
    /// Hold the six input pins (bit 0 arm … bit 5 scale B) for `clocks` FPGA clocks.
    Hold {
        /// Clocks, at least 1.
        clocks: u64,
        /// Pin levels.
        pins: u8,
    },
    /// One SPI mode-0 frame: `bits` bits of `cmd` then `data`, MSB first, SCK high and low
    /// for `half` FPGA clocks each.
    Frame {
        /// Command byte (bit 7: write; bits 6..0: address).
        cmd: u8,
        /// Data word.
        data: u32,
        /// Bits clocked before CS rises (40 for a complete frame).
        bits: u32,
        /// SCK half-period, FPGA clocks.
        half: u32,
    },
    /// Print the register-now, interrupt and fault pins.
    Pins,
}

impl SpiCommand {
    /// A complete read frame of `addr` at SCK = f_clk / (2 `half`).
    pub fn read(addr: u8, half: u32) -> Self {
        SpiCommand::Frame {
            cmd: addr & !SPI_WRITE,
            data: 0,
            bits: SPI_FRAME_BITS,
            half,
        }
    }

    /// A complete write frame of `data` to `addr`.
    pub fn write(addr: u8, data: u32, half: u32) -> Self {
        SpiCommand::Frame {
            cmd: addr | SPI_WRITE,
            data,
            bits: SPI_FRAME_BITS,
            half,
        }
    }
}

/// Every hold of a stimulus, segment by segment.
pub fn hold_stimulus(stimulus: &Stimulus) -> Vec<SpiCommand> {
    stimulus
        .segments
        .iter()
        .map(|s| SpiCommand::Hold {
            clocks: s.cycles.into(),
            pins: s.pins.0,
        })
        .collect()
}

/// What the bench printed for one command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpiReply {
    /// A frame: MISO during the command byte (the status word's low byte) and during the
    /// data bits (the word read), and the FPGA clocks simulated before CS rose.
    Frame {
        /// The command byte sent.
        cmd: u8,
        /// The status byte shifted out during the command byte.
        status: u8,
        /// The word shifted out after it.
        word: u32,
        /// FPGA clocks before CS rose.
        clock: u64,
    },
    /// The output pins.
    Pins {
        /// `register_now_out`.
        register_now: bool,
        /// `irq_out`.
        irq: bool,
        /// `fault_out`.
        fault: bool,
        /// FPGA clocks so far.
        clock: u64,
    },
}

/// The SPI design of one configuration compiled with its bench by Icarus.
#[derive(Clone, Debug)]
pub struct SpiBench {
    work: PathBuf,
    image: PathBuf,
}

impl SpiBench {
    /// Writes the SPI design of `config` and the bench under `work` and compiles them
    /// with `iverilog -g2005`.
    pub fn build(config: &MeasureConfig, options: &Options, work: &Path) -> Result<Self> {
        let design = generate_spi(config, options);
        let bench = tooltouch_hdl_gen::VerilogFile {
            name: "tooltouch_spi_bench.v".into(),
            text: SPI_BENCH.into(),
        };
        let files = write_design(&work.join("rtl"), &design, Some(&bench))?;
        let image = work.join("spi_bench.vvp");
        let iverilog = find_tool("iverilog")?;
        let out = Command::new(&iverilog)
            .args(["-g2005", "-Wall", "-s", "tooltouch_spi_bench", "-o"])
            .arg(&image)
            .args(&files)
            .output()
            .map_err(io_err(&iverilog))?;
        let text = String::from_utf8_lossy(&out.stderr).into_owned();
        if !out.status.success() || text.contains("warning") {
            return Err(HdlError::ToolFailed {
                command: "iverilog -g2005 -Wall (the SPI bench)".into(),
                status: out.status.to_string(),
                output: text,
            });
        }
        Ok(SpiBench {
            work: work.to_path_buf(),
            image,
        })
    }

    /// Runs `commands` and returns one reply per frame and pin print, in order.
    pub fn run(&self, name: &str, commands: &[SpiCommand]) -> Result<Vec<SpiReply>> {
        let mut text = String::new();
        for c in commands {
            // Writing into a String cannot fail.
            let _ = match *c {
                SpiCommand::Hold { clocks, pins } => writeln!(text, "H {clocks:x} {pins:x}"),
                SpiCommand::Frame {
                    cmd,
                    data,
                    bits,
                    half,
                } => writeln!(text, "F {cmd:x} {data:x} {bits:x} {half:x}"),
                SpiCommand::Pins => writeln!(text, "P"),
            };
        }
        let path = self.work.join(format!("{name}.commands"));
        std::fs::write(&path, text).map_err(io_err(&path))?;
        let vvp = find_tool("vvp")?;
        let out = Command::new(&vvp)
            .arg("-n")
            .arg(&self.image)
            .arg(format!("+commands={}", path.display()))
            .output()
            .map_err(io_err(&vvp))?;
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        if !out.status.success() || !stdout.lines().any(|l| l.starts_with("DONE")) {
            return Err(HdlError::ToolFailed {
                command: format!("vvp {} +commands={}", self.image.display(), path.display()),
                status: out.status.to_string(),
                output: stdout + &String::from_utf8_lossy(&out.stderr),
            });
        }
        stdout
            .lines()
            .filter(|l| l.starts_with("F ") || l.starts_with("P "))
            .map(parse_reply)
            .collect()
    }
}

/// One `F …` or `P …` line of the bench.
fn parse_reply(line: &str) -> Result<SpiReply> {
    let bad = || HdlError::Check {
        check: "SPI bench output".into(),
        details: format!("unreadable line {line:?}"),
    };
    let fields: Vec<&str> = line.split_whitespace().collect();
    let hex = |i: usize| -> Result<u64> {
        fields
            .get(i)
            .and_then(|f| u64::from_str_radix(f, 16).ok())
            .ok_or_else(bad)
    };
    match fields.first() {
        Some(&"F") => Ok(SpiReply::Frame {
            cmd: hex(1)? as u8,
            status: hex(2)? as u8,
            word: hex(3)? as u32,
            clock: hex(4)?,
        }),
        Some(&"P") => Ok(SpiReply::Pins {
            register_now: hex(1)? == 1,
            irq: hex(2)? == 1,
            fault: hex(3)? == 1,
            clock: hex(4)?,
        }),
        _ => Err(bad()),
    }
}

/// Proves with yosys (`equiv_make`, `equiv_simple`, `equiv_induct`, registers matched by
/// name) that the SPI design's `tt_frontend` with its thresholds tied to their reset values
/// ([`tooltouch_hdl_gen::spi::tied_frontend`]) equals the constant design's
/// ([`tooltouch_hdl_gen::spi::wrapped_frontend`]) on every input sequence from power-on: with
/// no SPI write the SPI design is the front end the formal proof covers. `Ok(())` when
/// proven; the unproven signals otherwise.
pub fn prove_tied_equals_constant(config: &MeasureConfig, work: &Path) -> Result<()> {
    prove_tied_equals_constant_with(config, &Options::default(), work)
}

/// [`prove_tied_equals_constant`] with the constant design generated with `constant_options`
/// (a fault, to show that the proof fails on a difference).
pub fn prove_tied_equals_constant_with(
    config: &MeasureConfig,
    constant_options: &Options,
    work: &Path,
) -> Result<()> {
    use tooltouch_hdl_gen::spi::{tied_frontend, wrapped_frontend, TIED_TOP, WRAPPED_TOP};
    let constant = tooltouch_hdl_gen::generate(config, constant_options);
    let mut gold = constant.clone();
    gold.files
        .retain(|f| f.name != format!("{}.v", tooltouch_hdl_gen::FPGA_TOP));
    let gold_files = write_design(
        &work.join("constant"),
        &gold,
        Some(&wrapped_frontend(config)),
    )?;
    let mut gate = generate_spi(config, &Options::default());
    gate.files.retain(|f| {
        f.name != format!("{}.v", tooltouch_hdl_gen::SPI_TOP)
            && f.name != format!("{}.v", tooltouch_hdl_gen::spi::SPI_MODULE)
    });
    let gate_files = write_design(&work.join("tied"), &gate, Some(&tied_frontend(config)))?;
    let list = |files: &[PathBuf]| {
        files
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let script = format!(
        "read_verilog {gold}\n\
         hierarchy -top {WRAPPED_TOP}\nproc\nflatten\nopt_clean\nrename {WRAPPED_TOP} gold\n\
         design -stash gold_design\n\
         read_verilog {gate}\n\
         hierarchy -top {TIED_TOP}\nproc\nflatten\nopt_clean\nrename {TIED_TOP} gate\n\
         design -stash gate_design\n\
         design -copy-from gold_design -as gold gold\n\
         design -copy-from gate_design -as gate gate\n\
         equiv_make gold gate equiv\nhierarchy -top equiv\nasync2sync\n\
         equiv_simple -seq 5\nequiv_induct -seq 5\nequiv_status -assert\n",
        gold = list(&gold_files),
        gate = list(&gate_files),
    );
    let path = work.join("tied_equiv.ys");
    std::fs::write(&path, script).map_err(io_err(&path))?;
    let yosys = find_tool("yosys")?;
    let log = work.join("tied_equiv.log");
    let out = Command::new(&yosys)
        .arg("-q")
        .arg("-l")
        .arg(&log)
        .arg(&path)
        .output()
        .map_err(io_err(&yosys))?;
    if out.status.success() {
        return Ok(());
    }
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    let unproven: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("Unproven"))
        .take(20)
        .collect();
    Err(HdlError::Check {
        check: "the SPI design with tied thresholds against the constant design".into(),
        details: format!(
            "not proven ({}); see {}:\n{}",
            out.status,
            log.display(),
            unproven.join("\n")
        ),
    })
}
