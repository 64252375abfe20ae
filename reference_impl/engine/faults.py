"""Fault models of the engine: asynchronous schedules, crashes, additions, lost, late,
duplicated and reordered messages, sensing noise (issue 6, issue 12).

Every random draw uses the fault generator the engine spawns from the run's seed
(``SeedSequence(seed, spawn_key=(1,))``), so a run with the same fault model and seed
-- a replay -- is bit-identical.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from swarmproof.models.errors import UsageError

__all__ = ["FaultModel", "TableSchedule", "DropSet"]


@dataclass(frozen=True)
class FaultModel:
    """Hook points for faults (issue 6); every field is optional.

    Attributes
    ----------
    schedule : callable ``(step, ids, rng) -> mask``, optional
        Which robots act in this step (asynchronous activation).  ``ids`` are
        the IDs of the present robots in slot order; return a boolean array of
        the same length.  A robot that does not act neither moves nor
        broadcasts in that step (its neighbors hear nothing from it next step)
        and its controller is not called.
    crashes : mapping ``step -> IDs``
        Robots that crash at the start of that step: they vanish (no longer
        sensed, no messages, no motion); their trace slot keeps the last pose
        with ``present=False``.
    additions : mapping ``step -> [(id, [x, y, theta]), ...]``
        Robots that join at the start of that step with a fresh controller.
    drop_message : callable ``(step, sender_id, receiver_id, rng) -> bool``, optional
        True drops that delivery.
    message_loss : float
        Probability that each delivery is lost (drawn from the fault
        generator), applied after ``drop_message``.
    sensing_noise : callable ``(step, robot_id, rel, rng) -> rel``, optional
        Perturb the ``(k, 3)`` body-frame poses a robot senses (return a new array).
    noise_std : (float, float)
        Gaussian noise standard deviations on sensed (x, y) and theta.
    message_delay : int
        Each delivery (after loss) arrives 0..``message_delay`` steps late,
        drawn uniformly per delivery.
    message_duplication : float
        Probability that a delivery arrives twice (both copies with the same delay).
    message_reorder : bool
        Each robot's deliveries of a step are shuffled (``Observation.inbox``
        order; ``messages`` keeps the last one per sender).

    Every random draw uses the fault generator, spawned from the run's seed,
    so a run with the same fault model and seed -- a replay -- is bit-identical;
    late and duplicated deliveries are recorded as ``late_delivery`` events.
    """

    schedule: Callable[[int, np.ndarray, np.random.Generator], Any] | None = None
    crashes: Mapping[int, Sequence[int]] = field(default_factory=dict)
    additions: Mapping[int, Sequence[tuple[int, Sequence[float]]]] = field(default_factory=dict)
    drop_message: Callable[[int, int, int, np.random.Generator], bool] | None = None
    message_loss: float = 0.0
    sensing_noise: Callable[[int, int, np.ndarray, np.random.Generator], np.ndarray] | None = None
    noise_std: tuple[float, float] = (0.0, 0.0)
    message_delay: int = 0
    message_duplication: float = 0.0
    message_reorder: bool = False

    def __post_init__(self) -> None:
        for name in ("message_loss", "message_duplication"):
            p = getattr(self, name)
            if isinstance(p, bool) or not isinstance(p, (int, float)) or not 0.0 <= float(p) <= 1.0:
                raise UsageError(f"{name}={p!r} must be a number in [0, 1]")
        d = self.message_delay
        if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or d < 0:
            raise UsageError(f"message_delay={d!r} must be an integer >= 0 (steps)")
        for k, s in enumerate(self.noise_std):
            if not (math.isfinite(float(s)) and float(s) >= 0):
                raise UsageError(f"noise_std[{k}]={s!r} must be a finite number >= 0")

    @property
    def drops_messages(self) -> bool:
        return self.drop_message is not None or self.message_loss > 0

    @property
    def late_messages(self) -> bool:
        """Deliveries may come late, twice or out of order."""
        return self.message_delay > 0 or self.message_duplication > 0 or bool(self.message_reorder)

    @property
    def noisy(self) -> bool:
        return self.sensing_noise is not None or any(float(s) > 0 for s in self.noise_std)

    def broken_model_assumptions(self, model) -> list[str]:
        """Names of the robot-model assumptions this fault model breaks."""
        out = []
        if self.schedule is not None and getattr(model, "clocks", "sync") == "sync":
            out.append("synchronous_clocks")
        if any(self.crashes.values()):
            out.append("no_crashes")
        if any(self.additions.values()):
            out.append("fixed_robot_set")
        if self.drops_messages:
            out.append("reliable_messages")
        if self.noisy:
            out.append("exact_sensing")
        timely = getattr(model, "message_timing", "timely") == "timely"
        if self.message_delay > 0 and timely:
            out.append("timely_messages")
        if self.message_duplication > 0:
            out.append("messages_delivered_once")
        if self.message_reorder and timely:
            out.append("ordered_messages")
        return out

    def describe(self) -> dict:
        """JSON-friendly summary for traces, reports and counterexample files.

        Data-driven hooks (:class:`TableSchedule`, :class:`DropSet`) are written
        as their data, so :meth:`from_dict` rebuilds the same fault model;
        other callables are written by name only (not replayable).
        """
        def hook(f):
            if f is None:
                return None
            if hasattr(f, "as_dict"):
                return f.as_dict()
            return {"kind": "callable", "name": getattr(f, "__name__", type(f).__name__)}

        out = {
            "schedule": hook(self.schedule),
            "crashes": {str(k): [int(i) for i in v] for k, v in sorted(self.crashes.items())},
            "additions": {str(k): [[int(i), [float(x) for x in p]] for i, p in v]
                          for k, v in sorted(self.additions.items())},
            "drop_message": hook(self.drop_message),
            "message_loss": float(self.message_loss),
            "sensing_noise": hook(self.sensing_noise),
            "noise_std": [float(s) for s in self.noise_std],
        }
        # written only when used, so the files of earlier fault models stay as they were
        if self.message_delay:
            out["message_delay"] = int(self.message_delay)
        if self.message_duplication:
            out["message_duplication"] = float(self.message_duplication)
        if self.message_reorder:
            out["message_reorder"] = True
        return out

    @staticmethod
    def from_dict(d: Mapping) -> "FaultModel":
        """Rebuild a fault model written by :meth:`describe` (data-driven hooks only).

        Raises
        ------
        UsageError
            A hook given only by name (a Python callable cannot be rebuilt from JSON).

        Examples
        --------
        >>> f = FaultModel(schedule=TableSchedule({2: (1, 3)}), drop_message=DropSet({(0, 1, 3)}),
        ...                crashes={4: [3]}, noise_std=(0.01, 0.0))
        >>> FaultModel.from_dict(f.describe()).describe() == f.describe()
        True
        """
        def hook(v, name):
            if v is None:
                return None
            kind = v.get("kind") if isinstance(v, Mapping) else None
            if kind == "table_schedule":
                return TableSchedule.from_dict(v)
            if kind == "drop_set":
                return DropSet.from_dict(v)
            raise UsageError(f"faults.{name}={v!r} cannot be rebuilt from data",
                             fix="use TableSchedule / DropSet for replayable faults")

        try:
            return FaultModel(
                schedule=hook(d.get("schedule"), "schedule"),
                crashes={int(k): [int(i) for i in v] for k, v in dict(d.get("crashes") or {}).items()},
                additions={int(k): [(int(i), [float(x) for x in p]) for i, p in v]
                           for k, v in dict(d.get("additions") or {}).items()},
                drop_message=hook(d.get("drop_message"), "drop_message"),
                message_loss=float(d.get("message_loss", 0.0)),
                sensing_noise=hook(d.get("sensing_noise"), "sensing_noise"),
                noise_std=tuple(float(x) for x in d.get("noise_std", (0.0, 0.0))),
                message_delay=int(d.get("message_delay", 0)),
                message_duplication=float(d.get("message_duplication", 0.0)),
                message_reorder=bool(d.get("message_reorder", False)),
            )
        except (TypeError, ValueError, AttributeError) as exc:
            if isinstance(exc, UsageError):
                raise
            raise UsageError(f"faults={dict(d)!r} is malformed ({exc})") from None


@dataclass(frozen=True)
class TableSchedule:
    """A replayable asynchronous schedule: ``table[step]`` lists the IDs that act.

    Steps missing from the table let every present robot act.

    >>> s = TableSchedule({1: (2,)})
    >>> s(1, np.array([1, 2, 3]), None).tolist(), s(0, np.array([1, 2]), None).tolist()
    ([False, True, False], [True, True])
    """

    table: Mapping[int, Sequence[int]]

    __name__ = "table_schedule"

    def __call__(self, step, ids, rng):
        act = self.table.get(int(step))
        if act is None:
            return np.ones(len(ids), dtype=bool)
        return np.isin(ids, np.asarray(list(act), dtype=np.int64))

    def as_dict(self) -> dict:
        return {"kind": "table_schedule",
                "table": {str(k): sorted(int(i) for i in v) for k, v in sorted(self.table.items())}}

    @staticmethod
    def from_dict(d: Mapping) -> "TableSchedule":
        return TableSchedule({int(k): tuple(int(i) for i in v) for k, v in dict(d["table"]).items()})


@dataclass(frozen=True)
class DropSet:
    """Replayable lost messages: the deliveries ``(step, sender_id, receiver_id)`` in ``drops``.

    >>> DropSet({(3, 1, 2)})(3, 1, 2, None), DropSet({(3, 1, 2)})(3, 2, 1, None)
    (True, False)
    """

    drops: frozenset | set

    __name__ = "drop_set"

    def __call__(self, step, sender, receiver, rng) -> bool:
        return (int(step), int(sender), int(receiver)) in self.drops

    def as_dict(self) -> dict:
        return {"kind": "drop_set", "drops": sorted([int(a), int(b), int(c)] for a, b, c in self.drops)}

    @staticmethod
    def from_dict(d: Mapping) -> "DropSet":
        return DropSet(frozenset((int(a), int(b), int(c)) for a, b, c in d["drops"]))
