"""Clock models: synchronous steps, or asynchronous clocks with a per-robot phase and rate
drawn from the seed (issue 12; 004 Sec. V-B3 relaxes clock rates)."""

from __future__ import annotations

import numpy as np

from swarmproof.models.errors import UsageError

from ..protocol import Params
from .common import _extra_number


def _draw_clocks(params: Params, n: int, seed: int):
    """``clocks="async"``: per-robot phase in [0, 1) and rate in ``[clock_rate_min,
    clock_rate_max]`` (``params.extra``, default 1 each), drawn from the run's seed (a
    generator of their own, so the robots' and the faults' draws are untouched), and the
    broadcast interval ``broadcast_every`` (local time units, default 1)."""
    lo = _extra_number(params, "clock_rate_min", 1.0)
    hi = _extra_number(params, "clock_rate_max", lo)
    if hi < lo:
        raise UsageError(f"params.extra clock_rate_max={hi!r} < clock_rate_min={lo!r}",
                         fix="give clock_rate_min <= clock_rate_max")
    every = _extra_number(params, "broadcast_every", 1.0)
    crng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2,)))
    phase = crng.uniform(0.0, 1.0, n)
    rate = crng.uniform(lo, hi, n) if hi > lo else np.full(n, lo)
    return phase, rate, every


class SyncClocks:
    """``clocks="sync"``: every robot decides and broadcasts in every step."""

    synchronous = True

    def ticks(self, t: int, idx):
        return None

    def clock_of(self, k: int, t: int) -> float:
        """Robot slot ``k``'s clock in step ``t``: the step."""
        return float(t)

    def describe(self) -> dict:
        return {}


class AsyncClocks:
    """``clocks="async"``: robot k's local clock is ``phase[k] + rate[k] * t``; it decides
    in step t when the clock passes an integer during the step, and broadcasts its last
    decided message when the clock passes ``j * broadcast_every + 1/2`` (docs/engine.md)."""

    synchronous = False

    def __init__(self, params: Params, n: int, seed: int) -> None:
        self.phase, self.rate, self.every = _draw_clocks(params, n, seed)

    def ticks(self, t: int, idx):
        """``(decides, broadcasts, local clock at t)`` of the present robots ``idx``."""
        tau0 = self.phase[idx] + self.rate[idx] * t
        tau1 = tau0 + self.rate[idx]
        decide = np.floor(tau1) > np.floor(tau0)
        bcast = np.floor((tau1 + 0.5) / self.every) > np.floor((tau0 + 0.5) / self.every)
        return decide, bcast, tau0

    def clock_of(self, k: int, t: int) -> float:
        """Robot slot ``k``'s local clock in step ``t`` (the ``tau0`` of :meth:`ticks`)."""
        return float(self.phase[k] + self.rate[k] * t)

    def describe(self) -> dict:
        """The recorded clocks (``trace.meta["clocks"]``)."""
        return {"clocks": {"phase": [float(x) for x in self.phase], "rate": [float(x) for x in self.rate],
                           "broadcast_every": self.every}}


def clock_model(model, params: Params, n: int, seed: int):
    """The clock model a :class:`~swarmproof.reference_impl.protocol.RobotModel` names."""
    return AsyncClocks(params, n, seed) if model.clocks == "async" else SyncClocks()
