"""An algorithm's own runtime invariants, checked at every step (the ``invariants`` property).

Some claims are about an algorithm's bookkeeping, not about geometry every
algorithm shares: Jiang et al.'s robots are each in at most one group, no two
heads take one assembling slot (002 Algs. 1-2).  An algorithm lists them on its
class as ``invariants``: a tuple of :class:`Invariant`, each a statement, where
it comes from, and ``check(t, ids, poses, states) -> str | None`` -- None
while it holds at step ``t``, else a message naming the robots and values.
The ``invariants`` property (registered in :mod:`swarmproof.invariants.registry`)
runs them on every step the engine makes (streaming, whatever is recorded),
and is inconclusive for an algorithm that declares none.

The same machinery judges other properties an algorithm declares as invariants
under another attribute (``completion_sound``: its ``completion_invariants``,
"whenever a robot declares the formation complete, it is formed"): the monitor
takes the property's name.  An invariant of the form "whenever X, then Y" may
count its X (``judged``); a run in which no invariant had anything to judge is
inconclusive (vacuous), never held.

Examples
--------
>>> import numpy as np
>>> from swarmproof.models.trace import Trace
>>> distinct = Invariant("distinct_targets", "no two robots share a target", "example",
...     lambda t, ids, poses, states: None if len({dict(s)["target"] for s in states}) == len(states)
...     else "two robots share a target")
>>> alg = type("A", (), {"invariants": (distinct,)})()
>>> tr = Trace(ids=[1, 2], poses=np.zeros((2, 2, 3)), states=[((("target", 1),), (("target", 2),)),
...                                                            ((("target", 1),), (("target", 1),))])
>>> r = check_invariants(tr, alg)
>>> r.status, r.witness["invariant"], r.witness["step"]
('violated', 'distinct_targets', 1)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .result import InvariantResult

__all__ = ["Invariant", "invariants_of", "InvariantsMonitor", "check_invariants", "CITE_INVARIANTS",
           "run_invariants"]

CITE_INVARIANTS = "the algorithm's own runtime invariants (its invariants attribute, each citing its paper)"


@dataclass(frozen=True)
class Invariant:
    """One runtime invariant of an algorithm.

    ``check(t, ids, poses, states)`` sees the IDs, poses and controller states
    of the robots present after step ``t`` (``t = 0``: the start) and returns
    None while the invariant holds, else a message.  ``states`` is a sequence
    valid during the call (a vectorised path's may build each state on first
    access and offer ``values_of(key)``, one key of every state).

    ``judged`` (optional), for an invariant of the form "whenever X, then Y":
    how many times X occurred so far in the run (the checks that had something
    to judge).  Without it every step counts.
    """

    name: str
    statement: str
    cites: str
    check: Callable[[int, Any, np.ndarray, tuple], str | None]
    judged: Callable[[], int] | None = None


def invariants_of(algorithm, only=None) -> tuple:
    """The algorithm's ``invariants`` attribute (a tuple of :class:`Invariant`), else ``()``;
    ``only`` (names, e.g. the explorer's property option ``invariants``) keeps those of them.

    Raises
    ------
    UsageError
        A name in ``only`` that the algorithm does not declare (naming the ones it does).
    """
    invs = tuple(getattr(algorithm, "invariants", None) or ())
    if only is None:
        return invs
    names = (only,) if isinstance(only, str) else tuple(only)
    known = [i.name for i in invs]
    who = getattr(algorithm, "name", "the algorithm")
    for name in names:
        if name not in known:
            from swarmproof.models.errors import UsageError, did_you_mean

            if not known:
                raise UsageError(f"invariant={name!r}: {who} declares no runtime invariants",
                                 fix="drop --invariant (the invariants property is not applicable to it)")
            renamed = dict(getattr(algorithm, "invariant_renames", None) or {})
            hint = f"; it became {renamed[name]}" if name in renamed else did_you_mean(name, known)
            raise UsageError(f"invariant={name!r} is not an invariant of {who}{hint}", fix=f"use some of {known!r}")
    return tuple(i for i in invs if i.name in names)


class InvariantsMonitor:
    """Streaming form of the ``invariants`` property: every step the engine makes.

    ``name`` and ``cites`` are those of the property it judges (default ``invariants``);
    ``declared`` says what the algorithm declares them as, for the vacuous verdict."""

    def __init__(self, invariants, *, name: str = "invariants", cites: str = CITE_INVARIANTS,
                 declared: str = "runtime invariants") -> None:
        self.invariants = tuple(invariants)
        self.name, self.cites, self.declared = name, cites, declared
        self.steps = 0
        self.first: dict = {}           # invariant name -> (step, message)

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)

    def observe(self, t, poses, states, present) -> None:
        self.steps += 1
        mask = np.asarray(present, dtype=bool)
        ids = self.ids[mask]
        pos = np.asarray(poses)[mask]
        # every robot present: the engine's states as they are (a vectorised path's lazy sequence
        # stays lazy, and an invariant may read one key as a column, ``values_of``)
        sts = states if mask.all() else tuple(s for s, p in zip(states, mask) if p)
        for inv in self.invariants:
            if inv.name in self.first:
                continue
            msg = inv.check(int(t), ids, pos, sts)
            if msg is not None:
                self.first[inv.name] = (int(t), str(msg))

    def result(self) -> InvariantResult:
        if not self.invariants:
            return InvariantResult(self.name, "inconclusive", self.cites, None,
                                   f"vacuous: the algorithm declares no {self.declared}", applicable=False)
        if self.first:
            name, (step, msg) = min(self.first.items(), key=lambda kv: (kv[1][0], kv[0]))
            inv = next(i for i in self.invariants if i.name == name)
            return InvariantResult(self.name, "violated", inv.cites,
                                   {"invariant": name, "step": step, "statement": inv.statement},
                                   f"{name} ({inv.cites}) broke in step {step}: {msg}")
        names = ", ".join(i.name for i in self.invariants)
        cites = "; ".join(i.cites for i in self.invariants)
        counts = {i.name: int(i.judged()) for i in self.invariants if i.judged is not None}
        if counts and len(counts) == len(self.invariants) and not any(counts.values()):
            return InvariantResult(self.name, "inconclusive", cites, None,
                                   f"vacuous: {names} had nothing to judge in {self.steps} observed steps",
                                   applicable=False, detail={"invariants": [i.name for i in self.invariants],
                                                             "judged": counts})
        judged = "".join(f", {k} judged {v} time{'s' if v != 1 else ''}" for k, v in counts.items())
        return InvariantResult(self.name, "held", cites, None,
                               f"{names} held at every one of {self.steps} observed steps{judged}",
                               detail={"invariants": [i.name for i in self.invariants],
                                       **({"judged": counts} if counts else {})})


class InvariantsStop:
    """Run-time form of the ``invariants`` property for ``simulate(stop_when=...)``: True at the
    first step where one of the invariants breaks, so the explorer does not run a violated
    scenario on to its end (each shrink of a leechong-neighbor counterexample ran hundreds of
    steps past it).  Judging the stopped trace finds the same first violation -- the same step,
    invariant and message -- as the whole run: every invariant is checked at every step up to it
    (tests/invariants/test_invariants_stop.py).  ``start(ids)`` first; a run whose robots change
    (a fault adds one) is not stopped.  ``step`` is where it fired.
    """

    def __init__(self, invariants, **monitor) -> None:
        self.monitor = InvariantsMonitor(invariants, **monitor)
        self.step: int | None = None

    def start(self, ids) -> None:
        self.monitor.start(ids)

    def __call__(self, t: int, poses, states, present) -> bool:
        if len(present) != len(self.monitor.ids):
            return False
        self.monitor.observe(t, poses, states, present)
        if self.monitor.first:
            self.step = int(t)
            return True
        return False


def check_invariants(trace, algorithm, only=None) -> InvariantResult:
    """Run the algorithm's invariants (``only``: those named) over every recorded step of ``trace``
    (the non-streaming form; a sparse trace is judged on what it kept -- the explorer streams)."""
    return run_invariants(trace, invariants_of(algorithm, only))


def run_invariants(trace, invariants, **monitor) -> InvariantResult:
    """:class:`InvariantsMonitor` (``monitor``: its name, cites, declared) over every recorded step
    of ``trace``: the non-streaming form of a property judged by invariants."""
    mon = InvariantsMonitor(invariants, **monitor)
    mon.start(trace.ids)
    present = getattr(trace, "present", None)
    for k in range(len(trace.poses)):
        pres = np.ones(len(trace.ids), bool) if present is None else np.asarray(present[k], dtype=bool)
        t = int(trace.times[k]) if getattr(trace, "times", None) else k
        mon.observe(t, trace.poses[k], trace.states[k], pres)
    return mon.result()
