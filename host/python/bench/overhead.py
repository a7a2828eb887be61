"""The call overhead of the Python module: a 1 s simulate of push_center from Python (in process)
against the `stickslip` binary as a whole process, each the minimum over repeats.

    python host/python/bench/overhead.py [--repeats N]   (the binary: STICKSLIP_BIN or target/release/stickslip)
"""

import argparse
import os
import subprocess
import time
from pathlib import Path

import stickslip

REPO = Path(__file__).resolve().parents[3]
BIN = os.environ.get("STICKSLIP_BIN", str(REPO / "target" / "release" / "stickslip"))


def best(f, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20)
    n = ap.parse_args().repeats
    py = best(lambda: stickslip.simulate("push_center"), n)
    py_series = best(lambda: stickslip.simulate("push_center", series=True), n)
    whole = best(lambda: subprocess.run([BIN, "simulate", "push_center", "--json"], capture_output=True, check=True), n)
    print(f"1 s simulate of push_center (25,600 steps), minimum of {n}:")
    print(f"  Python, statistics            {py * 1e3:8.2f} ms")
    print(f"  Python, with the series       {py_series * 1e3:8.2f} ms")
    print(f"  binary, whole process --json  {whole * 1e3:8.2f} ms")


if __name__ == "__main__":
    main()
