"""Which algorithm: a registry name, ``"module:qualname"``, or a class / factory.

Every checker that runs an algorithm names it the same way: the explorer, replay,
``simulate`` and ``verify`` (:mod:`swarmproof.checkers.runs`), campaigns.
:func:`resolve_algorithm` turns any accepted form into an :class:`AlgorithmSpec`:
what reports show, what counterexample files record, how a fresh algorithm object is
built and what its paper claims.  It is re-exported by :mod:`swarmproof.checkers.explore`,
where it was first defined.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Callable, Mapping

from swarmproof.models.errors import UsageError, did_you_mean

__all__ = ["AlgorithmSpec", "resolve_algorithm"]


@dataclass(frozen=True)
class AlgorithmSpec:
    """An algorithm the explorer can run and a counterexample file can name.

    Attributes
    ----------
    label : str
        Shown in reports and file names: the registry name, else the
        algorithm's ``name`` attribute, else its qualified name.
    ref : str
        Written to the counterexample file's ``algorithm`` field: the registry
        name, or ``"module:qualname"`` that :func:`resolve_algorithm` imports again.
    factory : callable
        Builds a fresh algorithm object (given ``n_robots=`` when it accepts it).
    claims : dict
        Property -> citation, or None where the algorithm claims nothing.
    """

    label: str
    ref: str
    factory: Callable = field(compare=False)
    claims: Mapping = field(default_factory=dict, compare=False)

    @property
    def reading(self) -> str:
        """The reading version of the algorithm (its class's ``reading``, ``"1"`` when it declares
        none: :func:`swarmproof.reference_impl.protocol.reading_of`); counterexample files record it."""
        from swarmproof.reference_impl.protocol import reading_of

        return reading_of(self.factory)

    def build(self, n_robots: int | None = None):
        """A fresh algorithm object (``n_robots`` passed only to factories that take it)."""
        import inspect

        kw = {}
        if n_robots is not None:
            try:
                if "n_robots" in inspect.signature(self.factory).parameters:
                    kw["n_robots"] = n_robots
            except (TypeError, ValueError):  # pragma: no cover - builtins without signatures
                pass
        try:
            algo = self.factory(**kw)
        except TypeError as exc:
            raise UsageError(f"algorithm={self.ref!r} cannot be built without arguments ({exc})",
                             fix="give every constructor parameter a default (swarmproof builds one per "
                                 "scenario), or register a factory function that supplies them") from None
        missing = [a for a in ("model", "assumptions", "controller", "finished") if not hasattr(algo, a)]
        if missing:
            raise UsageError(f"algorithm={self.ref!r} built an object without {missing!r}",
                             fix="follow the protocol of swarmproof.reference_impl.protocol.Algorithm")
        return algo


def _cwd_importable() -> None:
    """Let ``module:qualname`` name a module of the current directory, as pytest's rootdir does
    (the ``swarmproof`` command's own path does not include it)."""
    import sys

    cwd = os.getcwd()
    if cwd not in sys.path and "" not in sys.path:
        sys.path.append(cwd)


def _import_ref(ref: str):
    """Import ``"module:qualname"``; UsageError naming it when that fails."""
    import importlib

    modname, _, qual = ref.partition(":")
    fix = "give a registry name, or module:qualname of a class importable at module level"
    if not modname or not qual or "<locals>" in qual:
        raise UsageError(f"algorithm={ref!r} cannot be imported (not module:qualname of a module-level "
                         "class or function)", fix=fix)
    _cwd_importable()
    try:
        obj = importlib.import_module(modname)
        for part in qual.split("."):
            obj = getattr(obj, part)
    except ImportError as exc:
        raise UsageError(f"algorithm={ref!r} cannot be imported ({exc})", fix=fix) from None
    except AttributeError:
        raise UsageError(f"algorithm={ref!r} cannot be imported: {modname} has no {qual!r}", fix=fix) from None
    except Exception as exc:  # noqa: BLE001 - the user's module failed while importing
        raise UsageError(f"algorithm={ref!r}: importing {modname} raised {type(exc).__name__}: {exc}",
                         fix="fix the module so that it imports") from None
    return obj


def resolve_algorithm(algorithm) -> AlgorithmSpec:
    """What :func:`explore` and replay accept as an algorithm.

    * a registry name (``"song2016"``): factory and claims from the registry;
    * ``"module:qualname"`` of a class or factory function: imported;
    * a class or factory (a callable returning a protocol object): used as
      given; its file reference is ``"module:qualname"``.

    Claims of an unregistered class come from its ``claims`` attribute
    (property -> citation) when it has one, else nothing is claimed.  An
    algorithm *object* (an instance) is refused: pass its class or a factory,
    so every scenario gets a fresh one and a replay can rebuild it.

    Examples
    --------
    >>> resolve_algorithm("song2014").ref
    'song2014'
    >>> from swarmproof.reference_impl.examples import GatherToLowestId
    >>> s = resolve_algorithm(GatherToLowestId)
    >>> s.label, s.ref
    ('example-gather', 'swarmproof.reference_impl.examples.algorithms:GatherToLowestId')
    >>> resolve_algorithm(s.ref).factory is GatherToLowestId
    True
    """
    from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names, claims_of, resolve_alias

    if isinstance(algorithm, str):
        algorithm = resolve_alias(algorithm)      # an old name (registry.ALIASES): the new one, with a warning
        if algorithm in algorithm_names():
            return AlgorithmSpec(algorithm, algorithm, algorithm_factory(algorithm), claims_of(algorithm))
        if ":" not in algorithm:
            raise UsageError(f"algorithm={algorithm!r} is not known{did_you_mean(algorithm, algorithm_names())}",
                             fix=f"use one of {algorithm_names()!r}, or module:qualname of your algorithm class")
        factory = _import_ref(algorithm)
        ref = algorithm
    elif isinstance(algorithm, type) or (callable(algorithm) and not hasattr(algorithm, "controller")):
        factory = algorithm
        mod, qual = getattr(algorithm, "__module__", None), getattr(algorithm, "__qualname__", None)
        ref = f"{mod}:{qual}" if mod and qual else repr(algorithm)
    elif hasattr(algorithm, "controller"):
        raise UsageError(f"algorithm={algorithm!r} is an algorithm object",
                         fix=f"pass its class ({type(algorithm).__qualname__}) or a factory function instead")
    else:
        raise UsageError(f"algorithm={algorithm!r} is not a registry name, module:qualname, class or factory",
                         fix=f"use one of {algorithm_names()!r} or your algorithm class")
    if not callable(factory):
        raise UsageError(f"algorithm={ref!r} is not a class or factory")
    name = getattr(factory, "name", None)
    label = name if isinstance(name, str) and name else ref.rpartition(":")[2]
    claims = getattr(factory, "claims", None)
    claims = dict(claims) if isinstance(claims, Mapping) else {}
    return AlgorithmSpec(label, ref, factory, claims)
