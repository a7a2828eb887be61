//! A stack overflow on the emulated Cortex-M4F ends in the firmware's HardFault entry with both
//! valves vented (issue 14): the on-target program `stack_overflow` (tests/on-target), linked
//! like the firmware by flip-link, recurses without bound. Checked here, from QEMU's output:
//!
//! - the layout: the stack region starts at the start of RAM and ends at or below the statics
//!   (flip-link), so the overflow cannot reach them;
//! - the recursion reached the bottom of that region (its lowest stack pointer within 1 KB of
//!   it): the fault is the overflow, not something earlier;
//! - the fault: a bus fault on the stack (CFSR's STKERR, set when the fault's own frame cannot
//!   be pushed), escalated to HardFault (HFSR's FORCED); the program then printed from the
//!   firmware's fault entry (`stickslip_safety::hard_fault!`), so that entry ran on a valid
//!   stack, and QEMU exited with the program's success;
//! - the vent: QEMU's log of writes to the devices it does not emulate (`-d unimp`) holds the
//!   write of 0x30000000 (PD12 and PD13 reset) to GPIOD's BSRR (offset 0x18), which is
//!   `stickslip_safety::force_vent`, the firmware's vent.
//!
//! Ignored by default: it needs qemu-system-arm and the cross-built ELF. `scripts/test-all.sh`
//! builds it and runs
//!
//!     STICKSLIP_ON_TARGET_STACK_ELF=tests/on-target/target/thumbv7em-none-eabihf/release/stack_overflow \
//!         cargo test --release -p stickslip-crosscheck --test stack_overflow_on_target -- --ignored
//!
//! Without its variable it fails: it never passes vacuously.

mod qemu;

use qemu::elf_from_env;

/// Start of the STM32F405/407's RAM (memory.x) [address].
const RAM_START: u32 = 0x2000_0000;
/// CFSR: BusFault on exception entry stacking (BFSR.STKERR).
const CFSR_STKERR: u32 = 1 << 12;
/// HFSR: a configurable fault escalated to HardFault.
const HFSR_FORCED: u32 = 1 << 30;

/// `key=0x...` (or decimal) from a line of `key=value` words.
fn field(line: &str, key: &str) -> u32 {
    let v = line
        .split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no `{key}=` in `{line}`"));
    match v.strip_prefix("0x") {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => v.parse(),
    }
    .unwrap_or_else(|e| panic!("`{key}={v}` in `{line}`: {e}"))
}

#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_STACK_ELF (scripts/test-all.sh runs it)"]
fn a_stack_overflow_ends_in_the_fault_handler_with_both_valves_vented() {
    let elf = elf_from_env("STICKSLIP_ON_TARGET_STACK_ELF", "stack_overflow");
    let (status, out, err) = qemu::run_with(&elf, &["-d", "unimp"]);
    let out = String::from_utf8(out).expect("QEMU stdout is UTF-8");
    let all = format!("--- stdout\n{out}\n--- stderr\n{err}");
    println!("{all}");
    assert!(status.success(), "the program did not exit with success ({status}):\n{all}");

    let layout = out.lines().find(|l| l.starts_with("layout ")).unwrap_or_else(|| panic!("no layout line:\n{all}"));
    let (stack_end, stack_start, statics) =
        (field(layout, "stack_end"), field(layout, "stack_start"), field(layout, "statics_from"));
    assert_eq!(stack_end, RAM_START, "the stack does not start at the start of RAM: {layout}");
    assert!(stack_start <= statics, "the stack's top lies above the statics: {layout}");

    let fault = out.lines().find(|l| l.starts_with("hardfault ")).unwrap_or_else(|| panic!("no hardfault line:\n{all}"));
    assert!(!out.lines().any(|l| l.starts_with("error ")), "{all}");
    let (cfsr, hfsr, deepest) = (field(fault, "cfsr"), field(fault, "hfsr"), field(fault, "deepest_sp"));
    assert!(cfsr & CFSR_STKERR != 0, "no stacking bus fault (STKERR) in CFSR: {fault}");
    assert!(hfsr & HFSR_FORCED != 0, "the fault was not escalated to HardFault (FORCED): {fault}");
    assert!(
        (stack_end..stack_end + 1024).contains(&deepest),
        "the recursion's lowest stack pointer is not within 1 KB of the stack's bottom: {fault}"
    );
    let vent = format!("value 0x{:08x})", stickslip_safety_vent_word());
    assert!(
        err.lines().any(|l| l.starts_with("GPIOD: unimplemented device write (size 4, offset 0x018,") && l.ends_with(&vent)),
        "no write of the vent word to GPIOD's BSRR in QEMU's log:\n{all}"
    );
}

/// The vent's BSRR word, from the pins (PD12, PD13: the reset half, bits 16 + n), written out
/// here rather than taken from the crate under test.
fn stickslip_safety_vent_word() -> u32 {
    (1 << (16 + 12)) | (1 << (16 + 13))
}
