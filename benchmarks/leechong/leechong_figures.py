"""Lee & Chong (003) figure runs: flocking, switching, failures, positioning errors; PNGs and a GIF.

Usage (from the repository root)::

    MPLBACKEND=Agg .venv/bin/python benchmarks/leechong/leechong_figures.py [--out docs] [--scale paper|test]

The scenarios of :data:`SCENARIOS` re-run the simulations of 003's Figs. 9, 12, 13, 15, 20, 22,
24, 27 and 28 with 12 robots from one seeded start (testbed :data:`SEED`, whose half planes hold
5 and 6 followers, so Alg. 1's printed formula and Sec. 2.1's prose numbering -- the default --
give the same IDs 0..11).  The failures of Figs. 12 and 22 re-issue IDs over 11 survivors, where
the two numberings can differ: ``fig12-printed`` and ``fig22-printed`` run the ``-printed``
variants beside the defaults (Fig. 12: the printed formula's IDs 12 and 14 break the re-formed
wedge; Fig. 22: the same trace under both).  ``--scale test``
uses the short flights and the 8-robot switching runs that
``tests/reference_impl/test_leechong_figures.py`` checks; ``--scale paper`` (default here) flies
100 units at 30 degrees as Fig. 9 does.  Each run is drawn (trails, final formation, allocated
IDs, the leader a red star, failed robots a black cross, the goal a cross) to
``docs/leechong-fig-<name>.png``, and one run (switching, a follower failure and flocking) is
animated to ``docs/leechong-run.gif`` (:func:`swarmproof.checkers.plotting.animate_trace`).

The measures the tests assert on live here too (:func:`leader_drift`, :func:`neighbor_gaps`,
:func:`reversals`, :func:`pattern_epochs`): plain functions of a trace, each with a doctest.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

from swarmproof.models.errors import UsageError

__all__ = ["SEED", "SCENARIOS", "FIG15", "scenario", "run_scenario", "allocated_ids", "flock_start",
           "leader_drift", "chain_depth", "neighbor_gaps", "reversals", "pattern_epochs", "draw_run", "main"]

#: The start of every figure run (testbed 5 of benchmarks/leechong/leechong_tables.py: 12 robots whose
#: half planes hold 5 and 6 followers, so the prose numbering and Alg. 1's printed formula both give 1..11).
SEED = 5
#: 003 Sec. 3.6 (Fig. 15): circle first, then "hexagon, arc, two columns, diamond, circle, and wedge".
FIG15 = ("circle", "hexagon", "arc", "two-column", "diamond", "circle", "wedge")
#: Fig. 9 / Fig. 20: "a distance of 100 units and at the 30 deg angle"; the tests fly 5.
FLOCK_PAPER, FLOCK_TEST = "100,30", "5,30"
#: The step at which a robot fails in Figs. 12, 13, 22 (the pattern stands from step 54/60 on
#: seed 5 and the leader flies; the tests check that it is moving at this step).
FAIL_STEP = 70


def scenario(name: str, scale: str = "test") -> dict:
    """The run behind a figure: ``{alg, pattern, robots, extra, fig, says}``.

    >>> scenario("fig09")["alg"], scenario("fig09")["extra"]
    ('leechong-leader', {'flock_to': '5,30'})
    >>> scenario("fig09", "paper")["extra"]
    {'flock_to': '100,30'}
    """
    if scale not in ("test", "paper"):
        raise UsageError(f"scale={scale!r} is not 'test' or 'paper'")
    fly = FLOCK_TEST if scale == "test" else FLOCK_PAPER
    n_switch = 8 if scale == "test" else 12
    then = ",".join(FIG15[1:])
    table = {
        "fig09": dict(alg="leechong-leader", pattern="arc", robots=12, extra={"flock_to": fly},
                      fig="Fig. 9", says="the followers keep dist and angle to the leader while it flies (Sec. 3.3)"),
        "fig20": dict(alg="leechong-neighbor", pattern="arc", robots=12, extra={"flock_to": fly},
                      fig="Fig. 20", says="each follower keeps pace with its N_id (Sec. 4.3)"),
        "fig15": dict(alg="leechong-leader", pattern="circle", robots=n_switch, extra={"then": then},
                      fig="Fig. 15", says="seven patterns in turn; leader and IDs stay (Secs. 3.4, 3.6)"),
        "fig24": dict(alg="leechong-neighbor", pattern="circle", robots=n_switch, extra={"then": then},
                      fig="Fig. 24", says="the same sequence by neighbor reference (Sec. 4.3)"),
        "fig12": dict(alg="leechong-leader", pattern="wedge", robots=12,
                      extra={"flock_to": fly, "fail": f"leader@{FAIL_STEP}"},
                      fig="Fig. 12", says="the leader fails while flying; a new leader, the wedge again (Sec. 3.5)"),
        "fig12-printed": dict(alg="leechong-leader-printed", pattern="wedge", robots=12,
                              extra={"flock_to": fly, "fail": f"leader@{FAIL_STEP}"},
                              fig="Fig. 12 (printed formula)", says="as fig12 with Alg. 1's printed ID formula"),
        "fig13": dict(alg="leechong-leader", pattern="wedge", robots=12,
                      extra={"flock_to": fly, "fail": f"5@{FAIL_STEP}"},
                      fig="Fig. 13", says="a follower fails; the others re-form the wedge (Sec. 3.5)"),
        "fig22": dict(alg="leechong-neighbor", pattern="wedge", robots=12,
                      extra={"flock_to": fly, "fail": f"5@{FAIL_STEP}"},
                      fig="Fig. 22", says="a follower fails by neighbor reference (Sec. 4.4)"),
        "fig22-printed": dict(alg="leechong-neighbor-printed", pattern="wedge", robots=12,
                              extra={"flock_to": fly, "fail": f"5@{FAIL_STEP}"},
                              fig="Fig. 22 (printed formula)", says="as fig22 with Alg. 1's printed ID formula"),
    }
    for pat, fig in (("hexagon", "Fig. 27"), ("wedge", "Fig. 28")):
        for mode in ("leader", "neighbor"):
            table[f"{fig[-2:]}-{pat}-{mode}"] = dict(
                alg=f"leechong-{mode}", pattern=pat, robots=12, extra={"position_errors": "3,6,9", "error_size": 0.3},
                fig=fig, says="positioning errors on IDs 3, 6, 9 (Sec. 5.2)")
    table["gif"] = dict(alg="leechong-leader", pattern="circle", robots=12,
                        extra={"then": "hexagon,wedge", "fail": "5@150", "flock_to": "8,30" if scale == "test" else "30,30"},
                        fig="GIF", says="switching, a follower failure while forming, flocking")
    if name not in table:
        raise UsageError(f"scenario={name!r} is not known", fix=f"use one of {sorted(table)!r}")
    return dict(table[name])


#: The scenarios drawn by :func:`main` (``fig22-printed`` is run by the tests only: its trace is
#: fig22's, since the 11 survivors' IDs are the same under both numberings; ``--only`` draws it).
SCENARIOS = ("fig09", "fig20", "fig15", "fig24", "fig12", "fig12-printed", "fig13", "fig22",
             "27-hexagon-leader", "27-hexagon-neighbor", "28-wedge-leader", "28-wedge-neighbor", "gif")


def run_scenario(name: str, scale: str = "test", **override):
    """Run :func:`scenario` ``name`` from testbed :data:`SEED` (``run_and_check``); ``override``
    replaces entries of its ``extra``."""
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.models.targets import resolve_target

    s = scenario(name, scale)
    extra = {**s["extra"], **override}
    return run_and_check(s["alg"], resolve_target("lines:" + s["pattern"]), seed=SEED, robots=s["robots"], extra=extra)


# ---------------------------------------------------------------------------------------------
# measures on a trace
# ---------------------------------------------------------------------------------------------


def allocated_ids(trace, t: int) -> list:
    """The ID each robot (trace column) holds at step ``t`` (None before Alg. 1 or when absent)."""
    return [None if s is None else dict(s)["id"] for s in trace.states[t]]


def flock_start(positions, leader: int) -> int | None:
    """The first step after which column ``leader`` of ``positions`` (``(T+1, n, 2)``) moves.

    >>> p = np.zeros((4, 2, 2)); p[3:, 1, 0] = 1.0
    >>> flock_start(p, 1), flock_start(p, 0)
    (2, None)
    """
    mv = np.hypot(*(np.diff(np.asarray(positions)[:, leader], axis=0)).T)
    hits = np.flatnonzero(mv > 0)
    return int(hits[0]) if len(hits) else None


def leader_drift(positions, refs: dict, start: int) -> dict:
    """For each follower column ``i`` the largest drift of its offset to column ``refs[i]``
    after ``start``: ``max_t |(p_i(t) - p_r(t)) - (p_i(start) - p_r(start))|`` (003 Secs. 3.3, 4.3:
    distance and angle to the reference "remain unchanged during flocking").

    >>> p = np.zeros((3, 2, 2)); p[:, 0, 0] = [0.0, 0.1, 0.2]; p[:, 1, 0] = [1.0, 1.0, 1.2]
    >>> {k: round(v, 9) for k, v in leader_drift(p, {1: 0}, 0).items()}
    {1: 0.1}
    """
    p = np.asarray(positions, dtype=float)
    out = {}
    for i, r in refs.items():
        off = p[start:, i] - p[start:, r]
        out[i] = float(np.hypot(*(off - off[0]).T).max())
    return out


def chain_depth(rid: int, kind: str = "uni", k: int | None = None) -> int:
    """How many N_id links (003 Alg. 4) lead from ID ``rid`` to the leader.

    >>> [chain_depth(i) for i in range(1, 12)]
    [1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6]
    """
    from swarmproof.reference_impl.leechong.algorithm import neighbor_id

    depth = 0
    while rid != 0:
        rid = neighbor_id(rid, kind, k)
        depth += 1
    return depth


def neighbor_gaps(points_by_id: dict, pattern: str, n: int, d_u: float = 1.0) -> dict:
    """``|p_i - p_N| - |f_i - f_N|`` for every follower ID ``i`` (N = N_id of 003 Alg. 4, f the
    pattern's targets): zero where a robot keeps its interval to its neighbor ("keep d_u",
    Sec. 5.2).

    >>> from swarmproof.models.line_patterns import target_points
    >>> f = target_points("wedge", 5, 1.0)
    >>> pts = {i: f[i] for i in range(5)}; pts[3] = f[3] + [0.3, 0.0]
    >>> {i: round(g, 3) for i, g in neighbor_gaps(pts, "wedge", 5).items()}
    {1: 0.0, 2: 0.0, 3: -0.245, 4: 0.0}
    """
    from swarmproof.models.line_patterns import line_count, pattern_info, target_points
    from swarmproof.reference_impl.leechong.algorithm import neighbor_id

    f = target_points(pattern, n, d_u)
    info = pattern_info(pattern)
    kind, k = ("uni", None) if info["type"] == "uni" else ("multi", line_count(pattern, n, reading="alg4"))
    out = {}
    for i in sorted(points_by_id):
        if i == 0:
            continue
        nb = neighbor_id(i, kind, k)
        if nb not in points_by_id:
            continue
        got = float(np.hypot(*(np.asarray(points_by_id[i]) - np.asarray(points_by_id[nb]))))
        out[i] = got - float(np.hypot(*(f[i] - f[nb])))
    return out


def reversals(track, eps: float = 1e-9) -> int:
    """How often a robot turns back (003 Sec. 5.2, Fig. 28: "moved back and forth"): steps whose
    displacement makes an obtuse angle with the previous moving step's (both longer than ``eps``).

    >>> reversals([[0, 0], [1, 0], [2, 0], [1, 0], [1, 0], [2, 0]])
    2
    >>> reversals([[0, 0], [1, 0], [1, 1]])
    0
    """
    d = np.diff(np.asarray(track, dtype=float), axis=0)
    prev, count = None, 0
    for v in d:
        if math.hypot(*v) <= eps:
            continue
        if prev is not None and float(v @ prev) < 0:
            count += 1
        prev = v
    return count


def pattern_epochs(trace) -> list:
    """The leader's pattern over the run as ``[(pattern, first step, last step)]`` (003 Sec. 3.6:
    the leader switches when it sees the pattern stand)."""
    out = []
    for t in range(len(trace.states)):
        lead = [dict(s) for s in trace.states[t] if s is not None and dict(s)["id"] == 0 and not dict(s)["failed"]]
        if not lead:
            continue
        name = lead[0]["pattern"]
        if out and out[-1][0] == name and out[-1][2] == t - 1:
            out[-1] = (name, out[-1][1], t)
        else:
            out.append((name, t, t))
    return out


# ---------------------------------------------------------------------------------------------
# drawing
# ---------------------------------------------------------------------------------------------


def draw_run(run, title: str, path, goal=None) -> str:
    """Trails (grey), final positions labelled with their allocated IDs, the leader a red star,
    failed robots black crosses, the flocking goal a green plus (checkers.plotting helpers)."""
    from swarmproof.checkers.plotting import new_figure, save_png

    tr = run.result.trace
    P = np.asarray(tr.poses)[:, :, :2]
    fig, ax = new_figure(6.0, 6.0)
    for k in range(tr.n):
        ax.plot(P[:, k, 0], P[:, k, 1], lw=0.6, color="0.7", zorder=1)
    ax.plot(P[0, :, 0], P[0, :, 1], "o", ms=3, color="0.5", zorder=2, label="start")
    for k, s in enumerate(tr.states[-1]):
        d = dict(s)
        x, y = P[-1, k]
        if d["failed"]:
            ax.plot([x], [y], "x", ms=8, mew=2, color="black", zorder=4)
        elif d["id"] == 0:
            ax.plot([x], [y], "*", ms=14, color="red", zorder=4)
        else:
            ax.plot([x], [y], "o", ms=6, color="tab:blue", zorder=3)
        ax.annotate(str(d["id"]), (x, y), xytext=(4, 3), textcoords="offset points", fontsize=7)
    if goal is not None:
        ax.plot([goal[0]], [goal[1]], "P", ms=10, color="tab:green", zorder=2, label="goal")
    d = run.doc
    ax.set_title(f"{title}\n{d['algorithm']}: {d['steps']} steps ({d['status']}), "
                 f"satisfied={d['satisfied']}, distance {d['total_distance']:.1f}", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    return save_png(fig, path)


def _goal_of(run, extra):
    """The flocking goal in the world: DIST at ANGLE from u, from the leader's start (Alg. 1 at step 0)."""
    spec = extra.get("flock_to")
    if not spec:
        return None
    dist, ang = (float(x) for x in str(spec).split(","))
    tr = run.result.trace
    P = np.asarray(tr.poses)[:, :, :2]
    ids0 = allocated_ids(tr, 1)
    if 0 not in ids0:
        return None
    lead = ids0.index(0)
    u = P[0, lead] - P[0].mean(axis=0)
    th = math.atan2(u[1], u[0]) + math.radians(ang)
    return P[0, lead] + dist * np.array((math.cos(th), math.sin(th)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--scale", choices=("paper", "test"), default="paper")
    ap.add_argument("--only", action="append", default=None, help="scenario name (repeatable)")
    args = ap.parse_args(argv)
    import os

    from swarmproof.checkers.plotting import animate_trace

    names = args.only or list(SCENARIOS)
    try:
        for name in names:
            scenario(name)
    except UsageError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for name in names:
        s = scenario(name, args.scale)
        t0 = time.perf_counter()
        run = run_scenario(name, args.scale)
        secs = time.perf_counter() - t0
        d = run.doc
        print(f"{name} ({s['fig']}): {d['algorithm']} {s['pattern']} n={s['robots']} {s['extra']}: {d['status']}, "
              f"{d['steps']} steps, satisfied={d['satisfied']}, ids_unique={d['metrics'].get('ids_unique')}, "
              f"distance {d['total_distance']:.2f} ({secs:.1f} s)", flush=True)
        if name == "gif":
            path = animate_trace(run.result.trace, os.path.join(args.out, "leechong-run.gif"),
                                 title="003: circle, hexagon, wedge; ID 5 fails; flocking", max_frames=80, fps=10)
        else:
            path = draw_run(run, f"003 {s['fig']}: {s['says']}", os.path.join(args.out, f"leechong-fig-{name}.png"),
                            goal=_goal_of(run, s["extra"]))
        print("  wrote", path, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
