"""An exact, independent check of the centralized optimum of 004 Sec. V with z3's ``Optimize``.

:func:`swarmproof.models.assignment.optimal_assignment` solves the
distance-optimal assignment (004 Sec. V, the centralized method of its
reference [12]) with scipy.  For small swarms (``size <= MAX_Z3_ROBOTS``)
:func:`z3_optimal_assignment` solves the same problem as an integer program
in z3 (one Boolean per robot-goal pair, exactly one goal per robot and one
robot per goal, minimise the sum of Manhattan distances), and
:func:`check_optimal_assignment` compares the two totals: held when equal,
violated when they differ, inconclusive when z3 times out or answers
``unknown`` (never a pass).

References
----------
004_004a3703645971e3.txt (Wang & Rubenstein 2020), Sec. V (centralized
distance-optimal assignment), Figs. 10, 12.

Examples
--------
>>> z3_optimal_assignment([(0, 0), (5, 0)], [(4, 0), (1, 0)]).cells
2
>>> check_optimal_assignment([(0, 0), (5, 0), (2, 2)], [(4, 0), (1, 0), (2, 3)])["status"]
'held'
"""

from __future__ import annotations

import time

import z3

from swarmproof.models.assignment import Assignment, _check_cells, _check_sizes, manhattan_matrix, optimal_assignment
from swarmproof.models.errors import UsageError, check_positive

__all__ = ["MAX_Z3_ROBOTS", "Z3Inconclusive", "z3_optimal_assignment", "check_optimal_assignment"]

#: Largest swarm the z3 encoding is asked about (n^2 Booleans; 8 robots solve in well under a second).
MAX_Z3_ROBOTS = 8


class Z3Inconclusive(Exception):
    """z3 answered ``unknown`` or ran out of time: no optimum, no verdict."""


def z3_optimal_assignment(start_cells, goal_cells, *, spacing: float = 1.0, timeout_s: float = 10.0) -> Assignment:
    """The distance-optimal assignment found by ``z3.Optimize`` (at most ``MAX_Z3_ROBOTS`` robots).

    Variables ``x_i_j`` (robot ``i`` takes goal ``j``); each robot takes
    exactly one goal and each goal one robot (pseudo-Boolean equalities);
    minimise ``sum D[i, j] x_i_j`` with ``D`` the Manhattan distances.

    Raises
    ------
    UsageError
        More than ``MAX_Z3_ROBOTS`` robots, or what ``optimal_assignment`` refuses.
    Z3Inconclusive
        z3 timed out or answered ``unknown``.
    """
    s = _check_cells("start_cells", start_cells)
    g = _check_cells("goal_cells", goal_cells)
    n = _check_sizes(s, g)
    if n > MAX_Z3_ROBOTS:
        raise UsageError(f"size={n} robots is above MAX_Z3_ROBOTS={MAX_Z3_ROBOTS} for the z3 check",
                         fix="use optimal_assignment (scipy) for larger swarms")
    timeout_s = check_positive("timeout", timeout_s, fix="give a timeout in seconds > 0")
    spacing = check_positive("spacing", spacing, fix="e.g. 0.2 (004 Sec. V-B3)")
    d = manhattan_matrix(s.tolist(), g.tolist())
    x = [[z3.Bool(f"x_{i}_{j}") for j in range(n)] for i in range(n)]
    opt = z3.Optimize()
    opt.set("timeout", max(1, int(timeout_s * 1000)))
    for i in range(n):
        opt.add(z3.PbEq([(x[i][j], 1) for j in range(n)], 1))
    for j in range(n):
        opt.add(z3.PbEq([(x[i][j], 1) for i in range(n)], 1))
    cost = z3.Sum([z3.If(x[i][j], int(d[i, j]), 0) for i in range(n) for j in range(n)])
    opt.minimize(cost)
    from swarmproof.checkers.proofs import check_interruptibly

    answer = check_interruptibly(opt)
    if answer != z3.sat:
        raise Z3Inconclusive(f"z3 answered {answer} ({opt.reason_unknown() if answer == z3.unknown else ''})")
    m = opt.model()
    pairs = sorted((i, j) for i in range(n) for j in range(n) if z3.is_true(m.eval(x[i][j], model_completion=True)))
    cells = m.eval(cost, model_completion=True).as_long()
    return Assignment(cells * spacing, pairs, cells=cells, method="z3.Optimize", size=n)


def check_optimal_assignment(start_cells, goal_cells, *, timeout_s: float = 10.0) -> dict:
    """Compare scipy's optimum with z3's: ``{status, scipy, z3, seconds, message}``.

    ``status`` is ``'held'`` when both totals (in cells) are equal and each
    solver's pairs are a permutation of that cost, ``'violated'`` when they
    differ, ``'inconclusive'`` when z3 gives no answer in ``timeout_s``.
    """
    t0 = time.perf_counter()
    ref = optimal_assignment(start_cells, goal_cells)
    try:
        exact = z3_optimal_assignment(start_cells, goal_cells, timeout_s=timeout_s)
    except Z3Inconclusive as exc:
        return {"status": "inconclusive", "scipy": ref.as_dict(), "z3": None,
                "seconds": time.perf_counter() - t0, "message": str(exc)}
    d = manhattan_matrix(start_cells, goal_cells)
    z3_pairs_cost = sum(int(d[i, j]) for i, j in exact.pairs)
    perm_ok = (sorted(j for _, j in exact.pairs) == list(range(exact.size)) and z3_pairs_cost == exact.cells)
    same = ref.cells == exact.cells and perm_ok
    msg = (f"scipy and z3 agree: optimum {ref.cells} cells for {ref.size} robots" if same else
           f"scipy's optimum {ref.cells} cells != z3's {exact.cells} (z3's pairs cost {z3_pairs_cost})")
    return {"status": "held" if same else "violated", "scipy": ref.as_dict(), "z3": exact.as_dict(),
            "seconds": time.perf_counter() - t0, "message": msg}
