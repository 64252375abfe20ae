"""Runtime monitors of the proved lemmas' premises: the shared mechanism (issue 5; issue 32).

The z3 lemmas (:mod:`swarmproof.checkers.proofs`, docs/proofs.md) are about mathematics; the
monitors say whether a run met the lemmas' premises at every step, which is what ties the proofs
to the code.  Each failure names its lemma.  Since issue 32 a monitor is derived from its lemma's
one definition by a *binding* (:mod:`swarmproof.invariants.lemma_monitor`): the binding reads a
step's instances, the monitor judges the lemma's own premise and conclusion functions on them.

This module holds what every algorithm shares: the registry of monitors (:data:`MONITORS`,
:func:`register_monitor`; a binding registers with
:func:`swarmproof.invariants.lemma_monitor.register_binding`), the batch and streaming drivers
(:func:`check_premises`, :class:`PremisesMonitor`) and the ``premises`` verdict
(:func:`premises`, :func:`combine_premises`).  Each paper's monitors live in its package and
register themselves when it is imported (``swarmproof.reference_impl.song2016.monitors``:
``step_bounded``, ``nclb``, ``relocate``, ``child_toward_parent``;
``...song2014.monitors``: ``parent_bounded_range``; ``...wang2020.monitors``: ``grid_priorities``,
``grid_waited``).  Every one is derived from a lemma definition (a binding); the checks that no
lemma states are properties of their algorithms (``tree_link_cases``, ``grid_claims``,
``grid_heard``, ``grid_spacing``: docs/proofs.md, "Premise monitors").

An algorithm's class says which monitors apply to it (``premise_monitors``: names, or
:class:`~swarmproof.invariants.lemma_monitor.Binding` objects of its own); the engine records
them in ``trace.meta["premise_monitors"]`` and :func:`check_premises` runs those of the trace.

Blind spots: poses are sampled at step ends (straight-line motion is assumed in between, as the
lemmas assume); a state without the keys a monitor reads makes it ``inconclusive`` rather than
``held``.

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7; 001_7a4e517b856331bc.txt Lemma 7, Def. 8,
Sec. V-C (NCLB, relocate robot), Lemma 11.

Examples
--------
>>> import numpy as np
>>> import swarmproof.reference_impl.song2016      # registers song2016's monitors
>>> from swarmproof.models.trace import Trace
>>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.2, 0, 0]]], dtype=float)
>>> t = Trace(ids=[1, 2], poses=poses, states=[((), ())] * 2)
>>> MONITORS["step_bounded"](t, 1.0, 0.1, 1.0).witness["moved"]
0.2
"""

from __future__ import annotations

import math

import numpy as np


from .lemma_monitor import Binding, examined_steps
from .result import InvariantResult

__all__ = ["check_premises", "params_of", "MONITORS",
           "MONITOR_LEMMAS", "register_monitor", "premise_monitors_of", "PremisesMonitor", "premises",
           "combine_premises", "CITE_PREMISES", "register_binding", "BINDINGS", "MISSING", "Window", "StepFeed", "examined_steps", "present_robot_steps",
           "slot_of"]

MISSING = object()


def params_of(trace) -> tuple:
    """``(phi, v, dt)`` from ``trace.meta["params"]`` (the engine records them)."""
    p = trace.meta.get("params") or {}
    try:
        return float(p["range"]), float(p["v"]), float(p["dt"])
    except (KeyError, TypeError, ValueError):
        raise ValueError("trace.meta['params'] must hold range, v and dt; "
                         "pass phi, v and dt explicitly") from None


class Window:
    """Two consecutive steps ``t0`` and ``t0 + 1`` seen as a trace indexed by absolute step,
    so the monitors examine exactly one step and name it by its number."""

    def __init__(self, ids, meta, prev, cur) -> None:
        (t0, p0, s0, m0), (t1, p1, s1, m1) = prev, cur
        self.ids, self.meta, self.n = ids, meta, len(ids)
        self.steps = t0 + 1
        self.step_range = range(t0, t0 + 1)
        # the frame kept after step t0 is the engine's step t1 (= t0 + 1)
        self.poses = {t0: p0, t0 + 1: p1}
        self.states = {t0: s0, t0 + 1: s1}
        self._present = {t0: m0, t0 + 1: m1}

    def present_at(self, t):
        return self._present[t]


