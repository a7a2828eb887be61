//! The valve sequencer: the happy path through every state with its valve outputs; every fault
//! injected in every state vents both valves in the same tick and latches; reset is refused
//! while the cause persists.

use stickslip_model::rig::sequencer::{
    button_command, Command, CommandResult, FaultCause, PhaseEnd, PressureLimits, RecordEnd, SeqState, Sequencer, SequencerConfig,
    SequencerInputs, SequencerOutput, Valves,
};

/// Short durations so a test can walk through them tick by tick.
fn config() -> SequencerConfig {
    SequencerConfig {
        clamp_setpoint_bar: 5.0,
        clamp_tolerance_bar: 0.1,
        clamp_timeout_ticks: 20,
        drive_start_bar: 0.6,
        drive_timeout_ticks: 30,
        record: RecordEnd::Ticks(40),
        vent_ticks: 10,
        phase_end: PhaseEnd::Pressure,
        actuator_limits: PressureLimits { min_bar: -0.3, max_bar: 5.8 },
        band_limits: PressureLimits { min_bar: -0.3, max_bar: 2.0 },
    }
}

const OPEN_CLAMP: Valves = Valves { actuator_open: true, band_open: false };
const OPEN_BOTH: Valves = Valves { actuator_open: true, band_open: true };

/// Benign inputs: lines vented, nothing pressed.
fn quiet() -> SequencerInputs {
    SequencerInputs { actuator_bar: 0.0, band_bar: 0.0, ..Default::default() }
}

fn tick(s: &mut Sequencer, i: SequencerInputs) -> SequencerOutput {
    s.tick(&i, None)
}

#[test]
fn happy_path_through_every_state_with_its_valves() {
    let mut s = Sequencer::new(&config()).unwrap();
    // idle: vented, stays idle
    for _ in 0..5 {
        let o = tick(&mut s, quiet());
        assert_eq!((o.state, o.valves), (SeqState::Idle, Valves::VENTED));
    }
    // start: clamp, actuator valve open at once
    let o = s.tick(&quiet(), Some(Command::Start));
    assert_eq!((o.state, o.valves, o.command), (SeqState::Clamp, OPEN_CLAMP, Some(CommandResult::Accepted)));
    // pressure rises: still clamping below the tolerance band
    for p in [1.0, 3.0, 4.85] {
        let o = tick(&mut s, SequencerInputs { actuator_bar: p, ..quiet() });
        assert_eq!((o.state, o.valves), (SeqState::Clamp, OPEN_CLAMP), "at {p} bar");
    }
    // within 0.1 bar of 5: drive, band valve opens
    let clamped = SequencerInputs { actuator_bar: 4.95, ..quiet() };
    let o = tick(&mut s, clamped);
    assert_eq!((o.state, o.valves, o.changed), (SeqState::Drive, OPEN_BOTH, true));
    for p in [0.2, 0.5, 0.59] {
        let o = tick(&mut s, SequencerInputs { band_bar: p, ..clamped });
        assert_eq!((o.state, o.valves), (SeqState::Drive, OPEN_BOTH));
    }
    // band line at 0.6 bar: the band moves, record
    let driving = SequencerInputs { band_bar: 0.65, ..clamped };
    let mut record_outputs = 0;
    let mut o = tick(&mut s, driving);
    while o.state == SeqState::Record {
        assert_eq!(o.valves, OPEN_BOTH);
        record_outputs += 1;
        o = tick(&mut s, driving);
    }
    assert_eq!(record_outputs, 40, "record lasts its 40 ticks");
    // vent for 10 ticks, then idle
    let mut vent_outputs = 0;
    while o.state == SeqState::Vent {
        assert_eq!(o.valves, Valves::VENTED);
        vent_outputs += 1;
        o = tick(&mut s, quiet());
    }
    assert_eq!(vent_outputs, 10);
    assert_eq!((o.state, o.valves), (SeqState::Idle, Valves::VENTED));
}

