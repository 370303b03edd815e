//! The cross-slide's linear scale (docs/domain.md §1): the radial position of the tool in counts of
//! `resolution_um`, as x4 quadrature lines A and B.
//!
//! Count `c` means the tool's radial position (distance from the spindle axis) is in
//! `[c·res, (c+1)·res)`. Its lines are the phase `c mod 4` in the decoder's order
//! 00 → 10 → 11 → 01 (A leads B for increasing radius); home positions are chosen with
//! `c ≡ 0 (mod 4)`, so the lines start at 00 like the decoder's power-on phase.

/// Quadrature lines (A, B) for scale count `c`.
pub fn lines(count: i64) -> (bool, bool) {
    match count.rem_euclid(4) {
        0 => (false, false),
        1 => (true, false),
        2 => (true, true),
        _ => (false, true),
    }
}

/// A linear motion of the cross slide over a span of clocks: radial position
/// `x(t) = start_um + speed_um_per_cycle · (t - t0)`, µm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Clock at which the motion starts.
    pub t0: f64,
    /// Radial position at `t0`, µm.
    pub start_um: f64,
    /// Radial speed, µm per clock (negative toward the workpiece).
    pub speed_um_per_cycle: f64,
}

impl Motion {
    /// Standing still at `x_um`.
    pub fn hold(x_um: f64) -> Motion {
        Motion {
            t0: 0.0,
            start_um: x_um,
            speed_um_per_cycle: 0.0,
        }
    }

    /// Radial position at (real) clock `t`, µm.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        self.start_um + self.speed_um_per_cycle * (t - self.t0)
    }
}

/// Count changes of the scale while the slide moves by `motion` in clocks `(k_a, k_b)`,
/// starting from count `count` at `k_a`: `(clock, new count)`, at least `min_gap` clocks
/// apart (a real scale's lines cannot change faster than its interpolator allows; the
/// retract speed is validated so this never bites). A count changes at the first whole
/// clock at which the position is past the count's boundary.
pub fn count_changes(
    motion: &Motion,
    resolution_um: f64,
    count: i64,
    k_a: u64,
    k_b: u64,
    min_gap: u64,
    out: &mut Vec<(u64, i64)>,
) {
    let v = motion.speed_um_per_cycle;
    if v == 0.0 {
        return;
    }
    let mut c = count;
    let mut last = k_a;
    loop {
        // Next boundary in the direction of motion.
        let (boundary, next) = if v > 0.0 {
            ((c + 1) as f64 * resolution_um, c + 1)
        } else {
            (c as f64 * resolution_um, c - 1)
        };
        let t = motion.t0 + (boundary - motion.start_um) / v;
        let mut k = if v > 0.0 {
            t.ceil().max(0.0) as u64
        } else {
            t.floor().max(-1.0) as u64 + 1
        };
        k = k.max(last + if out.is_empty() { 1 } else { min_gap });
        if k >= k_b {
            return;
        }
        out.push((k, next));
        last = k;
        c = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_step_through_the_decoder_phases() {
        assert_eq!(lines(0), (false, false));
        assert_eq!(lines(1), (true, false));
        assert_eq!(lines(-1), (false, true));
        assert_eq!(lines(200_000), (false, false));
    }

    #[test]
    fn approach_counts_down_at_the_boundaries() {
        // 0.25 µm counts (binary-exact numbers), 1/32 µm per clock toward the axis.
        let m = Motion {
            t0: 0.0,
            start_um: 100.125,
            speed_um_per_cycle: -0.03125,
        };
        let mut out = Vec::new();
        count_changes(&m, 0.25, 400, 0, 30, 1, &mut out);
        // x(4) = 100.0 exactly still counts 400; x < 100.0 from clock 5 on.
        assert_eq!(out, vec![(5, 399), (13, 398), (21, 397), (29, 396)]);
    }
}
