//! Stopping a command from outside it: the Python module's Ctrl-C.
//!
//! The binary needs none of this: Ctrl-C ends its process (and `record` routes it to the
//! recording's end). Inside the Python interpreter a command runs on a worker thread of its own,
//! and the interpreter's Ctrl-C abandons it; the module then cancels the command's [`Cancel`]
//! token, and the command stops at its next cancellation point with
//! [`HostError::Cancelled`]:
//! - `map`: before each cell (a cell is milliseconds);
//! - `fit`: before each evaluation of the cost (every later one is refused at once, and the
//!   command ends as cancelled);
//! - a run of the thesis model or of model 2 on the command's own thread (`simulate`, ...),
//!   and the virtual rig's frames (`sil`): every [`CHECK_EVERY_STEPS`] steps;
//! - `record`: the recording ends as if interrupted.
//!
//! The token is the command thread's ([`with`]); work the command hands to other threads takes
//! it along explicitly: the map's cells through [`carried`], the fit's evaluations in its
//! problem ([`current`]). Without a token
//! (the binary, the tests) every check is a thread-local read that finds none.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::error::{HostError, Result};

/// A run's loop looks for a cancellation once per this many steps (2.6 s of a 1/25600 s run;
/// a few milliseconds of computing).
pub const CHECK_EVERY_STEPS: u64 = 1 << 16;

/// A command's cancellation: shared by whoever may cancel it and the command's threads.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the command to stop at its next cancellation point.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// `Err(HostError::Cancelled)` once cancelled.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(HostError::Cancelled)
        } else {
            Ok(())
        }
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Cancel>> = const { RefCell::new(None) };
}

/// Runs `f` with `token` as this thread's cancellation (the one before is restored after).
pub fn with<R>(token: Option<Cancel>, f: impl FnOnce() -> R) -> R {
    let before = CURRENT.with(|c| c.replace(token));
    let out = f();
    CURRENT.with(|c| *c.borrow_mut() = before);
    out
}

/// This thread's cancellation, for work handed to other threads.
pub fn current() -> Option<Cancel> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Runs `f` on this thread (another than the command's: a rayon worker) with the command's
/// `token` ([`current`], taken on the command's thread), after a [`check`]: a piece of work
/// handed over starts only while the command is not cancelled, and the runs in it check too.
pub fn carried<R>(token: &Option<Cancel>, f: impl FnOnce() -> Result<R>) -> Result<R> {
    with(token.clone(), || {
        check()?;
        f()
    })
}

/// `Err(HostError::Cancelled)` when this thread's command has been cancelled.
pub fn check() -> Result<()> {
    CURRENT.with(|c| c.borrow().as_ref().map_or(Ok(()), Cancel::check))
}

/// [`check`] on every [`CHECK_EVERY_STEPS`]-th value of a loop's counter `i`.
#[inline(always)]
pub fn check_every(i: u64) -> Result<()> {
    if i % CHECK_EVERY_STEPS == 0 {
        check()
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_token_reaches_its_thread_only_and_is_restored_after() {
        let t = Cancel::new();
        assert!(check().is_ok());
        with(Some(t.clone()), || {
            assert!(check().is_ok());
            t.cancel();
            assert!(matches!(check(), Err(HostError::Cancelled)));
            // another thread does not see it unless it is handed over
            std::thread::scope(|s| {
                s.spawn(|| assert!(check().is_ok()));
            });
            with(None, || assert!(check().is_ok()));
            assert!(check().is_err());
        });
        assert!(check().is_ok());
        assert!(check_every(1).is_ok());
    }
}
