//! The value parsers of the numeric options: each checks its option's range (the one its
//! `--help` states) while clap parses the command line, before any file is read or any run
//! starts. A value out of range is an [`OutOfRange`], whose message is the project's one line
//! (`--OPTION VALUE: the rule`), printed as it is by `main`; a value that is not a number keeps
//! clap's message.

use crate::limits::{
    ADC_NOISE_MAX_COUNTS, BREAKAWAY_JUMP_MAX_M_S2, FIT_MAX_BOOTSTRAP, FIT_MAX_ITERS, FIT_MAX_STARTS, GAIN_RANGE,
    NOISE_MAX_M_S2, QUIET_LEAD_MAX_S,
};
use crate::output::format::short;

/// A value out of its option's range: the whole line to print (after `error: `).
#[derive(Debug)]
pub struct OutOfRange(pub String);

impl std::fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for OutOfRange {}

type Parsed<T> = Result<T, Box<dyn std::error::Error + Send + Sync>>;

fn number<T: std::str::FromStr>(s: &str) -> Parsed<T>
where
    T::Err: std::fmt::Display,
{
    s.parse::<T>().map_err(|e| e.to_string().into())
}

fn out_of_range<T>(line: String) -> Parsed<T> {
    Err(Box::new(OutOfRange(line)))
}

/// `--segment`: an even number of samples from 16 to 1048576.
pub fn segment(s: &str) -> Parsed<usize> {
    let n: usize = number(s)?;
    if n < 16 || n % 2 != 0 || n > 1 << 20 {
        return out_of_range(format!(
            "--segment {n}: the Welch segment must be an even number of samples from 16 to 1048576"
        ));
    }
    Ok(n)
}

/// `--breakaway-jump`: 0 < J <= 1e6 m/s^2.
pub fn breakaway_jump(s: &str) -> Parsed<f64> {
    let j: f64 = number(s)?;
    if !(j.is_finite() && j > 0.0 && j <= BREAKAWAY_JUMP_MAX_M_S2) {
        return out_of_range(format!(
            "--breakaway-jump {}: must be an acceleration with 0 < J <= {} m/s^2",
            short(j),
            short(BREAKAWAY_JUMP_MAX_M_S2)
        ));
    }
    Ok(j)
}

/// `--from`: a finite time.
pub fn from_time(s: &str) -> Parsed<f64> {
    let t: f64 = number(s)?;
    if !t.is_finite() {
        return out_of_range(format!("--from {}: must be a finite time in s", short(t)));
    }
    Ok(t)
}

/// `map --kick`: 0 < kick <= 0.5.
pub fn kick(s: &str) -> Parsed<f64> {
    let k: f64 = number(s)?;
    if !(k.is_finite() && k > 0.0 && k <= 0.5) {
        return out_of_range(format!("--kick {k}: must satisfy 0 < kick <= 0.5"));
    }
    Ok(k)
}

/// `OPTION`: a count from 1 to `max` (`one` thing, `many` things).
fn count<T>(s: &str, option: &str, max: T, one: &str, many: &str) -> Parsed<T>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + From<u8>,
    T::Err: std::fmt::Display,
{
    let n: T = number(s)?;
    if n < T::from(1) {
        return out_of_range(format!("{option} {n}: at least 1 {one}"));
    }
    if n > max {
        return out_of_range(format!("{option} {n}: at most {max} {many}"));
    }
    Ok(n)
}

/// `fit --starts`: 1 to 1000.
pub fn starts(s: &str) -> Parsed<usize> {
    count(s, "--starts", FIT_MAX_STARTS, "start", "starts")
}

/// `fit --max-iters`: 1 to 1000000.
pub fn max_iters(s: &str) -> Parsed<u64> {
    count(s, "--max-iters", FIT_MAX_ITERS, "iteration", "iterations")
}

/// `fit --bootstrap`: 0 to 100000.
pub fn bootstrap(s: &str) -> Parsed<usize> {
    let n: usize = number(s)?;
    if n > FIT_MAX_BOOTSTRAP {
        return out_of_range(format!("--bootstrap {n}: at most {FIT_MAX_BOOTSTRAP} resamples"));
    }
    Ok(n)
}

/// One of `fit --horizons`: a finite number of periods, >= 0.
pub fn horizon(s: &str) -> Parsed<f64> {
    let n: f64 = number(s)?;
    if !(n.is_finite() && n >= 0.0) {
        return out_of_range(format!(
            "--horizons {n}: a horizon is a number of stick-slip periods, finite and >= 0 (0: none)"
        ));
    }
    Ok(n)
}

/// `OPTION`: a finite value from 0 to `max` [`unit`].
fn from_zero(s: &str, option: &str, max: f64, what: &str, unit: &str) -> Parsed<f64> {
    let v: f64 = number(s)?;
    if !(v.is_finite() && (0.0..=max).contains(&v)) {
        return out_of_range(format!("{option} {}: {what} must be from 0 to {} {unit}", short(v), short(max)));
    }
    Ok(v)
}

/// `--noise`: 0 to 10000 m/s^2 rms.
pub fn noise(s: &str) -> Parsed<f64> {
    from_zero(s, "--noise", NOISE_MAX_M_S2, "the sensor noise", "m/s^2 rms")
}

/// `--quiet-lead`: 0 to 60 s.
pub fn quiet_lead(s: &str) -> Parsed<f64> {
    from_zero(s, "--quiet-lead", QUIET_LEAD_MAX_S, "the quiet lead", "s")
}

/// `--adc-noise`: 0 to 4096 counts rms.
pub fn adc_noise(s: &str) -> Parsed<f64> {
    from_zero(s, "--adc-noise", ADC_NOISE_MAX_COUNTS, "the converter noise", "counts rms")
}

/// One of `--gain`: 0.001 to 1000 V/V.
pub fn gain(s: &str) -> Parsed<f64> {
    let g: f64 = number(s)?;
    let (lo, hi) = GAIN_RANGE;
    if !(g.is_finite() && g >= lo && g <= hi) {
        return out_of_range(format!(
            "--gain {}: the front-end gain must be from {} to {} V/V",
            short(g),
            short(lo),
            short(hi)
        ));
    }
    Ok(g)
}
