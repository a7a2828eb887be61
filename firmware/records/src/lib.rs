//! The defmt text of every [`Record`] of the firmware's log: the contract with the host's
//! `decode` command (firmware/README.md, "Log records", lists them with their fields and
//! units).
//!
//! Each record is one defmt frame whose text starts with the record's name and continues with
//! `key=value` fields separated by single spaces; arrays print as `[a, b, c, d]`. Keep names,
//! field names and field order stable; add fields only at the end of a record and bump
//! [`SCHEMA`] when a record changes. The timestamp is the logger's
//! (the firmware's: the uptime in microseconds, embassy-time's `defmt-timestamp-uptime`).
//!
//! The program that links this needs a defmt global logger (the firmware: defmt-rtt; the
//! on-target program `records`: defmt-semihosting). Its own crate so that the firmware builds
//! it for size (firmware/Cargo.toml, [profile.release]) and `stickslip-rig-core` for speed.
#![no_std]

use defmt::{error, info, warn};
use stickslip_model::rig::contact::ContactEventKind;
use stickslip_model::rig::sequencer::{Command, CommandResult, FaultCause, SeqState, Valves};
use stickslip_model::Halt;

pub use stickslip_rig_core::logbook::{Record, RecordSink, SCHEMA};

/// The sink that logs with defmt.
pub struct Defmt;

impl RecordSink for Defmt {
    #[inline]
    fn record(&mut self, r: &Record<'_>) {
        log(r)
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
        SeqState::Fault(c) => fault_name(c),
        _ => "none",
    }
}

/// Short names of the fault causes.
pub const fn fault_name(c: FaultCause) -> &'static str {
    match c {
        FaultCause::EStop => "estop",
        FaultCause::NonFinite => "non_finite",
        FaultCause::ActuatorPressure => "actuator_pressure",
        FaultCause::BandPressure => "band_pressure",
        FaultCause::AccelSaturation => "accel_saturation",
        FaultCause::ClampTimeout => "clamp_timeout",
        FaultCause::DriveTimeout => "drive_timeout",
        FaultCause::RecordTimeout => "record_timeout",
    }
}

pub const fn command_name(c: Command) -> &'static str {
    match c {
        Command::Start => "start",
        Command::Stop => "stop",
        Command::Reset => "reset",
    }
}

pub const fn result_name(r: CommandResult) -> &'static str {
    match r {
        CommandResult::Accepted => "accepted",
        CommandResult::Ignored => "ignored",
        CommandResult::Refused(_) => "refused",
    }
}

/// The fault that refused a command ("none" when it was not refused).
pub const fn refused_by(r: CommandResult) -> &'static str {
    match r {
        CommandResult::Refused(f) => fault_name(f),
        _ => "none",
    }
}

pub const fn event_name(k: ContactEventKind) -> &'static str {
    match k {
        ContactEventKind::StickToSlip => "stick_to_slip",
        ContactEventKind::SlipToStick => "slip_to_stick",
        ContactEventKind::Reversal => "reversal",
    }
}

pub const fn halt_name(h: Option<Halt>) -> &'static str {
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

/// Writes one record. Not inlined: one copy of the formatting.
#[inline(never)]
pub fn log(r: &Record<'_>) {
    match *r {
        Record::Boot(b) => info!(
            "boot fw={=str} schema={=u32} reset={=str} sysclk_hz={=u32} fs_hz={=f32} timer_clocks={=u32} adc_channels={=u32} window_samples={=u32} batch_frames={=u32} pressure={=bool} end_of_stroke={=bool} oversample={=u32}",
            b.fw,
            SCHEMA,
            b.reset.name(),
            b.sysclk_hz,
            b.fs_hz,
            b.timer_clocks,
            b.adc_channels,
            b.window_samples,
            b.batch_frames,
            b.pressure,
            b.end_of_stroke,
            b.oversample
        ),
        Record::Armed { build_us, caliper, beta_m, f_n_n, v_m_s, n0_n } => info!(
            "armed build_us={=u32} caliper={=str} beta={=f32} f_n={=f32} v={=f32} n0={=f32}",
            build_us, caliper, beta_m, f_n_n, v_m_s, n0_n
        ),
        Record::ConfigError { field, rule, value } => {
            error!("config_error field={=str} rule={=str} value={=f64}", field, rule, value)
        }
        Record::Start { watchdog_us, stack_used, stack_size } => info!(
            "start watchdog_us={=u32} stack_used={=u32} stack_size={=u32}",
            watchdog_us, stack_used, stack_size
        ),
        Record::State { n, record, from, to, valves } => info!(
            "state n={=u64} rec={=u32} from={=str} to={=str} cause={=str} valves={=u8}",
            n,
            record,
            state_name(from),
            state_name(to),
            cause_name(to),
            valve_bits(valves)
        ),
        Record::Command { n, state, command, result } => info!(
            "command n={=u64} in={=str} cmd={=str} result={=str} refused_by={=str}",
            n,
            state_name(state),
            command_name(command),
            result_name(result),
            refused_by(result)
        ),
        Record::Event { n, record, event, v_r_m_s, a_rel_m_s2 } => info!(
            "event n={=u64} rec={=u32} sample={=u64} kind={=str} v_r={=f32} a_rel={=f32}",
            n,
            record,
            event.sample,
            event_name(event.kind),
            v_r_m_s,
            a_rel_m_s2
        ),
        Record::Window { window: w, extras: x } => {
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
        Record::Floor { n, record, floor: f, onset_m_s2, stick_m_s2 } => info!(
            "floor n={=u64} rec={=u32} samples={=u32} mean={} sigma={} pp={} onset={=f32} stick={=f32}",
            n,
            record,
            f.samples,
            f.mean_m_s2,
            f.sigma_m_s2,
            f.pp_m_s2,
            onset_m_s2,
            stick_m_s2
        ),
        Record::Health { n, record, index, flat, noisy, undecided } => warn!(
            "health n={=u64} rec={=u32} idx={=u32} flat={=u8} noisy={=u8} undecided={=bool}",
            n,
            record,
            index,
            flat,
            noisy,
            undecided
        ),
        Record::Overrun { n, count } => warn!("overrun n={=u64} count={=u32}", n, count),
        Record::Stall { n, ms, adc_ovr } => error!("stall n={=u64} ms={=u32} adc_ovr={=bool}", n, ms, adc_ovr),
        Record::Input { name, active } => warn!("input name={=str} active={=bool}", name, active),
        Record::Panic { file, line, msg } => error!("panic file={=str} line={=u32} msg={=str}", file, line, msg),
    }
}
