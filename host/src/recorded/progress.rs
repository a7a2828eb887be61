//! Progress on stderr for recordings that take longer than a second to read: a bar over the
//! file's bytes (indicatif, as `map` and `fit` show theirs), drawn only when stderr is a
//! terminal, and only once a second has passed (a short file shows nothing).

use std::io::Read;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Bytes read so far, shared by the readers of one file.
#[derive(Clone, Debug, Default)]
pub struct Counter(Arc<AtomicU64>);

impl Counter {
    pub fn get(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }
}

/// A reader that counts what it reads into a [`Counter`].
#[derive(Debug)]
pub struct Counted<R> {
    inner: R,
    counter: Counter,
}

impl<R> Counted<R> {
    pub fn new(inner: R, counter: Counter) -> Self {
        Counted { inner, counter }
    }
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.counter.0.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
}

impl<R: std::io::Seek> std::io::Seek for Counted<R> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        self.inner.seek(pos)
    }
}

/// The bar of one command's reading: `total` bytes over all its passes.
pub struct Progress {
    what: String,
    total: u64,
    start: Instant,
    bar: Option<ProgressBar>,
    enabled: bool,
}

impl Progress {
    /// `enabled`: stderr is a terminal (the caller decides).
    pub fn new(what: &str, total: u64, enabled: bool) -> Self {
        Progress { what: what.to_string(), total, start: Instant::now(), bar: None, enabled: enabled && total > 0 }
    }

    /// `done` bytes of `total` read; call now and then (every few thousand rows).
    pub fn update(&mut self, done: u64) {
        if !self.enabled {
            return;
        }
        if self.bar.is_none() {
            if self.start.elapsed() < Duration::from_secs(1) {
                return;
            }
            let b = ProgressBar::with_draw_target(Some(self.total), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{msg} {bar:30} {bytes}/{total_bytes} {elapsed} (left {eta})").expect("valid template"),
            );
            b.set_message(self.what.clone());
            self.bar = Some(b);
        }
        if let Some(b) = &self.bar {
            b.set_position(done.min(self.total));
        }
    }

    /// Clears the bar.
    pub fn finish(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
