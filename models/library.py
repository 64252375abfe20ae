"""The bundled library of lattice graphs, loadable by name.

Each lattice is a ``lattice-graph/1`` YAML file in ``models/library/`` with unit
edge length, a recommended ``range`` strictly inside the interval of ranges for
which it is self-consistent (001 Def. 4), and a comment citing its source.
docs/library.md tables them.

==================== ===== ===== ============ ================ ===========
name                 roles edges kind         valid range      recommended
==================== ===== ===== ============ ================ ===========
square               1     4     periodic     (1, sqrt 2]      1.2
hexagon              2     6     periodic     (1, sqrt 3]      1.5
octagon-square       4     12    periodic     (1, sqrt 2]      1.2
triangle             1     6     periodic     (1, sqrt 3]      1.5
kagome               3     12    periodic     (1, sqrt 3]      1.5
honeycomb-rotating   1     3     periodic     (1, sqrt 3]      1.5
hexagon-ring         1     2     finite       (1, sqrt 3]      1.5
letter-f             5     20    finite       (sqrt 5, inf)    2.5
==================== ===== ===== ============ ================ ===========

References
----------
000_3ad33c5b62f11d5f.txt, Figs. 2, 3, 7 (square, hexagon, octagon-square), Sec. V
and Fig. 11 (letter F).
001_7a4e517b856331bc.txt, Sec. III-B, Figs. 3-5.

Examples
--------
>>> names()[:3]
['hexagon', 'hexagon-ring', 'honeycomb-rotating']
>>> g = load("square")
>>> g.roles, len(g.edges), g.range, g.source
(('A',), 4, 1.2, 'library:square')
>>> load("sqare")
Traceback (most recent call last):
...
swarmproof.models.errors.UsageError: lattice='sqare' is not a bundled lattice; fix: use one of ['hexagon', 'hexagon-ring', 'honeycomb-rotating', 'kagome', 'letter-f', 'octagon-square', 'square', 'triangle']
"""

from __future__ import annotations

import os
from importlib import resources

from .errors import InputFileError, UsageError, did_you_mean
from .lattice import LatticeGraph
from .lattice_io import load_lattice_file, loads_lattice

__all__ = ["names", "load", "resolve", "text"]

_SUFFIX = ".yaml"


def _folder():
    return resources.files(__package__) / "library"


def names() -> list[str]:
    """Names of the bundled lattices, sorted."""
    return sorted(p.name[: -len(_SUFFIX)] for p in _folder().iterdir()
                  if p.name.endswith(_SUFFIX) and p.is_file())


def _check_name(name: str) -> str:
    if not isinstance(name, str) or name not in names():
        raise UsageError(f"lattice={name!r} is not a bundled lattice", fix=f"use one of {names()!r}")
    return name


def text(name: str) -> str:
    """The YAML text of bundled lattice ``name`` (with its source comments).

    Raises
    ------
    UsageError
        If ``name`` is not one of :func:`names` (the message lists them).
    """
    return (_folder() / (_check_name(name) + _SUFFIX)).read_text(encoding="utf-8")


def load(name: str) -> LatticeGraph:
    """Load bundled lattice ``name``; its ``source`` is ``'library:NAME'``.

    Raises
    ------
    UsageError
        If ``name`` is not one of :func:`names` (the message lists them).
    """
    return loads_lattice(text(name), "yaml", source=f"library:{name}")


def resolve(name_or_path: str | os.PathLike) -> LatticeGraph:
    """A lattice from a file path or a bundled name; an existing path wins.

    Raises
    ------
    InputFileError
        If the argument is neither an existing path nor a bundled name, or the
        file is invalid.

    Examples
    --------
    >>> resolve("hexagon").roles
    ('A', 'B')
    >>> resolve("no/such/file.yaml")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: no/such/file.yaml: no such file and no bundled lattice of that name; fix: give the path of a lattice-graph/1 file or one of the bundled names ['hexagon', 'hexagon-ring', 'honeycomb-rotating', 'kagome', 'letter-f', 'octagon-square', 'square', 'triangle']
    """
    try:
        path = os.fspath(name_or_path)
    except TypeError:
        raise UsageError(f"lattice={name_or_path!r} must be a name or a path",
                         fix=f"give a file path or one of {names()!r}") from None
    if os.path.exists(path):
        return load_lattice_file(path)
    if path in names():
        return load(path)
    raise InputFileError(f"no such file and no bundled lattice of that name{did_you_mean(path, names())}", file=path,
                         fix=f"give the path of a lattice-graph/1 file or one of the bundled names {names()!r}")
