#!/usr/bin/env bash
# Instructions executed on the Cortex-M4F, counted under QEMU, for two programs of
# tests/on-target (run at the same time, each in its own QEMU):
#
#   count      one ExactStepper<f32>::step() of the default scene (release profile, as the
#              digests); fails above 200 instructions for a step without a transition;
#   rig_count  the rig's per-sample path (`firmware` profile: the firmware's own code
#              generation settings, see tests/on-target/Cargo.toml): path A, calibration of the
#              six channels + estimator + window statistics, and path B, the firmware's whole
#              per-sample call stickslip_rig_core::sample_words on the shared crate's rig
#              (with the lockstep model and the sequencer);
#              fails if any sample of path A takes more than 1,500 instructions.
#
# Builds the two programs unless COUNT_ELF / RIG_COUNT_ELF name ELFs, runs each on QEMU's
# netduinoplus2 with `-singlestep -d exec,nochain` (one `Trace` line per executed instruction,
# naming its function), and counts the trace lines between the marker calls
# stickslip_mark_begin / stickslip_mark_end of each measured window. The logs go through FIFOs
# into awk: nothing large is written to disk (14 and 20 million lines, 20-50 s each).
#
# Window 0 of each program is empty; its count (the calling glue of the markers) is subtracted
# from the others. `count` prints what its windows were; `rig_count` names the class of each
# window by calling a marker function `rig_class_<class>` right after it.
#
# Prints, last for each program:
#   instructions exact_f32_step no_transition=N with_transition=M
#   instructions rig_sample calibrate_estimator max=N ... / with_model_sequencer max=M ...
# These are instruction counts, not cycles (on the M4 most ALU/FPU instructions take 1 cycle,
# loads 2, VDIV/VSQRT 14).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"

count_elf="${COUNT_ELF:-}"
rig_elf="${RIG_COUNT_ELF:-}"
if [ -z "$count_elf" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --release --bin count)
    count_elf="$root/tests/on-target/target/$CROSS_TARGET/release/count"
fi
if [ -z "$rig_elf" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --profile firmware --bin rig_count)
    rig_elf="$root/tests/on-target/target/$CROSS_TARGET/firmware/rig_count"
fi
for elf in "$count_elf" "$rig_elf"; do
    [ -f "$elf" ] || { echo "count-instructions: no ELF at $elf" >&2; exit 1; }
done

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# trace_windows ELF DIR (QEMU, the trace through a FIFO into awk; see the file)
# shellcheck source=scripts/trace-windows.sh
. "$root/scripts/trace-windows.sh"

trace_windows "$count_elf" "$work/count" &
count_job=$!
trace_windows "$rig_elf" "$work/rig" &
rig_job=$!
wait "$count_job"
wait "$rig_job"

failed=0
for d in count rig; do
    status="$(cat "$work/$d/status")"
    if [ "$status" -ne 0 ]; then
        echo "count-instructions: QEMU exited with status $status ($d)" >&2
        cat "$work/$d/stdout" "$work/$d/stderr" >&2
        failed=1
    fi
done
[ "$failed" -eq 0 ] || exit 1

# ---- count: ExactStepper<f32>::step -------------------------------------------------------
# Window descriptions printed by the binary: "window <i> <label> step=<k> <from>-><to> transitions=<n>"
echo "== ExactStepper<f32>::step() (tests/on-target bin count, release profile)"
grep '^window ' "$work/count/stdout" >"$work/count/windows" || true
n_windows=$(wc -l <"$work/count/windows")
n_counts=$(grep -c '^W ' "$work/count/counts" || true)
if [ "$n_windows" -ne 5 ] || [ "$n_counts" -ne 5 ]; then
    echo "count-instructions: expected 5 windows, the program reported $n_windows and the trace has $n_counts" >&2
    cat "$work/count/stdout" "$work/count/counts" >&2
    exit 1
fi

awk -v elf="$count_elf" '
    FNR == NR {
        if ($1 == "total") total = $2; else if ($1 == "W") raw[$2] = $3
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
' "$work/count/counts" "$work/count/windows"

# ---- rig_count: the per-sample path ---------------------------------------------------------
echo
echo "== the rig's per-sample path (tests/on-target bin rig_count, firmware profile)"
if ! grep -q '^done rig_count' "$work/rig/stdout"; then
    echo "count-instructions: rig_count did not finish" >&2
    cat "$work/rig/stdout" >&2
    exit 1
fi
awk '
    $1 == "total" { total = $2 }
    $1 == "W" { raw[$2] = $3; nw++ }
    $1 == "C" { cls[$2] = $3 }
    END {
        if (cls[0] != "baseline") { print "count-instructions: rig_count window 0 is not the baseline" > "/dev/stderr"; exit 1 }
        base = raw[0]
        for (i = 1; i < nw; i++) {
            k = cls[i]
            if (k == "") { printf "count-instructions: rig_count window %d has no class\n", i > "/dev/stderr"; exit 1 }
            v = raw[i] - base
            n[k]++; sum[k] += v
            if (!(k in mn) || v < mn[k]) mn[k] = v
            if (!(k in mx) || v > mx[k]) mx[k] = v
        }
        printf "trace: %d instructions in all; %d windows; window 0 (marker glue) = %d, subtracted below\n", total, nw, base
        printf "%-22s %6s %6s %6s %6s\n", "class", "n", "min", "mean", "max"
        split("a_stick a_slip a_event a_window b_setup b_record_start b_stick b_slip b_event b_model_transition b_window", order, " ")
        for (j = 1; j in order; j++) {
            k = order[j]
            if (n[k] > 0) printf "%-22s %6d %6d %6d %6d\n", k, n[k], mn[k], int(sum[k] / n[k] + 0.5), mx[k]
            else printf "%-22s %6d %6s %6s %6s\n", k, 0, "-", "-", "-"
        }
        amax = 0
        for (k in mx) if (substr(k, 1, 2) == "a_" && mx[k] > amax) amax = mx[k]
        bmax_plain = 0
        for (k in mx) if (k == "b_stick" || k == "b_slip" || k == "b_event" || k == "b_window") if (mx[k] > bmax_plain) bmax_plain = mx[k]
        printf "instructions rig_sample calibrate_estimator stick=%d slip=%d window_close=%d max=%d\n", \
            int(sum["a_stick"] / n["a_stick"] + 0.5), int(sum["a_slip"] / n["a_slip"] + 0.5), mx["a_window"], amax
        printf "instructions rig_sample with_model_sequencer stick=%d slip=%d window_close=%d model_transition_max=%d record_start=%d max_without_model_transition=%d\n", \
            int(sum["b_stick"] / n["b_stick"] + 0.5), int(sum["b_slip"] / n["b_slip"] + 0.5), mx["b_window"], mx["b_model_transition"], mx["b_record_start"], bmax_plain
        # every class the program promises must have been seen
        split("a_stick a_slip a_event a_window b_stick b_slip b_event b_window b_model_transition b_record_start", need, " ")
        for (j = 1; j in need; j++) if (n[need[j]] == 0) { printf "count-instructions: rig_count saw no %s sample\n", need[j] > "/dev/stderr"; exit 1 }
        printf "bound (issue): <= 1500 instructions for every sample of the path without the lockstep model: %s\n", amax <= 1500 ? "met" : "NOT met"
        if (amax > 1500) exit 1
    }
' "$work/rig/counts"
