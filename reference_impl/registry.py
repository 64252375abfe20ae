"""The algorithms swarmproof knows by name, imported lazily.

``ALGORITHMS`` maps a registry name to ``"module:factory"``; the factory is
called with keyword options (if any) and returns an object following
:class:`~swarmproof.reference_impl.protocol.Algorithm`.  Modules are imported
only when asked for, so a broken or slow algorithm module never slows down
the rest.  Everything else the checkers need of an algorithm -- what its paper
claims, the lemma premises its proof uses, what ``swarmproof verify`` runs of
it -- is declared on its class (``claims``, ``premise_monitors``, ``verify``;
:class:`~swarmproof.reference_impl.protocol.Algorithm`), so a new algorithm is
one module and one line here (or one entry point in another package).

Examples
--------
>>> "example-gather" in algorithm_names()
True
>>> get_algorithm("example-gather").name
'example-gather'
>>> get_algorithm("wang2099")
Traceback (most recent call last):
...
swarmproof.models.errors.UsageError: algorithm='wang2099' is not known; did you mean 'wang2020'?; fix: use one of ['example-anonymous-line', 'example-gather', 'example-grid-goals', 'jiang', 'jiang-literal', 'leechong-leader', 'leechong-leader-fteam', 'leechong-leader-printed', 'leechong-neighbor', 'leechong-neighbor-fteam', 'leechong-neighbor-printed', 'song2014', 'song2016', 'song2016-literal', 'song2016-subtree-clock', 'wang2020', 'wang2020-broadcast-handshake']
"""

from __future__ import annotations

import importlib
import inspect
import sys
from typing import NamedTuple

from swarmproof.models.errors import UsageError, did_you_mean

__all__ = ["ALGORITHMS", "ALIASES", "Alias", "ENTRY_POINT_GROUP", "LEMMA_SETS", "READINGS", "RETIRED_READINGS",
           "get_algorithm", "resolve_alias",
           "algorithm_names", "algorithm_factory", "claims_of", "verify_plans", "lemma_sets", "reading_of_name",
           "find_reading"]

#: swarmproof's own algorithms: registry name -> ``"module:factory"``.  Another
#: package adds its own under the entry-point group :data:`ENTRY_POINT_GROUP`
#: (``[project.entry-points."swarmproof.algorithms"]`` in its pyproject.toml,
#: ``name = "package.module:Class"``); a name taken here wins.
ALGORITHMS: dict[str, str] = {
    "song2016": "swarmproof.reference_impl.song2016:Song2016",
    "song2016-literal": "swarmproof.reference_impl.song2016:Song2016Literal",
    "song2016-subtree-clock": "swarmproof.reference_impl.song2016:Song2016SubtreeClock",
    "song2014": "swarmproof.reference_impl.song2014:Song2014",
    "jiang": "swarmproof.reference_impl.jiang:Jiang",
    "jiang-literal": "swarmproof.reference_impl.jiang:JiangLiteral",
    "leechong-leader": "swarmproof.reference_impl.leechong:LeeChongLeader",
    "leechong-leader-printed": "swarmproof.reference_impl.leechong:LeeChongLeaderPrinted",
    "leechong-leader-fteam": "swarmproof.reference_impl.leechong:LeeChongLeaderFTeam",
    "leechong-neighbor": "swarmproof.reference_impl.leechong:LeeChongNeighbor",
    "leechong-neighbor-printed": "swarmproof.reference_impl.leechong:LeeChongNeighborPrinted",
    "leechong-neighbor-fteam": "swarmproof.reference_impl.leechong:LeeChongNeighborFTeam",
    "example-gather": "swarmproof.reference_impl.examples:GatherToLowestId",
    "example-anonymous-line": "swarmproof.reference_impl.examples:AnonymousLine",
    "example-grid-goals": "swarmproof.reference_impl.examples:GridGoals",
    "wang2020": "swarmproof.reference_impl.wang2020:Wang2020",
    "wang2020-broadcast-handshake": "swarmproof.reference_impl.wang2020:Wang2020BroadcastHandshake",
}

ENTRY_POINT_GROUP = "swarmproof.algorithms"


