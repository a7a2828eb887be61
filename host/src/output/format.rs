//! Number formatting for every text the tool prints (Markdown tables, summaries, figure
//! labels): one definition each. No NaN or infinity is printed as such: a value that does not
//! exist is `n/a` (or `none` for an optional value that is absent).

/// Six significant digits, plain notation between 1e-3 and 1e6; `n/a` if not finite.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e6).contains(&a) {
        let d = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.5e}")
    }
}

/// [`num`] of a value that may be absent (`none`).
pub fn opt(v: Option<f64>) -> String {
    v.map_or("none".into(), num)
}

/// Four significant digits, plain notation.
pub fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let d = (3 - v.abs().log10().floor() as i32).clamp(0, 9) as usize;
    format!("{v:.d$}")
}

/// A number for a one-line message: as given when that is short (`-1`, `0.25`, `1e-5`, `inf`),
/// else four significant digits ([`sig4`] between 1e-3 and 1e6, scientific outside: `1.000e300`),
/// never the 300 digits of a plain f64.
pub fn short(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 10 {
        return plain;
    }
    if (1e-3..1e6).contains(&v.abs()) {
        sig4(v)
    } else {
        format!("{v:.3e}")
    }
}

/// Scientific notation with `sig` significant digits, or "n/a".
pub fn sci(v: Option<f64>, sig: usize) -> String {
    match v {
        Some(v) if v.is_finite() => format!("{:.*e}", sig.saturating_sub(1), v),
        _ => "n/a".into(),
    }
}

/// `mean ± sd` with the sd to two significant digits and the mean to the same decimal place.
pub fn pm(mean: f64, sd: f64) -> String {
    if sd.is_nan() || sd <= 0.0 {
        return format!("{} ± 0", num(mean));
    }
    let d = 1 - sd.log10().floor() as i32;
    if d > 9 {
        return format!("{} ± {:.1e}", num(mean), sd);
    }
    let d = d.max(0) as usize;
    format!("{mean:.d$} ± {sd:.d$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formats by hand.
    #[test]
    fn numbers_print_as_stated() {
        assert_eq!((num(123.456789), num(-0.0123456789), num(0.0)), ("123.457".into(), "-0.0123457".into(), "0".into()));
        assert_eq!((num(1.5e7), num(2.5e-4), num(f64::NAN)), ("1.50000e7".into(), "2.50000e-4".into(), "n/a".into()));
        assert_eq!((opt(None), opt(Some(2.0))), ("none".into(), "2.00000".into()));
        assert_eq!((sig4(123.456), sig4(0.0123456)), ("123.5".into(), "0.01235".into()));
        assert_eq!((short(-1.0), short(1e300), short(1e-300), short(0.1 + 0.2)), ("-1".into(), "1.000e300".into(), "1.000e-300".into(), "0.3000".into()));
        assert_eq!((sci(Some(12345.0), 3), sci(None, 3)), ("1.23e4".into(), "n/a".into()));
        assert_eq!((pm(1.23456, 0.0123), pm(2.0, 0.0)), ("1.235 ± 0.012".into(), "2.00000 ± 0".into()));
    }
}
