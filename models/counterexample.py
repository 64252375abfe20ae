"""The ``swarmproof-counterexample/1`` file: a scenario that violates a property.

Fields (DESIGN.md section 2): ``algorithm, params, lattice,
initial{robots[{id, pose[x, y, theta]}]}, schedule, faults, seed, property,
violation{step, message}, version``, plus ``format`` and a few more fields
the replay needs (``max_steps``, ``allow_violations``,
``broken_assumptions``, ``options``), ``reading`` (the reading version of the
algorithm that made it: its class's ``reading``, bumped whenever its behaviour changes on
purpose; a file without the field was written before readings were versioned and is reading
``"1"``, :data:`~swarmproof.models.versions.DEFAULT_READING`; replay refuses a file of
another reading than the algorithm's, exit 2) and ``made_by`` (the swarmproof, Python and
numpy versions that wrote it; replay names it when no registered reading reproduces a file).  Angles in ``initial`` are radians
(``angle_unit: "rad"``) so a replay is bit-exact.  A counterexample found by exhaustive checking
(issue 33) adds ``choices``: the bound it was found within (``steps``, ``deviations``, ``kinds``,
``max_delay``, ``max_crashes``), ``choice_points`` (how many decisions the run made) and
``deviations`` (each non-default decision: its ``index`` among the run's decisions, ``kind``,
``at`` and ``option``); replay makes the same decisions again.

Examples
--------
>>> c = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.785, "dt": 1.0},
...                    lattice="square", robots=[(1, (0.0, 0.0, 0.0)), (0, (0.5, 0.0, 1.5707963267948966))],
...                    seed=3, property="connectivity", violation={"step": 17, "message": "split"},
...                    max_steps=200)
>>> print("\\n".join(c.format_steps()))
counterexample: song2014 violates connectivity
lattice square, range 1.2, v=0.05, omega=0.785, dt=1
1. place robot 1 at (0, 0) heading 0 deg
2. place robot 0 at (0.5, 0) heading 90 deg
3. run song2014 with seed 3 for at most 200 steps (synchronous, no faults)
4. at step 17: split
>>> Counterexample.from_dict(c.as_dict()) == c
True
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Mapping

from .errors import InputFileError
from .fileio import atomic_write_text, dumps_json

__all__ = ["COUNTEREXAMPLE_FORMAT", "COUNTEREXAMPLE_VERSION", "Counterexample"]

COUNTEREXAMPLE_FORMAT = "swarmproof-counterexample/1"
COUNTEREXAMPLE_VERSION = 1


def _g(x: float, digits: int = 6) -> str:
    """Short, exact-enough number text for people (``%.6g``, no ``-0``)."""
    s = f"{float(x):.{digits}g}"
    return "0" if s == "-0" else s


def _position_digits(points, phi: float) -> int:
    """The fewest significant digits (6 to 17) at which the printed positions keep every pair's
    neighbor relation (distance < ``phi``, 001 Sec. III) of the exact ones.

    The explorer draws starting links just short of phi; at 6 digits such a link prints as
    exactly phi, and a person who rebuilt the start from the printed steps would get robots
    that are not neighbors.

    >>> _position_digits([(0.0, 0.0), (1.0, 0.0)], 1.2)
    6
    >>> _position_digits([(0.0, 0.0), (1.1999999988, 0.0)], 1.2)
    10
    """
    def links(pts):
        return [math.hypot(px - qx, py - qy) < phi
                for i, (px, py) in enumerate(pts) for (qx, qy) in pts[i + 1:]]
    exact = links(points)
    for d in range(6, 17):
        shown = [(float(f"{x:.{d}g}"), float(f"{y:.{d}g}")) for x, y in points]
        if links(shown) == exact:
            return d
    return 17


def _fault_phrases(faults: Mapping) -> list[str]:
    """The faults of a ``FaultModel.describe()`` document in words (for :meth:`Counterexample.format_steps`).

    >>> _fault_phrases({"crashes": {"3": [1]}, "additions": {"16": [[5, [0.5, 1.25, 0.0]]]},
    ...                 "noise_std": [0.0125, 0.0], "drop_message": {"kind": "drop_set", "drops": [[1, 0, 2]]}})
    ['robot 1 crashes at step 3', 'robot 5 joins at step 16 at (0.5, 1.25) heading 0 deg', '1 lost delivery', 'sensing noise sd 0.0125 on x, y and 0 rad on theta']
    """
    out = []
    for step, ids in sorted((faults.get("crashes") or {}).items(), key=lambda kv: int(kv[0])):
        out += [f"robot {int(i)} crashes at step {int(step)}" for i in ids]
    for step, rows in sorted((faults.get("additions") or {}).items(), key=lambda kv: int(kv[0])):
        out += [f"robot {int(i)} joins at step {int(step)} at ({_g(p[0])}, {_g(p[1])}) heading "
                f"{_g(math.degrees(p[2]))} deg" for i, p in rows]
    drops = faults.get("drop_message")
    if drops:
        k = len(drops.get("drops", ())) if isinstance(drops, Mapping) else 0
        out.append(f"{k} lost deliver{'y' if k == 1 else 'ies'}" if k else "drop_message")
    if faults.get("sensing_noise"):
        out.append("sensing_noise")
    if faults.get("message_loss"):
        out.append(f"message loss {_g(faults['message_loss'])}")
    noise = faults.get("noise_std") or []
    if any(noise):
        out.append(f"sensing noise sd {_g(noise[0])} on x, y and {_g(noise[1])} rad on theta")
    if faults.get("message_delay"):
        out.append(f"messages up to {int(faults['message_delay'])} step(s) late"
                   + (", in any order" if faults.get("message_reorder") else ""))
    return out


def _check_clocks(clocks, err) -> None:
    """``clocks`` must look like ``trace.meta["clocks"]``: lists ``phase`` and ``rate`` of one
    length (finite numbers, rates > 0) and a number ``broadcast_every`` > 0."""
    def num(v, positive=False):
        return (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                and (v > 0 or not positive))

    fix = "write the run's trace.meta['clocks'], or drop the field (the replay draws the clocks from the seed)"
    if not isinstance(clocks, Mapping):
        raise err("clocks", f"clocks={clocks!r} must be a JSON object or null", fix=fix)
    for key, positive in (("phase", False), ("rate", True)):
        vals = clocks.get(key)
        if not isinstance(vals, list) or not all(num(v, positive) for v in vals):
            raise err(f"clocks.{key}", f"clocks.{key}={vals!r} must be a list of finite numbers"
                      + (" > 0" if positive else ""), fix=fix)
    if len(clocks["phase"]) != len(clocks["rate"]):
        raise err("clocks.rate", f"clocks has {len(clocks['phase'])} phases and {len(clocks['rate'])} rates",
                  fix=fix)
    if not num(clocks.get("broadcast_every"), True):
        raise err("clocks.broadcast_every",
                  f"clocks.broadcast_every={clocks.get('broadcast_every')!r} must be a finite number > 0", fix=fix)


def _clock_phrase(clocks, slot: int) -> str:
    """``", clock phase P rate R"`` of robot slot ``slot`` (nothing when the clocks are synchronous
    or unknown).

    >>> _clock_phrase({"phase": [0.25], "rate": [0.5], "broadcast_every": 2.0}, 0)
    ', clock phase 0.25 rate 0.5'
    """
    if clocks is None or slot >= len(clocks.get("phase") or ()):
        return ""
    return f", clock phase {_g(clocks['phase'][slot])} rate {_g(clocks['rate'][slot])}"


def _clocks_text(clocks, extra: Mapping, placed: int) -> str:
    """The activation of a run with asynchronous clocks, in words: the engine's rule
    (docs/engine.md), the rate range the parameters draw from (``clock_rate_min`` /
    ``clock_rate_max``, default 1) and the clocks of robots that join later.

    >>> _clocks_text({"phase": [0.1, 0.7], "rate": [0.5, 0.9], "broadcast_every": 2.0},
    ...              {"clock_rate_min": 0.5, "clock_rate_max": 1.0}, 2)
    'asynchronous clocks: robot clock = phase + rate * step, it decides when its clock passes an integer and broadcasts its last decision when it passes k * 2 + 1/2; phases drawn in [0, 1), rates drawn in [0.5, 1]'
    """
    def show(v) -> str:
        return _g(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else repr(v)

    lo = extra.get("clock_rate_min", 1.0)
    hi = extra.get("clock_rate_max", lo)
    text = (f"asynchronous clocks: robot clock = phase + rate * step, it decides when its clock passes an "
            f"integer and broadcasts its last decision when it passes k * {_g(clocks['broadcast_every'])} + 1/2; "
            f"phases drawn in [0, 1), rates drawn in [{show(lo)}, {show(hi)}]")
    later = [f"{_g(ph)} and {_g(r)}" for ph, r in zip(clocks["phase"][placed:], clocks["rate"][placed:])]
    if later:
        text += "; robots joining later, in order: phase and rate " + ", ".join(later)
    return text


@dataclass
class Counterexample:
    """One counterexample (see the module docstring for the file layout).

    Attributes
    ----------
    algorithm : str
    params : dict
        ``range, v, omega, dt`` and optionally ``extra``.
    lattice : str or None
        A bundled lattice name (or a path); None when ``target`` is of another kind.
    robots : list of (id, (x, y, theta radians))
    seed : int
        The engine's seed.
    property : str
    violation : dict
        ``{"step": int | None, "message": str}``.
    schedule : dict or None
        The fault model's schedule (``TableSchedule.as_dict()``) or None (synchronous).
    faults : dict or None
        ``FaultModel.describe()`` or None.
    max_steps : int or None
    allow_violations : bool
    broken_assumptions : list of str
    options : dict
        Property options (e.g. ``radius``).
    target : dict or None
        The target's ``describe()`` (:mod:`swarmproof.models.targets`) when it is not
        simply the bundled lattice ``lattice`` names; written only then, so files of
        bundled lattices are as before and every older file still loads.
    clocks : dict or None
        The run's asynchronous clocks as the trace records them (``trace.meta["clocks"]``:
        ``phase`` and ``rate`` per robot slot, ``broadcast_every``), None for synchronous
        steps; written only when given.  A replay draws them again from the seed; they are
        here so :meth:`format_steps` can say what the run was.
    reading : str or None
        The reading version of the algorithm that made it (``Algorithm.reading``); None when
        the file records none (written before readings were versioned:
        :attr:`recorded_reading` is then ``"1"``).
    made_by : dict or None
        The file's ``made_by`` as read (the versions that wrote it); not compared, and
        :meth:`as_dict` writes this process's versions.
    choices : dict or None
        An exhaustively found counterexample's decisions (module docstring); written only when given.
    """

    algorithm: str
    params: dict
    lattice: str
    robots: list
    seed: int
    property: str
    violation: dict
    schedule: dict | None = None
    faults: dict | None = None
    max_steps: int | None = None
    allow_violations: bool = False
    broken_assumptions: list = field(default_factory=list)
    options: dict = field(default_factory=dict)
    target: dict | None = None
    clocks: dict | None = None
    reading: str | None = None
    made_by: dict | None = field(default=None, compare=False)
    choices: dict | None = None

    @property
    def recorded_reading(self) -> str:
        """The reading the file was made with: ``reading``, or ``"1"`` when it records none."""
        from .versions import DEFAULT_READING

        return DEFAULT_READING if self.reading is None else self.reading

    def as_dict(self) -> dict:
        doc = {
            "format": COUNTEREXAMPLE_FORMAT,
            "version": COUNTEREXAMPLE_VERSION,
            "algorithm": self.algorithm,
            **({} if self.reading is None else {"reading": str(self.reading)}),
            "params": dict(self.params),
            "lattice": self.lattice,
            "initial": {"angle_unit": "rad",
                        "robots": [{"id": int(i), "pose": [float(v) for v in p]} for i, p in self.robots]},
            "schedule": self.schedule,
            "faults": self.faults,
            "seed": int(self.seed),
            "max_steps": None if self.max_steps is None else int(self.max_steps),
            "allow_violations": bool(self.allow_violations),
            "broken_assumptions": list(self.broken_assumptions),
            "property": self.property,
            "options": dict(self.options),
            "violation": {"step": self.violation.get("step"), "message": str(self.violation.get("message", ""))},
        }
        if self.target is not None:
            doc["target"] = dict(self.target)
        if self.clocks is not None:
            doc["clocks"] = dict(self.clocks)
        if self.choices is not None:
            doc["choices"] = dict(self.choices)
        # DESIGN.md section 5: counterexample files record what made them (read by nothing;
        # a replay that no longer reproduces can be traced to a changed library)
        from swarmproof.models.versions import tool_versions

        doc["made_by"] = tool_versions()
        return doc

    def to_json(self) -> str:
        return dumps_json(self.as_dict())

    def save(self, path: str | os.PathLike) -> str:
        """Write atomically; returns the path written."""
        return atomic_write_text(path, self.to_json())

    @classmethod
    def from_dict(cls, d: Any, *, file: str | None = None) -> "Counterexample":
        """Read and check a decoded counterexample document.

        Raises
        ------
        InputFileError
            Wrong format or version, a missing field or a field of the wrong type.
        """
        def err(fld, msg, fix=None):
            return InputFileError(msg, file=file, field=fld, fix=fix)

        if not isinstance(d, Mapping):
            raise err(None, f"document={type(d).__name__!r} must be a JSON object",
                      fix=f"write a {COUNTEREXAMPLE_FORMAT} file (swarmproof explore --out DIR)")
        if d.get("format") != COUNTEREXAMPLE_FORMAT:
            raise err("format", f"format={d.get('format')!r} must be {COUNTEREXAMPLE_FORMAT!r}",
                      fix="give a file written by swarmproof explore --out DIR")
        if d.get("version") != COUNTEREXAMPLE_VERSION:
            raise err("version", f"version={d.get('version')!r} is not supported",
                      fix=f"this swarmproof reads version {COUNTEREXAMPLE_VERSION}")
        target = d.get("target")
        if target is not None and not (isinstance(target, Mapping) and isinstance(target.get("kind"), str)
                                       and isinstance(target.get("name"), str)):
            raise err("target", f"target={target!r} must be a JSON object with string 'kind' and 'name'",
                      fix="write it as the target's describe() gives it, or drop it and name a lattice")
        for key, typ in (("algorithm", str), ("lattice", str), ("property", str), ("params", Mapping),
                         ("initial", Mapping), ("violation", Mapping)):
            if key == "lattice" and target is not None and d.get(key) is None:
                continue
            if key not in d:
                raise err(key, f"field {key!r} is missing")
            if not isinstance(d[key], typ):
                raise err(key, f"{key}={d[key]!r} must be a {'JSON object' if typ is Mapping else 'string'}")
        seed = d.get("seed")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise err("seed", f"seed={seed!r} must be an integer >= 0")
        params = dict(d["params"])
        for key in ("range", "v", "omega", "dt"):
            val = params.get(key)
            if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val):
                raise err(f"params.{key}", f"params.{key}={val!r} must be a finite number")
        init = d["initial"]
        unit = init.get("angle_unit", "rad")
        if unit not in ("rad", "deg"):
            raise err("initial.angle_unit", f"initial.angle_unit={unit!r} must be 'rad' or 'deg'")
        rows = init.get("robots")
        if not isinstance(rows, list) or not rows:
            raise err("initial.robots", f"initial.robots={rows!r} must be a non-empty list")
        robots = []
        for k, row in enumerate(rows):
            fld = f"initial.robots[{k}]"
            if not isinstance(row, Mapping) or "id" not in row or "pose" not in row:
                raise err(fld, f"{fld}={row!r} must be an object with 'id' and 'pose'")
            rid, pose = row["id"], row["pose"]
            if isinstance(rid, bool) or not isinstance(rid, int):
                raise err(f"{fld}.id", f"{fld}.id={rid!r} must be an integer")
            if (not isinstance(pose, list) or len(pose) != 3
                    or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                               for v in pose)):
                raise err(f"{fld}.pose", f"{fld}.pose={pose!r} must be [x, y, theta] (finite numbers)")
            th = math.radians(pose[2]) if unit == "deg" else float(pose[2])
            robots.append((rid, (float(pose[0]), float(pose[1]), th)))
        viol = d["violation"]
        step = viol.get("step")
        if step is not None and (isinstance(step, bool) or not isinstance(step, int)):
            raise err("violation.step", f"violation.step={step!r} must be an integer or null")
        max_steps = d.get("max_steps")
        if max_steps is not None and (isinstance(max_steps, bool) or not isinstance(max_steps, int)
                                      or max_steps < 0):
            raise err("max_steps", f"max_steps={max_steps!r} must be an integer >= 0 or null")
        for key in ("schedule", "faults"):
            if d.get(key) is not None and not isinstance(d.get(key), Mapping):
                raise err(key, f"{key}={d.get(key)!r} must be a JSON object or null")
        clocks = d.get("clocks")
        if clocks is not None:
            _check_clocks(clocks, err)
        reading = d.get("reading")
        if reading is not None and not (isinstance(reading, str) and reading.strip()):
            raise err("reading", f"reading={reading!r} must be a non-empty string (the algorithm's reading version)",
                      fix="write the algorithm's reading as its class declares it (e.g. \"1\"), or drop the "
                          "field: a file without one is reading \"1\"")
        choices = d.get("choices")
        if choices is not None:
            _check_choices(choices, err)
        made_by = d.get("made_by")
        return cls(algorithm=d["algorithm"], params=params, lattice=d.get("lattice"), robots=robots,
                   seed=seed, property=d["property"],
                   violation={"step": step, "message": str(viol.get("message", ""))},
                   schedule=d.get("schedule"), faults=d.get("faults"), max_steps=max_steps,
                   allow_violations=bool(d.get("allow_violations", False)),
                   broken_assumptions=list(d.get("broken_assumptions") or []),
                   options=dict(d.get("options") or {}),
                   target=None if target is None else dict(target),
                   clocks=None if clocks is None else dict(clocks), reading=reading,
                   made_by=dict(made_by) if isinstance(made_by, Mapping) else None,
                   choices=None if choices is None else dict(choices))

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Counterexample":
        """Read a counterexample file.

        Raises
        ------
        InputFileError
            The file is missing, not JSON (with the line), or malformed.
        """
        name = os.fspath(path)
        try:
            with open(name, encoding="utf-8") as fh:
                text = fh.read()
        except OSError as exc:
            raise InputFileError(f"cannot read file={name!r} ({exc.strerror})", file=name,
                                 fix="give the path of a counterexample file") from None
        except UnicodeDecodeError as exc:
            raise InputFileError(f"the file is not UTF-8 text (byte {exc.start}: {exc.reason})", file=name,
                                 fix=f"give a {COUNTEREXAMPLE_FORMAT} JSON file") from None
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputFileError(f"not JSON ({exc.msg})", file=name, line=exc.lineno,
                                 fix=f"give a {COUNTEREXAMPLE_FORMAT} JSON file") from None
        return cls.from_dict(doc, file=name)

    def target_label(self) -> str:
        """``lattice NAME``, or ``KIND NAME`` of another target."""
        if self.target is not None:
            return f"{self.target['kind']} {self.target['name']}"
        return f"lattice {self.lattice}"

    def format_steps(self) -> list[str]:
        """The counterexample as steps a person can follow (one string per line)."""
        p = self.params
        lines = [f"counterexample: {self.algorithm} violates {self.property}",
                 f"{self.target_label()}, range {_g(p['range'])}, v={_g(p['v'])}, "
                 f"omega={_g(p['omega'])}, dt={_g(p['dt'])}"]
        k = 0
        digits = _position_digits([(float(x), float(y)) for _, (x, y, _) in self.robots], float(p["range"]))
        clocks = self.clocks
        for k, (rid, (x, y, th)) in enumerate(self.robots, start=1):
            lines.append(f"{k}. place robot {rid} at ({_g(x, digits)}, {_g(y, digits)}) "
                         f"heading {_g(math.degrees(th))} deg" + _clock_phrase(clocks, k - 1))
        extra = dict(p.get("extra") or {})
        sched = "synchronous" if not self.schedule else "asynchronous schedule from the file"
        if clocks is not None:
            sched = _clocks_text(clocks, extra, len(self.robots)) + (
                "; a schedule from the file" if self.schedule else "")
        if self.choices is not None:      # an exhaustive search's decisions, not the plain schedule
            sched = "decisions chosen as below" if clocks is None else sched + "; decisions chosen as below"
        active = _fault_phrases(self.faults or {})
        fault_text = "no faults" if not active else "faults: " + "; ".join(active)
        cap = "" if self.max_steps is None else f" for at most {self.max_steps} steps"
        with_params = ("" if not extra else
                       " with params " + ", ".join(f"{key}={extra[key]!r}" for key in sorted(extra)))
        lines.append(f"{k + 1}. run {self.algorithm} with seed {self.seed}{cap}{with_params} ({sched}, {fault_text})")
        if self.broken_assumptions:
            lines[-1] += f" -- broken assumptions: {', '.join(self.broken_assumptions)}"
        if self.choices is not None:
            devs = list(self.choices.get("deviations") or [])
            lines[-1] += (f"; every decision of kinds {', '.join(self.choices.get('kinds') or [])} the default "
                          f"except {len(devs)}:" if devs else "; every decision the default")
            lines += [f"   - {_choice_phrase(d)}" for d in devs]
        step = self.violation.get("step")
        where = f"at step {step}" if step is not None else "at the end"
        lines.append(f"{k + 2}. {where}: {self.violation.get('message', '')}")
        return lines


def _choice_phrase(d: Mapping) -> str:
    """One recorded deviation as a sentence.

    >>> _choice_phrase({"index": 4, "kind": "activate", "at": [2], "option": [1, 3]})
    'step 2: only robots 1, 3 act (decision 4)'
    >>> _choice_phrase({"index": 9, "kind": "delay", "at": [3, 1, 2], "option": 2})
    'step 3: the message from robot 1 to robot 2 arrives 2 step(s) late (decision 9)'
    >>> _choice_phrase({"index": 1, "kind": "clock_phase", "at": [1], "option": 0.75})
    "before step 0: robot 1's clock phase is 0.75 (decision 1)"
    """
    kind, at, opt = d.get("kind"), list(d.get("at") or []), d.get("option")
    if kind == "clock_phase":       # at = (robot,): chosen before the first step, not in a step
        who = f"robot {at[0]}'s" if at else "a robot's"
        phase = f"{opt:g}" if isinstance(opt, (int, float)) else repr(opt)
        return f"before step 0: {who} clock phase is {phase} (decision {d.get('index')})"
    step = f"step {at[0]}: " if at else ""
    link = f"the message from robot {at[1]} to robot {at[2]}" if len(at) >= 3 else "a message"
    text = {
        "activate": lambda: "only robot" + ("s " if len(opt or []) != 1 else " ") + ", ".join(map(str, opt or [])) + " act"
                            + ("s" if len(opt or []) == 1 else ""),
        "loss": lambda: f"{link} is lost",
        "delay": lambda: f"{link} arrives {opt} step(s) late",
        "duplicate": lambda: f"{link} arrives {opt} times",
        "reorder": lambda: f"robot {at[1] if len(at) > 1 else '?'} reads its messages in the order {opt}",
        "crash": lambda: f"robot {opt} crashes",
    }.get(kind, lambda: f"{kind} = {opt!r}")()
    return f"{step}{text} (decision {d.get('index')})"


def _check_choices(choices, err) -> None:
    """``choices`` of an exhaustively found counterexample: its shape (the kinds' names are the
    engine's to check, at replay)."""
    if not isinstance(choices, Mapping):
        raise err("choices", f"choices={choices!r} must be a JSON object")
    kinds = choices.get("kinds")
    if not (isinstance(kinds, list) and kinds and all(isinstance(k, str) for k in kinds)):
        raise err("choices.kinds", f"choices.kinds={kinds!r} must be a non-empty list of choice kinds")
    for key in ("max_delay", "max_crashes"):
        v = choices.get(key, 0)
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise err(f"choices.{key}", f"choices.{key}={v!r} must be an integer >= 0")
    devs = choices.get("deviations")
    if not isinstance(devs, list):
        raise err("choices.deviations", f"choices.deviations={devs!r} must be a list")
    last = -1
    for j, dv in enumerate(devs):
        fld = f"choices.deviations[{j}]"
        if not isinstance(dv, Mapping) or not {"index", "kind", "option"} <= set(dv):
            raise err(fld, f"{fld}={dv!r} must be an object with index, kind and option")
        i = dv["index"]
        if isinstance(i, bool) or not isinstance(i, int) or i <= last:
            raise err(f"{fld}.index", f"{fld}.index={i!r} must be an integer above the previous deviation's",
                      fix="list the deviations in the order the run made them")
        last = i
