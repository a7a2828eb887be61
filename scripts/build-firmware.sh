#!/usr/bin/env bash
# Builds the rig firmware (firmware/) for thumbv7em-none-eabihf in release and prints the
# ELF's section sizes (arm-none-eabi-size: text/data/bss) and what they take of the
# STM32F407VG's 1024 KB flash and 128 KB RAM. The toolchain route is scripts/cross.sh's.
# In CI (CI=true) the build is --locked: firmware/Cargo.lock must be up to date.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"

locked=()
if [ "${CI:-}" = true ]; then locked=(--locked); fi

(cd "$root/firmware" && cross_cargo build --release "${locked[@]}")

elf="$root/firmware/target/$CROSS_TARGET/release/stickslip-firmware"
[ -f "$elf" ] || { echo "build-firmware: no ELF at $elf" >&2; exit 1; }
echo "firmware ELF: ${elf#"$root"/}"
arm-none-eabi-size "$elf"
arm-none-eabi-size "$elf" | awk 'NR == 2 {
    printf "flash (text+data) %d of 1048576 bytes (%.1f %%); static RAM (data+bss) %d of 131072 bytes (%.1f %%), stack not included\n",
        $1 + $2, 100 * ($1 + $2) / 1048576, $2 + $3, 100 * ($2 + $3) / 131072
}'
