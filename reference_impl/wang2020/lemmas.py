"""z3 lemmas for Wang & Rubenstein 2020's collision-freedom (004 Sec. IV-A; issue 15).

Listed in the algorithm registry's lemma sets, so :data:`swarmproof.checkers.proofs.LEMMAS`
holds them (ids prefixed ``wang2020_``), and solved by :func:`swarmproof.checkers.proofs.prove` like every lemma of the suite: premises
satisfiable, the negated conclusion ``unsat``, a negative control refuted, vacuity controls.

Each is declared once as a :class:`~swarmproof.invariants.lemma_api.LemmaSpec` (:data:`SPECS`,
issue 32): its variables, named premises and conclusion are Python functions that give the z3
terms of its proof (:data:`LEMMAS` is built from them) and judge float values (a run's step, a
counterexample; ``cross_check``).  Yes/no choices are ``Bool(name, "real")`` (a real that means
yes iff it equals 1, so counterexamples list numbers), grid moves, waypoint offsets and
priorities ``IntPoint(..., "real")``: z3 reals, as these encodings were first written.  The
functions :func:`planner_one_moment`, :func:`lemma_iv_a_1`, :func:`theorem_iv_a_2`,
:func:`time_normalisation`, :func:`separation`, :func:`speed_buffer_cases` and
:func:`separation_speeds` give the specs' encodings with other arguments (a window, a rule, a
bound factor: the controls and the tests' variants).

Seven lemmas and a normalisation (docs/proofs.md, "Wang & Rubenstein 2020"):

* ``wang2020_planner_vertex_one_moment`` (auxiliary): Alg. 2's decision rule (lines 25-31,
  lexicographic priority) at one moment, every agent deciding on the current claims and
  intents of the agents within ``R``: no two agents move to one waypoint, no agent moves
  onto a waypoint another claims.  Control: line 28 (the priority check) removed.
* ``wang2020_planner_edge_one_moment`` (auxiliary): the same rule never lets two agents
  swap along one edge.  Control: line 26 treating an occupant that is about to leave as
  absent (an "optimistic" planner).
* ``wang2020_lemma_iv_a_1`` (paper lemma, 004 Lemma IV-A.1): with broadcasts every
  ``1/f_comm`` at arbitrary phases, the window ``Delta t = 2/f_comm`` (Alg. 2 line 6), the
  wait of more than ``Delta t`` (line 30) and lossless delivery, no agent claims the waypoint
  another agent changes its claim to, at the moment of the change.  Control: ``Delta t =
  1/f_comm``.
* ``wang2020_theorem_iv_a_2`` (paper lemma, 004 Thm. IV-A.2): given Thm. IV-A.1's conclusion
  (claims pairwise distinct at every instant), two agents never travel one edge in opposite
  directions at the same time.  Control: ``Delta t = 1/(2 f_comm)``.
* ``wang2020_separation_equal_speeds`` (auxiliary, DESIGN.md section 5: it assumes equal
  speeds): two discs of radius ``r`` on a grid with ``l >= 2 sqrt(2) r``, each resting at
  its waypoint or moving at the common speed along an edge, with claims distinct at every
  instant (Thm. IV-A.1) and no swap (Thm. IV-A.2), are at least ``2r`` apart at every
  instant ``t``: the exact distance at ``t``, ``t`` free.  Control: ``l`` 1 % below the bound.
* ``wang2020_speed_buffer_v_b3_cases`` (auxiliary): 004 Sec. V-B3's derivation of its buffer
  space, its two cases (orthogonal and collinear adjacent edges, a common start), speeds in
  ``[v_min, v_max]``, ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min``.  Control: ``l`` 1 % below.
* ``wang2020_separation_speeds`` (auxiliary): ``wang2020_separation_equal_speeds`` with a speed
  per agent in ``[v_min, v_max]`` and Sec. V-B3's ``l``: every pair of moves, any start times
  (does V-B3's case analysis miss a pair of edges? It does not: docs/wang2020.md, Findings).
  Control: ``l`` 1 % below the bound.

Normalisations (documented, docs/proofs.md): the grid length ``l = 1`` and one agent's
waypoint at the origin (the grid is invariant under translation by whole cells and under
scaling, ``translation_invariance``, ``scale_invariance``); for the timing lemmas the
broadcast period ``1/f_comm = 1`` and the moment of the change ``t* = 0``
(``wang2020_time_normalisation``: order of times is kept under ``t -> (t - c) / T``).

Examples
--------
>>> from swarmproof.checkers.proofs import prove
>>> r = prove(LEMMAS["wang2020_lemma_iv_a_1"])
>>> r.status, r.kind, r.negative_control["status"]
('proved', 'paper lemma', 'counterexample')

References
----------
004_004a3703645971e3.txt Sec. II-A (assumptions a-e), Sec. III-A (Constraints III-A.1 and
III-A.2, l >= 2 sqrt(2) r), Alg. 2, Alg. 3, Sec. III-C, Lemma IV-A.1, Thms. IV-A.1/IV-A.2,
Sec. V-B3.
"""

from __future__ import annotations

import dataclasses

from swarmproof.invariants.lemma_api import (And, Bool, Eq, Ge, Gt, Iff, Implies, IntPoint, Le, LemmaSpec, Lt, Ne,
                                             Not, Or, Point, Real, Xor, constant, dist2)
from swarmproof.invariants.lemmas import Encoding

__all__ = ["planner_one_moment", "lemma_iv_a_1", "theorem_iv_a_2", "separation", "speed_buffer_cases",
           "separation_speeds", "time_normalisation", "SPECS", "LEMMAS", "UNITS", "BROADCASTS",
           "TIME_NORMALISATION", "PLANNER_VERTEX_ONE_MOMENT", "PLANNER_EDGE_ONE_MOMENT", "LEMMA_IV_A_1",
           "THEOREM_IV_A_2", "SEPARATION_EQUAL_SPEEDS", "SPEED_BUFFER_V_B3_CASES", "SEPARATION_SPEEDS"]

#: The four grid moves of Alg. 2 line 9 (``surroundings``) and ``wait``, in units of ``l``.
UNITS = ((1, 0), (-1, 0), (0, 1), (0, -1))


# ------------------------------------------------------------------ helpers
#
# Premise and conclusion functions of LemmaSpec (swarmproof.invariants.lemma_api): every helper
# works on z3 terms (the proof) and on floats (a judgment, the cross-check) alike.  Yes/no
# choices are Bool(name, sort="real") variables: a real that means yes iff it is 1, so that
# counterexamples list numbers only (swarmproof.checkers.proofs.model_to_numbers).  Grid moves,
# waypoint offsets and priorities are IntPoint(..., sort="real"): reals for z3, exactly as these
# encodings were first written (z3's search, and so its rlimit count, depends on the sort), and
# whole numbers in the cross-check's draws, where the premises' equalities can hold.

def _one_of_moves(d, allow_wait: bool = True):
    """``d`` is one of the four unit moves (or ``(0, 0)``, wait, when ``allow_wait``)."""
    opts = list(UNITS) + ([(0, 0)] if allow_wait else [])
    return Or(*[And(Eq(d[0], a), Eq(d[1], b)) for a, b in opts])


def _peq(a, b):
    return And(Eq(a[0], b[0]), Eq(a[1], b[1]))


