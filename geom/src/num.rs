//! Numbers in messages: [`Compact`] prints a double as `{}` does at ordinary magnitudes and in
//! exponent form beyond them, so that an error about `1e308` says `1e308`, not the 309 digits
//! of its decimal expansion.
//!
//! With `m = |x|`, the form is
//!
//! * `{}` (the shortest decimal that reads back as `x`, no exponent) when `x = 0` or
//!   `1e-4 ≤ m < 1e15`;
//! * `{:e}` (the shortest mantissa that reads back as `x`, e.g. `1e308`, `5e-324`,
//!   `1.7976931348623157e308`) otherwise;
//! * `NaN`, `inf` and `-inf` as they are.
//!
//! A precision (`{:.3}`) is kept in both forms (`{:.3}` or `{:.3e}`). Every printed number
//! still reads back as the same double when no precision is given.

use std::fmt;

/// A double printed compactly (see the [module docs](self)): `Compact(1e308)` prints `1e308`,
/// `Compact(0.25)` prints `0.25`, `Compact(1e-310)` prints `1e-310`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compact(pub f64);

/// Below this magnitude (and above zero) a number is printed in exponent form.
const SMALLEST_PLAIN: f64 = 1e-4;
/// From this magnitude on a number is printed in exponent form.
const LARGEST_PLAIN: f64 = 1e15;

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let m = x.abs();
        let plain = x == 0.0 || !x.is_finite() || (SMALLEST_PLAIN..LARGEST_PLAIN).contains(&m);
        match (plain, f.precision()) {
            (true, None) => write!(f, "{x}"),
            (true, Some(p)) => write!(f, "{x:.p$}"),
            (false, None) => write!(f, "{x:e}"),
            (false, Some(p)) => write!(f, "{x:.p$e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Compact;

    #[test]
    fn ordinary_numbers_print_as_display_and_extreme_ones_in_exponent_form() {
        let cases: [(f64, &str); 14] = [
            (0.0, "0"),
            (-0.0, "-0"),
            (0.25, "0.25"),
            (-3.0, "-3"),
            (1e-4, "0.0001"),
            (123_456.789, "123456.789"),
            (999_999_999_999_999.0, "999999999999999"),
            (1e15, "1e15"),
            (1e308, "1e308"),
            (-1e308, "-1e308"),
            (f64::MAX, "1.7976931348623157e308"),
            (5e-324, "5e-324"),
            (1e-310, "1e-310"),
            (9.9e-5, "9.9e-5"),
        ];
        for (x, want) in cases {
            assert_eq!(Compact(x).to_string(), want, "{x:e}");
        }
        assert_eq!(Compact(f64::NAN).to_string(), "NaN");
        assert_eq!(Compact(f64::NEG_INFINITY).to_string(), "-inf");
    }

    #[test]
    fn a_precision_is_kept_in_both_forms() {
        assert_eq!(format!("{:.3}", Compact(2.0)), "2.000");
        assert_eq!(format!("{:.3}", Compact(1e30)), "1.000e30");
        assert_eq!(format!("{:.2}", Compact(-1e-300)), "-1.00e-300");
    }

    #[test]
    fn every_printed_number_reads_back_as_itself() {
        // A fixed-seed walk over magnitudes from 1e-320 to 1e308.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..2000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            if !x.is_finite() {
                continue;
            }
            let text = Compact(x).to_string();
            assert!(text.len() <= 25, "{text}");
            assert_eq!(text.parse::<f64>().ok(), Some(x), "{text}");
        }
    }
}
