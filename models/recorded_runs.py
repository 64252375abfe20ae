"""A folder of recorded runs to gate CI on: ``recorded-runs.yaml`` (format ``swarmproof-recorded-runs/1``).

A team that records its swarm (hardware, Gazebo, a C++ port) keeps the logs in a folder with a
manifest; ``swarmproof verify --recorded FOLDER`` judges each log with ``check-run``'s options
and compares the verdicts with the baseline, as it does the bundled algorithms' rows
(docs/recorded-runs.md, docs/ci.md)::

    format: swarmproof-recorded-runs/1
    runs:
      - log: night-run.mcap          # a path relative to the folder (.csv, .mcap, a bag's folder)
        name: night-run              # the rows' subject (default: the log's file name)
        range: 1.2                   # phi (or a lattice target's range)
        target: lattice:square       # optional: formation, deadlock, oscillation
        algorithm: song2016          # optional: its claims, speed and lemma premises
        properties: [connectivity, collision]   # optional: default every one the log can give
        claims: [connectivity]       # optional: which rows decide the gate (default: every row;
                                     #   with algorithm: its claims)
        topics: /robot_{id}/pose     # optional, bags: as check-run's options
        parent_topics: /robot_{id}/parent
        time: header                 # or log
        period: 0.1                  # seconds; default the median sampling interval
        stale: 0.25                  # seconds; default 2.5 periods
        pos_tol: 0.02                # metres of pose error; margins follow
        radius: 0.1
        static_window: 2.0

Every mistake is an :class:`~swarmproof.models.errors.InputFileError` naming the file, line and
field.

Examples
--------
>>> spec = loads_recorded_runs("format: swarmproof-recorded-runs/1\\nruns:\\n  - {log: a.csv, range: 1}\\n", "/tmp/x.yaml")
>>> spec.runs[0].name, spec.runs[0].log, spec.runs[0].options["range"]
('a.csv', '/tmp/a.csv', 1.0)
>>> loads_recorded_runs("format: swarmproof-recorded-runs/1\\nruns:\\n  - {log: a.csv, rnage: 1}\\n", "m.yaml")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: m.yaml:3: field 'runs[0].rnage': key 'rnage' is not known here; did you mean 'range'?; fix: use only ['log', 'name', 'range', 'target', 'algorithm', 'properties', 'claims', 'topics', 'parent_topics', 'state_topics', 'time', 'period', 'stale', 'pos_tol', 'range_margin', 'collision_margin', 'radius', 'static_window', 'v']
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

from .errors import InputFileError, did_you_mean

__all__ = ["RECORDED_RUNS_FORMAT", "MANIFEST", "RecordedRun", "RecordedRuns", "loads_recorded_runs",
           "load_recorded_runs", "bundled_folder"]

RECORDED_RUNS_FORMAT = "swarmproof-recorded-runs/1"
MANIFEST = "recorded-runs.yaml"
_KEYS = ("log", "name", "range", "target", "algorithm", "properties", "claims", "topics", "parent_topics",
         "state_topics", "time",
         "period", "stale", "pos_tol", "range_margin", "collision_margin", "radius", "static_window", "v")
_NUMBERS = {"range": True, "period": True, "stale": True, "pos_tol": False, "range_margin": False,
            "collision_margin": False, "radius": False, "static_window": True, "v": False}   # True: > 0
_STRINGS = ("target", "algorithm", "topics", "parent_topics", "state_topics")


@dataclass(frozen=True)
class RecordedRun:
    """One log of the manifest: its path (absolute), row subject and check-run options."""

    name: str
    log: str
    options: dict = field(default_factory=dict)
    properties: tuple | None = None
    claims: tuple | None = None
    line: int | None = None


@dataclass(frozen=True)
class RecordedRuns:
    source: str
    runs: tuple


def bundled_folder() -> str:
    """The recorded runs swarmproof ships (``models/recorded/``): verify's default ``recorded`` rows."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "recorded")


