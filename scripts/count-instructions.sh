#!/usr/bin/env bash
# Instructions executed by one ExactStepper<f32>::step() on the Cortex-M4F, counted under QEMU.
#
# Builds tests/on-target (bin `count`) unless COUNT_ELF names an ELF, runs it on QEMU's
# netduinoplus2 with `-singlestep -d exec,nochain` (one `Trace` line per executed instruction,
# naming its function), and counts the trace lines between the marker calls
# stickslip_mark_begin / stickslip_mark_end of each measured window. The log goes through a
# FIFO into awk: nothing large is written to disk (about 14 million lines, 20-30 s).
#
# Window 0 is empty; its count (the calling glue of the markers) is subtracted from the others.
# Prints one line per window and, last:
#   instructions exact_f32_step no_transition=N with_transition=M
# where N is the larger of the stick and slip steps without a transition and M the larger of
# the two transition steps measured (stick->slip, end of that slip). These are instruction
# counts, not cycles (on the M4 most ALU/FPU instructions take 1 cycle, loads 2, VDIV 14).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"

elf="${COUNT_ELF:-}"
if [ -z "$elf" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --release --bin count)
    elf="$root/tests/on-target/target/$CROSS_TARGET/release/count"
fi
[ -f "$elf" ] || { echo "count-instructions: no ELF at $elf" >&2; exit 1; }

# One instruction per translation block: `-singlestep` up to QEMU 8.0, then
# `-accel tcg,one-insn-per-tb=on` (the old flag was deprecated in 8.1).
qemu_version="$(qemu-system-arm --version | sed -n 's/^QEMU emulator version \([0-9]*\)\.\([0-9]*\).*/\1 \2/p')"
read -r qemu_major qemu_minor <<<"${qemu_version:-0 0}"
if [ "$qemu_major" -gt 8 ] || { [ "$qemu_major" -eq 8 ] && [ "$qemu_minor" -ge 1 ]; }; then
    one_insn=(-accel tcg,one-insn-per-tb=on)
else
    one_insn=(-singlestep)
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkfifo "$work/trace"

# QEMU runs in a subshell that records its exit status and then opens and closes the FIFO once:
# if QEMU died before opening its log, that releases awk (which would otherwise wait forever
# for a writer). `timeout` is a hang guard (the run takes well under a minute), not a measure.
(
    status=0
    timeout 600 qemu-system-arm -M netduinoplus2 -nographic -monitor none -serial null \
        -semihosting-config enable=on,target=native \
        "${one_insn[@]}" -d exec,nochain -D "$work/trace" \
        -kernel "$elf" </dev/null >"$work/stdout" 2>"$work/stderr" || status=$?
    echo "$status" >"$work/status"
    exec 4<>"$work/trace"
    exec 4>&-
) &
runner=$!

# Counts the Trace lines strictly between the last line of stickslip_mark_begin and the first
# line of stickslip_mark_end, per window, in order.
awk '
    /^Trace/ {
        total++
        sym = $NF
        if (sym == "stickslip_mark_begin") { state = 1; next }
        if (sym == "stickslip_mark_end") {
            if (state == 2) { printf "%d %d\n", w, c; w++ }
            state = 0; c = 0; next
        }
        if (state == 1) { state = 2; c = 0 }
        if (state == 2) c++
    }
    END { printf "total %d\n", total }
' <"$work/trace" >"$work/counts"

wait "$runner"
status="$(cat "$work/status")"
if [ "$status" -ne 0 ]; then
    echo "count-instructions: QEMU exited with status $status" >&2
    cat "$work/stdout" "$work/stderr" >&2
    exit 1
fi

# Window descriptions printed by the binary: "window <i> <label> step=<k> <from>-><to> transitions=<n>"
grep '^window ' "$work/stdout" >"$work/windows" || true
n_windows=$(wc -l <"$work/windows")
n_counts=$(grep -vc '^total' "$work/counts" || true)
if [ "$n_windows" -ne 5 ] || [ "$n_counts" -ne 5 ]; then
    echo "count-instructions: expected 5 windows, the program reported $n_windows and the trace has $n_counts" >&2
    cat "$work/stdout" "$work/counts" >&2
    exit 1
fi

awk -v elf="$elf" '
    FNR == NR {
        if ($1 == "total") total = $2; else raw[$1] = $2
        next
    }
    {
        i = $2; label[i] = $3; step[i] = $4; move[i] = $5; tr[i] = $6
        sub("transitions=", "", tr[i])
    }
    END {
        base = raw[0]
        printf "trace: %d instructions in all; window 0 (marker glue) = %d, subtracted below\n", total, base
        for (i = 1; i <= 4; i++) {
            net[i] = raw[i] - base
            printf "window %d %-20s %-10s %-26s transitions=%s raw=%d net=%d\n", i, label[i], step[i], move[i], tr[i], raw[i], net[i]
        }
        # sanity: the windows measured what they claim
        bad = 0
        if (tr[1] != 0 || tr[3] != 0) { print "count-instructions: a no-transition window saw a transition" > "/dev/stderr"; bad = 1 }
        if (tr[2] < 1 || tr[4] < 1) { print "count-instructions: a transition window saw none" > "/dev/stderr"; bad = 1 }
        if (bad) exit 1
        no_tr = net[1] > net[3] ? net[1] : net[3]
        with_tr = net[2] > net[4] ? net[2] : net[4]
        printf "instructions exact_f32_step_detail no_transition_stick=%d no_transition_slip=%d stick_to_slip=%d slip_transition=%d\n", net[1], net[3], net[2], net[4]
        printf "instructions exact_f32_step no_transition=%d with_transition=%d\n", no_tr, with_tr
        printf "bound (issue): <= 200 instructions for a step without a transition: %s\n", no_tr <= 200 ? "met" : "NOT met"
        if (no_tr > 200) exit 1
    }
' "$work/counts" "$work/windows"
