//! Fixed-decimal formatting of coordinates for the layer files, with the bytes of Rust's own
//! `format!("{v:.N}")` (exact decimal value of the double, rounded half to even) but without its
//! general exact-digit machinery (Grisu with a Dragon fallback), the largest share of the SVG and
//! DXF writers' time at q = 20000 when they used it.
//!
//! A finite double is `m · 2^e` exactly, with `m < 2^53`. Then `v · 10^N = m · 10^N · 2^e`, and
//! `m · 10^N` fits in a `u128` for `N ≤ 12` (53 + 40 bits): scaling is one multiplication and
//! one shift, and the bits shifted out decide the rounding exactly. Values this cannot hold
//! (|v| ≥ 2^53, non-finite, more decimals) take `format!`'s path, so every input gives its bytes.

use std::fmt::Write as _;

/// Most decimals the exact integer path handles: `2^53 · 10^12 < 2^128`.
const MAX_DECIMALS: u32 = 12;

/// Appends `v` with exactly `decimals` digits after the point, byte for byte as
/// `format!("{v:.decimals$}")` writes it (including `-` for negative zero).
pub fn push_fixed(out: &mut String, v: f64, decimals: u32) {
    match scaled(v, decimals) {
        Some(q) => {
            if v.is_sign_negative() {
                out.push('-');
            }
            let unit = 10u64.pow(decimals);
            // Sheet coordinates scale to well under 2^64: 64-bit division is much cheaper than 128-bit.
            let (whole, frac) = match u64::try_from(q) {
                Ok(q) => (u128::from(q / unit), q % unit),
                // The remainder is below `unit` < 2^40.
                Err(_) => (q / u128::from(unit), (q % u128::from(unit)) as u64),
            };
            push_u128(out, whole);
            if decimals > 0 {
                out.push('.');
                let mut digits = [b'0'; MAX_DECIMALS as usize];
                let digits = &mut digits[..decimals as usize];
                let mut rest = frac;
                for d in digits.iter_mut().rev() {
                    *d = b'0' + (rest % 10) as u8;
                    rest /= 10;
                }
                out.push_str(std::str::from_utf8(digits).expect("ASCII digits"));
            }
        }
        None => {
            let _ = write!(out, "{v:.prec$}", prec = decimals as usize);
        }
    }
}

/// Formats a length with 6 decimals, trailing zeros trimmed, never `-0`.
pub fn fmt_mm(v: f64) -> String {
    let mut s = String::new();
    push_mm(&mut s, v);
    s
}

/// Appends `v` as [`fmt_mm`] formats it, without a string of its own: the writers' inner loop.
pub(crate) fn push_mm(out: &mut String, v: f64) {
    let start = out.len();
    push_fixed(out, v, 6);
    if out[start..].contains('.') {
        let trimmed = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + trimmed);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// `|v| · 10^decimals` rounded half to even, or `None` where the integer path does not apply.
fn scaled(v: f64, decimals: u32) -> Option<u128> {
    if !v.is_finite() || decimals > MAX_DECIMALS {
        return None;
    }
    let bits = v.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1u64 << 52) - 1);
    // v = m · 2^e exactly (subnormals have no hidden bit and the smallest exponent).
    let (m, e) = if exponent == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1u64 << 52), exponent - 1075)
    };
    if e >= 0 {
        return None;
    }
    let p = u128::from(m) * 10u128.pow(decimals);
    let shift = (-e) as u32;
    if shift >= 128 {
        // p < 2^93 ≤ 2^(shift - 1): below one half, so it rounds to zero.
        return Some(0);
    }
    let q = p >> shift;
    let rest = p & ((1u128 << shift) - 1);
    let half = 1u128 << (shift - 1);
    let round_up = rest > half || (rest == half && q & 1 == 1);
    Some(q + u128::from(round_up))
}

fn push_u128(out: &mut String, n: u128) {
    match u64::try_from(n) {
        Ok(n) => push_u64(out, n),
        Err(_) => {
            let _ = write!(out, "{n}");
        }
    }
}

/// Appends the decimal digits of `n`.
fn push_u64(out: &mut String, mut n: u64) {
    let mut digits = [0u8; 20];
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.push_str(std::str::from_utf8(&digits[at..]).expect("ASCII digits"));
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fixed(v: f64, decimals: u32) -> String {
        let mut s = String::new();
        push_fixed(&mut s, v, decimals);
        s
    }

    /// The reference is the standard library's own exact formatter (Grisu/Dragon), an independent
    /// implementation of the same rounding.
    fn std_fixed(v: f64, decimals: u32) -> String {
        format!("{v:.prec$}", prec = decimals as usize)
    }

    #[test]
    fn ties_round_to_even_like_the_standard_library() {
        // 2^-13 = 0.0001220703125 and 3 · 2^-13 = 0.0003662109375 are exact ties at 12 decimals.
        assert_eq!(fixed(0.0001220703125, 12), "0.000122070312");
        assert_eq!(fixed(0.0003662109375, 12), "0.000366210938");
        assert_eq!(fixed(2.5, 0), "2");
        assert_eq!(fixed(0.125, 2), "0.12");
        assert_eq!(fixed(0.375, 2), "0.38");
        for (v, n) in [(0.0001220703125, 12), (2.5, 0), (0.125, 2), (0.375, 2)] {
            assert_eq!(fixed(v, n), std_fixed(v, n));
        }
    }

    #[test]
    fn edge_values_match_the_standard_library() {
        let values = [
            0.0,
            -0.0,
            -1e-20,
            1e-300,
            f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            0.0000005,
            0.0000015,
            12.666666666666666,
            -0.049999952316,
            100.049999952316,
            1e20,
            -1e20,
            9007199254740991.0,
            9007199254740992.0,
            4503599627370495.5,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.999999999999_5,
            0.9999995,
        ];
        for v in values {
            for n in [0, 1, 6, 12, 13] {
                assert_eq!(fixed(v, n), std_fixed(v, n), "{v:e} with {n} decimals");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        #[test]
        fn any_double_matches_the_standard_library(bits in any::<u64>(), n in 0u32..=12) {
            let v = f64::from_bits(bits);
            prop_assert_eq!(fixed(v, n), std_fixed(v, n));
        }

        #[test]
        fn sheet_coordinates_match_the_standard_library(
            v in -2000.0f64..2000.0,
            n in prop_oneof![Just(6u32), Just(12u32)],
        ) {
            prop_assert_eq!(fixed(v, n), std_fixed(v, n));
        }

        #[test]
        fn round_grid_values_match_the_standard_library(k in -10_000_000i64..10_000_000, n in 0u32..=12) {
            // Sums and products of round millimetres sit on or next to decimal ties.
            for v in [k as f64 / 1e6, k as f64 * 0.05, k as f64 / 8192.0] {
                prop_assert_eq!(fixed(v, n), std_fixed(v, n));
            }
        }
    }
}
