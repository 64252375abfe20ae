"""Wang & Rubenstein 2020 (004): shape formation by local task swapping, followed line by line.

The paper (004_004a3703645971e3.txt) runs three threads on every agent
(Sec. III-C); here they are one controller that the engine asks once per
clock tick:

* **Algorithm 2, main component** (:meth:`Wang2020Controller._main`): at a
  waypoint, pick ``next_step`` greedily (lines 9-14, surroundings in the
  printed order W, S, E, N), run the hop-count gradient (lines 15-24), raise
  ``wait_flag`` when a message in ``msg_buff`` claims ``next_step`` (line 26)
  or a lexically larger agent wants it too (line 28), and move only when no
  flag is raised and the agent has waited more than ``Delta t`` (line 30).
  The move (line 32) blocks the loop until the agent arrives; ``last_check``
  is reset on arrival (line 33).
* **Algorithm 3, broadcast** (:class:`WangMsg`): ``{p, wp, next_step, T,
  q_u, hop}`` plus the handshake fields and the shape-complete count; the
  engine sends the last decided message at ``f_comm`` (``broadcast_every``).
* **Algorithm 4, goal manager** (:meth:`Wang2020Controller._goal_manager`),
  for every message received: same goal and ``p_j > p_i`` -> a new goal,
  ``q_u`` with probability 0.9 and a random element of Q with 0.1 (lines
  3-10); a swap that reduces the pairwise Manhattan cost (line 11), or one
  that leaves it equal with probability beta (line 16), runs the 2-way
  handshake of Sec. III-A (client: the lexically smaller agent, sends a
  request once and waits for the ACK; server: waits for its intended peer's
  request, takes the client's goal on receiving it and answers with an ACK
  carrying its old goal; anyone else's request gets a negative ACK).  The
  request is a point-to-point exchange of its own, answered within the tick
  as Sec. II-A c) and e) assume (lossless links, negligible latency): the
  tick has two phases, the goal manager (:meth:`Wang2020Controller.requests`)
  and, after the engine's exchanges, Algorithm 2 and the broadcast
  (:meth:`Wang2020Controller.step`), so a swap is atomic and done before
  either agent moves on it.  Reading "1", where request and
  ACK ride in the broadcasts, is :class:`Wang2020BroadcastHandshake`.
* **Shape complete** (Sec. III-B): an agent whose hop-count exceeds the
  number of agents knows no anchor is left; it says so in its messages,
  every agent that hears it does the same, and then forms the next shape if
  one is given (Fig. 9: "N" then "U"), restarting Algorithm 2's lines 2-7.

Every ambiguity and its reading is in docs/decisions.md, "Wang & Rubenstein
2020 (issue 15)"; docs/wang2020.md describes the implementation.

Examples
--------
>>> from swarmproof.reference_impl.engine import simulate
>>> from swarmproof.models.targets import resolve_target
>>> from swarmproof.models.trace import InitialConfiguration
>>> shape = resolve_target("shape:letter-l")
>>> cells = [(-2, 0), (-1, 0), (-2, 1), (-1, 1), (-2, 2)]
>>> init = InitialConfiguration([1, 2, 3, 4, 5], [[0.2 * x, 0.2 * y, 0] for x, y in cells])
>>> alg = Wang2020()
>>> r = simulate(alg, shape, init, alg.default_params(range=0.6, n=5), seed=0)
>>> r.status, shape.satisfied(r.final_ids, r.final_poses).status
('finished', 'held')
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from swarmproof.invariants.algorithm_invariants import Invariant
from swarmproof.reference_impl.protocol import (Assumption, Command, ExhaustiveCell, Observation, Params, ParamSpec,
                                               RobotModel, VerifyPlan)

__all__ = ["Wang2020", "Wang2020Controller", "Wang2020BroadcastHandshake", "BroadcastHandshakeController", "WangMsg",
           "manhattan", "lex_greater", "default_params", "J1", "J2", "INVARIANT_NAMES", "window_bound", "speed_range", "speed_buffer_bound"]

#: Alg. 2 lines 9 and 11: the surroundings in the printed order (x - l, y), (x, y - l), (x + l, y), (x, y + l).
SURROUNDINGS = ((-1, 0), (0, -1), (1, 0), (0, 1))
_EPS = 1e-9


def manhattan(a, b) -> int:
    """Manhattan distance between two cells, in grid edges (004 Sec. III-A, IV-B).

    >>> manhattan((0, 0), (2, -3))
    5
    """
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def lex_greater(p, q) -> bool:
    """``p > q`` in the lexicographic order of 004 Sec. II-B: ``p.x > q.x``, or equal x and ``p.y > q.y``.

    >>> lex_greater((0.2, 0.0), (0.0, 5.0)), lex_greater((0.0, 0.4), (0.0, 0.2)), lex_greater((0, 0), (0, 0))
    (True, True, False)
    """
    return (p[0], p[1]) > (q[0], q[1])


@dataclass(frozen=True)
class WangMsg:
    """004 Alg. 3 line 2: ``msg = {p, wp, next_step, T, q_u, hop}``, and what the handshake and
    shape-complete detection need (Sec. III-A, III-B).

    Cells are integer ``(i, j)`` of the engine's grid (position ``l * (i, j)``).

    Attributes
    ----------
    p : (float, float)
        The agent's position when it decided (the priority of Alg. 2 line 28).
    wp, next_step, T, q_u : (int, int)
        Claimed waypoint, next waypoint, goal, candidate goal.
    hop : int or None
        Hop-count; None stands for infinity (Alg. 2 line 2).
    completed : int
        How many shapes this agent knows to be complete (Sec. III-B; its shape
        index is ``min(completed, shapes - 1)``).
    request : (server id, seq, client goal) or None
        A client's handshake request (Sec. III-A).
    ack : (client id, seq, server's old goal) or None
        A server's ACK.
    """

    p: tuple
    wp: tuple
    next_step: tuple
    T: tuple
    q_u: tuple
    hop: int | None
    completed: int = 0
    request: tuple | None = None
    ack: tuple | None = None


@dataclass
class _Handshake:
    role: str            # "client" | "server"
    peer: int
    seq: int             # the client's request number (server: None until the request arrives)
    deadline: float      # local clock
    goal: tuple          # this agent's goal when the handshake began


class Wang2020Controller:
    """One agent of 004 (Algorithms 2-4); see the module docstring.

    ``shapes`` is a tuple of goal sets (sorted tuples of engine cells): the
    first is formed, then the next once it is complete (Fig. 9).
    """

    def __init__(self, robot_id: int, params: Params, shapes, rng: np.random.Generator) -> None:
        ex = params.extra
        self.id = int(robot_id)
        self.rng = rng
        self.l = float(ex.get("grid_spacing", 0.2))
        self.shapes = tuple(tuple(sorted(s)) for s in shapes)
        self.shape_sets = tuple(frozenset(s) for s in self.shapes)
        self.boxes = tuple((min(i for i, _ in s), min(j for _, j in s), max(i for i, _ in s),
                            max(j for _, j in s)) for s in self.shapes)
        self.delta_t = float(delta_t_of(params))
        self.beta = float(ex.get("beta", 0.5))
        self.p_random = float(ex.get("p_random", 0.1))
        self.timeout = float(ex.get("handshake_timeout", 3.0 * self.delta_t))
        self._last = len(self.shapes) - 1
        self.completed = 0
        self.shape = 0                   # index of the shape being formed (the last once all are complete)
        self.started = False
        self.buff: deque = deque()       # (receipt clock, sender, WangMsg): msg_buff (Alg. 2 line 15)
        self._senders: dict = {}         # sender -> its messages in msg_buff
        self._heard_cache: tuple | None = ()
        self.hs: _Handshake | None = None
        self.seq = 0
        self._send: int | None = None    # the request number to send in this tick's exchange
        self._prepared = None            # the Observation requests() ran the first part of the tick for
        self.ack: tuple | None = None    # (client, seq, old goal, until): the variant's ACK in its broadcasts
        self.moving = False
        self.p = (0.0, 0.0)
        self.cell = self.wp = self.next_step = None     # set by the first tick (Alg. 2 lines 1, 5)
        self.hop = math.inf
        self.T = self.q_u = None
        self.last_check = 0.0
        self.waited_at_departure = 0.0
        self.now = 0.0
        self.swaps = 0                   # successful handshakes (either role)
        self.took: tuple | None = None   # the last goal taken in a handshake: (role, peer, seq)
        # lines 26/28 inline unless a subclass redefines them (mutation tests)
        self._plain = (type(self).occupied is Wang2020Controller.occupied
                       and type(self).yields_to is Wang2020Controller.yields_to)

    # -- shape bookkeeping ------------------------------------------------------------

    @property
    def Q(self) -> tuple:
        return self.shapes[self.shape]

    def _random_goal(self) -> tuple:
        """A uniformly random element of Q (Alg. 2 lines 3-4, Alg. 4 line 9), from the agent's rng."""
        return self.Q[int(self.rng.integers(len(self.Q)))]

    def _begin_shape(self, now: float) -> None:
        """004 Alg. 2 lines 2-7 (the per-shape initialisation): hop = inf, q_u and T random in Q,
        next_step = wp, last_check = clock()."""
        self.hop = math.inf
        self.q_u = self._random_goal()          # line 3
        self.T = self._random_goal()            # line 4
        self.next_step = self.wp                # line 5
        self.last_check = now                   # line 7
        self.hs = None
        self.ack = None

    def _switch(self, now: float) -> None:
        """Sec. III-B / Fig. 9: the current shape is complete; form the next one, if any."""
        self.completed += 1
        self.shape = min(self.completed, len(self.shapes) - 1)
        if self.completed < len(self.shapes):
            self._begin_shape(now)

    # -- the tick -----------------------------------------------------------------------

    def requests(self, obs: Observation) -> tuple:
        """The first part of the tick (the engine's two-phase step, ``Controller.requests``): the
        arrival, the timeouts and the goal manager on every message received (Alg. 4); returns
        the client's request if a handshake began (Sec. III-A), which the engine answers before
        any agent's :meth:`step` -- the goal manager's handshake completes before the main
        component acts, as negligible latency (Sec. II-A e) has it."""
        self._tick_messages(obs)
        self._prepared = obs
        return self._requests()

    def step(self, obs: Observation) -> Command:
        """The tick: :meth:`requests`' part unless the engine ran it for ``obs`` already (called
        alone, a handshake's request is never sent), then Algorithm 2 and the broadcast."""
        if self._prepared is not obs:
            self._tick_messages(obs)
            self._send = None
        self._prepared = None
        now = self.now
        move = None if self.moving else self._main(now)
        return Command(message=self.message(), move=move)

    def _tick_messages(self, obs: Observation) -> None:
        clock = obs.clock
        now = float(clock) if clock is not None else float(obs.step)
        self.now = now
        x, y = obs.own_pose.tolist()[:2]
        x, y = float(x), float(y)
        self.p = (x, y)
        l = self.l
        c = (int(round(x / l)), int(round(y / l)))
        at_cell = abs(x - c[0] * l) <= _EPS * l and abs(y - c[1] * l) <= _EPS * l
        if not self.started:                    # Alg. 2 line 1: wp <- current waypoint
            self.started = True
            self.cell = self.wp = c
            self._begin_shape(now)
        if self.moving and at_cell and c == self.wp:
            self.moving = False                 # line 32 returns: the agent arrived
            self.cell = c
            self.last_check = now               # line 33
        # The timeouts first, then one pass over the tick's messages: buffer each and run the
        # goal manager on it.  Alg. 4 reads neither msg_buff nor anything buffering changes, so
        # this equals buffering all, expiring old ones, then running Alg. 4 on each in order.
        if self.hs is not None and now > self.hs.deadline:
            self.hs = None                      # handshake timeout (Sec. III-A)
        if self.ack is not None and now > self.ack[3]:
            self.ack = None
        last = self._last
        buff = self.buff
        append = buff.append
        senders = self._senders
        gm = self._goal_manager
        for s, m in obs.inbox:
            if not isinstance(m, WangMsg):
                continue
            mc = m.completed
            append((now, s, m, mc if mc < last else last))
            k = senders.get(s)
            if k is None:
                senders[s] = 1
                self._heard_cache = None
            else:
                senders[s] = k + 1
            gm(now, s, m)                       # Alg. 4: every message received
        cutoff = now - self.delta_t            # msg_buff: received since clock() - Delta t
        while buff and buff[0][0] < cutoff:
            s = buff.popleft()[1]
            k = senders[s] - 1
            if k:
                senders[s] = k
            else:
                del senders[s]
                self._heard_cache = None

    # -- Algorithm 2 ----------------------------------------------------------------------

    def _greedy_next(self) -> tuple:
        """004 Alg. 2 lines 9-14: the first of the surroundings that reduces the Manhattan
        distance to T; none (the agent is at its goal) -> the current waypoint (Sec. III-A's
        "wait"; docs/decisions.md).

        (Hot path: with W, S, E, N in that order, the first that reduces the distance is W if
        T is to the west, else S if T is to the south, else E, else N.)"""
        wx, wy = self.wp
        tx, ty = self.T
        if tx < wx:
            return (wx - 1, wy)
        if ty < wy:
            return (wx, wy - 1)
        if tx > wx:
            return (wx + 1, wy)
        if ty > wy:
            return (wx, wy + 1)
        return self.wp

    def _gradient(self) -> None:
        """004 Alg. 2 lines 15-24 over this shape's messages in msg_buff.

        (Hot path: the goals held in msg_buff are collected only when a surrounding waypoint is
        in Q, the only case lines 21-22 read them.)"""
        shape = self.shape
        best = None
        low = math.inf
        for e in self.buff:
            if e[3] != shape:
                continue
            m = e[2]
            h = m.hop
            if best is None or (h is not None and h < low):
                best = m                                                        # line 18 (first of ties)
                low = math.inf if h is None else h
        if best is None:
            return
        self.hop = math.inf if best.hop is None else 1 + best.hop               # line 19
        self.q_u = best.q_u                                                     # line 20
        Q = self.shape_sets[shape]
        wx, wy = self.wp
        near = [i for i in ((wx - 1, wy), (wx, wy - 1), (wx + 1, wy), (wx, wy + 1)) if i in Q]
        if not near:
            return
        held = {e[2].T for e in self.buff if e[3] == shape}
        for i in near:                                                          # lines 21-24
            if i not in held:
                self.q_u, self.hop = i, 0
                break

    def occupied(self, m: WangMsg) -> bool:
        """004 Alg. 2 line 26: ``i.wp == next_step`` (next_step is occupied)."""
        return m.wp == self.next_step

    def yields_to(self, m: WangMsg) -> bool:
        """004 Alg. 2 line 28: ``i.next_step == next_step and i.p > p`` (a lexically larger agent
        intends to go to the same waypoint)."""
        return m.next_step == self.next_step and lex_greater(m.p, self.p)

    def _main(self, now: float):
        """One pass of 004 Alg. 2's loop (lines 9-35) at a waypoint; returns the engine move or None."""
        self.next_step = self._greedy_next()                                   # lines 9-14
        self._gradient()                                                        # lines 15-24
        if self.completed < len(self.shapes) and self.hop != math.inf and self.hop > len(self.Q):  # III-B
            self._switch(now)
            self.next_step = self._greedy_next()
        if self._plain:                                                         # lines 25-29
            ns, p = self.next_step, self.p
            wait_flag = False
            for e in self.buff:
                m = e[2]
                if m.wp == ns or (m.next_step == ns and m.p > p):
                    wait_flag = True
                    break
        else:
            wait_flag = any(self.occupied(m) or self.yields_to(m) for _, _, m, _ in self.buff)
        if not wait_flag and now - self.last_check > self.delta_t:             # line 30
            target = self.next_step
            if target == self.wp:
                self.last_check = now                                           # lines 31-33, no move
                return None
            self.wp = target                                                    # line 31
            self.moving = True                                                  # line 32 (blocks)
            self.waited_at_departure = float(now - self.last_check)             # premise monitor grid_waited
            return (target[0] - self.cell[0], target[1] - self.cell[1])
        return None                                                             # line 35

    # -- Algorithm 4 -------------------------------------------------------------------

    def _goal_manager(self, now: float, sender: int, m: WangMsg) -> None:
        """004 Alg. 4 for one received message, with the handshake of Sec. III-A.

        (Hot path: ``manhattan`` and ``lex_greater`` are written out inline; ``m.p > self.p``
        compares two ``(x, y)`` tuples, which is :func:`lex_greater`.)"""
        mc = m.completed
        while mc > self.completed:                                              # Sec. III-B propagation
            self._switch(now)
        if (mc if mc < self._last else self._last) != self.shape:
            return                                                              # another shape's goals
        if self.hs is not None:
            return                                                              # blocked in a handshake
        T = self.T
        mT = m.T
        if mT == T and m.p > self.p:                                            # lines 3-5
            T = self.T = self.select_new_goal()                                 # lines 6-9
            self.last_check = now                                               # lines 7, 10
        (wx, wy), (mx, my) = self.wp, m.wp
        now_cost = abs(wx - T[0]) + abs(wy - T[1]) + abs(mx - mT[0]) + abs(my - mT[1])
        swap_cost = abs(wx - mT[0]) + abs(wy - mT[1]) + abs(mx - T[0]) + abs(my - T[1])
        if swap_cost < now_cost:                                                # line 11
            self._begin_handshake(now, sender, m)                               # line 12
        elif swap_cost == now_cost and self.rng.random() < self.beta:           # lines 16-17
            self._begin_handshake(now, sender, m)                               # line 18

    def select_new_goal(self) -> tuple:
        """004 Alg. 4 lines 6-9: ``rand(0, 1) > 0.1`` -> q_u (gradient-based selector, Sec. III-B2),
        else a random element of Q (random selector, Sec. III-B1); ``p_random`` sets the 0.1
        (1: random only, 0: gradient only)."""
        if self.rng.random() > self.p_random:
            return self.q_u
        return self._random_goal()

    def _begin_handshake(self, now: float, peer: int, m: WangMsg) -> None:
        """Sec. III-A: client when the peer is lexically larger (it sends its request once, in this
        tick's exchange), else server (it waits for its peer's request until its timeout)."""
        if lex_greater(m.p, self.p):
            self.seq += 1
            self.hs = _Handshake("client", int(peer), self.seq, now + self.timeout, self.T)
            self._send = self.seq
        else:
            self.hs = _Handshake("server", int(peer), -1, now + self.timeout, self.T)

    # -- the 2-way handshake as an exchange of its own (Sec. III-A, II-A c and e) -------------

    def _requests(self) -> tuple:
        """The client's request, sent once, point to point: ``((server, (seq, the client's
        goal)),)``; nothing when no handshake began this tick or it already ended (a shape
        switch later in the goal manager)."""
        seq, self._send = self._send, None
        hs = self.hs
        if seq is None or hs is None or hs.role != "client" or hs.seq != seq:
            return ()
        return ((hs.peer, (hs.seq, hs.goal)),)

    def answer(self, sender: int, payload, clock: float):
        """Server side, within the tick the request was sent (negligible latency, II-A e): from
        its intended peer while it waits -> take the client's goal and ACK with its old one
        ``("ack", seq, old goal)``; from anyone else -> ``("nack", seq)`` (Sec. III-A: "answer the
        requests from these agents with a negative ACK"; docs/decisions.md)."""
        seq, goal = int(payload[0]), tuple(payload[1])
        hs = self.hs
        if hs is None or hs.role != "server" or hs.peer != sender or clock > hs.deadline:
            return ("nack", seq)
        old = self.T
        self.T = goal
        self.last_check = float(clock)                                          # Alg. 4 line 21
        self.hs = None
        self.swaps += 1
        self.took = ("server", int(sender), seq)
        return ("ack", seq, old)

    def on_reply(self, peer: int, payload, reply, clock: float) -> None:
        """Client side: the ACK of its waiting request -> take the server's old goal (Sec. III-A:
        "only after receiving the ACK"); a NACK releases it at once.  A reply after its timeout
        (possible only under a delay fault) finds it no longer waiting and is ignored."""
        hs = self.hs
        if hs is None or hs.role != "client" or hs.peer != peer or int(reply[1]) != hs.seq or clock > hs.deadline:
            return
        self.hs = None
        if reply[0] == "ack":
            self.T = tuple(reply[2])
            self.last_check = float(clock)                                      # Alg. 4 line 15/21
            self.swaps += 1
            self.took = ("client", int(peer), hs.seq)

    # -- Algorithm 3 and the state ---------------------------------------------------------

    def message(self) -> WangMsg:
        """004 Alg. 3 line 2 (the handshake is an exchange of its own: no request or ACK field)."""
        return WangMsg(self.p, self.wp, self.next_step, self.T, self.q_u,
                       None if self.hop == math.inf else int(self.hop), self.completed, None, None)

    def _heard(self) -> tuple:
        """The senders in msg_buff, sorted (kept as a count per sender as msg_buff changes)."""
        h = self._heard_cache
        if h is None:
            h = self._heard_cache = tuple(sorted(self._senders))
        return h

    def state(self):
        """The keys other monitors read: ``cell`` (the waypoint the agent is at, or left),
        ``next`` (the waypoint it moves to, or its next_step while waiting; None at its goal),
        ``goal``, ``priority`` (its position as Alg. 2 line 28 compares it), ``wp``,
        ``moving``, ``shape``, the handshake and the timing premises, and ``took``: the last
        goal taken in a handshake, ``(role, peer, seq)`` (the ``pairwise_swap`` invariant)."""
        nxt = self.wp if self.moving else (None if self.next_step == self.wp else self.next_step)
        if not self.started:
            return (("cell", None), ("next", None), ("goal", None), ("priority", None), ("wp", None),
                    ("moving", False), ("shape", 0), ("completed", 0), ("done", False), ("hop", None),
                    ("q_u", None), ("handshake", None), ("ack", None), ("waited", 0.0), ("window", self.delta_t),
                    ("heard", ()),
                    ("n_goals", len(self.Q)), ("shape_box", self.boxes[0]), ("spacing", self.l), ("took", None))
        hs = None if self.hs is None else (self.hs.role, self.hs.peer, self.hs.seq)
        return (("cell", self.cell), ("next", nxt), ("goal", self.T), ("priority", self.p),
                ("wp", self.wp), ("moving", self.moving), ("shape", self.shape),
                ("completed", self.completed), ("done", self.completed >= len(self.shapes)),
                ("hop", None if self.hop == math.inf else int(self.hop)), ("q_u", self.q_u),
                ("handshake", hs), ("ack", None if self.ack is None else self.ack[:3]),
                ("waited", self.waited_at_departure), ("window", float(self.delta_t)),
                ("heard", self._heard()),
                ("n_goals", len(self.Q)), ("shape_box", self.boxes[self.shape]), ("spacing", self.l),
                ("took", self.took))


class BroadcastHandshakeController(Wang2020Controller):
    """:class:`Wang2020Controller` with the 2-way handshake carried by the broadcasts (reading "1"
    of ``wang2020``, swarmproof 0.2.0's default; :class:`Wang2020BroadcastHandshake`).

    The client's request ``(server, seq, client goal)`` rides in every broadcast of the client
    until the ACK or its timeout; the server takes the client's goal on the first request of its
    intended peer and answers with ``(client, seq, old goal)`` in its broadcasts for ``ack_hold``;
    requests of other agents get no answer.  Each direction waits for the sender's next broadcast
    and arrives a tick later, so the exchange takes rounds: latency the paper assumes away (004
    Sec. II-A e).  A client whose timeout ends before the ACK keeps its goal while the server
    has already taken it (a "half swap": J2 rises, Lemma IV-B.2's premise of an atomic swap is
    gone).
    """

    #: one-phase ticks: the engine never asks this controller for exchanges (``step`` alone drops
    #: the request number a client's handshake set: its request rides in :meth:`message`)
    requests = None

    def __init__(self, robot_id: int, params: Params, shapes, rng: np.random.Generator) -> None:
        super().__init__(robot_id, params, shapes, rng)
        self.ack_hold = float(params.extra.get("ack_hold", self.delta_t))
        self.answered: set = set()       # (client, seq) requests this server has answered

    def _goal_manager(self, now: float, sender: int, m: WangMsg) -> None:
        """The request or ACK addressed to this agent first, then 004 Alg. 4."""
        if m.request is not None and m.request[0] == self.id:
            self._on_request(now, sender, m.request)
        if m.ack is not None and m.ack[0] == self.id:
            self._on_ack(now, sender, m.ack)
        Wang2020Controller._goal_manager(self, now, sender, m)

    def _on_request(self, now: float, sender: int, req: tuple) -> None:
        """Server side: a request from its intended peer -> take the client's goal and ACK with the
        old one; from anyone else -> no answer (the client times out)."""
        hs = self.hs
        key = (int(sender), int(req[1]))
        if hs is None or hs.role != "server" or hs.peer != sender or key in self.answered:
            return
        old = self.T
        self.T = tuple(req[2])
        self.last_check = now                                                   # Alg. 4 line 21
        self.ack = (int(sender), int(req[1]), old, now + self.ack_hold)
        self.answered.add(key)
        self.hs = None
        self.swaps += 1
        self.took = ("server", int(sender), int(req[1]))

    def _on_ack(self, now: float, sender: int, ack: tuple) -> None:
        """Client side: the ACK of the request it is waiting on -> take the server's old goal."""
        hs = self.hs
        if hs is None or hs.role != "client" or hs.peer != sender or int(ack[1]) != hs.seq:
            return
        self.T = tuple(ack[2])
        self.last_check = now                                                   # Alg. 4 line 15/21
        self.hs = None
        self.swaps += 1
        self.took = ("client", int(sender), hs.seq)

    def message(self) -> WangMsg:
        """004 Alg. 3 line 2, with the handshake fields."""
        req = None
        if self.hs is not None and self.hs.role == "client":
            req = (self.hs.peer, self.hs.seq, self.hs.goal)
        ack = None if self.ack is None else self.ack[:3]
        return WangMsg(self.p, self.wp, self.next_step, self.T, self.q_u,
                       None if self.hop == math.inf else int(self.hop), self.completed, req, ack)


# -- parameters and assumptions -------------------------------------------------------------

def delta_t_of(params: Params) -> float:
    """Delta t in local clock units: ``params.extra["delta_t"]``, else ``2 / f_comm`` (004 Alg. 2
    line 6) with ``1 / f_comm = broadcast_every`` local units.

    >>> delta_t_of(Params(range=0.6, extra={"broadcast_every": 2}))
    4.0
    """
    ex = params.extra
    if ex.get("delta_t") is not None:
        return float(ex["delta_t"])
    return 2.0 * float(ex.get("broadcast_every", 1.0))


_POS = dict(low=0, low_open=True)

#: The ``Params.extra`` keys 004's algorithm reads (``--param KEY=VALUE``), with their types and hard
#: ranges (a value outside is refused before any run); the paper's own bounds on them are assumptions
#: (``ASSUMPTIONS``), which ``--allow-violations`` may break.  The engine's grid and clock keys
#: (``speed_min``, ``speed_max``, ``clock_rate_max``) are declared by the engine (engine/parameters.py).
PARAMETERS = (
    ParamSpec("grid_spacing", float, 0.2, **_POS, meaning="l, the distance between waypoints, m (Sec. V-B3)"),
    ParamSpec("robot_radius", float, 0.05, **_POS, meaning="r, the robots' radius, m (Sec. V-A)"),
    ParamSpec("broadcast_every", float, 2.0, **_POS, meaning="1/f_comm, local time units between broadcasts"),
    ParamSpec("clock_rate_min", float, 1.0, **_POS, meaning="the slowest local clock's rate (Sec. II-A a)"),
    ParamSpec("clock_rate_max", float, 1.0, **_POS, meaning="the fastest local clock's rate"),
    ParamSpec("beta", float, 0.5, low=0, high=1, meaning="the probability of swapping at equal cost "
              "(Alg. 4 line 16; assumption beta_in_unit_interval: 0 < beta < 1)"),
    ParamSpec("p_random", float, 0.1, low=0, high=1, meaning="the probability of choosing a goal at random"),
    ParamSpec("delta_t", float, None, **_POS, meaning="Delta t, local time units; default 2/f_comm (Alg. 2 line 6)"),
    ParamSpec("handshake_timeout", float, None, **_POS, meaning="a handshake's timeout; default 3 Delta t"),
    ParamSpec("loss_repeats", int, 1, low=1, meaning="m, times a message is sent so every neighbour hears it "
              "(Sec. V-B3)"),
    ParamSpec("arena", object, "32x32", meaning="the arena starts are drawn in: SIDE or WxH waypoints (Sec. V-A)"),
    ParamSpec("then", object, (), meaning="shapes to form next, in order, each once the one before is detected "
              "complete: names or files, comma-separated, each scaled to the team (Fig. 9: N then U; "
              "simulate --then)"),
)

#: ``wang2020-broadcast-handshake`` reads one more: the default's ACK is an answer within the tick
#: and is held nowhere, so ``ack_hold`` on ``wang2020`` exits 2 (an undeclared key), not silently.
BROADCAST_HANDSHAKE_PARAMETERS = PARAMETERS + (
    ParamSpec("ack_hold", float, None, low=0, meaning="how long a server keeps its ACK in its broadcasts; "
              "default Delta t"),
)


def default_params(range: float = 0.6, n: int = 0) -> Params:
    """004's values and our choices (docs/decisions.md, "Wang & Rubenstein 2020").

    Paper: r = 0.05 m, R = 0.6 m, v = 0.05 m/s (Sec. V-A), l = 0.20 m (Sec. V-B3).  Ours: a
    step of dt = 0.5 s, f_comm = 1 Hz (``broadcast_every`` = 2 ticks), hence Delta t = 2 s
    = 4 ticks, equal clock rates (Sec. II-A a), beta = 0.5, handshake timeouts 3 Delta t.

    >>> p = default_params(0.6, 9)
    >>> p.v, p.dt, p.extra["grid_spacing"], p.extra["robot_radius"], delta_t_of(p)
    (0.05, 0.5, 0.2, 0.05, 4.0)
    """
    return Params(range=range, v=0.05, dt=0.5, extra={
        "grid_spacing": 0.2, "robot_radius": 0.05, "broadcast_every": 2.0, "clock_rate_min": 1.0,
        "clock_rate_max": 1.0, "beta": 0.5, "p_random": 0.1})


def _r(params) -> float:
    return float(params.extra.get("robot_radius", 0.05))


def _range_vs_radius(params: Params, n, ids):
    r = _r(params)
    if params.range >= 4 * math.sqrt(2) * r - 1e-12:
        return None
    return f"range={params.range!r} < 4*sqrt(2)*robot_radius={4 * math.sqrt(2) * r:.6g} (robot_radius={r!r})"


def _spacing_bounds(params: Params, n, ids):
    r, l = _r(params), float(params.extra.get("grid_spacing", 1.0))
    if 2 * math.sqrt(2) * r - 1e-12 <= l <= params.range / 2 + 1e-12:
        return None
    return (f"grid_spacing={l!r} is outside [2*sqrt(2)*robot_radius, range/2] = "
            f"[{2 * math.sqrt(2) * r:.6g}, {params.range / 2:.6g}]")


def speed_range(params: Params) -> tuple:
    """``(v_min, v_max)`` of the grid robots' speeds (m/s): ``params.extra["speed_min"]`` and
    ``["speed_max"]``, each defaulting to ``params.v`` (004 Sec. II-A d: one ``v_m``; Sec. V-B3:
    ``v_min <= v_m^i <= v_max``; the engine draws them, :func:`~swarmproof.reference_impl.engine.motion.grid_speeds`).

    Raises
    ------
    UsageError
        A value that is no finite number > 0 (the engine's check, named ``params.extra[key]``).

    >>> speed_range(default_params()), speed_range(Params(range=0.6, v=0.05, extra={"speed_min": 0.03}))
    ((0.05, 0.05), (0.03, 0.05))
    """
    from swarmproof.reference_impl.engine.motion import _speed_bound

    return _speed_bound(params, "speed_min"), _speed_bound(params, "speed_max")


def speed_buffer_bound(params: Params) -> float:
    """004 Sec. V-B3's least grid length for robots of speeds in ``[v_min, v_max]``:
    ``l >= 2 r sqrt(v_max^2 + v_min^2) / v_min`` (written ``2 r sqrt(1 + (v_max / v_min)^2)``, so
    that equal speeds give exactly Sec. III-A's ``2 sqrt(2) r``).  It is the orthogonal hand-over
    case; the collinear case, ``l >= 2 r v_max / v_min``, is never larger (docs/wang2020.md).

    >>> round(speed_buffer_bound(default_params()), 6), 2 * math.sqrt(2) * 0.05 == speed_buffer_bound(default_params())
    (0.141421, True)
    >>> round(speed_buffer_bound(Params(range=0.6, extra={"robot_radius": 0.05, "speed_min": 0.025, "speed_max": 0.05})), 6)
    0.223607
    """
    lo, hi = speed_range(params)
    return 2 * _r(params) * math.sqrt(1 + (hi / lo) ** 2)


def _speed_buffer(params: Params, n, ids):
    l = float(params.extra.get("grid_spacing", 1.0))
    need = speed_buffer_bound(params)
    if l >= need - 1e-12:
        return None
    lo, hi = speed_range(params)
    return (f"grid_spacing={l!r} < 2*robot_radius*sqrt(speed_max^2 + speed_min^2)/speed_min = {need:.6g} "
            f"(robot_radius={_r(params)!r}, speed_min={lo!r}, speed_max={hi!r})")


def _same_speed(params: Params, n, ids):
    lo, hi = speed_range(params)
    return None if lo == hi else f"speed_min={lo!r} != speed_max={hi!r}"


def _same_clock_rate(params: Params, n, ids):
    lo = float(params.extra.get("clock_rate_min", 1.0))
    hi = float(params.extra.get("clock_rate_max", lo))
    return None if lo == hi else f"clock_rate_min={lo!r} != clock_rate_max={hi!r}"


def window_bound(params: Params) -> float:
    """004 Sec. V-B3's least Delta t, in local clock units: ``(2 m / f_comm) (f_max / f_min)`` with
    ``1 / f_comm = broadcast_every``, ``m = loss_repeats`` (a message sent m times in a row reaches
    every neighbour; default 1, no loss) and the clock rates ``clock_rate_min`` / ``clock_rate_max``.

    >>> window_bound(default_params()), window_bound(Params(range=0.6, extra={"broadcast_every": 2,
    ...     "clock_rate_min": 1.0, "clock_rate_max": 2.0, "loss_repeats": 3}))
    (4.0, 24.0)
    """
    ex = params.extra
    every = float(ex.get("broadcast_every", 1.0))
    lo = float(ex.get("clock_rate_min", 1.0))
    hi = float(ex.get("clock_rate_max", lo))
    m = float(ex.get("loss_repeats", 1))
    return 2.0 * m * every * (hi / lo)


def _window(params: Params, n, ids):
    need = window_bound(params)
    dt = delta_t_of(params)
    ex = params.extra
    return None if dt >= need - 1e-12 else (
        f"delta_t={dt!r} < 2/f_comm * f_max/f_min * m = {need:.6g} (broadcast_every="
        f"{ex.get('broadcast_every', 1.0)!r}, loss_repeats={ex.get('loss_repeats', 1)!r}, clock_rate_min="
        f"{ex.get('clock_rate_min', 1.0)!r}, clock_rate_max={ex.get('clock_rate_max', ex.get('clock_rate_min', 1.0))!r})")


def _beta(params: Params, n, ids):
    b = params.extra.get("beta", 0.5)
    p = params.extra.get("p_random", 0.1)
    if not (isinstance(b, (int, float)) and 0 < b < 1):
        return f"beta={b!r} must be in (0, 1)"
    if not (isinstance(p, (int, float)) and 0 <= p <= 1):
        return f"p_random={p!r} must be in [0, 1]"
    return None


def _own_waypoint(params: Params, ids, poses):
    l = float(params.extra.get("grid_spacing", 1.0))
    xy = np.asarray(poses, dtype=float)[:, :2]
    cells = np.rint(xy / l)
    bad = np.flatnonzero(np.abs(xy - cells * l).max(axis=1) > 1e-9 * l) if len(xy) else []
    if len(bad):
        k = int(bad[0])
        return f"robot {ids[k] if ids else k} at ({xy[k, 0]:.6g}, {xy[k, 1]:.6g}) is not on a waypoint"
    seen = {}
    for k, c in enumerate(map(tuple, cells.astype(int).tolist())):
        if c in seen:
            return f"robots {ids[seen[c]] if ids else seen[c]} and {ids[k] if ids else k} start on waypoint {c}"
        seen[c] = k
    return None


def goal_cells(target, spacing: float) -> tuple:
    """The target's goal cells on the engine's grid (origin + spacing * (i, j) -> integer cells)."""
    ox, oy = (float(v) for v in getattr(target, "origin", (0.0, 0.0)))
    oi, oj = int(round(ox / spacing)), int(round(oy / spacing))
    return tuple(sorted((oi + i, oj + j) for i, j in target.cells))


def _target_on_grid(params: Params, n, target):
    if target is None or getattr(target, "cells", None) is None:
        return f"target={target!r} is not a goal set (004 Sec. II-C: Q on grid waypoints)"
    l = float(params.extra.get("grid_spacing", 1.0))
    ox, oy = (float(v) for v in getattr(target, "origin", (0.0, 0.0)))
    if abs(float(target.spacing) - l) > 1e-9 * l or any(abs(o / l - round(o / l)) > 1e-9 for o in (ox, oy)):
        return (f"target {target.name!r} spacing={target.spacing!r}, origin=({ox:g}, {oy:g}) is not on the "
                f"grid of grid_spacing={l!r}")
    return None


def _goal_count(params: Params, n, target):
    cells = getattr(target, "cells", None)
    if cells is None or len(cells) == n:
        return None
    return f"|Q|={len(cells)} goal cells of {getattr(target, 'name', '?')!r} but |A|=n={n} robots"


def _goal_connected(params: Params, n, target):
    cells = getattr(target, "cells", None)
    if not cells:
        return None
    cells = set(map(tuple, cells))
    start = min(cells)
    seen, todo = {start}, [start]
    while todo:
        i, j = todo.pop()
        for dx, dy in SURROUNDINGS:
            c = (i + dx, j + dy)
            if c in cells and c not in seen:
                seen.add(c)
                todo.append(c)
    if len(seen) == len(cells):
        return None
    return f"the goal set {getattr(target, 'name', '?')!r} is not 4-connected ({len(cells) - len(seen)} cells apart)"


ASSUMPTIONS = (
    Assumption("range_vs_radius", "R >= 4 sqrt(2) r", "004 Sec. II-A", _range_vs_radius),
    Assumption("grid_spacing_bounds", "2 sqrt(2) r <= l <= R / 2", "004 Sec. III-A", _spacing_bounds),
    Assumption("speed_buffer", "l >= 2 r sqrt(v_max^2 + v_min^2) / v_min (equal speeds: 2 sqrt(2) r, as "
               "grid_spacing_bounds)", "004 Sec. V-B3", _speed_buffer),
    Assumption("same_clock_frequency", "every agent has the same clock frequency (phases arbitrary)",
               "004 Sec. II-A a)", _same_clock_rate),
    Assumption("same_speed", "every agent has the same speed v_m on a grid edge", "004 Sec. II-A d)",
               _same_speed),
    Assumption("message_window", "Delta t >= (2 m / f_comm) (f_max / f_min) (m = 1, equal rates: 2 / f_comm)",
               "004 Alg. 2 line 6, Lemma IV-A.1, Sec. V-B3", _window),
    Assumption("beta_in_unit_interval", "0 < beta < 1", "004 Alg. 2 input, Alg. 4 line 16", _beta),
    Assumption("own_waypoint", "each agent starts on its own waypoint", "004 Theorems IV-A.1/IV-A.2",
               lambda p, n, ids: None, check_start=_own_waypoint),
    Assumption("goals_on_grid", "Q is a set of waypoints of the grid of spacing l", "004 Sec. II-B, III-A",
               lambda p, n, ids: None, check_target=_target_on_grid),
    Assumption("goal_count", "|Q| = |A|", "004 Sec. II-C", lambda p, n, ids: None, check_target=_goal_count),
    Assumption("goal_connected", "the target formation Q is connected", "004 Sec. II-C",
               lambda p, n, ids: None, check_target=_goal_connected),
)


# -- J1, J2 and the runtime invariants ----------------------------------------------------------

def _split(poses, states, l: float):
    """Per robot: ``(state dict, rest cell or None, edge (from, to) or None)``.  A robot whose pose
    is exactly on a waypoint rests there (pose, not its own word); one between waypoints is on the
    edge from its state's ``cell`` to its ``wp`` (the waypoint it claims, Alg. 2 line 31)."""
    xy = np.asarray(poses, dtype=float)[:, :2] / l
    cells = np.rint(xy)
    on = (np.abs(xy - cells).max(axis=1) <= 1e-9) if len(xy) else np.zeros(0, bool)
    out = []
    for k, st in enumerate(states):
        d = dict(st)
        if on[k]:
            out.append((d, (int(cells[k, 0]), int(cells[k, 1])), None))
        else:
            out.append((d, None, (tuple(d["cell"]), tuple(d["wp"]))))
    return out


def _j1(split) -> int:
    total = 0
    for d, rest, edge in split:
        total += manhattan(rest, d["goal"]) if rest is not None else 1 + manhattan(edge[1], d["goal"])
    return total


def J1(poses, states, l: float) -> int:
    """004 Sec. IV-B: J1 = sum of d_i, the number of grid edges agent i still has to traverse to its
    goal: ``|cell - T|_1`` at a waypoint; on an edge, 1 (the rest of it) + ``|wp - T|_1`` of its end.

    >>> st = lambda cell, wp, goal: (("cell", cell), ("wp", wp), ("goal", goal))
    >>> J1([[0.0, 0.0, 0], [0.3, 0.2, 0]], [st((0, 0), (0, 0), (2, 0)), st((1, 1), (2, 1), (0, 1))], 0.2)
    5
    """
    return _j1(_split(poses, states, l))


def J2(states) -> int:
    """004 Sec. IV-B: J2 = |A| - (the number of goals held by some agent).

    >>> J2([(("goal", (0, 0)),), (("goal", (0, 0)),), (("goal", (1, 0)),)])
    1
    """
    return len(states) - len({tuple(dict(s)["goal"]) for s in states})


class _Checks:
    """The runtime invariants of one run; the J checks remember the previous step, so every
    monitor gets fresh ones (``Wang2020().invariants``).  One frame per step is computed once."""

    def __init__(self) -> None:
        self.key = None
        self.frame = None
        self.prev = None          # (shape, J1, J2, goals, handshakes)
        self.mono = (None, (None, None))   # (frame key, (J2 message, J1 message)) of the last step judged
        self.c0 = None            # (shape, c_t0)
        self.pending: dict = {}   # (client, seq) -> (server, step): a server took its client's goal
        self.took_prev: dict = {}

    def _frame(self, t, ids, poses, states):
        key = (t, id(states), id(poses))
        if key != self.key:
            l = float(dict(states[0])["spacing"]) if states else 1.0
            split = _split(poses, states, l) if states else []
            started = all(d["goal"] is not None for d, _, _ in split)
            shapes = {d["shape"] for d, _, _ in split}
            shape = shapes.pop() if started and len(shapes) == 1 else None
            self.key, self.frame = key, (l, split, shape)
        return self.frame

    def vertex(self, t, ids, poses, states):
        """Constraint III-A.1 from poses and states: no agent moves to a waypoint where another
        stands, and no two agents move toward one waypoint."""
        _, split, _ = self._frame(t, ids, poses, states)
        rid = ids.tolist()
        rest = {c: r for r, (_, c, _) in zip(rid, split) if c is not None}
        dest = {}
        for r, (_, _, edge) in zip(rid, split):
            if edge is None:
                continue
            to = edge[1]
            if to in rest:
                return f"robot {r} moves to waypoint {to} where robot {rest[to]} stands"
            if to in dest:
                return f"robots {dest[to]} and {r} both move toward waypoint {to}"
            dest[to] = r
        return None

    def edge(self, t, ids, poses, states):
        """Constraint III-A.2: no two agents travel one edge in opposite directions."""
        _, split, _ = self._frame(t, ids, poses, states)
        seen = {}
        for r, (_, _, edge) in zip(ids.tolist(), split):
            if edge is None:
                continue
            if (edge[1], edge[0]) in seen:
                return (f"robots {seen[(edge[1], edge[0])]} and {r} travel the edge between {edge[1]} and "
                        f"{edge[0]} in opposite directions")
            seen[edge] = r
        return None

    def bounded(self, t, ids, poses, states):
        """Lemma IV-B.1: J2 <= |A| - 1 and J1 <= |A| c_t0 (c_t0: x plus y extent, in edges, of the
        smallest rectangle holding every agent and goal at the first step of the shape)."""
        if t == 0:
            self.c0 = None
        l, split, shape = self._frame(t, ids, poses, states)
        if shape is None:
            return None
        if self.c0 is None or self.c0[0] != shape:
            box = split[0][0]["shape_box"]
            xy = np.asarray(poses, dtype=float)[:, :2] / l
            xs = [box[0], box[2], float(xy[:, 0].min()), float(xy[:, 0].max())]
            ys = [box[1], box[3], float(xy[:, 1].min()), float(xy[:, 1].max())]
            self.c0 = (shape, (max(xs) - min(xs)) + (max(ys) - min(ys)))
        n = len(split)
        j1, j2 = _j1(split), n - len({d["goal"] for d, _, _ in split})
        if j2 > n - 1:
            return f"J2={j2} > |A| - 1 = {n - 1}"
        if j1 > n * self.c0[1] + 1e-9:
            return f"J1={j1} > |A| c_t0 = {n} x {self.c0[1]:g}"
        return None

    def _monotone(self, t, ids, poses, states):
        """Lemma IV-B.2 on one step, once per step for both of its statements: ``(J2 message,
        J1 message)``, each None when that statement held (within one shape)."""
        key = (t, id(states), id(poses))
        if self.mono[0] == key:
            return self.mono[1]
        if t == 0:
            self.prev = None
        _, split, shape = self._frame(t, ids, poses, states)
        out = (None, None)
        if shape is None:
            self.prev = None
        else:
            rid = ids.tolist()
            goals = {r: d["goal"] for r, (d, _, _) in zip(rid, split)}
            hs = {r: d["handshake"] for r, (d, _, _) in zip(rid, split)}
            j1, j2 = _j1(split), len(split) - len(set(goals.values()))
            prev, self.prev = self.prev, (shape, j1, j2, goals, hs)
            if prev is not None and prev[0] == shape and (j2 > prev[2] or (prev[2] == 0 == j2 and j1 > prev[1])):
                changed = ", ".join(f"robot {r}: {prev[3].get(r)} -> {g}" + (f" (handshake {prev[4].get(r)})"
                                                                            if prev[4].get(r) else "")
                                    for r, g in goals.items() if prev[3].get(r) != g)
                m2 = m1 = None
                if j2 > prev[2]:
                    lost = sorted(set(prev[3].values()) - set(goals.values()))
                    m2 = f"J2 rose from {prev[2]} to {j2}: goal(s) {lost} no longer held ({changed})"
                else:
                    m1 = f"J1 rose from {prev[1]} to {j1} while J2 = 0 ({changed or 'no goal changed'})"
                out = (m2, m1)
        self.mono = (key, out)
        return out

    def j2_monotone(self, t, ids, poses, states):
        """Lemma IV-B.2, first statement: J2 never rises (within one shape)."""
        return self._monotone(t, ids, poses, states)[0]

    def j1_monotone(self, t, ids, poses, states):
        """Lemma IV-B.2, second statement: J1 never rises while J2 = 0 (before and after the step)."""
        return self._monotone(t, ids, poses, states)[1]

    def pairwise(self, t, ids, poses, states):
        """Sec. III-A: "Only the pair of who successfully handshake with each other can swap the
        goal": a server that took its client's goal (state ``took``) is matched by the client taking
        the server's (its ``took``) before the client's handshake ends.  A client that stops
        waiting without it leaves a half swap."""
        if t == 0:
            self.pending, self.took_prev = {}, {}
        took, waiting = {}, {}
        for r, st in zip(ids.tolist(), states):
            d = dict(st)
            took[r], waiting[r] = d.get("took"), d.get("handshake")
        new = [tk + (r,) for r, tk in took.items() if tk is not None and tk != self.took_prev.get(r)]
        for role, peer, seq, r in sorted(new, key=lambda x: x[0] != "server"):    # servers first
            if role == "server":
                self.pending[(peer, seq)] = (r, int(t))
            else:
                self.pending.pop((r, seq), None)
        self.took_prev = took
        for (c, seq), (srv, t0) in sorted(self.pending.items()):
            if c not in waiting:
                del self.pending[(c, seq)]          # the client is gone (crashed): no swap to finish
            elif waiting[c] != ("client", srv, seq):
                del self.pending[(c, seq)]
                return (f"half swap: robot {srv} took robot {c}'s goal in step {t0} (handshake {seq}), but robot "
                        f"{c}'s handshake ended without taking robot {srv}'s")
        return None


INVARIANT_NAMES = ("constraint_vertex", "constraint_edge", "j_bounded", "j2_monotone", "j1_monotone",
                   "pairwise_swap")


def make_invariants() -> tuple:
    """Fresh :class:`Invariant` objects (the J checks remember the previous step); the grid
    spacing is read from the states (key ``spacing``)."""
    ch = _Checks()
    return (
        Invariant("constraint_vertex", "no agent moves to an occupied waypoint; no two agents move toward "
                  "one waypoint", "004 Constraint III-A.1, Theorem IV-A.1", ch.vertex),
        Invariant("constraint_edge", "no two agents travel one edge in opposite directions",
                  "004 Constraint III-A.2, Theorem IV-A.2", ch.edge),
        Invariant("j_bounded", "J2 <= |A| - 1 and J1 <= |A| c_t0", "004 Lemma IV-B.1", ch.bounded),
        Invariant("j2_monotone", "J2 never rises", "004 Lemma IV-B.2 (\"J2 is monotonically decreasing\")",
                  ch.j2_monotone),
        Invariant("j1_monotone", "J1 never rises while J2 = 0", "004 Lemma IV-B.2 (\"moreover, J1 is monotonically "
                  "decreasing if J2 equals zero\")", ch.j1_monotone),
        Invariant("pairwise_swap", "a goal taken in a handshake is swapped by both of the pair (no half swap)",
                  "004 Sec. III-A (\"Only the pair of who successfully handshake with each other can swap the goal\")",
                  ch.pairwise),
    )


# -- the algorithm ----------------------------------------------------------------------------

def _then_shape(name: str):
    """The goal set a ``then`` entry names: a bundled shape or a shape file, ``shape:`` optional."""
    from swarmproof.models.errors import InputFileError, UsageError
    from swarmproof.models.targets import resolve_target

    try:
        g = resolve_target(name, kind=None if ":" in name else "shape")
    except UsageError as exc:
        if isinstance(exc, InputFileError) and (exc.line is not None or exc.field):
            raise                        # a shape file's own error names its file, line and field
        raise UsageError(f"then={name!r}: {exc.message}", fix=exc.fix or "name a shape (swarmproof list "
                         "shapes) or a shape file, e.g. --then shape:letter-u") from None
    if getattr(g, "cells", None) is None:
        raise UsageError(f"then={name!r} is a {getattr(g, 'kind', type(g).__name__)} target, not a shape",
                         fix="wang2020 forms goal sets: e.g. --then shape:letter-u")
    return g


#: ``swarmproof verify``'s exhaustive rows (issue 33): 3 agents on the scaled letter L, collision and
#: the runtime invariants (J monotone, no swap) for every clock phase (Sec. II-A a: any phase) and,
#: with one deviation, every asynchronous interleaving besides; about 6 s of CPU.
WANG2020_EXHAUSTIVE = (ExhaustiveCell(("collision", "invariants"), ("clock_phase",), steps=40, deviations=3),
                       ExhaustiveCell(("collision", "invariants"), ("activate", "clock_phase"), steps=30,
                                      deviations=1))


class Wang2020:
    """Wang & Rubenstein 2020's shape formation by local task swapping (registry name
    ``wang2020``): grid waypoints, Alg. 2-4; see the module docstring.

    Parameters
    ----------
    then : GoalSet or sequence of GoalSet, optional
        Shapes to form after the run's target, in order, each once the previous one is
        detected complete (004 Fig. 9, Sec. V-B4: "N" then "U").
    """

    name = "wang2020"
    #: The controller-state fields the shared checkers may read (swarmproof.invariants.capabilities):
    #: none of a spanning tree (its monitors read their own keys).
    state_fields = ()
    #: The seed paper (docs/references.md) whose claims ``claims`` cites.
    paper = "004"
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).  "2" (0.3.0, issue 30): the handshake is an exchange of its own,
    #: answered within the tick (Sec. II-A c, e); reading "1" is ``wang2020-broadcast-handshake``.
    reading = "2"
    #: Assumptions of the paper this reading does not keep (none: it is the paper's model).
    departs_from = ()
    #: Invariant names of older swarmproofs (``explore --invariant`` says what they became).
    invariant_renames = {"j_monotone": "j2_monotone and j1_monotone in swarmproof 0.3.0 (one per statement of "
                                       "Lemma IV-B.2)"}
    model = RobotModel(sensing="global", communication="neighbors", motion="grid", clocks="async",
                       neighbor_rule="inclusive")
    assumptions = ASSUMPTIONS
    randomized = True
    controller_class = Wang2020Controller
    #: the controller :mod:`.fast` reproduces: the vectorised path refuses an algorithm whose
    #: ``controller_class`` is another (a subclass that swaps the controller)
    vectorised_controller = Wang2020Controller
    claims = {
        "collision": "004 Theorems IV-A.1/IV-A.2 with l >= 2 sqrt(2) r (Sec. III-A): discs never overlap",
        "invariants": "004 Constraints III-A.1/2 (Theorems IV-A.1/2), Lemmas IV-B.1/IV-B.2 (J1, J2), Sec. III-A "
                      "(pairwise swaps)",
        "formation": "004 Theorem IV-B.1 (J1, J2 -> 0 almost surely; exploration: held over what it ran)",
        "termination": "004 Theorem IV-B.1 with Sec. III-B shape-complete detection (almost surely)",
        "deadlock": "004 Sec. II-C, Lemma IV-B.4 (deadlock-free)",
        "completion_sound": "004 Sec. III-B: an agent whose hop-count exceeds |A| declares the shape complete "
                            "(no anchor left), and the news spreads",
    }
    own_end = "every agent knows the last shape complete: hop-count > |A| (004 Sec. III-B)"
    explore_targets = ("shape:letter-l", "shape:square-9")
    #: Its ``Params.extra`` keys (:data:`PARAMETERS`) and the kind of target it forms (a goal set, Sec. II-C).
    parameters = PARAMETERS
    target_kinds = ("shape",)
    #: The premises of the z3 lemmas (reference_impl/wang2020/lemmas.py) monitored on every step (the
    #: ``premises`` property), each from its lemma's definition: distinct priorities within R,
    #: waited longer than the window (invariants/premises.py).
    premise_monitors = ("grid_priorities", "grid_waited")
    #: Its own properties (:mod:`.properties`; premise monitors until issue 32, which no lemma states
    #: as a run reads them): claims and cells distinct and no edge swap at every moment (Thms.
    #: IV-A.1/IV-A.2's conclusions), every robot within R throughout a window heard (Sec. II-A),
    #: the grid length against Sec. III-A's and V-B3's bounds at the run's parameters.
    properties = ("grid_claims", "grid_heard", "grid_spacing")
    #: ``swarmproof prove``'s lemmas about it (004's Sec. IV-A and V-B3, the lemmas of
    #: reference_impl/wang2020/lemmas.py; ``swarmproof prove --algorithm wang2020``).
    lemmas = ("wang2020_time_normalisation", "wang2020_planner_vertex_one_moment",
              "wang2020_planner_edge_one_moment", "wang2020_lemma_iv_a_1", "wang2020_theorem_iv_a_2",
              "wang2020_separation_equal_speeds", "wang2020_speed_buffer_v_b3_cases", "wang2020_separation_speeds")
    # exploration rows: 100 examples each (a scenario is hundreds of asynchronous ticks; 300 would
    # add about 4 minutes to `swarmproof verify`, docs/wang2020.md)
    verify = VerifyPlan(targets=("shape:letter-l",), robots=5, seeds=(0, 1, 2), explore=True, rank=30,
                        more=(("shape:square-9", 9, (0, 1, 2)),), explore_max_examples=100,
                        explore_cost=44, exhaustive=WANG2020_EXHAUSTIVE)
    #: simulate's ``--then`` becomes ``params.extra["then"]`` (Fig. 9's "N" then "U"): in the run's
    #: parameters, so counterexample files, replay and campaigns carry it.
    options = ("then",)
    #: Its paper's experiments as seeded trials, for a campaign's ``experiment:`` cell
    #: (docs/campaigns.md): name -> ``module:qualname`` of an experiment function.  They run this
    #: class's default reading; a campaign takes experiments from the class that declares them only
    #: (a subclass, e.g. ``Wang2020BroadcastHandshake``, declares its own or has none).
    experiments = {"fig10": "swarmproof.reference_impl.wang2020.experiments:fig10_task"}

    def __init__(self, then=()) -> None:
        if then is None:
            then = ()
        elif getattr(then, "cells", None) is not None:
            then = (then,)
        self.then = tuple(then)
        for g in self.then:
            if getattr(g, "cells", None) is None:
                from swarmproof.models.errors import UsageError

                raise UsageError(f"then={g!r} is not a goal set", fix="pass GoalSet objects (shape targets)")

    @staticmethod
    def vectorised_simulate(*args, **kwargs):
        """The vectorised path (:func:`~swarmproof.reference_impl.wang2020.fast.simulate_fast`):
        ``engine.simulate``'s signature and the same trace bit for bit (tested), for the plain model;
        a run it does not cover is a ``UsageError`` saying why (``swarmproof simulate --vectorised``)."""
        from .fast import simulate_fast

        return simulate_fast(*args, **kwargs)

    @property
    def invariants(self) -> tuple:
        """Fresh runtime invariants (every access: a new J memory)."""
        return make_invariants()

    @property
    def completion_invariants(self) -> tuple:
        """The ``completion_sound`` property's invariant (Sec. III-B), fresh on every access
        (:mod:`.completion`; it reads the goal sets :meth:`controller` keeps)."""
        from .completion import completion_invariant

        return (completion_invariant(self),)

    @staticmethod
    def progress_measure(ids, poses, states) -> float:
        """The omniscient observer's goal measure for the ``oscillation`` property's no-progress rule
        (deadlock / livelock): ``-(J1 + J2)`` (004 Sec. IV-B; higher is closer, 0 once formed).
        Lemma IV-B.4 says the swarm is never stuck, Theorem IV-B.1 that J1 and J2 reach 0 almost
        surely; a window in which the best ``-(J1 + J2)`` so far does not rise is a stall.  Before
        every agent has chosen a goal (the start) the measure is ``-inf``.

        >>> st = lambda cell, goal: (("cell", cell), ("wp", cell), ("goal", goal), ("spacing", 0.2))
        >>> Wang2020.progress_measure([1, 2], [[0, 0, 0], [0.2, 0, 0]], [st((0, 0), (0, 2)), st((1, 0), (0, 2))])
        -6.0
        """
        if not states or any(s is None or dict(s).get("goal") is None for s in states):
            return float("-inf")
        l = float(dict(states[0])["spacing"])
        return -float(J1(poses, states, l) + J2(states))

    @staticmethod
    def team_multiple(target) -> int:
        """004 Sec. II-C: |A| = |Q|."""
        return len(getattr(target, "cells", ()) or (0,))

    @staticmethod
    def default_params(range: float = 0.6, n: int = 0) -> Params:
        return default_params(range, n)

    @staticmethod
    def _need_shape(target) -> None:
        """A usage error unless ``target`` is a goal set (a lattice or a line pattern is not)."""
        if getattr(target, "cells", None) is None:
            from swarmproof.models.errors import UsageError

            kind = getattr(target, "kind", type(target).__name__)
            raise UsageError(f"target={getattr(target, 'name', target)!r} ({kind}): wang2020 needs a shape "
                             "target (goal cells)", fix="e.g. --target shape:letter-l (or --shape FILE.png|FILE.txt)")

    def controller(self, robot_id, params: Params, target, rng) -> Wang2020Controller:
        self._need_shape(target)
        l = float(params.extra.get("grid_spacing", 1.0))
        shapes = (goal_cells(target, l),) + tuple(goal_cells(g, l) for g in self.next_shapes(params, target))
        # metrics(): the centralized optimum, shape after shape; completion_invariants: the goal sets
        # a declaration is judged by
        self._shapes = shapes
        return self.controller_class(robot_id, params, shapes, rng)

    def next_shapes(self, params: Params | None, target) -> tuple:
        """The goal sets formed after ``target``, in order (Fig. 9): the constructor's ``then``, or
        ``params.extra["then"]`` (``simulate --then``: names or files, a comma-separated string or
        a sequence), each named one resolved as a shape and scaled to the team, ``|Q| = |A| =
        len(target.cells)`` (Sec. II-C, V-A).

        Raises
        ------
        UsageError
            A name that is no shape, or ``then`` given both ways.

        >>> from swarmproof.models.targets import resolve_target
        >>> n = Wang2020.scale_target(resolve_target("shape:letter-n"), 16)
        >>> [(g.name, len(g.cells)) for g in Wang2020().next_shapes(Params(range=0.6,
        ...     extra={"then": "shape:letter-u,letter-l"}), n)]
        [('letter-u', 16), ('letter-l', 16)]
        """
        from swarmproof.models.errors import UsageError

        raw = dict(getattr(params, "extra", None) or {}).get("then", ())
        items = [x for x in (raw.split(",") if isinstance(raw, str) else
                             (raw if isinstance(raw, (list, tuple)) else [raw])) if str(x).strip()]
        if not items:
            return self.then
        if self.then:
            raise UsageError(f"then={raw!r} is given in params.extra and to Wang2020(then=...) both",
                             fix="give the next shapes one way: --then (params) or the constructor")
        n = len(getattr(target, "cells", ()) or ())
        out = []
        for item in items:
            g = item if getattr(item, "cells", None) is not None else _then_shape(str(item).strip())
            out.append(self.scale_target(g, n))
        return tuple(out)

    def check_params(self, params: Params, n: int, target) -> None:
        """Before a run (the engine calls it): every ``then`` shape resolves (exit 2 naming it)."""
        self.next_shapes(params, target)

    def judging_target(self, target, n_start: int, params=None):
        """The shape a run ends in: the last of ``then`` (Fig. 9: "U" after "N"), scaled to the
        team, or the run's target itself (``formation`` judges the final configuration)."""
        shapes = self.next_shapes(params, target) if getattr(target, "cells", None) is not None else ()
        return shapes[-1] if shapes else target

    # -- hooks of the checkers: the target and the start of a run (004 Sec. V-A) ----------------

    @staticmethod
    def scale_target(target, n: int):
        """The goal set for ``n`` agents: 004 Sec. V-A, "the figure is scaled such that the number
        of goal pixels on the figure equals the number of agents" (|Q| = |A|, Sec. II-C).

        A goal set that already has ``n`` cells is returned as it is (the bundled ``square-9`` at
        9 agents); any other is rescaled by :func:`swarmproof.models.shapes.scale_to` (connected,
        exactly ``n`` cells, deterministic), keeping its name, spacing, origin and range.

        >>> from swarmproof.models.targets import resolve_target
        >>> g = Wang2020.scale_target(resolve_target("shape:letter-l"), 12)
        >>> g.name, len(g.cells), Wang2020.scale_target(g, 12) is g
        ('letter-l', 12, True)
        """
        cells = getattr(target, "cells", None)
        if cells is None or len(cells) == int(n):
            return target
        import dataclasses

        from swarmproof.models.shapes import scale_to

        return dataclasses.replace(target, cells=scale_to(cells, int(n)))

    @staticmethod
    def arena_size(params: Params) -> tuple:
        """``(width, height)`` in waypoints of the arena starts are drawn from: ``params.extra
        ["arena"]`` (an int side, ``"WxH"`` or a pair), default
        :data:`swarmproof.models.shapes.DEFAULT_ARENA` (32 x 32; 004 Sec. V-A's "fixed-size arena"
        has no stated size: docs/decisions.md).

        >>> Wang2020.arena_size(default_params()), Wang2020.arena_size(Params(range=0.6, extra={"arena": "40x20"}))
        ((32, 32), (40, 20))
        """
        from swarmproof.models.errors import UsageError
        from swarmproof.models.shapes import DEFAULT_ARENA

        a = params.extra.get("arena", DEFAULT_ARENA)
        try:
            if isinstance(a, str):
                w, _, h = a.lower().partition("x")
                size = (int(w), int(h or w))
            elif isinstance(a, (int, np.integer)) and not isinstance(a, bool):
                size = (int(a), int(a))
            else:
                size = (int(a[0]), int(a[1]))
        except (TypeError, ValueError, IndexError):
            size = None
        if size is None or min(size) < 1:
            raise UsageError(f"arena={a!r} is not an arena size", fix="give --param arena=SIDE or --param arena=WxH "
                             "(waypoints), e.g. arena=32")
        return size

    def initial(self, n: int, seed: int, params: Params, target):
        """The start of a run (the checkers' hook, used instead of a connected start): ``n``
        distinct waypoints drawn uniformly from the arena centred on the goal set's centre of mass
        (004 Sec. V-A: "a random initialization" in "a fixed-size arena"; Fig. 11: "a uniform
        random distribution centered at the shape's center of mass"), from
        ``numpy.random.default_rng(seed)``.

        Raises
        ------
        UsageError
            More agents than the arena holds, naming ``n`` and the arena.

        >>> from swarmproof.models.targets import resolve_target
        >>> init = Wang2020().initial(5, 0, default_params(), resolve_target("shape:letter-l"))
        >>> init.n, len({tuple(p[:2]) for p in init.poses.tolist()})
        (5, 5)
        """
        from swarmproof.models.errors import UsageError
        from swarmproof.models.shapes import centered_arena, random_start_cells
        from swarmproof.models.trace import InitialConfiguration

        self._need_shape(target)
        l = float(params.extra.get("grid_spacing", 1.0))
        w, h = self.arena_size(params)
        arena = centered_arena(goal_cells(target, l), w, h)
        try:
            cells = random_start_cells(int(n), arena, np.random.default_rng(seed))
        except UsageError as exc:
            raise UsageError(exc.message, fix=f"give at most {w * h} robots (--robots), or a larger arena "
                                 f"(--param arena=SIDE or WxH, now {w}x{h})") from None
        return InitialConfiguration(list(range(int(n))), [[l * i, l * j, 0.0] for i, j in cells])

    def metrics(self, result) -> dict:
        """004's figures of a finished run (Sec. IV-B, V-A, Fig. 10):

        * ``J1``, ``J2``: the final values (:func:`J1`, :func:`J2`; both 0 once the shape formed);
        * ``optimal_distance``: the centralized optimum, the distance-optimal assignment of the
          start waypoints to the run's goal set (:func:`swarmproof.models.assignment.optimal_assignment`),
          in metres (cells x grid length); with next shapes (``then``) plus, for each, the optimum
          from the shape before it;
        * ``distance_ratio``: ``total_distance / optimal_distance`` (Sec. V-A: "only around 20%
          more"); None when the optimum is 0;
        * ``constraint_violations``: how many recorded steps broke Constraint III-A.1 or III-A.2
          (the ``constraint_vertex`` / ``constraint_edge`` invariants; 0 is what Theorems
          IV-A.1/2 claim), and ``constraint_steps_checked``, how many steps were looked at (a
          sparse trace, ``--record-every K``, is counted on what it kept).
        """
        from swarmproof.invariants.metrics import total_distance
        from swarmproof.models.assignment import optimal_assignment

        trace = result.trace
        states = tuple(result.final_states)
        l = float(dict(states[0])["spacing"]) if states and states[0] is not None else 1.0
        live = [(p, s) for p, s in zip(result.final_poses, states) if s is not None and dict(s)["goal"] is not None]
        j1 = J1([p for p, _ in live], [s for _, s in live], l) if live else None
        j2 = J2([s for _, s in live]) if live else None
        starts = [(int(round(x / l)), int(round(y / l))) for x, y in np.asarray(trace.poses[0])[:, :2].tolist()]
        legs = [list(s) for s in getattr(self, "_shapes", ()) or ()]
        opt = ratio = None
        if legs and all(len(g) == len(starts) for g in legs):
            # start -> first shape, then shape -> next shape (--then): each leg's optimum
            opt = float(sum(optimal_assignment(a, b, spacing=l).total for a, b in zip([starts] + legs, legs)))
            ratio = None if opt == 0 else float(total_distance(trace)) / opt
        checks = {inv.name: inv for inv in make_invariants()}
        vertex, edge = checks["constraint_vertex"].check, checks["constraint_edge"].check
        present = trace.present
        ids = np.asarray(trace.ids)
        bad = 0
        for k in range(len(trace.poses)):
            mask = np.ones(len(ids), bool) if present is None else np.asarray(present[k], bool)
            sts = tuple(s for s, m in zip(trace.states[k], mask) if m)
            if not sts or any(s is None or dict(s)["cell"] is None for s in sts):
                continue
            t = int(trace.times[k]) if getattr(trace, "times", None) else k
            pos = np.asarray(trace.poses[k])[mask]
            if vertex(t, ids[mask], pos, sts) is not None or edge(t, ids[mask], pos, sts) is not None:
                bad += 1
        return {"J1": j1, "J2": j2, "optimal_distance": opt, "distance_ratio": ratio,
                "constraint_violations": bad, "constraint_steps_checked": len(trace.poses)}

    def finished(self, states) -> bool:
        """Every agent knows the last shape complete (Sec. III-B); stops at the first that does not."""
        live = False
        for s in states:
            if s is None:
                continue
            live = True
            e = s[8] if len(s) > 8 else None
            done = e[1] if e is not None and e[0] == "done" else dict(s)["done"]
            if not done:
                return False
        return live

    @staticmethod
    def default_max_steps(params: Params, n: int) -> int:
        """Generous: 20000 ticks plus 400 per agent."""
        return int(20000 + 400 * n)