class StepFeed:
    """The streaming monitor of a check with memory across steps (an object with ``scan(trace)``
    and ``result()``, e.g. song2016's ``TreeLinkCases``): the engine feeds it every step
    (``simulate(observers=...)``) and it scans that step as a :class:`Window`, so a check that
    reads every step runs on every step whatever a sparse trace keeps.  ``name`` is the property's
    (:meth:`~swarmproof.invariants.registry.Property.judge` finds it by that name)."""

    def __init__(self, name: str, scanner) -> None:
        self.name, self.scanner = name, scanner
        self._prev = None

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)

    def observe(self, t, poses, states, present) -> None:
        cur = (int(t), np.array(poses, copy=True), states, np.array(present, copy=True))
        prev, self._prev = self._prev, cur
        if prev is not None:
            self.scanner.scan(Window(self.ids, {}, prev, cur))

    def result(self) -> InvariantResult:
        return self.scanner.result()


def present_robot_steps(trace):
    """``(t, k, before, after, p0, p1, pres0, pres1)`` for every examined step ``t`` and every
    robot slot ``k`` present at both of its ends (states and poses before and after the step)."""
    for t in examined_steps(trace):
        before, after = trace.states[t], trace.states[t + 1]
        p0, p1 = trace.poses[t], trace.poses[t + 1]
        pres0, pres1 = trace.present_at(t), trace.present_at(t + 1)
        for k in range(trace.n):
            if pres0[k] and pres1[k]:
                yield t, k, before, after, p0, p1, pres0, pres1


def slot_of(trace) -> dict:
    return {int(i): k for k, i in enumerate(trace.ids.tolist())}


def check_premises(trace, phi: float | None = None, v: float | None = None,
                   dt: float | None = None, monitors=None) -> list:
    """The premise monitors of the trace's algorithm over one trace.

    Parameters
    ----------
    trace : Trace
        A recorded run (the engine's ``simulate(...).trace``).
    phi, v, dt : float, optional
        Range, speed and step; from ``trace.meta["params"]`` when omitted.
    monitors : sequence of str, optional
        Names from :data:`MONITORS`.  By default those the engine recorded
        from the algorithm (``trace.meta["premise_monitors"]``); a trace
        without them (written by hand, or before they were recorded) needs
        ``monitors``.

    Returns
    -------
    list of InvariantResult
        One per monitor, in order.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.05, 0, 0]]], dtype=float)
    >>> st = ((("parent", None),), (("parent", 1),))
    >>> t = Trace(ids=[1, 2], poses=poses, states=[st] * 2, meta={"algorithm": "mine",
    ...           "premise_monitors": ["step_bounded"],
    ...           "params": {"range": 1.2, "v": 0.1, "dt": 1.0}})
    >>> [(r.name, r.status) for r in check_premises(t)]
    [('premise:step_bounded', 'held')]
    """
    if phi is None or v is None or dt is None:
        mphi, mv, mdt = params_of(trace)
        phi = mphi if phi is None else phi
        v = mv if v is None else v
        dt = mdt if dt is None else dt
    if not (math.isfinite(phi) and phi > 0 and v >= 0 and dt > 0):
        raise ValueError(f"phi={phi!r}, v={v!r}, dt={dt!r} must be positive finite numbers")
    if monitors is None:
        monitors = trace.meta.get("premise_monitors")
        if monitors is None:
            raise ValueError(f"trace of algorithm={trace.meta.get('algorithm')!r} names no premise monitors "
                             "(trace.meta['premise_monitors'], recorded by the engine from the algorithm's "
                             "premise_monitors); pass monitors=[...] from "
                             f"{sorted(MONITORS)!r}")
    return [MONITORS[m](trace, phi, v, dt) for m in _known(monitors)]


