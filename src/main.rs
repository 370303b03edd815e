//! The `tooltouch` command line.

fn main() -> std::process::ExitCode {
    tooltouch::cli::main()
}
