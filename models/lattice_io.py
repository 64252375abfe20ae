"""Reading and writing lattice graph files, format ``lattice-graph/1``.

The format (DESIGN.md section 2, documented for users in docs/file-format.md)
is one mapping, in YAML or JSON, with these keys:

``format`` (required)
    exactly ``"lattice-graph/1"``.
``name`` (optional)
    a non-empty string; defaults to the file's stem.
``range`` (optional)
    the default sensing range phi, a finite number > 0.
``angle_unit`` (optional)
    ``deg`` (default) or ``rad``; the unit of every edge's ``theta``.
``roles`` (required)
    a non-empty list of unique non-empty strings; the first is v0.
``edges`` (required)
    a list of rows ``[from, to, x, y, theta]``: the pose of a robot in role
    ``to`` in the body frame of a robot in role ``from`` (001 Def. 1 and
    Def. 2).  Edges are kept exactly as written and in order (the out-edge
    order ranks vacancies, 001 Def. 9).

Every problem with a file raises :class:`~swarmproof.models.errors.InputFileError`
naming the file, the 1-based line, the field (e.g. ``edges[3][2]``), the
offending value as ``name=value!r`` and a fix; no other exception escapes
:func:`loads_lattice` or :func:`load_lattice_file`.  YAML is read with
PyYAML's safe loader only (libyaml's ``CSafeLoader`` where installed).  A JSON Schema (draft 2020-12) of the format ships as
``swarmproof/models/schemas/lattice-graph-1.schema.json``
(:func:`schema_path`).

This module imports PyYAML besides numpy/scipy/networkx: reading the file
format is part of the model layer (DESIGN.md section 1 puts "file formats
and their schemas" in models/), and PyYAML is a declared dependency.

References
----------
001_7a4e517b856331bc.txt, Sec. III-B, Definitions 1-2 (what an edge means).
000_3ad33c5b62f11d5f.txt, Sec. III-B, Definition 1, Eq. (1).

Examples
--------
>>> text = '''
... format: lattice-graph/1
... name: square
... range: 1.2
... roles: [A]
... edges:
...   - [A, A, 1, 0, 0]
...   - [A, A, 0, -1, 0]
...   - [A, A, -1, 0, 0]
...   - [A, A, 0, 1, 0]
... '''
>>> g = loads_lattice(text, "yaml", source="square.yaml")
>>> g.name, g.roles, len(g.edges), g.range
('square', ('A',), 4, 1.2)
>>> loads_lattice(dump_lattice(g, "json"), "json") == g
True
>>> loads_lattice(text.replace("[A, A, 0, 1, 0]", "[A, B, 0, 1, 0]"), "yaml", source="sq.yaml")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: sq.yaml:10: field 'edges[3][1]': edges[3][1]='B' is not a declared role; fix: use one of roles=['A'] or add 'B' to roles
"""

from __future__ import annotations

import bisect
import json
import math
import os
import re
import reprlib
from typing import Any, Callable

import yaml

from .errors import InputFileError, UsageError
from .fileio import atomic_write_text
from .lattice import LatticeGraph
from .lattice_document import ANGLE_UNITS as _ANGLE_UNITS
from .lattice_document import FORMAT, lattice_to_document
from .se2 import SE2

__all__ = [
    "FORMAT",
    "ALLOWED_KEYS",
    "loads_lattice",
    "load_lattice_file",
    "dump_lattice",
    "save_lattice",
    "lattice_to_document",
    "schema_path",
]

#: Top-level keys of the format, in the order they are written.
ALLOWED_KEYS = ("format", "name", "range", "angle_unit", "roles", "edges")
_REQUIRED = ("format", "roles", "edges")
_ROW_FIELDS = ("from", "to", "x", "y", "theta")

_repr = reprlib.Repr()
_repr.maxstring = 60
_repr.maxother = 60
_repr.maxlist = _repr.maxtuple = _repr.maxdict = 6
_repr.maxlevel = 3


def _r(value: Any) -> str:
    """A bounded ``repr`` (documents may hold huge or self-referencing values)."""
    try:
        return _repr.repr(value)
    except Exception:  # pragma: no cover - exotic objects with a broken __repr__
        return f"<{type(value).__name__}>"


