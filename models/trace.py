"""Initial configurations and simulation traces: data classes and file formats.

* :class:`InitialConfiguration`: robot IDs and poses in the (engine-only)
  global frame.
* :class:`Event`: something a checker may need (a clamped command, a broken
  assumption, a crash, an added robot, a dropped message ...).
* :class:`Trace`: everything a run produced: poses at every step, the
  controllers' states at every step, events, optionally the broadcasts.

File format ``swarmproof-trace/1`` (JSON, or NPZ for large traces)::

    {"format": "swarmproof-trace/1",
     "meta": {...},                     # algorithm, params, lattice, seed, status ...
     "ids": [3, 0, 1, 2],               # robot IDs, column order of poses
     "poses": [[[x, y, theta], ...], ...],   # (T+1) x n x 3, radians
     "present": [[true, ...], ...] | null,   # (T+1) x n, null = all present
     "states": [[s_0, ..., s_n-1], ...],     # (T+1) x n, JSON forms of Controller.state()
     "events": [{"step": 3, "kind": "clamp", "robots": [0, 2], "detail": {}}, ...],
     "messages": [{"<id>": message, ...}, ...] | null}   # T entries when recorded

``states[0]`` are the controllers' states before the first step and
``states[t]`` (t >= 1) their states right after step ``t - 1`` decided;
``poses[t]`` are the poses after ``t`` steps; ``messages[t]`` are the
broadcasts made in step ``t`` (heard in step ``t + 1``).

JSON cannot tell tuples from lists: :func:`to_jsonable` writes tuples and
lists as JSON arrays and frozen dataclasses as objects with a ``"__type__"``
key; :func:`Trace.load` turns arrays back into tuples (so states stay
hashable and compare equal to what a controller returns as tuples).
Writing is atomic (:mod:`swarmproof.models.fileio`); the same trace always
gives the same bytes.

Examples
--------
>>> import numpy as np
>>> t = Trace(ids=np.array([1, 0]), poses=np.zeros((2, 2, 3)),
...           states=[((("parent", None),), (("parent", 1),))] * 2,
...           events=[Event(0, "clamp", (1,))], meta={"seed": 0})
>>> t.steps, t.n
(1, 2)
>>> Trace.from_json(t.to_json()).to_json() == t.to_json()
True
>>> Trace.from_json(t.to_json()).states[1][1]
(('parent', 1),)
"""

from __future__ import annotations

import dataclasses
import io
import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from .errors import InputFileError, UsageError
from .fileio import atomic_write_bytes

__all__ = [
    "TRACE_FORMAT", "InitialConfiguration", "Event", "Trace", "to_jsonable", "from_jsonable", "dumps_trace_json",
]

TRACE_FORMAT = "swarmproof-trace/1"


# ----------------------------------------------------------------------------
# JSON forms of controller states and messages
# ----------------------------------------------------------------------------

def to_jsonable(obj: Any) -> Any:
    """A deterministic JSON form of a state or message.

    Tuples and lists become lists, mappings become objects with string keys
    (sorted when written), frozen dataclasses become objects with a
    ``"__type__"`` key, numpy scalars and arrays become numbers and lists,
    sets and frozensets become sorted lists.  Non-finite floats become the
    strings ``"inf"``, ``"-inf"``, ``"nan"`` (JSON has none).  Anything else
    becomes its ``repr`` (deterministic for well-behaved objects).

    >>> to_jsonable((("parent", 3), ("path", (1, 2)), ("d", float("inf"))))
    [['parent', 3], ['path', [1, 2]], ['d', 'inf']]
    """
    # Fast paths for the exact built-in types states are made of (a pure speed-up: the same
    # values as the general branches below, which subclasses and numpy types still take).
    t = type(obj)
    if t is tuple or t is list:
        return [to_jsonable(x) for x in obj]
    if t is str or t is int or t is bool or obj is None:
        return obj
    if t is float:
        if math.isfinite(obj):
            return obj
        return "nan" if math.isnan(obj) else ("inf" if obj > 0 else "-inf")
    if t is dict:
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        if math.isfinite(x):
            return x
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (tuple, list)):
        return [to_jsonable(x) for x in obj]
    if isinstance(obj, (set, frozenset)):
        items = [to_jsonable(x) for x in obj]
        return sorted(items, key=lambda v: json.dumps(v, sort_keys=True))
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        out = {"__type__": type(obj).__name__}
        for f in dataclasses.fields(obj):
            out[f.name] = to_jsonable(getattr(obj, f.name))
        return out
    return repr(obj)