#[test]
fn end_of_stroke_ends_the_record_early_and_stop_vents_from_every_active_state() {
    let mut s = Sequencer::new(&config()).unwrap();
    let driving = SequencerInputs { actuator_bar: 5.0, band_bar: 0.65, ..quiet() };
    drive_to(&mut s, SeqState::Record);
    let o = tick(&mut s, SequencerInputs { end_of_stroke: true, ..driving });
    assert_eq!((o.state, o.valves), (SeqState::Vent, Valves::VENTED));

    for state in [SeqState::Clamp, SeqState::Drive, SeqState::Record] {
        let mut s = Sequencer::new(&config()).unwrap();
        let inputs = drive_to(&mut s, state);
        let o = s.tick(&inputs, Some(Command::Stop));
        assert_eq!((o.state, o.valves, o.command), (SeqState::Vent, Valves::VENTED, Some(CommandResult::Accepted)));
    }
    // stop and reset are ignored where they do not apply; start only from idle
    let mut s = Sequencer::new(&config()).unwrap();
    assert_eq!(s.tick(&quiet(), Some(Command::Stop)).command, Some(CommandResult::Ignored));
    assert_eq!(s.tick(&quiet(), Some(Command::Reset)).command, Some(CommandResult::Ignored));
    let inputs = drive_to(&mut s, SeqState::Drive);
    assert_eq!(s.tick(&inputs, Some(Command::Start)).command, Some(CommandResult::Ignored));
}

#[test]
fn record_until_end_of_stroke_times_out() {
    let mut cfg = config();
    cfg.record = RecordEnd::EndOfStroke { timeout_ticks: 15 };
    let mut s = Sequencer::new(&cfg).unwrap();
    let driving = drive_to(&mut s, SeqState::Record);
    let mut n = 1; // the entering tick
    loop {
        let o = tick(&mut s, driving);
        if o.state != SeqState::Record {
            assert_eq!((o.state, o.valves), (SeqState::Fault(FaultCause::RecordTimeout), Valves::VENTED));
            break;
        }
        n += 1;
    }
    assert_eq!(n, 15);
    // and with the end of stroke in time: an orderly vent
    let mut s = Sequencer::new(&cfg).unwrap();
    let driving = drive_to(&mut s, SeqState::Record);
    for _ in 0..10 {
        assert_eq!(tick(&mut s, driving).state, SeqState::Record);
    }
    assert_eq!(tick(&mut s, SequencerInputs { end_of_stroke: true, ..driving }).state, SeqState::Vent);
}

/// Brings a fresh sequencer to `target` with benign inputs; returns the inputs that hold it
/// there.
fn drive_to(s: &mut Sequencer, target: SeqState) -> SequencerInputs {
    let idle = quiet();
    let clamping = SequencerInputs { actuator_bar: 2.0, ..quiet() };
    let clamped = SequencerInputs { actuator_bar: 5.0, ..quiet() };
    let driving = SequencerInputs { band_bar: 0.65, ..clamped };
    match target {
        SeqState::Idle => idle,
        SeqState::Clamp => {
            assert_eq!(s.tick(&idle, Some(Command::Start)).state, SeqState::Clamp);
            clamping
        }
        SeqState::Drive => {
            drive_to(s, SeqState::Clamp);
            assert_eq!(tick(s, clamped).state, SeqState::Drive);
            clamped
        }
        SeqState::Record => {
            drive_to(s, SeqState::Drive);
            assert_eq!(tick(s, driving).state, SeqState::Record);
            driving
        }
        SeqState::Vent => {
            drive_to(s, SeqState::Record);
            assert_eq!(s.tick(&driving, Some(Command::Stop)).state, SeqState::Vent);
            idle
        }
        SeqState::Fault(_) => {
            // an e-stop, released: the fault stays latched (always as EStop)
            assert_eq!(tick(s, SequencerInputs { estop: true, ..idle }).state, SeqState::Fault(FaultCause::EStop));
            assert_eq!(tick(s, idle).state, SeqState::Fault(FaultCause::EStop));
            idle
        }
    }
}

