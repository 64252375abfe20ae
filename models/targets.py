"""Targets: what a formation algorithm aims at, and how a configuration is judged against it.

The engine, the properties and the metrics take a *target*, not a lattice
(issue 12).  A target has a ``kind`` and a ``name`` and answers four
questions about a configuration of robots (IDs and poses):

* ``satisfied(ids, poses, *, phi, tol)`` -> :class:`TargetCheck`: the
  paper's goal predicate (held, violated with a witness, or inconclusive);
* ``progress(ids, poses, *, phi)`` -> float: higher is closer to the goal;
* ``metrics(ids, poses, *, phi)`` -> dict: the paper's figures (JSON-ready);
* ``describe()`` -> dict: ``{"kind", "name", ...}``, enough to rebuild it
  (:func:`target_from_description`), which counterexample files record.

Kinds (DESIGN.md section 5, "Targets on the command line"):

=========  =========================================================  ==============================
kind       class                                                      paper
=========  =========================================================  ==============================
lattice    :class:`~swarmproof.models.lattice.LatticeGraph`           001 Def. 2 (000 Def. 2), Q
lines      :class:`LinePattern`                                       003 Sec. 3, Table 1, Algs. 2-3
shape      :class:`~swarmproof.models.shapes.GoalSet`                 004 Sec. III (goal cells)
pattern    :class:`~swarmproof.models.repeating_pattern.RepeatingPattern`  002 Defs. 3-9 (epsilon = 1)
=========  =========================================================  ==============================

Kinds are a registry: :func:`register_target_kind` adds one (a user's, or an
algorithm module's at import time).  :func:`resolve_target` reads the
command line's ``[KIND:]NAME|FILE``; a bare name that two kinds bundle is a
usage error naming both.

This module is the top of the target modules: it imports every kind to register it.  What
the kinds share (:class:`TargetCheck`, the :class:`Target` protocol) lives in
:mod:`swarmproof.models.target_base`, which imports no kind, and is re-exported here, as is
:class:`~swarmproof.models.shapes.GoalSet`.

Examples
--------
>>> resolve_target("square").kind, resolve_target("lattice:square").name
('lattice', 'square')
>>> line = resolve_target("lines:line")
>>> line.satisfied([1, 2, 3], [[0, 0, 0], [0, 1, 0], [0, 2, 0]]).status
'held'
>>> sorted(target_kinds())
['lattice', 'lines', 'pattern', 'shape']
>>> resolve_target("lines:wedge").points(3).round(3).tolist()
[[0.0, 0.0], [-0.866, -0.5], [-0.866, 0.5]]
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any, Callable, Mapping

import numpy as np

from . import library
from . import line_patterns as _lp
from .errors import InputFileError, UsageError, did_you_mean
from .lattice_io import load_lattice_file, loads_lattice
from .repeating_pattern import RepeatingPattern, load_pattern, load_pattern_file, pattern_names, resolve_pattern
from .shapes import _BUNDLED_SHAPES, GoalSet, bundled_shape, bundled_shape_names, load_shape_file
from .target_base import Target, TargetCheck, as_xy

__all__ = ["TargetCheck", "Target", "LinePattern", "GoalSet", "register_target_kind", "target_kinds",
           "target_from_description", "resolve_target", "target_names", "describe_target"]

# ----------------------------------------------------------------------------
# the kind registry
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Kind:
    kind: str
    from_description: Callable[[Mapping], Any]
    bundled: Callable[[], list]            # -> bundled names
    by_name: Callable[[str], Any] | None   # bundled name -> target
    load_file: Callable[[str], Any] | None  # path -> target (None: files of this kind are JSON descriptions)
    by_other_name: Callable[[str], Any] | None = None  # other names the kind reads (e.g. pattern's lattice:NAME)


_KINDS: dict[str, _Kind] = {}


def register_target_kind(kind: str, *, from_description: Callable[[Mapping], Any],
                         bundled: Callable[[], list] | None = None,
                         by_name: Callable[[str], Any] | None = None,
                         load_file: Callable[[str], Any] | None = None,
                         by_other_name: Callable[[str], Any] | None = None) -> None:
    """Register a target kind.

    ``from_description(d)`` rebuilds a target from its ``describe()``
    dictionary; ``bundled()`` lists the bundled names and ``by_name(name)``
    builds one; ``load_file(path)`` reads a file of this kind; ``by_other_name(text)``
    builds one from a name that is neither a file nor bundled, or returns None (the
    ``pattern`` kind reads ``lattice:NAME`` this way).
    """
    if not isinstance(kind, str) or not kind or ":" in kind:
        raise UsageError(f"target kind={kind!r} must be a non-empty string without ':'")
    _KINDS[kind] = _Kind(kind, from_description, bundled or (lambda: []), by_name, load_file, by_other_name)


def target_kinds() -> list[str]:
    """The registered kinds, in registration order."""
    return list(_KINDS)


def target_names(kind: str | None = None) -> list[tuple[str, str]]:
    """``(kind, name)`` of every bundled target (of one kind)."""
    out = []
    for k in ([kind] if kind else _KINDS):
        out += [(k, n) for n in _kind(k).bundled()]
    return out


def _kind(kind: str) -> _Kind:
    if kind not in _KINDS:
        raise UsageError(f"target kind={kind!r} is not known", fix=f"use one of {target_kinds()!r}")
    return _KINDS[kind]


def describe_target(target) -> dict:
    """``target.describe()``, or ``{"kind": "lattice", "name": ...}`` for an object without it."""
    fn = getattr(target, "describe", None)
    if callable(fn):
        return dict(fn())
    return {"kind": getattr(target, "kind", "lattice"), "name": getattr(target, "name", None)}


def target_from_description(d: Mapping, *, file: str | None = None, field_name: str = "target"):
    """Rebuild a target from its ``describe()`` dictionary.

    Malformed descriptions raise :class:`~swarmproof.models.errors.UsageError`
    (or :class:`~swarmproof.models.errors.InputFileError` with ``file``)
    naming the field.
    """
    def bad(msg, fix=None):
        if file is not None:
            return InputFileError(msg, file=file, field=field_name, fix=fix)
        return UsageError(f"{field_name}: {msg}", fix=fix)

    if not isinstance(d, Mapping):
        raise bad(f"{field_name}={d!r} must be an object with 'kind' and 'name'")
    kind = d.get("kind")
    if kind not in _KINDS:
        raise bad(f"kind={kind!r} is not a known target kind", fix=f"use one of {target_kinds()!r}")
    try:
        return _KINDS[kind].from_description(d)
    except UsageError as exc:
        if file is not None and not isinstance(exc, InputFileError):
            raise InputFileError(exc.message, file=file, field=field_name, fix=exc.fix) from None
        raise


def resolve_target(text, kind: str | None = None, *, prefer: str | None = None):
    """A target from the command line's ``[KIND:]NAME|FILE``.

    ``kind`` (an alias option such as ``--lattice``) fixes the kind; a
    ``KIND:`` prefix does the same.  An existing file wins over a bundled
    name.  A bare name bundled by two kinds is a usage error naming both,
    unless ``prefer`` names one of them: verify plans and campaign files
    named lattices by bare names before other kinds bundled the same names
    (``hexagon``, ``triangle``), and read them with ``prefer="lattice"``.

    >>> resolve_target("hexagon", prefer="lattice").kind
    'lattice'
    """
    try:
        text = os.fspath(text)
    except TypeError:
        raise UsageError(f"target={text!r} must be a name or a path") from None
    prefix, sep, rest = text.partition(":")
    if kind is None and sep and prefix in _KINDS and not os.path.exists(text):
        kind, text = prefix, rest
    if kind is not None:
        k = _kind(kind)
        if os.path.exists(text):
            if k.load_file is not None:
                return k.load_file(text)
            return _load_description_file(text, expect=kind)
        if text in k.bundled() and k.by_name is not None:
            return k.by_name(text)
        if k.by_other_name is not None:
            found = k.by_other_name(text)
            if found is not None:
                return found
        raise InputFileError(f"no such file and no bundled {kind} target of that name"
                             f"{did_you_mean(text, k.bundled())}", file=text,
                             fix=f"give a file path or one of the bundled {kind} names {k.bundled()!r}")
    if os.path.exists(text):
        return _load_any_file(text)
    matches = [k for k in _KINDS if text in _KINDS[k].bundled()]
    if len(matches) == 1:
        return _KINDS[matches[0]].by_name(text)
    if len(matches) > 1 and prefer in matches:
        return _KINDS[prefer].by_name(text)
    if len(matches) > 1:
        raise UsageError(f"target={text!r} is ambiguous: bundled as {', '.join(matches)}",
                         fix="say which: " + " or ".join(f"{k}:{text}" for k in matches))
    names = [f"{k}:{n}" for k, n in target_names()]
    raise InputFileError(f"no such file and no bundled target of that name"
                         f"{did_you_mean(text, [n for _, n in target_names()] + names)}", file=text,
                         fix=f"give a file path or one of {names!r}")


def _read_json(path: str):
    import json

    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise InputFileError(f"cannot read the file ({exc.strerror or exc})", file=path) from None
    try:
        return json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError:
        raise InputFileError("the file is not UTF-8 text", file=path, fix="save it as UTF-8") from None
    except json.JSONDecodeError as exc:
        raise InputFileError(f"not JSON: {exc.msg}", file=path, line=exc.lineno) from None


def _load_description_file(path: str, expect: str | None = None):
    d = _read_json(path)
    if isinstance(d, Mapping) and expect is not None and d.get("kind") != expect:
        raise InputFileError(f"kind={d.get('kind')!r}, but a {expect} target was asked for", file=path,
                             field="kind", fix=f"give a {expect} target file")
    return target_from_description(d, file=path, field_name="target")


def _load_any_file(path: str):
    """A lattice-graph/1 or repeating-pattern/1 file (YAML or JSON) or a JSON target description."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError as exc:
        raise InputFileError(f"cannot read the file ({exc.strerror or exc})", file=path) from None
    if path.lower().endswith((".txt", ".png")):
        return _kind("shape").load_file(path)
    if b"repeating-pattern/" in head:
        return _kind("pattern").load_file(path)
    if path.endswith((".yaml", ".yml")) or b"lattice-graph/" in head or b'"kind"' not in head:
        return _kind("lattice").load_file(path)
    return _load_description_file(path)


