//! Read-only snapshots of the kernels' internal state registers (cargo feature
//! `internals`, which the firmware does not enable).
//!
//! The kernels' outputs ([`crate::MeasureOutputs`], [`crate::force::kernel::ForceOutputs`])
//! are public; the registers *behind* them — the glitch filters' counters, the pulse
//! counter's revolution count, the sampling chain's low-pass states, running sums and
//! averages, the estimator's no-load least-squares sums and intermediate powers and
//! torques, the controllers' accumulators, the wear monitor's filter, held threshold and
//! counters — are private fields. With this feature every kernel that has such registers
//! implements [`Internals`]: it calls a visitor once per register, in a fixed order, with
//! the register's stable name, its raw value and its [`Format`] (the word the value lives
//! in, its fractional bits, and for a clamped register the clamp's limits), so a host tool
//! (`tooltouch ranges`) can count ranges, saturations and headroom.
//!
//! Nothing here is called by a kernel: the accessors only read fields after the fact, so
//! no kernel's arithmetic or hot path changes, and with the feature off this module and
//! every `impl Internals` are not compiled at all. `no_std`, no allocation, no floating
//! point, like the rest of the crate.
//!
//! Registers that are single bits (synchronizer stages, filtered levels, the sticky bit,
//! armed/fired/reached flags) or state encodings (the quadrature decoder's 2-bit phase)
//! have no range to speak of and are not listed; registers already public as outputs
//! (positions, counts, charge, the force path's outputs) are not listed again, except the
//! wear monitor's filter, which is listed under its own name beside the `wear_power`
//! output it feeds.

/// What a register does at the end of its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Overflow {
    /// It is held at its limits (saturating arithmetic, or a clamp).
    Saturates,
    /// It wraps modulo 2^`word_bits`.
    Wraps,
}

/// A register's format: the machine word its value lives in and the limits it is held to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Format {
    /// Bits of the word: 8 for a `u8` counter, 64 for an I32F32 value, 128 for an `i128`
    /// sum.
    pub word_bits: u8,
    /// Fractional bits: the register's number is `raw / 2^frac_bits`.
    pub frac_bits: u8,
    /// Two's complement.
    pub signed: bool,
    /// Saturating or wrapping.
    pub overflow: Overflow,
    /// The clamp's limits as raw values, when the code holds the register inside limits
    /// narrower than its word's (the PI integrator between `integrator_min` and
    /// `integrator_max`); `None`: the word's own limits.
    pub clamp: Option<(i128, i128)>,
}

impl Format {
    /// An unsigned integer word of `bits`, saturating.
    pub const fn unsigned(bits: u8) -> Format {
        Format {
            word_bits: bits,
            frac_bits: 0,
            signed: false,
            overflow: Overflow::Saturates,
            clamp: None,
        }
    }

    /// A signed fixed-point word of `bits` with `frac` fractional bits, saturating.
    pub const fn fixed(bits: u8, frac: u8) -> Format {
        Format {
            word_bits: bits,
            frac_bits: frac,
            signed: true,
            overflow: Overflow::Saturates,
            clamp: None,
        }
    }

    /// I32F32 (the force path's [`crate::units::Fx`]), saturating.
    pub const I32F32: Format = Format::fixed(64, 32);

    /// This format clamped to the raw limits `lo..=hi`.
    pub const fn clamped(self, lo: i128, hi: i128) -> Format {
        Format {
            clamp: Some((lo, hi)),
            ..self
        }
    }

    /// The limits the register is held to, raw: the clamp's, or the word's.
    pub const fn limits(&self) -> (i128, i128) {
        if let Some(c) = self.clamp {
            return c;
        }
        // Shifts of 0..=127: `word_bits` is at most 128 and at least 1 by construction (a
        // larger or zero width reads as 128 bits).
        let bits = match self.word_bits {
            0 | 129.. => 128,
            b => b as u32,
        };
        if self.signed {
            (i128::MIN >> (128 - bits), i128::MAX >> (128 - bits))
        } else {
            // An unsigned 128-bit word's top half does not fit: i128::MAX.
            (0, i128::MAX >> 127u32.saturating_sub(bits))
        }
    }
}

/// One register at the snapshot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Register {
    /// Its stable name, `part.field` or `part.field[channel]` (e.g. `sampler.sums[power]`,
    /// `estimator.no_load.sww`, `pi.integral`).
    pub name: &'static str,
    /// Its format.
    pub format: Format,
    /// Its raw value (the number times `2^frac_bits`); `None` while the kernel holds no
    /// value in it yet (an `Option` register before its first period).
    pub raw: Option<i128>,
}

impl Register {
    /// A register holding `raw`.
    pub const fn new(name: &'static str, format: Format, raw: i128) -> Register {
        Register {
            name,
            format,
            raw: Some(raw),
        }
    }

    /// An I32F32 register holding `v`.
    pub fn fx(name: &'static str, format: Format, v: crate::units::Fx) -> Register {
        Register::new(name, format, i128::from(v.to_bits()))
    }
}

/// A kernel whose internal registers can be snapshotted.
pub trait Internals {
    /// Calls `f` once per internal register, always the same registers in the same order
    /// for a kernel of a given configuration.
    fn internals(&self, f: &mut dyn FnMut(Register));
}

#[cfg(test)]
mod tests;