class Wang2020BroadcastHandshake(Wang2020):
    """``wang2020`` with the 2-way handshake carried by the broadcasts: reading "1" of
    ``wang2020``, its default up to swarmproof 0.2.0, kept as a registered variant (issue 30).
    Its controller is :class:`BroadcastHandshakeController`; it runs on the per-robot reference
    only (the vectorised path copies the default).

    It breaks 004 Sec. II-A e) ("the communication latency is negligible"): each direction of
    the handshake waits for the sender's next broadcast, so a server can take a request whose
    ACK reaches the client after the client's timeout (a half swap: two agents on one goal, J2
    rises; Lemma IV-B.2's ``j2_monotone`` is violated).  Its findings are reported beside the
    default's in verify (docs/wang2020.md, "The handshake").
    """

    name = "wang2020-broadcast-handshake"
    reading = "1"
    departs_from = ("004 Sec. II-A e) \"The communication latency is negligible\": the handshake's request "
                    "and ACK ride in the broadcasts, one broadcast interval each way",)
    controller_class = BroadcastHandshakeController
    parameters = BROADCAST_HANDSHAKE_PARAMETERS
    verify = VerifyPlan(targets=("shape:letter-l",), robots=5, seeds=(0, 1, 2), explore=True, rank=31,
                        explore_max_examples=100, explore_cost=44, exhaustive=WANG2020_EXHAUSTIVE)