def from_jsonable(obj: Any) -> Any:
    """Inverse of :func:`to_jsonable` up to types: JSON arrays become tuples,
    objects become (insertion-ordered) dicts of converted values.

    >>> from_jsonable([["parent", 3], ["path", [1, 2]]])
    (('parent', 3), ('path', (1, 2)))
    """
    if isinstance(obj, list):
        return tuple(from_jsonable(x) for x in obj)
    if isinstance(obj, dict):
        return {k: from_jsonable(v) for k, v in obj.items()}
    return obj


def dumps_trace_json(doc: Mapping) -> str:
    """The text of a trace's JSON object: deterministic (sorted keys, no NaN), one top-level key
    a line and one list element a line, each written compactly.

    An indented layout put every number of every state on a line of its own, nested five deep:
    an 8-robot wang2020 run of 424 steps was 5.1 MB, 4.4 times the same values written compactly
    (docs/performance.md, "Trace size").  A frame a line keeps the file readable line by line
    (``grep``, ``diff``, ``sed -n``) at about the compact size.

    >>> print(dumps_trace_json({"ids": [1, 0], "meta": {"seed": 0}, "states": [[["d", 1.5]], []]}), end="")
    {
    "ids": [
    1,
    0
    ],
    "meta": {"seed":0},
    "states": [
    [["d",1.5]],
    []
    ]
    }
    """
    def compact(value) -> str:
        return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=False)

    lines = []
    for key in sorted(doc):
        value = doc[key]
        body = ("[\n" + ",\n".join(compact(x) for x in value) + "\n]") if isinstance(value, list) and value \
            else compact(value)
        lines.append(f"{json.dumps(key)}: {body}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


# ----------------------------------------------------------------------------
# Initial configuration
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class InitialConfiguration:
    """Robot IDs and poses ``[x, y, theta]`` (radians) in the global frame.

    Parameters
    ----------
    ids : array_like of int, shape (n,)
    poses : array_like of float, shape (n, 3)

    Raises
    ------
    UsageError
        If shapes disagree, an ID is not an integer, or a pose is not finite.
        (Duplicate IDs are *allowed* here: they break an assumption the engine
        checks, and the explorer may want them on purpose.)

    Examples
    --------
    >>> c = InitialConfiguration([2, 1], [[0, 0, 0], [1, 0, 3.14]])
    >>> c.n, c.ids.tolist()
    (2, [2, 1])
    >>> InitialConfiguration([1], [[0, float("nan"), 0]])
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: poses[0]=[0.0, nan, 0.0] must be finite; fix: give finite x, y, theta for every robot
    """

    ids: np.ndarray
    poses: np.ndarray

    def __post_init__(self) -> None:
        ids = np.asarray(self.ids)
        if ids.ndim != 1:
            raise UsageError(f"ids shape={ids.shape!r} must be (n,)")
        if ids.size and not np.issubdtype(ids.dtype, np.integer):
            raise UsageError(f"ids={ids.tolist()!r} must be integers", fix="give whole-number IDs")
        ids = ids.astype(np.int64)
        poses = np.asarray(self.poses, dtype=float)
        if poses.shape != (len(ids), 3):
            raise UsageError(f"poses shape={poses.shape!r} must be ({len(ids)}, 3): one [x, y, theta] per ID")
        bad = np.flatnonzero(~np.isfinite(poses).all(axis=1))
        if len(bad):
            k = int(bad[0])
            raise UsageError(f"poses[{k}]={poses[k].tolist()!r} must be finite",
                             fix="give finite x, y, theta for every robot")
        ids.setflags(write=False)
        poses = poses.copy()
        poses.setflags(write=False)
        object.__setattr__(self, "ids", ids)
        object.__setattr__(self, "poses", poses)

    @property
    def n(self) -> int:
        """Number of robots."""
        return len(self.ids)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, InitialConfiguration):
            return NotImplemented
        return np.array_equal(self.ids, other.ids) and np.array_equal(self.poses, other.poses)

    __hash__ = None

    def as_dict(self, angle_unit: str = "deg") -> dict:
        """The ``robots`` list of the file formats: ``[{id, pose: [x, y, theta]}]``."""
        rows = []
        for i, p in zip(self.ids.tolist(), self.poses.tolist()):
            th = math.degrees(p[2]) if angle_unit == "deg" else p[2]
            rows.append({"id": int(i), "pose": [p[0], p[1], th]})
        return {"robots": rows}


