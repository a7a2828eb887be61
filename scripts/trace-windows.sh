#!/usr/bin/env bash
# Sourced by scripts/count-instructions.sh and scripts/count-model2.sh: runs an on-target ELF
# on QEMU's netduinoplus2 with one `Trace` line per executed instruction and counts the lines
# between marker calls, window by window.
#
# Needs: qemu-system-arm, and `$work` (a scratch directory the caller removes).
#
# Markers the programs define (#[no_mangle], never inlined): stickslip_mark_begin and
# stickslip_mark_end around each measured call; optionally, right after the end marker, a class
# marker `rig_class_<class>` or `count_class_<class>` naming what the window measured.

# One instruction per translation block: `-singlestep` up to QEMU 8.0, then
# `-accel tcg,one-insn-per-tb=on` (the old flag was deprecated in 8.1).
qemu_version="$(qemu-system-arm --version | sed -n 's/^QEMU emulator version \([0-9]*\)\.\([0-9]*\).*/\1 \2/p')"
read -r qemu_major qemu_minor <<<"${qemu_version:-0 0}"
if [ "$qemu_major" -gt 8 ] || { [ "$qemu_major" -eq 8 ] && [ "$qemu_minor" -ge 1 ]; }; then
    one_insn=(-accel tcg,one-insn-per-tb=on)
else
    one_insn=(-singlestep)
fi

# trace_windows ELF DIR: runs ELF under QEMU with the instruction trace going through a FIFO
# into awk; writes DIR/stdout, DIR/stderr, DIR/status (QEMU's exit status) and DIR/counts:
#   W <window> <trace lines strictly between the end of stickslip_mark_begin and the start of
#               stickslip_mark_end>
#   C <window> <class>   (the first rig_class_<class> or count_class_<class> function entered
#                         after window <window>)
#   total <trace lines>
trace_windows() {
    local elf="$1" dir="$2"
    mkdir -p "$dir"
    mkfifo "$dir/trace"
    # QEMU runs in a subshell that records its exit status and then opens and closes the FIFO
    # once: if QEMU died before opening its log, that releases awk (which would otherwise wait
    # forever for a writer). `timeout` is a hang guard, not a measure: TRACE_TIMEOUT_S seconds
    # (default 900; scripts/count-model2.sh sets 2400: its three traced runs share the cores).
    (
        status=0
        timeout "${TRACE_TIMEOUT_S:-900}" qemu-system-arm -M netduinoplus2 -nographic -monitor none -serial null \
            -semihosting-config enable=on,target=native \
            "${one_insn[@]}" -d exec,nochain -D "$dir/trace" \
            -kernel "$elf" </dev/null >"$dir/stdout" 2>"$dir/stderr" || status=$?
        echo "$status" >"$dir/status"
        exec 4<>"$dir/trace"
        exec 4>&-
    ) &
    local runner=$!
    awk '
        /^Trace/ {
            total++
            sym = $NF
            if (sym == "stickslip_mark_begin") { state = 1; next }
            if (sym == "stickslip_mark_end") {
                if (state == 2) { printf "W %d %d\n", w, c; pending = 1; w++ }
                state = 0; c = 0; next
            }
            if (state == 1) { state = 2; c = 0 }
            if (state == 2) { c++; next }
            if (pending && substr(sym, 1, 10) == "rig_class_") {
                printf "C %d %s\n", w - 1, substr(sym, 11)
                pending = 0
            } else if (pending && substr(sym, 1, 12) == "count_class_") {
                printf "C %d %s\n", w - 1, substr(sym, 13)
                pending = 0
            }
        }
        END { printf "total %d\n", total }
    ' <"$dir/trace" >"$dir/counts"
    wait "$runner"
}

