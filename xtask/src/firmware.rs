//! Firmware builds, always run from inside firmware/ so its own .cargo/config.toml applies.
//! (Filled in by the firmware issue.)

use anyhow::Result;

/// Builds the firmware for every board.
pub fn build_all() -> Result<()> {
    check_all()
}

/// fmt, clippy and release builds of the firmware for every board.
pub fn check_all() -> Result<()> {
    let dir = crate::root().join("firmware");
    if !dir.join("Cargo.toml").exists() {
        anyhow::bail!("firmware/Cargo.toml is missing");
    }
    Ok(())
}
