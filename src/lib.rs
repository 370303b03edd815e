//! tooltouch, the command line: argument parsing, progress, printing and exit codes over the
//! host libraries (docs/architecture.md) — `tooltouch-plant` (the simulated machines),
//! `tooltouch-vectors` (files and `check`), `tooltouch-settings` (the configuration),
//! `tooltouch-stimuli` (random event streams), `tooltouch-firmware-runner` (the firmware under
//! QEMU and on the bench), `tooltouch-rtl-sim` (Verilator and Icarus), `tooltouch-formal`
//! (`tooltouch formal`), `tooltouch-plot`, `tooltouch-tune`. No domain
//! logic lives here: a subcommand parses, calls a library, prints, and exits.

pub mod cli;
