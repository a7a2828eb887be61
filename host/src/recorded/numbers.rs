//! Decimal numbers as loggers and spreadsheets print them: `-1.25`, `1,25` (decimal comma),
//! `3.9e-5`, `+7`, `.5`, `5.`. ASCII only, no thousands separators, no `NaN`/`inf`.
//!
//! The common case (at most 19 significant digits, a power of ten within 1e±22) is converted
//! with one multiplication or division by an exact power of ten, which is correctly rounded
//! (Clinger's fast path); anything else goes to the standard library's parser. Both give the
//! nearest f64 to the printed decimal.

/// Powers of ten that are exact in f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// A parsed number: its value and the decimal exponent of its last printed digit (the
/// printed resolution is 10^`last_digit_exp`: `0.000039` gives -6, `1.5e-3` gives -4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decimal {
    pub value: f64,
    pub last_digit_exp: i32,
}

impl Decimal {
    /// The place value of the last printed digit.
    pub fn resolution(&self) -> f64 {
        10f64.powi(self.last_digit_exp.clamp(-300, 300))
    }
}

/// Parses `s` (already trimmed). `comma`: a `,` is accepted as the decimal separator as well
/// as `.`. `None` if `s` is not a decimal number. The value may be infinite for huge
/// exponents (`1e999`): the caller checks the range.
pub fn parse(s: &[u8], comma: bool) -> Option<Decimal> {
    let n = s.len();
    let mut i = 0;
    let neg = match *s.first()? {
        b'-' => {
            i = 1;
            true
        }
        b'+' => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut mant: u64 = 0;
    let mut sig = 0u32; // significant digits in `mant`
    let mut overflow = false;
    let mut digits = 0u32;
    fn push(d: u8, mant: &mut u64, sig: &mut u32, overflow: &mut bool) {
        if *mant == 0 && d == 0 {
            return; // a leading zero
        }
        if *sig >= 19 {
            *overflow = true;
        } else {
            *mant = *mant * 10 + d as u64;
            *sig += 1;
        }
    }
    while i < n && s[i].is_ascii_digit() {
        push(s[i] - b'0', &mut mant, &mut sig, &mut overflow);
        digits += 1;
        i += 1;
    }
    let mut frac: i32 = 0;
    if i < n && (s[i] == b'.' || (comma && s[i] == b',')) {
        i += 1;
        while i < n && s[i].is_ascii_digit() {
            push(s[i] - b'0', &mut mant, &mut sig, &mut overflow);
            digits += 1;
            frac += 1;
            i += 1;
        }
    }
    if digits == 0 {
        return None;
    }
    let mut exp: i32 = 0;
    if i < n && (s[i] == b'e' || s[i] == b'E') {
        i += 1;
        let eneg = match s.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let mut ed = 0;
        while i < n && s[i].is_ascii_digit() {
            if exp < 100_000 {
                exp = exp * 10 + (s[i] - b'0') as i32;
            }
            ed += 1;
            i += 1;
        }
        if ed == 0 {
            return None;
        }
        if eneg {
            exp = -exp;
        }
    }
    if i != n {
        return None;
    }
    let e10 = exp - frac;
    let value = if !overflow && mant < (1u64 << 53) && (-22..=22).contains(&e10) {
        let m = mant as f64;
        if e10 >= 0 {
            m * POW10[e10 as usize]
        } else {
            m / POW10[(-e10) as usize]
        }
    } else {
        slow(s, comma)?.abs()
    };
    Some(Decimal { value: if neg { -value } else { value }, last_digit_exp: e10 })
}

/// The standard library's parser, after turning a decimal comma into a point (the input
/// was validated above: ASCII digits, one separator, an exponent).
fn slow(s: &[u8], comma: bool) -> Option<f64> {
    let text: String = s
        .iter()
        .map(|&b| if comma && b == b',' { '.' } else { b as char })
        .collect();
    text.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(s: &str, comma: bool) -> Option<f64> {
        parse(s.as_bytes(), comma).map(|d| d.value)
    }

    #[test]
    fn forms() {
        assert_eq!(v("1.25", false), Some(1.25));
        assert_eq!(v("-1,25", true), Some(-1.25));
        assert_eq!(v("-1,25", false), None);
        assert_eq!(v("1.25", true), Some(1.25));
        assert_eq!(v("+7", false), Some(7.0));
        assert_eq!(v(".5", false), Some(0.5));
        assert_eq!(v("5.", false), Some(5.0));
        assert_eq!(v("3.9e-5", false), Some(3.9e-5));
        assert_eq!(v("3,9E+2", true), Some(390.0));
        for bad in ["", "-", ".", "e5", "1e", "1.2.3", "1,2", "abc", "1 2", "nan", "inf", "0x10", "1e+"] {
            assert_eq!(v(bad, false), None, "{bad}");
        }
        assert_eq!(v("1,2,3", true), None);
    }

    #[test]
    fn correctly_rounded_against_std() {
        for s in [
            "0.1", "0.000039", "123456789012345678901234", "1.7976931348623157e308", "4.9e-324",
            "0.30000000000000004", "25600.000000000004", "9007199254740993", "1e-30", "-0.0",
        ] {
            assert_eq!(v(s, false), s.parse::<f64>().ok(), "{s}");
        }
    }

    #[test]
    fn resolution() {
        assert_eq!(parse(b"0.000039", false).unwrap().last_digit_exp, -6);
        assert_eq!(parse(b"1.5e-3", false).unwrap().last_digit_exp, -4);
        assert_eq!(parse(b"12", false).unwrap().last_digit_exp, 0);
        assert_eq!(parse(b"1,00", true).unwrap().last_digit_exp, -2);
    }
}
