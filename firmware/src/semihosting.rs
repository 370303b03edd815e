//! Semihosting file I/O for the co-simulation under QEMU: the event stream comes in and the
//! output trace goes out through the host's file system (`-semihosting-config
//! enable=on,target=native`), with the `semihosting` crate's `fs` and `stdio`. Messages go to
//! the host's console, and the run ends with SYS_EXIT_EXTENDED (the crate's
//! `process::exit`), whose subcode QEMU makes its exit status ([`exit_code`]).

use crate::cosim::{self, IoError, Port, Target};
use core::ffi::CStr;
use semihosting::fd::{AsFd, BorrowedFd, OwnedFd};
use semihosting::fs::File;

/// QEMU's exit status at the end of a run (docs/firmware.md lists them).
pub mod exit_code {
    /// Every stream replayed, the whole trace written.
    pub const OK: u8 = 0;
    /// The events file (`tooltouch-events.bin`) could not be opened.
    pub const NO_EVENTS_FILE: u8 = 2;
    /// The events file is malformed: the trace ends with a `FIRMWARE_ERROR` record.
    pub const MALFORMED_EVENTS: u8 = 3;
    /// Reading the events or writing the trace failed (or the trace file could not be
    /// created).
    pub const FILE_IO: u8 = 4;
    /// The baked configuration did not decode (build.rs decodes it first, so an image
    /// that built never exits with this).
    pub const BAD_BAKED_CONFIG: u8 = 5;
}

/// Ends the QEMU run with exit status `code` (SYS_EXIT_EXTENDED, reason
/// ADP_Stopped_ApplicationExit, subcode `code`).
pub fn exit(code: u8) -> ! {
    semihosting::process::exit(i32::from(code))
}

/// Writes `bytes` to the host's console; a console the host refuses is skipped (a
/// message is best effort).
pub fn print(bytes: &[u8]) {
    if let Ok(console) = File::create(CONSOLE) {
        let _ = write_all(&OwnedFd::from(console), bytes);
    }
}

/// The host's console (`:tt` opened for writing is its standard output).
const CONSOLE: &CStr = c":tt";
/// Input file, relative to QEMU's working directory.
pub const EVENTS_FILE: &CStr = c"tooltouch-events.bin";
/// Output file, relative to QEMU's working directory.
pub const OUTPUTS_FILE: &CStr = c"tooltouch-outputs.bin";
/// The emulated Nucleo's defmt frames (rzCOBS-encoded, as defmt-rtt would send them),
/// relative to QEMU's working directory.
pub const DEFMT_FILE: &CStr = c"tooltouch-defmt.bin";

/// The co-simulation's two files.
pub struct Files {
    input: OwnedFd,
    output: OwnedFd,
}

/// Which of the co-simulation's files could not be opened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpenError {
    /// [`EVENTS_FILE`] (missing, or unreadable).
    Events,
    /// [`OUTPUTS_FILE`] (could not be created).
    Outputs,
}

impl Files {
    /// Opens [`EVENTS_FILE`] for reading and [`OUTPUTS_FILE`] for writing (truncated).
    pub fn open() -> Result<Files, OpenError> {
        let input = File::open(EVENTS_FILE).map_err(|_| OpenError::Events)?;
        let output = File::create(OUTPUTS_FILE).map_err(|_| OpenError::Outputs)?;
        Ok(Files {
            input: input.into(),
            output: output.into(),
        })
    }

    /// Closes both files; false if the host reported an error closing either (a dropped
    /// file is closed too, without a report).
    pub fn close(self) -> bool {
        let a = close(self.input);
        let b = close(self.output);
        a && b
    }
}

/// Closes `fd`: true if the host closed it.
fn close(fd: OwnedFd) -> bool {
    let raw = fd.into_raw_fd();
    // SAFETY: `raw` comes from the descriptor just consumed, so it is open and closed only
    // here.
    unsafe { semihosting::sys::close(raw) }.is_ok()
}

