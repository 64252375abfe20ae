"""Repeating patterns of Jiang et al. (002): a basic pattern graph and an assembling graph.

A :class:`RepeatingPattern` is a target of kind ``pattern`` (``--pattern
NAME|FILE``, ``--target pattern:NAME``): B, the basic pattern graph (002
Def. 3: distinct points, the first at the origin) and A, the assembling
graph (Def. 7: distinct vectors; the zero vector, which Algorithm 2 removes,
may be listed and links nothing).  A configuration satisfies it when its
formation quality (Def. 9) is 1 -- an exact cover by full copies of B whose
centers are connected by vectors of A -- computed exactly by
:mod:`swarmproof.models.formation_quality`.

Files: ``repeating-pattern/1`` (YAML or JSON; docs/file-format.md, schema
``models/schemas/repeating-pattern-1.schema.json``)::

    format: repeating-pattern/1
    name: rhombus-triangles
    basic: [[0, 0], [0.5, 0], [0.25, 0.4330127]]       # B, Def. 3
    assembling: [[0, 0], [1, 0], [0.5, 0.8660254], [1.5, 0.8660254]]   # A, Def. 7
    tol: 1.0e-6        # optional: equality tolerance of Defs. 4 and 8 (default 1e-6 x B's shortest distance)
    range: 1.2         # optional: a recommended communication range for runs toward it

Every problem is an :class:`~swarmproof.models.errors.InputFileError` with
the file, the line, the field and a fix.  The bundled patterns
(``models/patterns/``) are the paper's Figs. 1, 3, 4 as its text describes
them (the figures are not in the text; docs/decisions.md, "Jiang et al.").

Examples
--------
>>> p = load_pattern("square-dots")
>>> p.kind, p.basic, len(p.formation(4))
('pattern', ((0.0, 0.0),), 4)
>>> p.satisfied([1, 2, 3, 4], [[x, y, 0] for x, y in p.formation(4)]).status
'held'
>>> loads_pattern("format: repeating-pattern/1\\nname: x\\nbasic: [[1, 0]]\\nassembling: [[1, 0]]\\n")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: <string>:3: field 'basic[0]': basic[0]=[1, 0] must be the origin [0, 0] (002 Def. 3: x_1 = 0, y_1 = 0); fix: list the origin first and the other points relative to it
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from importlib import resources
from typing import Any, Mapping

import numpy as np

from .doclines import field_name, line_of, parse_document
from .errors import InputFileError, UsageError, did_you_mean
from .verdict import ThreeValued

__all__ = ["PATTERN_FORMAT", "RepeatingPattern", "loads_pattern", "load_pattern_file", "load_pattern",
           "pattern_names", "resolve_pattern", "pattern_from_lattice", "schema_path", "PatternCheck",
           "check_pattern"]

PATTERN_FORMAT = "repeating-pattern/1"
_KEYS = ("format", "name", "description", "basic", "assembling", "tol", "range")
#: Bounds that keep a file's work bounded (a basic pattern is a handful of points).
MAX_BASIC = 64
MAX_ASSEMBLING = 64
#: Largest coordinate, and smallest distance between two points of B / length of a vector of A:
#: a pattern is judged within tol, which must stay far above the floating-point resolution.
MAX_COORD = 1e6
MIN_LENGTH = 1e-6


@dataclass(frozen=True)
class RepeatingPattern:
    """B and A of 002 (Defs. 3 and 7), with the tolerance of Defs. 4 and 8."""

    name: str
    basic: tuple
    assembling: tuple
    tol: float | None = None
    range: float | None = None
    description: str = ""
    kind: str = "pattern"
    cites: str = "002 Defs. 3-9 (basic pattern graph, assembling graph, formation quality)"

    def __post_init__(self) -> None:
        basic = tuple((float(x), float(y)) for x, y in self.basic)
        assembling = tuple((float(x), float(y)) for x, y in self.assembling)
        object.__setattr__(self, "basic", basic)
        object.__setattr__(self, "assembling", assembling)
        if not basic or basic[0] != (0.0, 0.0):
            raise UsageError(f"basic={list(basic)!r} must start at the origin (002 Def. 3)")
        if not assembling:
            raise UsageError("assembling=[] is empty", fix="give at least one vector (002 Def. 7)")
        if self.tol is None:
            from .formation_quality import default_tol

            object.__setattr__(self, "tol", default_tol(basic, assembling))

    # -- the desired formation ------------------------------------------------

    def _layers(self):
        """The growth's layers, in order: the root ``[(0, 0)]``, then each next layer, every point
        one vector of A (without (0, 0), in file order) beyond the last layer that is not taken
        yet, in the order the last layer's heads reach them (002 Sec. IV-B, Alg. 2's
        A' = A \\ {(0,0)} \\ O).  Ends after the root when A has no non-zero vector."""
        steps = [a for a in self.assembling if math.hypot(*a) > self.tol]
        layer = [(0.0, 0.0)]
        seen = {self._key((0.0, 0.0))}
        while layer:
            yield layer
            if not steps:
                return
            nxt = []
            for hx, hy in layer:
                for ax, ay in steps:
                    q = (hx + ax, hy + ay)
                    key = self._key(q)
                    if key not in seen:
                        seen.add(key)
                        nxt.append(q)
            layer = nxt

    def heads(self, copies: int) -> np.ndarray:
        """Positions of ``copies`` copies' first points, grown layer by layer from the origin
        by the vectors of A in file order (the layering of 002 Alg. 2, without robots)."""
        if copies <= 0:
            return np.zeros((0, 2))
        out: list = []
        for layer in self._layers():
            out.extend(layer)
            if len(out) >= copies:
                break
        return np.asarray(out[:copies], dtype=float)

    def layer_sizes(self, copies: int) -> tuple:
        """How many copies stand after each whole layer of the growth, up to the first count of at
        least ``copies``: the root is the first layer and each next layer is every point one
        vector of A (without (0, 0)) beyond the last one that is not taken yet (002 Sec. IV-B:
        "The root is the first layer ... they continue to select other heads that are not in
        the formation to join the tree and form a new layer"; Alg. 2's A' = A \\ {(0,0)} \\ O).

        Which copies stand after a whole layer does not depend on the order in which the heads of
        a layer act; within a layer it does (Alg. 2 queues the heads it places "according to the
        node IDs", and the last ones go to the free slots nearest to them), so a run's formation
        is a translate of :meth:`formation` for every start only when ``n / |B|`` is one of these
        counts (docs/jiang.md, "Fig. 7a's quality").

        >>> load_pattern("square-segments").layer_sizes(30)
        (1, 4, 9, 16, 25, 36)
        """
        sizes: list = []
        for layer in self._layers():
            sizes.append((sizes[-1] if sizes else 0) + len(layer))
            if sizes[-1] >= copies:
                break
        return tuple(sizes)

    def fills_whole_layers(self, n: int) -> bool:
        """True when ``n`` robots make whole copies of B that fill whole layers
        (:meth:`layer_sizes`): the one team size at which every run of 002's algorithm, whatever
        its start, can stand as :meth:`formation` ``(n)``.

        >>> p = load_pattern("square-segments")
        >>> p.fills_whole_layers(50), p.fills_whole_layers(100), p.fills_whole_layers(51)
        (True, False, False)
        """
        b = len(self.basic)
        return n > 0 and n % b == 0 and n // b in self.layer_sizes(n // b)

    def _key(self, q) -> tuple:
        g = max(self.tol, 1e-12) * 10
        return (round(q[0] / g), round(q[1] / g))

    def formation(self, n: int) -> np.ndarray:
        """The desired formation of ``n`` robots: ``n // |B|`` copies of B at :meth:`heads`,
        then the first ``n % |B|`` points of one more copy (a formation that cannot have
        quality 1: 002 Sec. V places ``|F_d|`` robots)."""
        b = np.asarray(self.basic)
        full, extra = divmod(int(n), len(b))
        hs = self.heads(full + (1 if extra else 0))
        pts = [h + b for h in hs[:full]]
        if extra:
            pts.append(hs[full] + b[:extra])
        return np.concatenate(pts) if pts else np.zeros((0, 2))

    # -- the Target protocol ----------------------------------------------------

    def quality(self, poses):
        """:func:`~swarmproof.models.formation_quality.formation_quality` of the positions
        (cached for the last few configurations)."""
        from .formation_quality import formation_quality

        xy = np.asarray(poses, dtype=float)
        xy = xy.reshape(-1, xy.shape[-1])[:, :2] if xy.size else np.zeros((0, 2))
        key = (self.basic, self.assembling, self.tol, xy.tobytes())
        hit = _CACHE.get(key)
        if hit is None:
            hit = formation_quality(xy, self.basic, self.assembling, tol=self.tol)
            if len(_CACHE) >= 16:
                _CACHE.pop(next(iter(_CACHE)))
            _CACHE[key] = hit
        return hit

    def satisfied(self, ids, poses, *, phi: float | None = None, tol=None):
        """Held when the formation quality (002 Def. 9) is exactly 1; violated when it is
        proven below 1; inconclusive when a search budget ran out."""
        from .target_base import TargetCheck

        q = self.quality(poses)
        detail = q.as_dict()
        if q.gamma is not None and q.gamma < 1:
            return TargetCheck("violated", f"formation quality {q.epsilon} < 1: {q.message}", self.cites,
                               {"epsilon": detail["epsilon_exact"]}, detail)
        if q.gamma == 1 and q.delta == 1:
            return TargetCheck("held", f"formation quality 1: {q.message}", self.cites, detail=detail)
        if q.gamma == 1 and q.optimal_partitions != "unknown" and "search stopped" not in q.message:
            return TargetCheck("violated", f"formation quality {q.epsilon} < 1: {q.message}", self.cites,
                               {"epsilon": detail["epsilon_exact"]}, detail)
        return TargetCheck("inconclusive", q.message, self.cites, detail=detail)

    def progress(self, ids, poses, *, phi: float | None = None) -> float:
        """The formation quality (its lower bound when not proven)."""
        q = self.quality(poses)
        if q.epsilon is not None:
            return float(q.epsilon)
        return float(q.gamma_bounds[0]) if q.gamma_bounds else 0.0

    def metrics(self, ids, poses, *, phi: float | None = None) -> dict:
        """``epsilon``, ``basic_fulfillment`` (gamma), ``assembling_fulfillment`` (delta), their exact
        fractions, ``method`` and ``size`` (002 Defs. 6-9), and ``alignment``, the "formation
        quality" 002 Sec. V-A actually plots (:meth:`alignment`)."""
        return {**self.quality(poses).as_dict(), "alignment": self.alignment(poses)}

    def alignment(self, poses) -> float | None:
        """002 Sec. V-A's measure: put the origin at "the leftmost point in the first line" of
        the generated formation and of the desired one (:meth:`formation` of as many robots),
        and count "the percentage of points that locate in both" (as a fraction, within
        ``tol``).  The first line is the lowest row (y within ``tol`` of the smallest y).
        None for no robots.

        >>> p = load_pattern("square-dots")
        >>> p.alignment([[5 + x, 7 + y] for x, y in p.formation(6)])
        1.0
        """
        from scipy.spatial import cKDTree

        xy = np.asarray(poses, dtype=float)
        xy = xy.reshape(-1, xy.shape[-1])[:, :2] if xy.size else np.zeros((0, 2))
        if len(xy) == 0:
            return None
        want = self.formation(len(xy))

        def origin(pts):
            low = pts[pts[:, 1] <= pts[:, 1].min() + self.tol]
            return low[np.argmin(low[:, 0])]

        got = xy - origin(xy)
        want = want - origin(want)
        dist, idx = cKDTree(want).query(got, k=1, distance_upper_bound=self.tol)
        hits = {int(j) for d, j in zip(dist, idx) if j < len(want)}
        return len(hits) / len(want)

    def describe(self) -> dict:
        d = {"kind": self.kind, "name": self.name, "basic": [list(p) for p in self.basic],
             "assembling": [list(a) for a in self.assembling], "tol": float(self.tol)}
        if self.range is not None:
            d["range"] = float(self.range)
        if self.description:
            d["description"] = self.description
        return d

    @classmethod
    def from_description(cls, d: Mapping) -> "RepeatingPattern":
        if "basic" not in d and d.get("name") in pattern_names():
            return load_pattern(d["name"])
        return _from_document({"format": PATTERN_FORMAT, **{k: v for k, v in d.items() if k in _KEYS}},
                              "<description>", {}, str(d.get("name") or "pattern"))

    def document(self) -> dict:
        """The ``repeating-pattern/1`` document of this pattern."""
        d = {"format": PATTERN_FORMAT, "name": self.name, "basic": [list(p) for p in self.basic],
             "assembling": [list(a) for a in self.assembling], "tol": float(self.tol)}
        if self.description:
            d["description"] = self.description
        if self.range is not None:
            d["range"] = float(self.range)
        return d