def _lex_gt(p, q):
    """``p > q`` in the lexicographic order of 004 Sec. II-B (``p^x > q^x``, or equal ``x``
    and ``p^y > q^y``)."""
    return Or(Gt(p[0], q[0]), And(Eq(p[0], q[0]), Gt(p[1], q[1])))


def _origin(like) -> tuple:
    """The origin as the kind of ``like`` (z3's ``RealVal(0)``, as the encodings were written)."""
    return (constant(0, like), constant(0, like))


def _disjoint(a0, a1, b0, b1):
    """Half-open intervals ``[a0, a1)`` and ``[b0, b1)`` do not meet (``None`` end: infinity)."""
    out = []
    if a1 is not None:
        out.append(Le(a1, b0))
    if b1 is not None:
        out.append(Le(b1, a0))
    return Or(*out) if out else constant(False, a0)


def _fn(make, *args):
    """A premise function: ``lambda v: make(v, *args)`` with ``args`` bound now (not late, as a
    lambda in a loop would bind them)."""
    return lambda v: make(v, *args)


# ------------------------------------------- (a) the planner at one moment

def _planner_variables(n: int) -> tuple:
    return ((Real("rho", 2.0, 4.0),) + tuple(IntPoint(f"c{k}", -3, 3, "real") for k in range(1, n))
            + tuple(IntPoint(f"d{k}", -1, 1, "real") for k in range(n))
            + tuple(IntPoint(f"q{k}", -2, 2, "real") for k in range(n))
            + tuple(Bool(f"ready{k}", "real") for k in range(n)))


def _planner_agents(v, n: int) -> tuple:
    """Waypoints ``c`` (agent 0's at the origin), intents ``nxt = c + d``, priorities ``q``,
    ``ready`` flags of the ``n`` agents."""
    c = [_origin(v.rho)] + [getattr(v, f"c{k}") for k in range(1, n)]
    d = [getattr(v, f"d{k}") for k in range(n)]
    q = [getattr(v, f"q{k}") for k in range(n)]
    nxt = [(c[k][0] + d[k][0], c[k][1] + d[k][1]) for k in range(n)]
    return c, nxt, q, [getattr(v, f"ready{k}") for k in range(n)]


def _planner_premises(n: int) -> tuple:
    def within_r(v, k):     # within R of agent 0, weakened to the square |x|, |y| <= R around the disc (linear)
        c = getattr(v, f"c{k}")
        return And(Le(c[0], v.rho), Le(-c[0], v.rho), Le(c[1], v.rho), Le(-c[1], v.rho))

    def distinct(v, which):
        pts = _planner_agents(v, n)[0] if which == "c" else [getattr(v, f"q{k}") for k in range(n)]
        return And(*[Not(_peq(pts[a], pts[b])) for a in range(n) for b in range(a + 1, n)])

    return ((("grid_length_at_most_half_R", lambda v: Ge(v.rho, 2)),)                # 004 Sec. III-A: l <= R/2
            + tuple((f"agent_{k}_intent_is_a_neighbouring_waypoint",
                     _fn(lambda v, k: _one_of_moves(getattr(v, f"d{k}")), k)) for k in range(n))
            + tuple((f"neighbour_{k}_within_R", _fn(within_r, k)) for k in range(1, n))
            + (("distinct_waypoints", _fn(distinct, "c")), ("distinct_priorities", _fn(distinct, "q"))))


def _planner_moves(v, n: int, rule: str) -> tuple:
    """``(c, nxt, move)``: ``move[k]`` is Alg. 2 lines 30-31, agent ``k`` sets ``wp <- next_step``."""
    c, nxt, q, ready = _planner_agents(v, n)

    def hears(k, j):
        # within R in the L1 norm: a subset of the disc of radius R (see planner_one_moment)
        dx, dy = c[k][0] - c[j][0], c[k][1] - c[j][1]
        return And(Le(dx + dy, v.rho), Le(dx - dy, v.rho), Le(-dx + dy, v.rho), Le(-dx - dy, v.rho))

    move = []
    for k in range(n):
        blocks = []
        for j in range(n):
            if j == k:
                continue
            occupied = _peq(c[j], nxt[k])                                     # Alg. 2 line 26
            if rule == "optimistic":
                occupied = And(occupied, _peq(nxt[j], c[j]))
            line28 = And(_peq(nxt[j], nxt[k]), _lex_gt(q[j], q[k]))           # Alg. 2 line 28
            trig = occupied if rule == "no_priority" else Or(occupied, line28)
            blocks.append(And(hears(k, j), trig))
        move.append(And(ready[k], Not(_peq(nxt[k], c[k])), Not(Or(*blocks))))
    return c, nxt, move


def _planner_parts(n: int, rule: str, conclusion: str) -> tuple:
    pairs = [(a, b) for a in range(n) for b in range(n) if a != b]

    def one_waypoint(v):
        _, nxt, move = _planner_moves(v, n, rule)
        return And(*[Not(And(move[a], move[b], _peq(nxt[a], nxt[b]))) for a, b in pairs if a < b])

    def onto_claimed(v):
        c, nxt, move = _planner_moves(v, n, rule)
        return And(*[Not(And(move[a], _peq(nxt[a], c[b]))) for a, b in pairs])

    def no_swap(v):
        c, nxt, move = _planner_moves(v, n, rule)
        return And(*[Not(And(move[a], move[b], _peq(nxt[a], c[b]), _peq(nxt[b], c[a]))) for a, b in pairs if a < b])

    if conclusion == "vertex":
        return (("no_two_agents_move_to_one_waypoint", one_waypoint), ("no_move_onto_a_claimed_waypoint", onto_claimed))
    return (("no_swap_along_an_edge", no_swap),)


