#!/usr/bin/env bash
# The Python module (host/python, docs/python.md): build it with pip + maturin into a virtual
# environment under target/, then run its tests (they compare it with the binary
# target/release/stickslip, which must be built). Installs what it needs from PyPI into that
# environment only (maturin, numpy, pytest, matplotlib for the worked example).
#
#   bash scripts/python-module.sh            (test-all.sh step 4d)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

if ! command -v python3 >/dev/null 2>&1 || ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    if command -v apt-get >/dev/null 2>&1; then
        apt-get install -y -q python3 python3-venv >/dev/null
    else
        echo "python-module: needs python3 with venv (3.9 or later)" >&2
        exit 1
    fi
fi

venv="$root/target/python-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check "maturin>=1.16,<2" numpy pytest matplotlib
# The extension shares the workspace's target directory, so the host crate's build is reused.
CARGO_TARGET_DIR="$root/target" "$venv/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps ./host/python
[ -x "$root/target/release/stickslip" ] || cargo build --release -p stickslip
STICKSLIP_BIN="$root/target/release/stickslip" "$venv/bin/python" -m pytest -q host/python/tests
"$venv/bin/python" host/python/bench/overhead.py --repeats 5