_CACHE: dict = {}


# ---------------------------------------------------------------------------
# reading repeating-pattern/1
# ---------------------------------------------------------------------------

class _Doc:
    def __init__(self, source: str, lines: dict) -> None:
        self.source, self.lines = source, lines

    def fail(self, path: tuple, message: str, fix: str):
        raise InputFileError(message, file=self.source, line=line_of(self.lines, path),
                             field=field_name(path) or None, fix=fix)

    def number(self, path: tuple, v: Any, what: str, *, limit: float = MAX_COORD) -> float:
        from .doclines import num_text, text_number_fix

        if isinstance(v, bool) or not isinstance(v, (int, float)):
            hint = text_number_fix(v) if isinstance(v, str) else None
            self.fail(path, f"{field_name(path)}={_short(v)} must be a number",
                      f"write {what} as a plain number" + (hint or ""))
        try:
            x = float(v)
        except OverflowError:
            x = math.inf
        if not math.isfinite(x) or abs(x) > limit:
            shown = num_text(v) if not isinstance(v, float) or math.isfinite(x) else repr(v)
            self.fail(path, f"{field_name(path)}={shown} must be a finite number of size at most {limit:g}",
                      f"write {what} in units where the pattern spans less than {limit:g}")
        return x

    def points(self, key: str, v: Any, limit: int, what: str) -> list[tuple[float, float]]:
        if not isinstance(v, list) or not v:
            self.fail((key,), f"{key}={v!r} must be a non-empty list of [x, y] pairs", f"e.g. {key}: [[0, 0], [1, 0]]")
        if len(v) > limit:
            self.fail((key,), f"{key} has {len(v)} entries (more than {limit})", f"a {what} is a handful of points")
        out = []
        for i, p in enumerate(v):
            if not isinstance(p, list) or len(p) != 2:
                self.fail((key, i), f"{key}[{i}]={p!r} must be a pair [x, y]", "write each entry as [x, y]")
            out.append((self.number((key, i, 0), p[0], "x"), self.number((key, i, 1), p[1], "y")))
        return out