def _known(names) -> tuple:
    """``names`` as a tuple; ValueError naming the first that is not in :data:`MONITORS`."""
    from swarmproof.models.errors import UsageError

    names = tuple(names)
    for n in names:
        if n not in MONITORS:
            raise UsageError(f"premise monitor={n!r} is not known; use some of {sorted(MONITORS)!r}",
                             fix="name a registered monitor, or give a swarmproof.invariants.lemma_monitor.Binding "
                                 "object in premise_monitors (docs/lemmas.md)")
    return names


#: Every monitor by name: a function ``(trace, phi, v, dt) -> InvariantResult``.  Each paper's
#: package adds its own when it is imported (:func:`register_monitor`).
MONITORS: dict = {}

#: The proof-suite lemma (``swarmproof prove`` id) whose premise each monitor checks.
MONITOR_LEMMAS: dict = {}

#: Monitors with memory across steps, for :class:`PremisesMonitor`: name -> factory
#: ``(phi, v, dt, meta) -> object with scan(trace) and result()``.
_ACCUMULATING: dict = {}


def register_monitor(name: str, check, lemma: str, accumulating=None) -> None:
    """Add a premise monitor to :data:`MONITORS` (a paper's package does, when imported).

    Parameters
    ----------
    name : str
        The name algorithms list in ``premise_monitors`` (and traces record).
    check : callable
        ``(trace, phi, v, dt) -> InvariantResult`` over a whole trace or one
        :class:`Window` (a step of a streaming run).
    lemma : str
        The ``swarmproof prove`` id of the lemma whose premise it checks.
    accumulating : callable, optional
        ``(phi, v, dt, meta) -> object`` with ``scan(window)`` and ``result()``, for
        a monitor with memory across steps (:class:`PremisesMonitor` feeds it every step).

    Examples
    --------
    >>> register_monitor("my_bound", lambda trace, phi, v, dt: MONITORS["step_bounded"](trace, phi, v, dt),
    ...                  "bounded_range")
    >>> MONITOR_LEMMAS["my_bound"]
    'bounded_range'
    >>> _ = MONITORS.pop("my_bound"), MONITOR_LEMMAS.pop("my_bound")
    """
    MONITORS[name] = check
    MONITOR_LEMMAS[name] = lemma
    if accumulating is not None:
        _ACCUMULATING[name] = accumulating
    else:
        _ACCUMULATING.pop(name, None)


#: Every monitor derived from a binding, by name (:func:`register_binding`).
BINDINGS: dict = {}


def register_binding(binding: Binding) -> str:
    """Register the monitor a :class:`~swarmproof.invariants.lemma_monitor.Binding` derives, under
    ``binding.name`` (:func:`register_monitor`, accumulating); returns the name.  A paper's
    package does it when imported; an algorithm may list a ``Binding`` in its
    ``premise_monitors`` directly (:func:`premise_monitors_of` registers it)."""
    old = BINDINGS.get(binding.name)
    if old is not binding and (old is not None or binding.name in MONITORS):
        if old is None or old.lemma is not binding.lemma or old.instances is not binding.instances:
            from swarmproof.models.errors import UsageError

            raise UsageError(f"binding name={binding.name!r} is taken by another premise monitor "
                             f"(of lemma {MONITOR_LEMMAS.get(binding.name)!r})",
                             fix="give your Binding a name of its own (swarmproof list lemmas shows the "
                                 "monitors' lemmas)")
    BINDINGS[binding.name] = binding
    register_monitor(binding.name, binding.check, binding.lemma.id, accumulating=binding.monitor)
    return binding.name


