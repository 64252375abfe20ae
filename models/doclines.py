"""Parse a YAML or JSON document and remember the line of every field.

The one reader of YAML for every swarmproof file format (lattice graphs,
repeating patterns, campaign specs, initial configurations):
:func:`load_yaml` composes the text with libyaml's ``yaml.CSafeLoader`` where
PyYAML has it (else the pure-Python ``yaml.SafeLoader``; both safe: no
Python objects), refuses a key written twice in one mapping (naming both
lines), and returns the node tree so that errors can name the line of any
field.  :func:`parse_document` is the generic front end: JSON by
:func:`json.loads` (a repeated key refused too), YAML by :func:`load_yaml`;
it maps every field path such as ``("robots", 2, "pose", 1)`` to the line
where its value starts.

Examples
--------
>>> data, lines = parse_document('robots:\\n  - id: 1\\n    pose: [0, 0, 0]\\n', "yaml", "a.yaml")
>>> data["robots"][0]["id"], lines[("robots", 0, "pose")]
(1, 3)
>>> field_name(("robots", 0, "pose", 2))
'robots[0].pose[2]'
>>> parse_document('{"a": [1,}', "json", "b.json")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: b.json:1: malformed JSON: Expecting value (column 10); fix: check commas, brackets and double quotes near this line
>>> parse_document('name: x\\nname: y\\n', "yaml", "c.yaml")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: c.yaml:2: field 'name': key 'name' appears twice (lines 1 and 2); fix: keep one of them
"""

from __future__ import annotations

import json
import math
from typing import Any

import yaml
from yaml.events import (AliasEvent, CollectionEndEvent, MappingStartEvent, ScalarEvent,
                         SequenceStartEvent, StreamEndEvent)
from yaml.nodes import MappingNode, ScalarNode, SequenceNode

from .errors import InputFileError, UsageError

__all__ = ["parse_document", "load_yaml", "check_duplicate_keys", "field_name", "line_of", "read_text",
           "num_text", "distinct_texts", "text_number_fix", "YAML_MAX_DEPTH", "LIBYAML"]

#: Deepest nesting any swarmproof file format needs is five levels (a campaign cell's
#: ``start``); a document nested deeper than this is refused (``nesting is too deep``).
YAML_MAX_DEPTH = 64
#: True when PyYAML was built with libyaml: :func:`load_yaml` then parses in C.
LIBYAML = hasattr(yaml, "CSafeLoader")
_MERGE = "tag:yaml.org,2002:merge"


