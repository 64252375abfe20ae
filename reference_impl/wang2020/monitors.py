"""Runtime monitors of the premises of Wang & Rubenstein 2020's lemmas on the grid (004, issue 15).

The z3 lemmas (:mod:`.lemmas`) prove the planner collision-free (Theorems IV-A.1/IV-A.2)
under premises about claims, priorities, spacing and what each robot has heard; these checks
over a trace (or one step of a streaming run) say whether a run met them.  Importing this
module registers them with :mod:`swarmproof.invariants.premises` (the shared mechanism).

The premise monitors, derived from their lemma's one definition (bindings, issue 32):
``grid_priorities`` (:data:`GRID_PRIORITIES`, :func:`grid_priorities_distinct`: premise
``distinct_priorities`` of ``wang2020_planner_vertex_one_moment``) and ``grid_waited``
(:data:`GRID_WAITED`, :func:`grid_waited_window`: premise ``i_waited_longer_than_window`` of
``wang2020_lemma_iv_a_1``).  The checks of the properties of :mod:`.properties` live here too
(they read the same states), each a property because no lemma states it as a run reads it
(docs/proofs.md, "Premise monitors of these lemmas"): ``grid_claims``
(:func:`grid_claims_distinct`: Thms. IV-A.1/IV-A.2's conclusions at one moment, which the lemmas
state over claim intervals a state does not record), ``grid_heard``
(:func:`grid_heard_neighbours`, :class:`GridHeard`: who is owed a message, from the frames of a
whole window) and ``grid_spacing`` (:func:`grid_spacing_of_trace`: the run's parameters, not a step).

References
----------
004_004a3703645971e3.txt Sec. II-A, Sec. III-A (Constraints III-A.1/2), Alg. 2, Thms. IV-A.1/IV-A.2.
"""

from __future__ import annotations

import math

import numpy as np

from swarmproof.invariants.lemma_monitor import Batch, Binding, MissingState
from swarmproof.invariants.premises import MISSING, examined_steps, register_binding
from swarmproof.invariants.result import InvariantResult, state_value
from swarmproof.models.sensing import INCLUSIVE_SLACK

from .lemmas import LEMMA_IV_A_1, PLANNER_VERTEX_ONE_MOMENT

__all__ = ["grid_claims_distinct", "grid_priorities_distinct", "grid_spacing_bound", "grid_spacing_of_trace",
           "SPEED_BOUND", "grid_waited_window", "grid_heard_neighbours", "GridHeard", "GRID_PRIORITIES", "GRID_WAITED"]

#: Cites of the grid monitors: the lemmas of :mod:`swarmproof.reference_impl.wang2020.lemmas`.
_GRID_CITES = {
    "claims": "wang2020_separation_equal_speeds, wang2020_theorem_iv_a_2 (004 Thms. IV-A.1/IV-A.2, Constraints III-A.1/2)",
    "priorities": "wang2020_planner_vertex_one_moment, wang2020_lemma_iv_a_1 (004 Alg. 2 line 28, Sec. II-B)",
    "spacing": "wang2020_separation_equal_speeds, wang2020_planner_vertex_one_moment (004 Sec. III-A: 2 sqrt(2) r <= l "
               "<= R/2); wang2020_separation_speeds where speeds differ (004 Sec. V-B3: l >= 2 r sqrt(v_max^2 + "
               "v_min^2) / v_min)",
    "waited": "wang2020_lemma_iv_a_1 (004 Alg. 2 line 30: waited longer than Delta t)",
    "heard": "wang2020_lemma_iv_a_1 (004 Sec. II-A c, e: every robot within R throughout the window heard)",
}


def _cell(value):
    """A waypoint from a state value: a pair of integers as a tuple, None stays None."""
    return None if value is None else tuple(int(c) for c in value)


def _grid_states(trace, t, keys):
    """``{slot: {key: value}}`` for the robots present at ``t``; ``(slot, key)`` of the first
    state that lacks a key instead, as ``("missing", slot, key)``."""
    out = {}
    pres = trace.present_at(t)
    for k in range(trace.n):
        if not pres[k]:
            continue
        st = trace.states[t][k]
        row = {}
        for key in keys:
            val = state_value(st, key, MISSING)
            if val is MISSING:
                return ("missing", k, key)
            row[key] = val
        out[k] = row
    return out


