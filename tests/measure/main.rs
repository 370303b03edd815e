//! Integration tests of the measurement path: the papers' physics, cycle level against event level, speed models, vector files.
//!
//! One test binary per area (`cargo test --release --test measure`); one module per topic
//! (`cargo test --release --test measure <topic>::`).

mod averaging;
mod budget;
mod calibration;
mod levels_agree;
mod no_false_alarm;
mod physics;
mod presets;
mod speed_models_agree;
mod spindle_path;
mod status;
mod vectors_files;
