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