def planner_one_moment(neighbours: int = 3, rule: str = "paper", conclusion: str = "vertex") -> Encoding:
    """Alg. 2 lines 25-31 at one moment, for an agent and ``neighbours`` agents within ``R``: the
    z3 encoding of :data:`PLANNER_VERTEX_ONE_MOMENT` (``conclusion="vertex"``) or
    :data:`PLANNER_EDGE_ONE_MOMENT` (``"edge"``) with ``neighbours`` and ``rule``.

    Normalised: ``l = 1``, agent 0's waypoint ``c_0`` at the origin; ``R`` is ``rho = R / l``.
    Every agent ``k`` has a waypoint ``c_k`` (its claim, Alg. 2 ``wp``; pairwise distinct),
    an intent ``n_k = c_k + d_k`` (``next_step``: a neighbouring waypoint, or ``c_k`` itself
    when it has nothing to do), a priority ``q_k`` (any pair of reals, pairwise distinct,
    compared lexicographically: 004 uses the position, "arbitrary priorities" is more
    general), and a free Boolean ``ready_k`` (line 30's clock condition).  Agent ``k`` hears
    ``j`` when ``|c_k - c_j|_1 <= R`` (inside Sec. II-B's disc ``N``: hearing more only
    makes agents wait more, so this is the stronger statement; the neighbours are within
    the square ``|x|, |y| <= R`` around agent 0, a weaker premise than the disc, which keeps
    the encoding linear).  It moves (``wp <- next_step``, line 31) exactly when it is ready, ``n_k != c_k``, and no heard agent triggers line 26
    (``c_j == n_k``) or line 28 (``n_j == n_k`` and ``q_j > q_k``).  The waypoints are any
    real points (distinct), which includes the grid's integer points.

    ``conclusion="vertex"`` (Constraint III-A.1 at this moment): no two agents move to one
    waypoint, and no agent moves onto another's waypoint.  ``conclusion="edge"``
    (Constraint III-A.2): no two agents move along one edge in opposite directions.

    ``rule="no_priority"`` drops line 28 (the control of ``vertex``);
    ``rule="optimistic"`` lets line 26 ignore an occupant that itself moves away (the
    control of ``edge``: a planner that allows edge swaps).

    Examples
    --------
    >>> enc = planner_one_moment(neighbours=1)
    >>> [name for name, _ in enc.premises]
    ['grid_length_at_most_half_R', 'agent_0_intent_is_a_neighbouring_waypoint', 'agent_1_intent_is_a_neighbouring_waypoint', 'neighbour_1_within_R', 'distinct_waypoints', 'distinct_priorities']
    >>> [name for name, _ in enc.parts]
    ['no_two_agents_move_to_one_waypoint', 'no_move_onto_a_claimed_waypoint']
    """
    n = neighbours + 1
    spec = PLANNER_VERTEX_ONE_MOMENT if conclusion == "vertex" else PLANNER_EDGE_ONE_MOMENT
    return dataclasses.replace(spec, variables=_planner_variables(n), premises=_planner_premises(n),
                               control_premises=_planner_premises(n),
                               parts=_planner_parts(n, rule, conclusion), control_parts=None).build()


# --------------------------------------------- message windows and clock phases

#: Broadcast indices ``k`` of the timing lemmas: agent ``a`` broadcasts at ``phase_a + k``
#: (period ``1/f_comm = 1``), for ``k`` in this range, i.e. at every broadcast time in
#: ``[-4, 1)``; the windows that matter lie in ``[-4, 0]`` (docs/proofs.md).  Broadcasts
#: outside the range are not constrained at all, which only weakens the premises.
BROADCASTS = range(-4, 1)


def _within(b, lo, hi, lo_closed: bool, hi_closed: bool):
    return And(Le(lo, b) if lo_closed else Lt(lo, b), Le(b, hi) if hi_closed else Lt(b, hi))


def _message_names(sender: str, reader: str) -> list:
    """The yes/no fields of ``sender``'s broadcasts as ``reader`` reads them, three a broadcast."""
    return [n.replace("-", "m") for k in BROADCASTS for n in (
        f"{sender}{k}_wp_is_{reader}_next", f"{sender}{k}_next_is_{reader}_next", f"{sender}{k}_outranks_{reader}")]


def _message_variables(sender: str, reader: str) -> tuple:
    return tuple(Bool(name, "real") for name in _message_names(sender, reader))


class _Messages:
    """The broadcasts of one agent as another agent reads them (Alg. 3 line 2): for each
    broadcast time ``phase + k`` three yes/no fields -- its ``wp`` is the reader's
    ``next_step`` (Alg. 2 line 26), its ``next_step`` is the reader's ``next_step`` and its
    sender has the higher priority (line 28's two conditions).  ``v``: the lemma's variables."""

    def __init__(self, v, sender: str, reader: str) -> None:
        self.phase = getattr(v, f"phase_{sender}")
        self.times = [self.phase + k for k in BROADCASTS]
        fields = [getattr(v, name) for name in _message_names(sender, reader)]
        self.flags = [tuple(fields[3 * i:3 * i + 3]) for i in range(len(BROADCASTS))]

    def wp(self, k):
        return self.flags[k][0]

    def nxt(self, k):
        return self.flags[k][1]

    def outranks(self, k):
        return self.flags[k][2]

    def during(self, lo, hi, lo_closed, hi_closed, what):
        """Every broadcast in the interval satisfies ``what(k)``."""
        return And(*[Implies(_within(b, lo, hi, lo_closed, hi_closed), what(k)) for k, b in enumerate(self.times)])

    def triggers(self, k):
        """Alg. 2 line 26 or line 28 fires on the reader."""
        return Or(self.wp(k), And(self.nxt(k), self.outranks(k)))


def _messages(v) -> tuple:
    """``(mi, mj)``: ``i``'s broadcasts as ``j`` reads them, ``j``'s as ``i`` reads them."""
    return _Messages(v, "i", "j"), _Messages(v, "j", "i")


def _phases(v):
    return And(*[And(Le(0, m.phase), Lt(m.phase, 1)) for m in _messages(v)])


def _decision_premises(window) -> tuple:
    """Alg. 2 line 30 for both agents (each changed its claim only if no message of its last
    ``Delta t`` triggered line 26 or 28) and lossless delivery: the premises the two timing
    lemmas share."""
    def i_changes(v):
        mj = _messages(v)[1]
        return Implies(v.i_hears_j, mj.during(-constant(window, v.t_j), 0, True, True, lambda k: Not(mj.triggers(k))))

    def j_changes(v):
        mi = _messages(v)[0]
        w = constant(window, v.t_j)
        return Implies(v.j_hears_i, mi.during(v.t_j - w, v.t_j, True, True, lambda k: Not(mi.triggers(k))))

    return (("i_changes_claim_at_t_star_alg2_line30", i_changes), ("j_changes_claim_at_t_j_alg2_line30", j_changes),
            ("lossless_delivery_within_R", lambda v: And(v.i_hears_j, v.j_hears_i)))


def _lemma_iv_a_1_premises(window) -> tuple:
    def w(v):
        return constant(window, v.t_j)

    def waiting(m, rank):
        return lambda k: And(Not(m.wp(k)), m.nxt(k), Iff(m.outranks(k), rank))

    def i_intends(v):
        mi = _messages(v)[0]
        return mi.during(v.last_check_i, 0, False, False, waiting(mi, v.i_outranks_j))

    def j_intends(v):
        mj = _messages(v)[1]
        return mj.during(v.last_check_j, v.t_j, False, False, waiting(mj, v.j_outranks_i))

    def j_claims(v):
        mj = _messages(v)[1]
        return mj.during(v.t_j, 0, False, True, mj.wp)

    def i_waited(v):
        # the same term as Lt(last_check_i, -w(v)) (RealVal(window)); it reads only last_check_i, so the
        # runtime monitor grid_waited judges it on that alone (reference_impl/wang2020/monitors.py)
        return Lt(v.last_check_i, -constant(window, v.last_check_i))

    return ((("broadcast_every_period_at_any_phase", _phases),
             ("i_waited_longer_than_window", i_waited),
             ("i_intends_wp1_since_last_check", i_intends),
             ("j_waited_longer_than_window", lambda v: Lt(v.last_check_j, v.t_j - w(v))),
             ("j_intends_wp1_since_last_check", j_intends),
             ("j_claims_wp1_from_t_j_to_t_star", j_claims),
             ("lexicographic_priority_of_distinct_waypoints", lambda v: Xor(v.j_outranks_i, v.i_outranks_j)))
            + _decision_premises(window))


