//! Taking a row: the checks of the time column (strictly increasing, uniform, a gap an
//! error or the start of a block with `--gaps split`) and the hand-over from the preview to the
//! running analysis.

use super::*;

/// An interval at least this many mean intervals long is a gap (time left out: `--gaps
/// split` analyses the blocks around it); a longer interval short of it is jitter.
pub const GAP_MIN_INTERVALS: f64 = 1.25;

impl Analyzer {
    /// Takes one sample: time [s], its printed resolution [s] (0 if exact), the four
    /// accelerations [m/s^2]; `line` is named in errors. The error is one line starting with
    /// "line N" (the caller adds the file).
    pub fn push(&mut self, line: u64, t: f64, t_resolution: f64, a: &[f64; CH]) -> Result<(), String> {
        self.check_time(line, t, t_resolution)?;
        if self.rows == 0 {
            self.t0 = t;
            self.line_first = line;
            self.block_t0 = t;
        }
        let gap = std::mem::take(&mut self.gap_pending);
        if gap {
            self.block_t0 = t;
            self.block_rows = 0;
        }
        self.t_prev = t;
        self.line_prev = line;
        self.rows += 1;
        self.block_rows += 1;
        match &mut self.phase {
            Phase::Running(r) => {
                if gap {
                    r.restart();
                }
                r.process(t, a)
            }
            Phase::Preview(buf) => {
                buf.push(Pending { t, a: *a, gap_before: gap });
                let c = self.cfg.face_coefficient;
                let more = match self.cfg.floor {
                    FloorSource::Range(_, to) => t <= to,
                    // anywhere: the search over the held rows (standard input)
                    FloorSource::Auto => buf.len() < MAX_AUTO_PREVIEW_ROWS,
                    // until a quiet stretch before a signal shows (checked every PREVIEW_ROWS)
                    FloorSource::Lead => {
                        buf.len() < MAX_AUTO_PREVIEW_ROWS
                            && (buf.len() % PREVIEW_ROWS != 0 || {
                                let rel: Vec<f32> = buf.iter().map(|p| a_rel_of(p, c)).collect();
                                find_quiet(&rel).is_none()
                            })
                    }
                    _ => false,
                };
                if more && matches!(self.cfg.floor, FloorSource::Range(..)) && buf.len() >= MAX_QUIET_ROWS {
                    return Err(format!(
                        "line {line}: --quiet: more than {MAX_QUIET_ROWS} rows before its end: give a shorter quiet stretch"
                    ));
                }
                if buf.len() >= PREVIEW_ROWS && !more {
                    self.start(false)?;
                }
            }
        }
        Ok(())
    }

    /// The mean interval of the rows so far, within the blocks [s].
    pub(super) fn mean_interval(&self) -> f64 {
        if self.gaps.is_empty() {
            (self.t_prev - self.t0) / (self.rows - 1) as f64
        } else {
            (self.done_span + (self.t_prev - self.block_t0)) / self.intervals() as f64
        }
    }

    /// The intervals the mean is taken over (within the blocks).
    pub(super) fn intervals(&self) -> u64 {
        if self.gaps.is_empty() {
            self.rows.saturating_sub(1)
        } else {
            self.done_intervals + self.block_rows.saturating_sub(1)
        }
    }

    pub(super) fn check_time(&mut self, line: u64, t: f64, res: f64) -> Result<(), String> {
        use crate::output::format::sig4;
        if !t.is_finite() {
            return Err(format!("line {line}: time {t} is not a finite number"));
        }
        let res_prev = std::mem::replace(&mut self.res_prev, res);
        self.res_max = self.res_max.max(res);
        if self.rows == 0 {
            return Ok(());
        }
        let dt = t - self.t_prev;
        if !(dt > 0.0) {
            let what = if dt == 0.0 { "repeats" } else { "goes back" };
            // too few decimals only where the printed resolution is near the interval
            let coarse = self.rows < 2 || res.max(res_prev) >= 0.25 * self.mean_interval();
            let hint = if dt == 0.0 && res.max(res_prev) > 0.0 && coarse {
                format!(" (printed to {} s: too few decimals for the sampling interval?)", sig4(res.max(res_prev)))
            } else {
                String::new()
            };
            return Err(format!(
                "line {line}: time {} s {what}: it does not come after {} s (line {}): the time column must increase strictly{hint}",
                t,
                self.t_prev,
                self.line_prev
            ));
        }
        if self.rows >= 2 && self.intervals() > 0 {
            let mean = self.mean_interval();
            let eps = 8.0 * f64::EPSILON * t.abs().max(self.t0.abs());
            // each row's time is within half its printed resolution of the truth
            let tol = RATE_TOLERANCE * mean + 0.5 * (res + res_prev) + eps;
            if (dt - mean).abs() > tol {
                let k = dt / mean;
                // a gap leaves out time: a quarter of an interval or more beyond the one
                let gap = k >= GAP_MIN_INTERVALS;
                if gap && self.split_gaps {
                    self.gaps.push(Gap { line, t_before: self.t_prev, t_after: t, intervals: k });
                    self.done_intervals += self.block_rows - 1;
                    self.done_span += self.t_prev - self.block_t0;
                    self.gap_pending = true;
                    return Ok(());
                }
                let whole = k.round();
                let what = if dt > mean && whole >= 2.0 && (dt - whole * mean).abs() <= tol {
                    format!("a drop: {} row{} missing", whole - 1.0, if whole == 2.0 { "" } else { "s" })
                } else if gap {
                    "a gap".to_string()
                } else if dt > mean {
                    "a long interval: timestamps that jitter (an irregular clock), not a gap".to_string()
                } else {
                    "a short interval: a row out of place or an irregular clock".to_string()
                };
                let way_on = if gap { " (--gaps split analyses the contiguous blocks and lists the gaps)" } else { "" };
                return Err(format!(
                    "line {line}: time {} s after {} s (line {}): an interval of {} s where the rows before have a mean interval of {} s ({} of them): {what}; the time column must be uniformly sampled (within 1 % plus the printed resolution){way_on}",
                    sig4(t),
                    sig4(self.t_prev),
                    self.line_prev,
                    sig4(dt),
                    sig4(mean),
                    sig4(k),
                ));
            }
        }
        Ok(())
    }
}
