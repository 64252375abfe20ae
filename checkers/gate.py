"""The CI gate: one ``verify`` run compared with a baseline, shared by the command and the pytest plugin.

:func:`verify` runs the report's sections (:mod:`swarmproof.checkers.report`)
over the bundled library or the named algorithms, compares the rows with a
baseline (:mod:`swarmproof.checkers.baseline`) and, on request, rewrites it.
``swarmproof verify`` parses options into a call of it; the pytest fixture
``swarmproof_verify`` calls it from a user's test.

Examples
--------
>>> rep = verify(sections=["lattices"])
>>> rep.exit_code, rep.comparison is None
(0, True)
"""

from __future__ import annotations

import os
from typing import Any, Sequence

from swarmproof.models.errors import UsageError

__all__ = ["verify", "resolve_gate"]


def resolve_gate(baseline, *, max_examples: int | None = None, robots=None, seed: int | None = None,
                 rewriting: bool = False) -> dict[str, Any]:
    """The exploration parameters: those given, else the baseline's gate, else the defaults.

    Raises
    ------
    UsageError
        A bad value, or one that differs from the baseline's gate (the rows
        would not compare) unless the baseline is being rewritten.
    """
    from swarmproof.checkers import report

    given = {"max_examples": max_examples, "seed": seed, "robots": None if robots is None else list(robots)}
    if max_examples is not None and (isinstance(max_examples, bool) or not isinstance(max_examples, int)
                                     or max_examples < 1):
        raise UsageError(f"--max-examples {max_examples!r} must be >= 1", fix="e.g. --max-examples 200")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise UsageError(f"--seed {seed!r} must be >= 0", fix="e.g. --seed 0")
    defaults = {"max_examples": report.VERIFY_EXPLORE_MAX_EXAMPLES, "seed": report.VERIFY_EXPLORE_SEED,
                "robots": list(report.VERIFY_EXPLORE_ROBOTS)}
    stored = dict(baseline.gate) if baseline is not None else {}
    gate: dict[str, Any] = {}
    for k, default in defaults.items():
        if given[k] is None:
            gate[k] = stored.get(k, default)
            continue
        if k in stored and stored[k] != given[k] and not rewriting:
            opt = "--" + k.replace("_", "-")
            raise UsageError(f"{opt} {given[k]!r} differs from the baseline's gate ({k}={stored[k]!r} in "
                             f"{baseline.path})", fix=f"drop {opt} (the gate's value is used), or rewrite the "
                                                      "baseline with --update-baseline")
        gate[k] = given[k]
    return gate


def _recorded_subjects(recorded) -> set | None:
    """The row subjects of the ``--recorded`` folders (None without them): each manifest checked,
    and a run name given twice across folders refused (their rows would overwrite each other)."""
    if recorded is None:
        return None
    from swarmproof.checkers.recorded_rows import check_manifest
    from swarmproof.models.recorded_runs import load_recorded_runs

    seen: dict = {}
    for folder in recorded:
        manifest = load_recorded_runs(folder)
        check_manifest(manifest)
        for run in manifest.runs:
            if run.name in seen:
                raise UsageError(f"run name={run.name!r} is in {seen[run.name]} and in {manifest.source}: their rows "
                                 "would be one row", fix="give the runs distinct names (name: in the manifests)")
            seen[run.name] = manifest.source
    return {f"recorded {name}" for name in seen}


def _scope(sections, subjects, properties, recorded_subjects=None):
    """Whether a baseline row is one this run would produce (rows outside are left alone; with
    ``--recorded`` folders, the recorded rows of other runs -- e.g. the bundled ones -- too)."""
    labels = {s.label for s in subjects}
    props = None if properties is None else set(properties)

    def in_scope(e) -> bool:
        if e.section not in sections:
            return False
        if e.section == "recorded" and recorded_subjects is not None:
            return e.subject in recorded_subjects
        if e.section in ("algorithms", "exploration", "exhaustive"):
            if e.algorithm is not None and e.algorithm not in labels:
                return False
            if props is not None and e.property not in props:
                return False
        return True
    return in_scope


