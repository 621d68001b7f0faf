//! Number formatting for people: one home for the styles the reports use.
//!
//! Each quantity is printed at a precision that fits it (the exact value
//! stays in JSON): translations and lengths to 0.1 mm ([`metres`]), angles
//! to 0.001 deg ([`degrees`]), ratios to four significant digits ([`ratio`]),
//! unit-vector and rotation entries to six decimals ([`unit()`]). A value
//! below the resolution prints `0` (never `-0.0000` nor `1.1102e-16`).
//! Vectors are `[a, b, c]` everywhere ([`vector`]). The resolutions are
//! defined here, where they are used: they are how numbers are printed, not
//! tolerances of the analysis (which keeps every digit).

/// A translation or length printed for people has this resolution (m): 0.1 mm,
/// finer than any published extrinsic calibration. Smaller magnitudes print 0.
pub const PRINT_LENGTH_RES_M: f64 = 1e-4;

/// An angle printed for people has this resolution (deg); smaller print 0.
pub const PRINT_ANGLE_RES_DEG: f64 = 1e-3;

/// Significant digits of a ratio printed for people (band edges, singular
/// values, eigenvalue ratios).
pub const PRINT_RATIO_DIGITS: usize = 4;

/// A ratio or dimensionless value below this magnitude prints 0 (rounding of
/// a composed chain, e.g. `1.1102e-16`); the exact value stays in JSON.
pub const PRINT_RATIO_ZERO: f64 = 1e-12;

/// Decimals of a resolution given as a power of ten (`1e-4` -> 4).
fn decimals_of(res: f64) -> usize {
    (-res.log10()).round().max(0.0) as usize
}

/// `x` to the resolution `res`; `0` when it rounds to zero.
fn at_resolution(x: f64, res: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x.abs() < res / 2.0 {
        return "0".into();
    }
    fixed(x, decimals_of(res))
}

/// A translation or length (m) to 0.1 mm ([`PRINT_LENGTH_RES_M`]).
pub fn metres(x: f64) -> String {
    at_resolution(x, PRINT_LENGTH_RES_M)
}

/// An angle (deg) to 0.001 deg ([`PRINT_ANGLE_RES_DEG`]).
pub fn degrees(x: f64) -> String {
    at_resolution(x, PRINT_ANGLE_RES_DEG)
}

/// An angle (deg) to 0.001 deg with trailing zeros cut (`90`, `-1.5`): the
/// pictures' edge labels, where every character counts.
pub fn degrees_trimmed(x: f64) -> String {
    let s = fixed(x, 3);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// An entry of a rotation matrix, a quaternion or a unit axis: six decimals
/// (1e-6 rad is 0.00006 deg, below the angle resolution), trailing zeros
/// dropped (`1`, `-0.707107`).
pub fn unit(x: f64) -> String {
    let s = at_resolution(x, 1e-6);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A ratio or other dimensionless value to [`PRINT_RATIO_DIGITS`] significant
/// digits: fixed for ordinary magnitudes, scientific otherwise; `0` below
/// [`PRINT_RATIO_ZERO`].
pub fn ratio(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if a < PRINT_RATIO_ZERO {
        return "0".into();
    }
    let digits = PRINT_RATIO_DIGITS.max(1);
    if (1e-3..1e5).contains(&a) {
        let mag = a.log10().floor() as i32;
        let dec = (digits as i32 - 1 - mag).max(0) as usize;
        // 9.99995 rounds up to 10.000: one decimal fewer then.
        let s = fixed(x, dec);
        let rounded_up = s
            .parse::<f64>()
            .is_ok_and(|r| r.abs() >= 10f64.powi(mag + 1));
        if dec > 0 && rounded_up {
            return fixed(x, dec - 1);
        }
        s
    } else {
        format!("{x:.prec$e}", prec = digits - 1)
    }
}

/// `[a, b, c]`, each entry printed by `f`: the one vector style.
pub fn vector(v: &[f64], f: fn(f64) -> String) -> String {
    format!(
        "[{}]",
        v.iter().map(|&x| f(x)).collect::<Vec<_>>().join(", ")
    )
}

/// Fixed decimals, with `-0.000` printed as `0.000`.
pub fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// A short number for tables: fixed for ordinary magnitudes, scientific otherwise.
pub fn short(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        fixed(x, 6)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{x:.3e}")
    }
}

/// One number for the detector tables: `prec` decimals for ordinary
/// magnitudes, scientific otherwise; `0` below [`PRINT_RATIO_ZERO`]
/// (rounding noise of a unit twist, `2.498e-16`).
pub fn sci(x: f64, prec: usize) -> String {
    let a = x.abs();
    if a < PRINT_RATIO_ZERO {
        return "0".into();
    }
    if (0.1..1e4).contains(&a) {
        format!("{x:.prec$}")
    } else {
        format!("{x:.prec$e}")
    }
}

/// `[a, b, c]` of [`sci`] numbers (the one vector style).
pub fn sci_vec(v: &[f64], prec: usize) -> String {
    let s: Vec<String> = v.iter().map(|&x| sci(x, prec)).collect();
    format!("[{}]", s.join(", "))
}

/// `h` in metres for the survey: four decimals, or two significant digits
/// below a millimetre.
pub fn metres_h(h: f64) -> String {
    if h == 0.0 {
        "0".into()
    } else if h.abs() < 1e-3 {
        format!("{h:.1e}")
    } else {
        fixed(h, 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_quantity_at_its_resolution() {
        assert_eq!(metres(-0.3640000001), "-0.3640");
        assert_eq!(metres(0.14226), "0.1423");
        assert_eq!(metres(-4e-5), "0");
        assert_eq!(metres(1.1102e-16), "0");
        assert_eq!(degrees(89.99999999), "90.000");
        assert_eq!(degrees(-0.0004), "0");
        assert_eq!(degrees(14.36), "14.360");
        assert_eq!(unit(1.0), "1");
        assert_eq!(unit(-std::f64::consts::FRAC_1_SQRT_2), "-0.707107");
        assert_eq!(unit(-1e-17), "0");
        assert_eq!(degrees_trimmed(-90.0), "-90");
        assert_eq!(degrees_trimmed(1.23456), "1.235");
        assert_eq!(degrees_trimmed(12.5), "12.5");
        assert_eq!(degrees_trimmed(-0.0001), "0");
    }

    #[test]
    fn ratios_have_four_significant_digits() {
        assert_eq!(ratio(1.474539), "1.475");
        assert_eq!(ratio(0.237773), "0.2378");
        assert_eq!(ratio(4.205697), "4.206");
        assert_eq!(ratio(123.456), "123.5");
        assert_eq!(ratio(9.99996), "10.00");
        assert_eq!(ratio(1.1102e-16), "0");
        assert_eq!(ratio(-2.5e-7), "-2.500e-7");
        assert_eq!(ratio(1.0), "1.000");
    }

    #[test]
    fn one_vector_style() {
        assert_eq!(
            vector(&[-0.364, 0.0, 0.1422], metres),
            "[-0.3640, 0, 0.1422]"
        );
        assert_eq!(sci_vec(&[1.0, 2.498e-16], 3), "[1.000, 0]");
    }
}
