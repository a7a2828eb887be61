#!/usr/bin/env bash
# Cross-build setup for thumbv7em-none-eabihf (the rig's STM32F407VG, Cortex-M4F).
#
# Two routes, picked automatically:
#   rustup  - `rustup target list --installed` shows thumbv7em-none-eabihf (a developer's
#             machine with internet: `rustup target add thumbv7em-none-eabihf`). Plain cargo,
#             linked by rust-lld.
#   debian  - otherwise: Debian's matched compiler and library source (rustc-web, cargo-web,
#             rust-web-src) build `core` for the target (-Zbuild-std=core, RUSTC_BOOTSTRAP=1).
#             Missing packages are installed with apt-get (needs root).
# Both routes link through flip-link (knurling: the stack at the bottom of RAM, so that an
# overflow faults instead of overwriting the statics; firmware/README.md, "Stack"), which runs
# rust-lld: the rustup route's own; for the debian route (Debian does not ship rust-lld) the
# host toolchain's, put on the linker's PATH. flip-link is installed with `cargo install
# flip-link --locked` when it is missing.
# Set CROSS_ROUTE=rustup or CROSS_ROUTE=debian beforehand to force a route.
#
# Sourced (`. scripts/cross.sh`): defines `cross_cargo` and exports CROSS_ROUTE, CROSS_CARGO,
# CROSS_TARGET and CROSS_CARGO_ARGS, without touching RUSTC or PATH of the calling shell (the
# host workspace keeps building with the host toolchain). `cross_cargo build --release` runs
# the route's cargo with its environment in the current directory.
# Called:
#   scripts/cross.sh                   print the route and the tools it uses
#   scripts/cross.sh --env             print `export` lines for a shell that only cross-builds
#   scripts/cross.sh build --release   run the route's cargo with these arguments (in $PWD)
#
# Also makes sure arm-none-eabi-size/objdump (binutils-arm-none-eabi) and qemu-system-arm are
# there, installing the Debian packages when they are not.

CROSS_TARGET=thumbv7em-none-eabihf
CROSS_DEBIAN_PACKAGES="rustc-web cargo-web rust-web-src binutils-arm-none-eabi qemu-system-arm"

_cross_log() { echo "cross.sh: $*" >&2; }

# apt-get install the given packages; `apt-get update` runs once per process first.
_cross_apt_install() {
    if ! command -v apt-get >/dev/null 2>&1; then
        _cross_log "need the Debian packages: $*; apt-get is not available here: install them by hand"
        return 1
    fi
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null 2>&1; then
            sudo="sudo"
        else
            _cross_log "need root to install: $*"
            return 1
        fi
    fi
    if [ -z "${_CROSS_APT_UPDATED:-}" ]; then
        _cross_log "apt-get update"
        $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq >&2 || return 1
        _CROSS_APT_UPDATED=1
    fi
    _cross_log "apt-get install -y $*"
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >&2 || return 1
}

# The oldest Debian rustc the firmware's dependencies accept (heapless 0.9 and
# embedded-storage 0.3.2 need 1.87). An older rustc-web (installed from stale package lists)
# is upgraded, not used.
CROSS_DEBIAN_MIN_RUSTC="1.87"

_cross_debian_rustc_recent() {
    local v
    v="$(/usr/bin/rustc --version 2>/dev/null | awk '{print $2}')" || return 1
    [ -n "$v" ] && [ "$(printf '%s\n%s\n' "$CROSS_DEBIAN_MIN_RUSTC" "$v" | sort -V | head -n 1)" = "$CROSS_DEBIAN_MIN_RUSTC" ]
}

_cross_debian_toolchain_ok() {
    [ -x /usr/bin/rustc ] && [ -x /usr/bin/cargo ] \
        && _cross_debian_rustc_recent \
        && [ -d /usr/lib/rustlib/src/rust/library/core ] \
        && command -v arm-none-eabi-ld >/dev/null 2>&1
}

# The directory of the host toolchain's rust-lld (rustup ships it in the sysroot's tools).
_cross_lld_dir() {
    local sysroot host
    sysroot="$(rustc --print sysroot 2>/dev/null)" || return 1
    host="$(rustc -vV 2>/dev/null | sed -n 's/^host: //p')"
    [ -x "$sysroot/lib/rustlib/$host/bin/rust-lld" ] || return 1
    echo "$sysroot/lib/rustlib/$host/bin"
}

