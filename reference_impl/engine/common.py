"""Small helpers the engine's phases share."""

from __future__ import annotations

import math

import numpy as np

from swarmproof.models.errors import UsageError

from ..protocol import Params

#: How often (in steps) the progress callback is called.
PROGRESS_EVERY = 50


def _robot_rng(seed: int, slot: int) -> np.random.Generator:
    """Robot slot ``slot``'s generator: ``SeedSequence(seed, spawn_key=(0, slot))``."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(0, slot)))


def _ro(a: np.ndarray) -> np.ndarray:
    """A read-only view (observers must not change the engine's arrays)."""
    v = a.view()
    v.setflags(write=False)
    return v


def _extra_number(params: Params, key: str, default: float, *, positive: bool = True) -> float:
    val = params.extra.get(key, default) if params.extra else default
    if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val) \
            or (positive and val <= 0):
        raise UsageError(f"params.extra[{key!r}]={val!r} must be a finite number > 0")
    return float(val)