/// The input faults, as a change to otherwise benign inputs.
fn inject(cause: FaultCause, base: SequencerInputs) -> SequencerInputs {
    match cause {
        FaultCause::EStop => SequencerInputs { estop: true, ..base },
        FaultCause::NonFinite => SequencerInputs { estimator_fault: true, ..base },
        FaultCause::ActuatorPressure => SequencerInputs { actuator_bar: 6.5, ..base },
        FaultCause::BandPressure => SequencerInputs { band_bar: 2.5, ..base },
        FaultCause::AccelSaturation => SequencerInputs { accel_saturated: true, ..base },
        _ => unreachable!("not an input fault"),
    }
}

const INPUT_FAULTS: [FaultCause; 5] = [
    FaultCause::EStop,
    FaultCause::NonFinite,
    FaultCause::ActuatorPressure,
    FaultCause::BandPressure,
    FaultCause::AccelSaturation,
];

const STATES: [SeqState; 6] = [
    SeqState::Idle,
    SeqState::Clamp,
    SeqState::Drive,
    SeqState::Record,
    SeqState::Vent,
    SeqState::Fault(FaultCause::EStop),
];

#[test]
fn every_input_fault_in_every_state_vents_at_once_and_latches() {
    for state in STATES {
        for cause in INPUT_FAULTS {
            let mut s = Sequencer::new(&config()).unwrap();
            let base = drive_to(&mut s, state);
            assert_eq!(s.state(), state);
            let o = tick(&mut s, inject(cause, base));
            assert!(o.valves.is_vented(), "{state:?} + {cause:?}: valves {:?} in the detecting tick", o.valves);
            let expect = match state {
                // an existing fault keeps its first cause
                SeqState::Fault(first) => SeqState::Fault(first),
                _ => SeqState::Fault(cause),
            };
            assert_eq!(o.state, expect, "{state:?} + {cause:?}");
            // the cause goes away: still latched, still vented, for as long as we look
            for _ in 0..100 {
                let o = tick(&mut s, base);
                assert_eq!((o.state, o.valves), (expect, Valves::VENTED), "{state:?} + {cause:?} latched");
            }
            // a start is not a way out
            let o = s.tick(&base, Some(Command::Start));
            assert_eq!(o.state, expect);
            assert!(o.valves.is_vented());
        }
    }
}

#[test]
fn nan_pressures_are_out_of_range() {
    for (actuator_bar, band_bar, cause) in
        [(f32::NAN, 0.0, FaultCause::ActuatorPressure), (0.0, f32::NAN, FaultCause::BandPressure)]
    {
        let mut s = Sequencer::new(&config()).unwrap();
        let o = tick(&mut s, SequencerInputs { actuator_bar, band_bar, ..quiet() });
        assert_eq!((o.state, o.valves), (SeqState::Fault(cause), Valves::VENTED));
    }
    // below the lower limit too (a broken transducer wire reads -2.5 bar)
    let mut s = Sequencer::new(&config()).unwrap();
    let o = tick(&mut s, SequencerInputs { actuator_bar: -2.5, ..quiet() });
    assert_eq!(o.state, SeqState::Fault(FaultCause::ActuatorPressure));
}