class Alias(NamedTuple):
    """An old registry name kept working (:data:`ALIASES`)."""

    #: the registry name it runs now
    name: str
    #: reading of the old name -> reading of ``name`` that behaves the same
    readings: dict
    #: why it is an alias (said in the warning and in the docs)
    why: str


#: Readings of an algorithm other than the one its registry name runs now, that this swarmproof
#: still has: ``(name, reading) -> registry name`` of the class that runs it (its ``reading``
#: attribute is that reading).  When a change bumps an algorithm's ``reading`` (its behaviour
#: changes on purpose, CHANGELOG.md), keep the old class registered under a new name (e.g.
#: ``"wang2020-r1"``) and list it here, so that a counterexample file made with the old reading
#: names what replays it.  A name's current reading is its class's ``reading`` and needs no entry.
READINGS: dict[tuple[str, str], str] = {
    # 0.2.0 (issue 31): Lee & Chong's default IDs became Sec. 2.1's prose numbering (reading "2");
    # reading "1", Alg. 1's printed formula, is the -printed variant.
    ("leechong-leader", "1"): "leechong-leader-printed",
    ("leechong-neighbor", "1"): "leechong-neighbor-printed",
    # 0.3.0 (issue 30): wang2020's handshake became an exchange answered within the tick (reading
    # "2", Sec. II-A c and e); reading "1", the handshake in the broadcasts, is the variant.
    ("wang2020", "1"): "wang2020-broadcast-handshake",
}

#: Old registry names that still work: ``old name -> Alias(new name, readings, why)``.  The old
#: name runs the new name's class (:func:`resolve_alias`; ``get_algorithm``, ``simulate``,
#: ``explore``, ``replay`` ... accept it) after a one-line warning on stderr naming the new name;
#: it is not listed by :func:`algorithm_names` (so ``verify`` and ``list`` show the new name
#: only).  ``readings`` maps a reading of the old name to the new name's reading that runs the
#: same, so a counterexample file made under the old name replays.
ALIASES: dict = {
    # 0.2.0 (issue 31): the prose numbering it ran is leechong-leader's default now; its reading
    # "1" is leechong-leader's reading "2" (traces bit-identical).
    "leechong-leader-prose": Alias(
        "leechong-leader", {"1": "2"},
        "Sec. 2.1's prose numbering is leechong-leader's default since swarmproof 0.2.0 (issue 31)"),
}

_WARNED: set = set()


def resolve_alias(name, *, warn: bool = True):
    """The registry name ``name`` runs: itself, or for an old name of :data:`ALIASES` the new one,
    after a one-line warning on stderr (once per process and name).  Anything else is returned
    unchanged.

    >>> resolve_alias("song2016")
    'song2016'
    >>> resolve_alias("leechong-leader-prose", warn=False)
    'leechong-leader'
    """
    if not isinstance(name, str) or name in ALGORITHMS or name not in ALIASES:
        return name
    alias = ALIASES[name]
    if warn and name not in _WARNED:
        _WARNED.add(name)
        print(f"swarmproof: warning: algorithm {name!r} is an alias of {alias.name!r} ({alias.why}); "
              f"use {alias.name!r}", file=sys.stderr)
    return alias.name


#: Readings this swarmproof can no longer run: ``(name, reading) -> where to get them`` (the last
#: swarmproof release and commit that had them), for the message of a replay or a baseline.
RETIRED_READINGS: dict[tuple[str, str], str] = {}

#: The modules that declare z3 lemmas, in the order ``swarmproof prove`` lists them (after the
#: normalisation lemmas of :mod:`swarmproof.invariants.lemmas`).  Each has ``LEMMAS`` (id ->
#: :class:`~swarmproof.invariants.lemmas.Lemma`) and may have ``EXTRA_LEMMAS`` (run only when
#: named) and ``CASE_FAMILIES``.  Song & O'Kane 2014's Lemma 7 is proved with 2016's.
LEMMA_SETS: tuple = (
    "swarmproof.reference_impl.song2016.lemmas",
    "swarmproof.reference_impl.wang2020.lemmas",
    "swarmproof.reference_impl.examples.lemmas",
)