#: The message fields of both agents, as the timing lemmas list them (``j``'s, then ``i``'s).
_MESSAGE_VARIABLES = _message_variables("j", "i") + _message_variables("i", "j")
_HEARS = (Bool("i_hears_j", "real"), Bool("j_hears_i", "real"))
_PHASES = (Real("phase_i", 0.0, 1.0), Real("phase_j", 0.0, 1.0))


def lemma_iv_a_1(window=2) -> Encoding:
    """004 Lemma IV-A.1 for agent ``a_i`` and any other agent ``a_j``, with the message
    windows and clock phases of its proof (Sec. II-A a-e, Alg. 2 lines 6, 15, 25-33, Alg. 3):
    the z3 encoding of :data:`LEMMA_IV_A_1` with the window ``window``.

    Normalised: the broadcast period ``1/f_comm = 1`` and ``t* = 0``
    (``wang2020_time_normalisation``); ``window`` is ``Delta t`` in periods (Alg. 2 line 6:
    2).  ``a_i`` changes its claim ``wp`` from ``wp^0_i`` to ``wp^1`` at ``t* = 0``; ``a_j``
    changes its claim to ``wp^1`` at ``t_j`` and claims it from then until ``t*`` (when
    ``t_j <= 0``).  Premises:

    * each agent broadcasts ``(p, wp, next_step)`` once a period at its own phase (Alg. 3;
      Sec. II-A: phases arbitrary, rates equal);
    * each waited at its waypoint longer than ``Delta t`` since ``last_check``
      (line 30; Sec. III-C: ``last_check`` is reset whenever the goal, hence
      ``next_step``, changes, Alg. 4 lines 7-21), so since ``last_check`` it broadcast its
      waypoint (not ``wp^1``), ``next_step = wp^1`` and its fixed priority;
    * the two positions are distinct waypoints, so exactly one outranks the other
      (lexicographic order, Sec. II-B);
    * ``a_j`` broadcasts ``wp = wp^1`` after ``t_j`` (until ``t*``);
    * each changed its claim (line 31) only if no message it received in the last
      ``Delta t`` (line 15, a closed window) triggered line 26 or 28;
    * lossless delivery without delay to the agents within ``R`` (Sec. II-A c, e): both are
      one edge from ``wp^1`` while they wait, so at most ``2l <= R`` apart, and every
      broadcast of one reaches the other (the monitored premise "heard every neighbour").

    Conclusion: ``t_j > 0``, i.e. no ``a_j`` claims ``wp^1`` at ``t*``.  A broadcast at the
    very instant of a change, or before ``last_check``, is left unconstrained (either
    content).  ``window=1`` is the control (``Delta t = 1/f_comm``).

    Examples
    --------
    >>> [n for n, _ in lemma_iv_a_1().premises][:3]
    ['broadcast_every_period_at_any_phase', 'i_waited_longer_than_window', 'i_intends_wp1_since_last_check']
    """
    return dataclasses.replace(LEMMA_IV_A_1, premises=_lemma_iv_a_1_premises(window)).build()


def _theorem_iv_a_2_premises(window) -> tuple:
    def w(v):
        return constant(window, v.t_j)

    def i_broadcasts(v):
        mi = _messages(v)[0]
        return And(mi.during(v.claim_i, 0, False, False, mi.wp),
                   mi.during(0, v.leave_i, False, False, lambda k: Not(mi.wp(k))))

    def j_broadcasts(v):
        mj = _messages(v)[1]
        return And(mj.during(v.claim_j, v.t_j, False, False, mj.wp),
                   mj.during(v.t_j, v.leave_j, False, False, lambda k: Not(mj.wp(k))))

    # i claims wp0 on [c_i, 0), wp1 on [0, leave_i); j claims wp1 on [c_j, t_j), wp0 on [t_j, leave_j)
    return ((("broadcast_every_period_at_any_phase", _phases),
             ("claims_start_before_last_check", lambda v: And(Lt(v.claim_i, v.last_check_i),
                                                              Lt(v.claim_j, v.last_check_j))),
             ("i_waited_longer_than_window", lambda v: Lt(v.last_check_i, -w(v))),
             ("j_waited_longer_than_window", lambda v: Lt(v.last_check_j, v.t_j - w(v))),
             ("travel_takes_positive_time", lambda v: And(Gt(v.tau_i, 0), Gt(v.tau_j, 0))),
             ("new_claims_end_after_arrival", lambda v: And(Ge(v.leave_i, v.tau_i), Ge(v.leave_j, v.t_j + v.tau_j))),
             ("i_broadcasts_its_claim", i_broadcasts),
             ("j_broadcasts_its_claim", j_broadcasts),
             ("claims_distinct_at_every_instant_thm_iv_a_1",
              lambda v: And(_disjoint(v.claim_i, 0, v.t_j, v.leave_j), _disjoint(0, v.leave_i, v.claim_j, v.t_j))))
            + _decision_premises(window))


def theorem_iv_a_2(window=2) -> Encoding:
    """004 Thm. IV-A.2, its proof's premises (the z3 encoding of :data:`THEOREM_IV_A_2` with the
    window ``window``): ``a_i`` changes its claim from ``wp^0`` to ``wp^1`` at ``t* = 0`` and
    ``a_j`` from ``wp^1`` to ``wp^0`` at ``t_j``; they never travel the edge in opposite
    directions at the same time.

    Normalised as :func:`lemma_iv_a_1`.  Premises: the broadcasts and the decision rule of
    :func:`lemma_iv_a_1` (``a_i`` reads line 26 against ``wp^1``, ``a_j`` against ``wp^0``;
    ``next_step`` and priorities left free), each agent claimed its old waypoint from
    ``c`` on, before its ``last_check`` (it claims a waypoint when it sets off for it, Alg. 2
    lines 31-33, and waits after arriving), waited longer than ``Delta t``, and -- Thm.
    IV-A.1, which the paper's proof uses (its case 1) -- the two agents' claims are distinct
    at every instant.  Travel takes any positive times ``tau_i``, ``tau_j`` (the proof does
    not use speeds, Sec. V-B3); each new claim lasts at least until the agent arrives
    (``leave_i >= tau_i``).  Conclusion: the travel intervals ``[0, tau_i)`` and
    ``[t_j, t_j + tau_j)`` do not meet.  ``window=1/2`` is the control.
    """
    return dataclasses.replace(THEOREM_IV_A_2, premises=_theorem_iv_a_2_premises(window)).build()


def _time_premises(positive_period: bool) -> tuple:
    return (("period_positive", lambda v: Gt(v.T, 0)) if positive_period else ("period_nonzero", lambda v: Ne(v.T, 0)),
            ("a_normalised", lambda v: Eq(v.T * v.a_n, v.a - v.c)),
            ("b_normalised", lambda v: Eq(v.T * v.b_n, v.b - v.c)))


def time_normalisation(positive_period: bool = True) -> Encoding:
    """Time can be shifted and scaled: for ``T > 0`` and times ``a, b, c``, and any integer
    offset ``k`` (broadcasts ``k`` periods apart), ``a <= b + k T`` iff
    ``(a - c)/T <= (b - c)/T + k``, and the same with ``<``.  So ``t* = 0`` and
    ``1/f_comm = 1`` lose nothing in :func:`lemma_iv_a_1` and :func:`theorem_iv_a_2`, whose
    premises and conclusion are such comparisons.  The control lets ``T`` be any non-zero
    number (a negative period reverses the order).

    Stated with the multiplication cleared (``T (a - c)/T = a - c``): ``a' = (a - c)/T`` is
    the variable with ``T a' = a - c``.  The z3 encoding of :data:`TIME_NORMALISATION` (its
    control with ``positive_period=False``)."""
    return TIME_NORMALISATION.build() if positive_period else TIME_NORMALISATION.control()