def premise_monitors_of(algorithm) -> tuple:
    """The monitor names that apply to ``algorithm``: its class's ``premise_monitors``
    attribute (the lemmas its paper's proof uses), else ``()`` (no lemma premises declared).

    >>> premise_monitors_of(type("A", (), {"name": "mine"})())
    ()
    >>> premise_monitors_of(type("B", (), {"name": "mine", "premise_monitors": ("nclb",)})())
    ('nclb',)
    """
    names = getattr(algorithm, "premise_monitors", None)
    out = []
    for n in names or ():
        if not isinstance(n, str):          # a Binding declared by the algorithm itself
            if not isinstance(n, Binding):
                from swarmproof.models.errors import UsageError

                raise UsageError(f"premise_monitors entry={n!r} of algorithm={getattr(algorithm, 'name', algorithm)!r} "
                                 "is neither a monitor name nor a swarmproof.invariants.lemma_monitor.Binding",
                                 fix="list monitor names or Binding objects (a LemmaSpec goes in lemmas; "
                                     "docs/lemmas.md)")
            n = register_binding(n)
        out.append(n)
    return _known(out)


class PremisesMonitor:
    """Streaming form of the ``premises`` property: the engine feeds it every step
    (``simulate(observers=...)``) and each monitor examines that one step, so a premise that
    fails at a step a sparse trace does not keep is found.  Verdicts as
    :func:`swarmproof.invariants.properties.premises`: the earliest violation over all
    monitors, inconclusive when a monitor cannot read its state keys or none is declared."""

    name = "premises"

    def __init__(self, monitors, phi: float, v: float, dt: float, *, meta=None) -> None:
        self.monitors = _known(monitors)
        self.phi, self.v, self.dt = float(phi), float(v), float(dt)
        #: run facts for the accumulating monitors (e.g. ``{"params": {"extra": ...}}``); the
        #: one-step windows carry no meta
        self.meta = dict(meta or {})
        self._prev = None
        self.steps = 0
        self.final: dict = {}            # monitor -> a violated or inconclusive result (it stops there)
        self.checked = {m: 0 for m in self.monitors}
        # monitors that keep memory across steps (a binding's: it judges every step it sees)
        self.accumulating = {m: _ACCUMULATING[m](self.phi, self.v, self.dt, self.meta) for m in self.monitors
                             if m in _ACCUMULATING}

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)
        self.slot = {int(i): k for k, i in enumerate(self.ids.tolist())}

    def observe(self, t, poses, states, present) -> None:
        cur = (int(t), np.array(poses, copy=True), states, np.array(present, copy=True))
        prev, self._prev = self._prev, cur
        if prev is None:
            return
        self.steps += 1
        window = Window(self.ids, {}, prev, cur)     # (accumulating monitors got self.meta when made)
        for name in self.monitors:
            if name in self.accumulating:
                self.accumulating[name].scan(window)
                continue
            if name in self.final:
                continue
            r = MONITORS[name](window, self.phi, self.v, self.dt)
            if r.status != "held":
                self.final[name] = r
            else:
                self.checked[name] += int((r.detail or {}).get("checked", 0))

    def results(self) -> list:
        """``(monitor, InvariantResult)`` over every step seen."""
        out = []
        for name in self.monitors:
            r = self.accumulating[name].result() if name in self.accumulating else self.final.get(name)
            if r is None:
                n = self.checked[name]
                applicable = n > 0
                r = InvariantResult(f"premise:{name}", "held", MONITOR_LEMMAS[name], None,
                                    f"held at every one of {self.steps} steps ({n} cases examined)",
                                    applicable=applicable, detail={"checked": n})
            out.append((name, r))
        return out

    def result(self) -> InvariantResult:
        return combine_premises(self.monitors, self.results(), self.steps)


CITE_PREMISES = "issue 5 / docs/proofs.md: the premises of the proved lemmas hold at every step"


