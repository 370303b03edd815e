//! Integration tests of the `tooltouch` command line as a user runs it: check, vectors, measure, hdl --vectors, bench, output folders, hostile inputs.
//!
//! One test binary per area (`cargo test --release --test cli`); one module per topic
//! (`cargo test --release --test cli <topic>::`).

#[path = "../common/mod.rs"]
mod common;

mod bench;
mod check_firmware;
mod check_inputs;
mod check_truncated;
mod doc_figures;
mod docs_index;
mod examples;
mod golden_fst;
mod hdl_clock;
mod hdl_faults;
mod hdl_vectors;
mod hostile_inputs;
mod measure_check;
mod output_folders;
mod plots;
mod readme_recipes;
mod run_files;
mod scaleout;
mod size_loop;
mod slurm_cluster;
mod spelling;
mod vectors;
