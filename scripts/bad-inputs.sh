#!/usr/bin/env bash
# A campaign of bad and careless inputs across every command (issue 33), as a hostile or hurried
# user would give them. Each input runs the release binary with a limit of 5 s and 200 MB
# (`timeout`, and the maximum resident set size from /usr/bin/time; `ulimit -v` at 2 GiB only
# keeps a runaway from taking the machine) and is classified:
#
#   error    exit 2, one line on stderr starting with `error: ` that names what was wrong
#            (the case's needle: the option, the file, the field)
#   halt     exit 0 with a classified outcome on stdout (the case's needle, e.g. `budget`)
#   wrong0   exit 0 without it: a plausible answer to a bad question
#   hang     killed at 5 s
#   oom      more than 200 MB resident, or an allocation failure
#   panic    a Rust panic
#   unclear  any other exit, or exit 2 with a message that does not name the needle
#
# error and halt are the good classes. Prints the failures, then the count per class; exits 1
# if any input is in a bad class.
#
#   bash scripts/bad-inputs.sh            # builds the release binary first
#   STICKSLIP_BIN=path bash scripts/bad-inputs.sh
#   bash scripts/bad-inputs.sh -v         # every case's class and message
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
verbose=false
if [ "${1:-}" = "-v" ]; then verbose=true; fi
if [ -z "${STICKSLIP_BIN:-}" ]; then
    (cd "$root" && cargo build --release -p stickslip --quiet) || exit 1
    STICKSLIP_BIN="$root/target/release/stickslip"
fi
bin="$STICKSLIP_BIN"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
LIMIT_S=5
LIMIT_KB=204800

declare -A count=([error]=0 [halt]=0 [wrong0]=0 [hang]=0 [oom]=0 [panic]=0 [unclear]=0)
failures=()
n=0

# t EXPECT NEEDLE ARG...: runs `stickslip ARG...` and classifies it. EXPECT: error (exit 2
# naming NEEDLE), halt (exit 0, NEEDLE on stdout), either (one of the two).
t() {
    local expect=$1 needle=$2
    shift 2
    n=$((n + 1))
    (cd "$work" && /usr/bin/time -f "%M" -o "$work/mem" timeout -s KILL "$LIMIT_S" \
        bash -c 'ulimit -v 2097152; exec "$@"' _ "$bin" "$@" >"$work/out" 2>"$work/err" </dev/null)
    local rc=$?
    local mem
    mem=$(tail -n 1 "$work/mem" 2>/dev/null | tr -dc '0-9')
    mem=${mem:-0}
    local class
    local first
    first=$(head -c 300 "$work/err" | head -n 1)
    if [ $rc -eq 137 ] || [ $rc -eq 124 ]; then
        class=hang
    elif grep -q "panicked" "$work/err"; then
        class=panic
    elif [ "$mem" -gt "$LIMIT_KB" ] || grep -q "memory allocation" "$work/err"; then
        class=oom
    elif [ $rc -eq 2 ]; then
        if [ "$expect" != halt ] && [ "$(wc -l <"$work/err")" -eq 1 ] && [[ "$first" == "error: "* ]] &&
            grep -qF -- "$needle" "$work/err"; then
            class=error
        else
            class=unclear
        fi
    elif [ $rc -eq 0 ]; then
        if [ "$expect" != error ] && grep -qF -- "$needle" "$work/out"; then
            class=halt
        else
            class=wrong0
        fi
    else
        class=unclear
    fi
    count[$class]=$((count[$class] + 1))
    local line
    line=$(printf "%-7s %6s KB  stickslip %s  => %s" "$class" "$mem" "$*" "${first:-(stdout) $(head -c 120 "$work/out" | head -n 1)}")
    if [ "$class" != error ] && [ "$class" != halt ]; then
        failures+=("$line")
    fi
    if $verbose; then echo "$line"; fi
}

