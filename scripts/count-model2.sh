#!/usr/bin/env bash
# Instructions executed on the Cortex-M4F (counted under QEMU) by one f32 step of each model-2
# composition and by one call of each f32 exponential: tests/on-target bin `count_model2`
# (release profile, as `count`), see its documentation.
#
#   scripts/count-model2.sh
#
# Builds the program three times: as it is (the model's f32 exp is its own expf::expf), with the
# feature `libm-exp` (libm::expf) and with `micromath` (micromath's F32Ext::exp), unless
# COUNT_MODEL2_ELF / COUNT_MODEL2_LIBM_ELF / COUNT_MODEL2_MICROMATH_ELF name ELFs, and runs the
# three at the same time, each in its own QEMU, through scripts/trace-windows.sh (the machinery
# of scripts/count-instructions.sh: one trace line per executed instruction, counted between
# the marker calls; window 0, the markers' glue, is subtracted from the others).
#
# Prints, per build: for each class `<composition>_<stick|slip|transition>` and
# `expf_model` / `expf_libm` / `exp_micromath` the number of windows and min / median / p90 /
# mean / max instructions; per composition the stepper's size, substeps per step and the
# stack's high-water mark; the ELF's text/data/bss. Last:
#   instructions model2_f32_step exp=<model|libm|micromath> <composition>_stick=N <composition>_slip=M ...  (medians)
#   bound (issue): Stribeck slip step <= 1000 instructions: median ... met / NOT met; max ...
# The exit status is 1 if the bound is not met in the default build (the model's exp) by every
# Stribeck slip step without a transition (the max; the median is printed beside it).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=scripts/cross.sh
. "$root/scripts/cross.sh"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

elf_model="${COUNT_MODEL2_ELF:-}"
elf_libm="${COUNT_MODEL2_LIBM_ELF:-}"
elf_mm="${COUNT_MODEL2_MICROMATH_ELF:-}"
built="$root/tests/on-target/target/$CROSS_TARGET/release/count_model2"
if [ -z "$elf_model" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --release --bin count_model2)
    cp "$built" "$work/count_model2_model"
    elf_model="$work/count_model2_model"
fi
if [ -z "$elf_libm" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --release --bin count_model2 --features libm-exp)
    cp "$built" "$work/count_model2_libm"
    elf_libm="$work/count_model2_libm"
fi
if [ -z "$elf_mm" ]; then
    (cd "$root/tests/on-target" && cross_cargo build --release --bin count_model2 --features micromath)
    cp "$built" "$work/count_model2_micromath"
    elf_mm="$work/count_model2_micromath"
fi
for elf in "$elf_model" "$elf_libm" "$elf_mm"; do
    [ -f "$elf" ] || { echo "count-model2: no ELF at $elf" >&2; exit 1; }
done

# trace_windows ELF DIR (three traced runs at once, each setting up five steppers in soft-float
# f64: a longer hang guard than count-instructions.sh's)
export TRACE_TIMEOUT_S="${TRACE_TIMEOUT_S:-2400}"
# shellcheck source=scripts/trace-windows.sh
. "$root/scripts/trace-windows.sh"

trace_windows "$elf_model" "$work/model" &
job_model=$!
trace_windows "$elf_libm" "$work/libm" &
job_libm=$!
trace_windows "$elf_mm" "$work/micromath" &
job_mm=$!
wait "$job_model"
wait "$job_libm"
wait "$job_mm"

failed=0
for d in model libm micromath; do
    status="$(cat "$work/$d/status")"
    if [ "$status" -ne 0 ] || ! grep -q '^done count_model2' "$work/$d/stdout"; then
        echo "count-model2: QEMU exited with status $status or the program did not finish ($d)" >&2
        cat "$work/$d/stdout" "$work/$d/stderr" >&2
        failed=1
    fi
done
[ "$failed" -eq 0 ] || exit 1

