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
# Fails if a build exceeds the issue's bounds: flash <= 64 KiB (65 536 bytes) and static RAM
# <= 48 KiB (49 152 bytes) for the thesis-configured builds (the first four); for the model-2
# builds flash <= 128 KiB (131 072 bytes) and static RAM <= 96 KiB (98 304 bytes: 32 KiB of
# the 128 KiB left for the stack). The feature builds share one target dir (only the firmware crate is rebuilt
# for each); the default build comes last, so that target/.../release/stickslip-firmware is
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

FLASH_BOUND=65536
RAM_BOUND=49152

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

# bounds_of VARIANT: "FLASH RAM"
bounds_of() {
    case "$1" in
        model2*) echo "131072 98304" ;;
        *) echo "$FLASH_BOUND $RAM_BOUND" ;;
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
    read -r flash_bound ram_bound < <(bounds_of "$v")
    verdict="met"
    if [ "$flash" -gt "$flash_bound" ] || [ "$ram" -gt "$ram_bound" ]; then
        verdict="NOT met"
        status=1
    fi
    printf "size %-15s %7d %6d %6d %7d %7d  flash <= %d, static RAM <= %d: %s\n" \
        "$v" "$text" "$data" "$bss" "$flash" "$ram" "$flash_bound" "$ram_bound" "$verdict"
done
if [ "$status" -ne 0 ]; then
    echo "build-firmware: a build exceeds the flash or static RAM bound" >&2
fi
exit "$status"