# ----------------------------------------------------------------------------
# lines (003): points of a pattern, judged on positions up to a rigid motion
# ----------------------------------------------------------------------------

def _kabsch_error(xy: np.ndarray, goal: np.ndarray) -> float:
    """Largest distance after the least-squares proper rigid motion of ``xy`` onto ``goal``
    (row k onto row k; Kabsch)."""
    a, b = xy - xy.mean(0), goal - goal.mean(0)
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    rot = u @ np.diag([1.0, d]) @ vt
    return float(np.hypot(*((a @ rot) - b).T).max())


def _rigid_fit(template: np.ndarray, xy: np.ndarray, tol: float):
    """The best proper rigid motion and one-to-one assignment of ``xy`` onto ``template``.

    Anchors: template point 0 and its nearest other point ``q`` against every
    ordered pair of robots at about the same distance (within 10%, closest first); for each, the
    rigid motion mapping the pair onto the anchors, then an optimal
    assignment (scipy's ``linear_sum_assignment``) of all robots, then the
    least-squares rigid motion for that assignment (Kabsch) when it fits
    better.  Returns ``(max_error, assignment)`` of the best candidate, or
    ``(inf, None)``.  The error is an upper bound of the best achievable
    (minimax) one, exact when the robots form the pattern.
    """
    from scipy.optimize import linear_sum_assignment

    n = len(template)
    if n == 1:
        return 0.0, [0]
    d0 = np.hypot(*(template - template[0]).T)
    d0[0] = np.inf
    q = int(np.argmin(d0))
    a0, b0 = template[0], template[q]
    ang0 = math.atan2(b0[1] - a0[1], b0[0] - a0[0])
    dd = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    best = (math.inf, None)
    # anchor pairs at about the anchors' distance, closest first: within 4 tol they find a
    # configuration that forms the pattern; up to 10% off they keep the witness error of a
    # configuration that does not near the best one (one moved robot may be an anchor)
    slack = max(4 * tol, 1e-9, 0.1 * float(d0[q]))
    gap = np.abs(dd - d0[q])
    cand = [(gap[i, j], i, j) for i, j in zip(*np.nonzero(gap <= slack)) if i != j]
    for _, i, j in sorted(cand):
        ang = math.atan2(xy[j, 1] - xy[i, 1], xy[j, 0] - xy[i, 0])
        c, s = math.cos(ang0 - ang), math.sin(ang0 - ang)
        rel = xy - xy[i]
        moved = np.column_stack((c * rel[:, 0] - s * rel[:, 1], s * rel[:, 0] + c * rel[:, 1])) + a0
        cost = np.hypot(moved[:, None, 0] - template[None, :, 0], moved[:, None, 1] - template[None, :, 1])
        rows, cols = linear_sum_assignment(cost)
        err = min(float(cost[rows, cols].max()), _kabsch_error(xy, template[cols]))
        if err < best[0]:
            best = (err, cols.tolist())
            if err <= tol:
                break
    return best


