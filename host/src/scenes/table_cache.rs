//! The thesis stepper's dyadic propagators, built once per [`PropagatorKey`] and shared: the
//! tables are most of a short run's set-up (162 matrix exponentials in f64), and a map's cells
//! that differ only in keys the flows do not read (mu_s, V, the run length, the window) have
//! the same ones, bit for bit. A map of beta x mu_s builds one per beta instead of one per
//! cell.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use stickslip_model::propagator::{Propagator, PropagatorKey};
use stickslip_model::{Coefficients, ExactState, ExactTables, Real, Scene, SceneError};

/// Propagators by key, in f32 and f64; bounded ([`Self::MAX_ENTRIES`] a precision: then it
/// starts again empty, so a map whose every cell has its own flows holds a few MB at most).
#[derive(Default)]
pub struct PropagatorCache {
    f32: Mutex<HashMap<PropagatorKey, Arc<Propagator<f32>>>>,
    f64: Mutex<HashMap<PropagatorKey, Arc<Propagator<f64>>>>,
}

/// The float types the cache holds.
pub trait Cached: Real {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<Self>>>>;
}

impl Cached for f32 {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<f32>>>> {
        &cache.f32
    }
}

impl Cached for f64 {
    fn slot(cache: &PropagatorCache) -> &Mutex<HashMap<PropagatorKey, Arc<Propagator<f64>>>> {
        &cache.f64
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
        // a poisoned lock (a panic elsewhere) only costs the cache
        let hit = T::slot(self).lock().ok().and_then(|m| m.get(&key).cloned());
        let prop = match hit {
            Some(p) => p,
            None => {
                // built outside the lock: the other threads keep running
                let p = Arc::new(Propagator::<T>::new(scene, &co, scene.dt));
                if let Ok(mut m) = T::slot(self).lock() {
                    if m.len() >= Self::MAX_ENTRIES {
                        m.clear();
                    }
                    m.insert(key, p.clone());
                }
                p
            }
        };
        ExactTables::with_propagator(scene, &prop)
    }
}
