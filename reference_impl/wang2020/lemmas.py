"""z3 lemmas for Wang & Rubenstein 2020's collision-freedom (004 Sec. IV-A; issue 15).

Listed in the algorithm registry's lemma sets, so :data:`swarmproof.checkers.proofs.LEMMAS`
holds them (ids prefixed ``wang2020_``), and solved by :func:`swarmproof.checkers.proofs.prove` like every lemma of the suite: premises
satisfiable, the negated conclusion ``unsat``, a negative control refuted, vacuity controls.

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

import z3

from swarmproof.invariants.lemmas import Encoding, Lemma, dist2, variables as _vars

__all__ = ["planner_one_moment", "lemma_iv_a_1", "theorem_iv_a_2", "separation", "speed_buffer_cases",
           "separation_speeds", "time_normalisation", "LEMMAS", "UNITS"]

#: The four grid moves of Alg. 2 line 9 (``surroundings``) and ``wait``, in units of ``l``.
UNITS = ((1, 0), (-1, 0), (0, 1), (0, -1))


# ------------------------------------------------------------------ helpers

def _one_of_moves(d, allow_wait: bool = True) -> z3.BoolRef:
    """``d`` is one of the four unit moves (or ``(0, 0)``, wait, when ``allow_wait``)."""
    opts = list(UNITS) + ([(0, 0)] if allow_wait else [])
    return z3.Or([z3.And(d[0] == a, d[1] == b) for a, b in opts])


def _peq(a, b) -> z3.BoolRef:
    return z3.And(a[0] == b[0], a[1] == b[1])


def _lex_gt(p, q) -> z3.BoolRef:
    """``p > q`` in the lexicographic order of 004 Sec. II-B (``p^x > q^x``, or equal ``x``
    and ``p^y > q^y``)."""
    return z3.Or(p[0] > q[0], z3.And(p[0] == q[0], p[1] > q[1]))


def _pt(name):
    return (z3.Real(f"{name}_x"), z3.Real(f"{name}_y"))


def _flag(name: str):
    """A yes/no choice as a real variable (counterexamples list numbers only,
    :func:`~swarmproof.checkers.proofs.model_to_numbers`): it is *yes* iff it equals 1.
    Returns ``(variable, the Boolean "it is 1")``."""
    x = z3.Real(name)
    return x, x == 1


# ------------------------------------------- (a) the planner at one moment

def planner_one_moment(neighbours: int = 3, rule: str = "paper", conclusion: str = "vertex") -> Encoding:
    """Alg. 2 lines 25-31 at one moment, for an agent and ``neighbours`` agents within ``R``.

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
    rho = z3.Real("rho")
    c = [(z3.RealVal(0), z3.RealVal(0))] + [_pt(f"c{k}") for k in range(1, n)]
    d = [_pt(f"d{k}") for k in range(n)]
    q = [_pt(f"q{k}") for k in range(n)]
    nxt = [(c[k][0] + d[k][0], c[k][1] + d[k][1]) for k in range(n)]
    ready_v, ready = zip(*[_flag(f"ready{k}") for k in range(n)])

    def hears(k, j):
        # within R in the L1 norm: a subset of the disc of radius R (see the docstring)
        dx, dy = c[k][0] - c[j][0], c[k][1] - c[j][1]
        return z3.And(dx + dy <= rho, dx - dy <= rho, -dx + dy <= rho, -dx - dy <= rho)

    prem = [("grid_length_at_most_half_R", rho >= 2)]                       # 004 Sec. III-A: l <= R/2
    prem += [(f"agent_{k}_intent_is_a_neighbouring_waypoint", _one_of_moves(d[k])) for k in range(n)]
    # within R of agent 0, weakened to the square |x|, |y| <= R around the disc (linear)
    prem += [(f"neighbour_{k}_within_R", z3.And(c[k][0] <= rho, -c[k][0] <= rho, c[k][1] <= rho,
                                                 -c[k][1] <= rho)) for k in range(1, n)]
    prem.append(("distinct_waypoints",
                 z3.And([z3.Not(_peq(c[a], c[b])) for a in range(n) for b in range(a + 1, n)])))
    prem.append(("distinct_priorities",
                 z3.And([z3.Not(_peq(q[a], q[b])) for a in range(n) for b in range(a + 1, n)])))
    move = []   # Alg. 2 lines 30-31: agent k sets wp <- next_step
    for k in range(n):
        blocks = []
        for j in range(n):
            if j == k:
                continue
            occupied = _peq(c[j], nxt[k])                                     # Alg. 2 line 26
            if rule == "optimistic":
                occupied = z3.And(occupied, _peq(nxt[j], c[j]))
            line28 = z3.And(_peq(nxt[j], nxt[k]), _lex_gt(q[j], q[k]))       # Alg. 2 line 28
            trig = occupied if rule == "no_priority" else z3.Or(occupied, line28)
            blocks.append(z3.And(hears(k, j), trig))
        move.append(z3.And(ready[k], z3.Not(_peq(nxt[k], c[k])), z3.Not(z3.Or(blocks))))
    pairs = [(a, b) for a in range(n) for b in range(n) if a != b]
    if conclusion == "vertex":
        parts = [
            ("no_two_agents_move_to_one_waypoint",
             z3.And([z3.Not(z3.And(move[a], move[b], _peq(nxt[a], nxt[b]))) for a, b in pairs if a < b])),
            ("no_move_onto_a_claimed_waypoint",
             z3.And([z3.Not(z3.And(move[a], _peq(nxt[a], c[b]))) for a, b in pairs])),
        ]
    else:
        parts = [("no_swap_along_an_edge",
                  z3.And([z3.Not(z3.And(move[a], move[b], _peq(nxt[a], c[b]), _peq(nxt[b], c[a])))
                          for a, b in pairs if a < b]))]
    return Encoding(premises=prem, conclusion=z3.And([t for _, t in parts]),
                    variables=[rho] + _vars(*c[1:], *d, *q) + list(ready_v), parts=parts)


