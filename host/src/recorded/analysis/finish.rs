//! The statistics of a finished analysis ([`Analyzer::finish`]).

use super::*;
use stickslip_model::rig::contact::{ONSET_QUANTA, ONSET_SIGMAS};
use stickslip_model::rig::health::NOISY_RMS_FACTOR;

/// A pad_x whose standard deviation exceeds this fraction of the stick level moves: with the
/// scene's thresholds (no quiet rows) and no slip onset, its stick fraction is not told
/// (noise of a clamped pad is far below: 0.01 to 0.1 m/s^2 against a stick level of 8.3).
pub const MOVING_FRACTION_OF_STICK_LEVEL: f64 = 0.1;

/// The largest relative sliding velocity at which a slip may end and be believed [m/s]: a
/// slip ends where v_r comes back to zero; one that the estimator's drift guard (or the
/// record's end) closes at 1 m/s, against a band pulled at mm/s to cm/s, is the estimator
/// integrating an offset of a_rel (a biased pad_x channel) or a slip slower than its guard,
/// not a motion.
pub const MAX_PLAUSIBLE_V_R_M_S: f64 = 1.0;

/// Where the contact thresholds are set by the converter's count (the quiet rows moved by less
/// than one or two), pad_x must span at least this many counts for the estimate to be told: the
/// stick level is then one count, and at fewer counts the slips' edges are lost in it (the
/// virtual rig at the default gain: rig_quiet_push_center spans 5.7 counts and gives a stick
/// fraction of 0.036 for 0.326; rig_push_center spans 38 and gives 0.312 for 0.309).
pub const MIN_SPAN_COUNTS: f64 = 16.0;

