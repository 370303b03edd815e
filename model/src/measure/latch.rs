//! The position latch: captures the scale position once, when a decision fires or at
//! first contact, and holds it until the next measurement cycle.

/// A capture-once register for a scale position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PositionLatch {
    valid: bool,
    position: i32,
}

impl PositionLatch {
    /// An empty latch.
    pub const fn new() -> Self {
        PositionLatch {
            valid: false,
            position: 0,
        }
    }
    /// Captures `position` (scale counts) unless a position is already held. Returns
    /// whether it captured.
    #[inline]
    pub fn capture(&mut self, position: i32) -> bool {
        if self.valid {
            return false;
        }
        self.valid = true;
        self.position = position;
        true
    }
    /// Empties the latch (the held position reads 0).
    #[inline]
    pub fn clear(&mut self) {
        *self = Self::new();
    }
    /// Whether a position is held.
    #[inline]
    pub fn valid(&self) -> bool {
        self.valid
    }
    /// The held position, scale counts (0 when empty).
    #[inline]
    pub fn position(&self) -> i32 {
        self.position
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn captures_once_until_cleared() {
        let mut l = PositionLatch::new();
        assert_eq!((l.valid(), l.position()), (false, 0));
        assert!(l.capture(5));
        assert!(l.valid());
        assert!(!l.capture(7));
        assert_eq!(l.position(), 5);
        l.clear();
        assert!(!l.valid());
        assert_eq!(l.position(), 0, "an empty latch reads 0");
        assert!(l.capture(7));
        assert_eq!(l.position(), 7);
    }

    #[test]
    fn holds_negative_and_extreme_positions() {
        for p in [-1, -123_456, i32::MIN, i32::MAX, 2] {
            let mut l = PositionLatch::new();
            assert!(l.capture(p));
            assert_eq!((l.valid(), l.position()), (true, p));
        }
    }
}