/// `fd` borrowed for a call. The crate asserts that a borrowed descriptor is not -1; the
/// test here, on the same value, lets the optimiser drop that assertion's panic path (the
/// `panic-check` build links none). An open descriptor is never -1, so this is never `None`.
fn borrow(fd: &OwnedFd) -> Option<BorrowedFd<'_>> {
    (fd.as_raw_fd() != -1).then(|| fd.as_fd())
}

/// Opens (creates or truncates) the host file `name` for writing; `None` if the host
/// refuses.
pub fn create(name: &CStr) -> Option<OwnedFd> {
    File::create(name).ok().map(OwnedFd::from)
}

/// Writes all of `bytes` to `fd`: false on an error or a host that writes nothing.
pub fn write_all(fd: &OwnedFd, bytes: &[u8]) -> bool {
    let mut rest = bytes;
    while !rest.is_empty() {
        let Some(fd) = borrow(fd) else {
            return false;
        };
        match semihosting::sys::write(fd, rest) {
            Ok(n) if n > 0 => match rest.get(n..) {
                Some(r) => rest = r,
                None => return false,
            },
            _ => return false,
        }
    }
    true
}

impl Port for Files {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoError> {
        let fd = borrow(&self.input).ok_or(IoError)?;
        let n = semihosting::sys::read(fd, buf).map_err(|_| IoError)?;
        Ok(n.min(buf.len()))
    }
    fn write(&mut self, bytes: &[u8]) -> Result<(), IoError> {
        if write_all(&self.output, bytes) {
            Ok(())
        } else {
            Err(IoError)
        }
    }
}

/// `value` in decimal: the digits and how many of them are used.
pub fn decimal(mut value: u64) -> ([u8; 20], usize) {
    let mut digits = [0u8; 20];
    let mut n = 0usize;
    loop {
        if let Some(d) = digits.get_mut(n) {
            *d = b'0'.wrapping_add((value % 10) as u8);
        }
        n = n.saturating_add(1);
        value /= 10;
        if value == 0 || n >= 20 {
            break;
        }
    }
    digits.get_mut(..n).unwrap_or(&mut []).reverse();
    (digits, n)
}

/// Replays `tooltouch-events.bin` through `target` into `tooltouch-outputs.bin`
/// ([`cosim::run`]), says on the console how the run ended and returns QEMU's exit status
/// for it ([`exit_code`]).
pub fn replay(target: &mut impl Target) -> u8 {
    match Files::open() {
        Ok(mut files) => {
            let ran = cosim::run(&mut files, target);
            let closed = files.close();
            report(ran, closed)
        }
        Err(OpenError::Events) => {
            print(
                b"tooltouch firmware: cannot open tooltouch-events.bin in QEMU's working \
                  directory: put an event stream there (tooltouch vectors writes events.ttv)\n",
            );
            exit_code::NO_EVENTS_FILE
        }
        Err(OpenError::Outputs) => {
            print(b"tooltouch firmware: cannot create tooltouch-outputs.bin\n");
            exit_code::FILE_IO
        }
    }
}

/// Says how the run ended and returns QEMU's exit status for it.
fn report(ran: Result<u32, cosim::Error>, closed: bool) -> u8 {
    match ran {
        Ok(streams) if closed => {
            let (digits, n) = decimal(u64::from(streams));
            print(b"tooltouch firmware: replayed ");
            print(digits.get(..n).unwrap_or(&[]));
            print(b" stream(s); trace in tooltouch-outputs.bin\n");
            exit_code::OK
        }
        Ok(_) | Err(cosim::Error::Io) => {
            print(
                b"tooltouch firmware: reading tooltouch-events.bin or writing \
                  tooltouch-outputs.bin failed\n",
            );
            exit_code::FILE_IO
        }
        Err(e) => {
            let (code, _, offset, _) = e.code();
            let (at, n) = decimal(offset);
            let (what, k) = decimal(u64::from(code));
            print(b"tooltouch firmware: tooltouch-events.bin is malformed at byte ");
            print(at.get(..n).unwrap_or(&[]));
            print(b" (error ");
            print(what.get(..k).unwrap_or(&[]));
            print(
                b"); the trace ends with an error record: \
                  `tooltouch check` or `tooltouch cosim firmware` explains it\n",
            );
            exit_code::MALFORMED_EVENTS
        }
    }
}
