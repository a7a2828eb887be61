"""stickslip from Python: scenes, runs, recordings, maps and fits of the brake-pad stick-slip tool.

Every function here builds the command line the ``stickslip`` tool would take and runs it in
this process, through the tool's own parser and commands (the Rust extension
``stickslip._stickslip``), so a result equals the tool's ``--json`` value for value, and a bad
input raises ``ValueError`` with the tool's one-line message.

Options are keyword arguments named as the tool's flags with ``_`` for ``-``
(``stats_from=0.5`` is ``--stats-from 0.5``): ``True`` gives a bare flag, ``None`` or
``False`` leaves it out, a list or tuple repeats the flag (``sweep=["beta=0.02:0.06:10"]``), a
dict gives ``KEY=VALUE`` pairs (``channel={"pad_x": "acc2"}``). Keyword arguments that are
scene keys (``beta``, ``mu_s``, ``caliper``, ...) change the scene instead:
``simulate("push_center", beta=0.03)`` runs push_center with the load at 30 mm (the changed
scene goes to the tool as a scene file). SI units throughout, as in the tool.

See docs/python.md for installation and a worked example.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import tempfile
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

try:  # Python 3.11 and later
    import tomllib
except ModuleNotFoundError:  # 3.9 and 3.10: the same parser as a package (pyproject.toml)
    import tomli as tomllib

from ._stickslip import read_series_csv as _read_series_csv
from ._stickslip import run as _run
from ._stickslip import scene_keys as _tool_scene_keys
from ._stickslip import switches as _tool_switches
from ._stickslip import version

__all__ = [
    "cli",
    "scenes",
    "scene",
    "simulate",
    "cases",
    "analyze",
    "sil",
    "map",
    "fit",
    "version",
    "DEFAULT_SCENE",
]

#: The scene the tool runs when none is named.
DEFAULT_SCENE = "push_center"

# Flags that belong to the run, not to the scene, although a scene file has keys of the same
# name: given as keyword arguments they go to the tool as flags (as `--dt` on its command line).
_RUN_FLAGS = {"dt", "duration", "stats_from", "precision"}

_scene_keys_cache: set[str] | None = None


def cli(*args: Any) -> str:
    """Runs one ``stickslip`` command line (without the program's name) and returns its stdout.

    ``cli("simulate", "push_center", "--json")`` is ``stickslip simulate push_center --json``.
    Raises ValueError for bad input (the tool's exit code 2), RuntimeError otherwise.
    """
    return _run([_arg(a) for a in args])


def _arg(a: Any, what: str = "argument") -> str:
    """One command-line argument as text: a path (bytes or os.PathLike too) decoded as the file
    system names it, numbers and strings as written; a path the tool cannot take (not UTF-8) is
    a ValueError naming it."""
    if isinstance(a, (bytes, os.PathLike)):
        a = os.fsdecode(a)
    s = str(a)
    try:
        s.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError(f"{what} {s!r}: not valid UTF-8 (a file name the tool cannot take; rename it)") from None
    return s


def _path(a: Any, what: str) -> str:
    """A file argument: str, bytes or os.PathLike, else a ValueError naming `what`."""
    if not isinstance(a, (str, bytes, os.PathLike)):
        raise ValueError(f"{what}: a file name (str or path), not {type(a).__name__}")
    s = _arg(a, what)
    if s == "-":
        raise ValueError(f"{what}: `-` (standard input) is the interpreter's own here; give a file")
    return s


def _scene_keys() -> set[str]:
    """The keys a scene file may hold (the tool's own list)."""
    global _scene_keys_cache
    if _scene_keys_cache is None:
        _scene_keys_cache = set(_tool_scene_keys())
    return _scene_keys_cache


def _toml_value(key: str, v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if math.isnan(f):
            return "nan"
        if math.isinf(f):
            return "inf" if f > 0 else "-inf"
        return repr(f)
    if isinstance(v, str):
        # a TOML basic string: JSON's escapes, which are TOML's, but for characters past U+FFFF
        # (JSON's surrogate pairs are no TOML escape: written as they are, in UTF-8) and DEL
        # (which TOML wants escaped)
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    raise ValueError(f"scene key `{key}`: a number, a bool or a string, not {type(v).__name__}")


def _scene_toml(values: Mapping[str, Any]) -> str:
    keys = _scene_keys()
    for k in values:
        if not isinstance(k, str) or k not in keys:
            raise ValueError(f"scene key {k!r}: not a scene key (the keys: `stickslip scenes show {DEFAULT_SCENE}`, and zeta_x, zeta_phi, zeta_b)")
    return "".join(f"{k} = {_toml_value(k, v)}\n" for k, v in values.items())


class _Call:
    """One command line under construction, with the temporary files it needs."""

    def __init__(self, *head: Any):
        self.args: list[str] = [str(a) for a in head]
        self._dir: tempfile.TemporaryDirectory | None = None
        # the scene file written from a dict or overrides, and its keys by line
        self._scene_file: str | None = None
        self._scene_keys: list[str] = []

    def tmp(self, name: str) -> str:
        if self._dir is None:
            self._dir = tempfile.TemporaryDirectory(prefix="stickslip-")
        return os.path.join(self._dir.name, name)

    def scene(self, scene: Any, overrides: Mapping[str, Any]) -> str:
        """The scene argument: a built-in name or a file as given, or a scene file written from
        a dict and/or scene-key overrides."""
        if isinstance(scene, (str, bytes, os.PathLike)):
            scene = _arg(scene, "scene")
            if scene.startswith("-"):
                # not a flag: a file of that name, as the tool's command line would need it
                scene = os.path.join(".", scene)
        if isinstance(scene, str) and not overrides:
            return scene
        if isinstance(scene, str):
            values = dict(tomllib.loads(cli("scenes", "show", scene)))
        elif isinstance(scene, Mapping):
            values = dict(scene)
        else:
            raise ValueError(f"scene: a built-in name, a scene file or a dict, not {type(scene).__name__}")
        # a damping ratio given replaces the damping written in the scene (`scenes show` writes c_x)
        for zeta, c in (("zeta_x", "c_x"), ("zeta_phi", "c_phi"), ("zeta_b", "c_b")):
            if zeta in overrides and c not in overrides:
                values.pop(c, None)
        values.update(overrides)
        path = self.tmp("scene.toml")
        Path(path).write_text(_scene_toml(values), encoding="utf-8")
        self._scene_file, self._scene_keys = path, list(values)
        return path

    def run(self, args: list[str]) -> str:
        """Runs `args`; an error about the scene file written here names the key, not the file."""
        try:
            return _run(args)
        except ValueError as e:
            message = str(e)
            if self._scene_file is None or self._scene_file not in message:
                raise
            keys = self._scene_keys

            def key_of(m: "re.Match[str]") -> str:
                i = int(m.group(1)) - 1
                return f"scene key `{keys[i]}`: " if 0 <= i < len(keys) else m.group(0)

            message = re.sub(re.escape(self._scene_file) + r": line (\d+)(?:, column \d+)?: ", key_of, message)
            raise ValueError(message.replace(self._scene_file, "the scene (from the dict and keyword arguments)")) from None

    def flags(self, options: Mapping[str, Any]) -> "_Call":
        switches = set(_tool_switches(self.args[:1]) or [])
        for key, v in options.items():
            # a trailing `_` is Python's way round a reserved word (from_ for --from)
            name = key.rstrip("_").replace("_", "-")
            flag = "--" + name
            if isinstance(v, (bool, np.bool_)) and name not in switches:
                # True or False for a flag that takes a value (noise=False) would be ambiguous
                raise ValueError(f"{key}: takes a value, not {bool(v)}")
            if v is None or v is False:
                continue
            if v is True:
                self.args.append(flag)
            elif isinstance(v, Mapping):
                for k, x in v.items():
                    if isinstance(x, (list, tuple, np.ndarray)):
                        x = ":".join(str(e) for e in np.asarray(x).ravel().tolist())  # (lo, hi) as LO:HI
                    self.args += [flag, f"{k}={x}"]
            elif isinstance(v, (list, tuple, np.ndarray)):
                for x in np.asarray(v).ravel().tolist() if isinstance(v, np.ndarray) else v:
                    self.args += [flag, _arg(x, key)]
            else:
                self.args += [flag, _arg(v, key)]
        return self

    def close(self) -> None:
        """Removes the temporary files."""
        if self._dir is not None:
            self._dir.cleanup()
            self._dir = None

    def json(self) -> dict:
        """Runs the command line with ``--json``, then removes its temporary files."""
        try:
            return json.loads(self.run(self.args + ["--json"]))
        finally:
            self.close()


def _split(kwargs: Mapping[str, Any]) -> tuple[dict, dict]:
    """Scene-key overrides apart from flags."""
    keys = _scene_keys()
    scene = {k: v for k, v in kwargs.items() if k in keys and k not in _RUN_FLAGS}
    flags = {k: v for k, v in kwargs.items() if k not in scene}
    return scene, flags


def scenes() -> list[dict]:
    """The built-in scenes: a list of {name, caliper, beta, description}."""
    rows = cli("scenes").splitlines()[1:]
    out = []
    for line in rows:
        if not line.strip():
            break  # the table ends at its first blank line (a hint follows)
        m = re.match(r"^(\S+)\s+(\S+)\s+(\S+)\s+(.*)$", line)
        if m:
            out.append({"name": m[1], "caliper": m[2], "beta": float(m[3]), "description": m[4]})
    return out


def scene(name: str | os.PathLike = DEFAULT_SCENE) -> dict:
    """One scene as a dict of its keys (a built-in name or a scene file, every key written)."""
    name = _path(name, "scene")
    if name.startswith("-"):
        name = os.path.join(".", name)
    return tomllib.loads(cli("scenes", "show", name))


def _read_series(path: str) -> dict[str, np.ndarray]:
    """A series CSV of the tool as arrays: float64 for numbers, str for text (the regime)."""
    header, columns = _read_series_csv(path)
    return {name: col if isinstance(col, np.ndarray) else np.array(col) for name, col in zip(header, columns)}


def _json_and_series(call: _Call, flags: dict, series: bool) -> dict:
    """Runs `call` with `flags` for its JSON; with `series`, also its ``--csv`` as arrays."""
    if not series:
        return call.flags(flags).json()
    # the user's --csv, when given, is the series' file (and stays); else a temporary one
    csv_path = _path(flags["csv"], "csv") if flags.get("csv") is not None else call.tmp("series.csv")
    call.flags(dict(flags, csv=csv_path))
    try:
        out = json.loads(call.run(call.args + ["--json"]))
        out["series"] = _read_series(csv_path)
        return out
    finally:
        call.close()


def simulate(scene: Any = DEFAULT_SCENE, *, series: bool = False, **kwargs: Any) -> dict:
    """Runs one scene: the statistics as ``stickslip simulate SCENE --json`` prints them.

    ``series=True`` adds ``result["series"]``: the sampled run as numpy arrays, one per column
    of the tool's ``--csv`` (t_s, x_m, xdot_m_per_s, phi_rad, phidot_rad_per_s, n_N, f_f_N,
    regime). Keyword arguments: scene keys, and the flags dt, duration, stats_from, precision.
    """
    overrides, flags = _split(kwargs)
    call = _Call("simulate")
    call.args.append(call.scene(scene, overrides))
    return _json_and_series(call, flags, series)


def cases(**kwargs: Any) -> dict:
    """The six cases (or another set: ``set="rig"``), as ``stickslip cases --json``."""
    return _Call("cases").flags(kwargs).json()


def _channel_array(name: str, values: Any) -> np.ndarray:
    """One channel of a recording dict as float64: a 1-D array of finite real numbers, or a
    ValueError naming the channel (and the first sample that is not a number)."""
    a = np.asarray(values)
    if a.dtype == object:
        try:
            a = a.astype(np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"recording: {name}: not numbers (an object array that does not convert to float)") from None
    if a.dtype.kind not in "iuf":
        raise ValueError(f"recording: {name}: dtype {a.dtype} is not a real number type (give floats, m/s^2 or s)")
    if a.ndim != 1:
        raise ValueError(f"recording: {name}: an array of shape {a.shape}; give each channel as a 1-D array of samples")
    a = a.astype(np.float64)
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"recording: {name}[{bad[0]}] is {a[bad[0]]}: every sample must be a finite number ({bad.size} are not)")
    return a


def _write_recording(call: _Call, arrays: Mapping[str, Any], rate: float | None) -> str:
    columns = {k: _channel_array(k, v) for k, v in arrays.items()}
    if not columns:
        raise ValueError("recording: the dict holds no channel")
    n = {len(v) for v in columns.values()}
    if len(n) != 1:
        raise ValueError(f"recording: the channels differ in length ({sorted(n)} samples)")
    (n,) = n
    if n == 0:
        raise ValueError("recording: the channels hold no samples")
    # without rate= the tool finds the time array by its name, as in a file (t_s, Time, time [ms],
    # ...); with rate= the time axis is written here, and a time array too is refused (below)
    if rate is not None:
        if isinstance(rate, (bool, np.bool_)) or not isinstance(rate, (int, float, np.integer, np.floating)):
            raise ValueError(f"rate: a number of samples per second, not {type(rate).__name__} {rate!r}")
        if not (rate > 0 and math.isfinite(rate)):
            raise ValueError(f"rate: {rate} is not a sample rate > 0 [1/s]")
        if "t_s" in columns:
            raise ValueError("recording: give rate= or a time array, not both")
        columns = {"t_s": np.arange(n, dtype=np.float64) / float(rate), **columns}
    path = call.tmp("recording.csv")
    names = list(columns)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for i in range(n):
            w.writerow([repr(float(columns[k][i])) for k in names])
    return path


def analyze(recording: Any, rate: float | None = None, **kwargs: Any) -> dict:
    """Analyses a recording, as ``stickslip analyze FILE --json``.

    ``recording``: a file (CSV, UFF 58/58b, WAV), or a dict of channel name -> array (disc_x,
    pad_x, pad_trail, pad_lead [m/s^2]; other names with ``channels={"pad_x": "name"}``, the
    tool's ``--channel``) with either ``rate`` [samples/s] or a time array ``t_s`` [s].
    """
    call = _Call("analyze")
    arrays_file = None
    if isinstance(recording, Mapping):
        arrays_file = _write_recording(call, recording, rate)
        call.args.append(arrays_file)
    elif rate is not None:
        raise ValueError("rate: only for a recording given as arrays (a file carries its own time axis)")
    else:
        path = _path(recording, "recording")
        call.args.append(os.path.join(".", path) if path.startswith("-") else path)
    if "channels" in kwargs:  # the name; the flag is --channel
        kwargs["channel"] = kwargs.pop("channels")
    scene = kwargs.pop("scene", None)
    if scene is not None:
        kwargs["scene"] = call.scene(scene, {})
    call.flags(kwargs)
    try:
        out = call.json()
        if arrays_file is not None:
            # told of the arrays, not of the temporary file they went through: no file, and a
            # gap at its sample index (the file's data line L is sample L - 2)
            out["file"] = None
            for gap in out.get("gaps", []):
                gap["sample"] = gap.pop("line") - 2
        return out
    except ValueError as e:
        if arrays_file is None:
            raise
        message = str(e)
        if rate is None and "has no column `time" in message:
            raise ValueError(f"recording: give rate= (samples per second) or a time array (t_s, or a name the tool takes for the time: {message.split(': ', 1)[-1]})") from None
        if rate is not None and "both name the time" in message:
            # column 1 is the time axis written from rate=: the other is the user's
            message = "recording: give rate= or a time array, not both (" + message.split(": ", 1)[-1] + ", the first from rate=)"
        raise ValueError(_of_arrays(message, arrays_file)) from None


def _of_arrays(message: str, path: str) -> str:
    """A message about the temporary CSV of a recording given as arrays, told of the arrays:
    its name as "recording", a data line L as sample L - 2 (the header is line 1)."""
    message = message.replace(f"{path}: line 1: ", "recording: ").replace(path, "recording")
    message = re.sub(r"\blines (\d+) to (\d+)", lambda m: f"samples {int(m.group(1)) - 2} to {int(m.group(2)) - 2}", message)
    return re.sub(r"\bline (\d+)", lambda m: f"sample {int(m.group(1)) - 2}" if int(m.group(1)) >= 2 else m.group(0), message)


def sil(scene: Any = DEFAULT_SCENE, *, series: bool = False, **kwargs: Any) -> dict:
    """The virtual rig, as ``stickslip sil SCENE --json``: scene keys and the tool's flags.

    ``series=True`` adds ``result["series"]``: the rig's calibrated channels as numpy arrays,
    one per column of the tool's ``--csv`` (t_s, disc_x_m_s2, pad_x_m_s2, pad_trail_m_s2,
    pad_lead_m_s2; the quiet lead before t = 0 included).
    """
    overrides, flags = _split(kwargs)
    call = _Call("sil")
    call.args.append(call.scene(scene, overrides))
    return _json_and_series(call, flags, series)


def _column(values: Iterable[Any]) -> np.ndarray:
    values = list(values)
    if values and all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=bool)
    if values and all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int64)
    if all(v is None or isinstance(v, (int, float)) for v in values):
        return np.array([np.nan if v is None else float(v) for v in values], dtype=np.float64)
    return np.array(["" if v is None else str(v) for v in values])


def _flatten(prefix: str, value: Any, row: dict) -> None:
    if isinstance(value, Mapping):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else k, v, row)
    elif not isinstance(value, list):
        row[prefix] = value


