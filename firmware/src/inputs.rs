//! The digital inputs: e-stop (PE4, EXTI4), end-of-stroke switch (PE5, EXTI9_5, feature
//! `end-of-stroke`) and the start/stop/reset button (PA0, EXTI0: the Discovery board's blue
//! user button); the pins are the `board`'s.
//!
//! E-stop and end-of-stroke are normally-closed contacts to ground with a pull-up: the contact
//! closed reads low (normal); pressed, reached, or a broken wire reads high (active). Each has
//! a task that waits on its EXTI line: a rising edge latches the input (so a pulse shorter than
//! a batch of samples is still seen by the sequencer) and, for the e-stop, vents both valves
//! from that task, without waiting for the estimator task's next half-ring (the task runs as
//! soon as the estimator task yields, within the processing of one half-ring). The estimator task reads, per sample, the
//! latch (taken once per batch) or'ed with the pin's present level ([`estop_active`],
//! [`end_of_stroke_active`]), so a held input is seen even if an edge fell between two waits.
//!
//! The button is active high (the Discovery's B1 connects PA0 to 3 V, with a pull-down): a
//! press held for [`BUTTON_DEBOUNCE_MS`] posts one press, which the estimator task turns into
//! start, stop or reset by the sequencer's state (`stickslip_model::rig::sequencer::button_command`).

use core::sync::atomic::{AtomicBool, Ordering};

use embassy_stm32::exti::ExtiInput;
use embassy_stm32::mode::Async;
use embassy_time::Timer;

use crate::board;
use crate::config::BUTTON_DEBOUNCE_MS;
use crate::records::{log, Record};
use crate::valves;

/// E-stop rising edge seen since the estimator task last looked.
static ESTOP_EDGE: AtomicBool = AtomicBool::new(false);
/// End-of-stroke rising edge seen since the estimator task last looked.
#[cfg(feature = "end-of-stroke")]
static EOS_EDGE: AtomicBool = AtomicBool::new(false);
/// A debounced button press not yet taken.
static BUTTON: AtomicBool = AtomicBool::new(false);

/// The e-stop's latched edges, taken: call once per batch of samples.
#[inline(always)]
pub fn take_estop_edge() -> bool {
    ESTOP_EDGE.swap(false, Ordering::AcqRel)
}

/// The e-stop pin reads active (pressed or wire broken) now.
#[inline(always)]
pub fn estop_active() -> bool {
    board::estop::is_high()
}

/// The end-of-stroke switch's latched edges, taken: call once per batch of samples.
#[inline(always)]
pub fn take_end_of_stroke_edge() -> bool {
    #[cfg(feature = "end-of-stroke")]
    return EOS_EDGE.swap(false, Ordering::AcqRel);
    #[cfg(not(feature = "end-of-stroke"))]
    return false;
}

/// The end-of-stroke switch reads active (reached or wire broken) now; always false without
/// the feature.
#[inline(always)]
pub fn end_of_stroke_active() -> bool {
    #[cfg(feature = "end-of-stroke")]
    return board::end_of_stroke::is_high();
    #[cfg(not(feature = "end-of-stroke"))]
    return false;
}

/// A button press posted since the last call, taken.
#[inline(always)]
pub fn take_button() -> bool {
    BUTTON.swap(false, Ordering::AcqRel)
}

#[embassy_executor::task]
pub async fn estop_task(mut pin: ExtiInput<'static, Async>) {
    loop {
        pin.wait_for_rising_edge().await;
        valves::force_vent();
        ESTOP_EDGE.store(true, Ordering::Release);
        log(&Record::Input { name: "estop", active: true });
        pin.wait_for_low().await;
        log(&Record::Input { name: "estop", active: false });
    }
}

#[cfg(feature = "end-of-stroke")]
#[embassy_executor::task]
pub async fn end_of_stroke_task(mut pin: ExtiInput<'static, Async>) {
    loop {
        pin.wait_for_rising_edge().await;
        EOS_EDGE.store(true, Ordering::Release);
        log(&Record::Input { name: "end_of_stroke", active: true });
        pin.wait_for_low().await;
        log(&Record::Input { name: "end_of_stroke", active: false });
    }
}

#[embassy_executor::task]
pub async fn button_task(mut pin: ExtiInput<'static, Async>) {
    loop {
        pin.wait_for_rising_edge().await;
        Timer::after_millis(BUTTON_DEBOUNCE_MS).await;
        if pin.is_high() {
            BUTTON.store(true, Ordering::Release);
            pin.wait_for_low().await;
            Timer::after_millis(BUTTON_DEBOUNCE_MS).await;
        }
    }
}
