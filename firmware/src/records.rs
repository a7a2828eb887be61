//! Every defmt log record of the firmware, in one place: the contract with the host's
//! `decode` command (see README.md, "Log records", which lists them with their fields).
//!
//! Each record is one defmt frame whose text starts with the record's name and continues with
//! `key=value` fields separated by single spaces; arrays print as `[a, b, c, d]`. Keep names,
//! field names and field order stable; add fields only at the end of a record and bump
//! [`SCHEMA`] when a record changes. The defmt timestamp of every record is the uptime in
//! microseconds (embassy-time's `defmt-timestamp-uptime`).

use defmt::{error, info, warn};
use stickslip_model::rig::contact::{ContactEvent, ContactEventKind};
use stickslip_model::rig::sequencer::{Command, CommandResult, FaultCause, SeqState, Valves};
use stickslip_model::Halt;

use stickslip_rig_core::ClosedWindow;

/// Version of the record layout, printed in the `boot` record.
pub const SCHEMA: u32 = 1;

/// Why the chip last reset, from RCC_CSR (read and cleared once at boot).
#[derive(Clone, Copy)]
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

    /// Reads the reset flags and clears them (RMVF), most specific first: a watchdog reset
    /// also sets the pin flag (the reset drives NRST).
    pub fn read_and_clear() -> Self {
        let rcc = embassy_stm32::pac::RCC;
        let csr = rcc.csr().read();
        let cause = if csr.wdgrstf() {
            ResetCause::Watchdog
        } else if csr.wwdgrstf() {
            ResetCause::WindowWatchdog
        } else if csr.lpwrrstf() {
            ResetCause::LowPower
        } else if csr.sftrstf() {
            ResetCause::Software
        } else if csr.porrstf() {
            ResetCause::PowerOn
        } else if csr.borrstf() {
            ResetCause::BrownOut
        } else if csr.padrstf() {
            ResetCause::Pin
        } else {
            ResetCause::Unknown
        };
        rcc.csr().modify(|w| w.set_rmvf(true));
        cause
    }
}

/// Short names of the sequencer's states, as logged.
pub const fn state_name(s: SeqState) -> &'static str {
    match s {
        SeqState::Idle => "idle",
        SeqState::Clamp => "clamp",
        SeqState::Drive => "drive",
        SeqState::Record => "record",
        SeqState::Vent => "vent",
        SeqState::Fault(_) => "fault",
    }
}

/// Short names of the fault causes, as logged ("none" outside a fault).
pub const fn cause_name(s: SeqState) -> &'static str {
    match s {
        SeqState::Fault(c) => match c {
            FaultCause::EStop => "estop",
            FaultCause::NonFinite => "non_finite",
            FaultCause::ActuatorPressure => "actuator_pressure",
            FaultCause::BandPressure => "band_pressure",
            FaultCause::AccelSaturation => "accel_saturation",
            FaultCause::ClampTimeout => "clamp_timeout",
            FaultCause::DriveTimeout => "drive_timeout",
            FaultCause::RecordTimeout => "record_timeout",
        },
        _ => "none",
    }
}

const fn command_name(c: Command) -> &'static str {
    match c {
        Command::Start => "start",
        Command::Stop => "stop",
        Command::Reset => "reset",
    }
}

const fn result_name(r: CommandResult) -> &'static str {
    match r {
        CommandResult::Accepted => "accepted",
        CommandResult::Ignored => "ignored",
        CommandResult::Refused(_) => "refused",
    }
}

const fn event_name(k: ContactEventKind) -> &'static str {
    match k {
        ContactEventKind::StickToSlip => "stick_to_slip",
        ContactEventKind::SlipToStick => "slip_to_stick",
        ContactEventKind::Reversal => "reversal",
    }
}

const fn halt_name(h: Option<Halt>) -> &'static str {
    match h {
        None => "none",
        Some(Halt::NonFinite { .. }) => "non_finite",
        Some(Halt::Diverged { .. }) => "diverged",
        Some(Halt::ContactLoss { .. }) => "contact_loss",
        Some(Halt::TransitionStorm { .. }) => "transition_storm",
    }
}

/// Valve bits: 1 actuator open, 2 band open (0: both vented).
pub const fn valve_bits(v: Valves) -> u8 {
    v.actuator_open as u8 | (v.band_open as u8) << 1
}

/// `boot`: once, after the clocks and the trigger timer are set.
#[allow(clippy::too_many_arguments)]
pub fn boot(
    reset: ResetCause,
    fs_hz: f32,
    timer_clocks: u32,
    adc_channels: u32,
    window_samples: u32,
    batch_frames: u32,
    pressure: bool,
    end_of_stroke: bool,
) {
    info!(
        "boot fw={=str} schema={=u32} reset={=str} sysclk_hz={=u32} fs_hz={=f32} timer_clocks={=u32} adc_channels={=u32} window_samples={=u32} batch_frames={=u32} pressure={=bool} end_of_stroke={=bool}",
        env!("CARGO_PKG_VERSION"),
        SCHEMA,
        reset.name(),
        crate::config::SYSCLK_HZ,
        fs_hz,
        timer_clocks,
        adc_channels,
        window_samples,
        batch_frames,
        pressure,
        end_of_stroke
    );
}

