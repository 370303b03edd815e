//! tooltouch's random event streams, drawn from one seed each: the measurement path's
//! physically shaped scenarios with their fault cases ([`scenario`]) and the force path's
//! random spindle-drive plant closed around the golden force kernel ([`force_scenario`]).
//! The firmware runners, the LinuxCNC golden stimulus and the tests replay them.
//!
//! Depends on the golden model (its test kit) and the plants; must not depend on any
//! runner (firmware, RTL, formal, LinuxCNC), tuning, plots or the command line.

pub mod force_scenario;
pub mod scenario;

pub use scenario::{generate, Case, Fault};
