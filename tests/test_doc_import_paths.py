"""Every import path the documentation names resolves (README.md and docs/*.md).

A module that moves (issue 28 moved every paper's code into ``reference_impl/<paper>/``) leaves
its old dotted name behind in the Markdown, where nothing imports it.  This test collects from
each Markdown file:

- dotted names under the namespace, ``swarmproof.a.b`` and ``swarmproof.a.b.Attr.attr``;
- ``module:qualname`` references whose module is swarmproof's (``swarmproof.a.b:Class``: the
  module must import and the qualname resolve on it, as the registry and the CLI read them);
- the short forms the docs use inside backticks, ``models.x.y``, ``invariants.x``,
  ``reference_impl.x``, ``checkers.x`` (read as ``swarmproof.models.x.y``, ...);
- ``from swarmproof.a import B, C`` and ``import swarmproof.a`` lines of the code blocks.

Each is resolved from the left: while the object is a package the next part is imported as a
submodule, otherwise it is an attribute (``a.b.C``: import ``a.b``, getattr ``C``).  A name
that does not resolve is listed with its file and line.  Names that are not import paths
(an entry-point group, an output file name, a pattern) are in :data:`NOT_IMPORT_PATHS`.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Names that look like import paths but are not, with the reason.
NOT_IMPORT_PATHS: dict[str, str] = {
    "swarmproof.algorithms": "the entry-point group of plug-in algorithms",
    "swarmproof.SECTION.SUBJECT": "the JUnit classname pattern of docs/ci.md",
}
#: ``swarmproof.md`` and the like are file names (docs/ci.md's report outputs).
FILE_SUFFIXES = {"md", "html", "xml", "json", "yaml", "yml", "txt", "png", "csv", "gif", "py", "toml"}

_IDENT = r"[A-Za-z_]\w*"
_DOTTED = rf"{_IDENT}(?:\.{_IDENT})*"
#: ``swarmproof.a.b`` or ``swarmproof.a.b:Qual.name``, not inside a longer word or path.
_FULL = re.compile(rf"(?<![\w./-])(swarmproof(?:\.{_IDENT})+(?::{_DOTTED})?)")
#: the short forms, inside backticks only: `models.x.y`, `reference_impl.x:Y`, ...
_SHORT = re.compile(rf"`((?:models|invariants|reference_impl|checkers)(?:\.{_IDENT})+(?::{_DOTTED})?)")
#: ``from swarmproof.x import a, b as c`` (parenthesised lists may span lines) and ``import swarmproof.x``.
_FROM = re.compile(rf"^\s*from\s+(swarmproof(?:\.{_IDENT})*)\s+import\s+(\([^)]*\)|[^\n#]+)", re.M)
_IMPORT = re.compile(rf"^\s*import\s+(swarmproof(?:\.{_IDENT})*)", re.M)


def markdown_files() -> list[Path]:
    """README.md and docs/*.md."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def collect(path: Path) -> dict[str, list[str]]:
    """The import paths ``path`` names: name -> ``["file:line", ...]`` (short forms under ``swarmproof.``)."""
    text = path.read_text(encoding="utf-8")
    found: dict[str, list[str]] = {}

    def add(name: str, offset: int) -> None:
        where = f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}:{text.count(chr(10), 0, offset) + 1}"
        found.setdefault(name, []).append(where)

    for m in _FULL.finditer(text):
        add(m.group(1), m.start(1))
    for m in _SHORT.finditer(text):
        add("swarmproof." + m.group(1), m.start(1))
    for m in _FROM.finditer(text):
        for item in m.group(2).strip("()").replace("\n", " ").split(","):
            item = item.split(" as ")[0].strip()
            if re.fullmatch(_IDENT, item):
                add(f"{m.group(1)}.{item}", m.start(1))
    for m in _IMPORT.finditer(text):
        add(m.group(1), m.start(1))
    return {name: where for name, where in found.items()
            if name not in NOT_IMPORT_PATHS and name.rsplit(".", 1)[-1] not in FILE_SUFFIXES}


def resolve(name: str) -> object:
    """The object ``name`` names (``a.b.C`` or ``a.b:C.d``); raises ImportError or AttributeError.

    >>> resolve("swarmproof.reference_impl.registry.ALGORITHMS")["song2016"]
    'swarmproof.reference_impl.song2016.algorithm:Song2016'
    """
    module, _, qualname = name.partition(":")
    parts = module.split(".")
    obj = importlib.import_module(parts[0])
    done = parts[0]
    for part in parts[1:]:
        done = f"{done}.{part}"
        if hasattr(obj, "__path__"):             # a package: the next part may be a submodule
            try:
                obj = importlib.import_module(done)
                continue
            except ModuleNotFoundError as exc:
                if exc.name != done:             # the submodule exists but imports something missing
                    raise
        if qualname:                             # module:qualname: everything left of ':' is a module
            raise ModuleNotFoundError(f"no module named {done!r}", name=done)
        if not hasattr(obj, part):
            raise AttributeError(f"{getattr(obj, '__name__', type(obj).__name__)!r} has no "
                                 f"{'submodule or ' if hasattr(obj, '__path__') else ''}attribute {part!r}")
        obj = getattr(obj, part)
    for part in qualname.split(".") if qualname else ():
        obj = getattr(obj, part)
    return obj


def unresolved(paths) -> list[str]:
    """One line per name in ``paths`` that does not resolve: where it is written, and why."""
    names: dict[str, list[str]] = {}
    for path in paths:
        for name, where in collect(path).items():
            names.setdefault(name, []).extend(where)
    bad = []
    for name, where in sorted(names.items()):
        try:
            resolve(name)
        except (ImportError, AttributeError) as exc:
            bad.append(f"{name} ({', '.join(where)}): {type(exc).__name__}: {exc}")
    return bad


def test_every_import_path_in_the_docs_resolves():
    files = markdown_files()
    assert len(files) > 10 and all(f.exists() for f in files)
    assert sum(len(collect(f)) for f in files) > 30       # the collector still finds the docs' names
    bad = unresolved(files)
    assert not bad, "import paths named in the docs that do not resolve:\n" + "\n".join(bad)


@pytest.mark.parametrize("name, reason", [
    ("swarmproof.reference_impl.song2016_geometry", "no submodule or attribute"),  # moved by issue 28
    ("swarmproof.reference_impl.song2016.geometry.no_such_function", "has no attribute 'no_such"),
    ("swarmproof.reference_impl.song2016.algorithm:NoSuchClass", "AttributeError"),
    ("swarmproof.reference_impl.song2016.Song2016:step", "ModuleNotFoundError"),  # ':' needs a module
], ids=["old-module", "missing-attribute", "missing-qualname", "class-before-colon"])
def test_a_path_that_does_not_resolve_is_listed_with_its_line(tmp_path, name, reason):
    md = tmp_path / "doc.md"
    md.write_text(f"# A doc\n\nSee `{name}` and `swarmproof.models.se2`.\n", encoding="utf-8")
    bad = unresolved([md])
    assert len(bad) == 1 and bad[0].startswith(f"{name} (") and ":3)" in bad[0] and reason in bad[0]


def test_the_collector_reads_short_forms_and_import_lines(tmp_path):
    md = tmp_path / "doc.md"
    md.write_text("`invariants.metrics.fulfillment_ratio`, swarmproof.md, swarmproof.algorithms\n"
                  "```python\nfrom swarmproof.models.se2 import (wrap_angle,\n    angle_diff as diff)\n"
                  "import swarmproof.checkers.replay\n```\n", encoding="utf-8")
    assert sorted(collect(md)) == ["swarmproof.checkers.replay", "swarmproof.invariants.metrics.fulfillment_ratio",
                                   "swarmproof.models.se2", "swarmproof.models.se2.angle_diff",
                                   "swarmproof.models.se2.wrap_angle"]
    assert unresolved([md]) == []