def _short(v: Any) -> str:
    """``repr`` of a value, cut to 60 characters (a 400-digit number stays readable)."""
    r = repr(v)
    return r if len(r) <= 60 else r[:57] + "..."


def _is_float(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def _distinct(doc: _Doc, key: str, pts: list, tol: float, what: str, min_distance: float = 0.0) -> None:
    """No two entries within ``tol`` (a repeat), nor closer than ``min_distance`` (too small to
    judge within a tolerance far above the floating-point resolution)."""
    for i in range(len(pts)):
        for j in range(i):
            d = math.hypot(pts[i][0] - pts[j][0], pts[i][1] - pts[j][1])
            if d <= tol:
                doc.fail((key, i), f"{key}[{i}]={list(pts[i])!r} repeats {key}[{j}]={list(pts[j])!r} "
                                   f"(within tol={tol:g})", f"{what} (remove one, or lower tol)")
            if d < min_distance:
                from .doclines import distinct_texts

                dt, mt = distinct_texts(d, min_distance, 3)
                doc.fail((key, i), f"{key}[{i}]={list(pts[i])!r} is {dt} from {key}[{j}] "
                                   f"(less than {mt})",
                         f"scale the pattern so that its points are at least {min_distance:g} apart")


#: A given ``tol`` larger than this share of the pattern's shortest nonzero length is blamed
#: itself: it merges points that the file lists as distinct.
MAX_REL_TOL = 0.5


def _check_tol(doc: _Doc, tol: float, basic: list, assembling: list) -> None:
    """Blame ``tol`` (not the points) when it is as large as the pattern's own lengths: a
    tolerance absorbs rounding, it must be far below the distances it tells apart."""
    from .doclines import num_text

    lengths = [math.hypot(p[0] - q[0], p[1] - q[1]) for i, p in enumerate(basic) for q in basic[:i]]
    lengths += [math.hypot(*a) for a in assembling]
    scale = max(lengths, default=0.0)
    nonzero = [d for d in lengths if d > 1e-9 * scale]
    if not nonzero:
        return
    shortest = min(nonzero)
    # only when tol is also large against the pattern: a tiny tol beside a near-duplicate
    # point blames the point
    if tol >= MAX_REL_TOL * shortest and tol > 1e-2 * scale:
        doc.fail(("tol",), f"tol={num_text(tol)} is not small against the pattern: its shortest distance "
                           f"between points of B or length of a vector of A is {num_text(shortest)}",
                 f"tol is an equality tolerance for rounding: give tol below {shortest * MAX_REL_TOL:g} "
                 "(e.g. tol: 1.0e-6), or leave it out for the default")


def _from_document(data: Any, source: str, lines: dict, default_name: str) -> RepeatingPattern:
    doc = _Doc(source, lines)
    if not isinstance(data, dict):
        doc.fail((), f"the document must be a mapping with format, basic and assembling, got "
                     f"{type(data).__name__}", f"start the file with  format: {PATTERN_FORMAT}")
    for k in data:
        if k not in _KEYS:
            doc.fail((k,), f"key {k!r} is not known in {PATTERN_FORMAT}", f"use only {list(_KEYS)!r}")
    if data.get("format") != PATTERN_FORMAT:
        doc.fail(("format",), f"format={data.get('format')!r} must be {PATTERN_FORMAT!r}",
                 f"start the file with  format: {PATTERN_FORMAT}")
    for k in ("basic", "assembling"):
        if k not in data:
            doc.fail((), f"the key {k!r} is missing", f"add {k}: [[0, 0], ...] (docs/file-format.md)")
    name = data.get("name", default_name)
    if not isinstance(name, str) or not name.strip() or len(name) > 100:
        doc.fail(("name",), f"name={name!r} must be a short non-empty text", "e.g. name: rhombus-triangles")
    desc = data.get("description", "")
    if not isinstance(desc, str):
        doc.fail(("description",), f"description={desc!r} must be text", "quote it")
    basic = doc.points("basic", data["basic"], MAX_BASIC, "basic pattern")
    assembling = doc.points("assembling", data["assembling"], MAX_ASSEMBLING, "assembling graph")
    if basic[0] != (0.0, 0.0):
        doc.fail(("basic", 0), f"basic[0]={list(data['basic'][0])!r} must be the origin [0, 0] "
                               "(002 Def. 3: x_1 = 0, y_1 = 0)",
                 "list the origin first and the other points relative to it")
    tol = None
    if data.get("tol") is not None:
        tol = doc.number(("tol",), data["tol"], "tol")
        if tol <= 0:
            doc.fail(("tol",), f"tol={_short(data['tol'])} must be > 0", "e.g. tol: 1.0e-6")
    rng = None
    if data.get("range") is not None:
        rng = doc.number(("range",), data["range"], "range")
        if rng <= 0:
            doc.fail(("range",), f"range={_short(data['range'])} must be > 0", "e.g. range: 1.2")
    from .formation_quality import default_tol

    t = tol if tol is not None else default_tol(basic, assembling)
    if tol is not None:
        _check_tol(doc, tol, basic, assembling)
    _distinct(doc, "basic", basic, t, "002 Def. 3: the points of B do not overlap", MIN_LENGTH)
    _distinct(doc, "assembling", assembling, t, "002 Def. 7: the vectors of A are distinct")
    steps = [k for k, a in enumerate(assembling) if math.hypot(*a) > t]
    if not steps:
        doc.fail(("assembling",), f"assembling={[list(a) for a in assembling]!r} has no nonzero vector: no two "
                                  "copies of B can be linked (002 Def. 8)",
                 "add the vectors from one copy's center to its neighbours' centers, e.g. [1, 0]")
    for i, a in enumerate(assembling):
        if 0 < math.hypot(*a) < MIN_LENGTH:
            doc.fail(("assembling", i), f"assembling[{i}]={list(a)!r} is shorter than {MIN_LENGTH:g}",
                     f"scale the pattern so that its vectors are at least {MIN_LENGTH:g} long, or write [0, 0]")
    if t < 1e-12:
        doc.fail(("tol",), f"tol={t!r} is below 1e-12", "give tol >= 1e-12 (and lengths of at least 1e-6)")
    return RepeatingPattern(name.strip(), tuple(basic), tuple(assembling), tol, rng, desc)


def loads_pattern(text: str, fmt: str = "yaml", source: str = "<string>") -> RepeatingPattern:
    """Parse a ``repeating-pattern/1`` document (YAML, or JSON with ``fmt="json"``)."""
    data, lines = parse_document(text, fmt, source)
    stem = os.path.splitext(os.path.basename(source))[0] if not source.startswith("<") else "pattern"
    return _from_document(data, source, lines, stem)


def load_pattern_file(path: str | os.PathLike) -> RepeatingPattern:
    """Read a ``repeating-pattern/1`` file (``.yaml``, ``.yml`` or ``.json``)."""
    from .doclines import read_text

    name = os.fspath(path)
    text = read_text(name, what="pattern file", max_bytes=1_000_000,
                     fix=f"give the path of a {PATTERN_FORMAT} file or one of {pattern_names()!r}")
    fmt = "json" if name.endswith(".json") else "yaml"
    return loads_pattern(text, fmt, name)


# ---------------------------------------------------------------------------
# bundled patterns and lattice conversions
# ---------------------------------------------------------------------------

def _folder():
    return resources.files(__package__) / "patterns"


def pattern_names() -> list[str]:
    """Names of the bundled patterns, sorted."""
    return sorted(p.name[:-5] for p in _folder().iterdir() if p.name.endswith(".yaml"))


def load_pattern(name: str) -> RepeatingPattern:
    """A bundled pattern by name (``models/patterns/NAME.yaml``)."""
    if name not in pattern_names():
        raise UsageError(f"pattern={name!r} is not a bundled pattern", fix=f"use one of {pattern_names()!r}")
    text = (_folder() / f"{name}.yaml").read_text(encoding="utf-8")
    return loads_pattern(text, "yaml", f"library:{name}")


def resolve_pattern(name_or_path) -> RepeatingPattern:
    """A pattern from a file path or a bundled name (an existing path wins); ``lattice:NAME``
    converts a one-role bundled lattice (:func:`pattern_from_lattice`)."""
    text = os.fspath(name_or_path)
    if os.path.exists(text):
        return load_pattern_file(text)
    if text in pattern_names():
        return load_pattern(text)
    if text.startswith("lattice:"):
        from . import library

        return pattern_from_lattice(library.load(text.split(":", 1)[1]))
    raise InputFileError(f"no such file and no bundled pattern of that name{did_you_mean(text, pattern_names())}",
                         file=text,
                         fix=f"give a {PATTERN_FORMAT} file or one of {pattern_names()!r}")


def pattern_from_lattice(graph) -> RepeatingPattern:
    """The repeating pattern of a one-role lattice graph: B a single point, A its edge vectors
    (each robot's neighbors sit at the edge translations, 001 Def. 1, so a copy of the dot
    at every vector of A from another is the lattice).  Lattices with several roles, or
    whose edges turn the robot (theta != 0), have no such reading and are refused.

    >>> from swarmproof.models import library
    >>> pattern_from_lattice(library.load("square")).assembling
    ((1.0, 0.0), (0.0, -1.0), (-1.0, 0.0), (0.0, 1.0))
    """
    if len(graph.roles) != 1:
        raise UsageError(f"lattice={graph.name!r} has {len(graph.roles)} roles; only a one-role lattice "
                         "converts to a repeating pattern (one point, its edge vectors)",
                         fix="write the pattern as a repeating-pattern/1 file (docs/file-format.md)")
    if any(abs(math.remainder(e.transform.theta, 2 * math.pi)) > 1e-9 for e in graph.edges):
        raise UsageError(f"lattice={graph.name!r} turns its robots along an edge (theta != 0); a repeating "
                         "pattern of 002 repeats by translations only",
                         fix="write the pattern as a repeating-pattern/1 file (docs/file-format.md)")
    vecs = []
    for e in graph.edges:
        v = (float(e.transform.x), float(e.transform.y))
        if all(math.hypot(v[0] - w[0], v[1] - w[1]) > 1e-9 for w in vecs):
            vecs.append(v)
    return RepeatingPattern(f"lattice-{graph.name}", ((0.0, 0.0),), tuple(vecs), None, graph.range,
                            f"converted from the one-role lattice {graph.name!r}")


def schema_path() -> str:
    """Path of the JSON Schema of ``repeating-pattern/1``."""
    return str(resources.files(__package__) / "schemas" / "repeating-pattern-1.schema.json")


# ---------------------------------------------------------------------------
# check-pattern
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class PatternCheck(ThreeValued):
    """The verdict of :func:`check_pattern`: held (well-formed, and the assembled pattern of
    ``copies`` copies has no two robots on one point), violated with the overlap, or
    inconclusive (the quality of the assembled formation was not proven 1)."""

    status: str
    message: str
    pattern: RepeatingPattern
    copies: int
    overlap: dict | None = None
    quality: dict | None = None

    def __post_init__(self) -> None:
        self._check_status()

    def to_json(self) -> dict:
        from .verdict import Verdict

        return {"pattern": self.pattern.document(), "verdict": self.status,
                "exit_code": Verdict(self.status).exit_code, "message": self.message, "copies": self.copies,
                "overlap": self.overlap, "quality": self.quality, "cites": self.pattern.cites}


def check_pattern(pattern: RepeatingPattern, copies: int = 64) -> PatternCheck:
    """Assemble ``copies`` copies (:meth:`RepeatingPattern.formation`) and check that no two
    points coincide (within ``tol``) and that the assembled formation has quality 1."""
    from scipy.spatial import cKDTree

    pts = pattern.formation(copies * len(pattern.basic))
    pairs = sorted(cKDTree(pts).query_pairs(pattern.tol)) if len(pts) > 1 else []
    if pairs:
        i, j = pairs[0]
        b = len(pattern.basic)
        return PatternCheck("violated", f"copies {i // b} and {j // b} of B overlap: point {i % b} of one and "
                                        f"point {j % b} of the other are both at ({pts[i][0]:.6g}, {pts[i][1]:.6g}); "
                                        f"{len(pairs)} overlapping pair(s) among {len(pts)} points",
                            pattern, copies, {"copies": [i // b, j // b], "points": [i % b, j % b],
                                              "at": [float(pts[i][0]), float(pts[i][1])], "pairs": len(pairs)})
    q = pattern.quality(pts)
    if q.gamma == 1 and q.delta == 1:
        return PatternCheck("held", f"{copies} copies of B ({len(pts)} points) assemble without overlap; "
                                    "formation quality 1", pattern, copies, None, q.as_dict())
    return PatternCheck("inconclusive", f"{copies} copies assemble without overlap, but the formation quality "
                                        f"of the assembled formation is not proven 1: {q.message}",
                        pattern, copies, None, q.as_dict())
