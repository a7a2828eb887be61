//! Setting up the analysis at the rate of the preview rows: the estimator, filters and
//! spectrum, and the noise floor the contact thresholds come from.

use super::*;
use crate::output::format::sig4;

impl Analyzer {
    /// Sets up the estimator, filters and spectrum at the rate of the rows so far, and runs
    /// the buffered rows through them; `at_end`: the rows so far are the whole record.
    pub(super) fn start(&mut self, at_end: bool) -> Result<(), String> {
        let Phase::Preview(buf) = &mut self.phase else { return Ok(()) };
        let buf = std::mem::take(buf);
        let k = buf.len();
        let fs = if self.gaps.is_empty() {
            (k - 1) as f64 / (buf[k - 1].t - buf[0].t)
        } else {
            1.0 / self.mean_interval()
        };
        let lines = format!("lines {} to {}", self.line_first, self.line_prev);
        let nyquist_min = 2.0 * GROAN_BAND_HZ.1;
        if !(fs > nyquist_min) {
            return Err(format!(
                "{lines}: sample rate {fs:.6} Hz from the time column: the groan band ({} to {} Hz) needs more than {nyquist_min} Hz",
                GROAN_BAND_HZ.0, GROAN_BAND_HZ.1
            ));
        }
        let ecfg = EstimatorConfig {
            fs_hz: fs,
            contact: ContactThresholds::from_breakaway_jump(self.cfg.breakaway_jump_m_s2, fs),
            window_samples: ((stickslip_model::rig::WINDOW_S * fs).round() as u32).max(1),
            band_speed_m_s: self.cfg.band_speed_m_s,
            face_coefficient: self.cfg.face_coefficient,
            ..EstimatorConfig::default()
        };
        ecfg.validate().map_err(|e| format!("{lines}: sample rate {fs:.6} Hz: the rig's estimator refuses it: {e}"))?;
        let floor = self.design_floor(&buf, at_end)?;
        let (from_eff, to_eff) = self.around_fill(floor.as_ref(), fs);
        let design = floor.as_ref().map(|f| {
            (f.report, ContactThresholds::from_noise_floor(f.report.sigma_m_s2[A_REL] as f64, f.quantum_m_s2, fs))
        });
        let rig_cfg = RigConfig::recording(ecfg);
        let rig = Rig::for_recording(&rig_cfg, design)
            .map_err(|e| format!("{lines}: sample rate {fs:.6} Hz: the rig's estimator refuses it: {e}"))?;
        let groan = *rig.estimator().groan_filter();
        let start_level = rig.estimator().contact().thresholds().stick_max_m_s2;
        let start_bias = design.as_ref().map_or(0.0, |d| d.0.mean_m_s2[A_REL]);
        let segment = self.cfg.segment.unwrap_or_else(|| default_segment(fs));
        let mut r = Running {
            fs,
            from_eff,
            to_eff,
            rig: Box::new(rig),
            welch: self.cfg.spectra.then(|| Welch::new(segment)),
            envelope: self.cfg.figures.then(Envelope::new),
            n: 0,
            t_first: 0.0,
            t_last: 0.0,
            extremes: Extremes::<f64, CH>::EMPTY,
            sum: [0.0; CH],
            sq: [0.0; CH],
            groan_sq: [0.0; CH],
            prev: [0.0; CH],
            step: [f64::INFINITY; CH],
            stick: 0,
            rel_sum: 0.0,
            rel_sq: 0.0,
            slip_end_v_r: 0.0,
            prev_v_r: 0.0,
            onsets: OnsetRate::new(),
            intervals: OnsetIntervals::default(),
            first_onset: None,
            at_range: 0,
            at_range_ch: [0; CH],
            floor,
            windows: self.cfg.windows.then(Vec::new),
            groan,
            groan_state: [CascadeState::<GROAN_SECTIONS>::ZERO; CH],
            groan_origin: None,
            rig_cfg,
            design,
            onset_intervals: 0,
            onset_span: 0.0,
            last_onset: 0.0,
            started: false,
            held: Vec::with_capacity(START_RUN),
            start_level,
            start_bias,
            face: self.cfg.face_coefficient,
        };
        for p in &buf {
            if p.gap_before {
                r.restart();
            }
            r.process(p.t, &p.a);
        }
        self.phase = Phase::Running(Box::new(r));
        Ok(())
    }

