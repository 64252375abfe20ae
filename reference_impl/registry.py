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

__all__ = ["ALGORITHMS", "get_algorithm", "algorithm_names", "algorithm_factory"]

#: Registry name -> ``"module:factory"``.
ALGORITHMS: dict[str, str] = {
    "song2016": "swarmproof.reference_impl.song2016:Song2016",
    "song2014": "swarmproof.reference_impl.song2014:Song2014",
    "example-gather": "swarmproof.reference_impl.examples:GatherToLowestId",
}


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