@dataclass(frozen=True)
class LinePattern:
    """A line pattern of 003 Sec. 3: ``n`` points at a uniform interval ``d_u``.

    ``shape="line"``: the points ``(k d_u, 0)``, k = 0..n-1 (the horizontal
    or vertical line of Table 1; which one depends only on the common
    direction, so up to a rigid motion they are the same pattern).  Any other
    shape is one of Lee & Chong's patterns
    (:data:`~swarmproof.models.line_patterns.PATTERN_NAMES`: Table 1 with
    003 Alg. 2, or Alg. 3), whose points are
    :func:`~swarmproof.models.line_patterns.target_points` with ``params``
    (``alpha_star``, ``m``, ``k``, ``rotation`` and the readings of
    docs/decisions.md).  The size is ``interval`` (``d_u``) or ``span``
    (``d_u = span / (n - 1)``, 003 Secs. 3.1, 3.5); neither given: interval 1.
    The robots are anonymous, so ``satisfied`` matches positions, not IDs, up
    to a proper rigid motion and a permutation (DESIGN.md section 5), within
    ``tol`` (default ``1e-6 d_u``); headings are not judged.

    >>> p = LinePattern("line", interval=1.0)
    >>> p.satisfied([7, 8, 9], [[0, 0, 0], [0.7071067811865476, 0.7071067811865476, 1],
    ...                         [1.4142135623730951, 1.4142135623730951, 2]]).status
    'held'
    >>> p.satisfied([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2.5, 0, 0]]).status
    'violated'
    >>> p.describe()
    {'kind': 'lines', 'name': 'line', 'shape': 'line', 'interval': 1.0}
    >>> LinePattern("line", range=1.5).describe()["range"]
    1.5
    >>> w = LinePattern("wide-wedge", "wedge", span=8.0, params={"alpha_star": 45})
    >>> w.describe()
    {'kind': 'lines', 'name': 'wide-wedge', 'shape': 'wedge', 'span': 8.0, 'params': {'alpha_star': 45}}
    >>> w.interval_for(5)
    2.0
    >>> w.satisfied(range(5), w.points(5)[::-1] + 3.0).status
    'held'
    """

    name: str
    shape: str = "line"
    interval: float | None = None   # d_u; None with span None means 1.0
    range: float | None = None   # a recommended range phi for runs toward it (as a lattice file's)
    kind: str = "lines"
    cites: str = "003 Sec. 3 (uni-line type, uniform interval d_u)"
    span: float | None = None    # 003 Sec. 3.1: span = d_u (n - 1); then d_u follows n
    params: Any = ()             # a pattern's parameters (a mapping; kept as sorted pairs)

    SHAPES = ("line",) + _lp.PATTERN_NAMES + _lp.GENERIC_NAMES

    def __post_init__(self) -> None:
        if self.shape not in self.SHAPES:
            raise UsageError(f"shape={self.shape!r} is not a known line pattern", fix=f"use one of {list(self.SHAPES)!r}")
        if self.interval is not None and self.span is not None:
            raise UsageError(f"interval={self.interval!r} and span={self.span!r} are both given",
                             fix="give one: the interval d_u, or the span d_u (n - 1) (003 Sec. 3.1)")
        if self.interval is None and self.span is None:
            object.__setattr__(self, "interval", 1.0)
        for key in ("interval", "span"):
            val = getattr(self, key)
            if val is not None and (isinstance(val, bool) or not (isinstance(val, (int, float))
                                                                  and math.isfinite(val) and val > 0)):
                raise UsageError(f"{key}={val!r} must be a finite number > 0")
        if self.range is not None and (isinstance(self.range, bool) or not isinstance(self.range, (int, float))
                                       or not math.isfinite(self.range) or self.range <= 0):
            raise UsageError(f"range={self.range!r} must be a finite number > 0 or null")
        params = self.params
        if isinstance(params, Mapping):
            params = tuple(sorted(params.items()))
        elif not (isinstance(params, tuple) and all(isinstance(p, tuple) and len(p) == 2 for p in params)):
            raise UsageError(f"params={params!r} must be a mapping of parameter names to values",
                             fix="e.g. {\"alpha_star\": 30}")
        object.__setattr__(self, "params", params)
        if self.shape == "line":
            if params:
                raise UsageError(f"params={dict(params)!r}: shape 'line' takes no parameters", fix="drop them")
        else:
            _lp._params(self.shape, dict(params))          # validates names and values now
            if self.cites == LinePattern.cites:
                object.__setattr__(self, "cites", _lp.pattern_info(self.shape)["citation"])

    def interval_for(self, n: int) -> float:
        """``d_u`` for ``n`` robots: the interval, or ``span / (n - 1)``."""
        if self.span is None:
            return float(self.interval)
        return _lp.interval_for_span(self.span, n)

    def points(self, n: int) -> np.ndarray:
        """The pattern's ``n`` target points in its own frame (row i: the robot with ID i, leader at row 0)."""
        if self.shape == "line":
            return np.column_stack((np.arange(n, dtype=float) * self.interval_for(n), np.zeros(n)))
        return _lp.target_points(self.shape, n, self.interval_for(n), 0.0, **dict(self.params))

    def _fit(self, poses, tol):
        xy = as_xy(poses)
        scale = self.interval_for(len(xy)) if (self.span is None or len(xy) >= 2) else float(self.span)
        tol = 1e-6 * scale if tol is None else float(tol[0] if isinstance(tol, tuple) else tol)
        if len(xy) == 0:
            return xy, tol, math.inf, None, scale
        if len(xy) == 1:
            return xy, tol, 0.0, [0], scale
        err, assign = _rigid_fit(self.points(len(xy)), xy, tol)
        return xy, tol, err, assign, scale

    def satisfied(self, ids, poses, *, phi: float | None = None, tol=None) -> TargetCheck:
        xy, tol, err, assign, d_u = self._fit(poses, tol)
        if len(xy) == 0:
            return TargetCheck("inconclusive", "no robots", self.cites)
        if err <= tol:
            return TargetCheck("held", f"{len(xy)} robots form the {self.shape} at interval "
                                       f"{d_u:g} (largest error {err:.3g})", self.cites,
                               detail={"max_error": err})
        why = (f"the best rigid fit leaves a robot {err:.4g} from its slot (tol {tol:.3g})" if math.isfinite(err)
               else "no two robots stand at (within 10 % of) the distance between the pattern's anchor points, "
                    "so no rigid motion brings them onto it")
        return TargetCheck("violated", f"{len(xy)} robots are not a {self.shape} at interval {d_u:g}: {why}",
                           self.cites, {"max_error": None if not math.isfinite(err) else err},
                           {"max_error": None if not math.isfinite(err) else err})

    def progress(self, ids, poses, *, phi: float | None = None) -> float:
        """Minus the largest slot error of the best rigid fit, in intervals (0 at the goal)."""
        _, _, err, _, d_u = self._fit(poses, None)
        return -float(err) / d_u if math.isfinite(err) else -math.inf

    def metrics(self, ids, poses, *, phi: float | None = None) -> dict:
        _, _, err, _, _ = self._fit(poses, None)
        return {"max_slot_error": err if math.isfinite(err) else None}

    def describe(self) -> dict:
        d = {"kind": self.kind, "name": self.name, "shape": self.shape}
        if self.span is not None:
            d["span"] = float(self.span)
        else:
            d["interval"] = float(self.interval)
        if self.params:
            d["params"] = dict(self.params)
        if self.range is not None:
            d["range"] = float(self.range)
        return d

    @classmethod
    def from_description(cls, d: Mapping) -> "LinePattern":
        name = d.get("name")
        shape = d.get("shape") or (name if name in cls.SHAPES else "line")
        params = d.get("params") or {}
        if not isinstance(params, Mapping):
            raise UsageError(f"params={params!r} must be an object of parameter names to values",
                             fix="e.g. {\"alpha_star\": 30}")
        return cls(str(name or shape), shape=shape, interval=d.get("interval"), span=d.get("span"),
                   range=d.get("range"), params=dict(params))


