"""Parse a YAML or JSON document and remember the line of every field.

A small generic helper for file formats whose errors must name the file,
the 1-based line and the field (DESIGN.md section 3).  The lattice loader
(:mod:`swarmproof.models.lattice_io`) has its own format-specific mapping;
this one walks any document: it parses with :func:`json.loads` (JSON) or
``yaml.SafeLoader`` (YAML), then composes the text as YAML nodes (JSON is
YAML too) to map every field path such as ``("robots", 2, "pose", 1)`` to
the line where its value starts.

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
"""

from __future__ import annotations

import json
from typing import Any

import yaml

from .errors import InputFileError, UsageError

__all__ = ["parse_document", "field_name", "line_of", "read_text"]


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


def _walk(node, path: tuple, lines: dict, depth: int = 0) -> None:
    lines[path] = node.start_mark.line + 1
    if depth > 50:
        return
    if isinstance(node, yaml.MappingNode):
        for k, v in node.value:
            if isinstance(k, yaml.ScalarNode):
                _walk(v, path + (k.value,), lines, depth + 1)
    elif isinstance(node, yaml.SequenceNode):
        for i, v in enumerate(node.value):
            _walk(v, path + (i,), lines, depth + 1)


def _lines(text: str) -> dict:
    try:
        loader = yaml.SafeLoader(text)
        try:
            node = loader.get_single_node()
        finally:
            loader.dispose()
    except Exception:  # the text parsed already; lines are a courtesy
        return {}
    lines: dict = {}
    if node is not None:
        _walk(node, (), lines)
    return lines


def parse_document(text: str, fmt: str, source: str) -> tuple[Any, dict]:
    """Parse ``text`` (``fmt`` is ``"yaml"`` or ``"json"``); return ``(data, lines)``.

    Raises
    ------
    InputFileError
        Malformed text (with the line where the parser stopped).
    """
    if fmt == "json":
        if text.startswith("\ufeff"):
            text = text[1:]
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputFileError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=source,
                                 line=exc.lineno,
                                 fix="check commas, brackets and double quotes near this line") from None
        except (RecursionError, ValueError) as exc:
            raise InputFileError(f"malformed JSON: {exc}", file=source) from None
    elif fmt == "yaml":
        try:
            data = yaml.safe_load(text)
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            what = " ".join(str(p) for p in (exc.context, exc.problem) if p)
            raise InputFileError(f"malformed YAML: {what}", file=source,
                                 line=None if mark is None else mark.line + 1,
                                 fix="check indentation, brackets and quoting near this line") from None
        except (yaml.YAMLError, RecursionError, ValueError, TypeError) as exc:
            raise InputFileError(f"malformed YAML: {exc}", file=source) from None
    else:
        raise UsageError(f"fmt={fmt!r} must be 'yaml' or 'json'")
    return data, _lines(text)


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