def map(scene: Any, sweeps: Iterable[str] | str, jobs: int | None = None, **kwargs: Any) -> dict:
    """A regime map, as ``stickslip map SCENE --sweep ... --json``.

    ``sweeps``: one or two ``KEY=FROM:TO:N[:log]``. Adds ``result["arrays"]``: one numpy array
    per cell field, in cell order (``beta``, ``from_rest.regime``, ``linear.max_growth_rate``,
    ...; null is NaN for numbers and "" for text).
    """
    if isinstance(sweeps, str):
        sweeps = [sweeps]
    if not isinstance(sweeps, (list, tuple)) or not all(isinstance(s, str) for s in sweeps):
        raise ValueError(f"sweeps: one or two strings KEY=FROM:TO:N[:log] (a str or a list of them), not {sweeps!r}")
    overrides, flags = _split(kwargs)
    if "sweep" in flags:
        raise ValueError("sweep: give the sweeps once, as the second argument (sweeps=...)")
    call = _Call("map")
    call.args.append(call.scene(scene, overrides))
    call.flags({"sweep": list(sweeps), "jobs": jobs, **flags})
    out = call.json()
    rows = []
    for cell in out.get("cells", []):
        row: dict = {}
        _flatten("", cell.get("params", {}), row)
        _flatten("", {k: v for k, v in cell.items() if k != "params"}, row)
        rows.append(row)
    names: list[str] = []
    for r in rows:
        names += [k for k in r if k not in names]
    out["arrays"] = {k: _column(r.get(k) for r in rows) for k in names}
    return out


def fit(scene: Any, free: Iterable[str] | str, recordings: Mapping[str, Any] | None = None, **kwargs: Any) -> dict:
    """Identification, as ``stickslip fit --scene SCENE --free KEYS [CASE=FILE...] --json``.

    ``recordings``: case name -> recording file (``{"oracle": "rec.csv"}``); or give
    ``table="table.csv"``. The other options are the tool's flags (starts, bounds, cost, ...).
    """
    if isinstance(free, (list, tuple)) and all(isinstance(k, str) for k in free):
        free = ",".join(free)
    if not isinstance(free, str) or not free:
        raise ValueError(f"free: the keys to fit, a comma-separated str or a list of str, not {free!r}")
    if recordings is not None and not isinstance(recordings, Mapping):
        raise ValueError(f"recordings: a dict of case name -> recording file, not {type(recordings).__name__}")
    overrides, flags = _split(kwargs)
    call = _Call("fit")
    call.flags({"scene": call.scene(scene, overrides), "free": free, **flags})
    for case, path in (recordings or {}).items():
        call.args.append(f"{case}={_path(path, f'recordings[{case!r}]')}")
    return call.json()