Path = tuple  # a field path such as ("edges", 3, 2)


def _field(path: Path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


class _Ctx:
    """Where we are: the source name and a field-path -> line table."""

    def __init__(self, source: str, lines) -> None:
        self.source = source
        self._lines = lines     # a dict, or a function that makes it (only when an error needs it)

    @property
    def lines(self) -> dict[Path, int]:
        if callable(self._lines):
            self._lines = self._lines()
        return self._lines

    def line(self, path: Path) -> int | None:
        path = tuple(path)
        while True:
            if path in self.lines:
                return self.lines[path]
            if not path:
                return None
            path = path[:-1]

    def error(self, path: Path, message: str, fix: str) -> InputFileError:
        return InputFileError(message, file=self.source, line=self.line(path),
                              field=_field(path) or None, fix=fix)


# ---------------------------------------------------------------------------
# parsing with line numbers
# ---------------------------------------------------------------------------

def parse_yaml_node(text: str, source: str, *, nesting: str) -> tuple[Any, Any]:
    """Parse one YAML document: ``(data, root node)`` (the node gives lines).

    The one YAML reader of every file format (:func:`swarmproof.models.doclines.load_yaml`:
    libyaml where installed, a key written twice refused); every YAML problem is an
    :class:`InputFileError` naming the file and, where known, the line; ``nesting`` is the
    fix given for a document nested too deep.
    """
    from .doclines import load_yaml

    return load_yaml(text, source, nesting=nesting)


def _parse_yaml(text: str, source: str) -> tuple[Any, dict[Path, int]]:
    """Parse YAML with ``SafeLoader``; map field paths to 1-based lines."""
    data, node = parse_yaml_node(text, source, nesting="a lattice-graph/1 file nests at most three levels")
    if node is None:
        return None, {}
    lines: dict[Path, int] = {(): node.start_mark.line + 1}
    if isinstance(node, yaml.MappingNode):
        seen: dict[str, int] = {}
        for knode, vnode in node.value:
            if not isinstance(knode, yaml.ScalarNode) or knode.tag == "tag:yaml.org,2002:merge":
                continue
            key, kline = knode.value, knode.start_mark.line + 1
            if key in seen:
                raise InputFileError(f"key {key!r} appears twice (lines {seen[key]} and {kline})",
                                     file=source, line=kline, field=key,
                                     fix="keep one of them")
            seen[key] = kline
            lines[(key,)] = kline
            if key in ("roles", "edges") and isinstance(vnode, yaml.SequenceNode):
                for i, item in enumerate(vnode.value):
                    lines[(key, i)] = item.start_mark.line + 1
                    if key == "edges" and isinstance(item, yaml.SequenceNode):
                        for j, cell in enumerate(item.value):
                            lines[(key, i, j)] = cell.start_mark.line + 1
    return data, lines


_WS = re.compile(r"[ \t\n\r]*")


def _parse_json(text: str, source: str) -> tuple[Any, dict[Path, int]]:
    """Parse JSON; map field paths to 1-based lines.

    The document is parsed by :func:`json.loads` first; a second pass over the
    (then known valid) text with ``JSONDecoder.raw_decode`` records where each
    top-level key, each ``roles``/``edges`` item and each row cell starts.
    """
    if text.startswith("\ufeff"):
        text = text[1:]
    from .doclines import _DuplicateJsonKey, _json_pairs, load_json

    try:
        data = json.loads(text, object_pairs_hook=_json_pairs)
    except _DuplicateJsonKey:
        _json_lines(text, source)   # names both lines of a repeated top-level key
        load_json(text, source)     # a key repeated deeper down
        raise AssertionError("unreachable: a repeated key was found")  # pragma: no cover
    except json.JSONDecodeError as exc:
        raise InputFileError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=source,
                             line=exc.lineno,
                             fix="check commas, brackets and double quotes near this line") from None
    except RecursionError:
        raise InputFileError("malformed JSON: nesting is too deep", file=source,
                             fix="a lattice-graph/1 file nests at most three levels") from None
    except (ValueError, TypeError, OverflowError) as exc:  # e.g. an integer with 5000 digits
        raise InputFileError(f"malformed JSON: a value cannot be read ({_r(str(exc))})",
                             file=source, fix="write plain numbers of ordinary size") from None
    return data, lambda: _json_lines(text, source)


