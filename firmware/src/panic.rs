//! The panic handler of each build. None of them should ever run: the `panic-check`
//! build proves that no panic path is linked at all.

#[cfg(feature = "panic-check")]
mod check {
    extern "C" {
        /// Defined nowhere: if any panic path survives optimisation, the handler below
        /// is linked and the link fails naming this symbol.
        fn tooltouch_firmware_panic_path_linked_into_the_image() -> !;
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        // SAFETY: never links (see above); the call only exists to make linking fail.
        unsafe { tooltouch_firmware_panic_path_linked_into_the_image() }
    }
}

/// QEMU (either board): report failure to the host (QEMU exits non-zero) without
/// formatting anything.
#[cfg(all(
    any(feature = "qemu", feature = "emulated"),
    not(feature = "panic-check")
))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    semihosting::process::exit(1)
}

/// Hardware: panic-probe prints the message over defmt and stops the probe run.
#[cfg(all(
    feature = "nucleo",
    not(feature = "qemu"),
    not(feature = "emulated"),
    not(feature = "panic-check")
))]
use panic_probe as _;
