//! The Illinois method (regula falsi with the stale end's value halved), as the event runners
//! locate a guard or an extreme inside a step: on the step's own solution, so the state at the
//! located time comes with it.

/// The sign change of a function on [lo, hi] in fractions of a step: `flo` = f(lo) and `fhi` =
/// f(hi) of opposite signs (or `fhi` = 0 for a guard, which fires at zero), `phi` the payload
/// (the state) at hi. `eval(x)` gives f(x) and its payload. The lo side keeps f(lo)'s sign, a
/// zero belongs to the hi side; stops when hi - lo <= `tol` or after `iterations`. Returns the
/// smallest fraction found past the change and its payload.
#[inline]
pub fn locate<P>(
    (mut lo, mut flo): (f64, f64),
    (mut hi, mut fhi, mut phi): (f64, f64, P),
    tol: f64,
    iterations: u32,
    mut eval: impl FnMut(f64) -> (f64, P),
) -> (f64, P) {
    let neg = flo < 0.0;
    let mut side = 0i32;
    for _ in 0..iterations {
        if hi - lo <= tol {
            break;
        }
        let mut x = if fhi != flo { (lo * fhi - hi * flo) / (fhi - flo) } else { 0.5 * (lo + hi) };
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let (fx, p) = eval(x);
        if if neg { fx < 0.0 } else { fx > 0.0 } {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            fhi = fx;
            phi = p;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        }
    }
    (hi, phi)
}
