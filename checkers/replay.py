"""Re-run a ``swarmproof-counterexample/1`` file exactly and judge its property again.

The run is rebuilt from the file alone: the bundled lattice (or lattice
file) by name, the algorithm from the registry (or, for an unregistered
class, imported from the ``"module:qualname"`` the file records), the parameters, the initial
poses (radians, bit-exact), the engine seed, the step cap, the data-driven
fault hooks (:meth:`FaultModel.from_dict`) and the property options; the
property is judged with :func:`swarmproof.checkers.explore.judge`, the same
judging the explorer used.  ``reproduced`` is True while the property is
still violated.

Readings: the file records the reading version of the algorithm that made it (``reading``; a
file without one is reading ``"1"``).  When the algorithm now runs another reading, its run is
not the file's, so :func:`replay` refuses it (:class:`InputFileError`, exit 2) and names the
registered reading that reproduces it (``registry.READINGS``), or, when none is registered,
where to get it (``registry.RETIRED_READINGS``, else the swarmproof version that wrote the
file) -- never "no longer reproduces".
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError, UsageError

__all__ = ["ReplayResult", "replay", "replay_file", "plot_replay", "gif_replay", "check_reading"]


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
                "algorithm": self.counterexample.algorithm, "reading": self.counterexample.recorded_reading,
                "robots": len(self.counterexample.robots),
                "steps_run": int(self.result.steps)}


def check_reading(cx: Counterexample, spec, *, file: str | None = None) -> None:
    """Refuse ``cx`` when it was made by another reading of its algorithm than ``spec`` runs now.

    Raises
    ------
    InputFileError
        Field ``reading``: the two readings, and what reproduces the file's -- the registry name
        of that reading (``registry.READINGS``), or the swarmproof release and commit that had it
        (``registry.RETIRED_READINGS``), or, when this swarmproof knows nothing of it, the
        swarmproof version that wrote the file (its ``made_by``).
    """
    from swarmproof.models.versions import tool_versions
    from swarmproof.reference_impl.registry import ALGORITHMS, ALIASES, algorithm_names, find_reading

    then, now = cx.recorded_reading, spec.reading
    if then == now:
        return
    alias = ALIASES.get(cx.algorithm) if cx.algorithm not in ALGORITHMS else None
    if alias is not None and alias.name == spec.label and alias.readings.get(then) == now:
        return          # an old name's reading that its new name runs now (registry.ALIASES)
    recorded = "" if cx.reading is not None else " (not recorded: a file from before readings were versioned)"
    head = (f"reading={then!r}{recorded}: this file was made with reading {then!r} of algorithm={cx.algorithm!r}, "
            f"which runs reading {now!r} here (readings differ on purpose: CHANGELOG.md), so replaying "
            "it here would not tell whether it still reproduces")
    made_by = (cx.made_by or {}).get("swarmproof")
    ours = tool_versions()["swarmproof"]
    if cx.algorithm in algorithm_names() or cx.algorithm in ALIASES:
        other, where = find_reading(cx.algorithm, then)
        if other is not None:
            raise InputFileError(f"{head}; reading {then!r} of {cx.algorithm} is registered as {other!r}",
                                 file=file, field="reading",
                                 fix=f'replay it with that reading: set "algorithm": "{other}" in the file')
        if where is not None:
            raise InputFileError(f"{head}; reading {then!r} of {cx.algorithm} is not registered in this "
                                 f"swarmproof ({ours}); it is in {where}", file=file, field="reading",
                                 fix=f"replay it with {where}")
        raise InputFileError(f"{head}; no reading {then!r} of {cx.algorithm} is registered in this swarmproof "
                             f"({ours})", file=file, field="reading",
                             fix=(f"replay it with the swarmproof that wrote it (made_by.swarmproof={made_by!r}: "
                                  f"check out release {made_by}'s commit of the swarmproof repository and "
                                  "`pip install -e .` there -- swarmproof is not on the package index; "
                                  "CHANGELOG.md lists each release's readings)" if made_by and made_by != "unknown"
                                  else "replay it with the swarmproof release that wrote it (CHANGELOG.md lists "
                                       "each release's readings)"))
    raise InputFileError(f"{head}; {cx.algorithm} is not registered, so no other reading of it is known",
                         file=file, field="reading",
                         fix=f"replay it with the version of {cx.algorithm} that declared reading {then!r}; if "
                             f"its behaviour did not change, set its class's reading back to {then!r}")


def replay(cx: Counterexample, *, file: str | None = None) -> ReplayResult:
    """Re-run ``cx`` and judge its property.

    Raises
    ------
    InputFileError
        The file names an unknown algorithm, lattice or property, or faults
        that cannot be rebuilt, or was made with another reading of the
        algorithm (:func:`check_reading`).
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
    check_reading(cx, spec, file=file)
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
    chooser = None
    if cx.choices is not None:
        from swarmproof.reference_impl.engine.choices import RecordedChoices, check_chooser

        ch = cx.choices
        try:
            chooser = RecordedChoices(ch["kinds"], ch.get("deviations") or [], max_delay=int(ch.get("max_delay", 1)),
                                      max_crashes=int(ch.get("max_crashes", 1)))
            check_chooser(chooser)
        except UsageError as exc:
            raise bad("choices", exc, ch.get("kinds")) from None
    p = cx.params
    params = Params(range=float(p["range"]), v=float(p["v"]), omega=float(p["omega"]), dt=float(p["dt"]),
                    extra=dict(p.get("extra") or {}))
    try:
        algorithm, result = run_scenario(spec, lattice, [i for i, _ in cx.robots],
                                         [pose for _, pose in cx.robots], params, seed=cx.seed,
                                         max_steps=cx.max_steps, allow_violations=cx.allow_violations,
                                         faults=faults, chooser=chooser)
    except InputFileError:
        raise
    except UsageError as exc:
        raise bad("params", exc, cx.params) from None
    misfit = None if chooser is None else chooser.check_end(cx.choices.get("choice_points"))
    if misfit is not None:
        raise InputFileError(f"choices: the run did not make the recorded decisions ({misfit}), so it "
                             "is not the run the file records", file=file, field="choices",
                             fix="replay it with the swarmproof and algorithm version that wrote it (made_by), or "
                                 "restore the file's choices as the search wrote them")
    verdict = judge(cx.property, algorithm, lattice, params, result, cx.options)
    verdict = _before_the_recorded_step(cx, verdict, result)
    return ReplayResult(cx, bool(verdict.violated), verdict, result)


def _before_the_recorded_step(cx: Counterexample, verdict, result):
    """A replay stopped by its step cap before the step its file records the violation at cannot
    say the violation is gone: "held" over fewer steps is inconclusive (exit 3), naming both
    steps.  (A run that ends by itself before that step did change: "held" stands.)"""
    import dataclasses

    at = (cx.violation or {}).get("step")
    if (verdict.status != "held" or result.status != "step_cap" or not isinstance(at, int)
            or isinstance(at, bool) or int(result.steps) >= at):
        return verdict
    return dataclasses.replace(
        verdict, status="inconclusive",
        message=(f"the replayed run ended after {int(result.steps)} steps (max_steps={cx.max_steps}), before "
                 f"step {at}, where the file records the violation: cannot tell whether it still occurs "
                 f"(it held up to step {int(result.steps)}); fix: give max_steps of at least {at} in the file"))


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
    f = None if step is None else trace.frame_of(int(step))    # None: a step the trace did not keep
    if f is not None:
        pres = trace.present_at(f)
        ax.plot(trace.poses[f, pres, 0], trace.poses[f, pres, 1], "o", ms=7, mfc="none", color="tab:red",
                zorder=4, label=f"step {int(step)}: violation")
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
