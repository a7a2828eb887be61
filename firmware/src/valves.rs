//! The two valve outputs: the actuator (clamp) valve and the band-drive valve (PD12, PD13:
//! `board`).
//!
//! High = solenoid energised = valve open (line pressurised); low = de-energised = closed and
//! vented: the safe state. It is also the state of a pin the firmware does not drive (after
//! reset every pin is a floating input, and the driver's gate pull-down holds the valve off:
//! see README.md, wiring), so a watchdog reset vents both lines. [`force_vent`] drives both
//! pins low by a single register write, from anywhere (panic and fault handlers, the e-stop
//! task); it and the pin numbers live in `stickslip-safety` (no HAL), which the fault entry and
//! the on-target stack-overflow test share.

use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::Peri;

use crate::board;
pub use stickslip_safety::force_vent;
use stickslip_model::rig::sequencer::Valves as ValveStates;

/// The valve outputs, owned by the estimator task.
pub struct ValveOutputs {
    actuator: Output<'static>,
    band: Output<'static>,
    last: ValveStates,
}

impl ValveOutputs {
    /// Both pins as push-pull outputs, low (vented) from the first instant.
    pub fn new(actuator: Peri<'static, board::actuator_valve::Pin>, band: Peri<'static, board::band_valve::Pin>) -> Self {
        ValveOutputs {
            actuator: Output::new(actuator, Level::Low, Speed::Low),
            band: Output::new(band, Level::Low, Speed::Low),
            last: ValveStates::VENTED,
        }
    }

    /// Sets the outputs to `v` (the sequencer's valves for this sample). Written every sample
    /// (two register writes), so a [`force_vent`] from elsewhere can never leave the pins and
    /// the sequencer's view apart for longer than until the next sample.
    #[inline(always)]
    pub fn set(&mut self, v: ValveStates) {
        self.actuator.set_level(if v.actuator_open { Level::High } else { Level::Low });
        self.band.set_level(if v.band_open { Level::High } else { Level::Low });
        self.last = v;
    }

    /// Vents both (and remembers it).
    pub fn vent(&mut self) {
        force_vent();
        self.last = ValveStates::VENTED;
    }
}