# --------------------------------------------- message windows and clock phases

#: Broadcast indices ``k`` of the timing lemmas: agent ``a`` broadcasts at ``phase_a + k``
#: (period ``1/f_comm = 1``), for ``k`` in this range, i.e. at every broadcast time in
#: ``[-4, 1)``; the windows that matter lie in ``[-4, 0]`` (docs/proofs.md).  Broadcasts
#: outside the range are not constrained at all, which only weakens the premises.
BROADCASTS = range(-4, 1)


def _within(b, lo, hi, lo_closed: bool, hi_closed: bool) -> z3.BoolRef:
    lo_t = lo <= b if lo_closed else lo < b
    hi_t = b <= hi if hi_closed else b < hi
    return z3.And(lo_t, hi_t)


class _Messages:
    """The broadcasts of one agent as another agent reads them (Alg. 3 line 2): for each
    broadcast time ``phase + k`` three yes/no fields -- its ``wp`` is the reader's
    ``next_step`` (Alg. 2 line 26), its ``next_step`` is the reader's ``next_step`` and its
    sender has the higher priority (line 28's two conditions)."""

    def __init__(self, sender: str, reader: str) -> None:
        self.phase = z3.Real(f"phase_{sender}")
        self.times = [self.phase + k for k in BROADCASTS]
        names = [(f"{sender}{k}_wp_is_{reader}_next", f"{sender}{k}_next_is_{reader}_next",
                  f"{sender}{k}_outranks_{reader}") for k in BROADCASTS]
        self.flags = [tuple(_flag(n.replace("-", "m")) for n in trio) for trio in names]
        self.variables = [v for trio in self.flags for v, _ in trio]

    def wp(self, k):
        return self.flags[k][0][1]

    def nxt(self, k):
        return self.flags[k][1][1]

    def outranks(self, k):
        return self.flags[k][2][1]

    def during(self, lo, hi, lo_closed, hi_closed, what) -> z3.BoolRef:
        """Every broadcast in the interval satisfies ``what(k)``."""
        return z3.And([z3.Implies(_within(b, lo, hi, lo_closed, hi_closed), what(k))
                       for k, b in enumerate(self.times)])

    def triggers(self, k) -> z3.BoolRef:
        """Alg. 2 line 26 or line 28 fires on the reader."""
        return z3.Or(self.wp(k), z3.And(self.nxt(k), self.outranks(k)))


