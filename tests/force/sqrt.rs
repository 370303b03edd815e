//! The force estimator's square root (`sqrt_fx`, `fixed`'s own `checked_sqrt`) is the exact
//! floor of the true root in the last I32F32 bit: equal to the integer square root of the
//! raw bits shifted by 32 for every input the property draws, and at the edges.

use proptest::prelude::*;
use tooltouch_model::force::estimator::sqrt_fx;
use tooltouch_model::units::Fx;

/// The reference: `floor(√(bits · 2³²))` in integers, 0 for a negative input.
fn exact_floor_root(x: Fx) -> Fx {
    let bits = x.to_bits();
    if bits <= 0 {
        return Fx::ZERO;
    }
    let root = ((bits as u128) << 32).isqrt();
    Fx::from_bits(i64::try_from(root).expect("a root below 2^48"))
}

#[test]
fn the_edges_match_the_exact_floor_root() {
    let mut edges = vec![
        Fx::ZERO,
        Fx::DELTA,
        -Fx::DELTA,
        Fx::MIN,
        Fx::MAX,
        Fx::MAX - Fx::DELTA,
        Fx::ONE,
        Fx::from_num(2),
    ];
    // Perfect squares of raw roots and their neighbours, across the whole range.
    for shift in 0..48 {
        let r: i64 = 1 << shift;
        for root in [r - 1, r, r + 1] {
            let square = (root as i128 * root as i128) >> 32;
            if let Ok(bits) = i64::try_from(square) {
                for b in [bits - 1, bits, bits + 1] {
                    edges.push(Fx::from_bits(b));
                }
            }
        }
    }
    for x in edges {
        assert_eq!(
            sqrt_fx(x),
            exact_floor_root(x),
            "sqrt of {x} (bits {})",
            x.to_bits()
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn every_input_matches_the_exact_floor_root(bits in any::<i64>()) {
        let x = Fx::from_bits(bits);
        prop_assert_eq!(sqrt_fx(x), exact_floor_root(x));
    }

    #[test]
    fn small_inputs_match_the_exact_floor_root(bits in 0i64..(1 << 40)) {
        let x = Fx::from_bits(bits);
        prop_assert_eq!(sqrt_fx(x), exact_floor_root(x));
    }
}