def verify(*, algorithms: Sequence[str] | None = None, sections: Sequence[str] | None = None,
           properties: Sequence[str] | None = None, baseline: str | os.PathLike | None = None,
           update_baseline: bool = False, strict: bool = False, max_examples: int | None = None,
           robots=None, seed: int | None = None, out_dir: str | None = None, progress=None,
           workers: int | None = None, recorded: Sequence[str] | None = None):
    """One ``verify`` run, compared with ``baseline`` when given; returns the
    :class:`~swarmproof.checkers.report.Report` (``report.comparison`` holds the comparison).

    Parameters
    ----------
    algorithms : list of str, optional
        Registry names or ``module:qualname`` of users' classes (default: the
        bundled library).  With them the default sections are ``algorithms``
        and ``exploration``.
    sections, properties : list of str, optional
        Which sections run; which properties the ``algorithms`` and
        ``exploration`` rows check.
    baseline : path, optional
        A ``swarmproof-baseline/1`` file.  Its gate (the exploration
        parameters) is used unless ``max_examples``, ``robots`` or ``seed``
        say the same; another value is a usage error unless ``update_baseline``.
    update_baseline : bool
        Write this run's verdicts into ``baseline`` (created if missing; rows
        outside this run's scope kept).  The returned comparison is then
        against the new file (``report.updated`` says how many rows differed).
    strict : bool
        Improvements and resized counterexamples fail; a baseline row that no
        longer exists is an error (UsageError, after the run).
    recorded : list of folders, optional
        Folders of recorded runs with their ``recorded-runs.yaml`` (docs/recorded-runs.md): the
        ``recorded`` section judges them instead of the bundled runs (and runs beside
        ``algorithms`` when those are given).

    Raises
    ------
    UsageError
        Bad options, an unreadable baseline (InputFileError), an unwritable
        baseline or ``out_dir`` (before anything runs).
    """
    from swarmproof.checkers import report as report_mod
    from swarmproof.checkers.baseline import Baseline, compare
    from swarmproof.models.fileio import check_output_path

    if update_baseline and baseline is None:
        raise UsageError("--update-baseline needs --baseline FILE (the file to write)",
                         fix="e.g. --baseline verify-baseline.json --update-baseline")
    if strict and baseline is None:
        raise UsageError("--strict needs --baseline FILE", fix="e.g. --baseline verify-baseline.json --strict")
    base = None
    path = None if baseline is None else os.fspath(baseline)
    if path is not None:
        if update_baseline:
            check_output_path(path, "--baseline")
        if not (update_baseline and not os.path.exists(path)):
            base = Baseline.load(path)
    if out_dir is not None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(out_dir, "--out")
    gate = resolve_gate(base, max_examples=max_examples, robots=robots, seed=seed, rewriting=update_baseline)
    if sections is not None:
        for name in sections:
            if name not in report_mod.SECTIONS:
                raise UsageError(f"section={name!r} is not known", fix=f"use one of {list(report_mod.SECTIONS)!r}")
    explore_props = None
    if properties is not None:
        from swarmproof.checkers.explore import explore_properties

        registered = list(explore_properties())     # and the own properties of the algorithms verified
        for s in report_mod.verify_subjects(None if algorithms is None else tuple(algorithms)):
            if s.declared is not None:
                registered += [p for p in explore_properties(s.declared) if p not in registered]
        known = set(registered) | set(report_mod.RUN_PROPERTIES)
        for prop in properties:
            if prop not in known:
                raise UsageError(f"--property {prop!r} is not a property of verify's rows",
                                 fix=f"use one of {sorted(known)!r}")
        properties = list(properties)
        explore_props = [p for p in registered if p in properties]
    subjects = report_mod.verify_subjects(None if algorithms is None else tuple(algorithms))
    recorded_subjects = _recorded_subjects(recorded)        # a bad manifest: refused before any row runs
    wanted = sections or ((["algorithms", "exploration", "exhaustive"] + (["recorded"] if recorded else []))
                          if algorithms else list(report_mod.SECTIONS))
    ordered = [s for s in report_mod.SECTIONS if s in wanted]
    if "exploration" in ordered:      # team sizes the explorer cannot draw: refused before any row runs
        from swarmproof.checkers.algorithm_spec import resolve_algorithm
        from swarmproof.checkers.explore import check_explore_robots

        for s in subjects:
            if algorithms or s.plan.explore:
                check_explore_robots(tuple(gate["robots"]), resolve_algorithm(s.ref).factory)
    rep = report_mod.run_report(ordered, progress=progress, options={
        "exploration": {"max_examples": gate["max_examples"], "robots": tuple(gate["robots"]),
                        "seed": gate["seed"], "out_dir": out_dir, "properties": explore_props,
                        "subjects": [s for s in subjects if algorithms or s.plan.explore],
                        "workers": workers},
        "algorithms": {"out_dir": out_dir, "subjects": subjects, "properties": properties},
        "exhaustive": {"out_dir": out_dir, "subjects": subjects},
        "recorded": {"out_dir": out_dir, "folders": None if recorded is None else list(recorded)}})
    in_scope = _scope(ordered, subjects, properties, recorded_subjects)
    if base is not None:
        rep.comparison = compare(rep.rows, base, in_scope=in_scope, strict=strict)
    if update_baseline:
        fresh = Baseline.from_rows(rep.rows, gate)
        new = base.merged(fresh, in_scope) if base is not None else fresh
        new.path = path
        new.save(path)
        differ = 0 if rep.comparison is None else sum(c.outcome not in ("same", "known")
                                                      for c in rep.comparison.changes)
        rep.updated = (f"verify: baseline written to {path} ({len(new.rows)} rows"
                       + (f"; {differ} differed from the previous one" if base is not None else "") + ")")
        rep.comparison = compare(rep.rows, new, in_scope=in_scope)   # the gate as it now stands
    return rep


def check_gone(rep, strict: bool, baseline_path) -> None:
    """With ``strict``, a baseline row this run no longer produced is an error (exit 2)."""
    gone = rep.comparison.of("gone") if rep.comparison is not None else []
    if gone and strict:
        k = gone[0].key
        raise UsageError(f"{len(gone)} row(s) of --baseline {baseline_path} no longer exist in this run "
                         f"(first: {k[0]}: {k[1]} / {k[2]})",
                         fix="rewrite the baseline on purpose with --update-baseline, or drop --strict")
