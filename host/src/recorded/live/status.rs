//! `record`'s lines on stderr as the records arrive: a status line per `window` record (stick
//! fraction, stick-slip frequency, pad_x peak-to-peak, the valves, the frames dropped so far),
//! a line per `state` and `command` record and per record of level warn or error; and the
//! firmware's own loss counts from the window records, for the summary.

use std::io::Write;

use serde_json::Value;

use crate::output::format::sig4;
use crate::recorded::decode::Record;

/// Index of pad_x in the window record's per-channel arrays (disc_x, pad_x, pad_trail, pad_lead).
const PAD_X: usize = 1;

/// What the firmware says it did not log, from its window records.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirmwareLoss {
    /// Window records seen.
    pub windows: u64,
    /// Sum of `events_dropped` (event records not logged, per window record).
    pub events_dropped: u64,
    /// Sum of `windows_dropped` (windows closed and replaced before they were taken).
    pub windows_dropped: u64,
    /// `overruns` of the last window record (ADC ring overruns since boot).
    pub overruns: u64,
}

/// The stderr side of a recording.
pub struct Status {
    /// Redraw the window line in place (a terminal) instead of one line per window.
    in_place: bool,
    /// A window line is on the screen without its newline.
    pending: bool,
    /// The valves of the last `state` record (bit 1 actuator open, bit 2 band open).
    valves: Option<u64>,
    pub firmware: FirmwareLoss,
}

fn number(v: Option<&Value>) -> String {
    match v {
        Some(Value::Number(n)) => n.as_f64().map_or_else(|| n.to_string(), sig4),
        Some(Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
        None => "?".into(),
    }
}

fn text(v: Option<&Value>) -> String {
    match v {
        Some(Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
        None => "?".into(),
    }
}

/// The valves as words.
pub fn valves_text(bits: Option<u64>) -> &'static str {
    match bits {
        None => "unknown",
        Some(0) => "vented",
        Some(1) => "actuator open",
        Some(2) => "band open",
        Some(3) => "actuator+band open",
        Some(_) => "invalid bits",
    }
}

fn timestamp(r: &Record) -> String {
    r.timestamp_s.map_or_else(|| "t ?".into(), |t| format!("t {t:.3} s"))
}

impl Status {
    pub fn new(in_place: bool) -> Self {
        Status { in_place, pending: false, valves: None, firmware: FirmwareLoss::default() }
    }

    /// The status line of a window record.
    pub fn window_line(&self, r: &Record, dropped: u64) -> String {
        let pad_x_pp = match r.field("pp") {
            Some(Value::Array(a)) => number(a.get(PAD_X)),
            _ => "?".into(),
        };
        format!(
            "{}  rec {} window {}: stick {}, stick-slip {} Hz, pad_x {} m/s^2 p-p, valves {} ({}), {} frame{} dropped",
            timestamp(r),
            text(r.field("rec")),
            text(r.field("idx")),
            number(r.field("stick")),
            number(r.field("ss_hz")),
            pad_x_pp,
            valves_text(self.valves),
            text(r.field("state")),
            dropped,
            if dropped == 1 { "" } else { "s" }
        )
    }

    /// Takes a record: updates the valves and the firmware's counts; returns the line it
    /// shows, if any, and whether it is a window's status line.
    pub fn line(&mut self, r: &Record, dropped: u64) -> Option<(String, bool)> {
        let u = |k: &str| r.field(k).and_then(Value::as_u64);
        match r.kind.as_str() {
            "window" => {
                self.firmware.windows += 1;
                self.firmware.events_dropped += u("events_dropped").unwrap_or(0);
                self.firmware.windows_dropped += u("windows_dropped").unwrap_or(0);
                self.firmware.overruns = u("overruns").unwrap_or(self.firmware.overruns);
                Some((self.window_line(r, dropped), true))
            }
            "state" => {
                self.valves = u("valves").or(self.valves);
                Some((format!("{}  {}", timestamp(r), r.message), false))
            }
            _ if r.kind == "command" || matches!(r.level, Some("warn" | "error")) => {
                Some((format!("{}  {}", timestamp(r), r.message), false))
            }
            _ => None,
        }
    }

    /// Shows what [`Status::line`] returns for `r` on `out`.
    pub fn show(&mut self, r: &Record, dropped: u64, out: &mut impl Write) {
        let Some((line, is_window)) = self.line(r, dropped) else { return };
        let _ = if self.in_place {
            let r = if is_window { write!(out, "\r{line}\x1b[K") } else { write!(out, "\r{line}\x1b[K\n") };
            self.pending = is_window;
            r
        } else {
            writeln!(out, "{line}")
        };
        let _ = out.flush();
    }

    /// Ends a window line left in place.
    pub fn finish(&mut self, out: &mut impl Write) {
        if self.pending {
            let _ = writeln!(out);
            self.pending = false;
        }
    }
}