def _grid_steps(trace):
    """The recorded states a grid monitor reads: after every examined step (and the start)."""
    r = examined_steps(trace)
    return ([r.start] if r.start == 0 else []) + [t + 1 for t in r]


def grid_claims_distinct(trace, phi: float = 0.0, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """Claims distinct and no edge swap, in every recorded state (004 Constraints III-A.1/2, the
    conclusions of Thms. IV-A.1/IV-A.2 and premises of ``wang2020_separation_equal_speeds``): the
    property ``grid_claims`` (:mod:`.properties`).

    A robot's claim (Alg. 2's ``wp``) is its state's ``"next"`` when that is not None (the
    waypoint it moves or decided to move to), else its ``"cell"``.  Violated when two robots
    share a cell or a claim, or when one's ``next`` is the other's ``cell`` and the other way
    round (opposite travel on one edge).  A state without ``cell`` and ``next`` is
    ``inconclusive``.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 2, 3)); poses[:, 1, 0] = 0.2
    >>> st = ((("cell", (0, 0)), ("next", (1, 1))), (("cell", (1, 0)), ("next", (1, 1))))
    >>> r = grid_claims_distinct(Trace(ids=[1, 2], poses=poses, states=[st, st]))
    >>> r.status, r.witness["robots"], r.witness["waypoint"], r.witness["lemma"]
    ('violated', [1, 2], [1, 1], 'wang2020_separation_equal_speeds')
    """
    name, cites = "grid_claims", _GRID_CITES["claims"]
    checked = 0
    for t in _grid_steps(trace):
        rows = _grid_states(trace, t, ("cell", "next"))
        if isinstance(rows, tuple):
            return InvariantResult(name, "inconclusive", cites, None,
                                   f"robot {int(trace.ids[rows[1]])} has no {rows[2]!r} in its state at step {t}")
        cells, claims, nxt = {}, {}, {}
        for k, row in sorted(rows.items()):
            cell, n = _cell(row["cell"]), _claim_of(trace.states[t][k], row)
            if cell is None:                    # not started yet (no waypoint before its first tick)
                continue
            checked += 1
            nxt[k] = n
            claim = _cell(state_value(trace.states[t][k], "wp", None)) or (n if n is not None else cell)
            for what, key, table in (("cell", cell, cells), ("claim", claim, claims)):
                if key in table:
                    a, b = int(trace.ids[table[key]]), int(trace.ids[k])
                    return InvariantResult(
                        name, "violated", cites,
                        {"step": t, "robots": [a, b], "waypoint": list(key), "kind": f"shared_{what}",
                         "lemma": "wang2020_separation_equal_speeds"},
                        f"robots {a} and {b} share the {what} {key} at step {t} (Constraint III-A.1)")
                table[key] = k
        for k, n in nxt.items():
            if n is None:
                continue
            j = cells.get(n)
            if j is not None and j != k and nxt.get(j) == _cell(rows[k]["cell"]):
                a, b = sorted((int(trace.ids[k]), int(trace.ids[j])))
                return InvariantResult(
                    name, "violated", cites,
                    {"step": t, "robots": [a, b], "waypoint": list(n), "kind": "edge_swap",
                     "lemma": "wang2020_theorem_iv_a_2"},
                    f"robots {a} and {b} travel one edge in opposite directions at step {t} (Constraint III-A.2)")
    return InvariantResult(name, "held", cites, None, f"{checked} robot-states with distinct cells and claims",
                           applicable=checked > 0, detail={"checked": checked})


def _priority_pairs(view):
    """Every pair of robots within ``phi`` (= ``R``, inclusive) of each other in a recorded state,
    both with a priority (None: not started yet), as instances of ``distinct_priorities``: the
    state after the step (and, in step 0, the start's too), ``q0``, ``q1`` the pair's priorities and
    ``q2``, ``q3`` two idle agents off the grid (priorities larger than every one of the step: the
    lemma's own reading of fewer than 3 neighbours, ``PLANNER_VERTEX_ONE_MOMENT.not_proved``), so
    the premise holds exactly when the pair's priorities differ.  The pairs are chosen within the
    disc of radius ``R`` (the lemma's ``neighbour_k_within_R`` is the square around it, a weaker
    premise: docs/decisions.md)."""
    ids_all = np.asarray(view.ids)
    for when in ((0, 1) if view.t == 0 else (1,)):
        ks = np.flatnonzero(view.present[when])
        states = view.states[when]
        prio = []
        for k in ks.tolist():
            q = state_value(states[k], "priority", MISSING)
            if q is MISSING:
                raise MissingState(f"robot {view.id(k)} has no 'priority' in its state at step {view.t + when}")
            prio.append(q)
        started = [i for i, q in enumerate(prio) if q is not None]
        if len(started) < 2:
            continue
        ks = ks[started]
        q = np.array([tuple(prio[i]) for i in started], dtype=float).reshape(len(started), -1)
        xy = view.p[when][ks, :2]
        d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
        a, b = np.nonzero(np.triu(d <= view.phi * INCLUSIVE_SLACK, 1))
        if not a.size:
            continue
        ids = ids_all[ks]
        pad = float(np.max(np.abs(q))) + 1.0
        yield Batch({"robots": np.stack([ids[a], ids[b]], axis=1)},
                    {"q0_x": q[a, 0], "q0_y": q[a, 1], "q1_x": q[b, 0], "q1_y": q[b, 1],
                     "q2_x": pad, "q2_y": pad, "q3_x": pad + 1.0, "q3_y": pad + 1.0},
                    facts={"priority": q[a], "frame": view.t + when})


#: ``grid_priorities``: robots within ``R`` of each other have distinct priorities in every recorded
#: state -- the premise ``distinct_priorities`` of ``wang2020_planner_vertex_one_moment`` (the
#: lexicographic priority of distinct waypoints, 004 Sec. II-B), on every pair within ``R``.
GRID_PRIORITIES = Binding("grid_priorities", PLANNER_VERTEX_ONE_MOMENT, _priority_pairs, what="pairs within R",
                          only=("distinct_priorities",), cites=_GRID_CITES["priorities"])


def grid_priorities_distinct(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """:data:`GRID_PRIORITIES` over ``trace``: robots within ``phi`` (= ``R``) of each other have
    distinct ``"priority"`` values in every recorded state (premise ``distinct_priorities`` of
    ``wang2020_planner_vertex_one_moment``).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 2, 3)); poses[:, 1, 0] = 0.2
    >>> st = ((("priority", (0, 0)),), (("priority", (0, 0)),))
    >>> r = grid_priorities_distinct(Trace(ids=[1, 2], poses=poses, states=[st, st]), 0.6)
    >>> r.witness["robots"], r.witness["premise"]
    ([1, 2], 'distinct_priorities')
    """
    return GRID_PRIORITIES.check(trace, phi, v, dt)


#: Sec. V-B3's bound on the grid length for agents of different speeds, as the witness names it.
SPEED_BOUND = "l >= 2 r sqrt(v_max^2 + v_min^2) / v_min"


def grid_spacing_bound(l: float, r: float, R: float, v_min: float | None = None,
                       v_max: float | None = None) -> InvariantResult:
    """``2 sqrt(2) r <= l <= R / 2`` (004 Sec. III-A), the grid-length premise of
    ``wang2020_separation_equal_speeds`` (lower bound) and of the planner lemmas (upper bound:
    agents that can conflict, at most ``2l`` apart, hear each other); and where the agents' speeds
    differ (``v_min < v_max``), Sec. V-B3's ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min``
    (:func:`~swarmproof.reference_impl.wang2020.algorithm.speed_buffer_bound`), the premise of
    ``wang2020_separation_speeds``.  The upper bound is not relaxed by V-B3; at equal speeds V-B3's
    bound is Sec. III-A's lower one and is not checked twice.  Sec. V's values pass:

    >>> grid_spacing_bound(0.20, 0.05, 0.6).status
    'held'
    >>> grid_spacing_bound(0.14, 0.05, 0.6).witness["bound"]
    'l >= 2 sqrt(2) r'
    >>> slow = grid_spacing_bound(0.20, 0.05, 0.6, v_min=0.025, v_max=0.05)
    >>> slow.status, slow.witness["bound"], round(slow.witness["need"], 6)
    ('violated', 'l >= 2 r sqrt(v_max^2 + v_min^2) / v_min', 0.223607)
    """
    name, cites = "grid_spacing", _GRID_CITES["spacing"]
    vals = {"l": l, "r": r, "R": R}
    speeds = {} if v_min is None or v_max is None else {"v_min": v_min, "v_max": v_max}
    for key, val in {**vals, **speeds}.items():
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            return InvariantResult(name, "inconclusive", cites, None, f"{key}={val!r} is not a positive number")
    low = 2 * math.sqrt(2) * r
    for ok, bound in ((l >= low * (1 - 1e-12), "l >= 2 sqrt(2) r"), (l <= R / 2 * (1 + 1e-12), "l <= R/2")):
        if not ok:
            return InvariantResult(name, "violated", cites,
                                   {"step": 0, **vals, "bound": bound, "lemma": "wang2020_separation_equal_speeds"
                                    if bound.startswith("l >=") else "wang2020_planner_vertex_one_moment"},
                                   f"grid length l={l!r} breaks {bound} (r={r!r}, R={R!r})")
    held = f"2 sqrt(2) r = {low:.6g} <= l = {l:g} <= R/2 = {R / 2:g}"
    if speeds and v_min != v_max:
        from swarmproof.reference_impl.protocol import Params

        from .algorithm import speed_buffer_bound

        need = speed_buffer_bound(Params(range=R, extra={"robot_radius": r, "speed_min": min(v_min, v_max),
                                                         "speed_max": max(v_min, v_max)}))
        if l < need - 1e-12:
            return InvariantResult(name, "violated", cites,
                                   {"step": 0, **vals, **speeds, "bound": SPEED_BOUND, "need": need,
                                    "lemma": "wang2020_separation_speeds"},
                                   f"grid length l={l!r} breaks Sec. V-B3's {SPEED_BOUND} = {need:.6g} for speeds "
                                   f"in [{v_min:g}, {v_max:g}] (r={r!r})")
        held += f"; Sec. V-B3 at speeds [{v_min:g}, {v_max:g}]: l >= {need:.6g}"
    return InvariantResult(name, "held", cites, None, held)


def _grid_params(trace, phi: float):
    """``(l, r)`` from the trace's meta (``grid_spacing``; ``params.extra`` ``grid_spacing`` and
    ``robot_radius`` or ``radius``), None where absent."""
    meta = getattr(trace, "meta", None) or {}
    extra = (meta.get("params") or {}).get("extra") or {}
    l = meta.get("grid_spacing", extra.get("grid_spacing"))
    r = extra.get("robot_radius", extra.get("radius"))
    return l, r


def _run_speeds(trace):
    """``(v_min, v_max)`` of the run's agents: the slowest and fastest of the speeds the engine drew
    (``meta["speeds"]["speed"]``, recorded only when they differ), else ``params.extra``'s
    ``speed_min`` / ``speed_max`` when both are given; ``(None, None)`` for one common speed."""
    meta = getattr(trace, "meta", None) or {}
    drawn = (meta.get("speeds") or {}).get("speed")
    if drawn:
        return float(min(drawn)), float(max(drawn))
    extra = (meta.get("params") or {}).get("extra") or {}
    lo, hi = extra.get("speed_min"), extra.get("speed_max")
    return (None, None) if lo is None or hi is None else (float(lo), float(hi))


def grid_spacing_of_trace(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """:func:`grid_spacing_bound` with ``l`` and ``r`` from ``trace.meta`` (``inconclusive``,
    never held, when the trace does not record them, e.g. a one-step streaming window), and, where
    the run's agents had different speeds, Sec. V-B3's bound at the slowest and fastest of them
    (:func:`_run_speeds`: the speeds drawn, which the premise of ``wang2020_separation_speeds`` is
    about, not the range they were drawn from, which the ``speed_buffer`` assumption checks)."""
    l, r = _grid_params(trace, phi)
    if l is None or r is None:
        return InvariantResult("grid_spacing", "inconclusive", _GRID_CITES["spacing"], None,
                               "the trace records no grid_spacing and robot_radius (params.extra)")
    v_min, v_max = _run_speeds(trace)
    return grid_spacing_bound(float(l), float(r), phi, v_min, v_max)


def _claim_of(state, row):
    """The waypoint a robot travels to: with a ``"moving"`` key (the wang2020 controller), its
    ``"wp"`` while it moves and None while it waits (its ``"next"`` is then only an intent);
    without one, its ``"next"``."""
    moving = state_value(state, "moving", MISSING)
    if moving is MISSING:
        return _cell(row["next"])
    return _cell(state_value(state, "wp", None)) if moving else None


def _set_off(before, after):
    """A robot set off between the states ``before`` and ``after`` of a step: ``moving`` False
    before and True after when the states have that key (the wang2020 controller), else ``next``
    None before, not None after; MISSING when they have neither."""
    m0, m1 = state_value(before, "moving", MISSING), state_value(after, "moving", MISSING)
    if m0 is not MISSING and m1 is not MISSING:
        return (not m0) and bool(m1)
    n0, n1 = state_value(before, "next", MISSING), state_value(after, "next", MISSING)
    if n0 is MISSING or n1 is MISSING:
        return MISSING
    return n0 is None and n1 is not None


def _decided(trace, t, k):
    """Robot slot ``k`` set off in step ``t`` (:func:`_set_off`)."""
    return _set_off(trace.states[t][k], trace.states[t + 1][k])


def _sets_off(view, k: int) -> bool:
    """Robot slot ``k`` set off in the step (:func:`_set_off`, read from a ``StepView``)."""
    went = _set_off(view.states[0][k], view.states[1][k])
    if went is MISSING:
        raise MissingState(f"robot {view.id(k)} has no 'next' in its state")
    return went


def _departures(view):
    """Every robot that sets off in the step (Alg. 2 lines 30-31), as agent ``a_i`` of Lemma IV-A.1
    at its ``t* = 0``: ``last_check_i = -2 waited / window``, time in units of ``Delta t / 2`` (the
    lemma's ``1/f_comm`` where ``Delta t = 2/f_comm``, Alg. 2 line 6; the relaxed ``Delta t`` of Sec.
    V-B3 is the same premise in its own units).  The quotient keeps the controller's comparison
    exactly: ``waited > window`` makes ``waited / window >= 1 + ulp / window > 1 + 2**-53``, which
    rounds above 1 (and ``waited < window`` below it); doubling is exact.  ``waited`` (time since ``last_check`` when it
    decided) and ``window`` (its ``Delta t``) from the state after the step."""
    ks, waited, window = [], [], []
    for k in view.robots():
        if not _sets_off(view, k):
            continue
        w, win = state_value(view.states[1][k], "waited", MISSING), state_value(view.states[1][k], "window", MISSING)
        if w is MISSING or win is MISSING:
            raise MissingState(f"robot {view.id(k)} set off in step {view.t} without 'waited' and 'window' "
                               "in its state")
        ks.append(k)
        waited.append(float(w))
        window.append(float(win))
    if ks:
        w, win = np.array(waited), np.array(window)
        yield Batch({"robot": view.ids_of(ks)}, {"last_check_i": -2.0 * w / win},
                    facts={"waited": w, "window": win})


#: ``grid_waited``: a robot that sets off had waited at its waypoint longer than its window -- the
#: premise ``i_waited_longer_than_window`` of ``wang2020_lemma_iv_a_1`` (004 Alg. 2 line 30), for
#: every departure.  ``tol=0``: ``waited`` and ``window`` are the numbers the controller compared, so
#: a departure at ``waited == window`` (the off-by-one ``>=`` of line 30) is a failure, not a
#: boundary instance.
GRID_WAITED = Binding("grid_waited", LEMMA_IV_A_1, _departures, what="departures",
                      only=("i_waited_longer_than_window",), cites=_GRID_CITES["waited"], tol=0.0)


def grid_waited_window(trace, phi: float = 0.0, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """:data:`GRID_WAITED` over ``trace``: a robot that sets off in step ``t`` (its ``"moving"``
    False before, True after; without that key its ``"next"`` None before, not None after) had
    waited at its waypoint longer than the window: state keys ``"waited"`` and ``"window"`` from
    the state after the step (004 Alg. 2 line 30).  ``phi`` is not read (1 when not given).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 1, 3))
    >>> before = ((("next", None), ("waited", 1.0), ("window", 2.0)),)
    >>> after = ((("next", (1, 0)), ("waited", 1.5), ("window", 2.0)),)
    >>> r = grid_waited_window(Trace(ids=[7], poses=poses, states=[before, after]))
    >>> r.status, r.witness["robot"], r.witness["waited"], r.witness["premise"]
    ('violated', 7, 1.5, 'i_waited_longer_than_window')
    """
    return GRID_WAITED.check(trace, phi if phi and phi > 0 else 1.0, v, dt)


def grid_heard_neighbours(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """A robot that sets off in step ``t`` had heard, within its window, every robot that was within
    ``phi`` (= ``R``) of it throughout that window (004 Sec. II-A b, c, e; premise
    ``lossless_delivery_within_R`` of ``wang2020_lemma_iv_a_1``): the whole-trace form of
    :class:`GridHeard`, which states the premise exactly (which robots, which frames, which window).

    State keys, from the state after the step: ``"heard"`` (the ids the robot holds a message of in
    its ``msg_buff``, 004 Alg. 2 line 15) and ``"window"`` (its ``Delta t``, local clock units); a
    departure is read by ``"moving"`` (or ``"next"``).  The clocks come from ``trace.meta``
    (``clocks``: the engine's per-robot rates and ``broadcast_every``; else ``params.extra``'s
    ``clock_rate_min`` / ``clock_rate_max`` / ``broadcast_every``; else 1, the engine's defaults).

    Examples
    --------
    Robot 2 stands 0.2 m from robot 1 for three steps (a window of 2 steps, a broadcast every
    step); robot 1 sets off in step 2 without a message from it:

    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((4, 2, 3)); poses[:, 1, 0] = 0.2
    >>> wait = ((("moving", False), ("heard", ()), ("window", 2.0)),) * 2
    >>> went = ((("moving", True), ("heard", ()), ("window", 2.0)), wait[1])
    >>> r = grid_heard_neighbours(Trace(ids=[1, 2], poses=poses, states=[wait] * 3 + [went]), 0.6)
    >>> r.status, r.witness["robot"], r.witness["unheard"], r.witness["frames"]
    ('violated', 1, [2], [1, 2])

    Had robot 2 come within R only in step 2 (it was 0.8 m away before), nothing was owed yet:

    >>> poses[:2, 1, 0] = 0.8
    >>> r = grid_heard_neighbours(Trace(ids=[1, 2], poses=poses, states=[wait] * 3 + [went]), 0.6)
    >>> r.status, r.detail["arrived_unheard"]
    ('held', 1)
    """
    acc = GridHeard(phi, meta=getattr(trace, "meta", None))
    acc.scan(trace)
    return acc.result()


def _clock_facts(meta) -> tuple:
    """``(rates by slot or None, rate_min, rate_max, broadcast_every)`` from a trace's meta: the
    engine's recorded ``clocks`` (exact), else ``params.extra`` (bounds), else the engine's
    defaults (every rate 1, a broadcast every step)."""
    meta = meta or {}
    extra = (meta.get("params") or {}).get("extra") or {}
    try:
        lo = float(extra.get("clock_rate_min", 1.0))
        hi = float(extra.get("clock_rate_max", lo))
        every = float(extra.get("broadcast_every", 1.0))
    except (TypeError, ValueError):
        lo = hi = every = 1.0
    clocks = meta.get("clocks") or {}
    rates = clocks.get("rate")
    if rates is not None:
        rates = [float(x) for x in rates]
        every = float(clocks.get("broadcast_every", every))
        if rates:
            lo, hi = min(rates), max(rates)
    return rates, lo, hi, every


#: Frames :class:`GridHeard` keeps at least (a window longer than this many steps is still judged:
#: the history grows to the longest window read).
_HEARD_HISTORY = 64


class GridHeard:
    """The property ``grid_heard`` (:mod:`.properties`): the delivery that the premise
    ``lossless_delivery_within_R`` of ``wang2020_lemma_iv_a_1`` takes for granted, with who is owed
    it selected as the lemma's proof uses it, over a whole trace or step by step (:meth:`scan` the
    one-step windows of :class:`~swarmproof.invariants.premises.StepFeed`, fed by the engine; it
    keeps the frames of the last windows itself).

    The statement (004 Lemma IV-A.1's proof, Sec. II-A b, c, e; the engine's timing,
    docs/engine.md): robot ``i`` sets off in step ``t`` (Alg. 2 lines 30-31) reading its
    ``msg_buff`` (line 15): the messages received in the steps ``u`` with ``t - W <= u <= t``,
    where ``W = floor(Delta t / rate_i)`` steps.  A message received in step ``u`` is a broadcast
    of step ``u - 1`` delivered to the robots within ``R`` (inclusive) at frame ``u``, the start of
    step ``u``.  Every robot ``j`` that was present and within ``R`` of ``i`` at *every* frame
    ``u`` of that window, and broadcast in it, must be among ``i``'s ``"heard"``.

    Why these robots.  The lemma's other agent ``a_j`` changes its claim to ``wp^1`` at
    ``t_j <= t*`` (the case the proof excludes); it waited more than ``Delta t`` one edge from
    ``wp^1`` before ``t_j`` and then travels toward ``wp^1``, so throughout ``i``'s window it is
    at most ``2 l <= R`` from ``i`` (Sec. III-A); every robot within ``R`` throughout is owed
    delivery by Sec. II-A c, e.  A robot that comes within ``R`` during the window is neither the
    lemma's ``a_j`` nor owed its earlier broadcasts (sent from beyond ``R``), so it is not checked
    (``detail["arrived_unheard"]`` counts those that were not heard; issue 15, the explorer's first
    counterexample, docs/wang2020.md).

    Where the window is not known exactly (the streaming form, which sees no per-robot clock
    rates): the span ``i``'s window may cover is taken at its longest (``rate_min``) for "within
    ``R`` throughout", and at its shortest (``rate_max``), less the boundary step (floating
    point at the cutoff), for "``j`` broadcast in it": ``K`` steps with ``K * rate_j >=
    broadcast_every``.  With equal rates (Sec. II-A a) both are the same window.  Receipts before
    step 1 do not exist (nobody broadcast before step 0).

    Blind spots: ``"heard"`` lists senders, not messages, so "every broadcast of ``j`` reached
    ``i``" is checked as "at least one did"; a window whose frames a sparse trace did not keep is
    not judged (``inconclusive`` if no violation is found; the streaming form sees every step).
    """

    name = "grid_heard"

    def __init__(self, phi: float, meta=None) -> None:
        self.phi = float(phi)
        self.rates, self.rate_min, self.rate_max, self.every = _clock_facts(meta)
        self.frames: dict = {}         # engine step -> (xy (n, 2), present (n,))
        self.keep = _HEARD_HISTORY
        self.checked = 0               # departures judged
        self.owed = 0                  # (departure, robot) pairs owed delivery
        self.arrived_unheard = 0       # pairs within R at the departure, not throughout the window, unheard
        self.unjudged = 0              # departures whose window frames were not kept (sparse trace)
        self.first = None              # (witness, message) of the first violation
        self.missing = None            # message of a state without the keys

    def _rate(self, k: int, low: bool) -> float:
        if self.rates is not None and k < len(self.rates):
            return self.rates[k]
        return self.rate_min if low else self.rate_max

    def scan(self, trace) -> None:
        if self.missing is not None or self.first is not None:
            return
        times = getattr(trace, "times", None)
        at = (lambda f: f) if times is None else (lambda f: times[f])
        for t in examined_steps(trace):
            for f in (t, t + 1):
                step = at(f)
                if step not in self.frames:
                    self.frames[step] = (np.asarray(trace.poses[f])[:, :2].copy(), np.asarray(trace.present_at(f), bool).copy())
            a = at(t)
            for old in [s for s in self.frames if s < a - self.keep]:
                del self.frames[old]
            pres0, pres1 = trace.present_at(t), trace.present_at(t + 1)
            for k in range(trace.n):
                if not (pres0[k] and pres1[k]):
                    continue
                went = _decided(trace, t, k)
                if went is MISSING:
                    self.missing = f"robot {int(trace.ids[k])} has no 'moving' or 'next' in its state"
                    return
                if not went:
                    continue
                after = trace.states[t + 1][k]
                heard, window = state_value(after, "heard", MISSING), state_value(after, "window", MISSING)
                if heard is MISSING or window is MISSING:
                    self.missing = (f"robot {int(trace.ids[k])} set off in step {a} without 'heard' and 'window' "
                                    "in its state")
                    return
                self._departure(trace, a, k, float(window), {int(h) for h in heard})
                if self.first is not None:
                    return

    def _departure(self, trace, a: int, k: int, window: float, heard: set) -> None:
        span = int(math.floor(window / self._rate(k, True) + 1e-9))       # the longest window, in steps
        sure = int(math.floor(window / self._rate(k, False) + 1e-9))      # the shortest
        self.keep = max(self.keep, span + 2)
        lo = max(1, a - span)                                             # receipts exist from step 1
        steps = range(lo, a + 1)
        if not steps:
            self.checked += 1                                             # step 0: nothing received yet
            return
        if any(u not in self.frames for u in steps):
            self.unjudged += 1
            return
        self.checked += 1
        xy = np.stack([self.frames[u][0] for u in steps])                 # (frames, n, 2)
        pres = np.stack([self.frames[u][1] for u in steps])
        d = np.hypot(xy[:, :, 0] - xy[:, k:k + 1, 0], xy[:, :, 1] - xy[:, k:k + 1, 1])
        within = (d <= self.phi * INCLUSIVE_SLACK) & pres & pres[:, k:k + 1]
        throughout = within.all(axis=0)
        now = within[-1]
        K = a - max(1, a - sure + 1) + 1                                  # broadcast steps surely read
        ids = trace.ids
        unheard, arrived = [], 0
        for j in range(trace.n):
            if j == k or not now[j]:
                continue
            rid = int(ids[j])
            if rid in heard:
                continue
            if not throughout[j]:
                arrived += 1
                continue
            if K * self._rate(j, True) < self.every * (1 - 1e-12):
                continue                                                  # j need not have broadcast in it
            unheard.append(rid)
        owed = int(sum(1 for j in range(trace.n) if j != k and throughout[j]))
        self.owed += owed
        self.arrived_unheard += arrived
        if unheard:
            rid = int(ids[k])
            witness = {"step": a, "robot": rid, "unheard": sorted(unheard), "frames": [lo, a],
                       "window_steps": span, "lemma": "wang2020_lemma_iv_a_1"}
            self.first = (witness, f"robot {rid} set off in step {a} without having heard {sorted(unheard)}, "
                                   f"within R throughout its window (steps {lo}..{a})")

    def result(self) -> InvariantResult:
        cites = _GRID_CITES["heard"]
        detail = {"checked": self.checked, "owed": self.owed, "arrived_unheard": self.arrived_unheard,
                  "unjudged": self.unjudged}
        if self.missing is not None:
            return InvariantResult(self.name, "inconclusive", cites, None, self.missing, detail=detail)
        if self.first is not None:
            witness, message = self.first
            return InvariantResult(self.name, "violated", cites, witness, message, detail=detail)
        if self.unjudged:
            return InvariantResult(self.name, "inconclusive", cites, None,
                                   f"{self.unjudged} departures whose window the trace did not keep (sparse); "
                                   f"{self.checked} judged, none unheard", detail=detail)
        return InvariantResult(self.name, "held", cites, None,
                               f"{self.checked} departures with every robot within R throughout the window heard "
                               f"({self.arrived_unheard} robots that came within R during a window, not owed)",
                               applicable=self.checked > 0, detail=detail)


# the premises of reference_impl/wang2020/lemmas.py's lemmas
register_binding(GRID_PRIORITIES)
register_binding(GRID_WAITED)
