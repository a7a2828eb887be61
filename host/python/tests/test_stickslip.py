"""The Python module against the `stickslip` binary: the same inputs give the same JSON, value for
value; bad input raises with the binary's one-line message; arrays in give what the same
samples in a file give.

The binary is `STICKSLIP_BIN`, or target/release/stickslip of this repository (build it with
`cargo build --release` first).
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import stickslip

REPO = Path(__file__).resolve().parents[3]
BIN = os.environ.get("STICKSLIP_BIN", str(REPO / "target" / "release" / "stickslip"))
RECORDINGS = REPO / "host" / "tests" / "data" / "recordings"


def tool(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def tool_json(*args: str) -> dict:
    p = tool(*args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def without(d: dict, *keys: str) -> dict:
    return {k: v for k, v in d.items() if k not in keys}


def same(a, b, path="") -> None:
    """Equal value for value (NaN equal to NaN), naming the first difference."""
    if isinstance(a, dict) and isinstance(b, dict):
        assert a.keys() == b.keys(), f"{path}: keys {sorted(a.keys() ^ b.keys())}"
        for k in a:
            same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list) and isinstance(b, list):
        assert len(a) == len(b), f"{path}: lengths {len(a)} and {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float) and math.isnan(a):
        assert math.isnan(b), f"{path}: NaN and {b}"
    else:
        assert a == b and type(a) is type(b), f"{path}: {a!r} and {b!r}"


def test_the_binary_is_there():
    assert Path(BIN).exists(), f"build the binary first (cargo build --release): {BIN}"
    assert stickslip.version() == tool("--version").stdout.split()[-1]


@pytest.mark.parametrize("scene", ["push_trail", "push_center", "push_lead", "pull_trail", "pull_center", "pull_lead"])
def test_simulate_equals_the_binary_on_the_six_cases(scene):
    same(stickslip.simulate(scene), tool_json("simulate", scene))


def test_cases_equals_the_binary():
    same(stickslip.cases(), tool_json("cases"))


def test_scene_overrides_are_a_scene_file(tmp_path):
    text = tool("scenes", "show", "push_center").stdout.replace("beta = 0.04 ", "beta = 0.03 ")
    assert "beta = 0.03" in text
    f = tmp_path / "s.toml"
    f.write_text(text)
    same(stickslip.simulate("push_center", beta=0.03), tool_json("simulate", str(f)))
    # a dict is a scene file of its keys: keys left out take the default pad's values
    g = tmp_path / "d.toml"
    g.write_text('name = "d"\nbeta = 0.03\nmu_k = 0.3\n')
    same(stickslip.simulate({"name": "d", "beta": 0.03, "mu_k": 0.3}), tool_json("simulate", str(g)))


def test_run_flags_are_flags():
    same(stickslip.simulate("oracle_stribeck", dt=1e-4, precision="f32"), tool_json("simulate", "oracle_stribeck", "--dt", "1e-4", "--precision", "f32"))


def test_series_are_the_csv(tmp_path):
    out = stickslip.simulate("pull_center", series=True, duration=0.2, stats_from=0.1)
    f = tmp_path / "s.csv"
    p = tool("simulate", "pull_center", "--duration", "0.2", "--stats-from", "0.1", "--csv", str(f))
    assert p.returncode == 0, p.stderr
    lines = f.read_text().splitlines()
    header = lines[0].split(",")
    assert list(out["series"]) == header
    rows = [l.split(",") for l in lines[1:]]
    assert len(out["series"]["t_s"]) == len(rows) == 5120
    for i, name in enumerate(header):
        col = out["series"][name]
        if name == "regime":
            assert list(col) == [r[i] for r in rows]
        else:
            assert col.dtype == np.float64
            assert [float(r[i]) for r in rows] == list(col)
    same(without(out, "series"), tool_json("simulate", "pull_center", "--duration", "0.2", "--stats-from", "0.1"))


def test_sil_equals_the_binary():
    same(stickslip.sil("pull_center", noise=0.01, seed=3), tool_json("sil", "pull_center", "--noise", "0.01", "--seed", "3"))


@pytest.mark.parametrize(
    "values, says",
    [
        (np.zeros((2, 1000)), "shape (2, 1000)"),
        (np.zeros(1000, dtype=complex), "dtype complex128"),
        (np.zeros(1000, dtype=bool), "dtype bool"),
        (np.array(["1.0"] * 1000), "dtype <U3"),
        (np.array([1.0, None] * 500, dtype=object), "pad_x[1] is nan"),
        (np.array([1.0, "x"] * 500, dtype=object), "an object array"),
        (np.r_[np.zeros(700), np.nan, np.zeros(299)], "pad_x[700] is nan"),
        (np.r_[np.zeros(10), np.inf, -np.inf, np.zeros(988)], "pad_x[10] is inf: every sample must be a finite number (2 are not)"),
        (np.float64(1.0), "shape ()"),
    ],
)
def test_a_channel_that_is_not_a_1d_array_of_finite_numbers_is_refused_by_name(values, says):
    """A 2-D array is not raveled into one long channel, a complex one not cut to its real part,
    a NaN named by its index in the array (not by a line of a temporary file)."""
    with pytest.raises(ValueError) as e:
        stickslip.analyze({"pad_x": values}, rate=1000.0)
    assert str(e.value).startswith("recording: pad_x"), str(e.value)
    assert says in str(e.value), str(e.value)


def test_the_tools_errors_on_arrays_name_the_sample_not_a_temporary_file():
    t = np.r_[np.arange(50) / 1000.0, np.arange(50) / 1000.0]
    with pytest.raises(ValueError) as e:
        stickslip.analyze({"t_s": t, "pad_x": np.zeros(100)})
    assert str(e.value).startswith("recording: sample 50: time 0 s goes back"), str(e.value)
    assert "(sample 49)" in str(e.value) and "stickslip-" not in str(e.value), str(e.value)
    with pytest.raises(ValueError) as e:
        stickslip.analyze({"acc": np.zeros(100)}, rate=1000.0)
    assert str(e.value).startswith("recording: no pad_x"), str(e.value)
    with pytest.raises(ValueError, match="recording: the channels hold no samples"):
        stickslip.analyze({"pad_x": []}, rate=1000.0)
    # a report of arrays names no file, and a gap by its sample index: samples 0..2999 at the
    # rig's rate, then 3000.. after 50 missing samples
    t = np.r_[np.arange(3000), 3050 + np.arange(3000)] / 25600.0
    r = stickslip.analyze({"t_s": t, "pad_x": np.sin(2 * np.pi * 200.0 * t)}, gaps="split")
    assert r["file"] is None
    assert [g["sample"] for g in r["gaps"]] == [3000] and "line" not in r["gaps"][0], r["gaps"]


def test_analyze_equals_the_binary():
    rec = str(RECORDINGS / "rec.csv")
    same(stickslip.analyze(rec), tool_json("analyze", rec))
    uff = str(RECORDINGS / "rec_58b_double.uff")
    same(stickslip.analyze(uff), tool_json("analyze", uff))


def test_analyze_of_arrays_is_that_of_the_same_samples_in_a_file():
    rec = RECORDINGS / "rec.csv"
    data = np.genfromtxt(rec, delimiter=",", names=True)
    names = data.dtype.names
    dt = np.diff(data["t_s"])
    arrays = {n: data[n] for n in names if n != "t_s"}
    from_file = stickslip.analyze(str(rec))
    # with the time axis as an array: the same samples, the same report (but the file's name)
    with_time = stickslip.analyze({"t_s": data["t_s"], **arrays})
    same(without(with_time, "file"), without(from_file, "file"))
    # with a rate: the time axis k / rate, equal to the file's when its first row is at 0
    rate = 1.0 / float(np.mean(dt))
    assert data["t_s"][0] == 0.0 and np.allclose(dt, 1.0 / rate, rtol=1e-12, atol=0)
    with_rate = stickslip.analyze(arrays, rate=rate)
    assert with_rate["channels"].keys() == from_file["channels"].keys()
    for ch in from_file["channels"]:
        a, b = with_rate["channels"][ch], from_file["channels"][ch]
        for k, v in b.items():
            if isinstance(v, float):
                assert a[k] == pytest.approx(v, rel=1e-9, abs=1e-12), (ch, k)


def test_a_map_equals_the_binary_and_gives_arrays():
    sweeps = ["beta=0.02:0.06:10", "mu_s=0.4:0.6:10"]
    out = stickslip.map("push_center", sweeps)
    ref = tool_json("map", "push_center", "--sweep", sweeps[0], "--sweep", sweeps[1])
    same(without(out, "arrays"), ref)
    arrays = out["arrays"]
    assert len(arrays["beta"]) == 100
    assert list(arrays["beta"]) == [c["params"]["beta"] for c in ref["cells"]]
    assert list(arrays["from_rest.regime"]) == [c["from_rest"]["regime"] for c in ref["cells"]]
    got = arrays["from_rest.stick_fraction"]
    want = [c["from_rest"]["stick_fraction"] for c in ref["cells"]]
    assert all((w is None and math.isnan(g)) or g == w for g, w in zip(got, want))


def test_a_small_fit_equals_the_binary():
    args = dict(table="thesis_table_3_1", starts=1, max_iters=20)
    out = stickslip.fit("push_center", ["mu_k"], **args)
    ref = tool_json("fit", "--scene", "push_center", "--free", "mu_k", "--table", "thesis_table_3_1", "--starts", "1", "--max-iters", "20")
    # the wall time is the only field that may differ
    same(without(out, "seconds"), without(ref, "seconds"))


@pytest.mark.parametrize(
    "call, args",
    [
        (lambda: stickslip.simulate("no_such_scene"), ["simulate", "no_such_scene"]),
        (lambda: stickslip.simulate("push_center", dt=0), ["simulate", "push_center", "--dt", "0"]),
        (lambda: stickslip.map("push_center", ["bogus=1:2:3"]), ["map", "push_center", "--sweep", "bogus=1:2:3"]),
        (lambda: stickslip.analyze(str(RECORDINGS / "missing.csv")), ["analyze", str(RECORDINGS / "missing.csv")]),
        (lambda: stickslip.cli("frobnicate"), ["frobnicate"]),
        (lambda: stickslip.sil("push_center", noise=-1), ["sil", "push_center", "--noise", "-1"]),
    ],
)
def test_bad_input_raises_value_error_with_the_binarys_message(call, args):
    p = tool(*args)
    assert p.returncode == 2
    line = p.stderr.strip().splitlines()[-1]
    with pytest.raises(ValueError) as e:
        call()
    assert "error: " + str(e.value) == line


def test_a_bad_scene_key_names_the_field():
    with pytest.raises(ValueError, match=r"field `m` = -1"):
        stickslip.simulate("push_center", m=-1.0)
    with pytest.raises(ValueError, match=r"beta"):
        stickslip.simulate("push_center", beta=0.2)
    with pytest.raises(ValueError, match=r"scene key `beta`"):
        stickslip.simulate("push_center", beta=[1, 2])


def test_bad_arrays_raise():
    with pytest.raises(ValueError, match="rate"):
        stickslip.analyze({"pad_x": np.zeros(100)})
    with pytest.raises(ValueError, match="differ in length"):
        stickslip.analyze({"pad_x": np.zeros(100), "disc_x": np.zeros(99)}, rate=1000.0)
    with pytest.raises(ValueError, match="rate"):
        stickslip.analyze({"pad_x": np.zeros(100)}, rate=-1.0)


def test_channels_name_the_columns():
    rec = RECORDINGS / "rec.csv"
    data = np.genfromtxt(rec, delimiter=",", names=True)
    renamed = {"t_s": data["t_s"], "acc_a": data["pad_x"], "acc_b": data["disc_x"]}
    got = stickslip.analyze(renamed, channels={"pad_x": "acc_a", "disc_x": "acc_b"})
    plain = stickslip.analyze({"t_s": data["t_s"], "pad_x": data["pad_x"], "disc_x": data["disc_x"]})
    same(without(got, "file"), without(plain, "file"))


def _interrupted(call: str, on_interrupt: str, wait_s: float) -> str:
    """Runs `call` in a Python of its own, sends it SIGINT after `wait_s`, and returns what it
    printed: `on_interrupt` runs where KeyboardInterrupt is caught (then exit status 7)."""
    import signal
    import sys
    import time

    code = (
        "import stickslip, sys, time\n"
        "from stickslip import _stickslip\n"
        "print('started', flush=True)\n"
        "try:\n"
        f"    {call}\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        + "".join(f"    {line}\n" for line in on_interrupt.splitlines())
        + "    sys.exit(7)\n"
        "print('finished', flush=True)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    time.sleep(wait_s)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 7, (out, err)
    assert "interrupted" in out
    return out


def test_ctrl_c_interrupts_a_long_call():
    """SIGINT during a 100 x 100 map (about 1.5 s of work) raises KeyboardInterrupt in the caller;
    the timeout only guards against a hang."""
    _interrupted("stickslip.map('push_center', ['beta=0.005:0.075:100', 'mu_s=0.36:0.8:100'])", "", 0.5)


def test_ctrl_c_cancels_the_abandoned_command():
    """After Ctrl-C the abandoned command stops at its next cancellation point instead of
    running on in the background: a 300 x 300 map of the floating rig set (about 13 minutes of
    work on two cores) ends within a cell per thread. The deadline only guards against a hang
    (a map left running would hold it for minutes)."""
    out = _interrupted(
        "stickslip.map('rig_float_push_center', ['beta=0.01:0.07:300', 'v=0.001:0.01:300'], duration=1.0)",
        "t0 = time.monotonic()\n"
        "while _stickslip.running() > 0 and time.monotonic() - t0 < 60.0:\n"
        "    time.sleep(0.01)\n"
        "print('running', _stickslip.running(), 'after', round(time.monotonic() - t0, 3), 's', flush=True)",
        1.0,
    )
    assert "running 0 after" in out, out


def test_the_package_runs_on_python_3_9():
    """pyproject.toml says Python 3.9 or later (abi3-py39): the package's source parses with
    3.9's grammar, and every module it imports at its top level outside a `try` is in 3.9's
    standard library or a declared dependency (tomllib came with 3.11: it falls back to tomli,
    which pyproject.toml requires before 3.11)."""
    import ast

    src = (Path(stickslip.__file__)).read_text()
    tree = ast.parse(src, feature_version=(3, 9))
    stdlib_39 = {"__future__", "csv", "json", "math", "os", "re", "tempfile", "pathlib", "typing", "sys", "io", "shutil", "subprocess", "collections", "itertools", "functools", "dataclasses", "contextlib", "warnings"}
    declared = {"numpy"}
    plain = []
    for node in tree.body:
        if isinstance(node, ast.Import):
            plain += [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            plain.append(node.module.split(".")[0])
    assert set(plain) <= stdlib_39 | declared, sorted(set(plain) - stdlib_39 - declared)
    guarded = [n for n in tree.body if isinstance(n, ast.Try)]
    assert any("tomli" in ast.dump(n) for n in guarded), "tomllib without its fallback"
    pyproject = (REPO / "host" / "python" / "pyproject.toml").read_text()
    assert "tomli>=1.1; python_version < '3.11'" in pyproject


def test_every_scene_key_is_a_keyword_argument_and_changes_the_scene():
    """The module knows the tool's whole key list: model 3's keys and the damping ratios change
    the scene (a ratio replaces the damping the scene writes), as in a scene file."""
    import sys

    by_kw = stickslip.simulate("rig_push_center", zeta_x=0.05, duration=0.2, stats_from=0.1)
    by_file = tool_json("simulate", "rig_push_center", "--duration", "0.2", "--stats-from", "0.1")
    assert by_kw["stick_fraction"] != by_file["stick_fraction"], "zeta_x changed nothing"
    sc = stickslip.scene("rig_push_center")
    del sc["c_x"]
    sc["zeta_x"] = 0.05
    same(by_kw, stickslip.simulate(sc, duration=0.2, stats_from=0.1))
    uni = stickslip.simulate("rig_float_push_center", contact="unilateral", duration=0.2, stats_from=0.1)
    assert "edges" in uni, sorted(uni)


def test_scene_dicts_and_paths_are_checked_not_injected():
    t = np.arange(2000) / 10000.0
    # a key that is not one is refused by name (it is not written into the file as it is)
    with pytest.raises(ValueError, match=re.escape("scene key 'beta = 0.03\\nmu_s': not a scene key")):
        stickslip.simulate({"beta = 0.03\nmu_s": 0.5})
    with pytest.raises(ValueError, match="scene key 'bet': not a scene key"):
        stickslip.simulate({"bet": 0.03})
    # an error about a value names its key, not a temporary file
    with pytest.raises(ValueError) as e:
        stickslip.simulate("push_center", mu_k=0.9)
    assert str(e.value).startswith("scene key `mu_k`: "), str(e.value)
    # text past U+FFFF in a string value
    assert stickslip.simulate("push_center", name="Bremse \U0001F642", duration=0.1, stats_from=0.05)["name"] == "Bremse \U0001F642"
    # bytes and paths name files; `-` is not standard input here; a name the tool cannot take
    assert stickslip.scene(b"push_center")["beta"] == 0.04
    with pytest.raises(ValueError, match="standard input"):
        stickslip.analyze("-")
    with pytest.raises(ValueError, match="not valid UTF-8"):
        stickslip.simulate(Path(os.fsdecode(b"/tmp/lat\xe9in.toml")))
    # arguments of the wrong type, each named
    for call, says in [
        (lambda: stickslip.analyze({"pad_x": np.zeros(100)}, rate="25600"), "rate: a number"),
        (lambda: stickslip.map("push_center", None), "sweeps: "),
        (lambda: stickslip.map("push_center", ["beta=0.02:0.06:2"], sweep=["mu_s=0.4:0.6:2"]), "sweep: give the sweeps once"),
        (lambda: stickslip.fit("push_center", None), "free: "),
        (lambda: stickslip.fit("push_center", [1]), "free: "),
        (lambda: stickslip.fit("push_center", "mu_k", [("push_center", "x.csv")]), "recordings: a dict"),
        (lambda: stickslip.fit("push_center", "mu_k", {"push_center": None}), "recordings['push_center']: a file name"),
    ]:
        with pytest.raises(ValueError, match=re.escape(says)):
            call()
    # the time array by any name the tool takes for it; rate= and a time array refused
    x = np.sin(2 * np.pi * 200 * t)
    same(without(stickslip.analyze({"pad_x": x, "Time": t}), "file"), without(stickslip.analyze({"pad_x": x, "t_s": t}), "file"))
    with pytest.raises(ValueError, match="give rate= or a time array, not both"):
        stickslip.analyze({"pad_x": x, "Time": t}, rate=10000.0)


def test_series_goes_to_the_users_csv_when_given(tmp_path):
    path = tmp_path / "run.csv"
    out = stickslip.simulate("push_center", series=True, csv=path, duration=0.1, stats_from=0.05)
    assert path.exists()
    header = path.read_text().splitlines()[0].split(",")
    assert header == list(out["series"].keys())


def test_flag_values_as_python_writes_them():
    """A bool only for a switch (noise=False would silently be the default noise); arrays and
    tuples as lists; a (lo, hi) pair as LO:HI; from_ for --from; a map's columns keep their
    type (bools, integers)."""
    with pytest.raises(ValueError, match="noise: takes a value, not False"):
        stickslip.sil("push_center", noise=False)
    gain = stickslip.sil("push_center", gain=np.array([0.2, 0.2, 10, 10]), duration=0.3, stats_from=0.1)["gain"]
    assert list(gain.values()) == [0.2, 0.2, 10.0, 10.0]
    p = stickslip.fit("push_center", ["mu_k"], table="thesis_table_3_1", bounds={"mu_k": (0.3, 0.449)}, from_=0.5, profile="mu_k=0.3:0.44:2")
    assert [q["value"] for q in p["points"]] == [0.3, 0.44]
    m = stickslip.map("push_center", ["beta=0.02:0.06:2"], jobs=1)
    assert m["arrays"]["linear.stable"].dtype == bool and m["arrays"]["index"].dtype == np.int64


def test_help_is_text_not_an_error():
    assert stickslip.cli("simulate", "--help") == tool("simulate", "--help").stdout


def test_scenes_lists_every_builtin():
    names = [s["name"] for s in stickslip.scenes()]
    assert names[:6] == ["push_trail", "push_center", "push_lead", "pull_trail", "pull_center", "pull_lead"]
    table = tool("scenes").stdout
    assert all(re.search(rf"^{re.escape(n)}\s", table, re.M) for n in names)
    assert stickslip.scene("push_center")["beta"] == 0.04


def test_the_worked_example_in_docs_python_md_runs(tmp_path, monkeypatch):
    """docs/python.md's example, run as written (matplotlib drawing to a file if it is installed)."""
    text = (REPO / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "docs/python.md has no ```python block"
    monkeypatch.chdir(tmp_path)
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    scope = {"RECORDING": str(RECORDINGS / "rec.csv")}
    for b in blocks:
        exec(compile(b, "docs/python.md", "exec"), scope)