#[test]
fn timeouts_fault_in_their_own_state_only() {
    // clamp: the pressure never arrives; the clamp shows exactly 20 outputs
    let mut s = Sequencer::new(&config()).unwrap();
    let clamping = drive_to(&mut s, SeqState::Clamp);
    let mut n = 1;
    loop {
        let o = tick(&mut s, clamping);
        if o.state != SeqState::Clamp {
            assert_eq!((o.state, o.valves), (SeqState::Fault(FaultCause::ClampTimeout), Valves::VENTED));
            break;
        }
        assert_eq!(o.valves, OPEN_CLAMP);
        n += 1;
    }
    assert_eq!(n, 20);
    // drive: the band line never reaches 0.6 bar
    let mut s = Sequencer::new(&config()).unwrap();
    let clamped = drive_to(&mut s, SeqState::Drive);
    let mut n = 1;
    loop {
        let o = tick(&mut s, clamped);
        if o.state != SeqState::Drive {
            assert_eq!((o.state, o.valves), (SeqState::Fault(FaultCause::DriveTimeout), Valves::VENTED));
            break;
        }
        n += 1;
    }
    assert_eq!(n, 30);
    // no timeout fires in idle, vent or a fault, however long they last
    for state in [SeqState::Idle, SeqState::Vent, SeqState::Fault(FaultCause::EStop)] {
        let mut s = Sequencer::new(&config()).unwrap();
        let base = drive_to(&mut s, state);
        for _ in 0..1000 {
            let o = tick(&mut s, base);
            assert!(matches!(o.state, SeqState::Idle | SeqState::Vent | SeqState::Fault(FaultCause::EStop)));
            assert!(o.valves.is_vented());
        }
    }
    // and the timeouts latch and can be reset (their cause does not persist)
    let mut s = Sequencer::new(&config()).unwrap();
    let clamping = drive_to(&mut s, SeqState::Clamp);
    for _ in 0..20 {
        tick(&mut s, clamping);
    }
    assert_eq!(s.state(), SeqState::Fault(FaultCause::ClampTimeout));
    let o = s.tick(&quiet(), Some(Command::Reset));
    assert_eq!((o.state, o.command), (SeqState::Idle, Some(CommandResult::Accepted)));
}

#[test]
fn reset_is_refused_while_the_cause_persists() {
    for cause in INPUT_FAULTS {
        let mut s = Sequencer::new(&config()).unwrap();
        let held = inject(cause, quiet());
        assert_eq!(tick(&mut s, held).state, SeqState::Fault(cause));
        for _ in 0..3 {
            let o = s.tick(&held, Some(Command::Reset));
            assert_eq!(o.command, Some(CommandResult::Refused(cause)), "{cause:?} held");
            assert_eq!((o.state, o.valves), (SeqState::Fault(cause), Valves::VENTED));
        }
        // released: reset returns to idle, vented
        let o = s.tick(&quiet(), Some(Command::Reset));
        assert_eq!((o.state, o.valves, o.command), (SeqState::Idle, Valves::VENTED, Some(CommandResult::Accepted)));
        // and a fresh start works
        assert_eq!(s.tick(&quiet(), Some(Command::Start)).state, SeqState::Clamp);
    }
    // a different fault still active also refuses the reset (it names that fault)
    let mut s = Sequencer::new(&config()).unwrap();
    tick(&mut s, SequencerInputs { estop: true, ..quiet() });
    let o = s.tick(&SequencerInputs { accel_saturated: true, ..quiet() }, Some(Command::Reset));
    assert_eq!(o.command, Some(CommandResult::Refused(FaultCause::AccelSaturation)));
    assert_eq!(o.state, SeqState::Fault(FaultCause::EStop));
}

#[test]
fn a_start_in_the_tick_of_a_fault_is_refused() {
    let mut s = Sequencer::new(&config()).unwrap();
    let o = s.tick(&SequencerInputs { estop: true, ..quiet() }, Some(Command::Start));
    assert_eq!(o.command, Some(CommandResult::Refused(FaultCause::EStop)));
    assert_eq!((o.state, o.valves), (SeqState::Fault(FaultCause::EStop), Valves::VENTED));
}

#[test]
fn invalid_configurations_are_refused_by_name() {
    let mut c = config();
    c.clamp_setpoint_bar = 7.0;
    assert_eq!(Sequencer::new(&c).unwrap_err().field, "clamp_setpoint_bar");
    let mut c = config();
    c.vent_ticks = 0;
    assert_eq!(Sequencer::new(&c).unwrap_err().field, "vent_ticks");
    let mut c = config();
    c.band_limits = PressureLimits { min_bar: 1.0, max_bar: f32::NAN };
    assert_eq!(Sequencer::new(&c).unwrap_err().field, "band_limits");
    assert!(Sequencer::new(&SequencerConfig::RIG).is_ok());
}

