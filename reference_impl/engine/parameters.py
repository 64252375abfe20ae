"""What a run's parameters may be: the declared ``Params.extra`` keys, meaningful motion, the
target's kind (issue 29: run inputs validated up front).

One code path for every command: the engine's :func:`~swarmproof.reference_impl.engine.run.preflight`
calls these before a run's first step, and :func:`swarmproof.checkers.runs.build_params` (simulate,
explore, campaign, verify) calls them before any run starts.

* :func:`check_extra`: every key of ``Params.extra`` must be declared -- by the algorithm (its class
  attribute ``parameters``, a tuple of :class:`~swarmproof.reference_impl.protocol.ParamSpec`), by
  the engine for the models that read it (:func:`engine_parameters`) or by the checkers
  (``robot_radius``) -- and each value within its declared range.  An algorithm that declares no
  ``parameters`` (a user's algorithm written before declarations existed) is not checked.
* :func:`check_motion`: parameters that make a run meaningless (robots that cannot move, or not
  measurably within a step) are refused, with the reason.
* :func:`check_target_kind`: the target is of a kind the algorithm forms (its class attribute
  ``target_kinds``).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

from swarmproof.models.errors import UsageError, did_you_mean

from ..protocol import ParamSpec, Params

__all__ = ["COMMON_PARAMETERS", "GRID_PARAMETERS", "ASYNC_PARAMETERS", "MIN_STEP_FRACTION", "engine_parameters",
           "declared_parameters", "check_extra", "check_motion", "check_motion_value", "check_target_kind"]

_POS = dict(low=0, low_open=True)

#: Keys every algorithm may be given: the checkers read them whatever the model.
COMMON_PARAMETERS: tuple = (
    ParamSpec("robot_radius", float, None, **_POS,
              meaning="the robots' body radius; the collision property's default radius"),
)

#: Keys the engine reads for ``motion="grid"`` (:mod:`~swarmproof.reference_impl.engine.motion`).
GRID_PARAMETERS: tuple = (
    ParamSpec("grid_spacing", float, 1.0, **_POS, meaning="the distance between grid waypoints"),
    ParamSpec("speed_min", float, None, **_POS, meaning="the slowest robot's speed, default v"),
    ParamSpec("speed_max", float, None, **_POS, meaning="the fastest robot's speed, default v"),
)

#: Keys the engine reads for ``clocks="async"`` (:mod:`~swarmproof.reference_impl.engine.clocks`).
ASYNC_PARAMETERS: tuple = (
    ParamSpec("clock_rate_min", float, 1.0, **_POS, meaning="the slowest local clock's rate"),
    ParamSpec("clock_rate_max", float, None, **_POS, meaning="the fastest local clock's rate, default clock_rate_min"),
    ParamSpec("broadcast_every", float, 1.0, **_POS, meaning="local time units between two broadcasts"),
)

#: A step shorter than this fraction of the range (``v*dt < MIN_STEP_FRACTION * range``) moves a robot
#: by less than the rounding of its coordinates over any step cap: the run could not move measurably.
MIN_STEP_FRACTION = 1e-9


def engine_parameters(model) -> tuple:
    """The ``Params.extra`` keys the engine and the checkers read for robots of ``model``.

    >>> from swarmproof.reference_impl.protocol import RobotModel
    >>> [s.name for s in engine_parameters(RobotModel())]
    ['robot_radius']
    >>> [s.name for s in engine_parameters(RobotModel(motion="grid", clocks="async", sensing="global"))][:3]
    ['robot_radius', 'grid_spacing', 'speed_min']
    """
    out = list(COMMON_PARAMETERS)
    if getattr(model, "motion", None) == "grid":
        out += GRID_PARAMETERS
    if getattr(model, "clocks", None) == "async":
        out += ASYNC_PARAMETERS
    return tuple(out)


def declared_parameters(algorithm) -> dict | None:
    """Name -> :class:`ParamSpec` of every key ``algorithm`` may be given (its own declarations win
    over the engine's), or None when the algorithm declares no ``parameters`` (nothing is checked)."""
    own = getattr(algorithm, "parameters", None)
    if own is None:
        return None
    out = {s.name: s for s in engine_parameters(getattr(algorithm, "model", None))}
    for s in own:
        out[s.name] = s
    return out


def _label(algorithm) -> str:
    return str(getattr(algorithm, "name", None) or type(algorithm).__name__)


def check_extra(algorithm, extra: Mapping[str, Any] | None) -> None:
    """Refuse a key of ``extra`` that ``algorithm`` does not declare, and a value outside its declared
    type or range (:class:`UsageError` naming ``key=value``); nothing is checked for an algorithm
    without ``parameters``.

    Examples
    --------
    >>> from swarmproof.reference_impl.protocol import RobotModel
    >>> class A:
    ...     name, model = "a", RobotModel()
    ...     parameters = (ParamSpec("gap", float, 0.5, low=0, low_open=True, meaning="the gap"),)
    >>> check_extra(A(), {"gap": 0.2, "robot_radius": 0.1})
    >>> check_extra(A(), {"gpa": 0.2})
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: parameter gpa=0.2 is not known to algorithm 'a'; did you mean 'gap'?; fix: use one of its parameters ['gap', 'robot_radius']
    >>> check_extra(A(), {"gap": 0})
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: parameter gap=0 is outside its range (0, inf) (the gap); fix: give gap a value in (0, inf)
    """
    declared = declared_parameters(algorithm)
    if declared is None or not extra:
        return
    for key, value in extra.items():
        spec = declared.get(key)
        if spec is None:
            raise UsageError(f"parameter {key}={value!r} is not known to algorithm {_label(algorithm)!r}"
                             f"{did_you_mean(key, declared)}",
                             fix=f"use one of its parameters {sorted(declared)!r}")
        why = spec.problem(value)
        if why is not None:
            raise UsageError(f"parameter {why}", fix=f"give {key} a value in {spec.range_text()}"
                             if spec.choices is None else f"give {key} {spec.range_text()}")


def check_motion(params: Params, *, prefix: str = "") -> None:
    """Refuse parameters that make a run meaningless, with the reason: ``v`` must be a finite
    number > 0 (robots that cannot move deadlock by construction), ``omega`` a finite number > 0
    (a robot that must turn could never face its goal), ``dt`` a finite number > 0, and a step
    ``v*dt`` finite and at least :data:`MIN_STEP_FRACTION` of the range (a shorter one moves no
    robot measurably).  ``prefix`` is how the caller spells the options (``"--"`` on the command
    line).

    >>> check_motion(Params(range=1.0, v=0.05))
    >>> check_motion(Params(range=1.0, v=0.0), prefix="--")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: --v 0.0 must be > 0: robots that cannot move make the run meaningless (every run would be a deadlock); fix: give a positive speed, e.g. --v 0.05
    >>> check_motion(Params(range=1.0, dt=1e-300))
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: v*dt=5e-302 is below 1e-09 * range=1: no robot could move measurably in a step; fix: give a larger dt or v (v=0.05, dt=1e-300)
    """
    for name in ("v", "omega", "dt"):
        check_motion_value(name, getattr(params, name), prefix=prefix)
    step = params.v * params.dt
    if not math.isfinite(step):
        raise UsageError(f"v*dt={step!r} is not finite (v={params.v!r}, dt={params.dt!r})",
                         fix="give a smaller dt or v")
    rng = params.range
    if isinstance(rng, (int, float)) and math.isfinite(rng) and rng > 0 and step < MIN_STEP_FRACTION * rng:
        raise UsageError(f"v*dt={step:.6g} is below {MIN_STEP_FRACTION:g} * range={rng:g}: no robot could move "
                         "measurably in a step", fix=f"give a larger dt or v (v={params.v!r}, dt={params.dt!r})")


def check_motion_value(name: str, val: Any, *, prefix: str = "--") -> None:
    """One of ``v``, ``omega``, ``dt`` (spelled ``--v`` with the default ``prefix``): a finite number
    > 0, else a :class:`UsageError` saying why a run with it is meaningless.

    >>> check_motion_value("v", -1.0)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: --v -1.0 must be > 0: robots that cannot move make the run meaningless (every run would be a deadlock); fix: give a positive speed, e.g. --v 0.05
    """
    sep = " " if prefix else "="
    example = {"v": "0.05", "omega": "0.785", "dt": "1"}[name]
    if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val):
        raise UsageError(f"{prefix}{name}{sep}{val!r} must be a finite number > 0",
                         fix=f"e.g. {prefix}{name}{sep}{example}")
    if val <= 0:
        why = {"v": "robots that cannot move make the run meaningless (every run would be a deadlock)",
               "omega": "robots that cannot turn make the run meaningless",
               "dt": "a step of no time makes the run meaningless"}[name]
        what = {"v": "a positive speed", "omega": "a positive turn rate", "dt": "a positive step length"}[name]
        raise UsageError(f"{prefix}{name}{sep}{val!r} must be > 0: {why}",
                         fix=f"give {what}, e.g. {prefix}{name}{sep}{example}")