# ----------------------------------------------------- (b) the geometric separation

def _waypoint_offset(x):
    """``x`` is an integer offset in cells: one of ``-2..2``, or at least 3 away (any real
    there: those waypoints are too far for any contact, so their integrality is not needed)."""
    return Or(*([Eq(x, k) for k in range(-2, 3)] + [Ge(x, 3), Le(x, -3)]))


def _j_source(v):
    return And(_waypoint_offset(v.A_j[0]), _waypoint_offset(v.A_j[1]))


def _agent(v, a: str) -> tuple:
    """Agent ``a``'s source waypoint (``i``'s at the origin), move ``D``, claim start ``e``,
    set-off time ``s`` and edge fraction ``lam``."""
    src = _origin(v.t) if a == "i" else v.A_j
    return src, getattr(v, f"D_{a}"), getattr(v, f"e_{a}"), getattr(v, f"s_{a}"), getattr(v, f"lam_{a}")


def _position(v, a: str) -> tuple:
    src, d, _, _, lam = _agent(v, a)
    return (src[0] + lam * d[0], src[1] + lam * d[1])


def _apart(v):
    """The conclusion: ``||p_i(t) - p_j(t)||^2 >= (2r)^2``."""
    return Ge(dist2(_position(v, "i"), _position(v, "j")), 4 * v.r * v.r)


def _common_speed(v, a: str):
    """``lam = min(1, max(0, t - s))``: the exact position on the edge at the common speed 1."""
    _, _, _, s, lam = _agent(v, a)
    return Or(And(Le(v.t, s), Eq(lam, 0)), And(Le(s, v.t), Le(v.t, s + 1), Eq(lam, v.t - s)),
              And(Ge(v.t, s + 1), Eq(lam, 1)))


def _edge_fraction(lam, w, t, s):
    """``lam = min(1, max(0, w (t - s)))``: the fraction of its edge an agent of speed ``w`` that
    set off at ``s`` has covered at ``t`` (the exact position on the edge, DESIGN.md section 5)."""
    run = w * (t - s)
    return Or(And(Le(t, s), Eq(lam, 0)), And(Le(s, t), Le(run, 1), Eq(lam, run)), And(Ge(run, 1), Eq(lam, 1)))


def _own_speed(v, a: str):
    _, _, _, s, lam = _agent(v, a)
    return _edge_fraction(lam, getattr(v, f"w_{a}"), v.t, s)


def _claims_distinct(v, moves: dict):
    """Thm. IV-A.1: claims (``A`` on ``[e, s)``, then ``A + D`` on ``[s, inf)``; a resting
    agent's ``A`` on ``[e, inf)``) distinct at every instant."""
    claims = {}
    for a in "ij":
        src, _, e, s, _ = _agent(v, a)
        d = moves[a]
        dest = (src[0] + d[0], src[1] + d[1])
        claims[a] = [(src, e, s), (dest, s, None)] if d != (0, 0) else [(src, e, None)]
    return And(*[Implies(_peq(wa, wb), _disjoint(a0, a1, b0, b1))
                 for wa, a0, a1 in claims["i"] for wb, b0, b1 in claims["j"]])


def _no_opposite_travel(v, di, dj):
    """Thm. IV-A.2: the two never travel one edge in opposite directions at the same time."""
    src_i, src_j = _agent(v, "i")[0], v.A_j
    swap = And(_peq(src_i, (src_j[0] + dj[0], src_j[1] + dj[1])), _peq(src_j, (di[0], di[1])))
    s_i, s_j = v.s_i, v.s_j
    return Implies(swap, _disjoint(s_i, s_i + 1, s_j, s_j + 1))


def _move_cases(speeds: bool) -> tuple:
    """The 25 cases of the two agents' moves: each rests or moves one unit step; ``speeds``:
    at its own speed (:func:`separation_speeds`), else at the common speed (:func:`separation`)."""
    cases = []
    for di in list(UNITS) + [(0, 0)]:
        for dj in list(UNITS) + [(0, 0)]:
            moves = {"i": di, "j": dj}
            extra = []
            for a in "ij":
                d = moves[a]
                extra.append((f"{a}_move_of_the_case", _fn(lambda v, a, d: _peq(getattr(v, f"D_{a}"), d), a, d)))
                extra.append((f"{a}_at_its_source_by_t",
                              _fn(lambda v, a: Ge(v.t, getattr(v, f"e_{a}") + 1), a)))
                if d != (0, 0) and speeds:
                    extra.append((f"{a}_moves_at_its_own_speed", _fn(_own_speed, a)))
                elif d != (0, 0):
                    extra.append((f"{a}_reached_its_source_before_setting_off",
                                  _fn(lambda v, a: Ge(getattr(v, f"s_{a}"), getattr(v, f"e_{a}") + 1), a)))
                    extra.append((f"{a}_moves_at_the_common_speed", _fn(_common_speed, a)))
                elif not speeds:
                    extra.append((f"{a}_rests", _fn(lambda v, a: Eq(getattr(v, f"lam_{a}"), 0), a)))
            extra.append(("claims_distinct_at_every_instant_thm_iv_a_1", _fn(_claims_distinct, moves)))
            if di != (0, 0) and dj != (0, 0):
                extra.append(("no_opposite_travel_on_one_edge_thm_iv_a_2", _fn(_no_opposite_travel, di, dj)))
            cases.append((f"i{_dname(di)}_j{_dname(dj)}", tuple(extra)))
    return tuple(cases)


def _dname(d) -> str:
    return {(1, 0): "east", (-1, 0): "west", (0, 1): "north", (0, -1): "south", (0, 0): "rests"}[d]


def _separation_premises(bound_factor2) -> tuple:
    return (("grid_length_at_least_2_sqrt2_r", lambda v: And(Gt(v.r, 0), Le(8 * bound_factor2 * v.r * v.r, 1))),
            ("j_source_is_a_waypoint", _j_source))


def _times(*names) -> tuple:
    return tuple(Real(n, -3.0, 3.0) for n in names)


