//! Cancelling a command from outside (`stickslip::cancel`, the Python module's Ctrl-C):
//! `commands::run_cancellable` with a token that is cancelled before the command starts, or
//! while it runs, ends the command at its next cancellation point with `HostError::Cancelled`
//! (exit code 130): a map, a fit, a single run; a recording ends as Ctrl-C ends it in the
//! binary, with its files and summary. A command whose token is never cancelled runs as
//! `commands::run` does.

use std::sync::mpsc;
use std::time::Duration;

use stickslip::cancel::Cancel;
use stickslip::cli::invoke::{self, Parsed};
use stickslip::commands;
use stickslip::error::HostError;

fn command(args: &[&str]) -> stickslip::cli::Command {
    match invoke::parse(std::iter::once("stickslip").chain(args.iter().copied())) {
        Ok(Parsed::Run(c)) => c,
        Ok(Parsed::Help(_)) => panic!("{args:?}: help, not a command"),
        Err(e) => panic!("{args:?}: {e}"),
    }
}

/// Runs `args` with `token` on a thread of its own; the result, or None if it has not ended
/// within `limit` (a hang guard: a command that is not cancelled runs for minutes).
fn run_with(args: &[&str], token: Cancel, limit: Duration) -> Option<Result<String, HostError>> {
    let cmd = command(args);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(commands::run_cancellable(&cmd, token));
    });
    rx.recv_timeout(limit).ok()
}

/// Starts `args` on a thread of its own, lets it run for `wait`, checks that it has not ended,
/// cancels it, and returns how it ended (None: not within the hang guard).
fn cancelled_while_running(args: &[&str], wait: Duration) -> Option<Result<String, HostError>> {
    let token = Cancel::new();
    let cmd = command(args);
    let (tx, rx) = mpsc::channel();
    let worker = token.clone();
    std::thread::spawn(move || {
        let _ = tx.send(commands::run_cancellable(&cmd, worker));
    });
    std::thread::sleep(wait);
    assert!(rx.try_recv().is_err(), "{args:?} ended before it was cancelled");
    token.cancel();
    rx.recv_timeout(HANG_GUARD).ok()
}

fn cancelled(token: &Cancel) -> Cancel {
    token.cancel();
    token.clone()
}

const HANG_GUARD: Duration = Duration::from_secs(120);

/// A map of the floating rig set too large to finish in the test's time (300 x 300 cells of
/// two 1 s runs: about 13 minutes on two cores).
const BIG_RIG_MAP: &[&str] = &["map", "rig_float_push_center", "--sweep", "beta=0.01:0.07:300", "--sweep", "v=0.001:0.01:300", "--json"];

#[test]
fn a_cancelled_map_fit_or_run_ends_as_cancelled_with_exit_code_130() {
    let cases: [&[&str]; 4] = [
        BIG_RIG_MAP,
        &["map", "push_center", "--sweep", "beta=0.01:0.07:20", "--sweep", "mu_s=0.4:0.8:20", "--json"],
        &["fit", "--scene", "push_center", "--free", "mu_s,mu_k", "--table", "thesis_table_3_1", "--json"],
        &["simulate", "rig_float_push_center", "--json"],
    ];
    for args in cases {
        let r = run_with(args, cancelled(&Cancel::new()), HANG_GUARD).unwrap_or_else(|| panic!("{args:?}: not ended"));
        match r {
            Err(e @ HostError::Cancelled) => {
                assert_eq!(e.exit_code(), 130);
                assert_eq!(e.to_string(), "cancelled");
            }
            Err(e) => panic!("{args:?}: {e}, not cancelled"),
            Ok(out) => panic!("{args:?}: ran to its end ({} bytes out)", out.len()),
        }
    }
}

#[test]
fn a_map_cancelled_while_it_runs_stops_at_its_next_cell() {
    // half a second gets it into its cells (the set-up of a cell is milliseconds)
    match cancelled_while_running(BIG_RIG_MAP, Duration::from_millis(500)) {
        Some(Err(HostError::Cancelled)) => {}
        Some(Err(e)) => panic!("{e}, not cancelled"),
        Some(Ok(_)) => panic!("the map ran to its end"),
        None => panic!("the map did not stop"),
    }
}

#[test]
fn an_event_driven_run_cancelled_while_it_runs_stops_at_its_next_grid_time() {
    // model 3 (unilateral edges, the pneumatic drive) runs on the event runner, not the
    // stepper: 3,000 s of rig_built_push_center take about 7 minutes
    let args = ["simulate", "rig_built_push_center", "--duration", "3000", "--json"];
    match cancelled_while_running(&args, Duration::from_millis(500)) {
        Some(Err(HostError::Cancelled)) => {}
        Some(Err(e)) => panic!("{e}, not cancelled"),
        Some(Ok(_)) => panic!("the run ran to its end"),
        None => panic!("the run did not stop"),
    }
}

#[test]
fn a_token_that_is_never_cancelled_changes_nothing() {
    let args = ["simulate", "push_center", "--json"];
    let plain = commands::run(&command(&args)).expect("runs");
    let with_token = run_with(&args, Cancel::new(), HANG_GUARD).expect("ends").expect("runs");
    assert_eq!(plain, with_token);
}

#[cfg(unix)]
#[test]
fn a_cancelled_recording_ends_as_interrupted_with_its_summary() {
    // a pipe that stays open and silent: without the cancellation the recording waits for ever
    let dir = std::env::temp_dir().join(format!("stickslip-cancel-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("stream.fifo");
    let status = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(status.success());
    let writer_path = fifo.clone();
    // the writer holds the pipe open (open blocks until the recording opens it to read)
    std::thread::spawn(move || {
        let _w = std::fs::OpenOptions::new().write(true).open(writer_path).expect("open the pipe to write");
        std::thread::sleep(Duration::from_secs(600));
    });
    let elf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.elf");
    let out = dir.join("rec");
    let args = ["record", "--elf", elf, "--input", fifo.to_str().unwrap(), "--out", out.to_str().unwrap()];
    let summary = match cancelled_while_running(&args, Duration::from_millis(300)) {
        Some(Ok(s)) => s,
        Some(Err(e)) => panic!("the recording failed: {e}"),
        None => panic!("the recording did not end"),
    };
    assert!(summary.contains("stopped by Ctrl-C"), "{summary}");
    assert!(out.join("raw.defmt").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