# --- inputs --------------------------------------------------------------------------------
cd "$work"
"$bin" scenes show push_center >push.toml
"$bin" scenes show rig_push_center >rig.toml
printf 'm = 1.0\nbeta = 0.02\nm = 2.0\n' >dup.toml
printf 'this is = not [toml\n' >syntax.toml
printf 'warp = 9\n' >unknown.toml
printf '' >empty.toml
head -c 2000000 /dev/urandom >random.bin
printf '\xff\xfe\x00m = 1\n' >binary.toml
python3 - <<'EOF' 2>/dev/null || printf '#%.0s' $(seq 1 10) >big.toml
print("#" * (1 << 20) + "\n", file=open("big.toml", "w"))
EOF
mkdir -p adir

# scene files: every numeric key, each with values no scene can have
keys="m inertia l w l_cl l_ct k_l k_t k_g f_n beta v mu_s mu_k c_x c_phi v_s stribeck_exponent m_b k_b c_b k_pivot c_y zeta_x zeta_phi zeta_b dt duration stats_from"
for k in $keys; do
    printf 'friction = "stribeck"\nband = true\n%s = nan\n' "$k" >"nan_$k.toml"
    t error "nan_$k.toml" simulate "nan_$k.toml"
    printf '%s = "abc"\n' "$k" >"str_$k.toml"
    t error "str_$k.toml" simulate "str_$k.toml"
    printf 'friction = "stribeck"\nband = true\n%s = -1e300\n' "$k" >"neg_$k.toml"
    t error "neg_$k.toml" simulate "neg_$k.toml"
done
# values that make the stepper crawl: classified as budget, or refused
for kv in "m = 1e-30" "k_l = 1e30" "k_g = 1e30" "k_t = 1e30" "zeta_x = 1e6" "inertia = 1e-30" "c_x = 1e30" "c_phi = 1e30"; do
    f="slow_${kv%% *}.toml"
    printf 'friction = "stribeck"\nband = true\n%s\n' "$kv" >"$f"
    t either budget simulate "$f"
    t either budget sil "$f"
done
printf 'friction = "stribeck"\nband = true\nk_b = 1e30\n' >slow_kb.toml
t either budget simulate slow_kb.toml
t either budget sil slow_kb.toml --json
t either budget simulate push_center --duration 20000
t error "--duration" simulate push_center --duration 1e6
t error "--duration" simulate push_center --duration 1e300
t error "--dt" simulate push_center --dt 1e-12
t either budget sil rig_push_center --duration 6000
t error "--dt" cases --dt 1
t error "--dt" simulate push_center --dt 0.8
t error "--dt" simulate push_center --dt 0
t error "--dt" simulate push_center --dt -1
t error "--dt" simulate push_center --dt nan
t error "--duration" simulate push_center --duration inf
t error "--stats-from" simulate push_center --stats-from 2
t error "--stats-from" cases --stats-from -1
t error "--plot-from" cases --plots plots --plot-from 5
t error "--plot-to" cases --plots plots --plot-to 0
t error "unknown scene" simulate no_such_scene
t error "dup.toml" simulate dup.toml
t error "syntax.toml" simulate syntax.toml
t error "warp" simulate unknown.toml
t error "random.bin" simulate random.bin
t error "binary.toml" simulate binary.toml
t error "big.toml" simulate big.toml
t error "/dev/zero" simulate /dev/zero
t error "/dev/zero" scenes show /dev/zero
t error "adir" simulate adir
t error "nonexistent" simulate ./nonexistent.toml
t error "--precision" simulate push_center --precision f16
t error "--set" cases --set bogus

