"""004 Sec. III-B's shape-complete detection, judged at every step: the ``completion_sound`` invariant.

Sec. III-B: "If the shape is completely formed, there will be no anchor nodes in the swarm, so
the gradient value of each agent will increase temporally.  If any agent holds a gradient value
larger than the number of agents, then the agent knows there are no anchor nodes, and therefore
the shape is completed.  Once any agent detects that the shape is complete, it will send a
message which propagates across the entire swarm telling every other agent that the shape is
complete."  The text argues "formed => no anchor => hop-counts grow" and then uses the converse,
"hop-count > |A| => formed", with no connectivity assumed (docs/decisions.md, "False completion").
The controller declares a shape complete by raising its state's ``completed`` count
(:meth:`~swarmproof.reference_impl.wang2020.algorithm.Wang2020Controller._switch`); this invariant
checks that declaration against the goal set.

What is checked.  At the step in which some agent's ``completed`` count first reaches ``c + 1``
(no agent had it before: the *declaration* of shape ``c``), every goal cell of shape ``c`` holds
an agent at rest: its pose exactly on that waypoint (within 1e-9 of the grid length, as the J
invariants decide who rests).  "Held" is read from poses, not from the agents' goals ``T``: the
shape the paper calls "completely formed" is the configuration Sec. II-C asks for (every agent on
a goal, no goal twice; with |Q| = |A| that is every goal cell occupied), and at the declaring step
the declaring agent of a shape that is not the last has already drawn its goal in the next shape
(Alg. 2 lines 2-7).  The declaring agent itself does not move in that step (its ``last_check`` is
reset, or, for the last shape, it stands on its goal when the shape is formed), so a formed
shape passes.

Blind spots: only the first declaration of each shape is judged; agents that raise their count
later, by hearing the news or by detecting it themselves, repeat a declaration already judged
(in a run of several shapes the first agents leave for the next shape, so the old goals empty on
purpose).  An agent resting on a goal cell that is not its own ``T`` counts as holding it (a
formed shape whose assignment is still a permutation passes).  The goal sets come from the
algorithm object that ran (``Wang2020.controller`` keeps them); an algorithm object that never
built a controller has nothing to judge against, and the run is then inconclusive.

References
----------
004_004a3703645971e3.txt Sec. III-B (shape-complete detection), Sec. II-C (the formed shape),
Sec. V-B4 / Fig. 9 (switching to the next shape).

Examples
--------
Three goals in a row; agents at rest on two of them and one on the edge toward the third; robot 1
declares the shape complete in step 7:

>>> import numpy as np
>>> alg = type("A", (), {"_shapes": (((0, 0), (1, 0), (2, 0)),)})()
>>> inv = completion_invariant(alg)
>>> st = lambda c, hop=None: (("completed", c), ("hop", hop), ("wp", (2, 0)), ("goal", (2, 0)), ("spacing", 0.2))
>>> poses = np.array([[0.0, 0, 0], [0.2, 0, 0], [0.3, 0, 0]])
>>> inv.check(0, np.array([1, 2, 3]), poses, (st(0), st(0), st(0))) is None
True
>>> print(inv.check(7, np.array([1, 2, 3]), poses, (st(1, 4), st(0), st(0))))
robot 1 declared shape 0 complete in step 7 (hop-count 4 > |A| = 3) while 1 of its 3 goals held no agent at rest: (2, 0) (robots 1, 2, 3's goal); robot 3 on the edge toward (2, 0)
>>> inv.judged()
1
"""

from __future__ import annotations

import numpy as np

from swarmproof.invariants.algorithm_invariants import Invariant
from swarmproof.invariants.result import state_value

__all__ = ["completion_invariant", "STATEMENT", "CITES"]

STATEMENT = ("whenever an agent declares a shape complete (its completed count rises to one no agent had), "
             "every goal cell of that shape holds an agent at rest")
CITES = "004 Sec. III-B"
#: How many unheld goals and misplaced agents a message names.
_SHOWN = 6


def _completed(state):
    """``state_value(state, "completed")``, first at its place in the controller's state (index 7,
    as ``Wang2020.finished`` reads ``done`` at 8): the monitor reads it for every agent every step."""
    e = state[7] if type(state) is tuple and len(state) > 7 else None
    if type(e) is tuple and e[0] == "completed":
        return e[1]
    return state_value(state, "completed")


