//! tooltouch-hdl-gen: writes the Verilog of the FPGA measurement front end from the
//! model's [`tooltouch_model::MeasureConfig`]. (Being built: see issue 5.)
#![deny(missing_docs)]
