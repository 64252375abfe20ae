"""Termination: every robot is static by the bound of Theorem 13 (001).

001 Defs. 5-6: a robot is *static* at time t if its pose never changes
after t; the execution time is the smallest time at which all robots are
static.  On a finite trace we can only see up to its end:
:func:`execution_steps` is the smallest step ``t`` with
``poses[t'] == poses[t]`` for every recorded ``t' >= t``.

:func:`static_by_bound` compares it with a bound the *algorithm* computes
(its constants are the algorithm's; :func:`theorem13_bound_steps` states
the form of 001 Theorem 13's proof with the constants we use).  Verdicts:

* ``violated``: some robot moved after step ``bound`` (witness: the robot,
  the step);
* ``held``: nobody moved after ``bound`` and the run ended finished or
  static (the engine's end conditions);
* ``inconclusive``: the run stopped at its step cap with robots still
  moving but before the bound was reached, or static only at the very end
  of a capped run.

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Defs. 5-6, Theorem 13 and its proof.

Examples
--------
>>> import numpy as np
>>> from swarmproof.models.trace import Trace
>>> poses = np.zeros((5, 1, 3)); poses[1:3, 0, 0] = [0.1, 0.2]; poses[3:, 0, 0] = 0.3
>>> t = Trace(ids=[0], poses=poses, states=[(None,)] * 5, meta={"status": "static"})
>>> execution_steps(t)
3
>>> static_by_bound(t, 3).status, static_by_bound(t, 2).status
('held', 'violated')
"""

from __future__ import annotations

import math

import numpy as np

from .result import InvariantResult

__all__ = ["execution_steps", "static_by_bound", "theorem13_bound_steps", "judge_termination"]

THEOREM_13 = "001 Theorem 13 (the lattice forms in finite time), Defs. 5-6"


def execution_steps(trace) -> int:
    """Smallest step after which no recorded pose changes (Def. 6 of 001, on the trace).

    On a sparse trace (``trace.times``) it is the engine step of the first
    recorded frame after the last change: exact to the recording interval.
    """
    p = trace.poses
    for t in range(len(p) - 1, 0, -1):
        if not np.array_equal(p[t], p[t - 1]):
            return trace.time_of(t) if hasattr(trace, "time_of") else t
    return 0


def theorem13_bound_steps(n: int, *, range: float, v: float, omega: float, dt: float,
                          timeout_steps: int) -> int:
    """The bound of 001 Theorem 13's proof, in steps, with explicit constants.

    ``T = sum_{i=1}^{n-1} T_i + O(n)`` with ``T_i <= T_timeout + (n-1)(phi/v + 2 pi/omega)``.
    We take each ``O(n)`` term as one communication timeout of
    ``timeout_steps`` steps (the paper's experiments use n), and convert
    times to steps with ``ceil(time / dt)``::

        bound = (n-1) * (timeout_steps + (n-1) * ceil((phi/v + 2 pi/omega) / dt)) + timeout_steps

    >>> theorem13_bound_steps(3, range=1.2, v=0.05, omega=math.pi / 4, dt=1.0, timeout_steps=3)
    137
    """
    if n <= 1:
        return int(timeout_steps)
    hop = math.ceil((range / v + 2 * math.pi / omega) / dt) if v > 0 else 10**12
    return int((n - 1) * (timeout_steps + (n - 1) * hop) + timeout_steps)


def static_by_bound(trace, bound: int, *, cites: str = THEOREM_13) -> InvariantResult:
    """Every robot is static by step ``bound`` (see the module docstring)."""
    bound = int(bound)
    p = trace.poses
    T = trace.steps
    t_exec = execution_steps(trace)
    status = trace.meta.get("status")
    if t_exec > bound:
        # frames, not steps: the last frame at or before the bound (the same index on a dense trace)
        times = getattr(trace, "times", None)
        f = bound if times is None else int(np.searchsorted(times, bound, side="right")) - 1
        moved = np.flatnonzero((p[f + 1:] != p[f:-1]).any(axis=2).any(axis=0))
        rid = int(trace.ids[moved[0]]) if len(moved) else None
        last = t_exec
        return InvariantResult("termination", "violated", cites,
                               {"bound": bound, "execution_steps": t_exec, "robot": rid, "step": last},
                               f"robots still moved at step {last}, after the bound {bound}"
                               + (f" (e.g. robot {rid})" if rid is not None else ""))
    if status in ("finished", "static"):
        return InvariantResult("termination", "held", cites, None,
                               f"static from step {t_exec} <= bound {bound} (run {status})",
                               detail={"execution_steps": t_exec})
    if T >= bound:
        return InvariantResult("termination", "inconclusive", cites, None,
                               f"no motion after step {t_exec} up to the step cap {T}, but the run "
                               "did not end finished or static", detail={"execution_steps": t_exec})
    return InvariantResult("termination", "inconclusive", cites, None,
                           f"the run stopped at step {T} (status {status!r}) before the bound {bound}",
                           detail={"execution_steps": t_exec})


def judge_termination(trace, algorithm, params, status: str, *, max_steps: int | None = None) -> InvariantResult:
    """The termination verdict of one run of ``algorithm`` (simulate, verify, explore, replay).

    * An algorithm that declares its own end (class attribute ``own_end``, a sentence
      citing it -- song2016: "no unstable robot remains") and whose run went static
      short of it is *deadlocked*: nothing will ever change again, so the algorithm
      never ends -- ``violated`` (001 Theorem 13 claims the lattice forms in finite
      time; the proof ends "until no more unstable robots remain").
    * Else, with a ``termination_bound(params, n)``: :func:`static_by_bound`.
    * Else: a run cut by the step cap is ``inconclusive``, any other end ``held``
      (001 Def. 5: every robot static).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> t = Trace(ids=[0], poses=np.zeros((4, 1, 3)), states=[(None,)] * 4, meta={"status": "static"})
    >>> judge_termination(t, type("A", (), {"own_end": "all done (paper Sec. 1)"})(), None, "static").status
    'violated'
    >>> judge_termination(t, object(), None, "static").status
    'held'
    """
    own_end = getattr(algorithm, "own_end", None)
    if own_end and status == "static":
        t_exec = execution_steps(trace)
        return InvariantResult(
            "termination", "violated", THEOREM_13, {"step": t_exec, "deadlock": True},
            f"deadlock: nothing moved or changed from step {t_exec} on, but the algorithm's own end "
            f"({own_end}) never came: it would wait forever")
    bound_fn = getattr(algorithm, "termination_bound", None)
    if callable(bound_fn):
        return static_by_bound(trace, int(bound_fn(params, trace.n)))
    if status == "step_cap":
        return InvariantResult("termination", "inconclusive", "001 Def. 5", None,
                               f"step cap {max_steps} reached; no termination bound to judge by")
    return InvariantResult("termination", "held", "001 Def. 5", None,
                           f"the run ended ({status}) after {trace.time_of(len(trace.poses) - 1)} steps")