def premises(trace, monitors, phi: float, v: float, dt: float) -> InvariantResult:
    """The named lemma premise monitors hold at every step of ``trace``.

    ``monitors`` are names of :data:`MONITORS`
    (:func:`premise_monitors_of` gives the ones
    an algorithm declares).  The verdict is

    * ``violated`` when a monitor is: the earliest step over all monitors,
      the witness naming the ``lemma`` and the ``monitor``;
    * ``inconclusive`` when no monitor is declared (nothing to check), the
      trace has no step, or a monitor cannot read its state keys;
    * ``held`` otherwise; ``detail["monitors"]`` gives each monitor's
      status and what it examined (a monitor that examined nothing, e.g. no
      moving parent, says so: ``applicable`` False).

    Blind spots: those of the monitors (step ends only; straight motion
    assumed in between; the case analysis of the paper is not checked), and a
    premise can only be as faithful as the state keys the algorithm reports.

    Examples
    --------
    Robot 7 moves 0.3 in one step, more than ``v dt = 0.2``:

    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> start, end = [[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.3, 0, 0]]
    >>> t = Trace(ids=[4, 7], poses=np.array([start, end], float), states=[((), ())] * 2)
    >>> r = premises(t, ("step_bounded",), 1.2, 0.2, 1.0)
    >>> r.status, r.witness["lemma"], r.witness["monitor"]
    ('violated', 'bounded_range', 'step_bounded')
    >>> premises(t, (), 1.2, 0.2, 1.0).status
    'inconclusive'
    """
    monitors = _known(monitors)
    results = [(name, MONITORS[name](trace, phi, v, dt)) for name in monitors] if len(trace.poses) >= 2 else []
    return combine_premises(monitors, results, trace.steps)


def combine_premises(monitors, results, steps: int) -> InvariantResult:
    """The ``premises`` verdict from each monitor's result (see :func:`premises`)."""
    if not monitors:
        return InvariantResult("premises", "inconclusive", CITE_PREMISES, None,
                               "the algorithm declares no lemma premises to monitor")
    if steps < 1:
        return InvariantResult("premises", "inconclusive", CITE_PREMISES, None,
                               "the trace has no step to check")
    detail = {"monitors": {name: {"status": r.status, "applicable": r.applicable, **r.detail}
                           for name, r in results}}
    bad = [(name, r) for name, r in results if r.violated]
    if bad:
        name, r = min(bad, key=lambda nr: nr[1].witness["step"])
        lemma = r.witness["lemma"]
        what = (f"transfer failure of lemma {lemma}" if r.witness.get("transfer")
                else f"premise of lemma {lemma} failed")
        return InvariantResult("premises", "violated", CITE_PREMISES,
                               {**r.witness, "monitor": name}, f"{what}: {r.message}", detail=detail)
    unsure = [(name, r) for name, r in results if r.status == "inconclusive" and not _vacuous(r)]
    if results and all(_vacuous(r) for _, r in results):
        unsure = results
    if unsure:
        return InvariantResult("premises", "inconclusive", CITE_PREMISES, None,
                               "; ".join(f"{name}: {r.message}" for name, r in unsure), detail=detail)
    parts = [_part(name, r) for name, r in results]
    return InvariantResult("premises", "held", CITE_PREMISES, None,
                           f"premises held at all {steps} steps: {', '.join(parts)}", detail=detail)


def _part(name: str, r) -> str:
    """One monitor in the ``premises`` message: its name and what it judged (a derived monitor's
    checked, boundary and outside instances), or why it judged nothing."""
    if not r.applicable:
        return f"{name} ({'vacuous' if _vacuous(r) else 'nothing to examine'})"
    d = r.detail or {}
    if "boundary" in d:        # a monitor derived from a lemma (a binding)
        counts = ", ".join(f"{d[k]} {k}" for k in ("checked", "boundary", "outside") if d.get(k) or k == "checked")
        return f"{name} ({counts})"
    return name


def _vacuous(r) -> bool:
    """A monitor derived from a lemma that found no instance with every premise holding: it is
    ``inconclusive`` for the run (issue 32), and the ``premises`` verdict names it vacuous
    rather than letting it make the whole verdict inconclusive (docs/decisions.md)."""
    return r.status == "inconclusive" and bool((r.detail or {}).get("vacuous"))