#: ``line``: interval 1, recommended range 1.5 (a finished line is connected, next-but-one
#: robots are not neighbors).  Lee & Chong's patterns (003 Table 1, Alg. 3): interval 1 and
#: no recommended range: 003's robots sense every robot (Sec. 5.3: "the sensing capability of
#: all robots is assumed to be unlimited"), so no finite range belongs to the pattern, and
#: every pattern's diameter grows with n (a run gives ``--range`` when a row needs one).
_BUNDLED_LINES = {"line": lambda: LinePattern("line", "line", 1.0, 1.5),
                  **{name: (lambda name=name: LinePattern(name, name, 1.0, None))
                     for name in _lp.PATTERN_NAMES}}


# ----------------------------------------------------------------------------
# registration of the built-in kinds
# ----------------------------------------------------------------------------

def _lattice_kind() -> None:
    def from_description(d):
        doc = d.get("document")
        if doc is not None:
            import json

            return loads_lattice(json.dumps(doc), "json", source=f"<{d.get('name')}>")
        name = d.get("name")
        if name not in library.names():
            raise UsageError(f"name={name!r} is not a bundled lattice and no document is given",
                             fix=f"use one of {library.names()!r}")
        return library.load(name)

    register_target_kind("lattice", from_description=from_description, bundled=library.names,
                         by_name=library.load, load_file=load_lattice_file)


