//! Semihosting file I/O for the co-simulation under QEMU: the event stream comes in and the
//! output trace goes out through the host's file system (`-semihosting-config
//! enable=on,target=native`).
//!
//! cortex-m-semihosting 0.5 has no public `open`, so this uses its raw `syscall!`: OPEN's
//! length excludes the terminating NUL; READ and WRITE return the number of bytes *not*
//! transferred. Messages go to the host's console (`:tt`), and the run ends with
//! SYS_EXIT_EXTENDED, whose subcode QEMU makes its exit status ([`exit_code`]).

use crate::cosim::{IoError, Port};
use cortex_m_semihosting::{nr, syscall};

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

/// `SYS_EXIT_EXTENDED`: exit with a reason and a subcode.
const SYS_EXIT_EXTENDED: usize = 0x20;
/// The reason of a normal application exit; the subcode is then the exit status.
const ADP_STOPPED_APPLICATION_EXIT: usize = 0x2_0026;

/// Ends the QEMU run with exit status `code`.
pub fn exit(code: u8) -> ! {
    let block = [ADP_STOPPED_APPLICATION_EXIT, usize::from(code)];
    loop {
        // SAFETY: the parameter block is two live words, as SYS_EXIT_EXTENDED reads them.
        unsafe {
            cortex_m_semihosting::syscall(SYS_EXIT_EXTENDED, &block);
        }
    }
}

/// Writes `bytes` to the host's console; a console the host refuses is skipped (a
/// message is best effort).
pub fn print(bytes: &[u8]) {
    if let Some(mut console) = File::open(b":tt\0", nr::open::W_TRUNC) {
        let _ = console.write(bytes);
        let _ = console.close();
    }
}

/// Input file, relative to QEMU's working directory.
pub const EVENTS_FILE: &[u8] = b"tooltouch-events.bin\0";
/// Output file, relative to QEMU's working directory.
pub const OUTPUTS_FILE: &[u8] = b"tooltouch-outputs.bin\0";

/// An open host file.
pub struct File {
    handle: usize,
}

impl File {
    /// Opens `path` (NUL-terminated) with a semihosting `mode` ([`nr::open`]); `None`
    /// when the host refuses.
    pub fn open(path: &[u8], mode: usize) -> Option<File> {
        let len = path.len().saturating_sub(1);
        // SAFETY: `path` is a live NUL-terminated buffer of `len + 1` bytes.
        let handle = unsafe { syscall!(OPEN, path.as_ptr(), mode, len) };
        if handle == usize::MAX {
            None
        } else {
            Some(File { handle })
        }
    }

    /// Reads up to `buf.len()` bytes; 0 at the end of the file.
    pub fn read(&mut self, buf: &mut [u8]) -> usize {
        // SAFETY: the host writes at most `buf.len()` bytes into `buf`.
        let not_read = unsafe { syscall!(READ, self.handle, buf.as_mut_ptr(), buf.len()) };
        buf.len().saturating_sub(not_read)
    }

    /// Writes all of `bytes`; false if the host wrote fewer.
    pub fn write(&mut self, bytes: &[u8]) -> bool {
        // SAFETY: the host reads `bytes.len()` bytes from `bytes`.
        let not_written = unsafe { syscall!(WRITE, self.handle, bytes.as_ptr(), bytes.len()) };
        not_written == 0
    }

    /// Closes the file; false if the host reports an error.
    pub fn close(self) -> bool {
        // SAFETY: the handle came from OPEN and is closed once (self is consumed).
        unsafe { syscall!(CLOSE, self.handle) == 0 }
    }
}

/// The co-simulation's two files.
pub struct Files {
    input: File,
    output: File,
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
        let input = File::open(EVENTS_FILE, nr::open::R_BINARY).ok_or(OpenError::Events)?;
        let output = match File::open(OUTPUTS_FILE, nr::open::W_TRUNC_BINARY) {
            Some(f) => f,
            None => {
                let _ = input.close();
                return Err(OpenError::Outputs);
            }
        };
        Ok(Files { input, output })
    }

    /// Closes both files; false if either close failed.
    pub fn close(self) -> bool {
        let a = self.input.close();
        let b = self.output.close();
        a && b
    }
}

impl Port for Files {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoError> {
        Ok(self.input.read(buf))
    }
    fn write(&mut self, bytes: &[u8]) -> Result<(), IoError> {
        if self.output.write(bytes) {
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