def separation(bound_factor2=1) -> Encoding:
    """Two discs of radius ``r`` on 004's grid, each resting at its waypoint or moving along an
    edge at the common speed, stay at least ``2r`` apart at every instant if
    ``l >= 2 sqrt(2) r`` (004 Sec. III-A; Sec. V-B3's bound with ``v_min = v_max``): the z3
    encoding of :data:`SEPARATION_EQUAL_SPEEDS` with ``bound_factor2``.

    Normalised: ``l = 1``, the common speed 1 (an edge takes one time unit), agent ``i``'s
    source waypoint at the origin (``translation_invariance``, ``scale_invariance``).  Each
    agent ``a`` has a source waypoint ``A_a`` (``i``: the origin; ``j``: integer offsets),
    a move ``D_a`` (a unit step, or ``(0, 0)``: resting), the time ``e_a`` its claim on
    ``A_a`` began and, when moving, the time ``s_a`` it set off.  At time ``t`` it is at
    ``A_a + lam_a D_a`` with ``lam_a = min(1, max(0, t - s_a))`` (the exact position on the
    edge, DESIGN.md section 5).  Premises:

    * ``r > 0`` and ``(2 sqrt(2) r)^2 <= l^2`` (``bound_factor2`` scales the left side: the
      control uses ``0.99^2``, ``l`` one per cent below the bound);
    * the agent reached its source before it set off and before ``t`` (``s_a >= e_a + 1``,
      ``t >= e_a + 1``; the wait itself is not needed);
    * claims (``A_a`` on ``[e_a, s_a)``, then ``A_a + D_a`` on ``[s_a, inf)``; a resting
      agent ``A_a`` on ``[e_a, inf)``) are distinct at every instant: Constraint III-A.1,
      Thm. IV-A.1's conclusion;
    * the two never travel one edge in opposite directions at the same time: Constraint
      III-A.2, Thm. IV-A.2's conclusion.

    Conclusion: ``||p_i(t) - p_j(t)||^2 >= (2r)^2``, for every ``t``.  Split into the 25
    cases of the two moves (``Encoding.cases``).
    """
    return dataclasses.replace(SEPARATION_EQUAL_SPEEDS, premises=_separation_premises(bound_factor2)).build()


def _speed_buffer_premise(bound_factor2) -> tuple:
    """004 Sec. V-B3's buffer space, normalised ``l = 1``, ``v_max = 1``, ``rho = v_min / v_max``:
    ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min`` squared and cleared of the division,
    ``4 r^2 (1 + rho^2) <= rho^2`` (``bound_factor2`` scales the left side: the control's
    ``0.99^2`` puts ``l`` one per cent below the bound)."""
    return ("grid_length_at_least_the_v_b3_speed_buffer",
            lambda v: And(Gt(v.r, 0), Gt(v.rho, 0), Le(v.rho, 1),
                          Le(4 * bound_factor2 * v.r * v.r * (1 + v.rho * v.rho), v.rho * v.rho)))


def _speed_buffer_premises(bound_factor2) -> tuple:
    return (_speed_buffer_premise(bound_factor2),
            ("speeds_within_v_min_v_max", lambda v: And(Le(v.rho, v.a), Le(v.a, 1), Le(v.rho, v.b), Le(v.b, 1))),
            ("f_on_its_edge_t_in_0_l_over_b", lambda v: And(Ge(v.t, 0), Le(v.b * v.t, 1), Eq(v.lam_F, v.b * v.t))),
            ("l_leaves_w_at_t_0", lambda v: _edge_fraction(v.lam_L, v.a, v.t, constant(0, v.t))))


def speed_buffer_cases(bound_factor2=1) -> Encoding:
    """004 Sec. V-B3's two cases, as the paper derives its buffer space (the z3 encoding of
    :data:`SPEED_BUFFER_V_B3_CASES` with ``bound_factor2``): agent ``L`` leaves
    waypoint ``W`` at ``t = 0`` at speed ``a`` while agent ``F`` sets off at ``t = 0`` toward
    ``W`` from the neighbouring waypoint at speed ``b``, both in ``[v_min, v_max]``; for ``t``
    in ``[0, l / b]`` (``F`` on its edge; the paper's ``[0, l / v_max]`` with ``b = v_max``)
    the two discs of radius ``r`` stay at least ``2r`` apart if
    ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min``.

    Normalised: ``l = 1``, ``v_max = 1`` (an edge at ``v_max`` takes one time unit),
    ``rho = v_min / v_max``; ``W`` at the origin, ``F`` coming from ``(-1, 0)`` eastward.
    Cases (``Encoding.cases``): ``orthogonal_adjacent_edges`` (``L`` leaves northward: the
    paper's ``sqrt((l - v_max t)^2 + (v_min t)^2) >= 2r``) and ``collinear_adjacent_edges``
    (``L`` leaves eastward, ahead of ``F``: ``l - v_max t + v_min t >= 2r``).  The paper
    takes ``L`` at ``v_min`` and ``F`` at ``v_max``, its worst case; here both speeds are free
    in ``[v_min, v_max]``.  ``L`` stops at the end of its edge (``min(1, a t)``).
    """
    return dataclasses.replace(SPEED_BUFFER_V_B3_CASES, premises=_speed_buffer_premises(bound_factor2)).build()


def _separation_speeds_premises(bound_factor2) -> tuple:
    return (_speed_buffer_premise(bound_factor2),
            ("speeds_within_v_min_v_max", lambda v: And(*[And(Le(v.rho, w), Le(w, 1)) for w in (v.w_i, v.w_j)])),
            ("j_source_is_a_waypoint", _j_source))


def separation_speeds(bound_factor2=1) -> Encoding:
    """:func:`separation` with speeds of their own (004 Sec. V-B3; the z3 encoding of
    :data:`SEPARATION_SPEEDS` with ``bound_factor2``): two discs of radius ``r``,
    each resting at its waypoint or moving along an edge at its own speed in ``[v_min, v_max]``,
    with claims distinct at every instant (Thm. IV-A.1) and no opposite travel on one edge (Thm.
    IV-A.2), on a grid with ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min``, are at least ``2r``
    apart at every instant ``t``.  All 25 pairs of moves (``Encoding.cases``), start times free:
    every pair of edges two agents can travel at once under Constraints III-A.1/2, not only
    Sec. V-B3's two cases with a common start (:func:`speed_buffer_cases`).

    Normalised: ``l = 1``, ``v_max = 1``, ``rho = v_min / v_max``, agent ``i``'s source at the
    origin.  Agent ``a`` moves at ``w_a`` in ``[rho, 1]``; at ``t`` it is at ``A_a + lam_a D_a``
    with ``lam_a = min(1, max(0, w_a (t - s_a)))``.  At ``t`` it has reached its source, at least
    one time unit (an edge at ``v_max``, the fastest) after its claim on it began (``t >= e_a +
    1``: weaker than the truth, ``e_a + l / w``, so the statement is stronger).  Unlike
    :func:`separation`, no premise says it reached its source before setting off (``s_a >= e_a +
    1``) and a resting agent's ``lam`` is left free (it moves by ``lam (0, 0)``): the vacuity
    controls showed both redundant there, and each redundant premise costs a full re-proof here.
    Claims as in :func:`separation`; no opposite travel is stated on ``[s_a, s_a + 1)``, the
    shortest travel (a subset of the true travel time: again a weaker premise).
    ``bound_factor2 = 0.99^2`` is the control (``l`` one per cent below the bound).
    """
    return dataclasses.replace(SEPARATION_SPEEDS, premises=_separation_speeds_premises(bound_factor2)).build()


# ------------------------------------------------------------------ registry

_SMT = (("solver", "smt"),)   # linear real arithmetic with Booleans: z3's SMT solver (docs/proofs.md)
_GRID = ("translation: agent i's (or agent 0's) waypoint at the origin, by whole cells (translation_invariance)",
         "scale: grid length l = 1 (scale_invariance)")
_TIME = ("time: t* = 0 and 1/f_comm = 1 (wang2020_time_normalisation)",)
_SPEED = ("time: v_max = 1, an edge at v_max takes one time unit: times t -> (t - c) / T with T = l / v_max keep "
          "every comparison a <= b + k T (wang2020_time_normalisation), speeds v -> v T / l keep every fraction "
          "v (t - s) / l of an edge; rho = v_min / v_max",)