_lattice_kind()
register_target_kind("lines", from_description=LinePattern.from_description,
                     bundled=lambda: sorted(_BUNDLED_LINES), by_name=lambda n: _BUNDLED_LINES[n]())


def _shape_kind() -> None:
    """The ``shape`` kind (004): bundled bitmaps of models/shape_bitmaps/ besides ``_BUNDLED_SHAPES``;
    files ``.txt`` / ``.png`` read by :func:`swarmproof.models.shapes.load_shape_file` at their own
    size, other files as JSON target descriptions."""

    def bundled():
        return sorted(set(_BUNDLED_SHAPES) | set(bundled_shape_names()))

    def by_name(name):
        return bundled_shape(name)

    def load_file(path):
        if str(path).lower().endswith((".txt", ".png")):
            return load_shape_file(path)
        return _load_description_file(path, expect="shape")

    register_target_kind("shape", from_description=GoalSet.from_description, bundled=bundled,
                         by_name=by_name, load_file=load_file)


_shape_kind()


def _pattern_kind() -> None:
    def other(text: str):
        if text.startswith("lattice:"):
            return resolve_pattern(text)
        return None

    register_target_kind("pattern", from_description=RepeatingPattern.from_description, bundled=pattern_names,
                         by_name=load_pattern, load_file=load_pattern_file, by_other_name=other)


_pattern_kind()
