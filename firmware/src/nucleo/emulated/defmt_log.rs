//! The emulated Nucleo's defmt logger: the frames defmt-rtt would put in its RTT buffer
//! for probe-rs, encoded by defmt's own [`defmt::Encoder`] (the image's `_defmt_encoding_`,
//! rzCOBS), written to the host file `tooltouch-defmt.bin` over semihosting instead (QEMU
//! has no debug probe to read RTT). The host decodes it with defmt's decoder and the
//! image's `.defmt` table, as `probe-rs run` would.
//!
//! The board logs only from `init` and `idle`; the frame is still encoded inside a
//! critical section, so a log from an interrupt would wait, not interleave.

use crate::semihosting::{create, write_all, DEFMT_FILE};
use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicBool, Ordering};
use semihosting::fd::OwnedFd;

/// The encoder and the open log file, used only between `acquire` and `release`.
struct State {
    encoder: defmt::Encoder,
    file: Option<OwnedFd>,
    /// Whether opening the file was tried (it is opened at the first frame).
    opened: bool,
    /// PRIMASK was clear at `acquire`: interrupts are enabled again at `release`.
    enable_at_release: bool,
}

struct Shared(UnsafeCell<State>);

// SAFETY: only touched with interrupts disabled (between acquire and release) on a single
// core, and `TAKEN` refuses a second user.
unsafe impl Sync for Shared {}

static STATE: Shared = Shared(UnsafeCell::new(State {
    encoder: defmt::Encoder::new(),
    file: None,
    opened: false,
    enable_at_release: false,
}));
/// A frame is being encoded.
static TAKEN: AtomicBool = AtomicBool::new(false);

#[defmt::global_logger]
struct SemihostingLogger;

// SAFETY: `acquire` disables interrupts and marks the logger taken; `write` and
// `release` are called by defmt only between `acquire` and `release`.
unsafe impl defmt::Logger for SemihostingLogger {
    fn acquire() {
        let primask = cortex_m::register::primask::read();
        cortex_m::interrupt::disable();
        if TAKEN.swap(true, Ordering::Acquire) {
            // Re-entered (never: the board logs from init and idle only): the frame goes
            // into the one being encoded, which the host's decoder then reports as
            // malformed.
            return;
        }
        // SAFETY: interrupts are off and the logger is ours until `release`.
        let state = unsafe { &mut *STATE.0.get() };
        state.enable_at_release = primask.is_active();
        if !state.opened {
            state.opened = true;
            state.file = create(DEFMT_FILE);
        }
        let State { encoder, file, .. } = state;
        encoder.start_frame(|b| {
            if let Some(fd) = file {
                let _ = write_all(fd, b);
            }
        });
    }

    unsafe fn flush() {}

    unsafe fn release() {
        // SAFETY: between acquire and release (the trait's contract).
        let state = unsafe { &mut *STATE.0.get() };
        let State { encoder, file, .. } = state;
        encoder.end_frame(|b| {
            if let Some(fd) = file {
                let _ = write_all(fd, b);
            }
        });
        let enable = state.enable_at_release;
        TAKEN.store(false, Ordering::Release);
        if enable {
            // SAFETY: restores the PRIMASK state of `acquire`.
            unsafe { cortex_m::interrupt::enable() };
        }
    }

    unsafe fn write(bytes: &[u8]) {
        // SAFETY: between acquire and release (the trait's contract).
        let state = unsafe { &mut *STATE.0.get() };
        let State { encoder, file, .. } = state;
        encoder.write(bytes, |b| {
            if let Some(fd) = file {
                let _ = write_all(fd, b);
            }
        });
    }
}
