"""The algorithms swarmproof knows by name, imported lazily.

``ALGORITHMS`` maps a registry name to ``"module:factory"``; the factory is
called with keyword options (if any) and returns an object following
:class:`~swarmproof.reference_impl.protocol.Algorithm`.  Modules are imported
only when asked for, so a broken or slow algorithm module never slows down
the rest.

Examples
--------
>>> "example-gather" in algorithm_names()
True
>>> get_algorithm("example-gather").name
'example-gather'
>>> get_algorithm("song2099")
Traceback (most recent call last):
...
swarmproof.models.errors.UsageError: algorithm='song2099' is not known; fix: use one of ['example-gather', 'song2014', 'song2016']
"""

from __future__ import annotations

import importlib
import inspect

from swarmproof.models.errors import UsageError

__all__ = ["ALGORITHMS", "CLAIMS", "PROPERTIES", "get_algorithm", "algorithm_names",
           "algorithm_factory", "claims_of"]

#: Registry name -> ``"module:factory"``.
ALGORITHMS: dict[str, str] = {
    "song2016": "swarmproof.reference_impl.song2016:Song2016",
    "song2014": "swarmproof.reference_impl.song2014:Song2014",
    "example-gather": "swarmproof.reference_impl.examples:GatherToLowestId",
}


#: The properties swarmproof judges a run by (``swarmproof verify`` rows; the
#: explorer's property names).
PROPERTIES: tuple[str, ...] = ("termination", "formation", "connectivity", "tree_links")

#: What each paper claims, property -> citation; ``None`` marks a property the
#: paper does NOT claim (a violation is then a finding about the algorithm,
#: shown in the matrix, not a failed claim).  A new algorithm registers its
#: claims here and needs no change in checkers/.
CLAIMS: dict[str, dict[str, str | None]] = {
    "song2016": {
        "termination": "001 Thm. 13 (all robots static in finite time)",
        "formation": "001 Thm. 13 (final configuration satisfies the lattice, Def. 2)",
        "connectivity": "001 Lemma 11 (communication graph stays connected)",
        "tree_links": "001 Lemma 11, Sec. V-C (NCLB keeps every spanning-tree link)",
    },
    "song2014": {
        "termination": None,   # 001 Sec. I: "no guarantee that the robots will eventually ... terminate"
        "formation": None,     # 001 Sec. I: "no guarantee that the robots will eventually form the desired pattern"
        "connectivity": None,  # 001 Sec. I: orphans' motion "often caused the team to become disconnected"
        "tree_links": "000 Lemma 7 (a descendant stays within range of its parent)",
    },
    "example-gather": {p: None for p in ("termination", "formation", "connectivity", "tree_links")},
}


def claims_of(name: str) -> dict[str, str | None]:
    """Property -> citation (or None when not claimed) for a registered algorithm.

    >>> claims_of("song2014")["connectivity"] is None
    True
    """
    algorithm_factory(name)
    return dict(CLAIMS.get(name, {p: None for p in PROPERTIES}))


def algorithm_names() -> list[str]:
    """The registered names, sorted."""
    return sorted(ALGORITHMS)


def algorithm_factory(name: str):
    """The factory (usually the class) registered under ``name``."""
    if not isinstance(name, str) or name not in ALGORITHMS:
        raise UsageError(f"algorithm={name!r} is not known", fix=f"use one of {algorithm_names()!r}")
    modname, _, attr = ALGORITHMS[name].partition(":")
    try:
        mod = importlib.import_module(modname)
    except ImportError as exc:
        raise UsageError(f"algorithm={name!r} cannot be loaded ({exc})",
                         fix=f"use one of {algorithm_names()!r}") from None
    try:
        return getattr(mod, attr)
    except AttributeError:
        raise UsageError(f"algorithm={name!r}: {modname} has no {attr!r}",
                         fix=f"use one of {algorithm_names()!r}") from None


def get_algorithm(name: str, *, n_robots: int | None = None, **options):
    """A fresh algorithm object for ``name``, built with keyword ``options``.

    ``n_robots`` is passed on only to factories that accept a keyword of that
    name (song2016 sets its timeouts to the number of robots, 001 Sec. VI);
    others never see it.

    >>> get_algorithm("example-gather", n_robots=5).name
    'example-gather'
    """
    factory = algorithm_factory(name)
    if n_robots is not None:
        try:
            accepts = "n_robots" in inspect.signature(factory).parameters
        except (TypeError, ValueError):  # pragma: no cover - builtins without signatures
            accepts = False
        if accepts:
            options["n_robots"] = n_robots
    return factory(**options)