def field_name(path: tuple) -> str:
    """``("robots", 2, "pose")`` -> ``"robots[2].pose"``."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def line_of(lines: dict, path: tuple) -> int | None:
    """The line of ``path``, or of its nearest ancestor that has one."""
    path = tuple(path)
    while True:
        if path in lines:
            return lines[path]
        if not path:
            return None
        path = path[:-1]


def num_text(v: Any) -> str:
    """A number as a person reads it, with every digit that tells it apart: the shortest
    text that reads back as the same float (``repr``), a huge integer in %g style.

    >>> num_text(0.2), num_text(0.1 + 0.1 + 1e-17), num_text(0.30000000000000004)
    ('0.2', '0.2', '0.30000000000000004')
    >>> num_text(10 ** 308), num_text(1e-300), num_text(3), num_text(10 ** 400)
    ('1e+308', '1e-300', '3', 'an integer of 401 digits')
    """
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, int):
        if abs(v) < 10 ** 15:
            return str(v)
        try:
            return repr(float(v))
        except OverflowError:
            return f"an integer of {int(v.bit_length() * math.log10(2)) + 1} digits"
    r = repr(float(v))
    return r[:-2] if r.endswith(".0") and "e" not in r and len(r) <= 17 else r


def distinct_texts(a: float, b: float, digits: int = 4) -> tuple[str, str]:
    """``a`` and ``b`` with ``digits`` significant digits, or with as many more as it takes to
    show that they differ (a comparison message never reads "0.2 < 0.2").

    >>> distinct_texts(0.1936, 0.2), distinct_texts(0.19999999, 0.2)
    (('0.1936', '0.2'), ('0.19999999', '0.2'))
    """
    a, b = float(a), float(b)
    for d in range(digits, 18):
        ta, tb = f"{a:.{d}g}", f"{b:.{d}g}"
        if ta != tb or a == b:
            return ta, tb
    return repr(a), repr(b)


_EXP = None


def text_number_fix(s: str) -> str | None:
    """The fix for a number that YAML read as text, or None when ``s`` is not a number.

    PyYAML reads YAML 1.1, where a float needs a dot and a signed exponent: ``1e-3`` and
    ``1.0e308`` are text, ``1.0e-3`` and ``1.0e+308`` numbers.

    The text is appended to "write X as a plain number".

    >>> text_number_fix("1.0e308")
    ' (YAML 1.1 reads 1.0e308 as text: a float needs a dot and a signed exponent: write 1.0e+308)'
    >>> text_number_fix("1e-6"), text_number_fix("0.5"), text_number_fix("x")
    (' (YAML 1.1 reads 1e-6 as text: a float needs a dot and a signed exponent: write 1.0e-6)', ' without quotes', None)
    """
    import re

    global _EXP
    try:
        float(s)
    except (TypeError, ValueError):
        return None
    if _EXP is None:
        _EXP = re.compile(r"\s*([-+]?)(\d*)(?:\.(\d*))?[eE]([-+]?)(\d+)\s*")
    m = _EXP.fullmatch(s)
    if m and (m.group(3) is None or not m.group(4)) and (m.group(2) or m.group(3)):
        sign, whole, frac, esign, exp = m.groups()
        lit = f"{sign}{whole or '0'}.{frac or '0'}e{esign or '+'}{exp}"
        return f" (YAML 1.1 reads {s.strip()} as text: a float needs a dot and a signed exponent: write {lit})"
    return " without quotes"


# ---------------------------------------------------------------------------
# YAML: one safe, fast loader for every file format
# ---------------------------------------------------------------------------

def _loader_classes() -> tuple:
    """(fast, exact): the libyaml loader (or SafeLoader) and the pure-Python SafeLoader whose
    error messages the project's tests and docs quote."""
    fast = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

    class Fast(fast):   # resolution of a plain scalar depends only on its text here
        _cache: dict = {}

        def resolve(self, kind, value, implicit):
            if kind is ScalarNode:
                key = (value, implicit)
                tag = self._cache.get(key)
                if tag is None:
                    tag = super().resolve(kind, value, implicit)
                    if len(self._cache) > 50_000:
                        self._cache.clear()
                    self._cache[key] = tag
                return tag
            return super().resolve(kind, value, implicit)

    return Fast, yaml.SafeLoader


_FAST, _EXACT = _loader_classes()


class _TooDeep(Exception):
    pass


def _compose(loader) -> Any:
    """Compose one document from the loader's events without recursion (libyaml's own composer
    recurses in C and crashes on deep nesting); refuse nesting deeper than YAML_MAX_DEPTH."""
    loader.get_event()                       # StreamStart
    if loader.check_event(StreamEndEvent):
        loader.get_event()
        return None
    loader.get_event()                       # DocumentStart
    anchors: dict = {}
    stack: list = []
    root = None
    while root is None:
        ev = loader.get_event()
        if isinstance(ev, AliasEvent):
            if ev.anchor not in anchors:
                raise yaml.composer.ComposerError(None, None, f"found undefined alias {ev.anchor!r}",
                                                  ev.start_mark)
            node = anchors[ev.anchor]
        elif isinstance(ev, ScalarEvent):
            tag = ev.tag
            if tag is None or tag == "!":
                tag = loader.resolve(ScalarNode, ev.value, ev.implicit)
            node = ScalarNode(tag, ev.value, ev.start_mark, ev.end_mark, style=ev.style)
            if ev.anchor is not None:
                anchors[ev.anchor] = node
        elif isinstance(ev, (SequenceStartEvent, MappingStartEvent)):
            kind = SequenceNode if isinstance(ev, SequenceStartEvent) else MappingNode
            tag = ev.tag
            if tag is None or tag == "!":
                tag = loader.resolve(kind, None, ev.implicit)
            node = kind(tag, [], ev.start_mark, None, flow_style=ev.flow_style)
            if ev.anchor is not None:
                anchors[ev.anchor] = node
            stack.append([node, None])
            if len(stack) > YAML_MAX_DEPTH:
                raise _TooDeep
            continue
        elif isinstance(ev, CollectionEndEvent):
            node = stack.pop()[0]
            node.end_mark = ev.end_mark
        else:  # pragma: no cover - the parser emits nothing else inside a document
            raise yaml.composer.ComposerError(None, None, f"unexpected {type(ev).__name__}", ev.start_mark)
        if not stack:
            root = node
        else:
            top = stack[-1]
            if isinstance(top[0], SequenceNode):
                top[0].value.append(node)
            elif top[1] is None:
                top[1] = node
            else:
                top[0].value.append((top[1], node))
                top[1] = None
    loader.get_event()                       # DocumentEnd
    if not loader.check_event(StreamEndEvent):
        ev = loader.get_event()
        raise yaml.composer.ComposerError("expected a single document in the stream", root.start_mark,
                                          "but found another document", ev.start_mark)
    loader.get_event()
    return root