def _json_lines(text: str, source: str) -> dict[Path, int]:
    """Where each top-level key, each ``roles``/``edges`` item and each row cell starts (a second
    pass over the text, known valid; made only when an error message needs a line)."""
    newlines = [m.start() for m in re.finditer("\n", text)]

    def line_at(pos: int) -> int:
        return bisect.bisect_left(newlines, pos) + 1

    lines: dict[Path, int] = {}
    dec = json.JSONDecoder()

    def ws(i: int) -> int:
        return _WS.match(text, i).end()

    def walk_array(i: int, path: Path, depth: int) -> int:
        i = ws(i + 1)
        idx = 0
        if text[i] == "]":
            return i + 1
        while True:
            i = ws(i)
            lines[path + (idx,)] = line_at(i)
            if depth > 1 and text[i] == "[":
                i = walk_array(i, path + (idx,), depth - 1)
            else:
                _, i = dec.raw_decode(text, i)
            i = ws(i)
            if text[i] == "]":
                return i + 1
            i += 1  # ','
            idx += 1

    try:
        i = ws(0)
        lines[()] = line_at(i)
        if text[i] == "{":
            i = ws(i + 1)
            seen: dict[str, int] = {}
            while text[i] != "}":
                key, j = dec.raw_decode(text, i)
                kline = line_at(i)
                if key in seen:
                    raise InputFileError(f"key {key!r} appears twice (lines {seen[key]} and {kline})",
                                         file=source, line=kline, field=key, fix="keep one of them")
                seen[key] = kline
                lines[(key,)] = kline
                i = ws(ws(j) + 1)  # skip ':'
                if key in ("roles", "edges") and text[i] == "[":
                    i = walk_array(i, (key,), 2 if key == "edges" else 1)
                else:
                    _, i = dec.raw_decode(text, i)
                i = ws(i)
                if text[i] == ",":
                    i = ws(i + 1)
    except InputFileError:
        raise
    except Exception:  # pragma: no cover - the text parsed above; keep what we have
        pass
    return lines


# ---------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------

def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


#: Largest |x|, |y|, |theta| (in the file's angle unit) and range a file may hold: far above any
#: lattice in metres or millimetres, and far enough below the float range that the checker's
#: holonomy products, squared lengths and translation refinement stay exact to its tolerances
#: (a coordinate of 1e160 squared overflows; docs/file-format.md "Limits").
MAX_MAGNITUDE = 1e6
#: Shortest range and shortest edge of non-zero length: a lattice at 1e-300 metres underflows
#: the checker's squared lengths and divisions (numpy warnings, a false "dense pattern"), so
#: lengths span at most 1e-6 .. 1e6 (check-pattern's bound; docs/file-format.md "Limits").
#: An edge of length exactly 0 stays legal: the checker reports it as a defect.
MIN_LENGTH = 1e-6
#: Largest file, roles and edges a lattice file may hold (docs/file-format.md "Limits"; a
#: 100 x 100 supercell, 10,000 roles and 40,000 edges, is checked in a few seconds).
MAX_FILE_BYTES = 16_000_000
MAX_ROLES = 20_000
MAX_EDGES = 100_000


_PLAIN = (int, float)


def _e(bound: float) -> str:
    """``1e6`` for 1e6 (not ``1e+06``)."""
    m, e = f"{bound:.0e}".split("e")
    return f"{m}e{int(e)}"