# map
t error "--sweep" map push_center --sweep beta=0.01:0.07:1000000000
t error "--sweep" map push_center --sweep beta=0.01:0.07:0
t error "--sweep" map push_center --sweep beta=0.01:0.07:1
t error "--duration" map push_center --sweep duration=0.2:0.3:2 --duration 0.5
t error "--sweep" map push_center --sweep beta=0.01:0.07:-3
t error "--sweep" map push_center --sweep beta=0.07:0.01:3:log
t error "--sweep" map push_center --sweep beta=0:0.07:3:log
t error "--sweep" map push_center --sweep beta=nan:0.07:3
t error "--sweep" map push_center --sweep beta=0.01:inf:3
t error "--sweep" map push_center --sweep warp=1:2:3
t error "--sweep" map push_center --sweep beta=1:2
t error "--sweep" map push_center --sweep beta=0.01:0.07:3:lin
t error "--sweep" map push_center --sweep v_s=0.01:0.1:3
t error "--sweep" map push_center --sweep k_b=1e6:1e7:3
t error "--sweep" map push_center --sweep c_y=1:2:3
t error "--sweep" map push_center --sweep beta=0.01:0.07:10000 --sweep mu_s=0.4:0.8:10000
t error "--sweep" map push_center --sweep beta=0.01:0.07:3 --sweep beta=0.02:0.03:2
t error "sweep" map push_center --sweep beta=0.01:0.07:3 --sweep mu_s=0.4:0.8:2 --sweep v=0.1:0.2:2
t error "--sweep" map push_center --sweep m=-1:-0.5:3
t error "--shard" map push_center --sweep beta=0.01:0.07:3 --shard 0/1000000000
t error "--shard" map push_center --sweep beta=0.01:0.07:3 --shard -1/3
t error "--shard" map push_center --sweep beta=0.01:0.07:3 --shard 3/3
t error "--shard" map push_center --sweep beta=0.01:0.07:3 --shard 1/0
t error "--shard" map push_center --sweep beta=0.01:0.07:3 --shard x
t error "--jobs" map push_center --sweep beta=0.01:0.07:3 --jobs 0
t error "--jobs" map push_center --sweep beta=0.01:0.07:3 --jobs 100000
t error "--kick" map push_center --sweep beta=0.01:0.07:3 --kick 0
t error "--kick" map push_center --sweep beta=0.01:0.07:3 --kick 2
t error "--kick" map push_center --sweep beta=0.01:0.07:3 --kick nan
t either budget map rig_push_center --sweep k_b=1e6:1e30:3:log --duration 0.05 --stats-from 0.02

# map merge: tampered shards
"$bin" map push_center --sweep beta=0.01:0.07:2 --duration 0.05 --stats-from 0.02 --json >good.json 2>/dev/null
tamper() { # NAME PYTHON-EXPRESSION-ON-m
    python3 -c "
import json,sys
m=json.load(open('good.json'))
$2
json.dump(m,open('$1','w'))
"
}
tamper dt0.json "m['dt_s']=0"
tamper dur.json "m['duration_s']=-1"
tamper prec.json "m['precision']='f128'"
tamper regime.json "m['cells'][0]['from_rest']['regime']='bogus'"
tamper offgrid.json "m['cells'][1]['params']['beta']=0.05"
tamper n0.json "m['sweeps'][0]['n']=0"
tamper n3.json "m['sweeps'][0]['n']=3"
tamper total.json "m['cells_total']=5"
tamper order.json "m['cells'].reverse()"
tamper kick.json "m['kick']=7"
tamper key.json "m['sweeps'][0]['key']='warp'"
tamper nokey.json "del m['cells'][0]['params']['beta']"
tamper strparam.json "m['cells'][0]['params']['beta']='x'"
tamper sf.json "m['cells'][0]['from_rest']['stick_fraction']=3"
tamper negpp.json "m['cells'][0]['from_rest']['pad_x_pp']=-1"
tamper toml.json "m['scene_toml']='garbage = ['"
tamper shard.json "m['shard']={'k':5,'n':2}"
tamper dupcell.json "m['cells'][1]=m['cells'][0]"
tamper nocells.json "m['cells']=[]"
tamper stats.json "m['stats_from_s']=10"
tamper steady.json "m['steady_pp_over_kick_v']=1"
tamper log.json "m['sweeps'][0]['log']=True; m['sweeps'][0]['from']=-1"
for f in dt0 dur prec regime offgrid n0 n3 total order kick key nokey strparam sf negpp toml shard dupcell nocells stats steady log; do
    t error "$f.json" map merge "$f.json"
