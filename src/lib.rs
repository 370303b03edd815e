//! tooltouch, the command line: argument parsing, progress, printing and exit codes over the
//! host libraries (docs/architecture.md) — `tooltouch-plant` (the simulated machines),
//! `tooltouch-vectors` (files and `check`), `tooltouch-settings` (the configuration),
//! `tooltouch-cosim` (QEMU and HDL runners), `tooltouch-plot`, `tooltouch-tune`. No domain
//! logic lives here: a subcommand parses, calls a library, prints, and exits.

pub mod cli;
