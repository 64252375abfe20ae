"""Re-run a ``swarmproof-counterexample/1`` file exactly and judge its property again.

The run is rebuilt from the file alone: the bundled lattice (or lattice
file) by name, the algorithm from the registry (or, for an unregistered
class, imported from the ``"module:qualname"`` the file records), the parameters, the initial
poses (radians, bit-exact), the engine seed, the step cap, the data-driven
fault hooks (:meth:`FaultModel.from_dict`) and the property options; the
property is judged with :func:`swarmproof.checkers.explore.judge`, the same
judging the explorer used.  ``reproduced`` is True while the property is
still violated.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError, UsageError

__all__ = ["ReplayResult", "replay", "replay_file", "plot_replay", "gif_replay"]


@dataclass
class ReplayResult:
    """Outcome of a replay."""

    counterexample: Counterexample
    reproduced: bool
    verdict: Any          # InvariantResult
    result: Any           # SimulationResult

    @property
    def step(self):
        return (self.verdict.witness or {}).get("step")

    def as_dict(self) -> dict:
        return {"reproduced": self.reproduced, "property": self.counterexample.property,
                "step": self.step, "message": self.verdict.message, "status": self.verdict.status,
                "recorded_violation": dict(self.counterexample.violation),
                "algorithm": self.counterexample.algorithm, "robots": len(self.counterexample.robots),
                "steps_run": int(self.result.steps)}


def replay(cx: Counterexample, *, file: str | None = None) -> ReplayResult:
    """Re-run ``cx`` and judge its property.

    Raises
    ------
    InputFileError
        The file names an unknown algorithm, lattice or property, or faults
        that cannot be rebuilt.
    """
    from swarmproof.checkers.explore import judge, resolve_algorithm, run_scenario
    from swarmproof.invariants.registry import get_property
    from swarmproof.models import library
    from swarmproof.reference_impl.engine import FaultModel
    from swarmproof.reference_impl.protocol import Params

    def bad(fld, exc, value):
        fix = getattr(exc, "fix", None)
        text = exc.message if hasattr(exc, "message") else str(exc)
        return InputFileError(f"{fld}={value!r}: {text}", file=file, field=fld, fix=fix)

    try:
        get_property(cx.property)
    except UsageError as exc:
        raise InputFileError(exc.message, file=file, field="property", fix=exc.fix) from None
    try:
        spec = resolve_algorithm(cx.algorithm)
    except UsageError as exc:
        raise bad("algorithm", exc, cx.algorithm) from None
    if cx.target is not None:
        # the algorithm's module is imported already (resolve_algorithm), so a kind it registers is known
        from swarmproof.models.targets import target_from_description

        lattice = target_from_description(cx.target, file=file, field_name="target")
    else:
        try:
            lattice = library.resolve(cx.lattice)
        except UsageError as exc:
            raise bad("lattice", exc, cx.lattice) from None
    faults = None
    if cx.faults:
        try:
            faults = FaultModel.from_dict(cx.faults)
        except UsageError as exc:
            raise bad("faults", exc, "...") from None
    p = cx.params
    params = Params(range=float(p["range"]), v=float(p["v"]), omega=float(p["omega"]), dt=float(p["dt"]),
                    extra=dict(p.get("extra") or {}))
    try:
        algorithm, result = run_scenario(spec, lattice, [i for i, _ in cx.robots],
                                         [pose for _, pose in cx.robots], params, seed=cx.seed,
                                         max_steps=cx.max_steps, allow_violations=cx.allow_violations,
                                         faults=faults)
    except InputFileError:
        raise
    except UsageError as exc:
        raise bad("params", exc, cx.params) from None
    verdict = judge(cx.property, algorithm, lattice, params, result, cx.options)
    return ReplayResult(cx, bool(verdict.violated), verdict, result)


def replay_file(path: str | os.PathLike) -> ReplayResult:
    """Load a counterexample file and :func:`replay` it."""
    name = os.fspath(path)
    return replay(Counterexample.load(name), file=name)


def plot_replay(rr, path) -> str:
    """Trajectories of the replayed run, start (o) and end (x) of each robot, the violation step marked."""
    from swarmproof.checkers.plotting import new_figure, save_png

    trace = rr.result.trace
    fig, ax = new_figure()
    step = rr.step
    for k in range(trace.n):
        ax.plot(trace.poses[:, k, 0], trace.poses[:, k, 1], lw=0.8, color="0.6", zorder=1)
        ax.plot(trace.poses[0, k, 0], trace.poses[0, k, 1], "o", ms=4, color="tab:blue", zorder=2)
        ax.plot(trace.poses[-1, k, 0], trace.poses[-1, k, 1], "x", ms=5, color="0.2", zorder=2)
        ax.annotate(str(int(trace.ids[k])), trace.poses[0, k, :2], fontsize=7, zorder=3)
    if step is not None and 0 <= int(step) <= trace.steps:
        s = int(step)
        pres = trace.present_at(s)
        ax.plot(trace.poses[s, pres, 0], trace.poses[s, pres, 1], "o", ms=7, mfc="none", color="tab:red",
                zorder=4, label=f"step {s}: violation")
        ax.legend(loc="best", fontsize=8)
    cx = rr.counterexample
    status = "reproduced" if rr.reproduced else "not reproduced"
    ax.set_title(f"{cx.algorithm} {cx.property} ({status})", fontsize=10)
    ax.set_aspect("equal")
    return save_png(fig, path)


def gif_replay(rr, path) -> str:
    """The replayed run as an animated GIF (:func:`swarmproof.checkers.plotting.animate_trace`)."""
    from swarmproof.checkers.plotting import animate_trace

    cx = rr.counterexample
    status = "reproduced" if rr.reproduced else "not reproduced"
    w = rr.verdict.witness or {}
    named = [w[k] for k in ("robot", "child", "parent", "relocate", "root") if isinstance(w.get(k), int)]
    named += [int(i) for i in w.get("robots", ()) if isinstance(i, int)]
    return animate_trace(rr.result.trace, path, phi=float(cx.params["range"]),
                         mark_step=None if rr.step is None else int(rr.step), mark_ids=named or None,
                         title=f"{rr.result.trace.meta.get('algorithm', cx.algorithm)} {cx.property} ({status})")