/// The single button: a press in Idle starts (clamp), a press while clamping stops (vent, then
/// Idle), and after a fault whose cause has gone a press resets it. Each press is accepted.
#[test]
fn the_button_starts_stops_and_resets() {
    let mut s = Sequencer::new(&config()).unwrap();
    let press = |s: &mut Sequencer, i: SequencerInputs| s.tick(&i, Some(button_command(s.state())));
    let o = press(&mut s, quiet());
    assert_eq!((o.state, o.command), (SeqState::Clamp, Some(CommandResult::Accepted)));
    let o = press(&mut s, SequencerInputs { actuator_bar: 2.0, ..quiet() });
    assert_eq!((o.state, o.valves, o.command), (SeqState::Vent, Valves::VENTED, Some(CommandResult::Accepted)));
    let mut o = tick(&mut s, quiet());
    while o.state == SeqState::Vent {
        o = tick(&mut s, quiet());
    }
    assert_eq!(o.state, SeqState::Idle);
    // an e-stop latches a fault; released, the button resets it to Idle
    let o = tick(&mut s, SequencerInputs { estop: true, ..quiet() });
    assert!(matches!(o.state, SeqState::Fault(_)), "{o:?}");
    let o = press(&mut s, quiet());
    assert_eq!((o.state, o.command), (SeqState::Idle, Some(CommandResult::Accepted)));
}

#[test]
fn timed_phases_end_after_their_ticks_whatever_the_lines_read() {
    // a rig without transducers: the lines read 0 bar throughout
    let mut cfg = config();
    cfg.phase_end = PhaseEnd::Timed { clamp_ticks: 7, drive_ticks: 4 };
    let mut s = Sequencer::new(&cfg).unwrap();
    assert_eq!(s.tick(&quiet(), Some(Command::Start)).state, SeqState::Clamp);
    let mut outputs = [0u32; 2];
    let mut o = tick(&mut s, quiet());
    for (k, state) in [SeqState::Clamp, SeqState::Drive].into_iter().enumerate() {
        outputs[k] = if k == 0 { 1 } else { 0 }; // Clamp's entering tick was the start's
        while o.state == state {
            outputs[k] += 1;
            o = tick(&mut s, quiet());
        }
    }
    assert_eq!(outputs, [7, 4], "Clamp and Drive show their ticks");
    assert_eq!((o.state, o.valves), (SeqState::Record, OPEN_BOTH));
    // the pressure limits still hold: a line out of range faults a timed phase too
    let mut s = Sequencer::new(&cfg).unwrap();
    s.tick(&quiet(), Some(Command::Start));
    let o = tick(&mut s, SequencerInputs { actuator_bar: 6.5, ..quiet() });
    assert_eq!((o.state, o.valves), (SeqState::Fault(FaultCause::ActuatorPressure), Valves::VENTED));
    // a timed clamp longer than its timeout times out
    cfg.phase_end = PhaseEnd::Timed { clamp_ticks: 25, drive_ticks: 4 };
    let mut s = Sequencer::new(&cfg).unwrap();
    s.tick(&quiet(), Some(Command::Start));
    let mut o = tick(&mut s, quiet());
    let mut n = 1;
    while o.state == SeqState::Clamp {
        n += 1;
        o = tick(&mut s, quiet());
    }
    assert_eq!((n, o.state), (20, SeqState::Fault(FaultCause::ClampTimeout)));
    // zero ticks is refused, naming the field
    cfg.phase_end = PhaseEnd::Timed { clamp_ticks: 3, drive_ticks: 0 };
    let e = Sequencer::new(&cfg).unwrap_err();
    assert_eq!(e.field, "phase_end.drive_ticks");
}