_PAPER_TIMING = ("equal clock rates, lossless delivery without delay (Sec. II-A a-c, e); Sec. V-B3's relaxed "
                 "Delta t >= (2m/f_comm)(f_max/f_min) for loss and clock rates is not encoded (the explorer "
                 "and the runtime monitors cover it)")


TIME_NORMALISATION = LemmaSpec(
        id="wang2020_time_normalisation",
        statement="Shifting and scaling time by a positive period keeps every comparison a <= b + k T (and <): "
                  "t* = 0 and 1/f_comm = 1 lose nothing.",
        cites=("normalisation lemma (docs/proofs.md)",),
        normalisations=(),
        variables=(Real("a"), Real("b"), Real("c"), Real("T"), Real("k"), Real("a_n"), Real("b_n")),
        premises=_time_premises(True),
        conclusion=lambda v: And(Iff(Le(v.a, v.b + v.k * v.T), Le(v.a_n, v.b_n + v.k)),
                                 Iff(Lt(v.a, v.b + v.k * v.T), Lt(v.a_n, v.b_n + v.k))),
        control_premises=_time_premises(False),
        control_note="the period may be negative (T != 0)",
)

PLANNER_VERTEX_ONE_MOMENT = LemmaSpec(
        id="wang2020_planner_vertex_one_moment",
        statement="At one moment, agents on distinct waypoints with distinct priorities, each deciding by Alg. 2 "
                  "lines 25-31 on the current claims and intents of the agents within R (l <= R/2), never move two "
                  "agents to one waypoint nor one agent onto a waypoint another claims (an agent and 3 neighbours; "
                  "any priorities, any intents).",
        cites=("004 Alg. 2 lines 25-31, Sec. III-A Constraint III-A.1 (one moment; Thm. IV-A.1 is not proved "
               "here)",),
        normalisations=_GRID,
        variables=_planner_variables(4), premises=_planner_premises(4), conclusion=None,
        parts=_planner_parts(4, "paper", "vertex"),
        control_premises=_planner_premises(4), control_parts=_planner_parts(4, "no_priority", "vertex"),
        control_note="Alg. 2 line 28 (the priority check) removed",
        solver_params=_SMT,
        not_proved=(
            "message windows, clock phases and waiting (Lemma IV-A.1's premises): every agent here decides on the "
            "current state of the others; wang2020_lemma_iv_a_1 has the timing",
            "more than 3 neighbours at once: conflicts are between two agents, and any counterexample with fewer "
            "agents extends to 3 neighbours (an idle agent off the grid changes no decision)",
            "hearing is taken within the L1 ball of radius R, inside the disc (hearing more only makes agents wait), "
            "and 'within R of agent 0' as the square around the disc (a weaker premise)",
        ),
)

PLANNER_EDGE_ONE_MOMENT = LemmaSpec(
        id="wang2020_planner_edge_one_moment",
        statement="At one moment, Alg. 2 lines 25-31 never let two agents swap along one edge (agents on distinct "
                  "waypoints, distinct priorities, within R, l <= R/2; an agent and 3 neighbours).",
        cites=("004 Alg. 2 lines 25-31, Sec. III-A Constraint III-A.2 (one moment; Thm. IV-A.2 is not proved "
               "here)",),
        normalisations=_GRID,
        variables=_planner_variables(4), premises=_planner_premises(4), conclusion=None,
        parts=_planner_parts(4, "paper", "edge"),
        control_premises=_planner_premises(4), control_parts=_planner_parts(4, "optimistic", "edge"),
        control_note="line 26 ignores an occupant that itself moves away (a planner allowing edge swaps)",
        solver_params=_SMT,
        not_proved=("message windows, clock phases and waiting: wang2020_theorem_iv_a_2 has the timing",),
)

LEMMA_IV_A_1 = LemmaSpec(
        id="wang2020_lemma_iv_a_1",
        statement="If agent a_i changes its claim wp from wp0 to wp1 at t*, no agent a_j claims wp1 at t*: each "
                  "agent broadcasts (p, wp, next_step) every 1/f_comm at any phase, waits at its waypoint longer "
                  "than Delta t = 2/f_comm with next_step fixed since last_check, reads the messages of the last "
                  "Delta t (lines 15, 25-29), every message reaches the agents within R, and the two waypoints "
                  "are distinct (lexicographic priority).",
        cites=("004 Lemma IV-A.1 and its proof (Conditions 1-2, Cases 1-2), Alg. 2 lines 6, 15, 25-33, Alg. 3, "
               "Sec. II-A",),
        normalisations=_TIME,
        variables=(Real("t_j", -5.0, 1.0), Real("last_check_i", -7.0, 0.0), Real("last_check_j", -7.0, 1.0))
        + _PHASES + (Bool("j_outranks_i", "real"), Bool("i_outranks_j", "real")) + _HEARS + _MESSAGE_VARIABLES,
        premises=_lemma_iv_a_1_premises(2), conclusion=lambda v: Gt(v.t_j, 0),
        control_premises=_lemma_iv_a_1_premises(1),
        control_note="Delta t = 1/f_comm instead of 2/f_comm",
        solver_params=_SMT,
        kind="paper lemma",
        not_proved=(
            "two agents at a time (the lemma is about every other agent a_j, one at a time, as in the paper)",
            _PAPER_TIMING,
            "that next_step stays fixed since last_check (Sec. III-C's timer reset, Alg. 4 lines 7-21) and that the "
            "waypoints are distinct (Thm. IV-A.1's induction): premises, checked at run time",
        ),
)

THEOREM_IV_A_2 = LemmaSpec(
        id="wang2020_theorem_iv_a_2",
        statement="Two agents never travel one edge in opposite directions at the same time, given the broadcasts, "
                  "windows and waits of Lemma IV-A.1 and Thm. IV-A.1's conclusion (claims distinct at every "
                  "instant); travel times are any positive numbers.",
        cites=("004 Thm. IV-A.2 and its proof (Cases 1-2), Alg. 2 lines 26, 30, Alg. 3",),
        normalisations=_TIME,
        variables=(Real("t_j", -5.0, 1.0), Real("claim_i", -8.0, 0.0), Real("claim_j", -8.0, 0.0),
                   Real("last_check_i", -7.0, 0.0), Real("last_check_j", -7.0, 1.0), Real("leave_i", 0.0, 3.0),
                   Real("leave_j", -1.0, 3.0), Real("tau_i", 0.0, 2.0), Real("tau_j", 0.0, 2.0))
        + _PHASES + _HEARS + _MESSAGE_VARIABLES,
        premises=_theorem_iv_a_2_premises(2),
        conclusion=lambda v: Not(And(Lt(v.t_j, v.tau_i), Lt(0, v.t_j + v.tau_j))),     # the travels overlap
        control_premises=_theorem_iv_a_2_premises(0.5),
        control_note="Delta t = 1/(2 f_comm): shorter than one broadcast period",
        solver_params=_SMT,
        kind="paper lemma",
        not_proved=(
            "Thm. IV-A.1 itself (claims distinct at every instant, from unique starts by induction over claim "
            "changes with Lemma IV-A.1): a premise here, argued on paper and monitored at run time",
            _PAPER_TIMING,
            "that Delta t = 2/f_comm is needed: given Thm. IV-A.1, Delta t >= 1/f_comm suffices for this theorem "
            "(z3 proves it with window 1); the factor 2 is for Lemma IV-A.1",
        ),
)