def _phases(*msgs) -> tuple:
    return ("broadcast_every_period_at_any_phase",
            z3.And([z3.And(0 <= m.phase, m.phase < 1) for m in msgs]))


def lemma_iv_a_1(window=2) -> Encoding:
    """004 Lemma IV-A.1 for agent ``a_i`` and any other agent ``a_j``, with the message
    windows and clock phases of its proof (Sec. II-A a-e, Alg. 2 lines 6, 15, 25-33, Alg. 3).

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
    w = z3.RealVal(window)
    tj, lci, lcj = z3.Reals("t_j last_check_i last_check_j")
    (jv, j_over_i), (iv, i_over_j) = _flag("j_outranks_i"), _flag("i_outranks_j")
    (hv_ij, heard_ij), (hv_ji, heard_ji) = _flag("i_hears_j"), _flag("j_hears_i")
    mj, mi = _Messages("j", "i"), _Messages("i", "j")   # j's broadcasts as i reads them; i's as j reads them
    waiting = lambda m, rank: lambda k: z3.And(z3.Not(m.wp(k)), m.nxt(k), m.outranks(k) == rank)  # noqa: E731
    prem = [
        _phases(mi, mj),
        ("i_waited_longer_than_window", lci < -w),
        ("i_intends_wp1_since_last_check", mi.during(lci, 0, False, False, waiting(mi, i_over_j))),
        ("j_waited_longer_than_window", lcj < tj - w),
        ("j_intends_wp1_since_last_check", mj.during(lcj, tj, False, False, waiting(mj, j_over_i))),
        ("j_claims_wp1_from_t_j_to_t_star", mj.during(tj, 0, False, True, mj.wp)),
        ("lexicographic_priority_of_distinct_waypoints", z3.Xor(j_over_i, i_over_j)),
        ("i_changes_claim_at_t_star_alg2_line30",
         z3.Implies(heard_ij, mj.during(-w, 0, True, True, lambda k: z3.Not(mj.triggers(k))))),
        ("j_changes_claim_at_t_j_alg2_line30",
         z3.Implies(heard_ji, mi.during(tj - w, tj, True, True, lambda k: z3.Not(mi.triggers(k))))),
        ("lossless_delivery_within_R", z3.And(heard_ij, heard_ji)),
    ]
    return Encoding(premises=prem, conclusion=tj > 0,
                    variables=[tj, lci, lcj, mi.phase, mj.phase, jv, iv, hv_ij, hv_ji]
                    + mj.variables + mi.variables)


def _disjoint(a0, a1, b0, b1) -> z3.BoolRef:
    """Half-open intervals ``[a0, a1)`` and ``[b0, b1)`` do not meet (``None`` end: infinity)."""
    out = []
    if a1 is not None:
        out.append(a1 <= b0)
    if b1 is not None:
        out.append(b1 <= a0)
    return z3.Or(out) if out else z3.BoolVal(False)


def theorem_iv_a_2(window=2) -> Encoding:
    """004 Thm. IV-A.2, its proof's premises: ``a_i`` changes its claim from ``wp^0`` to
    ``wp^1`` at ``t* = 0`` and ``a_j`` from ``wp^1`` to ``wp^0`` at ``t_j``; they never travel
    the edge in opposite directions at the same time.

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
    w = z3.RealVal(window)
    tj, lci, lcj, ci, cj, ui, uj, taui, tauj = z3.Reals(
        "t_j last_check_i last_check_j claim_i claim_j leave_i leave_j tau_i tau_j")
    (hv_ij, heard_ij), (hv_ji, heard_ji) = _flag("i_hears_j"), _flag("j_hears_i")
    mj, mi = _Messages("j", "i"), _Messages("i", "j")   # line 26 of i against wp1, of j against wp0
    prem = [
        _phases(mi, mj),
        ("claims_start_before_last_check", z3.And(ci < lci, cj < lcj)),
        ("i_waited_longer_than_window", lci < -w),
        ("j_waited_longer_than_window", lcj < tj - w),
        ("travel_takes_positive_time", z3.And(taui > 0, tauj > 0)),
        ("new_claims_end_after_arrival", z3.And(ui >= taui, uj >= tj + tauj)),
        # i claims wp0 on [c_i, 0), wp1 on [0, leave_i); j claims wp1 on [c_j, t_j), wp0 on [t_j, leave_j)
        ("i_broadcasts_its_claim", z3.And(mi.during(ci, 0, False, False, mi.wp),
                                         mi.during(0, ui, False, False, lambda k: z3.Not(mi.wp(k))))),
        ("j_broadcasts_its_claim", z3.And(mj.during(cj, tj, False, False, mj.wp),
                                         mj.during(tj, uj, False, False, lambda k: z3.Not(mj.wp(k))))),
        ("claims_distinct_at_every_instant_thm_iv_a_1",
         z3.And(_disjoint(ci, 0, tj, uj), _disjoint(0, ui, cj, tj))),
        ("i_changes_claim_at_t_star_alg2_line30",
         z3.Implies(heard_ij, mj.during(-w, 0, True, True, lambda k: z3.Not(mj.triggers(k))))),
        ("j_changes_claim_at_t_j_alg2_line30",
         z3.Implies(heard_ji, mi.during(tj - w, tj, True, True, lambda k: z3.Not(mi.triggers(k))))),
        ("lossless_delivery_within_R", z3.And(heard_ij, heard_ji)),
    ]
    overlap = z3.And(tj < taui, 0 < tj + tauj)
    return Encoding(premises=prem, conclusion=z3.Not(overlap),
                    variables=[tj, ci, cj, lci, lcj, ui, uj, taui, tauj, mi.phase, mj.phase, hv_ij, hv_ji]
                    + mj.variables + mi.variables)


