"""The ``lattice-graph/1`` document of a lattice graph as plain data (a dict in file order).

:mod:`swarmproof.models.lattice_io` reads and writes the format as YAML or JSON text;
this module holds what both a graph and the file reader need of it: the format's name,
its angle units, and the document of a graph.  It imports no lattice module (a graph is
read through its ``name``, ``range``, ``roles`` and ``edges``), so
:meth:`~swarmproof.models.lattice.LatticeGraph.describe` can embed a graph's document
and :mod:`~swarmproof.models.lattice_io` can build graphs without an import circle.

References
----------
001_7a4e517b856331bc.txt, Sec. III-B, Definitions 1-2 (what an edge means).

Examples
--------
>>> FORMAT, ANGLE_UNITS
('lattice-graph/1', ('deg', 'rad'))
"""

from __future__ import annotations

import math
from typing import Any

from .errors import UsageError
from .se2 import wrap_angle

__all__ = ["FORMAT", "ANGLE_UNITS", "lattice_to_document"]

#: The one format version swarmproof reads and writes.
FORMAT = "lattice-graph/1"
#: The units a document's ``angle_unit`` may name.
ANGLE_UNITS = ("deg", "rad")


def _deg(theta: float) -> float:
    """A degree value that reads back (via radians and wrapping) to exactly ``theta``
    when one exists among short decimals; else the plain conversion."""
    d = math.degrees(theta)
    for k in range(0, 16):
        c = round(d, k)
        if wrap_angle(math.radians(c)) == theta:
            return c + 0.0
    return d


def lattice_to_document(graph, angle_unit: str = "deg") -> dict:
    """The ``lattice-graph/1`` document of ``graph`` as a plain dict (keys in file order).

    Parameters
    ----------
    graph : LatticeGraph
        The graph (read through ``name``, ``range``, ``roles`` and ``edges``).
    angle_unit : {"deg", "rad"}
        The unit of every edge's ``theta`` in the document.

    Returns
    -------
    dict

    Raises
    ------
    UsageError
        An unknown ``angle_unit``.

    Examples
    --------
    >>> from swarmproof.models.lattice import LatticeGraph
    >>> from swarmproof.models.se2 import SE2
    >>> g = LatticeGraph("seg", ["A", "B"], [("A", "B", SE2(1, 0, math.pi)), ("B", "A", SE2(1, 0, math.pi))])
    >>> lattice_to_document(g)["edges"]
    [['A', 'B', 1.0, 0.0, -180.0], ['B', 'A', 1.0, 0.0, -180.0]]
    """
    if angle_unit not in ANGLE_UNITS:
        raise UsageError(f"angle_unit={angle_unit!r} is not a known unit", fix="use 'deg' or 'rad'")
    doc: dict[str, Any] = {"format": FORMAT, "name": graph.name}
    if graph.range is not None:
        doc["range"] = float(graph.range)
    doc["angle_unit"] = angle_unit
    doc["roles"] = list(graph.roles)
    doc["edges"] = [
        [e.source, e.target, e.transform.x, e.transform.y,
         _deg(e.transform.theta) if angle_unit == "deg" else e.transform.theta]
        for e in graph.edges
    ]
    return doc
