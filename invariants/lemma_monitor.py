"""Runtime monitors derived from a lemma's one definition (issue 32): a *binding* reads a run.

A :class:`~swarmproof.invariants.lemma_api.LemmaSpec` states a lemma once; the prover reads its
functions on z3 terms.  A :class:`Binding` says where the lemma applies in a run: it maps one
step ``t -> t + 1`` (a :class:`StepView`: the poses and controller states at both ends) to the
lemma's *instances* -- every decided parent-child link, every robot that moved, every pair that
met -- each an :class:`Instance` with the values of the lemma's variables (normalised as the
lemma is: translated, divided by ``phi``).  The monitor built from it
(:func:`swarmproof.invariants.premises.register_binding`,
then the ``premises`` property, simulate, explore and replay run it inside the engine on every
step) evaluates the *same* premise and conclusion functions on those floats:

* a premise false even with the tolerance that makes it easier to satisfy (``tol``, 1e-9 in the
  lemma's normalised units) failed beyond float noise: ``violated``, naming the lemma, the
  premise, the step and the instance (as the hand-written premise monitors did);
* a premise false exactly but true with that tolerance sits at its boundary: neither a failure
  nor a premise that held (counted as ``boundary``);
* every premise true exactly -- never with a tolerance in its favour -- and the conclusion false
  even with the tolerance in *its* favour: the worst finding, the proof does not transfer to the
  code (the binding or the encoding is wrong): ``violated`` with ``transfer: True``.  Premises
  are judged exactly rather than with a tolerance against them because a robot at full speed,
  or on the rim of a bounded range, sits exactly on a premise's boundary by construction; float
  noise (about 1e-16) there cannot move a conclusion by ``tol`` (docs/decisions.md);
* otherwise the instance is *checked*; a run with no checked instance is *vacuous*
  (``inconclusive`` for that run, as a proof whose premises are unsatisfiable).

A binding may declare ``given``: premises that *select* instances (where one fails the lemma does
not apply: not a finding, e.g. "the two were neighbours at t"), and ``only``: a subset of the
premises to monitor without the conclusion (a premise the algorithm must keep on its own, e.g.
"every robot moves at most v dt"; the instance then gives only the variables they read).

Examples
--------
A lemma "a robot that moves at most ``s`` stays within ``1 + s`` of a still point it was within
1 of", bound to every robot and the origin of the world:

>>> import numpy as np
>>> from swarmproof.invariants.lemma_api import LemmaSpec, Le, Point, Real, dist2
>>> spec = LemmaSpec(id="near_origin", statement="...", cites=("example",), control_note="-",
...     variables=(Real("s", 0, 1), Point("a"), Point("b")),
...     premises=(("within_one", lambda v: Le(dist2(v.a), 1)),
...               ("moves_at_most_s", lambda v: Le(dist2(v.b, v.a), v.s * v.s))),
...     conclusion=lambda v: Le(dist2(v.b), (1 + v.s) * (1 + v.s)),
...     control_premises=(("within_one", lambda v: Le(dist2(v.a), 1)),))
>>> def every_robot(view):
...     for k in view.robots():
...         yield Instance({"robot": view.id(k)}, {"s": view.s, **view.point("a", k, 0, at=0),
...                                                  **view.point("b", k, 1, at=0)})
>>> b = Binding("near_origin", spec, every_robot, what="robot steps")
>>> from swarmproof.models.trace import Trace
>>> poses = np.array([[[0.5, 0, 0]], [[0.55, 0, 0]]])
>>> r = b.check(Trace(ids=[7], poses=poses, states=[((),)] * 2), 1.0, 0.1, 1.0)
>>> r.status, r.detail["checked"]
('held', 1)
>>> poses = np.array([[[0.5, 0, 0]], [[0.6 + 1e-12, 0, 0]]])  # v dt and float noise: at the boundary
>>> r = b.check(Trace(ids=[7], poses=poses, states=[((),)] * 2), 1.0, 0.1, 1.0)
>>> r.status, r.detail["boundary"], r.message
('inconclusive', 1, 'vacuous: no robot steps with every premise of near_origin holding in 1 steps (1 boundary)')
>>> poses = np.array([[[0.5, 0, 0]], [[0.9, 0, 0]]])       # moved 0.4 > v dt = 0.1
>>> r = b.check(Trace(ids=[7], poses=poses, states=[((),)] * 2), 1.0, 0.1, 1.0)
>>> r.status, r.witness["premise"], r.witness["robot"]
('violated', 'moves_at_most_s', 7)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .lemma_api import LemmaSpec
from .result import InvariantResult

__all__ = ["Instance", "Batch", "judge_batch", "Binding", "StepView", "MissingState", "BindingMonitor", "judge_instance",
           "examined_steps"]


def examined_steps(trace):
    """The steps a monitor examines, as the index ``t`` of the frame before each (it reads frames
    ``t`` and ``t + 1``): every pair of consecutive frames of a trace (on a dense one, every step;
    a sparse one's frames are further apart, ``trace.times``), or the one step of a streaming
    window (:class:`swarmproof.invariants.premises.Window`)."""
    r = getattr(trace, "step_range", None)
    return range(len(trace.poses) - 1) if r is None else r


class MissingState(Exception):
    """A binding could not read what it needs from a state (a key the algorithm does not record):
    the monitor is ``inconclusive``, naming it."""


@dataclass(frozen=True)
class Instance:
    """One place a lemma applies at one step.

    ``key``: who (e.g. ``{"parent": 3, "child": 5}``), shown in a finding.  ``values``: the
    lemma's variables (``LemmaSpec.names()``; with ``only``, those the premises read).
    ``outcome`` (optional): values that replace some of ``values`` for the conclusion only --
    what followed, read apart from what the premises read.  ``facts``: extra witness fields in
    the run's units (``{"distance": 1.23}``)."""

    key: dict
    values: dict
    outcome: dict | None = None
    facts: dict = field(default_factory=dict)


def judge_instance(spec: LemmaSpec, inst: Instance, given: tuple = (), only: tuple | None = None,
                   tol: float | None = None) -> tuple:
    """``(kind, detail)`` of one instance: ``"outside"`` (a ``given`` premise does not hold
    strictly: the lemma does not apply), ``"failed"`` (premise names failed leniently),
    ``"boundary"``, ``"transfer"`` (premises held strictly, conclusion false leniently) or
    ``"checked"``.  ``tol``: the tolerance of "leniently" (default the lemma's, ``spec.tol``)."""
    if only is not None:
        only = tuple(only) + tuple(g for g in given if g not in only)
    j = spec.judge(inst.values, tol=tol, outcome=inst.outcome, loose=True, only=only, premise_tol=0.0)
    if given and not all(j.premises.get(g, True) for g in given):
        return "outside", None
    failed = tuple(n for n in j.failed if n not in given)
    if failed:
        return "failed", (failed, j.failed_in_cases)
    if not j.premises_hold:
        return "boundary", None
    if not j.conclusion:
        return "transfer", j.parts
    return "checked", None


@dataclass(frozen=True)
class Batch:
    """Many instances of one step at once, as columns: ``key`` maps each name to a sequence (one
    entry per instance; a 2-D array gives each instance its row, as a list), ``values`` and
    ``outcome`` each variable to a float array (or one float shared by all), ``facts`` each fact
    to a sequence (or one value shared by all).  The lemma's functions are judged on the
    arrays element by element (numpy), which is what keeps a monitor's cost near the run's own;
    a finding is then re-judged as the single :class:`Instance` it names."""

    key: dict
    values: dict
    outcome: dict | None = None
    facts: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(next(iter(self.key.values()))) if self.key else 0

    def instance(self, i: int) -> Instance:
        """The ``i``-th instance on its own."""
        def pick(x):
            return x[i] if isinstance(x, (np.ndarray, list, tuple)) else x

        def num(x):
            v = pick(x)
            if isinstance(v, np.ndarray):       # a row of a 2-D column (e.g. a pair of robot IDs)
                return v.tolist()
            return v.item() if isinstance(v, np.generic) else v

        return Instance({k: num(v) for k, v in self.key.items()},
                        {k: float(pick(v)) for k, v in self.values.items()},
                        None if self.outcome is None else {k: float(pick(v)) for k, v in self.outcome.items()},
                        {k: num(v) for k, v in self.facts.items()})


def judge_batch(spec: LemmaSpec, batch: Batch, given: tuple = (), only: tuple | None = None,
                tol: float | None = None) -> dict:
    """Each instance's kind (as :func:`judge_instance`), as boolean arrays ``{"outside",
    "failed", "boundary", "transfer", "checked"}`` over the batch's entries."""
    n = len(batch)
    if only is not None:
        only = tuple(only) + tuple(g for g in given if g not in only)
    def column(v):
        return np.asarray(v, dtype=float) if isinstance(v, (np.ndarray, list, tuple)) else float(v)

    # every premise value a column of n (a value shared by all is repeated), so each verdict is one
    arr = {k: np.broadcast_to(column(v), (n,)) for k, v in batch.values.items()}
    out = None if batch.outcome is None else {k: column(v) for k, v in batch.outcome.items()}
    j = spec.judge(arr, tol=tol, outcome=out, loose=True, only=only, premise_tol=0.0)

    def full(x):
        return np.broadcast_to(np.asarray(x, dtype=bool), (n,))

    ones = np.ones(n, dtype=bool)
    given_ok = ones.copy()
    for g in given:
        given_ok &= full(j.premises[g])
    common_strict, common_failed = ones.copy(), np.zeros(n, dtype=bool)
    for name, ok in j.premises.items():
        common_strict &= full(ok)
        if name not in given:
            common_failed |= ~full(j.loose[name])
    hold = common_strict
    if j.cases:
        any_strict = np.zeros(n, dtype=bool)
        any_loose = np.zeros(n, dtype=bool)
        for case, prem in j.cases.items():
            cs, cl = ones.copy(), ones.copy()
            for name, ok in prem.items():
                cs &= full(ok)
                cl &= full(j.loose_cases[case][name])
            any_strict |= cs
            any_loose |= cl
        hold = hold & any_strict
        common_failed |= ~any_loose
    outside = ~given_ok
    failed = given_ok & common_failed
    boundary = given_ok & ~failed & ~hold
    transfer = given_ok & hold & ~full(j.conclusion)
    checked = given_ok & hold & full(j.conclusion)
    return {"outside": outside, "failed": failed, "boundary": boundary, "transfer": transfer, "checked": checked}


class StepView:
    """One step ``t -> t + 1`` of a run as a binding reads it: the robots present at both ends,
    their poses and their controller states before and after the step (the state recorded after
    the step decided is ``"after"``), and ``phi``, ``v``, ``dt`` and ``s = v dt / phi``."""

    def __init__(self, trace, t: int, phi: float, v: float, dt: float) -> None:
        self.t = t
        self.phi, self.v, self.dt = phi, v, dt
        self.s = v * dt / phi
        self.ids = trace.ids
        self.p = (trace.poses[t], trace.poses[t + 1])
        self.states = (trace.states[t], trace.states[t + 1])
        self.present = (trace.present_at(t), trace.present_at(t + 1))
        self._slot = None
        self._dicts: dict = {}      # id(state) -> its items as a dict (states repeat: one per object)
        self._moved = None

    def robots(self):
        """The slots present at both ends of the step."""
        both = self.present[0] & self.present[1]
        return np.flatnonzero(both).tolist()

    def id(self, k: int) -> int:
        return int(self.ids[k])

    def slot(self, robot_id) -> int | None:
        """The slot of ``robot_id`` when it is present at both ends, else None."""
        if self._slot is None:
            self._slot = {int(i): k for k, i in enumerate(self.ids.tolist())}
        k = self._slot.get(int(robot_id))
        if k is None or not (self.present[0][k] and self.present[1][k]):
            return None
        return k

    def state(self, k: int, key: str, when: int = 1, default=MissingState):
        """Robot ``k``'s controller-state value ``key`` before (``when=0``) or after (1) the step;
        :class:`MissingState` when the state has no such key and no ``default`` is given."""
        st = self.states[when][k]
        d = self._dicts.get(id(st))
        if d is None:
            d = self._dicts[id(st)] = {item[0]: item[1] for item in st or ()
                                       if isinstance(item, tuple) and len(item) == 2}
        if key in d:
            return d[key]
        if default is MissingState:
            raise MissingState(f"robot {self.id(k)} has no {key!r} in its state")
        if getattr(st, "logged_only", False):
            # a recorded run's state holds what the log held (checkers/recorded.py): a key it lacks was
            # not logged, which is not the controller's "absent" that the default stands for
            raise MissingState(f"robot {self.id(k)}'s {key!r} is not in the log")
        return default

    def moved(self, k: int) -> bool:
        """Whether robot ``k``'s position changed in the step (exactly)."""
        if self._moved is None:
            self._moved = np.any(self.p[0][:, :2] != self.p[1][:, :2], axis=1).tolist()
        return self._moved[k]

    def distance(self, a: int, when_a: int, b: int, when_b: int) -> float:
        """The distance (run units) from ``a`` at ``when_a`` to ``b`` at ``when_b``."""
        d = self.p[when_a][a, :2] - self.p[when_b][b, :2]
        return float(np.hypot(d[0], d[1]))

    def point(self, name: str, k: int, when: int, origin: tuple | None = None, at=None) -> dict:
        """``{name_x, name_y}``: robot ``k``'s position at ``when``, translated so that the origin
        is 0 and divided by ``phi`` (the lemmas' normalisation).  The origin is robot
        ``origin = (slot, when)``'s position, or the point ``at`` (run units; 0: the world's
        origin), or by default robot ``k``'s own position before the step."""
        q = self.p[when][k, :2]
        if origin is not None:
            o = self.p[origin[1]][origin[0], :2]
        elif at is not None:
            o = np.zeros(2) + at
        else:
            o = self.p[0][k, :2]
        x, y = (q - o) / self.phi
        return {f"{name}_x": float(x), f"{name}_y": float(y)}


    # -- the same for many robots at once (a Batch): slot arrays in, float arrays out

    def robot_array(self) -> np.ndarray:
        """The slots present at both ends, as an integer array."""
        return np.flatnonzero(self.present[0] & self.present[1])

    def points(self, name: str, ks, when: int, origins=None, origin_when: int = 0) -> dict:
        """:meth:`point` for every robot of ``ks`` (``origins``: a slot per robot, at
        ``origin_when``; None: each robot's own position before the step)."""
        ks = np.asarray(ks, dtype=int)
        o = self.p[0][ks, :2] if origins is None else self.p[origin_when][np.asarray(origins, dtype=int), :2]
        d = (self.p[when][ks, :2] - o) / self.phi
        return {f"{name}_x": d[:, 0], f"{name}_y": d[:, 1]}

    def distances(self, a, when_a: int, b, when_b: int) -> np.ndarray:
        """:meth:`distance` for every pair of slots ``a[i]``, ``b[i]`` (run units)."""
        d = self.p[when_a][np.asarray(a, dtype=int), :2] - self.p[when_b][np.asarray(b, dtype=int), :2]
        return np.hypot(d[:, 0], d[:, 1])

    def ids_of(self, ks) -> list:
        """The robot IDs of slots ``ks``."""
        return [int(i) for i in self.ids[np.asarray(ks, dtype=int)]]


@dataclass(frozen=True)
class Binding:
    """Where a lemma applies in a run (module docstring).

    ``name``: the monitor's name (algorithms list it in ``premise_monitors``).  ``lemma``: the
    :class:`LemmaSpec`.  ``instances``: ``(StepView) -> iterable of Instance``; it may raise
    :class:`MissingState`.  ``what``: what an instance is, for messages ("moving-parent/child
    pairs").  ``given``: premises that select instances (module docstring).  ``only``: monitor
    just these premises, without the conclusion.  ``cites``: the citation (default: the
    lemma's first).  ``tol``: the tolerance of the boundary band and of the conclusion (default
    the lemma's, 1e-9 normalised); 0 for a binding that reads the very numbers the algorithm
    compared (a clock reading against its window: no float noise between the decision and the
    monitor, so a premise that fails exactly fails; docs/decisions.md)."""

    name: str
    lemma: LemmaSpec
    instances: Callable
    what: str = "instances"
    given: tuple = ()
    only: tuple | None = None
    cites: str = ""
    tol: float | None = None

    def __post_init__(self) -> None:
        from swarmproof.models.errors import UsageError

        common = {n for n, _ in self.lemma.premises}
        names = common | {n for _, extra in self.lemma.cases for n, _ in extra}
        for label, group in (("given", self.given), ("only", self.only or ())):
            for n in group:
                if n not in names:
                    raise UsageError(f"binding {self.name!r}: {label} premise={n!r} is not a premise of lemma "
                                     f"{self.lemma.id!r}", fix=f"use some of {sorted(names)}")
        for n in self.given:
            if n not in common and n not in (self.only or ()):
                raise UsageError(f"binding {self.name!r}: given premise={n!r} belongs to a case of lemma "
                                 f"{self.lemma.id!r}, not to every instance",
                                 fix=f"give only=(...) with {n!r} among them to monitor that case's premises, "
                                     f"or select with common premises: {sorted(common)}")
        if not callable(self.instances):
            raise UsageError(f"binding {self.name!r}: instances={self.instances!r} is not a function of a step",
                             fix="give a function view -> iterable of Instance or Batch")

    @property
    def citation(self) -> str:
        return self.cites or f"{self.lemma.id} ({self.lemma.cites[0]})"

    def monitor(self, phi: float, v: float, dt: float, meta=None) -> "BindingMonitor":
        """A fresh accumulating monitor (``scan`` every step, then ``result``)."""
        return BindingMonitor(self, phi, v, dt)

    def check(self, trace, phi: float, v: float, dt: float) -> InvariantResult:
        """The monitor over a whole trace (or one streaming window)."""
        m = self.monitor(phi, v, dt)
        m.scan(trace)
        return m.result()


class BindingMonitor:
    """The monitor a :class:`Binding` derives: it judges every instance of every step it scans
    and stops at the first finding; :meth:`result` is the verdict (module docstring)."""

    def __init__(self, binding: Binding, phi: float, v: float, dt: float) -> None:
        self.b = binding
        self.phi, self.v, self.dt = float(phi), float(v), float(dt)
        self.counts = {"checked": 0, "boundary": 0, "outside": 0}
        self.steps = 0
        self.finding: InvariantResult | None = None
        self.missing: str | None = None

    def scan(self, trace) -> None:
        if self.finding is not None or self.missing is not None:
            return
        b, spec = self.b, self.b.lemma
        for t in examined_steps(trace):
            self.steps += 1
            view = StepView(trace, t, self.phi, self.v, self.dt)
            try:
                found = b.instances(view)
                if found is None:
                    raise TypeError("the binding's function returned None, not an iterable of Instance or Batch")
                for inst in found:
                    if not isinstance(inst, (Batch, Instance)):
                        raise TypeError(f"the binding's function yielded {inst!r}, not an Instance or a Batch")
                    if isinstance(inst, Batch):
                        if not len(inst):
                            continue
                        kinds = judge_batch(spec, inst, b.given, b.only, b.tol)
                        bad = np.flatnonzero(kinds["failed"] | kinds["transfer"])
                        upto = int(bad[0]) if bad.size else len(inst)
                        for kind in self.counts:
                            self.counts[kind] += int(np.count_nonzero(kinds[kind][:upto]))
                        if not bad.size:
                            continue
                        inst = inst.instance(upto)          # the first finding, judged on its own
                    kind, info = judge_instance(spec, inst, b.given, b.only, b.tol)
                    if kind in self.counts:
                        self.counts[kind] += 1
                        continue
                    self.finding = self._finding(t, inst, kind, info)
                    return
            except MissingState as e:
                self.missing = str(e)
                return
            except (TypeError, KeyError, AttributeError, IndexError, ValueError) as exc:
                from swarmproof.models.errors import SwarmproofError, UsageError

                if isinstance(exc, SwarmproofError):
                    raise
                raise UsageError(f"binding {b.name!r} of lemma {spec.id!r} failed at step {t}: "
                                 f"{type(exc).__name__}: {exc}",
                                 fix="make its function yield Instance/Batch values for every variable of "
                                     f"the lemma ({', '.join(spec.names())}), or those its only= premises read "
                                     "(docs/lemmas.md)") from None

    def _finding(self, t: int, inst: Instance, kind: str, info) -> InvariantResult:
        b, spec = self.b, self.b.lemma
        who = ", ".join(f"{k} {v}" for k, v in inst.key.items())
        witness = {"step": t, **inst.key, **inst.facts, "lemma": spec.id,
                   "values": {k: round(float(x), 12) for k, x in inst.values.items()}}
        if kind == "transfer":
            witness.update(transfer=True, premise=None)
            if inst.outcome:
                witness["outcome"] = {k: round(float(x), 12) for k, x in inst.outcome.items()}
            if info:
                witness["parts_failed"] = [n for n, ok in info.items() if not ok]
            msg = (f"step {t}, {who}: every premise of lemma {spec.id} held and its conclusion did not -- "
                   "the proof does not transfer to this run (the binding reads the run wrongly, or the lemma "
                   f"is false: swarmproof prove {spec.id})")
            return InvariantResult(f"premise:{b.name}", "violated", b.citation, witness, msg,
                                   detail=dict(self.counts))
        failed, in_cases = info
        witness["premise"] = failed[0]
        if in_cases and failed[0].startswith("case:"):
            witness["cases_failed"] = {c: list(ps) for c, ps in in_cases.items()}
            what = "no case of the lemma (" + "; ".join(f"{c}: {', '.join(ps) or 'held'}"
                                                      for c, ps in in_cases.items()) + ")"
        else:
            what = f"premise {failed[0]}" + (f" (and {', '.join(failed[1:])})" if len(failed) > 1 else "")
        facts = "".join(f", {k} {v:.6g}" if isinstance(v, float) else f", {k} {v}" for k, v in inst.facts.items())
        msg = f"step {t}, {who}: {what} of lemma {spec.id} failed{facts}"
        return InvariantResult(f"premise:{b.name}", "violated", b.citation, witness, msg,
                               detail=dict(self.counts))

    def result(self) -> InvariantResult:
        b = self.b
        name = f"premise:{b.name}"
        if self.finding is not None:
            return self.finding
        if self.missing is not None:
            return InvariantResult(name, "inconclusive", b.citation, None, self.missing)
        n = self.counts["checked"]
        detail = {**self.counts, "vacuous": n == 0}
        extra = ", ".join(f"{v} {k}" for k, v in self.counts.items() if k != "checked" and v)
        extra = f" ({extra})" if extra else ""
        if n == 0:
            return InvariantResult(name, "inconclusive", b.citation, None,
                                   f"vacuous: no {b.what} with every premise of {b.lemma.id} holding in "
                                   f"{self.steps} steps{extra}", applicable=False, detail=detail)
        tail = "premises held" if b.only else "premises held and the conclusion followed"
        return InvariantResult(name, "held", b.citation, None,
                               f"{n} {b.what}: {tail}{extra}", detail=detail)
