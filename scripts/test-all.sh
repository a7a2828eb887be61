#!/usr/bin/env bash
# The project's test command (README): everything, from a fresh Debian machine (as root) or a
# developer's machine.
#
#   1. cross toolchain: the rustup target if installed, else Debian's rustc-web/cargo-web/
#      rust-web-src + binutils-arm-none-eabi + qemu-system-arm, and flip-link (`cargo install`)
#      as the linker (installed when missing, nothing else is installed)  scripts/cross.sh
#   2. firmware/ for thumbv7em-none-eabihf, release, with each feature set (default,
#      no-pressure, no-eos, neither, model2-band, model2-stribeck, model2); fails above 128 KiB
#      of flash or 80 KiB of static RAM (48 KiB kept for the stack)
#                                                                    scripts/build-firmware.sh
#   3. tests/on-target for thumbv7em-none-eabihf: release (bins digest, count, rig, rig_count,
#      records, count_model2, stack_overflow) and bin rig_count again with the firmware's code generation (profile `firmware`)
#   4. host workspace: cargo test --workspace --release; then, as a step of its own, the
#      debug-probe path of `stickslip record` (cargo feature `probe`, the probe-rs library):
#      cargo test --release -p stickslip --features probe --test record; and the campaign of
#      bad inputs, scripts/bad-inputs.sh (python3 and /usr/bin/time, in Debian's base image); the
#      docs' generated blocks current (scripts/docs-tables.sh --check); and the Python module
#      (host/python): scripts/python-module.sh (pip, maturin, pytest)
#   5. the model and the rig's per-sample chain on the emulated Cortex-M4F against the host,
#      bit for bit (bins digest and rig):
#      cargo test --release -p stickslip-crosscheck --test on_target -- --ignored
#      and the firmware's log: the defmt stream of bin records, captured under QEMU, decoded
#      record by record against the host (--test records_on_target), then by the command line
#      (`stickslip decode`, which must report nothing lost), and by `stickslip record` (fed the
#      stream as QEMU produces it, and by the command line: raw copy and CSVs equal to
#      decode's); and a stack overflow (bin
#      stack_overflow), which must end in the firmware's fault entry with both valves vented
#      (--test stack_overflow_on_target)
#   6. instruction counts under QEMU                                 scripts/count-instructions.sh
#      (and firmware/README.md's per-sample cost table held to them: scripts/docs-tables.sh)
#      ExactStepper<f32>::step() (fails above 200 instructions for a step without a
#      transition) and the rig's per-sample path (fails above 1,500 instructions for a sample
#      of calibration + estimator + window statistics)
#   7. the short accuracy and stability reports with --check (fail on a regressed bound)
#   8. firmware sizes (flash and static RAM of each feature build)
#
# Exits non-zero at the first failure. Prints each stage's wall time at the end.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

# The host toolchain is rustup's; make sure its cargo is found in a bare environment.
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
fi

locked=()
if [ "${CI:-}" = true ]; then locked=(--locked); fi

stage_names=()
stage_secs=()
t_all=$(date +%s)
t_stage=$t_all
current=""

section() {
    finish_stage
    current="$1"
    t_stage=$(date +%s)
    echo
    echo "=================================================================="
    echo "== $1"
    echo "=================================================================="
}

finish_stage() {
    if [ -n "$current" ]; then
        stage_names+=("$current")
        stage_secs+=($(($(date +%s) - t_stage)))
    fi
    current=""
}

on_exit() {
    local status=$?
    if [ "$status" -ne 0 ]; then
        echo
        echo "test-all: FAILED (exit status $status) in stage: ${current:-setup}" >&2
    fi
}
trap on_exit EXIT

section "1/8 cross toolchain (scripts/cross.sh)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"
cross_describe
echo "host:   $(cargo --version)"

section "2/8 firmware builds, thumbv7em-none-eabihf release, per feature set (scripts/build-firmware.sh)"
size_log="$(mktemp)"
bash "$root/scripts/build-firmware.sh" | tee "$size_log"
firmware_size="$(grep -E '^(firmware ELF|size )' "$size_log")"
rm -f "$size_log"

section "3/8 on-target test programs, thumbv7em-none-eabihf (tests/on-target)"
(cd "$root/tests/on-target" && cross_cargo build --release "${locked[@]}")
# the per-sample count with the firmware's code generation settings (firmware/Cargo.toml)
(cd "$root/tests/on-target" && cross_cargo build --profile firmware "${locked[@]}" --bin rig_count)
on_target_dir="$root/tests/on-target/target/$CROSS_TARGET/release"
rig_count_elf="$root/tests/on-target/target/$CROSS_TARGET/firmware/rig_count"
arm-none-eabi-size "$on_target_dir/digest" "$on_target_dir/count" "$on_target_dir/rig" "$on_target_dir/records" \
    "$rig_count_elf"

