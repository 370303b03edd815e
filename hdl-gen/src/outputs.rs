//! The front end's outputs as ports, VCD signals and hex-vector fields: names, widths for a
//! configuration and raw bits. A leaf module (re-exported at the crate root), so the
//! generators use it without importing the root.

use tooltouch_model::{MeasureConfig, MeasureOutputs, OutputWidth};

/// One output port of the top module for every configuration: its name and how wide it is
/// ([`OutputWidth`]: one bit, a configured width, a fixed width). What the scoreboards'
/// generated port lists ([`crate::scoreboard_lists`]) are written from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OutputPort {
    /// The port's name: the `MeasureOutputs` field's and the VCD signal's.
    pub name: &'static str,
    /// Its width.
    pub width: OutputWidth,
}

/// The output ports in `MeasureOutputs` / VCD contract order ([`MeasureOutputs::LAYOUT`],
/// the model's one list). The one place a port's name is made from the model's field
/// name: they are equal.
pub fn output_ports() -> [OutputPort; MeasureOutputs::FIELD_COUNT] {
    MeasureOutputs::LAYOUT.map(|(name, width)| OutputPort { name, width })
}

/// The output the top's `irq` port copies (`assign irq = register_now`): the MCU's
/// interrupt is the strobe to the CNC.
pub const IRQ_SOURCE: &str = "register_now";

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
/// ([`output_ports`] with their widths evaluated).
pub fn output_fields(config: &MeasureConfig) -> [OutputField; MeasureOutputs::FIELD_COUNT] {
    output_ports().map(|p| OutputField {
        name: p.name,
        width: p.width.bits(config),
    })
}

/// Total width of all outputs, bits.
pub fn outputs_width(config: &MeasureConfig) -> u32 {
    output_fields(config).iter().map(|f| f.width).sum()
}

/// The raw bits of every output (two's-complement positions truncated to `scale_bits`),
/// in [`output_fields`] order.
pub fn output_values(
    config: &MeasureConfig,
    o: &MeasureOutputs,
) -> [u64; MeasureOutputs::FIELD_COUNT] {
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
