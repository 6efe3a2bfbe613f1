//! Real numbers as STEP (ISO 10303-21 §6.3.3) and IGES (§2.2.2.3) readers expect them.
//!
//! Both formats want a decimal point in every real and an upper-case `E` before an exponent:
//! `3.`, `-0.5`, `2.08E-17`. Rust's own shortest round-trip text (`3`, `2.08e-17`) is not
//! that syntax — FreeCAD 0.20 silently reads wrong geometry from it — so the digits are taken
//! from Rust's shortest round-trip formatting (every value reads back to the same `f64`) and
//! only the punctuation is changed. Magnitudes in `[1e-4, 1e15)` are written positionally
//! (`0.25`), others with an exponent (`1.5E-7`, `1.E20`).

use std::fmt::Write;

/// Appends `x` in STEP/IGES real syntax to `out`. `x` must be finite (callers check: the
/// writers refuse non-finite input before writing anything).
pub fn push_real(out: &mut String, x: f64) {
    debug_assert!(x.is_finite(), "non-finite real {x}");
    if x == 0.0 {
        out.push_str("0.");
        return;
    }
    let a = x.abs();
    if (1e-4..1e15).contains(&a) {
        let start = out.len();
        let _ = write!(out, "{x}");
        if !out[start..].contains('.') {
            out.push('.');
        }
        return;
    }
    // `{:e}` is the shortest round-trip mantissa: `2.08e-17`, `1e20`.
    let text = format!("{x:e}");
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    out.push_str(mantissa);
    if !mantissa.contains('.') {
        out.push('.');
    }
    out.push('E');
    out.push_str(exponent);
}

/// `x` in STEP/IGES real syntax (see [`push_real`]).
#[must_use]
pub fn real(x: f64) -> String {
    let mut s = String::new();
    push_real(&mut s, x);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_have_a_point_an_upper_case_exponent_and_round_trip() {
        for (x, text) in [
            (0.0, "0."),
            (-0.0, "0."),
            (3.0, "3."),
            (-3.0, "-3."),
            (0.25, "0.25"),
            (2.08e-17, "2.08E-17"),
            (1e20, "1.E20"),
            (-1.5e-7, "-1.5E-7"),
            (1e15, "1.E15"),
            (123456.5, "123456.5"),
        ] {
            assert_eq!(real(x), text, "{x:e}");
        }
        // Random bit patterns of finite doubles read back exactly (Rust's parser reads the
        // `E` and the bare trailing point).
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..20_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            if !x.is_finite() {
                continue;
            }
            let t = real(x);
            assert!(t.contains('.') && !t.contains('e'), "{t}");
            assert_eq!(t.parse::<f64>().ok(), Some(x), "{t}");
        }
    }
}