bound_failed=0
for d in model libm micromath; do
    elf="$elf_model"
    [ "$d" = libm ] && elf="$elf_libm"
    [ "$d" = micromath ] && elf="$elf_mm"
    echo "== count_model2, the model's f32 exp = $d (tests/on-target, release profile)"
    grep '^comp ' "$work/$d/stdout" | sed 's/^comp /composition /'
    arm-none-eabi-size "$elf" | awk 'NR == 2 { printf "ELF: text=%d data=%d bss=%d bytes\n", $1, $2, $3 }'
    # classes: n min median p90 mean max; the medians line; the bound
    set +e
    awk -v exp_name="$d" '
        $1 == "total" { total = $2 }
        $1 == "W" { raw[$2] = $3; nw++ }
        $1 == "C" { cls[$2] = $3 }
        END {
            if (cls[0] != "baseline") { print "count-model2: window 0 is not the baseline" > "/dev/stderr"; exit 2 }
            base = raw[0]
            for (i = 1; i < nw; i++) {
                k = cls[i]
                if (k == "") { printf "count-model2: window %d has no class\n", i > "/dev/stderr"; exit 2 }
                v = raw[i] - base
                n[k]++; sum[k] += v; val[k, n[k]] = v
                if (!(k in mn) || v < mn[k]) mn[k] = v
                if (!(k in mx) || v > mx[k]) mx[k] = v
            }
            printf "trace: %d instructions in all; %d windows; window 0 (marker glue) = %d, subtracted below\n", total, nw, base
            printf "%-22s %6s %6s %6s %6s %6s %6s\n", "class", "n", "min", "median", "p90", "mean", "max"
            split("thesis damping band stribeck all face float", comps, " ")
            split("stick slip transition", kinds, " ")
            line = "instructions model2_f32_step exp=" exp_name
            for (c = 1; c in comps; c++) for (q = 1; q in kinds; q++) order[++no] = comps[c] "_" kinds[q]
            order[++no] = "expf_model"; order[++no] = "expf_libm"; order[++no] = "exp_micromath"
            for (j = 1; j <= no; j++) {
                k = order[j]
                if (n[k] == 0) { printf "%-22s %6d %6s %6s %6s %6s %6s\n", k, 0, "-", "-", "-", "-", "-"; continue }
                # median: insertion sort of the values
                m = n[k]
                for (a = 1; a <= m; a++) s[a] = val[k, a]
                for (a = 2; a <= m; a++) { x = s[a]; b = a - 1; while (b >= 1 && s[b] > x) { s[b + 1] = s[b]; b-- } s[b + 1] = x }
                med[k] = (m % 2) ? s[(m + 1) / 2] : int((s[m / 2] + s[m / 2 + 1]) / 2 + 0.5)
                # p90: the smallest value with at least 90 % of the values at or below it
                q = int(0.9 * m); if (q < 0.9 * m) q++; if (q < 1) q = 1
                printf "%-22s %6d %6d %6d %6d %6d %6d\n", k, m, mn[k], med[k], s[q], int(sum[k] / m + 0.5), mx[k]
                if (k !~ /transition$/) line = line " " k "=" med[k]
            }
            print line " (medians)"
            need = "thesis_stick thesis_slip damping_stick damping_slip band_stick band_slip stribeck_stick stribeck_slip all_stick all_slip face_stick face_slip float_stick float_slip"
            split(need, nd, " ")
            for (j = 1; j in nd; j++) if (n[nd[j]] == 0) { printf "count-model2: no %s step was measured\n", nd[j] > "/dev/stderr"; exit 2 }
            wmed = med["stribeck_slip"] > med["all_slip"] ? med["stribeck_slip"] : med["all_slip"]
            worst = mx["stribeck_slip"] > mx["all_slip"] ? mx["stribeck_slip"] : mx["all_slip"]
            printf "bound (issue): Stribeck slip step without a transition <= 1000 instructions: median (larger of stribeck_slip, all_slip) = %d: %s; max = %d: %s\n", wmed, wmed <= 1000 ? "met" : "NOT met", worst, worst <= 1000 ? "met" : "NOT met"
            if (worst > 1000) exit 1
        }
    ' "$work/$d/counts"
    rc=$?
    set -e
    if [ "$rc" -ne 0 ]; then
        [ "$rc" -eq 1 ] || exit 1
        if [ "$d" = model ]; then bound_failed=1; fi
    fi
    echo
done
exit "$bound_failed"
