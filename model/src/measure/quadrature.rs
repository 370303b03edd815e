//! The linear scale's x4 quadrature decoder (docs/domain.md §1): the cross-slide position in scale
//! counts, with an error count for illegal transitions.
//!
//! Phase order for positive motion: (A,B) = 00 → 10 → 11 → 01 → 00 (A leads B). A change
//! of both lines at once skips a phase: the direction is unknown, so the position is left
//! unchanged and the error count goes up.

use crate::measure::config::MeasureConfig;

/// Quadrature decoder with a `scale_bits`-wide two's-complement position counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct QuadratureDecoder {
    mask: u32,
    sign_bit: u32,
    /// Last (A, B) phase, `0..4` in the order above.
    phase: u8,
    /// Position, scale counts, stored as the low `scale_bits` bits (wrapping).
    raw_position: u32,
    /// Illegal transitions seen since power-on, saturating at 255.
    errors: u8,
}

fn phase_of(a: bool, b: bool) -> u8 {
    match (a, b) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

impl QuadratureDecoder {
    /// A decoder at position 0 with lines (A,B) = 00.
    pub fn new(config: &MeasureConfig) -> Self {
        let bits = config.settings().scale_bits;
        QuadratureDecoder {
            mask: if bits >= 32 {
                u32::MAX
            } else {
                (1u32 << bits) - 1
            },
            sign_bit: 1u32 << (bits - 1),
            phase: 0,
            raw_position: 0,
            errors: 0,
        }
    }

    /// New levels of lines A and B. Counts ±1 per legal transition (wrapping at
    /// `scale_bits`); a double change counts an error (saturating at 255). Returns whether
    /// the transition was illegal.
    pub fn on_ab(&mut self, a: bool, b: bool) -> bool {
        let phase = phase_of(a, b);
        let mut illegal = false;
        match phase.wrapping_sub(self.phase) & 3 {
            1 => self.raw_position = self.raw_position.wrapping_add(1) & self.mask,
            3 => self.raw_position = self.raw_position.wrapping_sub(1) & self.mask,
            2 => {
                self.errors = self.errors.saturating_add(1);
                illegal = true;
            }
            _ => {}
        }
        self.phase = phase;
        illegal
    }

    /// Position, scale counts, sign-extended from `scale_bits`.
    pub fn position(&self) -> i32 {
        let raw = self.raw_position;
        if raw & self.sign_bit != 0 {
            (raw | !self.mask) as i32
        } else {
            raw as i32
        }
    }
    /// The position register's raw `scale_bits` bits.
    pub fn raw_position(&self) -> u32 {
        self.raw_position
    }
    /// Illegal transitions since power-on (saturating at 255).
    pub fn errors(&self) -> u8 {
        self.errors
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::config::MeasureSettings;

    fn decoder(bits: u8) -> QuadratureDecoder {
        let s = MeasureSettings {
            scale_bits: bits,
            ..Default::default()
        };
        QuadratureDecoder::new(&s.validate().unwrap())
    }

    const FORWARD: [(bool, bool); 4] = [(true, false), (true, true), (false, true), (false, false)];

    #[test]
    fn counts_four_per_cycle_both_ways() {
        let mut q = decoder(24);
        for _ in 0..3 {
            for (a, b) in FORWARD {
                q.on_ab(a, b);
            }
        }
        assert_eq!(q.position(), 12);
        for _ in 0..5 {
            for (a, b) in FORWARD
                .iter()
                .rev()
                .skip(1)
                .chain(core::iter::once(&(false, false)))
            {
                q.on_ab(*a, *b);
            }
        }
        assert_eq!(q.position(), -8);
        assert_eq!(q.errors(), 0);
    }

    #[test]
    fn double_change_is_an_error_and_does_not_count() {
        let mut q = decoder(24);
        q.on_ab(true, true);
        assert_eq!((q.position(), q.errors()), (0, 1));
        q.on_ab(false, true);
        assert_eq!(q.position(), 1);
    }

    #[test]
    fn every_backward_step_counts_minus_one() {
        let mut q = decoder(24);
        // 00 → 01 → 11 → 10 → 00: B leads A.
        let backward = [(false, true), (true, true), (true, false), (false, false)];
        for (k, (a, b)) in backward.into_iter().enumerate() {
            q.on_ab(a, b);
            assert_eq!(q.position(), -(k as i32) - 1);
        }
        // A repeated level is no transition.
        q.on_ab(false, false);
        assert_eq!((q.position(), q.errors()), (-4, 0));
    }

    #[test]
    fn errors_saturate_at_255() {
        let mut q = decoder(24);
        for k in 1..=300u32 {
            // 00 ↔ 11 changes both lines every time.
            q.on_ab(k % 2 == 1, k % 2 == 1);
            assert_eq!(u32::from(q.errors()), k.min(255));
        }
        assert_eq!(q.position(), 0);
    }

    #[test]
    fn a_32_bit_scale_wraps_like_i32() {
        let mut q = decoder(32);
        q.on_ab(false, true);
        assert_eq!((q.position(), q.raw_position()), (-1, u32::MAX));
        let mut q = decoder(31);
        q.on_ab(false, true);
        assert_eq!((q.position(), q.raw_position()), (-1, 0x7fff_ffff));
        q.on_ab(false, false);
        q.on_ab(true, false);
        assert_eq!((q.position(), q.raw_position()), (1, 1));
    }

    #[test]
    fn position_wraps_at_scale_bits() {
        let mut q = decoder(8);
        q.on_ab(false, true);
        assert_eq!(q.position(), -1, "00 -> 01 is one step backwards");
        assert_eq!(q.raw_position(), 0xff);
        q.on_ab(false, false);
        assert_eq!(q.position(), 0);
        for _ in 0..31 {
            for (a, b) in FORWARD {
                q.on_ab(a, b);
            }
        }
        for (a, b) in &FORWARD[..3] {
            q.on_ab(*a, *b);
        }
        assert_eq!(q.position(), 127);
        q.on_ab(false, false);
        assert_eq!(q.position(), -128, "127 + 1 wraps to -128 in 8 bits");
    }
}
