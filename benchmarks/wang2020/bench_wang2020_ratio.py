"""Why wang2020's distance ratio (ours / the centralized optimum) grows with n (issue 15).

Usage (from the repository root)::

    .venv/bin/python benchmarks/wang2020/bench_wang2020_ratio.py decompose --n 144 --seeds 0,1
    .venv/bin/python benchmarks/wang2020/bench_wang2020_ratio.py decompose --n 64 --seeds 0,1,2 --reading req
    .venv/bin/python benchmarks/wang2020/bench_wang2020_ratio.py decompose --n 144 --seeds 0 --params '{"beta": 0.1}'
    .venv/bin/python benchmarks/wang2020/bench_wang2020_ratio.py bounds --sizes 16,64,144,256,529 --seeds 0,1,2

``decompose`` runs the per-robot reference (Fig. 10's trial: ``random_shape(n)``, starts uniform in a
32 x 32 arena, stop once formed) with an instrumented controller and prints one JSON line per seed:
the distance travelled in grid edges and how it splits.  Every greedy move (Alg. 2 lines 9-14)
shortens the distance to the agent's goal by one edge, so

    travelled = initial + swaps + duplicates - residual

exactly: ``initial`` is the distance to the random goals of Alg. 2 line 4, ``swaps`` and
``duplicates`` sum the change of the agent's distance to its goal at every goal change by a
handshake (Alg. 4 lines 11-21) or by duplicate resolution (lines 3-10), and ``residual`` is what is
left when the run stops (goal distances plus edges under way).  It also counts ``half_swaps``: a
server took the client's goal (on the request) but the client never got the ACK (its timeout came
first), which leaves two agents on one goal (Sec. III-A's handshake is not atomic).

``--reading`` runs one or more ("+"-joined) other readings of ambiguous text, each a subclass
here, never the registered algorithm (:data:`READINGS`; docs/wang2020.md, "Why the distance ratio
grows with n").  ``--params`` overrides ``params.extra`` (beta, handshake_timeout, ack_hold,
broadcast_every; ``dt`` sets the time step).

``bounds`` needs no simulation: for the same instances, the random assignment's expected cost,
the optimum, and two idealised centralized swap processes from a random permutation (no
duplicates, no handshakes, no waiting): ``static`` applies improving swaps between agents within R
(3 grid edges, Euclidean) of each other at their start positions until none is left; ``dynamic``
does the same every round at the current positions, then moves every agent one greedy step (no
collisions).  Every random choice comes from an explicit seed.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import time

import numpy as np

from swarmproof.models.assignment import optimal_assignment
from swarmproof.reference_impl.wang2020 import algorithm as W
from swarmproof.reference_impl.protocol import Command
from swarmproof.reference_impl.wang2020.algorithm import manhattan as md
from swarmproof.reference_impl.wang2020.experiments import (ARENA, ProgressObserver, experiment_params,
                                                            random_assignment_cells)
from swarmproof.reference_impl.wang2020.experiments import fig10_instance as instance

R_CELLS = 3.0    # R / l = 0.6 m / 0.2 m (004 Sec. V-A, V-B3)


def costs(starts, goals) -> tuple:
    """``(optimum, random assignment's expected cost)`` in grid edges: the distance-optimal
    assignment (the centralized method's total, Fig. 10) and n times the mean start-goal distance."""
    return int(optimal_assignment(starts, goals).cells), random_assignment_cells(starts, goals)


# -- the instrumented controller --------------------------------------------------------------

class Counting(W.BroadcastHandshakeController):
    """The controller of reading "1" (``wang2020-broadcast-handshake``: the handshake in the
    broadcasts, wang2020's default up to 0.3.0, on which this study of issue 15 was made), counting
    (in ``self.c``) where its goal changes come from."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        self.c = dict(initial=0, swaps=0, duplicates=0, dup_changes=0, dup_same=0, begun_reduce=0,
                      begun_equal=0, server_ok=0, client_ok=0, ticks=0, ticks_in_handshake=0)

    def _begin_shape(self, now):
        super()._begin_shape(now)
        self.c["initial"] += md(self.wp, self.T)
        self.initial_goal = self.T

    def step(self, obs):
        self.c["ticks"] += 1
        self.c["ticks_in_handshake"] += self.hs is not None
        return super().step(obs)

    def select_new_goal(self):
        old = self.T
        g = super().select_new_goal()
        self.c["dup_changes"] += 1
        self.c["dup_same"] += g == old
        self.c["duplicates"] += md(self.wp, g) - md(self.wp, old)
        return g

    def _begin_handshake(self, now, peer, m):
        reduce = md(self.wp, m.T) + md(m.wp, self.T) < md(self.wp, self.T) + md(m.wp, m.T)
        self.c["begun_reduce" if reduce else "begun_equal"] += 1
        super()._begin_handshake(now, peer, m)

    def _counted(self, outcome: str, handler, *args):
        """Run a handshake handler; when it ended the handshake, count ``outcome`` and the goal change."""
        before, hs = self.T, self.hs
        handler(*args)
        if hs is not None and self.hs is None:
            self.c[outcome] += 1
            self.c["swaps"] += md(self.wp, self.T) - md(self.wp, before)

    def _on_request(self, now, sender, req):
        self._counted("server_ok", super()._on_request, now, sender, req)

    def _on_ack(self, now, sender, ack):
        self._counted("client_ok", super()._on_ack, now, sender, ack)


# -- other readings of ambiguous text (never the registered algorithm) ------------------------

class OwnGoalAssigned:
    """(a) Alg. 2 lines 21-22: the agent's own goal T counts as assigned, so an agent next to its own
    goal does not anchor the gradient on it (the reference: only the goals in msg_buff count)."""

    def _gradient(self):
        T = self.T
        mine = [e for e in self.buff if e[3] == self.shape]
        if not mine or any(e[2].T == T for e in mine):      # line 16: empty; or T already held
            return super()._gradient()
        # Put a stand-in message holding T into the buffer for lines 21-22 only: hop None (infinity)
        # and our own q_u, so lines 18-20 pick what they would without it.
        probe = (self.now, -1, W.WangMsg(self.p, self.wp, self.next_step, T, self.q_u, None), self.shape)
        self.buff.append(probe)
        try:
            return super()._gradient()
        finally:
            self.buff.pop()


class RestingKeepsGoal:
    """(b) a duplicate between an agent resting on the goal and one that is not: the one not on it
    changes goal, whatever the lexical order (the reference: the lexically smaller one, Alg. 4 line 5).
    The rest is the reference's goal manager line for line."""

    def _goal_manager(self, now, sender, m):
        if m.request is not None and m.request[0] == self.id:
            self._on_request(now, sender, m.request)
        if m.ack is not None and m.ack[0] == self.id:
            self._on_ack(now, sender, m.ack)
        while m.completed > self.completed:
            self._switch(now)
        if min(m.completed, self._last) != self.shape or self.hs is not None:
            return
        T, mT = self.T, m.T
        if mT == T:
            me_on = (not self.moving) and self.wp == T
            he_on = m.wp == mT and abs(m.p[0] - self.l * mT[0]) < 1e-9 and abs(m.p[1] - self.l * mT[1]) < 1e-9
            if (he_on and not me_on) or (me_on == he_on and W.lex_greater(m.p, self.p)):
                T = self.T = self.select_new_goal()
                self.last_check = now
        now_cost = md(self.wp, T) + md(m.wp, mT)
        swap_cost = md(self.wp, mT) + md(m.wp, T)
        if swap_cost < now_cost:
            self._begin_handshake(now, sender, m)
        elif swap_cost == now_cost and self.rng.random() < self.beta:
            self._begin_handshake(now, sender, m)


class PreferReducing:
    """(c) within one tick's messages, the handshake goes to the peer whose swap reduces the pairwise
    cost most; an equal-cost peer (drawn with beta, line 16) only if none reduces it (the reference:
    the first message that triggers line 11 or 16)."""

    def step(self, obs):
        self._cands, self._defer = [], True
        cmd = super().step(obs)
        self._defer = False
        if self._cands:                       # moving: Alg. 2 did not run this tick
            self._resolve(self.now)
            cmd = Command(message=self.message(), move=cmd.move)
        return cmd

    def _main(self, now):
        self._defer = False
        self._resolve(now)
        return super()._main(now)

    def _begin_handshake(self, now, peer, m):
        if getattr(self, "_defer", False):
            self._cands.append((peer, m))
            return
        super()._begin_handshake(now, peer, m)

    def _resolve(self, now):
        cands, self._cands = self._cands, []
        if self.hs is not None:
            return
        best, gain, equal = None, 0, None
        for peer, m in cands:
            if m.T == self.T:
                continue
            g = md(self.wp, self.T) + md(m.wp, m.T) - md(self.wp, m.T) - md(m.wp, self.T)
            if g > gain:
                best, gain = (peer, m), g
            elif g == 0 and equal is None:
                equal = (peer, m)
        pick = best or equal
        if pick is not None:
            super()._begin_handshake(now, *pick)


class AcceptAnyReducing:
    """(d) an agent that is not a waiting client accepts any request whose swap reduces the pairwise
    cost, not only its intended peer's (the reference: only the intended peer, Sec. III-A)."""

    def _goal_manager(self, now, sender, m):
        r = m.request
        if (r is not None and r[0] == self.id and (self.hs is None or self.hs.role == "server")
                and not (self.hs is not None and self.hs.peer == sender)
                and (int(sender), int(r[1])) not in self.answered):
            cT = tuple(r[2])
            if md(self.wp, cT) + md(m.wp, self.T) < md(self.wp, self.T) + md(m.wp, cT):
                self.hs = W._Handshake("server", int(sender), -1, now + self.timeout, self.T)
        return super()._goal_manager(now, sender, m)


class RequestThenWait:
    """(e) Sec. III-A's client "send[s] a handshake request ... and then wait[s] for the ACK": the
    request goes out only while an answer can still arrive before the client's timeout (a round
    trip, Delta t = 2 / f_comm, before it); the reference repeats it until the timeout, so a
    server may take the goal on a request whose ACK comes too late (a half swap)."""

    def message(self):
        msg = super().message()
        if msg.request is not None and self.now + self.delta_t > self.hs.deadline + 1e-9:
            msg = dataclasses.replace(msg, request=None)
        return msg


#: reading name -> mixin (``--reading``; "+" joins several).
READINGS = {"own": OwnGoalAssigned, "rest": RestingKeepsGoal, "pref": PreferReducing,
            "srv": AcceptAnyReducing, "req": RequestThenWait}


def controller_class(reading: str = ""):
    """The counting controller with the named readings mixed in (``""``: the reference)."""
    mix = tuple(READINGS[r] for r in reading.split("+") if r)
    return type("Counting_" + (reading.replace("+", "_") or "reference"), mix + (Counting,), {})


# -- one decomposed trial -----------------------------------------------------------------------

def decompose(n: int, seed: int, reading: str = "", params: dict | None = None, *, arena: int = ARENA,
              max_steps: int = 60000) -> dict:
    """One Fig. 10 trial on the per-robot reference (instrumented); the dict of the module docstring."""
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.engine import simulate

    goals, starts = instance(n, seed, arena)
    extra = dict(params or {})
    dt = extra.pop("dt", None)
    p = experiment_params(n, **extra)
    if dt is not None:
        p = dataclasses.replace(p, dt=float(dt))
    l = float(p.extra["grid_spacing"])
    made = []

    class Ctrl(controller_class(reading)):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            made.append(self)

    alg = type("Instrumented", (W.Wang2020BroadcastHandshake,), {"controller_class": Ctrl})()
    init = InitialConfiguration(list(range(n)), [[l * x, l * y, 0.0] for x, y in starts])
    ob = ProgressObserver(W.goal_cells(goals, l), l, every=10)
    t0 = time.process_time()
    r = simulate(alg, goals, init, p, seed=seed, record_every=10 ** 9, observers=[ob],
                 stop_when=lambda *a: ob.formed_step is not None, max_steps=max_steps)
    res = ob.result()
    c = {k: sum(x.c[k] for x in made) for k in made[0].c}
    # what is left: each agent's goal distance from the waypoint it claims, plus the part of the
    # edge it is still on (poses in grid edges)
    poses = np.asarray(r.final_poses, dtype=float)[:, :2] / l
    order = {rid: k for k, rid in enumerate(r.final_ids)}
    residual = sum(md(a.wp, a.T) + abs(poses[order[a.id], 0] - a.wp[0]) + abs(poses[order[a.id], 1] - a.wp[1])
                   for a in made)
    opt, rand = costs(starts, sorted(goals.cells))
    travelled = res["distance"] / l
    return {"n": n, "seed": seed, "reading": reading or "reference", "params": params or {},
            "status": r.status, "formed_s": None if res["formed_step"] is None else round(res["formed_step"] * p.dt, 1),
            "travelled": round(travelled, 2), "optimum": int(opt), "random_assignment": round(rand, 1),
            "ratio": round(travelled / opt, 3), "initial": c["initial"], "swaps": c["swaps"],
            "duplicates": c["duplicates"], "residual": round(float(residual), 2),
            "initial_duplicated_agents": n - len({a.initial_goal for a in made}),
            "dup_changes": c["dup_changes"], "dup_same_goal": c["dup_same"],
            "half_swaps": c["server_ok"] - c["client_ok"], "swaps_done": c["client_ok"],
            "begun_reduce": c["begun_reduce"], "begun_equal": c["begun_equal"],
            "in_handshake": round(c["ticks_in_handshake"] / max(c["ticks"], 1), 3),
            "cpu_s": round(time.process_time() - t0, 1)}


# -- idealised centralized swapping -------------------------------------------------------------

def _swap_pass(cost, pairs, a, rng) -> bool:
    """One pass over ``pairs`` (i, j) in a seeded random order, applying every improving swap of
    the assignment ``a`` (agent -> goal index) under ``cost(i, goal)``; True if any."""
    changed = False
    for k in rng.permutation(len(pairs)):
        i, j = pairs[k]
        if cost(i, a[i]) + cost(j, a[j]) > cost(i, a[j]) + cost(j, a[i]):
            a[i], a[j] = a[j], a[i]
            changed = True
    return changed


def _pairs_within(P, R: float):
    E = ((P[:, None, :] - P[None, :, :]) ** 2).sum(-1)
    I, J = np.nonzero(np.triu(E <= R * R + 1e-9, 1))
    return list(zip(I.tolist(), J.tolist()))


def static_swaps(starts, goals, a0, rng, R: float = R_CELLS) -> int:
    """Improving swaps between agents within ``R`` at their start positions until none; the cost."""
    S, G = np.asarray(starts), np.asarray(goals)
    D = np.abs(S[:, None, :] - G[None, :, :]).sum(-1)
    a = np.array(a0)
    pairs = _pairs_within(S, R)
    while _swap_pass(lambda i, g: D[i, g], pairs, a, rng):
        pass
    return int(D[np.arange(len(a)), a].sum())


def dynamic_swaps(starts, goals, a0, rng, R: float = R_CELLS) -> int:
    """Every round: improving swaps within ``R`` at the current positions until none, then every
    agent one greedy step (x first; agents pass through each other); the distance travelled."""
    P, G = np.array(starts), np.asarray(goals)
    a = np.array(a0)
    travelled = 0
    while True:
        pairs = _pairs_within(P, R)
        while _swap_pass(lambda i, g: abs(P[i, 0] - G[g, 0]) + abs(P[i, 1] - G[g, 1]), pairs, a, rng):
            pass
        d = G[a] - P
        if not d.any():
            return travelled
        step = np.zeros_like(P)
        mx = d[:, 0] != 0
        step[mx, 0] = np.sign(d[mx, 0])
        step[~mx, 1] = np.sign(d[~mx, 1])
        P = P + step
        travelled += int(np.abs(step).sum())


def bounds(n: int, seed: int, reps: int = 3, arena: int = ARENA, dynamic: bool = True) -> dict:
    """The optimum, the random assignment's expected cost and the idealised swap processes' costs
    (mean over ``reps`` random initial permutations) for Fig. 10's instance (n, seed)."""
    goals, starts = instance(n, seed, arena)
    G = sorted(goals.cells)
    opt, rand = costs(starts, G)
    S, Ga = np.array(starts), np.array(G)
    rng = np.random.default_rng([n, seed, 4])
    st, dy = [], []
    for _ in range(reps):
        a0 = rng.permutation(n)
        st.append(static_swaps(S, Ga, a0, rng))
        if dynamic:
            dy.append(dynamic_swaps(S, Ga, a0, rng))
    out = {"n": n, "seed": seed, "arena": arena, "optimum": int(opt),
           "mean_neighbours": round(2 * len(_pairs_within(S, R_CELLS)) / n, 2),
           "random_over_opt": round(rand / opt, 3), "static_over_opt": round(float(np.mean(st)) / opt, 3)}
    if dynamic:
        out["dynamic_over_opt"] = round(float(np.mean(dy)) / opt, 3)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("decompose")
    d.add_argument("--n", type=int, required=True)
    d.add_argument("--seeds", default="0")
    d.add_argument("--reading", default="")
    d.add_argument("--params", default="{}")
    b = sub.add_parser("bounds")
    b.add_argument("--sizes", default="16,64,144,256,529")
    b.add_argument("--seeds", default="0,1,2")
    b.add_argument("--arena", type=int, default=ARENA)
    b.add_argument("--no-dynamic", action="store_true")
    args = ap.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    if args.cmd == "decompose":
        for s in seeds:
            print(json.dumps(decompose(args.n, s, args.reading, json.loads(args.params))), flush=True)
    else:
        for n in (int(x) for x in args.sizes.split(",")):
            for s in seeds:
                print(json.dumps(bounds(n, s, arena=args.arena, dynamic=not args.no_dynamic)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
