//! The board: every pin and peripheral the firmware uses, each defined once, and the bring-up
//! that takes them (README.md, "Pin map").
//!
//! A GPIO pin is one line of [`board!`]: `role: P <port> <number>`. From it come the typed
//! peripheral the HAL drives (the field `Board::role`, `Peri<'static, peripherals::P..>`) and
//! its register index for the accesses that bypass the HAL (`board::role::{PORT, INDEX}`: the
//! inputs' levels read per sample, and `is_high`). The valves' HAL-free vent
//! (`stickslip-safety`, which the HardFault entry runs) states its pins by number: a
//! compile-time assertion below holds the two to the same pins. Other peripherals (ADC, DMA,
//! timer, EXTI lines, watchdog, the analog inputs) are typed fields, named once.

use embassy_stm32::{bind_interrupts, dma, exti, interrupt, peripherals, Peri};

bind_interrupts!(pub struct Irqs {
    DMA2_STREAM0 => dma::InterruptHandler<peripherals::DMA2_CH0>;
    EXTI0 => exti::InterruptHandler<interrupt::typelevel::EXTI0>;
    EXTI4 => exti::InterruptHandler<interrupt::typelevel::EXTI4>;
    EXTI9_5 => exti::InterruptHandler<interrupt::typelevel::EXTI9_5>;
});

/// Defines [`Board`] and, per GPIO pin, a module with its register block and index.
macro_rules! board {
    (
        gpio { $( $(#[$gm:meta])* $gpio:ident: P $port:ident $n:literal, )* }
        peripherals { $( $(#[$pm:meta])* $field:ident: $periph:ident, )* }
    ) => { paste::paste! {
        /// What the firmware owns of the chip, taken from the HAL once ([`bring_up`]).
        pub struct Board {
            $( $(#[$gm])* pub $gpio: Peri<'static, $gpio::Pin>, )*
            $( $(#[$pm])* pub $field: Peri<'static, peripherals::$periph>, )*
        }

        impl Board {
            // the table's doc comments ride along with its cfg attributes onto the initializers
            #[allow(unused_doc_comments)]
            fn take(p: embassy_stm32::Peripherals) -> Self {
                Board {
                    $( $(#[$gm])* $gpio: p.[<P $port $n>], )*
                    $( $(#[$pm])* $field: p.$periph, )*
                }
            }
        }

        $(
            $(#[$gm])*
            #[allow(dead_code)]
            pub mod $gpio {
                use embassy_stm32::pac;
                /// The typed peripheral (embassy), the type of the field `Board::<role>`.
                pub type Pin = embassy_stm32::peripherals::[<P $port $n>];
                /// The port's register block.
                pub const PORT: pac::gpio::Gpio = pac::[<GPIO $port>];
                /// The port's number (A = 0, B = 1, ...).
                pub const PORT_NUMBER: u32 = (stringify!($port).as_bytes()[0] - b'A') as u32;
                /// The pin's number in its port.
                pub const INDEX: usize = $n;
                /// The pin's input level is high now (one read of the port's IDR).
                #[inline(always)]
                pub fn is_high() -> bool {
                    PORT.idr().read().idr(INDEX) == pac::gpio::vals::Idr::HIGH
                }
            }
        )*
    }};
}

board! {
    gpio {
        /// Actuator (clamp) valve: high = open, low = vented.
        actuator_valve: P D 12,
        /// Band-drive valve: high = open, low = vented.
        band_valve: P D 13,
        /// E-stop, normally closed to ground with a pull-up: high = pressed or wire broken
        /// (EXTI4).
        estop: P E 4,
        /// End-of-stroke switch, normally closed to ground with a pull-up: high = reached or
        /// wire broken (EXTI5, on the EXTI9_5 interrupt).
        #[cfg(feature = "end-of-stroke")]
        end_of_stroke: P E 5,
        /// Start/stop/reset button, active high with a pull-down (the Discovery's blue B1,
        /// EXTI0).
        button: P A 0,
    }
    peripherals {
        /// disc_x accelerometer (ADC1 IN1).
        disc_x: PA1,
        /// pad_x accelerometer (ADC1 IN2).
        pad_x: PA2,
        /// pad_trail accelerometer (ADC1 IN3).
        pad_trail: PA3,
        /// pad_lead accelerometer (ADC1 IN8).
        pad_lead: PB0,
        /// Actuator line pressure transducer (ADC1 IN11).
        #[cfg(feature = "pressure")]
        actuator_pressure: PC1,
        /// Band line pressure transducer (ADC1 IN12).
        #[cfg(feature = "pressure")]
        band_pressure: PC2,
        /// The converter of the regular sequence.
        adc: ADC1,
        /// Its DMA stream, into the ring.
        adc_dma: DMA2_CH0,
        /// The trigger timer: its update event starts each scan (TRGO).
        trigger_timer: TIM3,
        /// The e-stop's EXTI line.
        estop_exti: EXTI4,
        /// The end-of-stroke switch's EXTI line.
        #[cfg(feature = "end-of-stroke")]
        end_of_stroke_exti: EXTI5,
        /// The button's EXTI line.
        button_exti: EXTI0,
        /// The independent watchdog.
        watchdog: IWDG,
    }
}

// The HAL-free vent drives the same two pins as the valve outputs.
const _: () = assert!(
    actuator_valve::INDEX == stickslip_safety::ACTUATOR_VALVE_PIN as usize
        && band_valve::INDEX == stickslip_safety::BAND_VALVE_PIN as usize
        && actuator_valve::PORT_NUMBER == stickslip_safety::VALVE_PORT_NUMBER
        && band_valve::PORT_NUMBER == stickslip_safety::VALVE_PORT_NUMBER,
    "stickslip-safety's vent and the board's valve pins differ"
);

/// Brings the chip up (clocks: [`crate::config::clock_config`]) and takes the board's
/// peripherals. Nothing is driven yet: every pin is still the reset state's floating input
/// (valves vented by the drivers' pull-downs).
pub fn bring_up() -> Board {
    Board::take(embassy_stm32::init(crate::config::clock_config()))
}
