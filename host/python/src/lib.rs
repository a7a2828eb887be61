//! `stickslip._stickslip`: the desktop tool's commands inside the Python interpreter.
//!
//! One entry point, [`run`]: a command line (without the program's name) in, what the tool
//! prints on stdout out, through the same parser and dispatcher as the `stickslip` binary
//! (`stickslip::cli::invoke::parse`, `stickslip::commands::run`). The Python package
//! (`python/stickslip/__init__.py`) builds the command lines and turns the JSON and CSV into
//! dicts and numpy arrays.
//!
//! - Errors: an input error (the tool's exit code 2) raises `ValueError`, any other failure
//!   `RuntimeError`, each with the tool's one-line message (without its `error: ` prefix).
//! - A panic inside the tool is caught on its worker thread and raised as `RuntimeError`; it
//!   never unwinds into the interpreter.
//! - The command runs on its own thread with the GIL released; the calling thread wakes every
//!   50 ms to let Python handle signals, so Ctrl-C in a notebook raises `KeyboardInterrupt` at
//!   once. The abandoned command is cancelled (`stickslip::cancel`): it stops at its next
//!   cancellation point (a map before its next cell, a fit before its next evaluation, a run
//!   or the virtual rig within 65,536 steps, a recording within 50 ms), its result dropped. [`running`] counts the
//!   commands whose threads have not ended yet.

use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use numpy::IntoPyArray;
use pyo3::prelude::*;

use stickslip::cancel::Cancel;
use stickslip::cli::invoke::{self, Parsed};

/// How often the waiting thread lets Python look for a signal.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The worker thread's stack [bytes]: the binary's main thread has 8 MiB; a spawned thread's
/// default is 2 MiB.
const WORKER_STACK_BYTES: usize = 8 << 20;

/// What a command line came to: stdout's text, or (exit code, one-line message).
type Outcome = Result<String, (u8, String)>;

/// Commands whose worker threads are still running (abandoned ones included).
static RUNNING: AtomicUsize = AtomicUsize::new(0);

/// Counts a worker thread in [`RUNNING`] for as long as it lives (a panic included).
struct Running;

impl Running {
    fn start() -> Self {
        RUNNING.fetch_add(1, Ordering::SeqCst);
        Running
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        RUNNING.fetch_sub(1, Ordering::SeqCst);
    }
}

