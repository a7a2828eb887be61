#!/usr/bin/env bash
# Builds the rig firmware (firmware/) for thumbv7em-none-eabihf in release, once per feature
# set a rig may have, and prints each ELF's section sizes (arm-none-eabi-size: text/data/bss),
# its flash (text + data) and static RAM (data + bss, stack not included):
#
#   default       pressure + end-of-stroke (what `cargo run --release` flashes)
#   no-pressure   end-of-stroke only: four accelerometers, timed clamp and drive
#   no-eos        pressure only: records of fixed length
#   neither       no pressure transducers, no end-of-stroke switch
#   model2-band   default + the lockstep model on model 2: Coulomb friction and the band
#   model2-stribeck  default + model 2: Stribeck friction, no band
#   model2        default + model 2: Stribeck friction and the band (every option of part 1)
#
# Fails if a build exceeds the bounds, the same for every build and set from the chip
# (STM32F407VG: 1 MB flash, 128 KB RAM + 64 KB CCM; memory.x lists the flash and the 128 KB):
#   flash (text + data)       <= 128 KiB (131 072 bytes): an eighth of the chip's flash;
#   static RAM (data + bss)   <= 80 KiB (81 920 bytes), so that the stack, the rest of the
#                                128 KiB of RAM (flip-link puts it below the statics), has at
#                                least 48 KiB: 1.6 times the deepest use measured, the rig's
#                                set-up (the `stack rig_init` line of
#                                `cargo test --release -p stickslip-crosscheck --test on_target -- --ignored --nocapture`).
# The feature builds share one target dir (only the firmware crate is rebuilt for each); the
# default build comes last, so that target/.../release/stickslip-firmware is
# the default image. Each variant's ELF is also kept as
# target/thumbv7em-none-eabihf/release/stickslip-firmware-<variant>.
#
# `--default-only` builds and checks the default feature set alone. The toolchain route is
# scripts/cross.sh's. In CI (CI=true) the builds are --locked: firmware/Cargo.lock must be up to
# date.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"

locked=()
if [ "${CI:-}" = true ]; then locked=(--locked); fi

FLASH_BOUND=131072
RAM_BOUND=81920

variants=(no-pressure no-eos neither model2-band model2-stribeck model2 default)
if [ "${1:-}" = "--default-only" ]; then variants=(default); fi

features_of() {
    case "$1" in
        default) echo "" ;;
        no-pressure) echo "--no-default-features --features end-of-stroke" ;;
        no-eos) echo "--no-default-features --features pressure" ;;
        neither) echo "--no-default-features" ;;
        model2-band) echo "--features model2-band" ;;
        model2-stribeck) echo "--features model2-stribeck" ;;
        model2) echo "--features model2" ;;
    esac
}

out_dir="$root/firmware/target/$CROSS_TARGET/release"
elf="$out_dir/stickslip-firmware"
for v in "${variants[@]}"; do
    echo "== build-firmware: $v ($(features_of "$v" | sed 's/^$/default features/'))"
    # shellcheck disable=SC2046  # the feature flags are a word list
    (cd "$root/firmware" && cross_cargo build --release "${locked[@]}" $(features_of "$v"))
    [ -f "$elf" ] || { echo "build-firmware: no ELF at $elf" >&2; exit 1; }
    cp "$elf" "$out_dir/stickslip-firmware-$v"
done

echo "firmware ELF: ${elf#"$root"/} (default features)"
status=0
printf "size %-15s %7s %6s %6s %7s %7s\n" variant text data bss flash ram
for v in "${variants[@]}"; do
    read -r text data bss < <(arm-none-eabi-size "$out_dir/stickslip-firmware-$v" | awk 'NR == 2 { print $1, $2, $3 }')
    flash=$((text + data))
    ram=$((data + bss))
    flash_bound=$FLASH_BOUND
    ram_bound=$RAM_BOUND
    verdict="met"
    if [ "$flash" -gt "$flash_bound" ] || [ "$ram" -gt "$ram_bound" ]; then
        verdict="NOT met"
        status=1
    fi
    printf "size %-15s %7d %6d %6d %7d %7d  flash <= %d, static RAM <= %d: %s\n" \
        "$v" "$text" "$data" "$bss" "$flash" "$ram" "$flash_bound" "$ram_bound" "$verdict"
done
if [ "$status" -ne 0 ]; then
    echo "build-firmware: a build exceeds the flash bound ($((FLASH_BOUND / 1024)) KiB) or the static RAM bound ($((RAM_BOUND / 1024)) KiB, which keeps $(((131072 - RAM_BOUND) / 1024)) KiB of the 128 KiB for the stack)" >&2
fi
exit "$status"