def check_duplicate_keys(node, source: str) -> None:
    """Refuse a key written twice in one mapping (YAML would keep the last one silently),
    naming both lines and the field.  Walks every mapping once (aliases are not re-walked)."""
    seen_nodes: set = set()
    todo = [(node, ())]
    while todo:
        n, path = todo.pop()
        if n is None or id(n) in seen_nodes:
            continue
        seen_nodes.add(id(n))
        if isinstance(n, MappingNode):
            keys: dict = {}
            for k, v in n.value:
                if isinstance(k, ScalarNode) and k.tag != _MERGE:
                    line = k.start_mark.line + 1
                    if k.value in keys:
                        p = path + (k.value,)
                        raise InputFileError(f"key {k.value!r} appears twice (lines {keys[k.value]} and {line})",
                                             file=source, line=line, field=field_name(p), fix="keep one of them")
                    keys[k.value] = line
                    todo.append((v, path + (k.value,)))
                else:
                    todo.append((v, path))
        elif isinstance(n, SequenceNode):
            todo.extend((v, path + (i,)) for i, v in enumerate(n.value)
                        if not isinstance(v, ScalarNode))


def _load_with(cls, text: str, source: str | None = None) -> tuple[Any, Any]:
    loader = cls(text)
    try:
        node = _compose(loader)
        if source is not None and node is not None:   # before construction merges `<<` keys in
            check_duplicate_keys(node, source)
        data = None if node is None else loader.construct_document(node)
    finally:
        loader.dispose()
    return data, node


def load_yaml(text: str, source: str, *, nesting: str = "write a flatter document") -> tuple[Any, Any]:
    """Parse one YAML document safely: ``(data, root node)``; the node gives every field's line.

    libyaml parses where PyYAML has it; a key written twice in one mapping is refused; nesting
    deeper than :data:`YAML_MAX_DEPTH` is refused with ``nesting`` as the fix.  Every problem is
    an :class:`InputFileError` naming the file and, where known, the line (with PyYAML's
    pure-Python wording of the error).

    >>> load_yaml("a: [1, 2.5, x]", "s.yaml")[0]
    {'a': [1, 2.5, 'x']}
    >>> load_yaml("[" * 100 + "]" * 100, "d.yaml", nesting="a lattice file nests three levels")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: d.yaml: malformed YAML: nesting is too deep (more than 64 levels); fix: a lattice file nests three levels
    """
    try:
        try:
            data, node = _load_with(_FAST, text, source)
        except yaml.YAMLError:
            if _FAST is _EXACT or issubclass(_FAST, _EXACT):
                raise
            data, node = _load_with(_EXACT, text, source)   # the pure-Python parser's wording of the error
    except InputFileError:   # a key written twice
        raise
    except _TooDeep:
        raise InputFileError(f"malformed YAML: nesting is too deep (more than {YAML_MAX_DEPTH} levels)",
                             file=source, fix=nesting) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        what = " ".join(" ".join(str(p).split()) for p in (exc.context, exc.problem) if p)
        raise InputFileError(f"malformed YAML: {what}", file=source, line=line,
                             fix="check indentation, brackets and quoting near this line; "
                                 "quote values that contain ':' or '#'") from None
    except yaml.reader.ReaderError as exc:
        line = text.count("\n", 0, exc.position) + 1 if isinstance(exc.position, int) else None
        ch = chr(exc.character) if isinstance(exc.character, int) else exc.character
        raise InputFileError(f"malformed YAML: character {ch!r} is not allowed in YAML text",
                             file=source, line=line,
                             fix="remove control characters; save the file as plain UTF-8 text") from None
    except yaml.YAMLError as exc:
        what = " ".join(str(exc).split())
        raise InputFileError(f"malformed YAML: {what}", file=source,
                             fix="check the file is one YAML document") from None
    except RecursionError:
        raise InputFileError("malformed YAML: nesting is too deep", file=source, fix=nesting) from None
    except (ValueError, TypeError, OverflowError) as exc:  # e.g. a timestamp 2020-13-45
        raise InputFileError(f"malformed YAML: a value cannot be read ({exc})", file=source,
                             fix="quote the value or write a plain number") from None
    return data, node