def lemma_sets() -> list:
    """The modules of :data:`LEMMA_SETS`, imported, in order.

    >>> [m.__name__.rsplit(".", 2)[1] for m in lemma_sets()]
    ['song2016', 'wang2020', 'examples']
    """
    return [importlib.import_module(name) for name in LEMMA_SETS]

_PLUGINS_LOADED = False


def _load_entry_points() -> None:
    """Add the installed packages' algorithms (once per process)."""
    global _PLUGINS_LOADED
    if _PLUGINS_LOADED:
        return
    _PLUGINS_LOADED = True
    from importlib.metadata import entry_points

    try:
        eps = entry_points(group=ENTRY_POINT_GROUP)
    except Exception:  # noqa: BLE001 - broken metadata of another package must not stop swarmproof
        return
    for ep in sorted(eps, key=lambda e: e.name):
        ALGORITHMS.setdefault(ep.name, ep.value)


def claims_of(name: str) -> dict[str, str | None]:
    """Property -> citation (or None when not claimed) for a registered algorithm:
    its class's ``claims`` attribute.

    >>> claims_of("song2014")["connectivity"] is None
    True
    >>> claims_of("example-gather")
    {}
    """
    claims = getattr(algorithm_factory(name), "claims", None)
    return dict(claims) if claims else {}


def verify_plans() -> list[tuple[str, object]]:
    """``(name, VerifyPlan)`` of every registered algorithm whose class declares a
    ``verify`` plan, in the plans' ``rank`` order (ties by name).

    >>> [name for name, _ in verify_plans()]
    ['song2016', 'song2016-literal', 'song2016-subtree-clock', 'song2014', 'jiang', 'jiang-literal', 'wang2020', 'wang2020-broadcast-handshake', 'leechong-leader', 'leechong-neighbor', 'leechong-leader-printed', 'leechong-neighbor-printed', 'example-gather', 'example-anonymous-line', 'example-grid-goals']
    """
    plans = []
    for name in algorithm_names():
        plan = getattr(algorithm_factory(name), "verify", None)
        if plan is not None:
            plans.append((name, plan))
    return sorted(plans, key=lambda np_: (getattr(np_[1], "rank", 100), np_[0]))


def algorithm_names() -> list[str]:
    """The registered names (swarmproof's and the installed plug-ins'), sorted."""
    _load_entry_points()
    return sorted(ALGORITHMS)


def algorithm_factory(name: str):
    """The factory (usually the class) registered under ``name`` (an old name of :data:`ALIASES`:
    the new name's, with a warning)."""
    _load_entry_points()
    name = resolve_alias(name)
    if not isinstance(name, str) or name not in ALGORITHMS:
        raise UsageError(f"algorithm={name!r} is not known{did_you_mean(name, algorithm_names())}",
                         fix=f"use one of {algorithm_names()!r}")
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


def reading_of_name(name: str) -> str:
    """The reading the registry name ``name`` runs now (its class's ``reading``).

    >>> reading_of_name("song2016")
    '1'
    """
    from .protocol import reading_of

    return reading_of(algorithm_factory(name))


def find_reading(name: str, reading: str) -> tuple[str | None, str | None]:
    """Where reading ``reading`` of the registered algorithm ``name`` is:
    ``(registry name that runs it, None)`` when this swarmproof has it (``name`` itself when it is
    the current reading, else :data:`READINGS`), ``(None, where)`` when it is retired
    (:data:`RETIRED_READINGS`), ``(None, None)`` when nothing here knows it.

    >>> find_reading("song2016", "1")
    ('song2016', None)
    >>> find_reading("song2016", "0")
    (None, None)
    >>> find_reading("leechong-leader", "1")
    ('leechong-leader-printed', None)
    >>> find_reading("leechong-leader-prose", "1")
    ('leechong-leader', None)
    """
    reading = str(reading)
    alias = ALIASES.get(name) if name not in ALGORITHMS else None
    if alias is not None:
        if alias.readings.get(reading) == reading_of_name(alias.name):
            return alias.name, None
        name, reading = alias.name, alias.readings.get(reading, reading)
    if reading_of_name(name) == reading:
        return name, None
    other = READINGS.get((name, reading))
    if other is not None:
        return other, None
    return None, RETIRED_READINGS.get((name, reading))
