//! The test sequencer of the rig's two valves: the normal-load actuator (clamp) and the
//! band-drive cylinder. Tick-driven: one call per tick, durations in ticks.
//!
//! ```text
//! Idle --start--> Clamp --actuator within tolerance of its setpoint--> Drive
//!      --band line at the drive pressure (the band starts moving)--> Record
//!      --record ticks done, or end of stroke--> Vent --vent ticks--> Idle
//! stop: Clamp / Drive / Record --> Vent (orderly)
//! any fault, in any state --> Fault(cause), latched; reset --> Idle once no fault is active
//! ```
//!
//! Valves per state (open = pressurised; closed = vented to atmosphere, the de-energised,
//! safe position and the reset/default state):
//!
//! | state  | actuator | band |
//! |--------|----------|------|
//! | Idle   | vented   | vented |
//! | Clamp  | open     | vented |
//! | Drive  | open     | open |
//! | Record | open     | open |
//! | Vent   | vented   | vented |
//! | Fault  | vented   | vented |
//!
//! **Phase ends.** Clamp and Drive end on the measured line pressures ([`PhaseEnd::Pressure`],
//! pressure transducers fitted) or, on a rig without transducers, after fixed fill times
//! ([`PhaseEnd::Timed`]: Clamp after `clamp_ticks` outputs, Drive after `drive_ticks`; set them
//! above the lines' measured fill times). The pressure limits are checked either way, on
//! whatever the pressure channels read (about 0 bar without transducers).
//!
//! **Faults.** Checked at the start of every tick, in every state, in this order of priority:
//! e-stop, a non-finite estimator value, actuator line pressure outside its limits, band line
//! pressure outside its limits (NaN is outside), accelerometer saturation (range or rail). Then
//! the state's own faults: clamp timeout, drive timeout (the band line never reached the drive
//! pressure), record timeout (recording until end of stroke, which never came). A fault vents
//! both valves in the tick that detects it (that tick's output is already vented) and latches
//! `Fault(cause)`; later faults do not replace the first cause. `reset` is refused, naming the
//! fault, while any fault condition is still active (e.g. the e-stop held); otherwise it
//! returns to Idle.
//!
//! **Ticks.** Entering a state counts as its first tick; a state given `n` ticks (record,
//! vent, the timeouts) shows in exactly `n` outputs before it moves on. One transition per tick
//! at most.

use super::{check, ConfigError};

/// Why the sequencer stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultCause {
    EStop = 1,
    /// The estimator refused a non-finite (or implausible) value.
    NonFinite = 2,
    /// Actuator line pressure outside its limits.
    ActuatorPressure = 3,
    /// Band line pressure outside its limits.
    BandPressure = 4,
    /// An accelerometer at its measuring range or at an ADC rail.
    AccelSaturation = 5,
    /// The actuator line did not reach its setpoint in time.
    ClampTimeout = 6,
    /// The band line did not reach the drive pressure in time.
    DriveTimeout = 7,
    /// The end of stroke did not come in time.
    RecordTimeout = 8,
}

impl FaultCause {
    pub const ALL: [FaultCause; 8] = [
        FaultCause::EStop,
        FaultCause::NonFinite,
        FaultCause::ActuatorPressure,
        FaultCause::BandPressure,
        FaultCause::AccelSaturation,
        FaultCause::ClampTimeout,
        FaultCause::DriveTimeout,
        FaultCause::RecordTimeout,
    ];
    pub const fn name(self) -> &'static str {
        match self {
            FaultCause::EStop => "e-stop",
            FaultCause::NonFinite => "non-finite estimator value",
            FaultCause::ActuatorPressure => "actuator pressure out of range",
            FaultCause::BandPressure => "band pressure out of range",
            FaultCause::AccelSaturation => "accelerometer saturation",
            FaultCause::ClampTimeout => "clamp timeout",
            FaultCause::DriveTimeout => "drive timeout",
            FaultCause::RecordTimeout => "record timeout",
        }
    }
}

/// The sequencer's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeqState {
    Idle,
    Clamp,
    Drive,
    Record,
    Vent,
    Fault(FaultCause),
}

