"""verify's ``recorded`` section: recorded runs judged as rows of the property matrix (issue 34).

Each log of a folder's manifest (:mod:`swarmproof.models.recorded_runs`) is judged as
``swarmproof check-run`` judges it (:func:`swarmproof.checkers.recorded.judge_log`); each property
is one row, subject ``recorded <name>``, compared with the baseline like every other row -- so a
team gates its CI on its own recorded runs: a known finding of a log (a split it recorded) is a
baseline row that keeps the gate green, and a change of verdict fails it.  Which rows decide the
gate: the manifest's ``claims`` if it lists them, else the algorithm's claims with
``algorithm``, else every judged row.  Without ``--recorded`` verify judges the runs swarmproof
ships (``models/recorded/``).
"""

from __future__ import annotations

import os
import shlex

from swarmproof.models.verdict import Verdict

__all__ = ["recorded_cells", "check_run_command", "check_manifest"]

_STATUS = {"held": Verdict.HELD, "violated": Verdict.VIOLATED, "inconclusive": Verdict.INCONCLUSIVE}
_OPTION = {"range": "--range", "target": "--target", "algorithm": "--algorithm", "topics": "--topics",
           "parent_topics": "--parent-topics", "state_topics": "--state-topics", "time": "--time", "period": "--period", "stale": "--stale",
           "pos_tol": "--pos-tol", "range_margin": "--range-margin", "collision_margin": "--collision-margin",
           "radius": "--radius", "static_window": "--static-window", "v": "--v"}


def check_run_command(run) -> str:
    """The ``swarmproof check-run`` command that repeats a run's rows.

    >>> from swarmproof.models.recorded_runs import RecordedRun
    >>> check_run_command(RecordedRun("a", "/logs/a.csv", {"range": 1.2, "pos_tol": 0.02}, ("connectivity",)))
    'swarmproof check-run /logs/a.csv --range 1.2 --pos-tol 0.02 --property connectivity'
    """
    parts = ["swarmproof", "check-run", _display(run.log)]
    for key, opt in _OPTION.items():
        if key in run.options:
            v = run.options[key]
            parts += [opt, f"{v:g}" if isinstance(v, float) else str(v)]
    for p in run.properties or ():
        parts += ["--property", p]
    return " ".join(shlex.quote(x) for x in parts)


def check_manifest(manifest) -> None:
    """The names a manifest gives, checked before any log is read, each refused at its run's line:
    properties and claims known, claims among the run's properties, the target and algorithm known."""
    from swarmproof.invariants.registry import get_property
    from swarmproof.models.errors import InputFileError, UsageError

    for i, run in enumerate(manifest.runs):
        def fail(field, exc_or_text, fix=None):
            text = exc_or_text.message if isinstance(exc_or_text, UsageError) else exc_or_text
            raise InputFileError(text, file=manifest.source, line=run.line, field=f"runs[{i}].{field}",
                                 fix=fix or getattr(exc_or_text, "fix", None) or "see docs/recorded-runs.md")
        for key in ("properties", "claims"):
            for j, name in enumerate(getattr(run, key) or ()):
                try:
                    get_property(name)
                except UsageError as exc:
                    fail(f"{key}[{j}]", exc)
        for j, name in enumerate(run.claims or ()):
            if run.properties is not None and name not in run.properties:
                fail(f"claims[{j}]", f"claims entry {name!r} is not among the run's properties {list(run.properties)}",
                     "claim only properties the run judges (add it to properties)")
        try:
            if "target" in run.options:
                from swarmproof.models.targets import resolve_target

                resolve_target(run.options["target"])
            if "algorithm" in run.options:
                from swarmproof.checkers.algorithm_spec import resolve_algorithm

                resolve_algorithm(run.options["algorithm"])
        except UsageError as exc:
            fail("target" if "target" in str(exc.message) and "algorithm" not in str(exc.message) else "algorithm", exc)


def _display(path: str) -> str:
    """A log's path as rows show it: relative to the working folder when below it (stable files)."""
    rel = os.path.relpath(path)
    return path if rel.startswith("..") else rel


def recorded_cells(*, folders=None, progress=None) -> list:
    """One cell per (recorded run, property) of each folder's manifest (default: the bundled runs):
    ``(subject, property, verdict or None, detail, data, claim)``; verdict None is not applicable
    (the reason in the detail).  :func:`swarmproof.checkers.report.section_recorded` makes them rows."""
    from swarmproof.checkers.recorded import fmt_s, judge_log
    from swarmproof.models.recorded_runs import bundled_folder, load_recorded_runs

    rows = []
    for folder in (folders or [bundled_folder()]):
        manifest = load_recorded_runs(folder)
        check_manifest(manifest)
        for run in manifest.runs:
            if progress:
                progress(run.name)
            opts = dict(run.options)
            rep, claims = judge_log(run.log, properties=list(run.properties) if run.properties else None,
                                    range=opts.pop("range", None), target=opts.pop("target", None),
                                    algorithm=opts.pop("algorithm", None), topics=opts.pop("topics", None),
                                    parent_topics=opts.pop("parent_topics", None), time=opts.pop("time", None),
                                    state_topics=opts.pop("state_topics", None),
                                    **opts)
            subject = f"recorded {run.name}"
            clock = rep.clock
            data = {"file": _display(run.log), "format": rep.log.format, "robots": len(rep.log.robots),
                    "instants": clock.instants, "judged_instants": rep.judged_instants,
                    "period_s": clock.period_ns / 1e9, "stale_s": clock.stale_ns / 1e9,
                    "tolerance": dict(rep.tolerance), "reproduce": check_run_command(run)}

            def claim_of(prop):
                if run.claims is not None:
                    return f"{run.name}: claimed in {os.path.basename(manifest.source)}" if prop in run.claims else None
                if claims is not None:
                    return claims.get(prop)
                return f"{run.name}: every judged property (no claims listed in {os.path.basename(manifest.source)})"

            for prop, why in rep.not_applicable.items():
                if run.properties is None and prop in ("no_crash", "invariants", "completion_sound"):
                    continue          # never given by a log: listed by check-run, not rows of every run
                rows.append((subject, prop, None, why, data, claim_of(prop)))
            for prop, r in rep.results.items():
                sens = rep.sensitive.get(prop)
                detail = r.message + (" [depends on the tolerance]" if sens else "") + \
                    f" (clock {fmt_s(clock.period_ns / 1e9)} s, {rep.judged_instants} of {clock.instants} instants judged)"
                rd = {**data, "tolerance_sensitive": sens}
                if r.witness:
                    rd["violation"] = {k: v for k, v in r.witness.items() if k in ("step", "time_s", "robots",
                                                                                      "components", "child", "parent")}
                rows.append((subject, prop, _STATUS.get(r.status, Verdict.INCONCLUSIVE), detail, rd, claim_of(prop)))
    return rows