def check_target_kind(algorithm, target, *, where: str = "target") -> None:
    """Refuse a target of a kind ``algorithm`` does not form (its class attribute ``target_kinds``),
    naming the kinds it accepts; an algorithm without ``target_kinds`` takes any.

    >>> class A:
    ...     name, target_kinds = "a", ("lattice",)
    >>> check_target_kind(A(), type("T", (), {"kind": "shape", "name": "letter-l"})())
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: target='letter-l' (shape) is not of a kind algorithm 'a' forms: it takes a lattice target only; fix: give a lattice target, e.g. --target lattice:NAME
    """
    kinds = getattr(algorithm, "target_kinds", None)
    if not kinds or target is None:
        return
    kind = getattr(target, "kind", "lattice")
    if kind in kinds:
        return
    accepted = " or ".join(kinds)
    named = tuple(getattr(algorithm, "explore_targets", None) or ()) + tuple(
        getattr(getattr(algorithm, "verify", None), "targets", None) or ())
    examples = [t if ":" in t else f"lattice:{t}" for t in named if (t.partition(":")[0] if ":" in t else "lattice")
                in kinds]
    example = examples[0] if examples else f"{kinds[0]}:NAME"
    raise UsageError(f"{where}={getattr(target, 'name', target)!r} ({kind}) is not of a kind algorithm "
                     f"{_label(algorithm)!r} forms: it takes a {accepted} target only",
                     fix=f"give a {accepted} target, e.g. --target {example}")