done
t error "n0.json" map merge n0.json --plot m.svg
t error "n3.json" map merge n3.json --plot m.svg --csv m.csv
t error "offgrid.json" map merge good.json offgrid.json --csv m.csv
t error "good.json" map merge good.json good.json
t error "random.bin" map merge random.bin
t error "/dev/zero" map merge /dev/zero
t error "push.toml" map merge push.toml
t error "missing.json" map merge missing.json

# fit
printf 'case,channel,statistic,value\npush_center,,stick_fraction,1.5\npush_center,pad_x,pp,100\n' >t_sf.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,1e308\n' >t_huge.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,1e-308\n' >t_tiny.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,-3\n' >t_neg.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,nan\n' >t_nan.csv
printf 'case,channel,statistic,value\npush_center,pad_x,stick_slip_hz,1e9\n' >t_hz.csv
printf 'case,channel,statistic,value\npush_center,pad_z,pp,10\n' >t_chan.csv
printf 'case,channel,statistic,value\npush_center,pad_x,ppp,10\n' >t_stat.csv
printf 'case,channel,statistic,value\nwarp_case,pad_x,pp,10\n' >t_case.csv
printf 'case,channel,statistic,value\n' >t_empty.csv
printf 'a,b,c\n1,2,3\n' >t_head.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,10\npush_center,pad_x,pp,11\n' >t_twice.csv
printf 'case,channel,statistic,value\npush_center,pad_x,pp,10,5\n' >t_ragged.csv
printf 'case,channel,statistic,value,sigma\npush_center,pad_x,pp,10,nan\n' >t_sig_nan.csv
printf 'case,channel,statistic,value,sigma\npush_center,pad_x,pp,10,0\n' >t_sig_zero.csv
printf 'case,channel,statistic,value,sigma\npush_center,pad_x,pp,10\n' >t_sig_short.csv
F=(fit --scene push_center --free mu_k)
for table in t_sf t_huge t_tiny t_neg t_nan t_hz t_chan t_stat t_case t_empty t_head t_twice t_ragged t_sig_nan t_sig_zero t_sig_short; do
    t error "$table.csv" "${F[@]}" --table "$table.csv"
done
t error "/dev/zero" "${F[@]}" --table /dev/zero
t error "random.bin" "${F[@]}" --table random.bin
t error "--free k_b" fit --scene push_center --free k_b --table thesis_table_3_1
t error "--free v_s" fit --scene push_center --free v_s --table thesis_table_3_1
t error "--free c_y" fit --scene rig_push_center --free c_y --table thesis_table_3_1
t error "--free" fit --scene push_center --free warp --table thesis_table_3_1
t error "--free" fit --scene push_center --free beta --table thesis_table_3_1
t error "--free" fit --scene push_center --free mu_k,mu_k --table thesis_table_3_1
t error "--free" fit --scene push_center --free c_x --table thesis_table_3_1
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_k=0.1:0.4:1000000000
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_k=0.4:0.1:5
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_k=0:0.4:5
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_k=0.1:inf:5
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_k=0.1:0.4:1
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile mu_s=0.1:0.4:3
t error "--profile" "${F[@]}" --table thesis_table_3_1 --profile garbage
t error "--starts" "${F[@]}" --table thesis_table_3_1 --starts 100000
t error "--starts" "${F[@]}" --table thesis_table_3_1 --starts 0
t error "--max-iters" "${F[@]}" --table thesis_table_3_1 --max-iters 10000000000
t error "--bootstrap" "${F[@]}" --table thesis_table_3_1 --bootstrap 100000000
t error "--horizons" "${F[@]}" --table thesis_table_3_1 --horizons -1
t error "--horizons" "${F[@]}" --table thesis_table_3_1 --horizons nan
t error "--bounds" "${F[@]}" --table thesis_table_3_1 --bounds mu_k=1:0.5
t error "--bounds" "${F[@]}" --table thesis_table_3_1 --bounds mu_k=0.5:0.9
t error "--bounds" "${F[@]}" --table thesis_table_3_1 --bounds warp=1:2
t error "bounded twice" "${F[@]}" --table thesis_table_3_1 --bounds mu_k=0.2:0.4 --bounds mu_k=0.1:0.44
t error "--weights" "${F[@]}" --table thesis_table_3_1 --weights pp=-1
t error "--weights" "${F[@]}" --table thesis_table_3_1 --weights warp=1
t error "--holdout" "${F[@]}" --table thesis_table_3_1 --holdout warp_case
t error "target" "${F[@]}" justafile.csv
t error "push_center=-" "${F[@]}" push_center=-
t error "missing.csv" "${F[@]}" push_center=missing.csv
t error "--breakaway-jump" "${F[@]}" --table thesis_table_3_1 --breakaway-jump 1e308
t error "no target" "${F[@]}"
t error "--scene" fit --free mu_k --table thesis_table_3_1

