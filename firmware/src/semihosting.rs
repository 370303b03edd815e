//! Semihosting file I/O for the co-simulation under QEMU: the event stream comes in and the
//! output trace goes out through the host's file system (`-semihosting-config
//! enable=on,target=native`).
//!
//! cortex-m-semihosting 0.5 has no public `open`, so this uses its raw `syscall!`: OPEN's
//! length excludes the terminating NUL; READ and WRITE return the number of bytes *not*
//! transferred.

use crate::cosim::{IoError, Port};
use cortex_m_semihosting::{nr, syscall};

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

impl Files {
    /// Opens [`EVENTS_FILE`] for reading and [`OUTPUTS_FILE`] for writing (truncated).
    pub fn open() -> Option<Files> {
        let input = File::open(EVENTS_FILE, nr::open::R_BINARY)?;
        let output = File::open(OUTPUTS_FILE, nr::open::W_TRUNC_BINARY)?;
        Some(Files { input, output })
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
