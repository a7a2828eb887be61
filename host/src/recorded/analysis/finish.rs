//! The statistics of a finished analysis ([`Analyzer::finish`]).

use super::*;

/// A pad_x whose standard deviation exceeds this fraction of the stick level moves: with the
/// scene's thresholds (no quiet rows) and no slip onset, its stick fraction is not told
/// (noise of a clamped pad is far below: 0.01 to 0.1 m/s^2 against a stick level of 8.3).
pub const MOVING_FRACTION_OF_STICK_LEVEL: f64 = 0.1;

impl Analyzer {
    /// The statistics. Errors (one line, starting with what is wrong): no rows, a single row,
    /// no row at or after `from_s`.
    pub fn finish(mut self) -> Result<Analysis, String> {
        if self.rows == 0 {
            return Err("no data rows".into());
        }
        if self.rows == 1 {
            return Err(format!("line {}: a single data row: the sample rate needs at least two", self.line_first));
        }
        if matches!(self.phase, Phase::Preview(_)) {
            self.start()?;
        }
        let mean_interval = self.mean_interval();
        let Phase::Running(r) = self.phase else { unreachable!("started above") };
        let mut r = *r;
        r.flush_held();
        if r.n == 0 {
            return Err(format!(
                "--from {} s: no row at or after it (the last row, line {}, is at {} s)",
                self.cfg.from_s, self.line_prev, self.t_prev
            ));
        }
        let sample_rate_hz = if self.gaps.is_empty() {
            (self.rows - 1) as f64 / (self.t_prev - self.t0)
        } else {
            1.0 / mean_interval
        };
        if r.floor.is_none() && self.floor_note.is_none() && self.cfg.floor == FloorSource::Auto {
            self.floor_note = Some(format!("no quiet rows found in the first {MAX_AUTO_PREVIEW_ROWS} rows read from standard input"));
        }
        let hz_pooled = r.hz();
        let spectrum = r.welch.and_then(|w| w.finish(sample_rate_hz));
        let n = r.n as f64;
        let channels = std::array::from_fn(|c| ChannelStats {
            pp: r.extremes.pp(c),
            rms: (r.sq[c] / n).sqrt(),
            mean: r.sum[c] / n,
            min: r.extremes.min[c],
            max: r.extremes.max[c],
            // a constant channel has no spectral peak (its segments' round-off is not one)
            peak_hz: spectrum.as_ref().and_then(|s| s.peak(c)).map(|p| p.1).filter(|_| r.extremes.pp(c) > 0.0),
            groan_rms: (r.groan_sq[c] / n).sqrt(),
            step: if r.step[c].is_finite() { r.step[c] } else { 0.0 },
        });
        let stick_slip_hz = hz_pooled;
        let thresholds = *r.rig.estimator().contact().thresholds();
        // the rig's rule (stickslip_model::rig::health): flat, saturated, noisier than the
        // signal; pad_x must carry a signal, disc_x must not be saturated
        let present = self.present;
        let verdict = HealthReport::new(std::array::from_fn(|c| {
            if !present[c] {
                return ChannelHealth::default();
            }
            ChannelHealth::assess(
                channels[c].pp as f32,
                channels[c].rms as f32,
                r.at_range_ch[c] > 0 || self.at_full_scale[c] >= super::super::wav::FULL_SCALE_MIN_SAMPLES,
                // a floor found in the stick phases is a noise floor of a_rel, pad_x and disc_x
                // only: the pad still rotates in stick, so the edge sensors' is not theirs
                r.floor.as_ref().filter(|f| f.quiet_blocks == 0 || c == PAD_X || c == DISC_X).map(|f| (f.report.mean_m_s2[c], f.report.sigma_m_s2[c])),
            )
        }));
        let health: [Vec<&'static str>; CH] = std::array::from_fn(|c| verdict.channels[c].words().collect());
        let undecided = verdict.undecidable().then(|| {
            let mut bad = vec![];
            for (c, name) in [(PAD_X, "pad_x"), (DISC_X, "disc_x")] {
                for what in verdict.channels[c].words() {
                    if !(c == DISC_X && what == "flat") {
                        bad.push(format!("{name} {what}"));
                    }
                }
            }
            format!("{}: the contact estimate (stick fraction, frequency) would be a guess", bad.join(", "))
        });
        // the estimator starts at START_RUN quiet rows in a row (Running::process): a shorter
        // record never runs it, and its rows would all count as slip
        let short = (self.rows < START_RUN as u64).then(|| {
            format!(
                "{} rows: the rig's estimator starts at {START_RUN} rows in a row within its stick level, so a record of fewer rows never runs it",
                self.rows
            )
        });
        // thresholds from the scene's breakaway jump because no quiet rows were found (the
        // floor's note says why; not a jump the user gave): a pad that moves without one onset
        // above the scene's level may slip below it (a sliding oscillation) or stick: the
        // estimate cannot tell
        let pad_sd = (channels[PAD_X].rms.powi(2) - channels[PAD_X].mean.powi(2)).max(0.0).sqrt();
        let stick_level = f64::from(thresholds.stick_max_m_s2);
        let below_guess = (r.floor.is_none()
            && self.floor_note.is_some()
            && r.onsets.count() == 0
            && pad_sd > MOVING_FRACTION_OF_STICK_LEVEL * stick_level)
            .then(|| {
                format!(
                    "no quiet rows set the contact thresholds, and pad_x moves (standard deviation {} m/s^2) without one slip onset \
                     above the scene's level ({} m/s^2, from its breakaway jump): a slip below it cannot be told from stick \
                     (give --quiet FROM:TO or --breakaway-jump)",
                    crate::output::format::short(pad_sd),
                    crate::output::format::short(f64::from(thresholds.slip_onset_m_s2))
                )
            });
        // every reason the contact estimate is not told, in this order
        let reasons: Vec<String> = [short, undecided, below_guess].into_iter().flatten().collect();
        let undecided = (!reasons.is_empty()).then(|| reasons.join("; "));
        Ok(Analysis {
            channels,
            stick_fraction: r.stick as f64 / n,
            stick_slip_hz,
            slip_onsets: u64::from(r.onsets.count()),
            first_onset_s: r.first_onset,
            sample_rate_hz,
            setup_rate_hz: r.fs,
            rows: self.rows,
            samples: r.n,
            t_first: r.t_first,
            t_last: r.t_last,
            from_s: self.cfg.from_s,
            time_resolution_s: self.res_max,
            samples_at_range: r.at_range,
            thresholds,
            breakaway_jump_m_s2: self.cfg.breakaway_jump_m_s2,
            floor: r.floor,
            at_range: r.at_range_ch,
            at_full_scale: self.at_full_scale,
            full_scale: self.full_scale,
            undecided,
            health,
            spectrum,
            envelope: r.envelope.map(Envelope::finish).unwrap_or_default(),
            windows: r.windows.unwrap_or_default(),
            present,
            gaps: self.gaps,
            floor_note: self.floor_note,
            notes: self.notes,
            format: "",
        })
    }
}
