//! What the firmware logs, as values: the [`Record`]s of its log (the contract with the host's
//! `decode` command; their defmt text is the crate `stickslip-records`, ../records) and the
//! [`Logbook`], the bookkeeping of the estimator task around the [`Rig`]: frames counted since
//! boot, a command or a state change per sample, contact events rate-limited per window, ring
//! overruns, batch cycle counts, and one window record per closed window.
//!
//! No logging here: records go to a [`RecordSink`]. The firmware's sink writes them with
//! defmt over RTT; the on-target program `tests/on-target/src/bin/records.rs` writes them with
//! defmt over semihosting; the host test `tests/tests/records_on_target.rs` collects them and
//! compares them with what it decodes from that program's stream.

use stickslip_model::rig::contact::ContactEvent;
use stickslip_model::rig::health::ChannelHealth;
use stickslip_model::rig::noise_floor::FloorReport;
use stickslip_model::rig::sequencer::{Command, CommandResult, SeqState, Valves};

use stickslip_model::rig::pipeline::{ClosedWindow, Rig, SampleOut};

/// Version of the record layout, printed in the `boot` record. Keep names, field names and
/// field order stable; add fields only at the end of a record and bump this when one changes.
pub const SCHEMA: u32 = 2;

/// Why the chip last reset (the firmware reads RCC_CSR once at boot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResetCause {
    Watchdog,
    WindowWatchdog,
    LowPower,
    Software,
    PowerOn,
    Pin,
    BrownOut,
    Unknown,
}

impl ResetCause {
    pub const fn name(self) -> &'static str {
        match self {
            ResetCause::Watchdog => "watchdog",
            ResetCause::WindowWatchdog => "window_watchdog",
            ResetCause::LowPower => "low_power",
            ResetCause::Software => "software",
            ResetCause::PowerOn => "power_on",
            ResetCause::Pin => "pin",
            ResetCause::BrownOut => "brown_out",
            ResetCause::Unknown => "unknown",
        }
    }
}

/// The `boot` record: once, after the clocks and the trigger timer are set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Boot {
    pub fw: &'static str,
    pub reset: ResetCause,
    pub sysclk_hz: u32,
    /// The actual sampling rate per channel [Hz].
    pub fs_hz: f32,
    /// Trigger timer clocks per scan (`oversample` scans per sample).
    pub timer_clocks: u32,
    pub adc_channels: u32,
    pub window_samples: u32,
    /// Frames per half of the DMA ring (one batch of the estimator task).
    pub batch_frames: u32,
    pub pressure: bool,
    pub end_of_stroke: bool,
    /// Scans summed per frame (the calibration's `adc.oversample`).
    pub oversample: u32,
}

/// What the estimator task adds to a window record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowExtras {
    /// Frames since boot when the record is written.
    pub n: u64,
    pub state: SeqState,
    pub overruns: u32,
    pub events_dropped: u32,
    pub windows_dropped: u32,
    pub batch_cycles_max: u32,
    pub batch_cycles_budget: u32,
}

