//! Where `record`'s bytes come from, and the raw copy: a source (a file or pipe read in its own
//! thread, or the probe's RTT poll) sends [`Chunk`]s over a bounded channel; [`TeeReader`] hands
//! them to decode's [`decode_stream`](crate::recorded::decode::decode_stream) as a
//! [`Read`], writing each chunk to the raw file before the decoder sees it (so the raw file
//! always holds at least what was decoded, in order). The stream ends with the first
//! [`End`]: the input's end, Ctrl-C, a lost probe, a read or write error.

use std::fs::File;
use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::{Arc, Mutex, Once};

/// Chunks in flight between a source and the decoder (at most 64 x 64 KiB).
pub const CHANNEL_CHUNKS: usize = 64;

/// Bytes per read of a file or pipe.
const READ_BYTES: usize = 1 << 16;

/// Why the stream ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum End {
    /// The input's end (end of file, the writer of the pipe closed it).
    Input,
    /// Ctrl-C (SIGINT).
    Interrupted,
    /// The input could not be read: the message.
    ReadFailed(String),
    /// The probe connection was lost: the message.
    Lost(String),
    /// The raw file could not be written: the message.
    RawWriteFailed(String),
    /// A CSV could not be written (the pipeline stopped the stream).
    CsvWriteFailed,
}

/// What a source sends.
#[derive(Debug)]
pub enum Chunk {
    Data(Vec<u8>),
    End(End),
}

/// Reads `input` in a thread of its own and sends what it reads, then [`End::Input`] or
/// [`End::ReadFailed`]. The thread ends when the receiver is gone.
pub fn spawn_reader<R: Read + Send + 'static>(mut input: R, tx: SyncSender<Chunk>) {
    std::thread::spawn(move || {
        let mut buf = vec![0u8; READ_BYTES];
        loop {
            let end = match input.read(&mut buf) {
                Ok(0) => End::Input,
                Ok(n) => {
                    if tx.send(Chunk::Data(buf[..n].to_vec())).is_err() {
                        return;
                    }
                    continue;
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => End::ReadFailed(e.to_string()),
            };
            let _ = tx.send(Chunk::End(end));
            return;
        }
    });
}

/// The stop request of the running recording (Ctrl-C, or the pipeline after a write error):
/// a flag the reader checks before every chunk, and a wake-up for a reader that waits on an
/// empty channel.
#[derive(Clone)]
pub struct Stop {
    flag: Arc<AtomicBool>,
    wake: SyncSender<Chunk>,
}

impl Stop {
    pub fn new(wake: SyncSender<Chunk>) -> Self {
        Stop { flag: Arc::new(AtomicBool::new(false)), wake }
    }

    /// Asks the stream to end with `why` (if it has not ended yet).
    pub fn request(&self, why: End) {
        self.flag.store(true, Ordering::SeqCst);
        // a full channel needs no wake-up: the reader checks the flag before its next chunk
        let _ = self.wake.try_send(Chunk::End(why));
    }

    pub fn requested(&self) -> bool {
        self.flag.load(Ordering::SeqCst)
    }

    /// The flag, for a source that polls it (the probe).
    pub fn flag(&self) -> Arc<AtomicBool> {
        self.flag.clone()
    }
}

/// The recording that Ctrl-C stops.
static CTRL_C_TARGET: Mutex<Option<Stop>> = Mutex::new(None);
static CTRL_C_INSTALL: Once = Once::new();

/// Routes Ctrl-C (SIGINT; on Windows Ctrl-C and Ctrl-Break) to `stop` for the rest of the
/// process: the first asks the stream to end with [`End::Interrupted`], a second exits at
/// once with status 130. Returns the handler's error as one line, if it cannot be installed.
pub fn stop_on_ctrl_c(stop: &Stop) -> Result<(), String> {
    *CTRL_C_TARGET.lock().unwrap_or_else(|e| e.into_inner()) = Some(stop.clone());
    let mut result = Ok(());
    CTRL_C_INSTALL.call_once(|| {
        result = ctrlc::set_handler(|| {
            let target = CTRL_C_TARGET.lock().unwrap_or_else(|e| e.into_inner()).clone();
            match target {
                Some(s) if !s.requested() => s.request(End::Interrupted),
                _ => std::process::exit(130),
            }
        })
        .map_err(|e| format!("cannot install the Ctrl-C handler: {e}"));
    });
    result
}

/// How often [`stop_on_cancel`]'s watcher looks at the token.
const CANCEL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// Ends the recording with [`End::Interrupted`] once `token` is cancelled (the Python module's
/// Ctrl-C, [`crate::cancel`]), looked at every 50 ms by a thread of its own, which ends when
/// the returned guard is dropped or the recording has been asked to stop.
pub fn stop_on_cancel(stop: &Stop, token: crate::cancel::Cancel) -> CancelWatch {
    let done = Arc::new(AtomicBool::new(false));
    let (stop, watching) = (stop.clone(), done.clone());
    std::thread::spawn(move || {
        while !watching.load(Ordering::SeqCst) && !stop.requested() {
            if token.is_cancelled() {
                stop.request(End::Interrupted);
                return;
            }
            std::thread::sleep(CANCEL_POLL);
        }
    });
    CancelWatch(done)
}

/// Ends [`stop_on_cancel`]'s watcher when dropped.
pub struct CancelWatch(Arc<AtomicBool>);

impl Drop for CancelWatch {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// The chunks as one byte stream for the decoder; each chunk goes to the raw file first.
pub struct TeeReader {
    rx: Receiver<Chunk>,
    raw: File,
    stop: Stop,
    chunk: Vec<u8>,
    at: usize,
    /// Bytes written to the raw file (= bytes handed to the decoder).
    pub raw_bytes: u64,
    /// Why the stream ended, once it has.
    pub end: Option<End>,
}

impl TeeReader {
    pub fn new(rx: Receiver<Chunk>, raw: File, stop: Stop) -> Self {
        TeeReader { rx, raw, stop, chunk: Vec::new(), at: 0, raw_bytes: 0, end: None }
    }

    fn finish(&mut self, why: End) {
        if self.end.is_none() {
            self.end = Some(why);
        }
    }
}

impl Read for TeeReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        while self.at == self.chunk.len() {
            if self.end.is_some() {
                return Ok(0);
            }
            if self.stop.requested() {
                // the first request's reason, if it is still in the channel; else Ctrl-C's
                let why = loop {
                    match self.rx.try_recv() {
                        Ok(Chunk::End(e @ (End::Interrupted | End::CsvWriteFailed))) => break e,
                        Ok(_) => continue,
                        Err(_) => break End::Interrupted,
                    }
                };
                self.finish(why);
                return Ok(0);
            }
            match self.rx.recv() {
                Ok(Chunk::Data(d)) => {
                    if let Err(e) = self.raw.write_all(&d) {
                        self.finish(End::RawWriteFailed(e.to_string()));
                        return Ok(0);
                    }
                    self.raw_bytes += d.len() as u64;
                    self.chunk = d;
                    self.at = 0;
                }
                Ok(Chunk::End(e)) => {
                    self.finish(e);
                    return Ok(0);
                }
                // every sender gone without an end: the source's thread died
                Err(_) => {
                    self.finish(End::ReadFailed("the input's reader stopped".into()));
                    return Ok(0);
                }
            }
        }
        let n = buf.len().min(self.chunk.len() - self.at);
        buf[..n].copy_from_slice(&self.chunk[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}