def loads_recorded_runs(text: str, source: str) -> RecordedRuns:
    """Parse a manifest's text; ``source`` is its path (logs are relative to its folder)."""
    from .campaign_spec import _parse
    from .lattice_io import _Ctx, _field

    data, lines = _parse(text, source)
    ctx = _Ctx(source, lines)

    def fail(path, message, fix):
        raise ctx.error(path, message, fix)

    if not isinstance(data, dict):
        fail((), f"the document={data!r} must be a mapping with format and runs", f"start with format: {RECORDED_RUNS_FORMAT}")
    for k in data:
        if k not in ("format", "runs"):
            fail((k,), f"key {k!r} is not known here{did_you_mean(str(k), ['format', 'runs'])}", "use only format and runs")
    if data.get("format") != RECORDED_RUNS_FORMAT:
        fail(("format",), f"format={data.get('format')!r} must be {RECORDED_RUNS_FORMAT!r}",
             f"write format: {RECORDED_RUNS_FORMAT}")
    runs = data.get("runs")
    if not isinstance(runs, list) or not runs:
        fail(("runs",), f"runs={runs!r} must be a non-empty list of logs", "e.g. runs: [{log: night.mcap, range: 1.2}]")
    folder = os.path.dirname(os.path.abspath(source))
    out, names = [], {}
    for i, d in enumerate(runs):
        p = ("runs", i)
        if not isinstance(d, dict):
            fail(p, f"{_field(p)}={d!r} must be a mapping (log: ..., range: ...)", "e.g. - {log: night.mcap, range: 1.2}")
        for k in d:
            if k not in _KEYS:
                fail(p + (k,), f"key {k!r} is not known here{did_you_mean(str(k), _KEYS)}", f"use only {list(_KEYS)!r}")
        log = d.get("log")
        if not isinstance(log, str) or not log:
            fail(p + ("log",), f"{_field(p + ('log',))}={log!r} must be the log's path", "e.g. log: night-run.mcap")
        name = d.get("name", os.path.basename(os.path.normpath(log)))
        if not isinstance(name, str) or not name:
            fail(p + ("name",), f"{_field(p + ('name',))}={name!r} must be a non-empty string", "e.g. name: night-run")
        if name in names:
            fail(p + ("name",), f"name={name!r} is the name of runs[{names[name]}] too", "give each run its own name")
        names[name] = i
        opts: dict[str, Any] = {}
        for k, positive in _NUMBERS.items():
            if k in d:
                v = d[k]
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0 \
                        or (positive and v == 0):
                    fail(p + (k,), f"{_field(p + (k,))}={v!r} must be a finite {'positive' if positive else 'non-negative'} "
                                   "number", f"e.g. {k}: 0.1")
                opts[k] = float(v)
        for k in _STRINGS:
            if k in d:
                if not isinstance(d[k], str) or not d[k]:
                    fail(p + (k,), f"{_field(p + (k,))}={d[k]!r} must be a non-empty string", "see docs/recorded-runs.md")
                opts[k] = d[k]
        if "time" in d:
            if d["time"] not in ("header", "log"):
                fail(p + ("time",), f"{_field(p + ('time',))}={d['time']!r} must be header or log", "e.g. time: header")
            opts["time"] = d["time"]
        lists = {}
        for k in ("properties", "claims"):
            if k in d:
                v = [d[k]] if isinstance(d[k], str) else d[k]
                if not isinstance(v, list) or not v or not all(isinstance(x, str) and x for x in v):
                    fail(p + (k,), f"{_field(p + (k,))}={d[k]!r} must be a non-empty list of property names",
                         f"e.g. {k}: [connectivity, collision]")
                lists[k] = tuple(v)
        if "range" not in opts and "target" not in opts:
            fail(p, f"{_field(p)} gives no range", "give range: PHI (or a lattice target, whose range is used)")
        out.append(RecordedRun(name, os.path.normpath(os.path.join(folder, log)), opts, lists.get("properties"),
                               lists.get("claims"), ctx.line(p)))
    return RecordedRuns(source, tuple(out))


def load_recorded_runs(folder: str | os.PathLike) -> RecordedRuns:
    """The manifest of ``folder`` (its ``recorded-runs.yaml``), or the manifest file itself."""
    path = os.fspath(folder)
    if not os.path.exists(path):
        raise InputFileError(f"--recorded={path!r} does not exist", file=path,
                             fix=f"give a folder of logs with its {MANIFEST} (docs/recorded-runs.md)")
    if os.path.isdir(path):
        path = os.path.join(path, MANIFEST)
    elif not path.lower().endswith((".yaml", ".yml")):
        raise InputFileError(f"--recorded={path!r} is a file, not a folder of logs or its manifest", file=path,
                             fix=f"give the folder that holds the logs and {MANIFEST} (check-run judges one log)")
    if not os.path.isfile(path):
        raise InputFileError(f"--recorded={os.fspath(folder)!r} has no {MANIFEST}", file=path,
                             fix=f"write {MANIFEST} in the folder (docs/recorded-runs.md): format: "
                                 f"{RECORDED_RUNS_FORMAT} and runs: [{{log: FILE, range: PHI}}]")
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{MANIFEST} cannot be read ({exc})", file=path, fix="check the file") from None
    return loads_recorded_runs(text, path)
