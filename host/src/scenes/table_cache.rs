//! The thesis stepper's dyadic propagators, built once per [`PropagatorKey`] and shared: the
//! tables are most of a short run's set-up (162 matrix exponentials in f64), and a map's cells
//! that differ only in keys the flows do not read (mu_s, V, the run length, the window) have
//! the same ones, bit for bit. A map of beta x mu_s builds one per beta instead of one per
//! cell. Each thread also keeps the whole tables built on them ([`ExactTables`], 26 KB in
//! f64, nearly all of it the propagator) by key and rebuilds the rest in place for the next
//! cell of that key ([`ExactTables::retarget`]): a cell's set-up copies no propagator.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use stickslip_model::propagator::{Propagator, PropagatorKey};
use stickslip_model::exact::TaylorFlows;
use stickslip_model::{Coefficients, ExactState, ExactTables, Halt, Real, Scene, SceneError};

/// Propagators by key, in f32 and f64; bounded ([`Self::MAX_ENTRIES`] a precision: then it
/// starts again empty, so a map whose every cell has its own flows holds a few MB at most).
#[derive(Default)]
pub struct PropagatorCache {
    f32: Mutex<HashMap<PropagatorKey, Arc<Propagator<f32>>>>,
    f64: Mutex<HashMap<PropagatorKey, Arc<Propagator<f64>>>>,
}

/// A thread's tables by propagator key ([`PropagatorCache::with_tables`]).
type LocalTables<T> = RefCell<HashMap<PropagatorKey, Box<ExactTables<T>>>>;

thread_local! {
    static LOCAL_F32: LocalTables<f32> = RefCell::new(HashMap::new());
    static LOCAL_F64: LocalTables<f64> = RefCell::new(HashMap::new());
}

/// The float types the cache holds.
pub trait Cached: Real {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<Self>>>>;
    /// This thread's tables by key.
    fn local<R>(f: impl FnOnce(&LocalTables<Self>) -> R) -> R;
    /// A step whose guard fires or may crest, for a map's run: with its transitions located on
    /// the Taylor polynomials of `taylor` in f64 ([`ExactTables::step_located`]); in f32 the
    /// stepper's own step (binary lifting to 2^-24 of a substep), as before.
    fn step_located(tables: &ExactTables<Self>, s: &mut ExactState<Self>, taylor: &TaylorFlows) -> Result<usize, Halt>;
}

impl Cached for f32 {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<f32>>>> {
        &cache.f32
    }
    fn local<R>(f: impl FnOnce(&LocalTables<f32>) -> R) -> R {
        LOCAL_F32.with(f)
    }
    fn step_located(tables: &ExactTables<f32>, s: &mut ExactState<f32>, _taylor: &TaylorFlows) -> Result<usize, Halt> {
        tables.step(s)
    }
}

impl Cached for f64 {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<f64>>>> {
        &cache.f64
    }
    fn local<R>(f: impl FnOnce(&LocalTables<f64>) -> R) -> R {
        LOCAL_F64.with(f)
    }
    fn step_located(tables: &ExactTables<f64>, s: &mut ExactState<f64>, taylor: &TaylorFlows) -> Result<usize, Halt> {
        tables.step_located(taylor, s)
    }
}

impl PropagatorCache {
    /// Entries kept per precision (an f64 propagator is 26 KB).
    pub const MAX_ENTRIES: usize = 256;

    pub fn new() -> PropagatorCache {
        PropagatorCache::default()
    }

    /// The exact stepper's tables of `scene` (validated here) and its start state, on the
    /// cached propagator of the scene's key (built and kept on a miss): the tables
    /// [`ExactTables::new`] builds, bit for bit.
    pub fn tables<T: Cached>(&self, scene: &Scene) -> Result<(ExactTables<T>, ExactState<T>), SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let key = Propagator::<T>::key(scene, &co, scene.dt);
        ExactTables::with_propagator(scene, &self.propagator::<T>(scene, &co, &key))
    }

    /// `f` on the tables [`Self::tables`] gives and their start state, from this thread's
    /// tables of the scene's key (rebuilt in place for `scene`, [`ExactTables::retarget`]:
    /// no propagator copied), built on a miss and kept ([`Self::MAX_ENTRIES`] a thread and
    /// precision, then the thread starts again empty). `f` must not call this again.
    pub fn with_tables<T: Cached, R>(&self, scene: &Scene, f: impl FnOnce(&ExactTables<T>, ExactState<T>) -> R) -> Result<R, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let key = Propagator::<T>::key(scene, &co, scene.dt);
        T::local(|local| {
            let mut map = local.borrow_mut();
            if let Some(tables) = map.get_mut(&key) {
                let state = tables.retarget(scene)?;
                return Ok(f(tables, state));
            }
            let (tables, state) = ExactTables::with_propagator(scene, &self.propagator::<T>(scene, &co, &key))?;
            if map.len() >= Self::MAX_ENTRIES {
                map.clear();
            }
            let tables = map.entry(key).or_insert(Box::new(tables));
            Ok(f(tables, state))
        })
    }

    /// The propagator of `key` (the key of `scene` and its coefficients `co`), built and
    /// kept on a miss.
    fn propagator<T: Cached>(&self, scene: &Scene, co: &Coefficients, key: &PropagatorKey) -> Arc<Propagator<T>> {
        // a poisoned lock (a panic elsewhere) only costs the cache
        let hit = T::slot(self).lock().ok().and_then(|m| m.get(key).cloned());
        match hit {
            Some(p) => p,
            None => {
                // built outside the lock: the other threads keep running
                let p = Arc::new(Propagator::<T>::new(scene, co, scene.dt));
                if let Ok(mut m) = T::slot(self).lock() {
                    if m.len() >= Self::MAX_ENTRIES {
                        m.clear();
                    }
                    m.insert(*key, p.clone());
                }
                p
            }
        }
    }
}
