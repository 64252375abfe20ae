"""The experiments of 000 Sec. V, run on the swarmproof engine.

* :func:`run_formation`: n robots from a random connected start form a
  lattice (square, hexagon, octagon-square; Figs. 8-9).
* :func:`run_robustness`: robots form a lattice; at the first static state
  some random robots are removed (a "massive failure") and the rest re-form
  (Fig. 10: 150 robots, hexagon, 50 removed).
* :func:`execution_time`: Def. 3's execution time, read from a trace.

The non-fulfillment ratio (Eq. 3) is an invariant-level metric
(:mod:`swarmproof.invariants.metrics`); this module returns engine results
and leaves the measuring to the caller (import rules, DESIGN.md section 1).

References
----------
000_3ad33c5b62f11d5f.txt, Sec. III-C (Def. 3, Eq. 3), Sec. V (Figs. 8-10).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swarmproof.models.errors import UsageError, check_type
from swarmproof.models.library import load

from ..engine import FaultModel, SimulationResult, simulate
from ..initial import random_connected
from ..protocol import Params
from .algorithm import Song2014

__all__ = ["execution_time", "run_formation", "run_robustness", "RobustnessResult", "default_params"]


def default_params(lattice) -> Params:
    """The parameters our experiments use: the lattice's range, ``v=0.05``, ``omega=pi/4``, ``dt=1``.

    The paper says only "we keep a consistent velocity in all experiments"
    (Sec. V); see docs/decisions.md (song2014).

    >>> default_params(load("hexagon"))
    Params(range=1.5, v=0.05, omega=0.7853981633974483, dt=1.0, extra={})
    """
    return Params(range=float(lattice.range))


def execution_time(result: SimulationResult, *, start: int = 0) -> int | None:
    """Def. 3's execution time, in steps: the first step ``t >= start`` after
    which no present robot's pose changes until the end of the trace.

    Returns None unless the run ended static (``result.static``): on a
    step-capped run the future is unknown and Def. 3 cannot be read off.
    Multiply by ``params.dt`` for time.

    Parameters
    ----------
    result : SimulationResult
    start : int
        Count from this step (e.g. the step of a removal); the value returned
        is still an absolute step number.

    References
    ----------
    000 Sec. III-C-1, Definition 3 and the definition of ``t_exe``.
    """
    if not result.static:
        return None
    poses = result.trace.poses
    final = poses[-1]
    present = result.trace.present_at(-1)
    t = len(poses) - 1
    while t > start and np.array_equal(poses[t - 1][present], final[present]):
        t -= 1
    return t


def _initial(lattice, n: int, seed: int, spread_factor: float | None = None):
    """The random connected start of ``seed``; with ``spread_factor`` the robots
    lie in a square of side ``spread_factor * sqrt(n) * phi`` (a denser start)."""
    phi = float(lattice.range)
    spread = None if spread_factor is None else float(spread_factor) * math.sqrt(n) * phi
    return random_connected(n, np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(7,))),
                            range=phi, spread=spread)


def run_formation(lattice_name: str, n: int, seed: int, *, params: Params | None = None,
                  max_steps: int | None = None, spread_factor: float | None = None) -> SimulationResult:
    """One run of Sec. V's formation experiment (Figs. 8-9).

    ``n`` robots start from :func:`~swarmproof.reference_impl.initial.random_connected`
    (range = the lattice's, minimum separation phi/4) drawn from ``seed``, and
    run song2014 until static or the cap.  ``spread_factor`` confines the start
    to a square of side ``spread_factor * sqrt(n) * phi`` (denser starts).

    Examples
    --------
    >>> r = run_formation("square", 6, seed=1)
    >>> r.status, execution_time(r) is not None
    ('static', True)
    """
    check_type("n", n, (int, np.integer))
    lattice = load(lattice_name)
    params = params or default_params(lattice)
    return simulate(Song2014(), lattice, _initial(lattice, int(n), seed, spread_factor), params,
                    seed=seed, max_steps=max_steps)


@dataclass(frozen=True)
class RobustnessResult:
    """The two phases of the robustness experiment.

    Attributes
    ----------
    before : SimulationResult
        The run to the first static state.
    after : SimulationResult
        The same run replayed with the removal at step ``removed_at``,
        continued until static again or the cap.
    removed_at : int
        The step at which the robots crash: the first run's execution time
        (Def. 3), i.e. the first step from which no pose changes.
    removed : tuple of int
        The IDs removed.
    """

    before: SimulationResult
    after: SimulationResult
    removed_at: int
    removed: tuple[int, ...]


def run_robustness(seed: int, *, lattice_name: str = "hexagon", n: int = 150, remove: int = 50,
                   params: Params | None = None, max_steps: int | None = None,
                   spread_factor: float | None = None) -> RobustnessResult:
    """Sec. V's robustness experiment (Fig. 10): form, remove ``remove`` robots, re-form.

    The first run stops when the engine sees it static; its execution time
    ``T1`` (Def. 3) is the first step from which no pose changes.  The engine
    is deterministic, so the second run replays it with a fault model that
    crashes ``remove`` robots, chosen uniformly with a generator spawned from
    ``seed``, at the start of step ``T1``; the survivors keep their last
    messages, as physical robots would.  The time to re-form is
    ``execution_time(after, start=T1) - T1``.

    Raises
    ------
    UsageError
        If ``remove`` is not in ``[0, n)``, or the first run did not reach a
        static state (nothing to remove robots from).
    """
    if not 0 <= remove < n:
        raise UsageError(f"remove={remove!r} must be in [0, n={n!r})")
    lattice = load(lattice_name)
    params = params or default_params(lattice)
    init = _initial(lattice, n, seed, spread_factor)
    before = simulate(Song2014(), lattice, init, params, seed=seed, max_steps=max_steps)
    if not before.static:
        raise UsageError(f"the first phase ended with status={before.status!r} after "
                         f"{before.steps} steps, not static", fix="raise max_steps or change seed")
    # Remove at the first static time of Def. 3 (poses final from here on),
    # not at the step the engine noticed it: the replay would stop there first.
    t1 = execution_time(before)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(8,)))
    removed = tuple(sorted(int(i) for i in rng.choice(init.ids, size=remove, replace=False)))
    cap = None if max_steps is None else t1 + int(max_steps)
    if cap is None:
        from ..engine import default_max_steps
        cap = t1 + default_max_steps(n - remove, params)
    after = simulate(Song2014(), lattice, init, params, seed=seed, max_steps=cap,
                     faults=FaultModel(crashes={t1: removed}))
    return RobustnessResult(before, after, t1, removed)