def _number(ctx: _Ctx, path: Path, v: Any, what: str, bound: float = MAX_MAGNITUDE) -> float:
    from .doclines import num_text, text_number_fix

    name = _field(path)
    if isinstance(v, bool):
        raise ctx.error(path, f"{name}={v!r} must be a number, not a boolean", f"write {what} as a number")
    if not _is_number(v):
        fix = f"write {what} as a plain number"
        hint = text_number_fix(v) if isinstance(v, str) else None
        if hint:
            fix += hint
            try:
                if not abs(float(v)) <= bound:
                    fix += f"; and note |{what.split()[0]}| <= {_e(bound)}"
            except ValueError:  # pragma: no cover - text_number_fix parsed it
                pass
        raise ctx.error(path, f"{name}={_r(v)} must be a number, got {type(v).__name__}", fix)
    try:
        x = float(v)
    except OverflowError:  # an integer of more than 308 digits
        x = math.inf if v > 0 else -math.inf
    else:
        if not math.isfinite(x):
            raise ctx.error(path, f"{name}={v!r} must be a finite number", f"write {what} as a finite number")
    if not abs(x) <= bound:
        raise ctx.error(path, f"{name}={num_text(v)} is beyond the bound |{what.split()[0]}| <= {_e(bound)}",
                        "reduce the angle modulo 360 deg (2 pi rad)" if what.startswith("theta") else
                        f"scale the whole lattice (every x, y and the range by one factor, e.g. metres "
                        f"instead of micrometres) so that coordinates and range are at most {_e(bound)}")
    return x


def _document_to_graph(data: Any, ctx: _Ctx, default_name: str) -> LatticeGraph:
    """Validate a parsed document and build the :class:`LatticeGraph`: its keys and format,
    then the header fields, the roles and the edge rows, each refused with file, line and field."""
    _check_keys_and_format(data, ctx)
    name, rng, unit = _header_fields(data, ctx, default_name)
    roles, seen = _role_names(data, ctx)
    rows = _edge_rows(data, ctx, roles, seen, unit)
    try:
        graph = LatticeGraph(name, roles, rows, range=rng, source=ctx.source)
        graph.angle_unit = unit   # fix rows are printed in the file's own unit
        return graph
    except UsageError as exc:  # pragma: no cover - everything was checked above
        raise ctx.error((), str(exc), "see docs/file-format.md") from None


def _check_keys_and_format(data: Any, ctx: _Ctx) -> None:
    """The document is a mapping of known keys with ``format: lattice-graph/1`` and the required keys."""
    if data is None:
        raise ctx.error((), "the file is empty",
                        f"write a {FORMAT} document (see docs/file-format.md)")
    if not isinstance(data, dict):
        raise ctx.error((), f"the document must be a mapping of keys, got {type(data).__name__} {_r(data)}",
                        f"write a mapping with keys {list(ALLOWED_KEYS)} (see docs/file-format.md)")
    for key in data:
        if key not in ALLOWED_KEYS:
            kname = key if isinstance(key, str) else _r(key)
            raise ctx.error((kname,), f"unknown key {kname!r}",
                            f"use only the keys {list(ALLOWED_KEYS)}; check the spelling")
    # format first: another version may mean other keys
    if "format" not in data:
        raise ctx.error((), "key 'format' is missing", f"add `format: {FORMAT}` as the first line")
    fmt = data["format"]
    if fmt != FORMAT or not isinstance(fmt, str):
        if isinstance(fmt, str) and fmt.startswith("lattice-graph/"):
            msg = f"format={fmt!r} is not supported; this swarmproof reads only {FORMAT!r}"
        else:
            msg = f"format={_r(fmt)} is not a lattice graph format; expected {FORMAT!r}"
        raise ctx.error(("format",), msg, f"write `format: {FORMAT}` (and convert the file if it "
                                          "follows another version)")
    for key in _REQUIRED:
        if key not in data:
            raise ctx.error((), f"key {key!r} is missing",
                            {"roles": "add `roles: [A, ...]` listing the role names; the first is v0",
                             "edges": "add `edges:` with rows [from, to, x, y, theta]"}[key])


def _header_fields(data: dict, ctx: _Ctx, default_name: str) -> tuple:
    """``(name, range or None, angle unit)``, each checked."""
    name = data.get("name", default_name)
    if not isinstance(name, str) or not name.strip():
        raise ctx.error(("name",), f"name={_r(name)} must be a non-empty string",
                        "write a name such as `name: square` (quote it if it looks like a number)")
    rng = None
    if "range" in data:
        rng = _number(ctx, ("range",), data["range"], "range")
        if not rng > 0:
            from .doclines import num_text

            raise ctx.error(("range",), f"range={num_text(data['range'])} must be > 0",
                            "give the sensing range phi as a positive number, or remove the key")
        if rng < MIN_LENGTH:
            from .doclines import num_text

            raise ctx.error(("range",), f"range={num_text(data['range'])} is below the bound range >= {_e(MIN_LENGTH)}",
                            f"scale the whole lattice (every x, y and the range by one factor, e.g. "
                            f"micrometres instead of metres) so that the range and every edge are at "
                            f"least {_e(MIN_LENGTH)}")
    unit = data.get("angle_unit", "deg")
    if unit not in _ANGLE_UNITS or not isinstance(unit, str):
        raise ctx.error(("angle_unit",), f"angle_unit={_r(unit)} is not a known unit",
                        "use 'deg' (the default) or 'rad'")
    return name, rng, unit