impl SeqState {
    /// A small number per state (faults: 16 + cause), for logs and digests.
    pub const fn code(self) -> u8 {
        match self {
            SeqState::Idle => 0,
            SeqState::Clamp => 1,
            SeqState::Drive => 2,
            SeqState::Record => 3,
            SeqState::Vent => 4,
            SeqState::Fault(c) => 16 + c as u8,
        }
    }
    /// The valve outputs of the state.
    pub const fn valves(self) -> Valves {
        match self {
            SeqState::Clamp => Valves { actuator_open: true, band_open: false },
            SeqState::Drive | SeqState::Record => Valves { actuator_open: true, band_open: true },
            SeqState::Idle | SeqState::Vent | SeqState::Fault(_) => Valves::VENTED,
        }
    }
}

/// The two valve outputs; `false` = closed and vented (the default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Valves {
    pub actuator_open: bool,
    pub band_open: bool,
}

impl Valves {
    pub const VENTED: Valves = Valves { actuator_open: false, band_open: false };
    pub const fn is_vented(self) -> bool {
        !self.actuator_open && !self.band_open
    }
}

/// Operator commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    Start,
    /// Orderly stop: vent, then Idle.
    Stop,
    /// Leave a fault.
    Reset,
}

/// The command the rig's single start/stop/reset button gives in `state`: start from Idle, stop
/// (orderly vent) from Clamp, Drive, Record (and Vent, where the sequencer ignores it), reset
/// from a fault.
pub const fn button_command(state: SeqState) -> Command {
    match state {
        SeqState::Idle => Command::Start,
        SeqState::Clamp | SeqState::Drive | SeqState::Record | SeqState::Vent => Command::Stop,
        SeqState::Fault(_) => Command::Reset,
    }
}

/// What became of a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandResult {
    Accepted,
    /// Not applicable in the current state.
    Ignored,
    /// Refused because this fault is active.
    Refused(FaultCause),
}

impl CommandResult {
    pub const fn code(self) -> u8 {
        match self {
            CommandResult::Accepted => 1,
            CommandResult::Ignored => 2,
            CommandResult::Refused(c) => 16 + c as u8,
        }
    }
}

/// The inputs of one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SequencerInputs {
    /// Actuator line pressure [bar].
    pub actuator_bar: f32,
    /// Band line pressure [bar].
    pub band_bar: f32,
    /// Any accelerometer at its range or at a rail this tick.
    pub accel_saturated: bool,
    /// The e-stop is pressed.
    pub estop: bool,
    /// The band has reached the end of its stroke.
    pub end_of_stroke: bool,
    /// The estimator refused a non-finite value this tick.
    pub estimator_fault: bool,
}

/// Allowed range of a line's pressure [bar].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressureLimits {
    pub min_bar: f32,
    pub max_bar: f32,
}

impl PressureLimits {
    /// Inside [min, max]; NaN is outside.
    #[inline(always)]
    pub fn contains(&self, p: f32) -> bool {
        p >= self.min_bar && p <= self.max_bar
    }
}

/// How a record ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecordEnd {
    /// After this many ticks (or earlier at the end of stroke).
    Ticks(u32),
    /// At the end of stroke; not reached within `timeout_ticks` is a [`FaultCause::RecordTimeout`].
    EndOfStroke { timeout_ticks: u32 },
}

/// How Clamp and Drive end (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhaseEnd {
    /// On the line pressures: Clamp when the actuator line is within tolerance of its
    /// setpoint, Drive when the band line reaches the drive pressure.
    Pressure,
    /// After fixed times (a rig without pressure transducers): Clamp shows `clamp_ticks`
    /// outputs, Drive `drive_ticks`, each then taken to be at its pressure.
    Timed { clamp_ticks: u32, drive_ticks: u32 },
}

/// The sequencer's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SequencerConfig {
    /// Actuator line setpoint [bar] (5 bar on the thesis's rig).
    pub clamp_setpoint_bar: f32,
    /// Clamp is reached when |p - setpoint| <= this [bar].
    pub clamp_tolerance_bar: f32,
    pub clamp_timeout_ticks: u32,
    /// Band line pressure at which the band moves and the record starts [bar] (0.6 to 0.7 bar
    /// on the thesis's rig).
    pub drive_start_bar: f32,
    pub drive_timeout_ticks: u32,
    pub record: RecordEnd,
    pub vent_ticks: u32,
    /// How Clamp and Drive end.
    pub phase_end: PhaseEnd,
    pub actuator_limits: PressureLimits,
    pub band_limits: PressureLimits,
}