/// `armed`: the lockstep model every record runs is built (once, at boot): its scene's
/// caliper and load position [m], F_N [N] (the clamp setpoint's), band speed [m/s], and the
/// normal force N0 at its start [N].
pub fn armed(build_us: u32, caliper: &'static str, beta_m: f32, f_n_n: f32, v_m_s: f32, n0_n: f32) {
    info!(
        "armed build_us={=u32} caliper={=str} beta={=f32} f_n={=f32} v={=f32} n0={=f32}",
        build_us, caliper, beta_m, f_n_n, v_m_s, n0_n
    );
}

/// `config_error`: the rig configuration was refused at boot; nothing runs (valves vented).
pub fn config_error(field: &'static str, rule: &'static str, value: f64) {
    error!("config_error field={=str} rule={=str} value={=f64}", field, rule, value);
}

/// `start`: sampling starts; the watchdog is running from here on. With the stack's
/// high-water mark since reset (the set-up's, the deepest it gets) and its size [bytes].
pub fn start(watchdog_us: u32, stack_used: u32, stack_size: u32) {
    info!("start watchdog_us={=u32} stack_used={=u32} stack_size={=u32}", watchdog_us, stack_used, stack_size);
}

/// `state`: the sequencer changed state at frame `n` (frames since boot).
pub fn state(n: u64, record: u32, from: SeqState, to: SeqState, valves: Valves) {
    info!(
        "state n={=u64} rec={=u32} from={=str} to={=str} cause={=str} valves={=u8}",
        n,
        record,
        state_name(from),
        state_name(to),
        cause_name(to),
        valve_bits(valves)
    );
}

/// `command`: a button press became a command at frame `n`.
pub fn command(n: u64, state: SeqState, c: Command, r: CommandResult) {
    let refused = match r {
        CommandResult::Refused(f) => cause_name(SeqState::Fault(f)),
        _ => "none",
    };
    info!(
        "command n={=u64} in={=str} cmd={=str} result={=str} refused_by={=str}",
        n,
        state_name(state),
        command_name(c),
        result_name(r),
        refused
    );
}

/// `event`: a contact event (rate-limited: see `config::EVENT_LOGS_PER_WINDOW`).
pub fn event(n: u64, record: u32, e: ContactEvent, v_r_m_s: f32, a_rel_m_s2: f32) {
    info!(
        "event n={=u64} rec={=u32} sample={=u64} kind={=str} v_r={=f32} a_rel={=f32}",
        n,
        record,
        e.sample,
        event_name(e.kind),
        v_r_m_s,
        a_rel_m_s2
    );
}

/// What the estimator task adds to a window record.
pub struct WindowExtras {
    pub n: u64,
    pub state: SeqState,
    pub overruns: u32,
    pub events_dropped: u32,
    pub windows_dropped: u32,
    pub batch_cycles_max: u32,
    pub batch_cycles_budget: u32,
}

/// `window`: the statistics of one window (one per 100 ms by default).
pub fn window(w: &ClosedWindow, x: &WindowExtras) {
    let r = &w.report;
    let m = r.model.unwrap_or_default();
    info!(
        "window n={=u64} rec={=u32} idx={=u32} first={=u64} samples={=u32} valid={=u32} pp={} rms={} groan_rms={} stick={=f32} ss_hz={=f32} onsets={=u32} saturated={=u32} faulted={=u32} nonfinite={=bool} model={=bool} model_samples={=u32} model_stick={=f32} model_ss_hz={=f32} model_onsets={=u32} residual_rms={=f32} model_halt={=str} p_mean={} p_min={} p_max={} state={=str} overruns={=u32} events_dropped={=u32} windows_dropped={=u32} batch_cyc_max={=u32} batch_cyc_budget={=u32}",
        x.n,
        w.record,
        r.index,
        r.first_sample,
        r.samples,
        r.valid_samples,
        r.pp_m_s2,
        r.rms_m_s2,
        r.groan_rms_m_s2,
        r.stick_fraction,
        r.stick_slip_hz,
        r.slip_onsets,
        r.saturated_samples,
        r.faulted_samples,
        r.non_finite,
        r.model.is_some(),
        m.samples,
        m.stick_fraction,
        m.stick_slip_hz,
        m.slip_onsets,
        m.residual_rms_m_s2,
        halt_name(m.halt),
        w.pressure.mean_bar,
        w.pressure.min_bar,
        w.pressure.max_bar,
        state_name(x.state),
        x.overruns,
        x.events_dropped,
        x.windows_dropped,
        x.batch_cycles_max,
        x.batch_cycles_budget
    );
}

/// `overrun`: the DMA ring was overwritten before the estimator task read it (frames lost;
/// the ring restarts at the next whole frame).
pub fn overrun(n: u64, count: u32) {
    warn!("overrun n={=u64} count={=u32}", n, count);
}

/// `stall`: no frames for `ms` milliseconds: valves vented, the watchdog will reset the chip.
pub fn stall(n: u64, ms: u32, adc_ovr: bool) {
    error!("stall n={=u64} ms={=u32} adc_ovr={=bool}", n, ms, adc_ovr);
}

/// `input`: a digital input changed (from its EXTI task).
pub fn input(name: &'static str, active: bool) {
    warn!("input name={=str} active={=bool}", name, active);
}

/// `panic`: the panic handler, after venting the valves.
pub fn panic(file: &str, line: u32, msg: &str) {
    error!("panic file={=str} line={=u32} msg={=str}", file, line, msg);
}