# Installs whatever of the route's needs is missing and sets the CROSS_* variables.
cross_setup() {
    if [ -z "${CROSS_ROUTE:-}" ]; then
        if command -v rustup >/dev/null 2>&1 \
            && rustup target list --installed 2>/dev/null | grep -qx "$CROSS_TARGET"; then
            CROSS_ROUTE=rustup
        else
            CROSS_ROUTE=debian
        fi
    fi
    local missing=""
    case "$CROSS_ROUTE" in
        rustup)
            CROSS_CARGO="$(command -v cargo)" || { _cross_log "cargo not found"; return 1; }
            CROSS_CARGO_ARGS=""
            ;;
        debian)
            if ! _cross_debian_toolchain_ok; then
                missing="rustc-web cargo-web rust-web-src binutils-arm-none-eabi"
            fi
            CROSS_CARGO=/usr/bin/cargo
            CROSS_CARGO_ARGS="-Zbuild-std=core"
            ;;
        *)
            _cross_log "unknown CROSS_ROUTE '$CROSS_ROUTE' (rustup or debian)"
            return 1
            ;;
    esac
    if ! command -v flip-link >/dev/null 2>&1; then
        _cross_log "cargo install flip-link --locked"
        cargo install flip-link --locked >&2 || { _cross_log "cannot install flip-link"; return 1; }
    fi
    CROSS_LLD_DIR="$(_cross_lld_dir)" || { _cross_log "no rust-lld in the host toolchain (rustc --print sysroot)"; return 1; }
    command -v arm-none-eabi-size >/dev/null 2>&1 || missing="$missing binutils-arm-none-eabi"
    command -v qemu-system-arm >/dev/null 2>&1 || missing="$missing qemu-system-arm"
    if [ -n "$missing" ]; then
        # shellcheck disable=SC2086  # word splitting of the package list is intended
        _cross_apt_install $(echo "$missing" | tr ' ' '\n' | sort -u | tr '\n' ' ') || return 1
        if [ "$CROSS_ROUTE" = debian ] && ! _cross_debian_toolchain_ok; then
            _cross_log "Debian toolchain still incomplete after installing: $CROSS_DEBIAN_PACKAGES"
            return 1
        fi
    fi
    export CROSS_ROUTE CROSS_CARGO CROSS_CARGO_ARGS CROSS_TARGET CROSS_LLD_DIR
}

# cross_cargo SUBCOMMAND [ARGS...]: the route's cargo, for the target, in the current directory
# (whose .cargo/config.toml sets the target, runner and link flags).
cross_cargo() {
    local sub="$1"
    shift
    if [ "$CROSS_ROUTE" = debian ]; then
        # shellcheck disable=SC2086  # CROSS_CARGO_ARGS is a flag list
        env RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 PATH="$CROSS_LLD_DIR:$PATH" \
            CARGO_TARGET_THUMBV7EM_NONE_EABIHF_LINKER=flip-link \
            "$CROSS_CARGO" "$sub" $CROSS_CARGO_ARGS --target "$CROSS_TARGET" "$@"
    else
        env PATH="$CROSS_LLD_DIR:$PATH" "$CROSS_CARGO" "$sub" --target "$CROSS_TARGET" "$@"
    fi
}

cross_describe() {
    echo "route:  $CROSS_ROUTE"
    echo "cargo:  $CROSS_CARGO $CROSS_CARGO_ARGS ($("$CROSS_CARGO" --version 2>/dev/null))"
    if [ "$CROSS_ROUTE" = debian ]; then
        echo "rustc:  /usr/bin/rustc ($(/usr/bin/rustc --version 2>/dev/null)), RUSTC_BOOTSTRAP=1"
    else
        echo "rustc:  $(rustc --version 2>/dev/null)"
    fi
    echo "linker: $(command -v flip-link) (flip-link), rust-lld from $CROSS_LLD_DIR"
    echo "qemu:   $(qemu-system-arm --version 2>/dev/null | head -n 1)"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
    # called, not sourced
    set -euo pipefail
    cross_setup
    case "${1:-}" in
        "")
            cross_describe
            ;;
        --env)
            echo "export CROSS_ROUTE=$CROSS_ROUTE CROSS_TARGET=$CROSS_TARGET"
            if [ "$CROSS_ROUTE" = debian ]; then
                echo "export RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1"
                echo "export CARGO_TARGET_THUMBV7EM_NONE_EABIHF_LINKER=flip-link"
                echo "export PATH=\"$CROSS_LLD_DIR:\$PATH\""
                echo "alias cargo='/usr/bin/cargo'  # then: cargo build --release $CROSS_CARGO_ARGS"
            fi
            ;;
        *)
            cross_cargo "$@"
            ;;
    esac
else
    cross_setup || return 1
fi