    /// The statistics' start and end [s] (a row counts at from <= t <= to): `--from`, and past
    /// a logger's fill at the record's start or end that the floor search found
    /// ([`super::super::quiet`]: one value on every channel, no signal), each fill noted.
    fn around_fill(&mut self, floor: Option<&FloorOutcome>, fs: f64) -> (f64, f64) {
        let mut from = self.cfg.from_s - 0.25 / fs;
        let mut to = f64::INFINITY;
        let Some(f) = floor else { return (from, to) };
        if let Some((t0, t1)) = f.fill_lead {
            let left = if from <= t1 {
                from = t1 + 0.25 / fs;
                "the noise floor and the statistics, which start at the next row"
            } else {
                "the noise floor"
            };
            self.note(format!(
                "t = {} to {} s: every channel holds one value (a logger's fill before its trigger): left out of {left}",
                sig4(t0),
                sig4(t1)
            ));
        }
        if let Some((runs, rows, (t0, t1))) = f.fill_inside {
            self.note(format!(
                "{runs} run{} of one value on every channel inside the record ({rows} rows in whole blocks; the first t = {} to {} s: a logger holding its last value through a dropout?): left out of the noise floor, not of the statistics (their time counts as stick)",
                if runs == 1 { "" } else { "s" },
                sig4(t0),
                sig4(t1)
            ));
        }
        if let Some((t0, t1)) = f.fill_trail {
            to = t0 - 0.25 / fs;
            self.note(format!(
                "t = {} to {} s: every channel holds one value to the record's end (a logger's fill after its stop): left out of the noise floor and the statistics",
                sig4(t0),
                sig4(t1)
            ));
        }
        (from, to)
    }

    /// The noise floor the thresholds come from (`None` for [`FloorSource::Jump`]); `at_end`:
    /// `buf` is the whole record (a run of one value it ends in may be trailing fill).
    pub(super) fn design_floor(&self, buf: &[Pending], at_end: bool) -> Result<Option<FloorOutcome>, String> {
        let a_rel = |p: &Pending| a_rel_of(p, self.cfg.face_coefficient);
        let (rows, auto): (Vec<&Pending>, bool) = match self.cfg.floor {
            FloorSource::Jump => return Ok(None),
            FloorSource::Found(f) => return Ok(Some(f)),
            FloorSource::Auto => {
                let mut q = super::super::quiet::QuietSearch::new(self.cfg.face_coefficient);
                for p in buf {
                    q.push(p.t, &p.a);
                }
                return Ok(if at_end { q.finish() } else { q.finish_preview() }.ok());
            }
            FloorSource::Range(from, to) => (buf.iter().filter(|p| p.t >= from && p.t <= to).collect(), false),
            FloorSource::Lead => {
                let rel: Vec<f32> = buf.iter().map(a_rel).collect();
                match find_quiet(&rel) {
                    Some((i0, i1)) => (buf[i0..i1].iter().collect(), true),
                    // no quiet stretch against a signal: the fixed thresholds of the jump
                    None => return Ok(None),
                }
            }
        };
        if rows.len() < MIN_FLOOR_SAMPLES as usize {
            let what = match self.cfg.floor {
                FloorSource::Range(from, to) => format!("--quiet {from}:{to}: {} rows in it", rows.len()),
                _ => format!(
                    "no quiet stretch of {MIN_FLOOR_SAMPLES} rows in the first {} (the clamped, band-still phase a record should start with)",
                    buf.len()
                ),
            };
            return Err(format!(
                "{what}: the noise floor needs at least {MIN_FLOOR_SAMPLES}: give --quiet FROM:TO over a stretch where nothing moves, or --breakaway-jump M_S2 for fixed thresholds"
            ));
        }
        let mut nf = NoiseFloor::new();
        for p in &rows {
            nf.add(&p.a.map(|v| v as f32), a_rel(p));
        }
        // the quantum: the smallest nonzero step of pad_x and of disc_x over the buffered rows
        let step = |c: usize| {
            buf.windows(2)
                .map(|w| (w[1].a[c] - w[0].a[c]).abs())
                .filter(|&d| d > 0.0)
                .fold(f64::INFINITY, f64::min)
        };
        let q = [step(1), step(0)].into_iter().filter(|v| v.is_finite()).fold(0.0, f64::max);
        Ok(Some(FloorOutcome {
            t_from: rows[0].t,
            t_to: rows[rows.len() - 1].t,
            auto,
            report: nf.report(),
            quantum_m_s2: q,
            quiet_blocks: 0,
            fill_lead: None,
            fill_trail: None,
            fill_inside: None,
        }))
    }
}
