#!/usr/bin/env python3
"""Table 3.1 against the rig-built set with the pneumatic band drive (issue 34, item 5).

`fit` cannot run the drive (the virtual rig's fixed-step stepper refuses it), so this sweeps the
drive's keys over a grid and runs `stickslip simulate --json` on the six cases of each combination:
the bilateral twin of the `rig-built` set (its `contact` line removed: no edge opens in these
runs, a spring in tension would halt them as contact_loss) with `drive = "pneumatic"`. It prints
per combination the RMS of ln(model / measured) over Table 3.1's 12 pad_x and disc_x values
(`simulate --json`'s pad_x_pp and disc_x_pp; it gives no edge channels) and the push cases' pad_x, best last.

    python3 scripts/table31_pneumatic.py COLUMNS DROPS SEAL_V_S MU_K [--cases]

each a comma-separated list: column_length [m], the seal's drop seal_static - seal_kinetic [N]
(seal_static 80 N), seal_v_s [m/s], mu_k. `--cases` prints each case's residuals too. The binary
is target/release/stickslip (or $STICKSLIP). Example (docs/fit.md):

    python3 scripts/table31_pneumatic.py 0.04 0 0.005 0.4480 --cases
"""
import csv
import itertools
import json
import math
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("STICKSLIP", os.path.join(ROOT, "target", "release", "stickslip"))
CASES = [(c, p, b) for c in ("push", "pull") for p, b in (("trail", 0.025), ("center", 0.04), ("lead", 0.055))]
DROP_KEYS = ("contact =", "caliper =", "beta =", "name =", "mu_k =")


def table():
    rows = csv.reader(l for l in open(os.path.join(ROOT, "host", "data", "thesis_table_3_1.csv")) if not l.startswith("#"))
    return {(r[0], r[1]): float(r[3]) for r in rows if r[0] != "case"}


def base_scene():
    out = subprocess.run([BIN, "scenes", "show", "rig_built_push_center"], capture_output=True, text=True, check=True).stdout
    return [l for l in out.splitlines() if not l.startswith(DROP_KEYS)]


def run(base, tmp, combo, case):
    col, drop, v_ss, mu_k = combo
    cal, pos, beta = case
    lines = base + [
        f'caliper = "{cal}"', f"beta = {beta}", f'name = "{cal}_{pos}"', f"mu_k = {mu_k}",
        'drive = "pneumatic"', f"column_length = {col}", "seal_static = 80.0",
        f"seal_kinetic = {80.0 - drop}", f"seal_v_s = {v_ss}",
    ]
    path = os.path.join(tmp, f"{abs(hash((combo, case)))}.toml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    out = subprocess.run([BIN, "simulate", path, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    run = json.loads(out.stdout)
    if run.get("outcome") != "completed" or "pad_x_pp" not in run or "disc_x_pp" not in run:
        return None
    return run["pad_x_pp"], run["disc_x_pp"]


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 4:
        sys.exit(__doc__)
    grid = [[float(v) for v in a.split(",")] for a in args]
    combos = list(itertools.product(*grid))
    tab, base = table(), base_scene()
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(os.cpu_count() or 2) as ex:
        jobs = [(c, k) for c in combos for k in CASES]
        res = list(ex.map(lambda j: run(base, tmp, *j), jobs))
    lines = []
    for i, combo in enumerate(combos):
        r = res[i * 6:(i + 1) * 6]
        head = f"column {combo[0]:.4f} m, drop {combo[1]:g} N, seal v_s {combo[2]:g} m/s, mu_k {combo[3]:.5f}:"
        if any(x is None for x in r):
            lines.append((math.inf, head + " a case did not complete", []))
            continue
        res_ln = []
        for (cal, pos, _), (px, dx) in zip(CASES, r):
            case = f"{cal}_{pos}"
            res_ln.append((case, px, dx, math.log(px / tab[(case, "pad_x")]), math.log(dx / tab[(case, "disc_x")])))
        rms = math.sqrt(sum(a * a + b * b for *_, a, b in res_ln) / 12)
        push = [x[1] for x in res_ln[:3]]
        order = "right" if push[0] > push[1] > push[2] else "not"
        lines.append((rms, f"{head} RMS (12) {rms:.3f}, push pad_x {push[0]:.2f} / {push[1]:.2f} / {push[2]:.2f} (order {order})", res_ln))
    for rms, text, res_ln in sorted(lines, key=lambda x: -x[0]):
        print(text)
        if "--cases" in sys.argv:
            for case, px, dx, a, b in res_ln:
                print(f"    {case:12} pad_x {px:7.3f} (ln {a:+.2f})  disc_x {dx:7.3f} (ln {b:+.2f})")


if __name__ == "__main__":
    main()