def time_normalisation(positive_period: bool = True) -> Encoding:
    """Time can be shifted and scaled: for ``T > 0`` and times ``a, b, c``, and any integer
    offset ``k`` (broadcasts ``k`` periods apart), ``a <= b + k T`` iff
    ``(a - c)/T <= (b - c)/T + k``, and the same with ``<``.  So ``t* = 0`` and
    ``1/f_comm = 1`` lose nothing in :func:`lemma_iv_a_1` and :func:`theorem_iv_a_2`, whose
    premises and conclusion are such comparisons.  The control lets ``T`` be any non-zero
    number (a negative period reverses the order).

    Stated with the multiplication cleared (``T (a - c)/T = a - c``): ``a' = (a - c)/T`` is
    the variable with ``T a' = a - c``."""
    a, b, c, T, k, a2, b2 = z3.Reals("a b c T k a_n b_n")
    prem = [("period_positive" if positive_period else "period_nonzero", T > 0 if positive_period else T != 0),
            ("a_normalised", T * a2 == a - c), ("b_normalised", T * b2 == b - c)]
    concl = z3.And((a <= b + k * T) == (a2 <= b2 + k), (a < b + k * T) == (a2 < b2 + k))
    return Encoding(premises=prem, conclusion=concl, variables=[a, b, c, T, k, a2, b2])


# ----------------------------------------------------- (b) the geometric separation

def _waypoint_offset(x) -> z3.BoolRef:
    """``x`` is an integer offset in cells: one of ``-2..2``, or at least 3 away (any real
    there: those waypoints are too far for any contact, so their integrality is not needed)."""
    return z3.Or([x == v for v in range(-2, 3)] + [x >= 3, x <= -3])