fn execute(args: Vec<String>, token: Cancel) -> Outcome {
    let argv = std::iter::once("stickslip".to_string()).chain(args);
    match invoke::parse(argv) {
        Ok(Parsed::Help(h)) => Ok(h.render().to_string()),
        Ok(Parsed::Run(command)) => {
            stickslip::commands::run_cancellable(&command, token).map_err(|e| (e.exit_code(), e.to_string()))
        }
        Err(line) => Err((2, line.strip_prefix("error: ").unwrap_or(&line).to_string())),
    }
}

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Runs one `stickslip` command line (`args` without the program's name) and returns what the
/// tool prints on stdout. Raises ValueError for bad input (the tool's exit code 2) and
/// RuntimeError for any other failure, with the tool's one-line message.
#[pyfunction]
fn run(py: Python<'_>, args: Vec<String>) -> PyResult<String> {
    let (tx, rx) = mpsc::channel::<Outcome>();
    let token = Cancel::new();
    let worker_token = token.clone();
    std::thread::Builder::new()
        .name("stickslip".into())
        .stack_size(WORKER_STACK_BYTES)
        .spawn(move || {
            let _running = Running::start();
            let out = panic::catch_unwind(AssertUnwindSafe(|| execute(args, worker_token)))
                .unwrap_or_else(|p| Err((101, format!("internal error (a bug: please report it): {}", panic_message(p)))));
            // The caller may have gone (Ctrl-C): nobody to tell.
            let _ = tx.send(out);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the worker thread: {e}")))?;
    // A Receiver is not Sync: the waiting closure, which runs without the GIL, borrows it
    // through a Mutex (only this thread ever locks it).
    let rx = std::sync::Mutex::new(rx);
    loop {
        let next = py.detach(|| match rx.lock() {
            Ok(rx) => rx.recv_timeout(SIGNAL_POLL),
            Err(_) => Err(RecvTimeoutError::Disconnected),
        });
        match next {
            Ok(Ok(text)) => return Ok(text),
            Ok(Err((2, msg))) => return Err(PyValueError::new_err(msg)),
            Ok(Err((_, msg))) => return Err(PyRuntimeError::new_err(msg)),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    // Ctrl-C (or another signal handler's exception): the command is abandoned
                    token.cancel();
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the worker thread ended without a result"))
            }
        }
    }
}

/// One column of a series CSV: numbers, or text where any row is not a number.
enum Column {
    Numbers(Vec<f64>),
    Text(Vec<String>),
}

impl Column {
    /// Numbers as a float64 numpy array (moved, not copied); text as a list of str.
    fn into_py(self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(match self {
            Column::Numbers(v) => v.into_pyarray(py).into_any().unbind(),
            Column::Text(v) => v.into_pyobject(py)?.into_any().unbind(),
        })
    }
}

/// Reads a series CSV the tool wrote (`simulate --csv`, `sil --csv`): its header and its
/// columns, each all numbers (a float64 numpy array, parsed exactly as Rust parses the tool's
/// own output) or text (a list of str). Raises ValueError naming the line of a row with the wrong number of fields.
#[pyfunction]
fn read_series_csv(py: Python<'_>, path: std::path::PathBuf) -> PyResult<(Vec<String>, Vec<Py<PyAny>>)> {
    let (header, columns) = py.detach(move || -> PyResult<(Vec<String>, Vec<Column>)> {
        let mut r = csv::Reader::from_path(&path).map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
        let header: Vec<String> = r
            .headers()
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut text: Vec<Vec<String>> = vec![Vec::new(); header.len()];
        for (i, row) in r.records().enumerate() {
            let row = row.map_err(|e| PyValueError::new_err(format!("{}: line {}: {e}", path.display(), i + 2)))?;
            for (c, field) in row.iter().enumerate() {
                text[c].push(field.to_string());
            }
        }
        let columns = text
            .into_iter()
            .map(|col| match col.iter().map(|x| x.parse::<f64>()).collect::<Result<Vec<f64>, _>>() {
                Ok(v) => Column::Numbers(v),
                Err(_) => Column::Text(col),
            })
            .collect();
        Ok((header, columns))
    })?;
    let columns = columns.into_iter().map(|c| c.into_py(py)).collect::<PyResult<Vec<_>>>()?;
    Ok((header, columns))
}

/// The number of commands whose worker threads have not ended yet: an abandoned (cancelled)
/// command counts until it reaches its cancellation point.
#[pyfunction]
fn running() -> usize {
    RUNNING.load(Ordering::SeqCst)
}

/// Every key a scene file may hold, in the tool's order (`stickslip::scenes::scene_file::KEYS`):
/// the one list the module tells scene keys from flags by.
#[pyfunction]
fn scene_keys() -> Vec<&'static str> {
    stickslip::scenes::scene_file::KEYS.iter().map(|(k, _)| *k).collect()
}

/// The flags of `command` (e.g. `["map"]`) that take no value, without their `--`; None for
/// an unknown command.
#[pyfunction]
fn switches(command: Vec<String>) -> Option<Vec<String>> {
    let path: Vec<&str> = command.iter().map(String::as_str).collect();
    invoke::switches(&path)
}

/// The tool's version (the host crate's).
#[pyfunction]
fn version() -> &'static str {
    stickslip::VERSION
}

#[pymodule]
fn _stickslip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(running, m)?)?;
    m.add_function(wrap_pyfunction!(scene_keys, m)?)?;
    m.add_function(wrap_pyfunction!(switches, m)?)?;
    m.add_function(wrap_pyfunction!(read_series_csv, m)?)?;
    Ok(())
}