def _role_names(data: dict, ctx: _Ctx) -> tuple:
    """``(roles, {role: index})``: a non-empty list of distinct non-empty names within the limit."""
    roles = data["roles"]
    if not isinstance(roles, list):
        raise ctx.error(("roles",), f"roles={_r(roles)} must be a list of role names",
                        "write `roles: [A, B]`")
    if not roles:
        raise ctx.error(("roles",), "roles=[] is empty", "list at least one role; the first is v0")
    if len(roles) > MAX_ROLES:
        raise ctx.error(("roles",), f"roles has {len(roles)} entries, more than the limit of {MAX_ROLES}",
                        f"check at most {MAX_ROLES} roles at a time: use a smaller supercell "
                        "(docs/file-format.md, Limits)")
    seen: dict[str, int] = {}
    for i, r in enumerate(roles):
        if not isinstance(r, str) or not r:
            raise ctx.error(("roles", i), f"roles[{i}]={_r(r)} must be a non-empty string",
                            "quote role names that YAML reads as numbers, booleans or null "
                            "(e.g. '1', 'yes', 'null')")
        if r in seen:
            raise ctx.error(("roles", i), f"roles[{i}]={r!r} is listed twice (also roles[{seen[r]}])",
                            "give each role once")
        seen[r] = i
    return roles, seen


def _edge_rows(data: dict, ctx: _Ctx, roles: list, seen: dict, unit: str) -> list:
    """The rows ``(from, to, SE2)``: each a list of two declared roles and three bounded numbers."""
    edges = data["edges"]
    if edges is None:
        raise ctx.error(("edges",), "edges=None has no rows",
                        "write the rows under `edges:` as `- [from, to, x, y, theta]`, "
                        "or `edges: []` for a graph without edges")
    if not isinstance(edges, list):
        raise ctx.error(("edges",), f"edges={_r(edges)} must be a list of rows [from, to, x, y, theta]",
                        "write one row per line: `- [A, A, 1, 0, 0]`")
    if len(edges) > MAX_EDGES:
        raise ctx.error(("edges",), f"edges has {len(edges)} rows, more than the limit of {MAX_EDGES}",
                        f"check at most {MAX_EDGES} edges at a time: use a smaller supercell "
                        "(docs/file-format.md, Limits)")
    scale = math.pi / 180.0 if unit == "deg" else 1.0
    rows: list[tuple[str, str, SE2]] = []
    for i, row in enumerate(edges):
        if not isinstance(row, list):
            raise ctx.error(("edges", i), f"edges[{i}]={_r(row)} must be a list [from, to, x, y, theta]",
                            "write the row as `[from, to, x, y, theta]`")
        if len(row) != 5:
            raise ctx.error(("edges", i), f"edges[{i}]={_r(row)} has {len(row)} items, expected 5 "
                                          "[from, to, x, y, theta]",
                            "give exactly five items: two role names, x, y and theta")
        for j in (0, 1):
            r = row[j]
            if not isinstance(r, str) or r not in seen:
                raise ctx.error(("edges", i, j), f"edges[{i}][{j}]={_r(r)} is not a declared role",
                                f"use one of roles={list(roles)!r} or add {_r(r)} to roles")
        x, y, th = row[2], row[3], row[4]
        # the common case first (plain finite numbers within the bound); anything else is
        # judged, and refused with its message, by _number
        if not (type(x) in _PLAIN and type(y) in _PLAIN and type(th) in _PLAIN
                and -MAX_MAGNITUDE <= x <= MAX_MAGNITUDE and -MAX_MAGNITUDE <= y <= MAX_MAGNITUDE
                and -MAX_MAGNITUDE <= th <= MAX_MAGNITUDE):
            x = _number(ctx, ("edges", i, 2), x, "x")
            y = _number(ctx, ("edges", i, 3), y, "y")
            th = _number(ctx, ("edges", i, 4), th, f"theta (in {unit})")
        x, y, th = float(x), float(y), float(th)
        if (x or y) and math.hypot(x, y) < MIN_LENGTH:
            raise ctx.error(("edges", i), f"edges[{i}] has length {math.hypot(x, y):.3g}, below the bound "
                                          f"length >= {_e(MIN_LENGTH)} (or exactly 0)",
                            f"scale the whole lattice (every x, y and the range by one factor) so that every "
                            f"edge is at least {_e(MIN_LENGTH)} long, or write x=0 y=0 for a robot on its "
                            f"neighbour's spot")
        t = th * scale
        if not math.isfinite(t):  # pragma: no cover - scale <= 1 keeps it finite
            raise ctx.error(("edges", i, 4), f"edges[{i}][4]={row[4]!r} is too large", "use a smaller angle")
        rows.append((row[0], row[1], SE2(x, y, t)))
    return rows


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------

