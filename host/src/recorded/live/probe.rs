//! `record`'s probe source (cargo feature `probe`): the board through a debug probe with the
//! probe-rs library. Opens the probe (the only one, or the one `--probe VID:PID[:SERIAL]`
//! names), attaches to the chip (`--chip`), optionally flashes the ELF and resets, finds the
//! RTT control block (at the ELF's `_SEGGER_RTT` symbol, else by a scan of the chip's RAM) and
//! polls up-channel 0, the firmware's defmt log, sending what it reads as raw chunks. A probe
//! error while polling ends the stream with [`End::Lost`].
//!
//! Everything runs in the poll thread (probe-rs's session stays on one thread); the set-up's
//! outcome comes back before [`start`] returns, so a missing probe fails before any file is made.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, SyncSender};
use std::sync::Arc;
use std::time::{Duration, Instant};

use probe_rs::flashing::{download_file, ElfLoader, ElfOptions};
use probe_rs::probe::list::Lister;
use probe_rs::probe::DebugProbeSelector;
use probe_rs::rtt::{find_rtt_control_block_in_raw_file, Rtt, ScanRegion};
use probe_rs::{Permissions, Session};

use super::source::{Chunk, End};
use crate::error::{HostError, Result};

/// The firmware's log channel (defmt-rtt's up-channel 0).
const LOG_CHANNEL: usize = 0;
/// How long to look for the control block after a reset [s] (the firmware sets it up at boot,
/// after the clocks: well under this).
const RTT_WAIT_S: f64 = 3.0;
/// The pause after an empty poll: the firmware's 4 KB RTT buffer fills in about 0.25 s at
/// its ~15 KB/s, so polling every 5 ms never lets it overflow.
const IDLE_POLL: Duration = Duration::from_millis(5);
/// Bytes per read of the channel (the firmware's RTT buffer is 4 KB).
const READ_BYTES: usize = 4096;

/// What to attach to.
pub struct ProbeRequest<'a> {
    /// The chip, as probe-rs names it.
    pub chip: &'a str,
    /// VID:PID[:SERIAL] of the probe.
    pub probe: Option<&'a str>,
    /// Flash this ELF (the `--elf` file) and reset first.
    pub flash: Option<&'a Path>,
    /// The ELF's bytes (its `_SEGGER_RTT` symbol).
    pub elf: &'a [u8],
}

/// Opens the probe, attaches and finds the log channel, then polls it in a thread of its own
/// until `stop` is set or the connection fails. Returns a line describing the source; the
/// errors of the set-up are bad input (exit 2), one line each.
pub fn start(req: &ProbeRequest, tx: SyncSender<Chunk>, stop: Arc<AtomicBool>) -> Result<String> {
    let selector = match req.probe {
        Some(s) => Some(s.parse::<DebugProbeSelector>().map_err(|e| {
            HostError::Input(format!("--probe {s}: not VID:PID[:SERIAL] with VID and PID in hex, e.g. 0483:374b ({e})"))
        })?),
        None => None,
    };
    let chip = req.chip.to_string();
    let flash = req.flash.map(Path::to_path_buf);
    let rtt_at = find_rtt_control_block_in_raw_file(req.elf).ok().flatten();
    let (ready_tx, ready_rx) = channel::<Result<String>>();
    std::thread::spawn(move || {
        let (mut session, mut rtt, what) = match attach(selector.as_ref(), &chip, flash.as_deref(), rtt_at) {
            Ok(s) => s,
            Err(e) => {
                let _ = ready_tx.send(Err(e));
                return;
            }
        };
        let _ = ready_tx.send(Ok(what));
        let mut buf = vec![0u8; READ_BYTES];
        while !stop.load(Ordering::SeqCst) {
            let read = match session.core(0) {
                Ok(mut core) => match rtt.up_channel(LOG_CHANNEL) {
                    Some(ch) => ch.read(&mut core, &mut buf).map_err(|e| one_line(&e)),
                    None => Err(format!("up-channel {LOG_CHANNEL} is gone")),
                },
                Err(e) => Err(one_line(&e)),
            };
            match read {
                Ok(0) => std::thread::sleep(IDLE_POLL),
                Ok(n) => {
                    if tx.send(Chunk::Data(buf[..n].to_vec())).is_err() {
                        return;
                    }
                }
                Err(e) => {
                    let _ = tx.send(Chunk::End(End::Lost(e)));
                    return;
                }
            }
        }
    });
    ready_rx
        .recv()
        .unwrap_or_else(|_| Err(HostError::Input("the probe's thread ended during the set-up".into())))
}