/// Slips shorter than this on average are noise crossing the onset level, not stick-slip [s]
/// (and at least [`MIN_MEAN_SLIP_SAMPLES`]): the groan band's top, 500 Hz, is a 2 ms period,
/// and a stick-slip cycle's slip lasts a good part of one. Sticks shorter than this between
/// slips are the estimated velocity crossing zero in a sliding oscillation (`sil thesis-mu`,
/// a pad that ends up sliding: 65 onsets between sticks of 3 rows).
pub const MIN_MEAN_SLIP_S: f64 = 2e-4;
/// ... and at least this many samples on average.
pub const MIN_MEAN_SLIP_SAMPLES: f64 = 4.0;
/// Stick-slip cycles shorter than this many rows on average are noise crossing the onset
/// level: the estimator needs [`START_RUN`] rows within its stick level to start, and a cycle
/// holds a stick and a slip (24 rows: 1067 Hz at 25.6 kHz, 83 Hz at 2 kHz).
pub const MIN_CYCLE_ROWS: f64 = 24.0;

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
            // the record ended inside the preview: its last rows are its end
            self.start(true)?;
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
            && (self.floor_note.is_some() || self.cfg.floor == FloorSource::Lead)
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
        // thresholds from a floor that the converter's count set rather than its noise (the
        // quiet rows moved by less than a count or two: onset = ONSET_QUANTA counts >= ONSET_SIGMAS
        // sigma), no onset, and pad_x moves (changes by a count or more: a flat one is told
        // above): a slip whose accelerations stay within the
        // onset's counts (a coarse range: a low front-end gain) cannot be told from stick
        let coarse = r
            .floor
            .as_ref()
            .filter(|f| f.quantum_m_s2 > 0.0 && ONSET_QUANTA * f.quantum_m_s2 >= ONSET_SIGMAS * f64::from(f.report.sigma_m_s2[A_REL]))
            .filter(|f| {
                let pp = channels[PAD_X].pp;
                pp > 0.0 && (r.onsets.count() == 0 || pp < MIN_SPAN_COUNTS * f.quantum_m_s2)
            })
            .map(|f| {
                format!(
                    "the contact thresholds are set by the converter's count ({} m/s^2: the quiet rows moved by less), the slip onset at {ONSET_QUANTA} counts ({} m/s^2), \
                     and pad_x spans {} counts (peak-to-peak {} m/s^2) with {} slip onsets: too coarse to tell stick from slip \
                     (it takes a span of {MIN_SPAN_COUNTS} counts or more and an onset: more front-end gain)",
                    crate::output::format::short(f.quantum_m_s2),
                    crate::output::format::short(f64::from(thresholds.slip_onset_m_s2)),
                    crate::output::format::short((channels[PAD_X].pp / f.quantum_m_s2).round()),
                    crate::output::format::short(channels[PAD_X].pp),
                    r.onsets.count()
                )
            });
        // thresholds from a noise floor, no onset, and a_rel carries more than noise (its
        // standard deviation over NOISY_RMS_FACTOR of the floor's sigma): the pad moves below
        // the onset level, or the floor was not a noise floor (blocks taken in slips): either
        // way stick cannot be told from slip
        let n_rows = r.n.max(1) as f64;
        let rel_sd = (r.rel_sq / n_rows - (r.rel_sum / n_rows).powi(2)).max(0.0).sqrt();
        let moves_below = r
            .floor
            .as_ref()
            .map(|f| f64::from(f.report.sigma_m_s2[A_REL]))
            .filter(|&sigma| sigma > 0.0 && r.onsets.count() == 0 && rel_sd > f64::from(NOISY_RMS_FACTOR) * sigma)
            .map(|sigma| {
                format!(
                    "no slip onset, yet a_rel's standard deviation ({} m/s^2) is {} times its noise floor's sigma ({} m/s^2): \
                     the pad moves below the slip onset ({} m/s^2), or the floor's rows were not quiet; stick cannot be told from slip \
                     (give --quiet FROM:TO over a stretch known to be still, or --breakaway-jump)",
                    crate::output::format::short(rel_sd),
                    crate::output::format::short(rel_sd / sigma),
                    crate::output::format::short(sigma),
                    crate::output::format::short(f64::from(thresholds.slip_onset_m_s2))
                )
            });
        // a slip that ended (or the record ended in) at a sliding velocity no pad reaches on
        // the rig: the estimator integrated an offset, and its drift guard (or the record's end)
        // cut the slip rather than v_r's return to zero
        let open_slip = if r.started && r.prev_v_r != 0.0 { r.prev_v_r.abs() } else { 0.0 };
        let end_v = r.slip_end_v_r.max(open_slip);
        let runaway = (end_v > MAX_PLAUSIBLE_V_R_M_S).then(|| {
            format!(
                "a slip ended at an estimated sliding velocity of {} m/s (more than {MAX_PLAUSIBLE_V_R_M_S} m/s against a band pulled at mm/s to cm/s): \
                 a_rel did not return within the stick level where v_r came back to zero, as an offset of pad_x against disc_x or a slow slip \
                 makes it; the stick fraction would be a guess",
                crate::output::format::short(end_v)
            )
        });
        // slips of a sample or two: noise crossing the onset level
        let slip_s = (r.n - r.stick.min(r.n)) as f64 / sample_rate_hz;
        let min_slip_s = MIN_MEAN_SLIP_S.max(MIN_MEAN_SLIP_SAMPLES / sample_rate_hz);
        let onsets = f64::from(r.onsets.count());
        let cycle_rows = stick_slip_hz.map(|hz| sample_rate_hz / hz);
        let short_slips = (onsets > 0.0 && slip_s / onsets < min_slip_s).then(|| {
            format!(
                "slips of {} ms on average (a slip lasts {} ms or more)",
                crate::output::format::short(1e3 * slip_s / onsets),
                crate::output::format::short(1e3 * min_slip_s)
            )
        });
        let short_cycles = cycle_rows.filter(|&c| c < MIN_CYCLE_ROWS).map(|c| {
            format!(
                "cycles of {} rows on average ({MIN_CYCLE_ROWS} or more: the estimator starts at {START_RUN} rows within its stick level)",
                crate::output::format::short(c)
            )
        });
        let blips = (short_slips.is_some() || short_cycles.is_some()).then(|| {
            format!(
                "{} slip onsets with {}: noise crossing the onset level ({} m/s^2), not stick-slip",
                r.onsets.count(),
                [short_slips, short_cycles].into_iter().flatten().collect::<Vec<_>>().join(" and "),
                crate::output::format::short(f64::from(thresholds.slip_onset_m_s2))
            )
        });
        // sticks of a sample or two between slips: the estimated velocity crossing zero in a
        // sliding oscillation, not a stick
        let stick_s = r.stick.min(r.n) as f64 / sample_rate_hz;
        let blip_sticks = (onsets >= 2.0 && stick_s > 0.0 && stick_s / onsets < min_slip_s).then(|| {
            format!(
                "{} slip onsets between sticks of {} ms on average (a stick lasts {} ms or more): the estimated sliding velocity crossing zero \
                 in a sliding oscillation, not stick-slip",
                r.onsets.count(),
                crate::output::format::short(1e3 * stick_s / onsets),
                crate::output::format::short(1e3 * min_slip_s)
            )
        });
        // the estimator never started (no START_RUN rows in a row within its stick level): no
        // stick and no onset seen, every row counted slip
        let never_started = (self.rows >= START_RUN as u64 && r.stick == 0 && r.onsets.count() == 0).then(|| {
            format!(
                "the rig's estimator never started: no {START_RUN} rows in a row within its stick level ({} m/s^2), so it saw neither stick nor a slip onset \
                 (noise or a signal above the stick level throughout)",
                crate::output::format::short(stick_level)
            )
        });
        // slips split in two (a false re-stick, then a second onset), onsets taken from noise
        // or onsets missed: intervals far from their median (see `intervals`)
        let onset_intervals = r.intervals.stats();
        let split = onset_intervals.split().then(|| {
            let i = &onset_intervals;
            format!(
                "{} of {} intervals between slip onsets are far from their median ({} ms): {} under a third of it (slips split in two, or onsets \
                 taken from noise, as where the noise reaches the slip onset level of {} m/s^2), {} over three times it (onsets missed, or a \
                 stick-slip that stopped and started again); the frequency and the stick fraction would be biased",
                i.short + i.long,
                i.count,
                crate::output::format::short(1e3 * i.median_s),
                i.short,
                crate::output::format::short(f64::from(thresholds.slip_onset_m_s2)),
                i.long
            )
        });
        let no_stick_slip_seen =
            r.onsets.count() == 0 || blips.is_some() || never_started.is_some() || moves_below.is_some() || below_guess.is_some();
        // every reason the contact estimate is not told, in this order
        let reasons: Vec<String> =
            [short, undecided, below_guess, coarse, moves_below, runaway, blips, blip_sticks, never_started, split].into_iter().flatten().collect();
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
            onset_intervals,
            no_stick_slip_seen,
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