impl SequencerConfig {
    /// The thesis's rig at one tick per sample (25.6 kHz): clamp 5 +- 0.1 bar within 2 s,
    /// drive at 0.6 bar within 2 s, record 1 s, vent 0.5 s; actuator line limits -0.3 to 5.8
    /// bar (a vented line reads about 0, the supply is about 6 bar), band line -0.3 to 2 bar.
    pub const RIG: SequencerConfig = SequencerConfig {
        clamp_setpoint_bar: 5.0,
        clamp_tolerance_bar: 0.1,
        clamp_timeout_ticks: 51_200,
        drive_start_bar: 0.6,
        drive_timeout_ticks: 51_200,
        record: RecordEnd::Ticks(25_600),
        vent_ticks: 12_800,
        phase_end: PhaseEnd::Pressure,
        actuator_limits: PressureLimits { min_bar: -0.3, max_bar: 5.8 },
        band_limits: PressureLimits { min_bar: -0.3, max_bar: 2.0 },
    };

    pub fn validate(&self) -> Result<(), ConfigError> {
        let lim = |l: &PressureLimits, field: &'static str| {
            check(
                l.min_bar.is_finite() && l.max_bar.is_finite() && l.min_bar < l.max_bar,
                field,
                "need finite min < max",
                l.min_bar as f64,
            )
        };
        lim(&self.actuator_limits, "actuator_limits")?;
        lim(&self.band_limits, "band_limits")?;
        check(
            self.actuator_limits.contains(self.clamp_setpoint_bar),
            "clamp_setpoint_bar",
            "setpoint must lie inside the actuator limits",
            self.clamp_setpoint_bar as f64,
        )?;
        check(
            self.clamp_tolerance_bar.is_finite() && self.clamp_tolerance_bar > 0.0,
            "clamp_tolerance_bar",
            "must be > 0 bar",
            self.clamp_tolerance_bar as f64,
        )?;
        check(
            self.band_limits.contains(self.drive_start_bar),
            "drive_start_bar",
            "drive pressure must lie inside the band limits",
            self.drive_start_bar as f64,
        )?;
        for (field, n) in [
            ("clamp_timeout_ticks", self.clamp_timeout_ticks),
            ("drive_timeout_ticks", self.drive_timeout_ticks),
            ("vent_ticks", self.vent_ticks),
            (
                "record",
                match self.record {
                    RecordEnd::Ticks(n) => n,
                    RecordEnd::EndOfStroke { timeout_ticks } => timeout_ticks,
                },
            ),
        ] {
            check(n >= 1, field, "must be >= 1 tick", n as f64)?;
        }
        if let PhaseEnd::Timed { clamp_ticks, drive_ticks } = self.phase_end {
            check(clamp_ticks >= 1, "phase_end.clamp_ticks", "must be >= 1 tick", clamp_ticks as f64)?;
            check(drive_ticks >= 1, "phase_end.drive_ticks", "must be >= 1 tick", drive_ticks as f64)?;
        }
        Ok(())
    }
}

impl Default for SequencerConfig {
    fn default() -> Self {
        Self::RIG
    }
}

/// The outputs of one tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SequencerOutput {
    /// The state after this tick.
    pub state: SeqState,
    /// The valves for this tick (those of `state`).
    pub valves: Valves,
    /// What became of this tick's command, if there was one.
    pub command: Option<CommandResult>,
    /// The state changed in this tick.
    pub changed: bool,
}

/// The sequencer (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct Sequencer {
    cfg: SequencerConfig,
    state: SeqState,
    /// Outputs made in the current state, this tick's included.
    ticks: u32,
}

impl Sequencer {
    pub fn new(cfg: &SequencerConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(Sequencer { cfg: *cfg, state: SeqState::Idle, ticks: 0 })
    }

    pub fn state(&self) -> SeqState {
        self.state
    }
    pub fn config(&self) -> &SequencerConfig {
        &self.cfg
    }

