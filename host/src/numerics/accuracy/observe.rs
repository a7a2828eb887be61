//! Running a method under test on a scene: what it observes (slip onsets, extrema, the final
//! state) and its run time per step.

use super::*;

/// What a run of a method shows about the motion.
#[derive(Clone, Debug, Default)]
pub(super) struct Observed {
    pub(super) onsets: Vec<f64>,
    pub(super) min: [f64; 4],
    pub(super) max: [f64; 4],
    pub(super) stick_fraction: f64,
    pub(super) final_state: [f64; 4],
    pub(super) steps: u64,
    pub(super) halt: Option<Halt>,
}

impl Observed {
    pub(super) fn period(&self) -> Option<f64> {
        (self.onsets.len() >= 2).then(|| (self.onsets[self.onsets.len() - 1] - self.onsets[0]) / (self.onsets.len() - 1) as f64)
    }
    pub(super) fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }
}

pub(super) struct ExactObserver<T: Real> {
    pub(super) stats: StatsObserver<T>,
    pub(super) onsets: Vec<f64>,
    pub(super) from: f64,
}

impl<T: Real> Observer<T> for ExactObserver<T> {
    fn segment(&mut self, seg: &Segment<T>, prop: &Propagator<T>) {
        self.stats.segment(seg, prop);
    }
    fn transition(&mut self, tr: &Transition<T>) {
        self.stats.transition(tr);
        if tr.from == Regime::Stick && tr.t >= self.from {
            self.onsets.push(tr.t);
        }
    }
}

pub(super) fn steps_of(scene: &Scene) -> u64 {
    (scene.duration / scene.dt).round() as u64
}

pub(super) fn to_f64(z: stickslip_model::State<impl Real>) -> [f64; 4] {
    [z.x.to_f64(), z.xdot.to_f64(), z.phi.to_f64(), z.phidot.to_f64()]
}

/// Runs `kind` in precision `T` with observation (untimed).
#[allow(clippy::needless_range_loop)] // min and max of the same component
pub(super) fn observe<T: Real>(kind: MethodKind, scene: &Scene) -> Result<Observed> {
    let n = steps_of(scene);
    let window_from = (scene.stats_from / scene.dt).round() as u64;
    if kind == MethodKind::Exact {
        let mut st = ExactStepper::<T>::new(scene).map_err(|e| HostError::Input(e.to_string()))?;
        let mut ob = ExactObserver { stats: StatsObserver::<T>::new(scene.stats_from, scene.dt), onsets: Vec::new(), from: window_from as f64 * scene.dt };
        let mut halt = None;
        let mut steps = 0;
        for _ in 0..n {
            if let Err(h) = st.step_observed(&mut ob) {
                halt = Some(h);
                break;
            }
            steps += 1;
        }
        let s = ob.stats.finish();
        return Ok(Observed {
            onsets: ob.onsets,
            min: s.min,
            max: s.max,
            stick_fraction: s.stick_fraction,
            final_state: to_f64(st.state()),
            steps,
            halt,
        });
    }
    let mut m = AnyMethod::<T>::new(kind, scene).map_err(|e| HostError::Input(e.to_string()))?;
    let mut o = Observed { min: [f64::INFINITY; 4], max: [f64::NEG_INFINITY; 4], ..Default::default() };
    let (mut stick, mut in_window) = (0u64, 0u64);
    for i in 0..n {
        if let Err(h) = m.step() {
            o.halt = Some(h);
            break;
        }
        o.steps += 1;
        if i + 1 >= window_from {
            for tr in m.transitions() {
                if tr.from == Regime::Stick {
                    o.onsets.push(tr.t);
                }
            }
            let z = to_f64(m.state());
            for k in 0..4 {
                o.min[k] = o.min[k].min(z[k]);
                o.max[k] = o.max[k].max(z[k]);
            }
            in_window += 1;
            if m.regime() == Regime::Stick {
                stick += 1;
            }
        }
    }
    o.stick_fraction = if in_window > 0 { stick as f64 / in_window as f64 } else { 0.0 };
    o.final_state = to_f64(m.state());
    Ok(o)
}

/// Wall time of a plain loop of `n` steps (`step` false: the run halted), the minimum over
/// `repeats` fresh steppers from `make` [s], and the steps done.
pub(super) fn time_loop<S>(
    n: u64,
    repeats: usize,
    mut make: impl FnMut() -> Result<S>,
    mut step: impl FnMut(&mut S) -> bool,
) -> Result<(f64, u64)> {
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..repeats.max(1) {
        let mut m = make()?;
        let t0 = Instant::now();
        let mut k = 0;
        while k < n {
            if !step(&mut m) {
                break;
            }
            k += 1;
        }
        best = best.min(t0.elapsed().as_secs_f64());
        steps = k;
    }
    Ok((best, steps))
}

/// Wall time of the plain stepping loop of a method, the minimum over `repeats` [s].
pub(super) fn time_steps<T: Real>(kind: MethodKind, scene: &Scene, repeats: usize) -> Result<(f64, u64)> {
    time_loop(
        steps_of(scene),
        repeats,
        || AnyMethod::<T>::new(kind, scene).map_err(|e| HostError::Input(e.to_string())),
        |m| std::hint::black_box(m.step()).is_ok(),
    )
}