def separation(bound_factor2=1) -> Encoding:
    """Two discs of radius ``r`` on 004's grid, each resting at its waypoint or moving along an
    edge at the common speed, stay at least ``2r`` apart at every instant if
    ``l >= 2 sqrt(2) r`` (004 Sec. III-A; Sec. V-B3's bound with ``v_min = v_max``).

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
    r, t = z3.Reals("r t")
    x, y = z3.Reals("A_j_x A_j_y")
    e, s, lam = {}, {}, {}
    for a in "ij":
        e[a], s[a], lam[a] = z3.Reals(f"e_{a} s_{a} lam_{a}")
    src = {"i": (z3.RealVal(0), z3.RealVal(0)), "j": (x, y)}
    D = {a: _pt(f"D_{a}") for a in "ij"}
    pos = {a: (src[a][0] + lam[a] * D[a][0], src[a][1] + lam[a] * D[a][1]) for a in "ij"}
    prem = [
        ("grid_length_at_least_2_sqrt2_r", z3.And(r > 0, 8 * bound_factor2 * r * r <= 1)),
        ("j_source_is_a_waypoint", z3.And(_waypoint_offset(x), _waypoint_offset(y))),
    ]
    cases = []
    for di in list(UNITS) + [(0, 0)]:
        for dj in list(UNITS) + [(0, 0)]:
            mv = {"i": di, "j": dj}
            extra, claims = [], {}
            for a in "ij":
                d, A = mv[a], src[a]
                moving = d != (0, 0)
                B = (A[0] + d[0], A[1] + d[1])
                extra.append((f"{a}_move_of_the_case", _peq(D[a], d)))
                extra.append((f"{a}_at_its_source_by_t", t >= e[a] + 1))
                if moving:
                    extra.append((f"{a}_reached_its_source_before_setting_off", s[a] >= e[a] + 1))
                    extra.append((f"{a}_moves_at_the_common_speed", z3.Or(
                        z3.And(t <= s[a], lam[a] == 0),
                        z3.And(s[a] <= t, t <= s[a] + 1, lam[a] == t - s[a]),
                        z3.And(t >= s[a] + 1, lam[a] == 1))))
                    claims[a] = [(A, e[a], s[a]), (B, s[a], None)]
                else:
                    extra.append((f"{a}_rests", lam[a] == 0))
                    claims[a] = [(A, e[a], None)]
            extra.append(("claims_distinct_at_every_instant_thm_iv_a_1", z3.And(
                [z3.Implies(_peq(wa, wb), _disjoint(a0, a1, b0, b1))
                 for wa, a0, a1 in claims["i"] for wb, b0, b1 in claims["j"]])))
            if di != (0, 0) and dj != (0, 0):
                bi = (di[0], di[1])
                bj = (x + dj[0], y + dj[1])
                swap = z3.And(_peq(src["i"], bj), _peq(src["j"], bi))
                extra.append(("no_opposite_travel_on_one_edge_thm_iv_a_2", z3.Implies(
                    swap, _disjoint(s["i"], s["i"] + 1, s["j"], s["j"] + 1))))
            cases.append((f"i{_dname(di)}_j{_dname(dj)}", extra))
    return Encoding(premises=prem, conclusion=dist2(pos["i"], pos["j"]) >= 4 * r * r,
                    variables=[r, t, x, y, e["i"], s["i"], lam["i"], e["j"], s["j"], lam["j"]]
                    + _vars(D["i"], D["j"]), cases=cases)


def _speed_buffer_premise(r, rho, bound_factor2) -> tuple:
    """004 Sec. V-B3's buffer space, normalised ``l = 1``, ``v_max = 1``, ``rho = v_min / v_max``:
    ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min`` squared and cleared of the division,
    ``4 r^2 (1 + rho^2) <= rho^2`` (``bound_factor2`` scales the left side: the control's
    ``0.99^2`` puts ``l`` one per cent below the bound)."""
    return ("grid_length_at_least_the_v_b3_speed_buffer",
            z3.And(r > 0, rho > 0, rho <= 1, 4 * bound_factor2 * r * r * (1 + rho * rho) <= rho * rho))


def _edge_fraction(lam, w, t, s) -> z3.BoolRef:
    """``lam = min(1, max(0, w (t - s)))``: the fraction of its edge an agent of speed ``w`` that
    set off at ``s`` has covered at ``t`` (the exact position on the edge, DESIGN.md section 5)."""
    run = w * (t - s)
    return z3.Or(z3.And(t <= s, lam == 0),
                 z3.And(s <= t, run <= 1, lam == run),
                 z3.And(run >= 1, lam == 1))


def speed_buffer_cases(bound_factor2=1) -> Encoding:
    """004 Sec. V-B3's two cases, as the paper derives its buffer space: agent ``L`` leaves
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
    r, rho, a, b, t, lam_l, lam_f = z3.Reals("r rho a b t lam_L lam_F")
    prem = [
        _speed_buffer_premise(r, rho, bound_factor2),
        ("speeds_within_v_min_v_max", z3.And(rho <= a, a <= 1, rho <= b, b <= 1)),
        ("f_on_its_edge_t_in_0_l_over_b", z3.And(t >= 0, b * t <= 1, lam_f == b * t)),
        ("l_leaves_w_at_t_0", _edge_fraction(lam_l, a, t, z3.RealVal(0))),
    ]
    f = (-1 + lam_f, z3.RealVal(0))
    p_l = _pt("L")          # the leaving agent's position: a case premise puts it on its edge
    cases = [("orthogonal_adjacent_edges", [("l_leaves_w_orthogonally_to_f_edge", _peq(p_l, (0, lam_l)))]),
             ("collinear_adjacent_edges", [("l_leaves_w_along_f_edge", _peq(p_l, (lam_l, 0)))])]
    return Encoding(premises=prem, conclusion=dist2(p_l, f) >= 4 * r * r,
                    variables=[r, rho, a, b, t, lam_l, lam_f, *p_l], cases=cases)


