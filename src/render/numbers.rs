//! Number formatting for people: one home for the styles the reports use.

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

/// `[a, b, c]` with fixed decimals (the rig report's vectors).
pub fn vec_str(v: &[f64], decimals: usize) -> String {
    format!(
        "[{}]",
        v.iter()
            .map(|x| fixed(*x, decimals))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// One number for the detector tables: `prec` decimals for ordinary
/// magnitudes, scientific otherwise.
pub fn sci(x: f64, prec: usize) -> String {
    let a = x.abs();
    if x == 0.0 || (0.1..1e4).contains(&a) {
        format!("{x:.prec$}")
    } else {
        format!("{x:.prec$e}")
    }
}

/// `[a b c]` in the detector tables' style.
pub fn sci_vec(v: &[f64], prec: usize) -> String {
    let s: Vec<String> = v.iter().map(|&x| sci(x, prec)).collect();
    format!("[{}]", s.join(" "))
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