class _Completion:
    """The state of one run's check: the highest ``completed`` count seen, declarations judged."""

    def __init__(self, algorithm) -> None:
        self.algorithm = algorithm
        self.declared = 0
        self.count = 0

    def judged(self) -> int:
        return self.count

    def __call__(self, t, ids, poses, states):
        if int(t) == 0:
            self.declared, self.count = 0, 0
        # one key per step, as a column where the states offer one (the vectorised path's
        # ``values_of``); whole states only at a declaration
        column = getattr(states, "values_of", None)
        counts = column("completed") if callable(column) else [_completed(s) for s in states]
        counts = [int(c or 0) for c in counts]
        top = max(counts, default=0)
        if top <= self.declared:
            return None
        sts = [None if s is None else dict(s) for s in states]
        first, self.declared = self.declared, top
        shapes = getattr(self.algorithm, "_shapes", None)
        if not shapes:
            return None                          # nothing to judge against: not counted (inconclusive)
        msgs = []
        for c in range(first, top):
            self.count += 1
            msg = self._judge(c, t, ids, poses, sts, counts, tuple(shapes[c]), c == len(shapes) - 1)
            if msg is not None:
                msgs.append(msg)
        return "; ".join(msgs) if msgs else None

    @staticmethod
    def _judge(c, t, ids, poses, sts, counts, goals, last):
        """The declaration of shape ``c`` in step ``t``: None when every goal holds an agent at rest.
        The message names each unheld goal's owners (the agents whose goal it is; a declaring agent
        of a shape that is not the ``last`` already holds a goal of the next one, so then an
        unheld goal without an owner is "no known owner" rather than "nobody's goal")."""
        live = [d for d in sts if d is not None]
        l = float(live[0].get("spacing", 1.0)) if live else 1.0
        xy = np.asarray(poses, dtype=float).reshape(len(sts), -1)[:, :2] / l
        cells = np.rint(xy)
        rest = (np.abs(xy - cells).max(axis=1) <= 1e-9) if len(xy) else np.zeros(0, bool)
        at = {(int(x), int(y)) for (x, y), r in zip(cells.tolist(), rest.tolist()) if r}
        unheld = [g for g in goals if tuple(g) not in at]
        if not unheld:
            return None
        rid = [int(i) for i in np.asarray(ids).tolist()]
        who = [k for k, n in enumerate(counts) if n > c]
        hops = sorted({sts[k].get("hop") for k in who if sts[k] is not None and sts[k].get("hop") is not None})
        names = ", ".join(str(rid[k]) for k in who[:_SHOWN]) + (f" (and {len(who) - _SHOWN} more)"
                                                                  if len(who) > _SHOWN else "")
        hop = (f"hop-count {', '.join(map(str, hops))} > |A| = {len(goals)}" if hops
               else f"hop-count > |A| = {len(goals)}")
        gset = {tuple(g) for g in goals}
        known = [k for k, d in enumerate(sts) if d is not None and (last or counts[k] <= c)]
        owners: dict = {}
        for k in known:
            g = sts[k].get("goal")
            if g is not None:
                owners.setdefault(tuple(g), []).append(rid[k])
        nobody = "nobody's goal" if len(known) == sum(d is not None for d in sts) else "no known owner"

        def owned(g):
            who = owners.get(tuple(g))
            if not who:
                return f"{tuple(g)} ({nobody})"
            return f"{tuple(g)} (robot{'s' if len(who) > 1 else ''} {', '.join(map(str, who))}'s goal)"
        away = []
        for k, d in enumerate(sts):
            if d is None:
                continue
            if not rest[k]:
                to = d.get("wp")
                away.append(f"robot {rid[k]} on the edge" + (f" toward {tuple(to)}" if to is not None else ""))
            elif (int(cells[k, 0]), int(cells[k, 1])) not in gset:
                away.append(f"robot {rid[k]} at rest on {(int(cells[k, 0]), int(cells[k, 1]))}, off the shape")
        more = lambda xs: "" if len(xs) <= _SHOWN else f" (and {len(xs) - _SHOWN} more)"
        return (f"robot{'s' if len(who) > 1 else ''} {names} declared shape {c} complete in step {int(t)} ({hop}) "
                f"while {len(unheld)} of its {len(goals)} goals held no agent at rest: "
                f"{', '.join(owned(g) for g in unheld[:_SHOWN])}{more(unheld)}"
                + (f"; {', '.join(away[:_SHOWN])}{more(away)}" if away else ""))


def completion_invariant(algorithm) -> Invariant:
    """A fresh ``completion_sound`` invariant for one run of ``algorithm`` (a ``Wang2020`` object:
    its goal sets are read when the check runs, after the engine built the controllers).

    ``judged()`` counts the declarations judged, so a run in which no agent declared completion
    is inconclusive, not held (:class:`~swarmproof.invariants.algorithm_invariants.InvariantsMonitor`).
    """
    check = _Completion(algorithm)
    return Invariant("completion_sound", STATEMENT, CITES, check, judged=check.judged)