/// One record of the firmware's log. `n` is the number of frames since boot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Record<'a> {
    Boot(Boot),
    /// The lockstep model every record runs is built (once, at boot): its scene's caliper and
    /// load position [m], F_N [N] (the clamp setpoint's), band speed [m/s], and the normal
    /// force N0 at its start [N].
    Armed { build_us: u32, caliper: &'static str, beta_m: f32, f_n_n: f32, v_m_s: f32, n0_n: f32 },
    /// The rig configuration was refused at boot; nothing runs (valves vented).
    ConfigError { field: &'static str, rule: &'static str, value: f64 },
    /// Sampling starts; the watchdog runs from here on. With the stack's high-water mark since
    /// reset and its size [bytes].
    Start { watchdog_us: u32, stack_used: u32, stack_size: u32 },
    /// The sequencer changed state at frame `n`.
    State { n: u64, record: u32, from: SeqState, to: SeqState, valves: Valves },
    /// A button press became a command at frame `n`, in state `state`.
    Command { n: u64, state: SeqState, command: Command, result: CommandResult },
    /// A contact event (rate-limited per window), with the relative velocity [m/s] and
    /// acceleration [m/s^2] of the sample.
    Event { n: u64, record: u32, event: ContactEvent, v_r_m_s: f32, a_rel_m_s2: f32 },
    /// The statistics of one window.
    Window { window: &'a ClosedWindow, extras: WindowExtras },
    /// The clamped phase ended into Drive: the noise floor it measured (per accelerometer and
    /// a_rel: mean, sigma and peak-to-peak [m/s^2] over `samples`) and the contact thresholds
    /// designed from it (slip onset and stick level [m/s^2]), in force from here on.
    Floor { n: u64, record: u32, floor: FloorReport, onset_m_s2: f32, stick_m_s2: f32 },
    /// A window of a record on which an accelerometer is flat or noisier than the signal
    /// (masks: bit i for channel i, in the order disc_x, pad_x, pad_trail, pad_lead);
    /// `undecided`: the window's stick fraction and frequency are a guess.
    Health { n: u64, record: u32, index: u32, flat: u8, noisy: u8, undecided: bool },
    /// The DMA ring was overwritten before it was read (`count` since boot).
    Overrun { n: u64, count: u32 },
    /// No frames for `ms` milliseconds: valves vented, the watchdog will reset the chip.
    Stall { n: u64, ms: u32, adc_ovr: bool },
    /// A digital input changed.
    Input { name: &'static str, active: bool },
    /// The panic handler, after venting the valves.
    Panic { file: &'a str, line: u32, msg: &'a str },
}

/// Where records go.
pub trait RecordSink {
    fn record(&mut self, r: &Record<'_>);
}

/// The estimator task's log bookkeeping (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Logbook {
    /// Frames since boot.
    n: u64,
    overruns: u32,
    events_logged: u32,
    events_dropped: u32,
    batch_cycles_max: u32,
    batch_cycles_budget: u32,
    event_logs_per_window: u32,
}

impl Logbook {
    /// `batch_cycles_budget`: core cycles in the time of one batch; at most
    /// `event_logs_per_window` event records per window (the rest are counted in the window
    /// record's `events_dropped`).
    pub const fn new(batch_cycles_budget: u32, event_logs_per_window: u32) -> Self {
        Logbook {
            n: 0,
            overruns: 0,
            events_logged: 0,
            events_dropped: 0,
            batch_cycles_max: 0,
            batch_cycles_budget,
            event_logs_per_window,
        }
    }

    /// Frames since boot.
    pub fn frames(&self) -> u64 {
        self.n
    }

    /// Ring overruns since boot.
    pub fn overruns(&self) -> u32 {
        self.overruns
    }

    /// After `core` ran one frame (`out`; `command` is what it was given): the command, the
    /// state change and the contact event of that frame. Counts the frame.
    #[inline]
    pub fn sample<S: RecordSink>(&mut self, sink: &mut S, rig: &Rig, command: Option<Command>, out: &SampleOut) {
        let n = self.n;
        if let (Some(c), Some(r)) = (command, out.sequencer.command) {
            sink.record(&Record::Command { n, state: out.before, command: c, result: r });
        }
        if out.sequencer.changed {
            sink.record(&Record::State {
                n,
                record: rig.record(),
                from: out.before,
                to: out.sequencer.state,
                valves: out.sequencer.valves,
            });
        }
        if let Some(e) = out.estimate.contact.event {
            if self.events_logged < self.event_logs_per_window {
                sink.record(&Record::Event {
                    n,
                    record: rig.record(),
                    event: e,
                    v_r_m_s: out.estimate.contact.v_r_m_s,
                    a_rel_m_s2: out.estimate.contact.a_rel_m_s2,
                });
                self.events_logged += 1;
            } else {
                self.events_dropped = self.events_dropped.saturating_add(1);
            }
        }
        self.n += 1;
    }

    /// The ring was overwritten before it was read: counted and logged (the lost frames are
    /// not counted in [`frames`](Self::frames): nobody knows how many there were).
    pub fn overrun<S: RecordSink>(&mut self, sink: &mut S) {
        self.overruns = self.overruns.saturating_add(1);
        sink.record(&Record::Overrun { n: self.n, count: self.overruns });
    }

    /// After a batch of frames that took `cycles` core cycles: the floor record if the batch
    /// ended a clamp into Drive, and the record of every window the batch closed (their
    /// divisions and square roots are done here, outside the per-sample loop), with a health
    /// record after a record's window on which a channel is flat or noisier than the signal.
    /// The event rate limit and the batch maximum restart with each window.
    pub fn end_batch<S: RecordSink>(&mut self, sink: &mut S, rig: &mut Rig, cycles: u32) {
        self.batch_cycles_max = self.batch_cycles_max.max(cycles);
        if let Some((floor, th)) = rig.take_floor() {
            sink.record(&Record::Floor {
                n: self.n,
                record: rig.record(),
                floor,
                onset_m_s2: th.slip_onset_m_s2,
                stick_m_s2: th.stick_max_m_s2,
            });
        }
        while let Some(w) = rig.take_window() {
            let extras = WindowExtras {
                n: self.n,
                state: rig.state(),
                overruns: self.overruns,
                events_dropped: self.events_dropped,
                windows_dropped: rig.windows_dropped(),
                batch_cycles_max: self.batch_cycles_max,
                batch_cycles_budget: self.batch_cycles_budget,
            };
            sink.record(&Record::Window { window: &w, extras });
            if rig.state() == SeqState::Record {
                let h = rig.window_health(&w.report);
                if !h.ok() {
                    sink.record(&Record::Health {
                        n: self.n,
                        record: w.record,
                        index: w.report.index,
                        flat: h.mask(ChannelHealth::FLAT),
                        noisy: h.mask(ChannelHealth::NOISY),
                        undecided: h.undecidable(),
                    });
                }
            }
            self.events_logged = 0;
            self.events_dropped = 0;
            self.batch_cycles_max = 0;
        }
    }
}
