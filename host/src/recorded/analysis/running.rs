//! The analysis once the preview rows have set it up: the rows held until a sample is
//! played ([`Pending`]), and the running statistics, estimator, filters and spectrum that every
//! row after the preview goes through ([`Running`]).

use super::*;

#[derive(Clone, Copy)]
pub(super) struct Pending {
    pub(super) t: f64,
    pub(super) a: [f64; CH],
    /// The first row after a gap (`--gaps split`).
    pub(super) gap_before: bool,
}

pub(super) struct Running {
    pub(super) fs: f64,
    pub(super) from_eff: f64,
    /// Statistics end: rows after it (a logger's fill to the record's end) only run through
    /// the estimator and filters.
    pub(super) to_eff: f64,
    /// The rig, playing the record back (`Rig::for_recording`): its estimator and windows.
    pub(super) rig: Box<Rig>,
    pub(super) welch: Option<Welch>,
    pub(super) envelope: Option<Envelope>,
    pub(super) n: u64,
    pub(super) t_first: f64,
    pub(super) t_last: f64,
    pub(super) extremes: Extremes<f64, CH>,
    pub(super) sum: [f64; CH],
    pub(super) sq: [f64; CH],
    pub(super) groan_sq: [f64; CH],
    pub(super) prev: [f64; CH],
    pub(super) step: [f64; CH],
    pub(super) stick: u64,
    /// a_rel ([`a_rel`], as the estimator takes it) over the statistics' rows: sum and sum of
    /// squares [m/s^2, m^2/s^4].
    pub(super) rel_sum: f64,
    pub(super) rel_sq: f64,
    /// The largest |v_r| [m/s] at which a slip ended (its last sample before the estimator
    /// went back to stick), over the statistics' rows; and the last played sample's v_r (a slip
    /// still open at the record's end counts with it, see `finish`).
    pub(super) slip_end_v_r: f64,
    pub(super) prev_v_r: f64,
    pub(super) onsets: OnsetRate,
    /// The intervals between consecutive onsets within a block ([`OnsetIntervals`]).
    pub(super) intervals: OnsetIntervals,
    pub(super) first_onset: Option<f64>,
    pub(super) at_range: u64,
    pub(super) at_range_ch: [u64; CH],
    pub(super) floor: Option<FloorOutcome>,
    /// `Some` when the windows are kept.
    pub(super) windows: Option<Vec<EstimatorWindow>>,
    /// The statistics' groan band-pass (the estimator's coefficients) on each channel minus
    /// its first sample, and that first sample.
    pub(super) groan: stickslip_model::rig::bandpass::BandPass<GROAN_SECTIONS>,
    pub(super) groan_state: [CascadeState<GROAN_SECTIONS>; CH],
    pub(super) groan_origin: Option<[f64; CH]>,
    /// To restart the rig after a gap: its configuration and floor design.
    pub(super) rig_cfg: RigConfig,
    pub(super) design: Option<(stickslip_model::rig::noise_floor::FloorReport, ContactThresholds)>,
    /// Onsets of the blocks before the current one: (n - 1) summed, and their spans [s].
    pub(super) onset_intervals: u64,
    pub(super) onset_span: f64,
    pub(super) last_onset: f64,
    /// The rig's estimator has started (see [`Running::process`]); the rows held meanwhile;
    /// the stick level [m/s^2] and a_rel's bias that start it; the face term.
    pub(super) started: bool,
    pub(super) held: Vec<(f64, [f64; CH])>,
    pub(super) start_level: f32,
    pub(super) start_bias: f32,
    pub(super) face: f32,
}

impl Running {
    /// After a gap: the rig starts again from rest with the same thresholds (its filters and
    /// contact state do not reach across the gap), the onsets of the block before are kept
    /// apart, and the spectrum's partial segment is dropped.
    pub(super) fn restart(&mut self) {
        if let Some((n, first, last)) = self.onsets.first().map(|f| (self.onsets.count(), f, self.onsets_last())) {
            if n >= 2 && last > first {
                self.onset_intervals += u64::from(n - 1);
                self.onset_span += last - first;
            }
        }
        self.onsets = OnsetRate::new();
        self.flush_held();
        self.started = false;
        if let Ok(rig) = Rig::for_recording(&self.rig_cfg, self.design) {
            self.rig = Box::new(rig);
        }
        if let Some(w) = &mut self.welch {
            w.restart();
        }
    }

    pub(super) fn onsets_last(&self) -> f64 {
        self.last_onset
    }

    /// The stick-slip frequency over the blocks (one block: the onsets' rate as before).
    pub(super) fn hz(&self) -> Option<f64> {
        let (mut n, mut span) = (self.onset_intervals, self.onset_span);
        if let Some(first) = self.onsets.first() {
            if self.onsets.count() >= 2 && self.last_onset > first {
                if n == 0 {
                    return self.onsets.hz();
                }
                n += u64::from(self.onsets.count() - 1);
                span += self.last_onset - first;
            }
        }
        (n > 0 && span > 0.0).then(|| n as f64 / span)
    }

