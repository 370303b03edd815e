//! tooltouch: the host side of the co-design workspace — the lathe and spindle-drive
//! plants, scenarios, vector files, float reference models, tuning sweeps, plots, and the
//! co-simulation runners. The fixed-point golden model itself is `tooltouch-model`.

pub mod cli;
pub mod cosim;
pub mod drive;
pub mod hdl;
pub mod lathe;
pub mod measurement_cycle;
pub mod milling;
pub mod output;
pub mod plot;
pub mod reference;
pub mod settings;
pub mod speed;
pub mod stimulus;
pub mod tune;
pub mod vectors;