def _stem(source: str) -> str:
    base = os.path.basename(source)
    stem = os.path.splitext(base)[0]
    if source.startswith("library:"):
        return source.split(":", 1)[1]
    return stem if stem and not stem.startswith("<") else "unnamed"


def loads_lattice(text: str, fmt: str = "yaml", source: str = "<string>") -> LatticeGraph:
    """Parse a ``lattice-graph/1`` document from a string.

    Parameters
    ----------
    text : str
        The document.
    fmt : {"yaml", "json"}
        Its syntax.
    source : str
        Name used in error messages (a path, or ``library:NAME``).

    Returns
    -------
    LatticeGraph
        With ``range`` from the file (or None) and ``source`` set.

    Raises
    ------
    InputFileError
        For every problem in the document (file, line, field and fix named).
    UsageError
        If ``fmt`` is not ``"yaml"`` or ``"json"``.

    Examples
    --------
    >>> loads_lattice('{"format": "lattice-graph/2", "roles": ["A"], "edges": []}', "json")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: <string>:1: field 'format': format='lattice-graph/2' is not supported; this swarmproof reads only 'lattice-graph/1'; fix: write `format: lattice-graph/1` (and convert the file if it follows another version)
    """
    if fmt not in ("yaml", "json"):
        raise UsageError(f"fmt={fmt!r} is not a lattice file syntax", fix="use 'yaml' or 'json'")
    if not isinstance(text, str):
        raise UsageError(f"text must be str, got {type(text).__name__}", fix="decode the bytes as UTF-8 first")
    if not text.strip():
        raise InputFileError("the file is empty", file=source, line=1,
                             fix=f"write a {FORMAT} document (see docs/file-format.md)")
    parse: Callable = _parse_yaml if fmt == "yaml" else _parse_json
    data, lines = parse(text, source)
    return _document_to_graph(data, _Ctx(source, lines), _stem(source))