# sil and compare
t error "--noise" sil push_center --noise 1e300
t error "--noise" sil push_center --noise -1
t error "--noise" sil push_center --noise nan
t error "--gain" sil push_center --gain 1e6
t error "--gain" sil push_center --gain 1e-300
t error "--gain" sil push_center --gain 0
t error "--gain" sil push_center --gain 1,2
t error "--gain" sil push_center --gain inf
t error "--quiet-lead" sil push_center --quiet-lead 1e6
t error "--quiet-lead" sil push_center --quiet-lead -1
t error "--adc-noise" sil push_center --adc-noise 1e300
t error "--oversample" sil push_center --oversample 0
t error "--oversample" sil push_center --oversample 1000
t error "--segment" sil push_center --segment 3
t error "--segment" sil push_center --segment 100000000
t error "--breakaway-jump" sil push_center --breakaway-jump 0
t error "--breakaway-jump" sil push_center --breakaway-jump 1e308
t error "--front-end" sil push_center --front-end magic
t either "cannot decide" sil push_center --gain 1000
t either "cannot decide" sil push_center --noise 5000
t error "--seed" sil push_center --seed -1
t error "--dt" sil push_center --dt 0

# recordings (analyze, compare): the readers' checks
printf 't,disc_x,pad_x,pad_trail,pad_lead\n' >r_head.csv
printf 't,disc_x,pad_x,pad_trail\n0,0,0,0\n' >r_col.csv
printf 't,disc_x,pad_x,pad_trail,pad_lead\n0,0,x,0,0\n' >r_cell.csv
printf 't,disc_x,pad_x,pad_trail,pad_lead\n0,0,0,0\n' >r_ragged.csv
printf 't,disc_x,pad_x,pad_trail,pad_lead\n0,0,0,0,0\n0,0,0,0,0\n' >r_dup.csv
python3 -c "
import math
rows=['t,disc_x,pad_x,pad_trail,pad_lead']+['%r,0,%r,0,0'%(i/25600, math.sin(i/10)) for i in range(6000)]
open('r_cr.csv','w').write('\r'.join(rows)+'\r')
open('r_ok.csv','w').write('\n'.join(rows)+'\n')
"
t error "r_head.csv" analyze r_head.csv
t error "r_col.csv" analyze r_col.csv
t error "r_cell.csv" analyze r_cell.csv
t error "r_ragged.csv" analyze r_ragged.csv
t error "r_dup.csv" analyze r_dup.csv
t error "r_cr.csv" analyze r_cr.csv
t error "empty.toml" analyze empty.toml
t error "random.bin" analyze random.bin
t error "missing.csv" analyze missing.csv
t error "--breakaway-jump" analyze r_ok.csv --breakaway-jump 1e308
t error "--breakaway-jump" analyze r_ok.csv --breakaway-jump -5
t error "--from" analyze r_ok.csv --from nan
t error "--from" analyze r_ok.csv --from 1e300
t error "--quiet" analyze r_ok.csv --quiet 5:1
t error "--quiet" analyze r_ok.csv --quiet x
t error "--quiet" analyze r_ok.csv --quiet 0:0.01 --breakaway-jump 10
t error "--segment" analyze r_ok.csv --segment 7
t error "no_such_scene" analyze r_ok.csv --scene no_such_scene
t error "r_col.csv" compare push_center r_col.csv
t error "--noise" compare push_center r_ok.csv --noise 1e300
t error "--gain" compare push_center r_ok.csv --gain 1e-300
t error "--quiet-lead" compare push_center r_ok.csv --quiet-lead 1e9
# foreign recordings: ambiguous names, a record too short for the estimator, a WAV clipped at
# its own full scale, a WAV whose valid bits exceed its container
printf 't,Acc [m/s^2],Acc [g]\n0,0,0\n0.001,1,0.1\n0.002,0,0\n' >r_acc2.csv
printf 't,pad_x\n0,0\n0.0001,0.001\n0.0002,0\n0.0003,0.001\n' >r_short.csv
python3 -c "
import math, struct
def wav(name, fmt, data):
    body = b'WAVEfmt ' + struct.pack('<I', len(fmt)) + fmt + b'data' + struct.pack('<I', len(data)) + data
    open(name, 'wb').write(b'RIFF' + struct.pack('<I', len(body)) + body)