def node_lines(node, max_depth: int = 50) -> dict:
    """Every field path of a composed document -> the 1-based line where its value starts
    (each aliased node is walked once)."""
    lines: dict = {}
    if node is None:
        return lines
    seen: set = set()
    todo = [(node, (), 0)]
    while todo:
        n, path, depth = todo.pop()
        lines.setdefault(path, n.start_mark.line + 1)
        if depth > max_depth or id(n) in seen:
            continue
        seen.add(id(n))
        if isinstance(n, MappingNode):
            for k, v in n.value:
                if isinstance(k, ScalarNode):
                    todo.append((v, path + (k.value,), depth + 1))
        elif isinstance(n, SequenceNode):
            todo.extend((v, path + (i,), depth + 1) for i, v in enumerate(n.value))
    return lines


def _json_pairs(pairs):
    d: dict = {}
    for k, v in pairs:
        if k in d:
            raise _DuplicateJsonKey(k)
        d[k] = v
    return d


class _DuplicateJsonKey(Exception):
    def __init__(self, key) -> None:
        super().__init__(key)
        self.key = key


def load_json(text: str, source: str, *, nesting: str = "write a flatter document") -> Any:
    """Parse JSON; a key written twice in one object is refused (JSON readers disagree on
    which one wins), every problem an :class:`InputFileError` naming the file and line."""
    if text.startswith("\ufeff"):
        text = text[1:]
    try:
        return json.loads(text, object_pairs_hook=_json_pairs)
    except json.JSONDecodeError as exc:
        raise InputFileError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=source,
                             line=exc.lineno,
                             fix="check commas, brackets and double quotes near this line") from None
    except _DuplicateJsonKey as exc:
        key = exc.key
        hits = [i for i, ln in enumerate(text.splitlines(), 1) if json.dumps(key) in ln]
        where = f" (lines {', '.join(map(str, hits[:4]))})" if len(hits) > 1 else ""
        raise InputFileError(f"key {key!r} appears twice in one object{where}", file=source,
                             line=hits[1] if len(hits) > 1 else None, field=key,
                             fix="keep one of them") from None
    except RecursionError:
        raise InputFileError("malformed JSON: nesting is too deep", file=source, fix=nesting) from None
    except (ValueError, TypeError, OverflowError) as exc:  # e.g. an integer with 5000 digits
        r = str(exc)
        raise InputFileError(f"malformed JSON: a value cannot be read ({r[:80]})",
                             file=source, fix="write plain numbers of ordinary size") from None


def parse_document(text: str, fmt: str, source: str) -> tuple[Any, dict]:
    """Parse ``text`` (``fmt`` is ``"yaml"`` or ``"json"``); return ``(data, lines)``.

    Raises
    ------
    InputFileError
        Malformed text (with the line where the parser stopped), a key written twice.
    """
    if fmt == "json":
        data = load_json(text, source)
        try:    # JSON is YAML: the YAML composer finds the lines (a courtesy: lines may stay unknown)
            _, node = _load_with(_FAST, text[1:] if text.startswith("\ufeff") else text)
        except Exception:
            node = None
        return data, node_lines(node)
    if fmt == "yaml":
        data, node = load_yaml(text, source)
        return data, node_lines(node)
    raise UsageError(f"fmt={fmt!r} must be 'yaml' or 'json'")


def read_text(path, *, what: str, fix: str, max_bytes: int) -> str:
    """Read a UTF-8 input file of at most ``max_bytes`` characters; every failure an
    :class:`InputFileError` naming the file and a fix (``what`` names the kind of file,
    ``fix`` says what to give instead of a missing one).

    >>> read_text("no/such.yaml", what="campaign file", fix="give a campaign file", max_bytes=10)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: no/such.yaml: campaign file='no/such.yaml' does not exist; fix: give a campaign file
    """
    import os

    name = os.fspath(path)
    try:
        with open(name, encoding="utf-8") as fh:
            text = fh.read(max_bytes + 1)
    except FileNotFoundError:
        raise InputFileError(f"{what}={name!r} does not exist", file=name, fix=fix) from None
    except IsADirectoryError:
        raise InputFileError(f"{what}={name!r} is a folder", file=name, fix="give the path of a file") from None
    except OSError as exc:
        raise InputFileError(f"cannot read {what}={name!r} ({exc.strerror})", file=name,
                             fix="check the path and its permissions") from None
    except UnicodeDecodeError as exc:
        raise InputFileError(f"the file is not UTF-8 text (byte {exc.start})", file=name,
                             fix="save it as UTF-8 text") from None
    if len(text) > max_bytes:
        raise InputFileError(f"the {what} is larger than {max_bytes // 1_000_000} MB", file=name,
                             fix=f"a {what} is a few lines")
    return text