def load_lattice_file(path: str | os.PathLike) -> LatticeGraph:
    """Read a lattice graph file (``.yaml``/``.yml`` or ``.json``).

    Any other extension is tried as JSON, then as YAML.

    Raises
    ------
    InputFileError
        A missing, unreadable, empty or non-UTF-8 file, a directory, or any
        problem in the document.
    """
    try:
        source = os.fspath(path)
    except TypeError:
        raise UsageError(f"path={path!r} must be a file path", fix="pass a str or os.PathLike") from None
    if os.path.isdir(source):
        raise InputFileError("is a directory, not a lattice file", file=source,
                             fix="give the path of a .yaml or .json file")
    try:
        with open(source, "rb") as f:
            raw = f.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise InputFileError("no such file", file=source,
                             fix="check the path, or give a bundled lattice name "
                                 "(`swarmproof.models.library.names()`)") from None
    except PermissionError:
        raise InputFileError("permission denied: the file cannot be read", file=source,
                             fix="make the file readable (chmod u+r)") from None
    except OSError as exc:
        raise InputFileError(f"cannot read the file ({exc.strerror or exc})", file=source,
                             fix="give a readable regular file") from None
    if len(raw) > MAX_FILE_BYTES:
        try:
            size = f"{os.path.getsize(source) / 1e6:.1f} MB"
        except OSError:  # pragma: no cover - a pipe
            size = "larger"
        raise InputFileError(f"the file is {size}, more than the limit of {MAX_FILE_BYTES // 1_000_000} MB "
                             f"(and at most {MAX_ROLES} roles, {MAX_EDGES} edges)", file=source,
                             fix="check a smaller supercell of the lattice (docs/file-format.md, Limits)")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise InputFileError(f"byte {raw[exc.start:exc.start + 1]!r} at offset {exc.start} is not UTF-8 text",
                             file=source, line=line,
                             fix="save the file as UTF-8 text") from None
    ext = os.path.splitext(source)[1].lower()
    if ext in (".yaml", ".yml"):
        return loads_lattice(text, "yaml", source)
    if ext == ".json":
        return loads_lattice(text, "json", source)
    if not text.strip():
        return loads_lattice(text, "yaml", source)
    try:
        json.loads(text)
    except (ValueError, RecursionError):
        return loads_lattice(text, "yaml", source)
    return loads_lattice(text, "json", source)


class _Flow(list):
    """A list written in YAML flow style (``[a, b]``)."""


class _Dumper(yaml.SafeDumper):
    pass


_Dumper.add_representer(_Flow, lambda d, data: d.represent_sequence(
    "tag:yaml.org,2002:seq", list(data), flow_style=True))


def dump_lattice(graph: LatticeGraph, fmt: str = "yaml", angle_unit: str = "deg") -> str:
    """Serialize ``graph`` as ``lattice-graph/1`` text; deterministic.

    Coordinates are written with ``repr`` precision, so they read back
    bit-identically.  With ``angle_unit="rad"`` angles read back
    bit-identically too; with ``"deg"`` they do whenever the angle came from
    a decimal number of degrees (else within one unit in the last place).

    >>> from swarmproof.models.lattice import LatticeGraph
    >>> g = LatticeGraph("seg", ["A", "B"], [("A", "B", SE2(1, 0, 0)), ("B", "A", SE2(-1, 0, 0))], range=1.5)
    >>> print(dump_lattice(g), end="")
    format: lattice-graph/1
    name: seg
    range: 1.5
    angle_unit: deg
    roles: [A, B]
    edges:
    - [A, B, 1.0, 0.0, 0.0]
    - [B, A, -1.0, 0.0, 0.0]
    """
    if fmt not in ("yaml", "json"):
        raise UsageError(f"fmt={fmt!r} is not a lattice file syntax", fix="use 'yaml' or 'json'")
    doc = lattice_to_document(graph, angle_unit)
    if fmt == "json":
        parts = []
        for key, value in doc.items():
            if key == "edges":
                rows = ",\n".join("    " + json.dumps(r, allow_nan=False) for r in value)
                parts.append(f'  "edges": [\n{rows}\n  ]' if value else '  "edges": []')
            else:
                parts.append(f"  {json.dumps(key)}: {json.dumps(value, allow_nan=False)}")
        return "{\n" + ",\n".join(parts) + "\n}\n"
    doc["roles"] = _Flow(doc["roles"])
    doc["edges"] = [_Flow(r) for r in doc["edges"]]
    return yaml.dump(doc, Dumper=_Dumper, sort_keys=False, allow_unicode=True,
                     default_flow_style=False, width=10_000)


def save_lattice(graph: LatticeGraph, path: str | os.PathLike, angle_unit: str = "deg") -> str:
    """Write ``graph`` to ``path`` atomically; JSON for ``.json``, else YAML.

    Returns
    -------
    str
        The path written.
    """
    p = os.fspath(path)
    fmt = "json" if p.lower().endswith(".json") else "yaml"
    return atomic_write_text(p, dump_lattice(graph, fmt, angle_unit))


def schema_path() -> str:
    """Filesystem path of the shipped JSON Schema (draft 2020-12) of ``lattice-graph/1``."""
    from importlib import resources

    return str(resources.files(__package__) / "schemas" / "lattice-graph-1.schema.json")