    /// One row. The rig's estimator starts in stick (the rig clamps the pad before the band
    /// moves): it is started at the first [`START_RUN`] rows in a row whose a_rel is within its
    /// stick level of the floor's mean, so a record that starts inside a slip does not start
    /// it in stick with a wrong relative velocity. Rows before that (the record's first,
    /// partial slip) go into the statistics and count as slip, not through the rig. A record
    /// that starts in stick (a clamped lead-in) starts it at its first row, as the rig does.
    #[inline]
    pub(super) fn process(&mut self, t: f64, a: &[f64; CH]) {
        if self.started {
            return self.process_row(t, a, true);
        }
        let rel = a_rel(a, self.face) - self.start_bias;
        self.held.push((t, *a));
        if rel.abs() <= self.start_level {
            if self.held.len() >= START_RUN {
                self.started = true;
                for (t, a) in std::mem::take(&mut self.held) {
                    self.process_row(t, &a, true);
                }
            }
        } else {
            self.flush_held();
        }
    }

    /// The held rows, not played (the record ended, or the run of quiet rows broke).
    pub(super) fn flush_held(&mut self) {
        for (t, a) in std::mem::take(&mut self.held) {
            self.process_row(t, &a, false);
        }
    }

    #[inline]
    pub(super) fn process_row(&mut self, t: f64, a: &[f64; CH], played: bool) {
        let mut bits = 0u16;
        for (i, v) in a.iter().enumerate() {
            if v.abs() >= SENSOR_RANGE_M_S2 {
                bits |= 1 << i;
            }
        }
        let mut stick = false;
        let mut onset_lead = None;
        let mut slip_end = None;
        if played {
            let cal = Calibrated {
                accel_m_s2: a.map(|v| v as f32),
                pressure_bar: [0.0; 2],
                saturation: Saturation { bits },
            };
            let s = self.rig.play(&cal);
            if s.window_ready {
                let closed = self.rig.take_window();
                if let (Some(w), Some(closed)) = (&mut self.windows, closed) {
                    w.push(EstimatorWindow { t_end_s: t, report: closed.report });
                }
            }
            let onset = matches!(s.contact.event, Some(e) if e.kind == ContactEventKind::StickToSlip);
            if onset && self.first_onset.is_none() {
                self.first_onset = Some(t - s.contact.lead_samples as f64 / self.fs);
            }
            stick = s.contact.regime == Regime::Stick;
            if matches!(s.contact.event, Some(e) if e.kind == ContactEventKind::SlipToStick) {
                slip_end = Some(self.prev_v_r.abs());
            }
            self.prev_v_r = f64::from(s.contact.v_r_m_s);
            onset_lead = onset.then_some(s.contact.lead_samples);
        }
        if t < self.from_eff || t > self.to_eff {
            return;
        }
        if self.n == 0 {
            self.t_first = t;
        }
        self.t_last = t;
        self.n += 1;
        let o = *self.groan_origin.get_or_insert(*a);
        let g: [f32; CH] = std::array::from_fn(|c| self.groan.run(&mut self.groan_state[c], (a[c] - o[c]) as f32));
        for c in 0..CH {
            let v = a[c];
            self.extremes.take(c, v);
            self.sum[c] += v;
            self.sq[c] += v * v;
            let d = (v - self.prev[c]).abs();
            if d > 0.0 && d < self.step[c] && self.n > 1 {
                self.step[c] = d;
            }
            self.prev[c] = v;
            let gv = g[c] as f64;
            self.groan_sq[c] += gv * gv;
        }
        if bits != 0 {
            self.at_range += 1;
            for c in 0..CH {
                if bits & (1 << c) != 0 {
                    self.at_range_ch[c] += 1;
                }
            }
        }
        if stick {
            self.stick += 1;
        }
        if let Some(v) = slip_end {
            self.slip_end_v_r = self.slip_end_v_r.max(v);
        }
        let rel = f64::from(a_rel(a, self.face));
        self.rel_sum += rel;
        self.rel_sq += rel * rel;
        if let Some(lead_samples) = onset_lead {
            // the estimator dates the slip back by its lead: those samples were counted stick
            let lead = (lead_samples as u64).min(self.stick);
            self.stick -= lead;
            let t = t - lead as f64 / self.fs;
            if self.onsets.count() > 0 {
                self.intervals.add(t - self.last_onset);
            }
            self.onsets.add(t);
            self.last_onset = t;
        }
        if let Some(w) = &mut self.welch {
            w.push(a);
        }
        if let Some(e) = &mut self.envelope {
            e.push(t, a);
        }
    }
}

/// a_rel of a buffered row: pad_x - disc_x + the face term.
pub(super) fn a_rel_of(p: &Pending, face_coefficient: f32) -> f32 {
    a_rel(&p.a, face_coefficient)
}

/// a_rel of a row as the rig's estimator takes it (f32): pad_x - disc_x + the face term
/// (face_coefficient x (pad_lead - pad_trail)).
#[inline]
pub(super) fn a_rel(a: &[f64; CH], face_coefficient: f32) -> f32 {
    (a[1] - a[0]) as f32 + face_coefficient * (a[3] - a[2]) as f32
}

pub(super) enum Phase {
    Preview(Vec<Pending>),
    Running(Box<Running>),
}