SEPARATION_EQUAL_SPEEDS = LemmaSpec(
        id="wang2020_separation_equal_speeds",
        statement="Two discs of radius r on a grid with l >= 2 sqrt(2) r, each resting at its waypoint or moving "
                  "along an edge at the common speed, with claims distinct at every instant (Thm. IV-A.1) and no "
                  "opposite travel on one edge (Thm. IV-A.2), are at least 2r apart at every instant (the exact "
                  "position on the edge at time t).",
        cites=("004 Sec. III-A (2 sqrt(2) r <= l), Sec. II-C (||p_i - p_j|| >= 2r), Sec. V-B3 (its bound with "
               "v_min = v_max)",),
        normalisations=_GRID + ("scale: the common speed 1, an edge takes one time unit (scale_invariance)",),
        variables=(Real("r", 0.0, 0.5), Real("t", -3.0, 3.0), IntPoint("A_j", -4, 4, "real"))
        + _times("e_i", "s_i") + (Real("lam_i", 0.0, 1.0),) + _times("e_j", "s_j") + (Real("lam_j", 0.0, 1.0),)
        + (IntPoint("D_i", -1, 1, "real"), IntPoint("D_j", -1, 1, "real")),
        premises=_separation_premises(1), conclusion=_apart, cases=_move_cases(speeds=False),
        control_premises=_separation_premises(0.99 ** 2),
        control_note="l one per cent below 2 sqrt(2) r",
        not_proved=(
            "different speeds (Sec. V-B3: l >= 2 r sqrt(v_max^2 + v_min^2) / v_min) and the spin time of a "
            "differential-drive robot: equal speeds only, so auxiliary (DESIGN.md section 5)",
            "two agents at a time; Thms. IV-A.1/IV-A.2 are premises (monitored at run time)",
        ),
)

SPEED_BUFFER_V_B3_CASES = LemmaSpec(
        id="wang2020_speed_buffer_v_b3_cases",
        statement="Sec. V-B3's two cases: an agent leaving a waypoint W and an agent entering W from a neighbouring "
                  "waypoint, setting off at once at speeds in [v_min, v_max], on orthogonal or on collinear adjacent "
                  "edges, stay at least 2r apart while the entering agent is on its edge, if "
                  "l >= 2 r sqrt(v_max^2 + v_min^2) / v_min.",
        cites=("004 Sec. V-B3 (the buffer space l >= 2 sqrt(v_max^2 + v_min^2) r / v_min from its orthogonal and "
               "collinear cases; the paper's worst case is the leaver at v_min, the enterer at v_max)",),
        normalisations=_GRID + _SPEED,
        variables=(Real("r", 0.0, 0.5), Real("rho", 0.0, 1.0), Real("a", 0.0, 1.0), Real("b", 0.0, 1.0),
                   Real("t", 0.0, 2.0), Real("lam_L", 0.0, 1.0), Real("lam_F", 0.0, 1.0), Point("L", -1.0, 1.0)),
        premises=_speed_buffer_premises(1),
        conclusion=lambda v: Ge(dist2(v.L, (-1 + v.lam_F, constant(0, v.t))), 4 * v.r * v.r),
        # the leaving agent's position: a case premise puts it on its edge
        cases=(("orthogonal_adjacent_edges", (("l_leaves_w_orthogonally_to_f_edge", lambda v: _peq(v.L, (0, v.lam_L))),)),
               ("collinear_adjacent_edges", (("l_leaves_w_along_f_edge", lambda v: _peq(v.L, (v.lam_L, 0))),))),
        control_premises=_speed_buffer_premises(0.99 ** 2),
        control_note="l one per cent below 2 r sqrt(v_max^2 + v_min^2) / v_min",
        not_proved=(
            "any other pair of edges or start times than a common start: wang2020_separation_speeds covers them",
            "the spin time of a differential-drive robot (Sec. V-B3's second buffer, v_max pi / (2 omega*)): the "
            "engine's grid robots are holonomic",
        ),
)

SEPARATION_SPEEDS = LemmaSpec(
        id="wang2020_separation_speeds",
        statement="Two discs of radius r on a grid with l >= 2 r sqrt(v_max^2 + v_min^2) / v_min, each resting at its "
                  "waypoint or moving along an edge at its own speed in [v_min, v_max], with claims distinct at every "
                  "instant (Thm. IV-A.1) and no opposite travel on one edge (Thm. IV-A.2), are at least 2r apart at "
                  "every instant: every pair of moves (25 cases) and any start times.",
        cites=("004 Sec. V-B3 (v_min <= v_m^i <= v_max, the buffer space l), Sec. II-C (||p_i - p_j|| >= 2r), "
               "Constraints III-A.1/III-A.2",),
        normalisations=_GRID + _SPEED,
        variables=(Real("r", 0.0, 0.5), Real("rho", 0.0, 1.0), Real("t", -3.0, 3.0), IntPoint("A_j", -4, 4, "real"))
        + _times("e_i", "s_i") + (Real("lam_i", 0.0, 1.0), Real("w_i", 0.0, 1.0)) + _times("e_j", "s_j")
        + (Real("lam_j", 0.0, 1.0), Real("w_j", 0.0, 1.0), IntPoint("D_i", -1, 1, "real"), IntPoint("D_j", -1, 1, "real")),
        premises=_separation_speeds_premises(1), conclusion=_apart, cases=_move_cases(speeds=True),
        control_premises=_separation_speeds_premises(0.99 ** 2),
        control_note="l one per cent below 2 r sqrt(v_max^2 + v_min^2) / v_min",
        not_proved=(
            "two agents at a time; Thms. IV-A.1/IV-A.2 are premises (Sec. V-B3 argues they survive the relaxed "
            "clocks and loss with its larger Delta t; monitored at run time)",
            "a speed that changes along an edge: each agent keeps one speed per edge (the engine: one per robot; "
            "in the step it arrives a robot's recorded straight segment is slower, docs/wang2020.md)",
            "the spin time of a differential-drive robot (Sec. V-B3's second buffer)",
        ),
)

#: The 004 lemmas declared as :class:`~swarmproof.invariants.lemma_api.LemmaSpec` (issue 32), by
#: id, in the suite's order: each is defined once, for its proof and for float judgments.
SPECS: dict = {spec.id: spec for spec in (TIME_NORMALISATION, PLANNER_VERTEX_ONE_MOMENT, PLANNER_EDGE_ONE_MOMENT,
                                          LEMMA_IV_A_1, THEOREM_IV_A_2, SEPARATION_EQUAL_SPEEDS,
                                          SPEED_BUFFER_V_B3_CASES, SEPARATION_SPEEDS)}

#: This module's lemmas by id, in order; :mod:`swarmproof.checkers.proofs` puts them in its
#: suite (``swarmproof prove``) through the algorithm registry's lemma sets.
LEMMAS: dict = {lemma_id: spec.lemma() for lemma_id, spec in SPECS.items()}