/// An error and its causes on one line.
fn one_line(e: &(dyn std::error::Error + 'static)) -> String {
    let mut s = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let t = c.to_string();
        if !s.contains(&t) {
            s.push_str(": ");
            s.push_str(&t);
        }
        cause = c.source();
    }
    s
}

fn attach(
    selector: Option<&DebugProbeSelector>,
    chip: &str,
    flash: Option<&Path>,
    rtt_at: Option<u64>,
) -> Result<(Session, Rtt, String)> {
    let lister = Lister::new();
    let found = lister.list(selector);
    let info = match (found.len(), selector) {
        (0, None) => {
            return Err(HostError::Input(
                "no debug probe found (USB): connect the board's ST-LINK (or another probe-rs probe), \
                 check the udev rules (README, At the rig), or read a saved stream with --input"
                    .into(),
            ))
        }
        (0, Some(s)) => {
            let all: Vec<String> = lister.list_all().iter().map(|p| p.to_string()).collect();
            return Err(HostError::Input(format!(
                "--probe {:04x}:{:04x}: no such probe connected (found: {})",
                s.vendor_id,
                s.product_id,
                if all.is_empty() { "none".to_string() } else { all.join("; ") }
            )));
        }
        (1, _) => found[0].clone(),
        (n, _) => {
            let all: Vec<String> = found.iter().map(|p| p.to_string()).collect();
            return Err(HostError::Input(format!(
                "{n} debug probes found: choose one with --probe VID:PID:SERIAL ({})",
                all.join("; ")
            )));
        }
    };
    let name = info.to_string();
    let probe = info.open().map_err(|e| {
        HostError::Input(format!("{name}: cannot open the probe: {} (udev rules: README, At the rig)", one_line(&e)))
    })?;
    let mut session = probe
        .attach(chip, Permissions::default())
        .map_err(|e| HostError::Input(format!("--chip {chip}: cannot attach through {name}: {}", one_line(&e))))?;
    let region = rtt_at.map_or(ScanRegion::Ram, ScanRegion::Exact);
    let mut flashed = "";
    if let Some(elf) = flash {
        let label = elf.display();
        {
            let mut core = session.core(0).map_err(|e| HostError::Input(format!("--flash {label}: {}", one_line(&e))))?;
            // a control block left in RAM by the previous run is not the new firmware's
            let _ = core.halt(Duration::from_millis(500));
            let _ = Rtt::clear_control_block(&mut core, &region);
        }
        download_file(&mut session, elf, ElfLoader(ElfOptions::default()))
            .map_err(|e| HostError::Input(format!("--flash {label}: cannot flash: {}", one_line(&e))))?;
        session
            .core(0)
            .and_then(|mut core| core.reset())
            .map_err(|e| HostError::Input(format!("--flash {label}: cannot reset the chip: {}", one_line(&e))))?;
        flashed = ", flashed and reset";
    }
    let started = Instant::now();
    let rtt = loop {
        let attempt = session.core(0).map_err(|e| e.to_string()).and_then(|mut core| {
            Rtt::attach_region(&mut core, &region).map_err(|e| one_line(&e))
        });
        match attempt {
            Ok(rtt) => break rtt,
            Err(e) if started.elapsed().as_secs_f64() > RTT_WAIT_S => {
                return Err(HostError::Input(format!(
                    "--chip {chip}: no RTT control block{} within {RTT_WAIT_S} s: {e} (is the --elf firmware running on the board?)",
                    rtt_at.map_or(" in RAM".to_string(), |a| format!(" at {a:#010x} (_SEGGER_RTT)"))
                )))
            }
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    };
    let mut rtt = rtt;
    let channel = rtt
        .up_channel(LOG_CHANNEL)
        .map(|c| format!("up-channel {LOG_CHANNEL} {:?}, {} bytes", c.name().unwrap_or(""), c.buffer_size()))
        .ok_or_else(|| HostError::Input(format!("--chip {chip}: the RTT control block has no up-channel {LOG_CHANNEL}")))?;
    let what = format!("{chip} through {name}{flashed}, RTT at {:#010x}, {channel}", rtt.ptr());
    Ok((session, rtt, what))
}
