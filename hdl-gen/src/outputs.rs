//! The front end's outputs as ports, VCD signals and hex-vector fields: names, widths for a
//! configuration and raw bits. A leaf module (re-exported at the crate root), so the
//! generators use it without importing the root.

use tooltouch_model::{MeasureConfig, MeasureOutputs};

/// One output of the front end, as a port of the top module, a VCD signal and a field of
/// the expected-response hex vectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OutputField {
    /// Name, equal to the `MeasureOutputs` field and the VCD signal.
    pub name: &'static str,
    /// Width, bits (the VCD contract's widths).
    pub width: u32,
}

/// The outputs in `MeasureOutputs` / VCD contract order, with their widths for `config`
/// ([`MeasureOutputs::widths`], the model's one list).
pub fn output_fields(config: &MeasureConfig) -> [OutputField; 15] {
    MeasureOutputs::widths(config).map(|(name, width)| OutputField { name, width })
}

/// Total width of all outputs, bits.
pub fn outputs_width(config: &MeasureConfig) -> u32 {
    output_fields(config).iter().map(|f| f.width).sum()
}

/// The raw bits of every output (two's-complement positions truncated to `scale_bits`),
/// in [`output_fields`] order.
pub fn output_values(config: &MeasureConfig, o: &MeasureOutputs) -> [u64; 15] {
    o.register_bits(config)
}

/// `width` low bits set (`width <= 64`).
pub fn mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}