    /// The input faults active now, highest priority first.
    pub fn active_fault(&self, i: &SequencerInputs) -> Option<FaultCause> {
        if i.estop {
            Some(FaultCause::EStop)
        } else if i.estimator_fault {
            Some(FaultCause::NonFinite)
        } else if !self.cfg.actuator_limits.contains(i.actuator_bar) {
            Some(FaultCause::ActuatorPressure)
        } else if !self.cfg.band_limits.contains(i.band_bar) {
            Some(FaultCause::BandPressure)
        } else if i.accel_saturated {
            Some(FaultCause::AccelSaturation)
        } else {
            None
        }
    }

    fn enter(&mut self, s: SeqState) {
        self.state = s;
        self.ticks = 1;
    }

    /// One tick: faults, then the command, then the state's own progress.
    pub fn tick(&mut self, i: &SequencerInputs, command: Option<Command>) -> SequencerOutput {
        let before = self.state;
        self.ticks = self.ticks.saturating_add(1);
        let active = self.active_fault(i);
        let result = match self.state {
            SeqState::Fault(_) => command.map(|c| match (c, active) {
                (Command::Reset, Some(f)) => CommandResult::Refused(f),
                (Command::Reset, None) => {
                    self.enter(SeqState::Idle);
                    CommandResult::Accepted
                }
                (Command::Start, Some(f)) => CommandResult::Refused(f),
                _ => CommandResult::Ignored,
            }),
            _ => {
                if let Some(f) = active {
                    self.enter(SeqState::Fault(f));
                    command.map(|c| match c {
                        Command::Start => CommandResult::Refused(f),
                        _ => CommandResult::Ignored,
                    })
                } else {
                    let r = command.map(|c| self.command(c));
                    if self.state == before {
                        self.progress(i);
                    }
                    r
                }
            }
        };
        SequencerOutput {
            state: self.state,
            valves: self.state.valves(),
            command: result,
            changed: self.state != before,
        }
    }

    fn command(&mut self, c: Command) -> CommandResult {
        match (c, self.state) {
            (Command::Start, SeqState::Idle) => {
                self.enter(SeqState::Clamp);
                CommandResult::Accepted
            }
            (Command::Stop, SeqState::Clamp | SeqState::Drive | SeqState::Record) => {
                self.enter(SeqState::Vent);
                CommandResult::Accepted
            }
            _ => CommandResult::Ignored,
        }
    }

    fn progress(&mut self, i: &SequencerInputs) {
        let cfg = &self.cfg;
        let t = self.ticks;
        match self.state {
            SeqState::Clamp => {
                let filled = match cfg.phase_end {
                    PhaseEnd::Pressure => (i.actuator_bar - cfg.clamp_setpoint_bar).abs() <= cfg.clamp_tolerance_bar,
                    PhaseEnd::Timed { clamp_ticks, .. } => t > clamp_ticks,
                };
                if filled {
                    self.enter(SeqState::Drive);
                } else if t > cfg.clamp_timeout_ticks {
                    self.enter(SeqState::Fault(FaultCause::ClampTimeout));
                }
            }
            SeqState::Drive => {
                let moving = match cfg.phase_end {
                    PhaseEnd::Pressure => i.band_bar >= cfg.drive_start_bar,
                    PhaseEnd::Timed { drive_ticks, .. } => t > drive_ticks,
                };
                if moving {
                    self.enter(SeqState::Record);
                } else if t > cfg.drive_timeout_ticks {
                    self.enter(SeqState::Fault(FaultCause::DriveTimeout));
                }
            }
            SeqState::Record => {
                if i.end_of_stroke {
                    self.enter(SeqState::Vent);
                } else {
                    match cfg.record {
                        RecordEnd::Ticks(n) => {
                            if t > n {
                                self.enter(SeqState::Vent);
                            }
                        }
                        RecordEnd::EndOfStroke { timeout_ticks } => {
                            if t > timeout_ticks {
                                self.enter(SeqState::Fault(FaultCause::RecordTimeout));
                            }
                        }
                    }
                }
            }
            SeqState::Vent => {
                if t > cfg.vent_ticks {
                    self.enter(SeqState::Idle);
                }
            }
            SeqState::Idle | SeqState::Fault(_) => {}
        }
    }
}