def separation_speeds(bound_factor2=1) -> Encoding:
    """:func:`separation` with speeds of their own (004 Sec. V-B3): two discs of radius ``r``,
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
    r, rho, t = z3.Reals("r rho t")
    x, y = z3.Reals("A_j_x A_j_y")
    e, s, lam, w = {}, {}, {}, {}
    for a in "ij":
        e[a], s[a], lam[a], w[a] = z3.Reals(f"e_{a} s_{a} lam_{a} w_{a}")
    src = {"i": (z3.RealVal(0), z3.RealVal(0)), "j": (x, y)}
    D = {a: _pt(f"D_{a}") for a in "ij"}
    pos = {a: (src[a][0] + lam[a] * D[a][0], src[a][1] + lam[a] * D[a][1]) for a in "ij"}
    prem = [
        _speed_buffer_premise(r, rho, bound_factor2),
        ("speeds_within_v_min_v_max", z3.And([z3.And(rho <= w[a], w[a] <= 1) for a in "ij"])),
        ("j_source_is_a_waypoint", z3.And(_waypoint_offset(x), _waypoint_offset(y))),
    ]
    cases = []
    for di in list(UNITS) + [(0, 0)]:
        for dj in list(UNITS) + [(0, 0)]:
            mv = {"i": di, "j": dj}
            extra, claims = [], {}
            for a in "ij":
                d, A = mv[a], src[a]
                B = (A[0] + d[0], A[1] + d[1])
                extra.append((f"{a}_move_of_the_case", _peq(D[a], d)))
                extra.append((f"{a}_at_its_source_by_t", t >= e[a] + 1))
                if d != (0, 0):
                    extra.append((f"{a}_moves_at_its_own_speed", _edge_fraction(lam[a], w[a], t, s[a])))
                    claims[a] = [(A, e[a], s[a]), (B, s[a], None)]
                else:       # resting: D = (0, 0), so lam does not matter
                    claims[a] = [(A, e[a], None)]
            extra.append(("claims_distinct_at_every_instant_thm_iv_a_1", z3.And(
                [z3.Implies(_peq(wa, wb), _disjoint(a0, a1, b0, b1))
                 for wa, a0, a1 in claims["i"] for wb, b0, b1 in claims["j"]])))
            if di != (0, 0) and dj != (0, 0):
                swap = z3.And(_peq(src["i"], (x + dj[0], y + dj[1])), _peq(src["j"], di))
                extra.append(("no_opposite_travel_on_one_edge_thm_iv_a_2", z3.Implies(
                    swap, _disjoint(s["i"], s["i"] + 1, s["j"], s["j"] + 1))))
            cases.append((f"i{_dname(di)}_j{_dname(dj)}", extra))
    return Encoding(premises=prem, conclusion=dist2(pos["i"], pos["j"]) >= 4 * r * r,
                    variables=[r, rho, t, x, y, e["i"], s["i"], lam["i"], w["i"], e["j"], s["j"], lam["j"], w["j"]]
                    + _vars(D["i"], D["j"]), cases=cases)


def _dname(d) -> str:
    return {(1, 0): "east", (-1, 0): "west", (0, 1): "north", (0, -1): "south", (0, 0): "rests"}[d]


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

_LEMMA_LIST = [
    Lemma(
        id="wang2020_time_normalisation",
        statement="Shifting and scaling time by a positive period keeps every comparison a <= b + k T (and <): "
                  "t* = 0 and 1/f_comm = 1 lose nothing.",
        cites=("normalisation lemma (docs/proofs.md)",),
        normalisations=(),
        build=time_normalisation,
        control=lambda: time_normalisation(positive_period=False),
        control_note="the period may be negative (T != 0)",
        solver_params=(),
    ),
    Lemma(
        id="wang2020_planner_vertex_one_moment",
        statement="At one moment, agents on distinct waypoints with distinct priorities, each deciding by Alg. 2 "
                  "lines 25-31 on the current claims and intents of the agents within R (l <= R/2), never move two "
                  "agents to one waypoint nor one agent onto a waypoint another claims (an agent and 3 neighbours; "
                  "any priorities, any intents).",
        cites=("004 Alg. 2 lines 25-31, Sec. III-A Constraint III-A.1 (one moment; Thm. IV-A.1 is not proved "
               "here)",),
        normalisations=_GRID,
        build=planner_one_moment,
        control=lambda: planner_one_moment(rule="no_priority"),
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
    ),
    Lemma(
        id="wang2020_planner_edge_one_moment",
        statement="At one moment, Alg. 2 lines 25-31 never let two agents swap along one edge (agents on distinct "
                  "waypoints, distinct priorities, within R, l <= R/2; an agent and 3 neighbours).",
        cites=("004 Alg. 2 lines 25-31, Sec. III-A Constraint III-A.2 (one moment; Thm. IV-A.2 is not proved "
               "here)",),
        normalisations=_GRID,
        build=lambda: planner_one_moment(conclusion="edge"),
        control=lambda: planner_one_moment(rule="optimistic", conclusion="edge"),
        control_note="line 26 ignores an occupant that itself moves away (a planner allowing edge swaps)",
        solver_params=_SMT,
        not_proved=("message windows, clock phases and waiting: wang2020_theorem_iv_a_2 has the timing",),
    ),
    Lemma(
        id="wang2020_lemma_iv_a_1",
        statement="If agent a_i changes its claim wp from wp0 to wp1 at t*, no agent a_j claims wp1 at t*: each "
                  "agent broadcasts (p, wp, next_step) every 1/f_comm at any phase, waits at its waypoint longer "
                  "than Delta t = 2/f_comm with next_step fixed since last_check, reads the messages of the last "
                  "Delta t (lines 15, 25-29), every message reaches the agents within R, and the two waypoints "
                  "are distinct (lexicographic priority).",
        cites=("004 Lemma IV-A.1 and its proof (Conditions 1-2, Cases 1-2), Alg. 2 lines 6, 15, 25-33, Alg. 3, "
               "Sec. II-A",),
        normalisations=_TIME,
        build=lemma_iv_a_1,
        control=lambda: lemma_iv_a_1(window=1),
        control_note="Delta t = 1/f_comm instead of 2/f_comm",
        solver_params=_SMT,
        kind="paper lemma",
        not_proved=(
            "two agents at a time (the lemma is about every other agent a_j, one at a time, as in the paper)",
            _PAPER_TIMING,
            "that next_step stays fixed since last_check (Sec. III-C's timer reset, Alg. 4 lines 7-21) and that the "
            "waypoints are distinct (Thm. IV-A.1's induction): premises, checked at run time",
        ),
    ),
    Lemma(
        id="wang2020_theorem_iv_a_2",
        statement="Two agents never travel one edge in opposite directions at the same time, given the broadcasts, "
                  "windows and waits of Lemma IV-A.1 and Thm. IV-A.1's conclusion (claims distinct at every "
                  "instant); travel times are any positive numbers.",
        cites=("004 Thm. IV-A.2 and its proof (Cases 1-2), Alg. 2 lines 26, 30, Alg. 3",),
        normalisations=_TIME,
        build=theorem_iv_a_2,
        control=lambda: theorem_iv_a_2(window=0.5),
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
    ),
    Lemma(
        id="wang2020_separation_equal_speeds",
        statement="Two discs of radius r on a grid with l >= 2 sqrt(2) r, each resting at its waypoint or moving "
                  "along an edge at the common speed, with claims distinct at every instant (Thm. IV-A.1) and no "
                  "opposite travel on one edge (Thm. IV-A.2), are at least 2r apart at every instant (the exact "
                  "position on the edge at time t).",
        cites=("004 Sec. III-A (2 sqrt(2) r <= l), Sec. II-C (||p_i - p_j|| >= 2r), Sec. V-B3 (its bound with "
               "v_min = v_max)",),
        normalisations=_GRID + ("scale: the common speed 1, an edge takes one time unit (scale_invariance)",),
        build=separation,
        control=lambda: separation(bound_factor2=0.99 ** 2),
        control_note="l one per cent below 2 sqrt(2) r",
        not_proved=(
            "different speeds (Sec. V-B3: l >= 2 r sqrt(v_max^2 + v_min^2) / v_min) and the spin time of a "
            "differential-drive robot: equal speeds only, so auxiliary (DESIGN.md section 5)",
            "two agents at a time; Thms. IV-A.1/IV-A.2 are premises (monitored at run time)",
        ),
    ),
    Lemma(
        id="wang2020_speed_buffer_v_b3_cases",
        statement="Sec. V-B3's two cases: an agent leaving a waypoint W and an agent entering W from a neighbouring "
                  "waypoint, setting off at once at speeds in [v_min, v_max], on orthogonal or on collinear adjacent "
                  "edges, stay at least 2r apart while the entering agent is on its edge, if "
                  "l >= 2 r sqrt(v_max^2 + v_min^2) / v_min.",
        cites=("004 Sec. V-B3 (the buffer space l >= 2 sqrt(v_max^2 + v_min^2) r / v_min from its orthogonal and "
               "collinear cases; the paper's worst case is the leaver at v_min, the enterer at v_max)",),
        normalisations=_GRID + _SPEED,
        build=speed_buffer_cases,
        control=lambda: speed_buffer_cases(bound_factor2=0.99 ** 2),
        control_note="l one per cent below 2 r sqrt(v_max^2 + v_min^2) / v_min",
        not_proved=(
            "any other pair of edges or start times than a common start: wang2020_separation_speeds covers them",
            "the spin time of a differential-drive robot (Sec. V-B3's second buffer, v_max pi / (2 omega*)): the "
            "engine's grid robots are holonomic",
        ),
    ),
    Lemma(
        id="wang2020_separation_speeds",
        statement="Two discs of radius r on a grid with l >= 2 r sqrt(v_max^2 + v_min^2) / v_min, each resting at its "
                  "waypoint or moving along an edge at its own speed in [v_min, v_max], with claims distinct at every "
                  "instant (Thm. IV-A.1) and no opposite travel on one edge (Thm. IV-A.2), are at least 2r apart at "
                  "every instant: every pair of moves (25 cases) and any start times.",
        cites=("004 Sec. V-B3 (v_min <= v_m^i <= v_max, the buffer space l), Sec. II-C (||p_i - p_j|| >= 2r), "
               "Constraints III-A.1/III-A.2",),
        normalisations=_GRID + _SPEED,
        build=separation_speeds,
        control=lambda: separation_speeds(bound_factor2=0.99 ** 2),
        control_note="l one per cent below 2 r sqrt(v_max^2 + v_min^2) / v_min",
        not_proved=(
            "two agents at a time; Thms. IV-A.1/IV-A.2 are premises (Sec. V-B3 argues they survive the relaxed "
            "clocks and loss with its larger Delta t; monitored at run time)",
            "a speed that changes along an edge: each agent keeps one speed per edge (the engine: one per robot; "
            "in the step it arrives a robot's recorded straight segment is slower, docs/wang2020.md)",
            "the spin time of a differential-drive robot (Sec. V-B3's second buffer)",
        ),
    ),
]

#: This module's lemmas by id, in order; :mod:`swarmproof.checkers.proofs` puts them in its
#: suite (``swarmproof prove``) through the algorithm registry's lemma sets.
LEMMAS: dict = {lem.id: lem for lem in _LEMMA_LIST}
