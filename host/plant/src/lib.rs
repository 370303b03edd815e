//! The simulated machines of tooltouch, in float: the lathe that a measurement runs on
//! (surface, spindle, contact electrics, linear scale) and its closed-loop measurement cycle
//! around the golden model, the spindle drive and turning process of the force-control
//! scenario, face-milling power with tool wear, and the float references of the force path.
//! The pin stimuli they produce ([`stimulus`]) are what every embodiment is driven with.
//!
//! Depends on the golden model only; must not depend on vector files, settings files, the
//! co-simulation runners, plots or the command line.

pub mod drive;
pub mod lathe;
pub mod measurement_cycle;
pub mod milling;
pub mod milling_transients;
pub mod random;
pub mod reference;
pub mod stimulus;
pub mod stress;