codes = [max(-32767, min(32767, round(3 * 16383 * math.sin(2 * math.pi * 200 * i / 25600)))) for i in range(4096)]
wav('w_clip.wav', struct.pack('<HHIIHH', 1, 1, 25600, 51200, 2, 16), struct.pack('<%dh' % len(codes), *codes))
sub = bytes([1, 0, 0, 0, 0, 0, 0x10, 0, 0x80, 0, 0, 0xaa, 0, 0x38, 0x9b, 0x71])
wav('w_valid.wav', struct.pack('<HHIIHHHHI', 0xFFFE, 1, 25600, 51200, 2, 16, 22, 24, 4) + sub, struct.pack('<%dh' % len(codes), *codes))
"
t error "pad_x=Acc" analyze r_acc2.csv --channel pad_x=Acc
t halt "cannot decide" analyze r_short.csv
t halt "cannot decide" analyze w_clip.wav --channel pad_x=#1*4
t error "24 valid bits" analyze w_valid.wav --channel pad_x=#1*4

# decode
"$bin" decode --help >/dev/null
fixture="$root/host/tests/data/defmt-fixture"
python3 - "$fixture.defmt" <<'EOF'
import sys
b = bytearray(open(sys.argv[1], 'rb').read())
start = True
for i, x in enumerate(b):
    if start and x != 0:
        b[i] = 1 if x == 0xFE else x + 1
    start = b[i] == 0
open('other.defmt', 'wb').write(b)
open('junk.defmt', 'wb').write(bytes((i * 37 + 11) % 255 + 1 if i % 9 else 0 for i in range(4000)))
open('text.csv', 'w').write('t,pad_x\n' + ''.join(f'{i / 25600},{i % 7}\n' for i in range(400)))
EOF
t error "other.defmt" decode --elf "$fixture.elf" other.defmt
t error "junk.defmt" decode --elf "$fixture.elf" junk.defmt
t error "random.bin" decode --elf "$fixture.elf" random.bin
t error "text.csv" decode --elf "$fixture.elf" text.csv
t error "/dev/zero" decode --elf /dev/zero "$fixture.defmt"
t error "push.toml" decode --elf push.toml "$fixture.defmt"
t error "random.bin" decode --elf random.bin "$fixture.defmt"
t error "missing.elf" decode --elf missing.elf "$fixture.defmt"
t error "missing.defmt" decode --elf "$fixture.elf" missing.defmt
t error "--kind" decode --elf "$fixture.elf" "$fixture.defmt" --kind transition

# accuracy, stability, scenes, the command line itself
t error "--repeats" accuracy --repeats 0
t error "--repeats" accuracy --repeats 100000
t error "--warp" stability --warp
t error "frobnicate" frobnicate
t error "no_such" scenes show no_such
t error "--plot" accuracy --plot

# --- the outcome ---------------------------------------------------------------------------
if [ ${#failures[@]} -gt 0 ]; then
    echo "inputs not in a good class:"
    printf '  %s\n' "${failures[@]}"
fi
echo
echo "| class | inputs |"
echo "|---|---:|"
for c in error halt wrong0 hang oom panic unclear; do
    echo "| $c | ${count[$c]} |"
done
echo "| total | $n |"
if [ ${#failures[@]} -gt 0 ]; then exit 1; fi