# ----------------------------------------------------------------------------
# Trace
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class Event:
    """Something that happened in one step.

    Attributes
    ----------
    step : int
        The step it happened in.
    kind : str
        ``"clamp"`` (a command exceeded the motion limits and was clamped),
        ``"assumption_broken"`` (a run with ``allow_violations=True``),
        ``"crash"``, ``"add"``, ``"drop"`` (a lost message), ``"noise"``...
    robots : tuple of int
        IDs of the robots concerned.
    detail : tuple of (str, value) pairs
        Anything else, JSON-friendly.
    """

    step: int
    kind: str
    robots: tuple = ()
    detail: tuple = ()

    def as_dict(self) -> dict:
        return {"step": int(self.step), "kind": self.kind,
                "robots": [int(r) for r in self.robots],
                "detail": {str(k): to_jsonable(v) for k, v in self.detail}}

    @staticmethod
    def from_dict(d: Mapping) -> "Event":
        detail = tuple((k, from_jsonable(v)) for k, v in dict(d.get("detail", {})).items())
        return Event(int(d["step"]), str(d["kind"]), tuple(int(r) for r in d.get("robots", ())), detail)


@dataclass
class Trace:
    """The record of one run (see the module docstring for the layout).

    Attributes
    ----------
    ids : numpy.ndarray of int, shape (n,)
    poses : numpy.ndarray, shape (T+1, n, 3)
    states : list of length T+1 of tuples of n hashable states
    events : list of Event
    messages : list of length T of dicts ``id -> message``, or None
    present : numpy.ndarray of bool, shape (T+1, n), or None (all present)
    meta : dict
        JSON-friendly description of the run (algorithm, params, seed, status ...).
    times : list of int, or None
        A sparse trace (``simulate(record_every=k)``) keeps some steps only:
        ``times[i]`` is the engine step recorded at index ``i`` (increasing,
        from 0, the last step included); None for a dense trace (index = step).
        Everything indexed by step above is then indexed by recorded step, and
        ``messages[i-1]`` are the broadcasts of step ``times[i] - 1``.
    """

    ids: np.ndarray
    poses: np.ndarray
    states: list
    events: list = field(default_factory=list)
    messages: list | None = None
    present: np.ndarray | None = None
    meta: dict = field(default_factory=dict)
    times: list | None = None

    def __post_init__(self) -> None:
        self.ids = np.asarray(self.ids, dtype=np.int64)
        self.poses = np.asarray(self.poses, dtype=float)
        if self.poses.ndim != 3 or self.poses.shape[1:] != (len(self.ids), 3):
            raise UsageError(f"poses shape={self.poses.shape!r} must be (T+1, {len(self.ids)}, 3)")
        if len(self.states) != len(self.poses):
            raise UsageError(f"len(states)={len(self.states)} must equal T+1={len(self.poses)}")
        if self.present is not None:
            self.present = np.asarray(self.present, dtype=bool)
            if self.present.shape != self.poses.shape[:2]:
                raise UsageError(f"present shape={self.present.shape!r} must be {self.poses.shape[:2]!r}")
        if self.times is not None:
            self.times = [int(x) for x in self.times]
            if (len(self.times) != len(self.poses) or (self.times and self.times[0] != 0)
                    or any(b <= a for a, b in zip(self.times, self.times[1:]))):
                raise UsageError(f"times={self.times[:5]!r}... must be increasing step numbers from 0, one per "
                                 f"recorded step ({len(self.poses)})")

    @property
    def sparse(self) -> bool:
        """Whether some engine steps are not recorded (``times`` is given)."""
        return self.times is not None

    def time_of(self, i: int) -> int:
        """The engine step recorded at index ``i``."""
        return i if self.times is None else self.times[i]

    def frame_of(self, step: int) -> int | None:
        """The index at which engine step ``step`` is recorded, or None when the trace did not
        keep it (a sparse trace) or the run never reached it.

        >>> t = Trace(ids=[0], poses=np.zeros((3, 1, 3)), states=[(None,)] * 3, times=[0, 5, 7])
        >>> t.frame_of(5), t.frame_of(6), t.frame_of(8)
        (1, None, None)
        """
        step = int(step)
        if self.times is None:
            return step if 0 <= step < len(self.poses) else None
        import bisect

        i = bisect.bisect_left(self.times, step)
        return i if i < len(self.times) and self.times[i] == step else None

    # -- views -----------------------------------------------------------
    @property
    def steps(self) -> int:
        """T, the number of steps run: the last recorded step (a sparse trace always keeps the
        last one), not the number of frames kept (:attr:`frames`).

        >>> t = Trace(ids=[0], poses=np.zeros((3, 1, 3)), states=[(None,)] * 3, times=[0, 5, 7])
        >>> t.steps, t.frames
        (7, 3)
        """
        return len(self.poses) - 1 if self.times is None else self.times[-1]

    @property
    def frames(self) -> int:
        """The number of recorded frames (``len(poses)``): ``steps + 1`` on a dense trace; index
        ``poses``, ``states`` and :meth:`present_at` with ``range(frames)``."""
        return len(self.poses)

    @property
    def n(self) -> int:
        """Number of robot slots (robots added by a fault model included)."""
        return len(self.ids)

    def present_at(self, i: int) -> np.ndarray:
        """Boolean mask of the robots present in recorded frame ``i`` (a dense trace: after ``i``
        steps; a sparse one: after step ``times[i]``); ``-1`` is the last frame."""
        if self.present is None:
            return np.ones(self.n, dtype=bool)
        return self.present[i]

    def final_poses(self) -> np.ndarray:
        """Poses after the last step (present robots only)."""
        return self.poses[-1][self.present_at(-1)]

    def final_ids(self) -> np.ndarray:
        """IDs of the robots present after the last step."""
        return self.ids[self.present_at(-1)]

    # -- serialisation -------------------------------------------------------
    def as_dict(self) -> dict:
        """The JSON object of ``swarmproof-trace/1``."""
        return {
            "format": TRACE_FORMAT,
            "meta": to_jsonable(self.meta),
            "ids": [int(i) for i in self.ids.tolist()],
            "poses": self.poses.tolist(),
            "present": None if self.present is None else self.present.tolist(),
            "states": [to_jsonable(list(s)) for s in self.states],
            "events": [e.as_dict() for e in self.events],
            "messages": None if self.messages is None else [
                {str(k): to_jsonable(v) for k, v in m.items()} for m in self.messages],
            **({} if self.times is None else {"times": list(self.times)}),
        }

    def to_json(self) -> str:
        """Deterministic JSON text (sorted keys, same bytes for the same trace): one top-level key
        a line, each element of a list (a frame's poses or states, an event) on a line of its own,
        written without spaces (:func:`dumps_trace_json`)."""
        return dumps_trace_json(self.as_dict())

    @classmethod
    def from_dict(cls, d: Mapping, *, file: str | None = None) -> "Trace":
        """Build from the JSON object; raises :class:`InputFileError` naming the field."""
        if not isinstance(d, Mapping):
            raise InputFileError(f"top level is {type(d).__name__}, expected an object", file=file,
                                 fix=f"write a {TRACE_FORMAT} object")
        fmt = d.get("format")
        if fmt != TRACE_FORMAT:
            raise InputFileError(f"format={fmt!r} is not {TRACE_FORMAT!r}", file=file, field="format",
                                 fix=f"this reader understands {TRACE_FORMAT!r} only")
        for key in ("ids", "poses", "states"):
            if key not in d:
                raise InputFileError(f"required field {key!r} is missing", file=file, field=key)
        try:
            ids = np.asarray(d["ids"], dtype=np.int64)
        except (TypeError, ValueError):
            raise InputFileError(f"ids={d['ids']!r} must be a list of integers", file=file,
                                 field="ids") from None
        try:
            poses = np.asarray(d["poses"], dtype=float).reshape(-1, len(ids), 3)
        except (TypeError, ValueError):
            raise InputFileError("poses must be a (T+1) x n x 3 array of numbers", file=file,
                                 field="poses") from None
        states = [tuple(from_jsonable(s)) for s in d["states"]]
        try:
            events = [Event.from_dict(e) for e in d.get("events") or []]
        except (KeyError, TypeError, ValueError) as exc:
            raise InputFileError(f"malformed event ({exc})", file=file, field="events") from None
        msgs = d.get("messages")
        messages = None if msgs is None else [
            {int(k): from_jsonable(v) for k, v in m.items()} for m in msgs]
        present = d.get("present")
        try:
            return cls(ids=ids, poses=poses, states=states, events=events, messages=messages,
                       present=None if present is None else np.asarray(present, dtype=bool),
                       meta=dict(d.get("meta") or {}), times=d.get("times"))
        except UsageError as exc:
            raise InputFileError(exc.message, file=file, fix=exc.fix) from None

    @classmethod
    def from_json(cls, text: str, *, file: str | None = None) -> "Trace":
        """Parse JSON text of ``swarmproof-trace/1``."""
        try:
            d = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputFileError(f"not valid JSON ({exc.msg})", file=file, line=exc.lineno,
                                 fix="write the trace with Trace.save") from None
        return cls.from_dict(d, file=file)

    def save(self, path: str | os.PathLike) -> str:
        """Write atomically: ``.npz`` gives NPZ (arrays binary, the rest as JSON), else JSON."""
        path = os.fspath(path)
        if path.endswith(".npz"):
            d = self.as_dict()
            rest = {k: v for k, v in d.items() if k not in ("poses", "present")}
            buf = io.BytesIO()
            # the JSON header as UTF-8 bytes: a numpy string array holds at most 2**31 bytes, which
            # the states of a few hundred agents over thousands of steps exceed (004 at n = 256)
            arrays = {"poses": self.poses, "ids": self.ids,
                      "header": np.frombuffer(dumps_trace_json(rest).encode("utf-8"), dtype=np.uint8)}
            if self.present is not None:
                arrays["present"] = self.present
            np.savez_compressed(buf, **arrays)
            return atomic_write_bytes(path, buf.getvalue())
        return atomic_write_bytes(path, self.to_json().encode("utf-8"))

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Trace":
        """Read a trace written by :meth:`save` (JSON or NPZ)."""
        path = os.fspath(path)
        if not os.path.exists(path):
            raise InputFileError("file does not exist", file=path, fix="check the path")
        if path.endswith(".npz"):
            try:
                with np.load(path, allow_pickle=False) as z:
                    head = z["header"]
                    # UTF-8 bytes (current) or a numpy string (files written before)
                    rest = json.loads(head.tobytes().decode("utf-8") if head.dtype == np.uint8 else str(head))
                    rest["poses"] = z["poses"]
                    rest["present"] = z["present"] if "present" in z.files else None
            except (OSError, ValueError, KeyError) as exc:
                raise InputFileError(f"not a {TRACE_FORMAT} NPZ file ({exc})", file=path) from None
            return cls.from_dict(rest, file=path)
        with open(path, encoding="utf-8") as f:
            return cls.from_json(f.read(), file=path)