section "4/8 host workspace: cargo test --workspace --release"
cargo test --workspace --release
echo
echo "== 4b: the campaign of bad inputs (scripts/bad-inputs.sh: each one line and exit 2 or a classified halt, within 5 s and 200 MB)"
bash scripts/bad-inputs.sh | tee "$root/target/bad-inputs.log"
echo
echo "== 4c: the docs' generated blocks are current (scripts/docs-tables.sh --check: README's sample output, the campaign's counts)"
bash scripts/docs-tables.sh --check --bad-inputs "$root/target/bad-inputs.log"
echo
echo "== 4d: stickslip record's debug-probe path (cargo feature probe, probe-rs): build and tests"
cargo test --release -p stickslip --features probe --test record
echo
echo "== 4e: the Python module (host/python): built with maturin into a virtual environment, its tests against the binary (scripts/python-module.sh)"
bash scripts/python-module.sh

section "5/8 model and rig chain on the emulated Cortex-M4F == on the host, the fault path (QEMU netduinoplus2)"
STICKSLIP_ON_TARGET_ELF="$on_target_dir/digest" STICKSLIP_ON_TARGET_RIG_ELF="$on_target_dir/rig" \
    cargo test --release -p stickslip-crosscheck --test on_target -- --ignored --nocapture
# the firmware's log records (bin records: the rig through the firmware's sample_words, Logbook and defmt formatting)
records_stream="$on_target_dir/records.defmt"
rm -f "$records_stream"
STICKSLIP_ON_TARGET_RECORDS_ELF="$on_target_dir/records" STICKSLIP_ON_TARGET_RECORDS_STREAM="$records_stream" \
    cargo test --release -p stickslip-crosscheck --test records_on_target -- --ignored --nocapture
# a stack overflow ends in the firmware's fault entry with both valves vented (bin stack_overflow)
STICKSLIP_ON_TARGET_STACK_ELF="$on_target_dir/stack_overflow" \
    cargo test --release -p stickslip-crosscheck --test stack_overflow_on_target -- --ignored --nocapture
decode_out="$(mktemp)"
decode_err="$(mktemp)"
cargo run --release -q -p stickslip -- decode --elf "$on_target_dir/records" "$records_stream" --kind window \
    >"$decode_out" 2>"$decode_err"
cut -c1-150 "$decode_out" | head -n 3
cat "$decode_err"
grep -q "dropped 0 frames (0 bytes skipped); 0 bytes of an incomplete frame" "$decode_err" \
    || { echo "stickslip decode lost frames of the on-target stream" >&2; exit 1; }
rm -f "$decode_out" "$decode_err"
# `stickslip record --input` on the same stream: the raw copy is the stream, window.csv is decode's
record_parent="$(mktemp -d)"
cargo run --release -q -p stickslip -- record --elf "$on_target_dir/records" --input "$records_stream" \
    --out "$record_parent/rec" 2>/dev/null
cmp "$records_stream" "$record_parent/rec/raw.defmt"
cargo run --release -q -p stickslip -- decode --elf "$on_target_dir/records" "$records_stream" --kind window 2>/dev/null \
    | cmp - "$record_parent/rec/window.csv"
rm -rf "$record_parent"

section "6/8 instruction counts under QEMU (scripts/count-instructions.sh)"
COUNT_ELF="$on_target_dir/count" RIG_COUNT_ELF="$rig_count_elf" bash "$root/scripts/count-instructions.sh" \
    | tee "$root/target/count-instructions.log"
# firmware/README.md's per-sample cost table is these counts (fails when it is stale)
bash scripts/docs-tables.sh --check --counts "$root/target/count-instructions.log"

section "7/8 short work-precision and stability reports, held to their bounds"
# exit code 3 when a figure regresses past its bound (see `stickslip accuracy --help`)
cargo run --release -q -p stickslip -- accuracy --quick --check
cargo run --release -q -p stickslip -- stability --quick --check > /dev/null
echo "stability --quick --check: every run classified, exact bounded at 1e10 N/m, no NaN"

section "8/8 firmware sizes (flash = text + data, static RAM = data + bss)"
echo "$firmware_size"
finish_stage

echo
echo "== stage times (wall clock, seconds)"
for i in "${!stage_names[@]}"; do
    printf "%6d  %s\n" "${stage_secs[$i]}" "${stage_names[$i]}"
done
printf "%6d  total\n" $(($(date +%s) - t_all))
echo "test-all: all stages passed"
