"""The verification report behind ``swarmproof verify``: one property matrix.

Each *section* is a function returning :class:`Row` s; a row is one subject
(a lattice, an algorithm on a lattice, a lemma) and one property, with a
three-valued verdict and a short detail.  The report's verdict is the worst
row (violated > inconclusive > held > proved), and the exit code follows
(DESIGN.md section 2).

Sections (they grow with the project):

* ``lattices`` — every bundled lattice checked at its recommended range by
  the lattice-graph checker (001 Defs. 1 and 4);
* ``algorithms`` — each reference implementation run on each periodic
  lattice of the papers from seeded connected starts, with its claims
  checked (terminates, satisfies the lattice, stays connected);
* ``lemmas`` — the z3 proof suite (:func:`swarmproof.checkers.proofs.run_suite`),
  one row per lemma: ``proved`` / ``counterexample`` / ``inconclusive`` map to
  ``proved`` / ``violated`` / ``inconclusive``;
* ``exploration`` — the Hypothesis explorer
  (:func:`swarmproof.checkers.explore.explore`) on each reference
  implementation and each explorer property, read at run time: ``held`` (over
  what was explored, never proved), ``violated`` with the counterexample, or
  ``inconclusive``; a time budget that was hit is never a pass.

A property the algorithm cannot give what it needs for (its ``needs`` against the
algorithm's declarations, :mod:`swarmproof.invariants.capabilities`) gets a row marked
``n/a`` (:data:`~swarmproof.models.verdict.NOT_APPLICABLE`) that names what is missing: no
verdict, counted apart, never run (DESIGN.md section 5, "Not applicable").

Rows of properties a paper does not claim (the algorithm class's ``claims``,
:func:`~swarmproof.reference_impl.registry.claims_of`) are findings: shown, marked ``*``, not counted in the verdict.
Wall-clock seconds stay out of the JSON, so the same inputs give a
bit-identical document.

Examples
--------
>>> r = Report([Row("lattices", "square", "self-consistent", Verdict.HELD, "ok")])
>>> r.verdict, r.exit_code
(<Verdict.HELD: 'held'>, 0)

References
----------
001_7a4e517b856331bc.txt Defs. 1, 2, 4, Lemma 11, Thm. 13; 000_3ad33c5b62f11d5f.txt
Lemma 7 (the claims the rows check).
"""

from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass, field
from typing import Any, Callable

from swarmproof.checkers.runs import RUN_PROPERTIES, run_counterexample, run_property_verdicts
from swarmproof.models.errors import UsageError
from swarmproof.models.verdict import NOT_APPLICABLE, Verdict

__all__ = ["Row", "Report", "SECTIONS", "run_report", "lemma_rows", "exploration_row",
           "section_lattices", "section_algorithms", "section_lemmas", "section_formulas", "section_exploration"]

#: A progress callback: receives one short status text (what runs now).
Progress = Callable[[str], None]


@dataclass(frozen=True)
class Row:
    """One cell of the property matrix."""

    section: str
    subject: str
    property: str
    verdict: Verdict
    detail: str = ""
    data: dict[str, Any] = field(default_factory=dict, compare=False)
    #: Where the paper claims this property; None when it does not (the row is
    #: then a finding about the algorithm and does not decide the exit code).
    claim: str | None = "claimed"
    #: The counterexample of a violated algorithm or exploration row (a
    #: :class:`~swarmproof.models.counterexample.Counterexample`), for the HTML
    #: report; not in JSON (the file it was saved to is, as ``counterexample``).
    artifact: Any = field(default=None, compare=False, repr=False)
    #: The seed key of the algorithm's paper (its class's ``paper``), None for a class without
    #: one (a user's): the legend says "not claimed by the paper" only of the former.
    paper: str | None = field(default=None, compare=False, repr=False)

    @property
    def claimed(self) -> bool:
        return self.claim is not None

    @property
    def applicable(self) -> bool:
        """False for a row marked n/a (:data:`~swarmproof.models.verdict.NOT_APPLICABLE`)."""
        return self.verdict is not NOT_APPLICABLE

    def to_json(self) -> dict[str, Any]:
        return {"section": self.section, "subject": self.subject, "property": self.property,
                "verdict": self.verdict.value, "detail": self.detail, "claim": self.claim,
                **self.data}


@dataclass
class Report:
    rows: list[Row]
    seconds: dict[str, float] = field(default_factory=dict)
    #: The comparison with a baseline (``verify --baseline``,
    #: :class:`~swarmproof.checkers.baseline.Comparison`), None without one.
    comparison: Any = None
    #: What ``--update-baseline`` wrote (one line), '' otherwise.
    updated: str = ""

    @property
    def verdict(self) -> Verdict:
        """Worst verdict over the rows that check a claim (unclaimed rows are findings; n/a rows
        have no verdict)."""
        return Verdict.combine(r.verdict for r in self.rows if r.claimed and r.applicable)

    def counts(self) -> dict[str, int]:
        """Rows per verdict, and the not-applicable rows apart (``"n/a"``)."""
        out = {v.value: sum(r.verdict is v for r in self.rows) for v in Verdict}
        out[NOT_APPLICABLE.value] = sum(not r.applicable for r in self.rows)
        return out

    def counts_text(self) -> str:
        """``"3 proved, 5 held, 1 violated, 0 inconclusive"``, then ``"; 2 n/a (not applicable)"``
        when there are such rows: n/a is counted apart, never with inconclusive."""
        n = self.counts()
        text = ", ".join(f"{n[v.value]} {v.value}" for v in Verdict)
        if n[NOT_APPLICABLE.value]:
            text += f"; {n[NOT_APPLICABLE.value]} n/a (not applicable)"
        return text

    def legend(self) -> str:
        """The line under the table that explains ``*``, '' when no row is marked: "not claimed
        by the paper" only when every unclaimed row's algorithm has a paper."""
        rows = [r for r in self.rows if not r.claimed and r.applicable]
        if not rows:
            return ""
        papers = {r.paper is not None for r in rows}
        by = {frozenset({True}): "not claimed by the paper", frozenset({False}): "not claimed by the algorithm"}.get(
            frozenset(papers), "not claimed (by the paper; by the algorithm for a class without one)")
        return f"* {by}: a finding about the algorithm, not counted in the verdict"

    @property
    def exit_code(self) -> int:
        """The claims' verdict's code, or the baseline comparison's when there is one."""
        if self.comparison is not None:
            return self.comparison.exit_code
        return self.verdict.exit_code

    def outcome(self, row: Row) -> str | None:
        """How ``row`` compares with the baseline (None without one)."""
        if self.comparison is None:
            return None
        return self.comparison.outcome_of((row.section, row.subject, row.property))

    def assert_no_regression(self) -> "Report":
        """Raise ``AssertionError`` unless the gate passes (exit code 0): with a baseline, no
        regression and nothing inconclusive; without one, every claimed row held or proved.

        The message is the summary line, then each failing row with its counterexample as steps
        and the command that replays or repeats it (a test helper: the pytest plugin's
        ``swarmproof_verify`` fixture returns reports)."""
        __tracebackhide__ = True
        if self.exit_code == 0:
            return self
        from swarmproof.checkers.ci_outputs import row_status, row_steps, summary_line

        lines = [summary_line(self)]
        for r in self.rows:
            kind, message = row_status(self, r)
            if kind in ("failure", "error"):
                lines.append(f"{r.section}: {r.subject} / {r.property}: {r.verdict.value} -- {message}")
                lines.append(f"  {r.detail}")
                lines += ["  " + s for s in row_steps(r)]
        from swarmproof.models.citations import readable

        raise AssertionError(readable("\n".join(lines)))

    def to_json(self, *, timings: bool = False) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "verdict": self.verdict.value,
            "rows": [r.to_json() for r in self.rows],
            "counts": self.counts(),
            "findings": sum(r.verdict is Verdict.VIOLATED and not r.claimed for r in self.rows),
            "exit_code": self.exit_code,
        }
        why = self.nothing_claimed()
        if why:
            doc["reason"] = why[2:]     # why "inconclusive": nothing was judged
        if self.comparison is not None:
            doc["baseline"] = self.comparison.to_json()
            for row_doc, r in zip(doc["rows"], self.rows):
                row_doc["baseline"] = self.outcome(r)
        if timings:  # wall-clock figures break bit-identical JSON, so only on request
            doc["seconds"] = {k: round(v, 3) for k, v in self.seconds.items()}
        return doc

    def format_table(self) -> str:
        """A fixed-width table, grouped by section, then a one-line summary."""
        lines: list[str] = []
        w_subj = max([len(r.subject) for r in self.rows] + [7])
        w_prop = max([len(r.property) for r in self.rows] + [8])
        current = None
        for r in self.rows:
            if r.section != current:
                current = r.section
                if lines:
                    lines.append("")
                secs = self.seconds.get(current)
                lines.append(f"== {current}" + (f" ({secs:.1f} s)" if secs is not None else ""))
                lines.append(f"{'subject':<{w_subj}}  {'property':<{w_prop}}  {'verdict':<12}  detail")
            mark = "" if r.claimed or not r.applicable else "*"
            outcome = self.outcome(r)
            shown = "" if outcome in (None, "same") else f"[{outcome}] "
            lines.append(f"{r.subject:<{w_subj}}  {r.property:<{w_prop}}  "
                         f"{r.verdict.value + mark:<12}  {shown}{r.detail}")
        counts = self.counts_text()
        lines.append("")
        if self.legend():
            lines.append(self.legend())
        if self.comparison is not None:
            block = self.comparison.lines()
            if block:
                lines.extend(block + [""])
            lines.append(f"claims alone: {self.verdict.value} ({counts})")
            lines.append(self.comparison.summary_line())
        else:
            lines.append(f"verify: {self.verdict.value.upper()} ({counts}){self.nothing_claimed()}")
        return "\n".join(lines)

    def nothing_claimed(self) -> str:
        """Why the verdict is inconclusive when no applicable row checks a claim (nothing was judged:
        never a pass), as a tail for the summary line; '' otherwise."""
        if any(r.claimed and r.applicable for r in self.rows):
            return ""
        subjects = sorted({str(r.data.get("algorithm") or r.subject) for r in self.rows if r.applicable})
        if not subjects:
            return ": every row is not applicable, so nothing was judged"
        return (f": no row checks a claim ({', '.join(subjects)} claim{'s' if len(subjects) == 1 else ''} none of "
                "these properties), so nothing was judged; the rows marked * are findings (give your class a "
                "`claims` mapping, property -> citation, to have them judged: docs/explorer.md)")


# ---------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------

def _count(n: int, noun: str) -> str:
    """``_count(1, 'role') == '1 role'``, ``_count(2, 'role') == '2 roles'``."""
    return f"{n} {noun}" + ("" if n == 1 else "s")


def section_lattices(*, progress: Progress | None = None) -> list[Row]:
    """Every bundled lattice at its recommended range (001 Defs. 1, 4)."""
    from swarmproof.checkers.lattice_check import check_lattice
    from swarmproof.models import library

    rows = []
    for name in library.names():
        if progress:
            progress(name)
        g = library.load(name)
        rep = check_lattice(g)
        cls = rep.classification
        detail = (f"phi={g.range:g}, {_count(len(g.roles), 'role')}, {_count(len(g.edges), 'edge')}, "
                  f"{cls['kind']} (rotation order {cls['rotation_order']}, "
                  f"rank {cls['translation_rank']})")
        if rep.defects:
            detail += f"; {len(rep.defects)} defect(s): {rep.defects[0].kind}"
        rows.append(Row("lattices", name, "valid and self-consistent", rep.verdict, detail,
                        {"range": g.range, "classification": cls,
                         "defects": [d.kind for d in rep.defects]}, claim="001 Defs. 1, 4"))
    return rows


#: The algorithm rows: each registered algorithm whose class declares a
#: ``verify`` plan (:func:`~swarmproof.reference_impl.registry.verify_plans`), on
#: the plan's targets, its robots from the seeded connected starts of its seeds.
#: Small on purpose: ``make verify`` must stay within 10 minutes; the acceptance
#: runs (``make test-slow``) go wider.


def verify_algorithms() -> tuple[str, ...]:
    """The algorithms verify has rows for, in report order."""
    return tuple(s.label for s in verify_subjects())


@dataclass(frozen=True)
class Subject:
    """One algorithm ``verify`` has rows for.

    ``label`` names its rows (the registry name, or the class's ``name``);
    ``ref`` is what commands and counterexample files name (the registry
    name, or ``module:qualname`` of a user's class); ``plan`` its
    :class:`~swarmproof.reference_impl.protocol.VerifyPlan`; ``claims`` property -> citation.
    """

    label: str
    ref: str
    plan: Any
    claims: dict = field(default_factory=dict)
    #: What declares the algorithm's capabilities (its class, or an object a factory built):
    #: :func:`not_applicable` reads its model and class attributes.
    declared: Any = field(default=None, compare=False, repr=False)

    @property
    def paper(self) -> str | None:
        paper = getattr(self.declared, "paper", None)
        return paper if isinstance(paper, str) and paper else None

    def not_applicable(self, prop: str, target=None) -> str | None:
        """Why ``prop`` is not applicable to this algorithm (None: it is, or may be)."""
        from swarmproof.invariants.registry import get_property

        if self.declared is None:
            return None
        return get_property(prop).not_applicable_to(self.declared, target)


def _declared(spec):
    """The object whose declarations say what ``spec``'s algorithm can give: its class, or for a
    factory function the object it builds."""
    return spec.factory if isinstance(spec.factory, type) else spec.build()


def not_applicable_row(section: str, subject: str, prop: str, reason: str, data: dict, claim: str | None,
                       paper: str | None = None) -> Row:
    """A row marked n/a: no verdict; the detail and ``not_applicable`` in JSON say what is missing.

    >>> r = not_applicable_row("algorithms", "jiang pattern:x n=12", "connectivity", "no range graph", {}, None)
    >>> r.verdict, r.detail, r.to_json()["verdict"], r.to_json()["not_applicable"]
    (NOT_APPLICABLE, 'not applicable: no range graph', 'n/a', 'no range graph')
    """
    return Row(section, subject, prop, NOT_APPLICABLE, f"not applicable: {reason}",
               {**data, "not_applicable": reason}, claim=claim, paper=paper)


def verify_subjects(refs=None) -> list[Subject]:
    """The algorithms of the ``algorithms`` and ``exploration`` rows.

    Default: every registered algorithm whose class declares a ``verify``
    plan, in the plans' rank order.  ``refs`` (``verify --algorithm REF``):
    just those -- registry names or ``module:qualname`` of a user's class --
    each with its own claims, plan and scenarios; a class without a ``verify``
    plan gets ``VerifyPlan()`` (exploration rows only: no target to run on).

    Raises
    ------
    UsageError
        An unknown name or unimportable reference, or two references with one label.
    """
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.reference_impl import registry
    from swarmproof.reference_impl.protocol import VerifyPlan

    if refs is None:
        return [Subject(name, name, plan, registry.claims_of(name), registry.algorithm_factory(name))
                for name, plan in registry.verify_plans()]
    out: list[Subject] = []
    for ref in refs:
        spec = resolve_algorithm(ref)
        plan = getattr(spec.factory, "verify", None)
        if not isinstance(plan, VerifyPlan):
            plan = VerifyPlan()
        if any(s.label == spec.label for s in out):
            raise UsageError(f"--algorithm {ref!r}: another --algorithm already has the name {spec.label!r}",
                             fix="give each algorithm once (rows are named by the class's `name`)")
        out.append(Subject(spec.label, spec.ref, plan, dict(spec.claims), _declared(spec)))
    return out


def simulate_command(algorithm: str, target: str, robots: int, seed: int) -> str:
    """The ``swarmproof simulate`` command line that repeats one run of an ``algorithms`` row.

    >>> simulate_command("song2016-literal", "hexagon", 40, 2)
    'swarmproof simulate song2016-literal --target hexagon --robots 40 --seed 2'
    """
    return f"swarmproof simulate {algorithm} --target {target} --robots {robots} --seed {seed}"


def section_algorithms(*, progress: Progress | None = None, out_dir: str | None = None,
                       subjects: list[Subject] | None = None, properties=None) -> list[Row]:
    """Each reference implementation on each lattice: its claims, run by run (001, 000).

    A violated row names the ``swarmproof simulate`` command that repeats its first
    violated run (``reproduce`` in JSON); with ``out_dir`` that run is also written as a
    counterexample file for ``swarmproof replay`` (``counterexample`` in JSON).
    ``subjects`` (default :func:`verify_subjects`) and ``properties`` (default
    :data:`RUN_PROPERTIES`) choose the rows."""
    import os

    from swarmproof.checkers.explore import _safe
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.models.targets import resolve_target

    wanted = RUN_PROPERTIES if properties is None else tuple(p for p in RUN_PROPERTIES if p in properties)
    rows = []
    for subj in (verify_subjects() if subjects is None else subjects):
        algo, claims = subj.label, subj.claims
        for lname, robots, seeds in subj.plan.runs():
            lattice = resolve_target(lname, prefer="lattice")   # plans name lattices by bare names
            base = {"algorithm": algo, "lattice": lname, "robots": robots, "seeds": list(seeds)}
            if subj.ref != algo:
                base["ref"] = subj.ref
            na = {p: subj.not_applicable(p, lattice) for p in wanted}
            per_prop: dict[str, list[tuple[int, Verdict, str]]] = {p: [] for p in wanted if na[p] is None}
            first_bad: dict[str, Any] = {}
            for seed in (seeds if per_prop else ()):     # nothing applicable: nothing to run
                if progress:
                    progress(f"{algo} {lname} n={robots} seed {seed}")
                checked = run_and_check(subj.ref, lattice, seed=seed, robots=robots)
                for prop, (verdict, msg) in run_property_verdicts(checked).items():
                    if prop not in per_prop:
                        continue
                    per_prop[prop].append((seed, verdict, msg))
                    if verdict is Verdict.VIOLATED and prop not in first_bad:
                        first_bad[prop] = (seed, checked, msg)
            for prop in wanted:
                if na[prop] is not None:
                    rows.append(not_applicable_row("algorithms", f"{algo} {lname} n={robots}", prop, na[prop],
                                                   dict(base), claims.get(prop), subj.paper))
                    continue
                results = per_prop[prop]
                verdict = Verdict.combine(v for _, v, _ in results)
                held = sum(v.passed for _, v, _ in results)
                detail = f"{held}/{len(results)} runs held"
                worst = next(((s, m) for s, v, m in results if v is verdict and not v.passed), None)
                if worst is not None:
                    detail += f"; seed {worst[0]}: {worst[1]}"
                data = dict(base)
                cx = None
                if verdict is Verdict.VIOLATED and prop in first_bad:
                    seed, checked, msg = first_bad[prop]
                    data["reproduce"] = simulate_command(subj.ref, lname, robots, seed)
                    cx = run_counterexample(checked, prop, msg, ref=subj.ref)
                    data["violation"] = {"seed": seed, "step": cx.violation["step"], "message": msg}
                    if out_dir is not None:
                        os.makedirs(out_dir, exist_ok=True)
                        data["counterexample"] = cx.save(os.path.join(
                            os.fspath(out_dir), f"{_safe(algo)}-{_safe(lname)}-n{robots}-{prop}-seed{seed}.json"))
                        detail += f"; replay: swarmproof replay {data['counterexample']}"
                    else:
                        detail += f"; repeat: {data['reproduce']}"
                rows.append(Row("algorithms", f"{algo} {lname} n={robots}", prop, verdict,
                                detail, data, claim=claims.get(prop), artifact=cx, paper=subj.paper))
    return rows


# -- lemmas --------------------------------------------------------------------

#: ``prove`` status -> verdict (DESIGN.md section 2: proved | counterexample | inconclusive).
LEMMA_VERDICT = {"proved": Verdict.PROVED, "counterexample": Verdict.VIOLATED,
                 "inconclusive": Verdict.INCONCLUSIVE}


def _num(x: float) -> str:
    """``%.6g`` without ``-0`` (a counterexample's numbers in a table cell)."""
    t = f"{float(x):.6g}"
    return "0" if t == "-0" else t


def lemma_rows(results) -> list[Row]:
    """One ``lemmas`` row per :class:`~swarmproof.checkers.proofs.LemmaResult`.

    The detail says whether the premises are satisfiable (a proof from
    contradictory premises is vacuous, hence inconclusive) and whether the
    negative control (one premise weakened) was refuted; a counterexample's
    numbers come first, an inconclusive lemma's reason likewise.  The JSON
    data is the ``prove`` document of the lemma without ``seconds`` (wall
    clock), so the verify JSON stays bit-identical.

    Examples
    --------
    >>> from swarmproof.checkers.proofs import LEMMAS, prove
    >>> row, = lemma_rows([prove(LEMMAS["relocate_stays_in_range"])])
    >>> row.verdict
    <Verdict.PROVED: 'proved'>
    >>> print(row.detail)
    auxiliary; premises satisfiable, negative control refuted (weakened: the segment's end may be 2 phi away), vacuity controls ok (needed: end_within_range, on_segment, root_still, start_within_range); not proved: that the relocate robot's step ends within phi of the root: the run-time monitor checks that end directly (a disc is convex; this lemma only extends the two ends to the path between them)
    """
    rows = []
    for r in results:
        premises = {True: "premises satisfiable", False: "premises unsatisfiable (vacuous)",
                    None: "premises not decided"}[r.premises_satisfiable]
        ctrl = r.negative_control or {}
        refuted = ctrl.get("status") == "counterexample"
        control = ("negative control refuted" if refuted
                   else f"negative control not refuted ({ctrl.get('status')})")
        if ctrl.get("weakened"):
            control += f" (weakened: {ctrl['weakened']})"
        vac = r.vacuity or {}
        detail = f"{r.kind}; {premises}, {control}"
        if vac.get("verdict") not in (None, "not_run"):
            detail += f", vacuity controls {vac['verdict']} ({vac.get('note', '')})"
        if r.not_proved:
            detail += "; not proved: " + "; ".join(r.not_proved)
        if r.status == "counterexample":
            nums = ", ".join(f"{k}={_num(v)}" for k, v in (r.counterexample or {}).items())
            detail = f"counterexample {nums}; {detail}"
        elif r.status == "inconclusive":
            detail = f"{r.reason}; {detail}"
        data = {k: v for k, v in r.to_dict().items() if k not in ("seconds", "id")}
        rows.append(Row("lemmas", r.id, "z3 proof", LEMMA_VERDICT[r.status], detail, data,
                        claim="; ".join(r.cites) or "lemma"))
    return rows


def section_lemmas(*, ids=None, timeout_s: float | None = None,
                   progress: Progress | None = None) -> list[Row]:
    """The z3 proof suite (issue 5), one row per lemma of ``proofs.LEMMAS``.

    Runs lemma by lemma, as ``swarmproof prove`` does
    (:func:`~swarmproof.checkers.proofs.run_suite`), with the default
    timeout per lemma unless ``timeout_s`` is given.
    """
    from swarmproof.checkers.proofs import DEFAULT_TIMEOUT_S, lookup, run_suite

    timeout = DEFAULT_TIMEOUT_S if timeout_s is None else timeout_s
    results = []
    for lem in lookup(ids):
        if progress:
            progress(lem.id)
        results.extend(run_suite([lem.id], timeout_s=timeout))
    return lemma_rows(results)


# -- exploration ------------------------------------------------------------------

#: Defaults of the exploration rows.  The gate is bounded by example counts
#: only, never by wall time (DESIGN.md section 5, "Baselines"): a slow CI
#: runner gives the same verdicts, and the JSON is bit-identical.  A caller
#: may still give a time ``budget`` per property or a ``section_budget``
#: (seconds); a budget that is hit makes a held row inconclusive and a
#: property not reached in time is inconclusive.  ``make verify``'s time is
#: in docs/performance.md.
VERIFY_EXPLORE_MAX_EXAMPLES = 300
VERIFY_EXPLORE_ROBOTS = (3, 8)
VERIFY_EXPLORE_SEED = 0
VERIFY_EXPLORE_BUDGET: float | None = None
VERIFY_EXPLORE_SECTION_BUDGET: float | None = None

_EXPLORE_STATUS = {"held": Verdict.HELD, "violated": Verdict.VIOLATED,
                   "inconclusive": Verdict.INCONCLUSIVE}


def explore_command(algorithm: str, prop: str, *, max_examples: int, robots: tuple[int, int],
                    seed: int, budget: float | None, out_dir: str = "DIR") -> str:
    """The ``swarmproof explore`` command line that repeats one exploration row.

    >>> explore_command("song2014", "tree_links", max_examples=200, robots=(3, 8), seed=0, budget=60)
    'swarmproof explore song2014 --property tree_links --max-examples 200 --robots 3..8 --seed 0 --budget 60 --out DIR'
    >>> explore_command("song2014", "tree_links", max_examples=300, robots=(3, 8), seed=0, budget=None)
    'swarmproof explore song2014 --property tree_links --max-examples 300 --robots 3..8 --seed 0 --budget none --out DIR'
    """
    shown = "none" if budget is None else f"{budget:g}"
    return (f"swarmproof explore {algorithm} --property {prop} --max-examples {max_examples} "
            f"--robots {robots[0]}..{robots[1]} --seed {seed} --budget {shown} --out {out_dir}")


def exploration_row(algorithm: str, prop: str, entry: dict | None, claim: str | None, *,
                    max_examples: int, robots: tuple[int, int], seed: int, budget: float | None,
                    assumptions: dict | None = None, skipped: str = "",
                    budget_used: float | None = None, ref: str | None = None, artifact: Any = None,
                    paper: str | None = None) -> Row:
    """One ``exploration`` row from the explorer's JSON entry of one property.

    ``entry`` is ``ExploreReport.as_dict()["properties"][prop]`` (``status,
    scenarios, conclusive, steps, capped, budget_hit, message,
    counterexample, violation, robots``), or None when the property was not
    explored (``skipped`` says why: inconclusive).  ``budget_used`` is the
    time budget the explorer really had when the section's cap cut it below
    ``budget``.  Verdicts: ``held`` only
    when the explorer held *and* its time budget was not hit (a held verdict
    that stopped at the budget would depend on the machine's speed, so it is
    inconclusive); ``violated`` with the counterexample; ``inconclusive``
    otherwise.  Never ``proved``.

    Examples
    --------
    >>> e = {"status": "held", "scenarios": 200, "conclusive": 200, "steps": 12016, "capped": 0,
    ...      "budget_hit": False, "message": "", "counterexample": None, "violation": None, "robots": None}
    >>> row = exploration_row("song2016", "connectivity", e, "001 Lemma 11", max_examples=200,
    ...                       robots=(3, 8), seed=0, budget=60)
    >>> row.verdict, row.detail
    (<Verdict.HELD: 'held'>, 'held over 200 scenarios, 12016 steps (explored, not proved)')
    >>> row = exploration_row("song2016", "connectivity", dict(e, budget_hit=True, scenarios=57),
    ...                       "001 Lemma 11", max_examples=200, robots=(3, 8), seed=0, budget=60)
    >>> row.verdict, row.detail
    (<Verdict.INCONCLUSIVE: 'inconclusive'>, 'time budget 60 s hit after 57 of 200 scenarios: not a pass (raise the budget or run on a less loaded machine)')
    """
    cmd = explore_command(ref or algorithm, prop, max_examples=max_examples, robots=robots, seed=seed,
                          budget=budget)
    data: dict[str, Any] = {"algorithm": algorithm, "robots": list(robots), "seed": seed,
                            "max_examples": max_examples, "budget": budget, "explored": entry is not None,
                            "reproduce": cmd}
    if ref is not None and ref != algorithm:
        data["ref"] = ref
    if assumptions is not None:
        data.update(assumptions)
    subject = f"{algorithm} n={robots[0]}..{robots[1]}"
    if entry is None:
        return Row("exploration", subject, prop, Verdict.INCONCLUSIVE, f"not explored: {skipped}", data,
                   claim=claim, paper=paper)
    data.update({k: entry.get(k) for k in ("status", "scenarios", "conclusive", "steps", "capped",
                                          "budget_hit", "violation", "counterexample")})
    data["counterexample_robots"] = entry.get("robots")
    status = entry["status"]
    verdict = _EXPLORE_STATUS.get(status, Verdict.INCONCLUSIVE)
    scen, steps = entry.get("scenarios", 0), entry.get("steps", 0)
    if verdict is Verdict.VIOLATED:
        detail = entry.get("message") or str((entry.get("violation") or {}).get("message", ""))
        if entry.get("budget_hit"):
            detail += " (shrinking stopped at the time budget: may not be minimal)"
        path = entry.get("counterexample")
        detail += (f"; replay: swarmproof replay {path}" if path
                   else "; the file: swarmproof verify --out DIR")
    elif verdict is Verdict.HELD and entry.get("budget_hit"):
        verdict = Verdict.INCONCLUSIVE
        detail = (f"time budget {budget if budget_used is None else budget_used:.3g} s hit after {scen} of {max_examples} scenarios: not a pass "
                  f"(raise the budget or run on a less loaded machine)")
    elif verdict is Verdict.HELD:
        detail = f"held over {_count(scen, 'scenario')}, {_count(steps, 'step')} (explored, not proved)"
        if entry.get("capped"):
            detail += f"; {entry['capped']} runs hit the step cap"
    else:
        detail = entry.get("message") or f"explorer status {status!r}"
    if status == "not_applicable":     # the explorer found it not applicable (a user's property list)
        return not_applicable_row("exploration", subject, prop, entry.get("message") or "", data, claim, paper)
    return Row("exploration", subject, prop, verdict, detail, data, claim=claim,
               artifact=artifact if verdict is Verdict.VIOLATED else None, paper=paper)


def _explore_one(ref: str, props, n_examples: int, robots: tuple, seed: int, budget, out_dir, show=None):
    """One algorithm's exploration rows in one explorer call: ``[(doc, counterexample), ...]``, one
    per property of ``props``, ``doc`` the ``ExploreReport.as_dict()`` with that property alone.
    One call per algorithm, not per row: the explorer then judges each run for the properties
    after the one that ran it (``checkers/explore.py``, ``_SharedRuns``), the same rows sooner.
    ``budget`` is per property, as the rows report it.  A module-level function, so that a Dask
    worker can run it (``section_exploration(workers=N)``)."""
    from swarmproof.checkers.explore import explore

    props = list(props)
    rep = explore(ref, props, budget=None if budget is None else budget * len(props), max_examples=n_examples,
                  robots=tuple(robots), seed=seed, out_dir=out_dir, progress=show)
    doc = rep.as_dict()
    return [({**doc, "properties": {p: doc["properties"][p]}},
             getattr(rep.properties.get(p), "counterexample", None)) for p in props]


def _explore_on_worker(*job):
    """:func:`_explore_one` inside a Dask task (the workers' own use of `random` silenced)."""
    from swarmproof.checkers.campaign import worker_warnings

    with worker_warnings():
        return _explore_one(*job)


def costliest_first(costs: list) -> list[int]:
    """The order in which to hand out tasks of about these ``costs`` (None: unknown) to a few
    workers: unknown first, then costliest first, ties in the given order (longest processing time
    first: the last task to finish is then a short one).

    >>> costliest_first([22, None, 196, 44, 196])
    [1, 2, 4, 3, 0]
    """
    return sorted(range(len(costs)), key=lambda i: (costs[i] is not None, -(costs[i] or 0), i))


def _explore_parallel(jobs: list, workers: int, progress: Progress | None, client=None,
                      costs: list | None = None) -> list:
    """Run :func:`_explore_one` on each job's arguments on an embedded Dask ``LocalCluster`` of
    ``workers`` processes (the campaigns' engine, docs/campaigns.md), or on ``client``'s cluster
    when given (:func:`run_report` shares one with the other sections); results in the jobs'
    order.  Each row is bounded by its example count, so the rows are the serial run's (tested).
    ``costs`` (each job's ``VerifyPlan.explore_cost``) set the order in which the workers take the
    jobs (:func:`costliest_first`); it changes no result."""
    from swarmproof.checkers.campaign import local_client

    # submitted in that order (an idle worker takes a task as soon as it arrives), at falling priority
    order = costliest_first(list(costs) if costs is not None else [None] * len(jobs))
    with contextlib.nullcontext(client) if client is not None else local_client(workers) as client:
        from distributed import as_completed     # after local_client: without Dask, its usage error first

        futures = [client.submit(_explore_on_worker, *jobs[i], key=f"swarmproof-verify-{i}-{jobs[i][0]}",
                                 pure=False, priority=len(jobs) - k)
                   for k, i in enumerate(order)]
        index = {f.key: i for f, i in zip(futures, order)}
        out: list = [None] * len(jobs)
        done = 0
        for fut in as_completed(futures):
            out[index[fut.key]] = fut.result()       # an error in a row is raised here, as in the serial run
            done += 1
            if progress:
                ref, props = jobs[index[fut.key]][:2]
                progress(f"{done}/{len(jobs)} algorithms explored on {workers} processes (last: {ref}, "
                         f"{len(props)} properties)")
        return out


def section_exploration(*, algorithms=None, properties=None,
                        max_examples: int = VERIFY_EXPLORE_MAX_EXAMPLES,
                        robots: tuple[int, int] = VERIFY_EXPLORE_ROBOTS, seed: int = VERIFY_EXPLORE_SEED,
                        budget: float | None = None, section_budget: float | None = None,
                        out_dir: str | None = None, progress: Progress | None = None,
                        subjects: list[Subject] | None = None, workers: int | None = None,
                        client=None) -> list[Row]:
    """The explorer's property matrix: each algorithm by each explorer property (issue 6).

    For each algorithm (default: those whose ``verify`` plan asks for
    exploration, :func:`verify_subjects`; ``algorithms`` names them, or
    ``subjects`` gives them) and each property (default every registered one
    when this runs, and the algorithm's own properties,
    :func:`~swarmproof.checkers.explore.explore_properties`) one
    :func:`~swarmproof.checkers.explore.explore` run with ``max_examples`` (or fewer: the
    plan's ``explore_max_examples``), ``robots`` and ``seed``.  No wall-clock limit by default
    (:data:`VERIFY_EXPLORE_BUDGET`, read when the section runs, as is
    :data:`VERIFY_EXPLORE_SECTION_BUDGET`): a ``budget`` per property or a
    ``section_budget`` may be given; once ``section_budget`` seconds are
    spent the remaining properties are not explored and are inconclusive.
    Counterexample files are written into ``out_dir`` only when it is given
    (``swarmproof verify --out DIR``); otherwise each violated row carries the
    ``swarmproof explore`` command that repeats it (``reproduce`` in JSON).
    Each algorithm's properties are explored in one explorer call, which shares runs between them
    (the same rows as one call per row, sooner; ``_SharedRuns`` in checkers/explore.py).
    ``workers`` > 1 runs the algorithms on that many local processes (Dask, as campaigns do): the
    same rows, in the same order, sooner on a machine with that many cores; a ``section_budget``
    keeps them in this process, one call per row (its deadline is spent in row order).
    """
    import math

    from swarmproof.checkers.explore import explore_properties

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise UsageError(f"--workers {workers!r} must be >= 1", fix="e.g. --workers 2, or --workers auto")
    budget = VERIFY_EXPLORE_BUDGET if budget is None else budget
    section_budget = VERIFY_EXPLORE_SECTION_BUDGET if section_budget is None else section_budget
    if subjects is None:
        subjects = [s for s in verify_subjects(None if algorithms is None else tuple(algorithms))
                    if algorithms is not None or s.plan.explore]
    deadline = math.inf if section_budget is None else time.monotonic() + section_budget
    plan = []
    for subj in subjects:
        cap = getattr(subj.plan, "explore_max_examples", None)
        n_examples = max_examples if cap is None else min(int(max_examples), int(cap))
        only = getattr(subj.plan, "explore_properties", None)
        # every registered property, and the algorithm's own ones (no row for another's)
        props = explore_properties(subj.declared) if properties is None else tuple(properties)
        plan.extend((subj, prop, n_examples) for prop in props if only is None or prop in only)
    # not applicable (the algorithm's declarations against the property's needs): no exploration
    na = [subj.not_applicable(prop) for subj, prop, _ in plan]
    ran = None
    todo = [i for i, reason in enumerate(na) if reason is None]
    # one explorer call per algorithm (its applicable properties together: they share runs), unless
    # a section budget is spent row by row
    groups: dict[int, list[int]] = {}
    for i in todo:
        groups.setdefault(id(plan[i][0]), []).append(i)
    jobs = [(plan[g[0]][0].ref, tuple(plan[i][1] for i in g), plan[g[0]][2], tuple(robots), seed, budget, out_dir)
            for g in groups.values()]
    if section_budget is None and workers is not None and workers > 1 and len(jobs) > 1:
        ran = {}
        costs = [getattr(plan[g[0]][0].plan, "explore_cost", None) for g in groups.values()]
        for g, out in zip(groups.values(), _explore_parallel(jobs, workers, progress, client, costs)):
            ran.update(zip(g, out))
    elif section_budget is None:
        ran = {}
        for g, job in zip(groups.values(), jobs):
            show = None
            if progress:
                def show(prop, k, total, algo=plan[g[0]][0].label):
                    progress(f"{algo} {prop}: example {k} (max {total} + shrinking)")
                show(job[1][0], 0, job[2])
            ran.update(zip(g, _explore_one(*job, show)))
    rows = []
    for i, (subj, prop, n_examples) in enumerate(plan):
        algo, claims = subj.label, subj.claims
        kw = dict(max_examples=n_examples, robots=tuple(robots), seed=seed, budget=budget, ref=subj.ref)
        if na[i] is not None:
            data = {"algorithm": algo, "robots": list(robots), "seed": seed, "max_examples": n_examples,
                    "budget": budget, "explored": False}
            if subj.ref != algo:
                data["ref"] = subj.ref
            rows.append(not_applicable_row("exploration", f"{algo} n={robots[0]}..{robots[1]}", prop, na[i], data,
                                           claims.get(prop), subj.paper))
            continue
        if ran is not None:
            used = budget
            doc, artifact = ran[i]
        else:
            left = deadline - time.monotonic()
            if left <= 0:
                rows.append(exploration_row(algo, prop, None, claims.get(prop), **kw, paper=subj.paper,
                                            skipped=f"the section's time budget of {section_budget:g} s "
                                                    "was spent before it"))
                continue
            show = None
            if progress:
                def show(_p, k, total, algo=algo, prop=prop):
                    progress(f"{algo} {prop}: example {k} (max {total} + shrinking)")
                show(prop, 0, n_examples)
            used = None if budget is None and math.isinf(left) else min(math.inf if budget is None else budget, left)
            [(doc, artifact)] = _explore_one(subj.ref, (prop,), n_examples, tuple(robots), seed, used, out_dir, show)
        assumptions = {"kept_assumptions": doc.get("kept_assumptions", []),
                       "broken_assumptions": doc.get("broken_assumptions", [])}
        row = exploration_row(algo, prop, doc["properties"][prop], claims.get(prop), **kw,
                              assumptions=assumptions, budget_used=used, artifact=artifact, paper=subj.paper)
        rows.append(row)
        if prop == "premises":
            rows.extend(monitor_rows(row, doc["properties"][prop]))
    return rows


def monitor_rows(premises_row: Row, entry: dict) -> list[Row]:
    """One exploration row per lemma premise monitor (issue 32: verify has a row per monitor),
    from the ``premises`` exploration's per-monitor tallies (the same runs: no extra cost).

    A monitor is ``violated`` when it failed in some explored scenario (the ``premises`` row's
    counterexample is that of the monitor that failed first in the smallest scenario; another
    one's failure has the tally, not a file), ``held`` when it held in some scenario and failed in none, ``inconclusive`` when it
    was vacuous or could not judge in every scenario.  Rows take the property name
    ``premises:MONITOR``.

    >>> base = Row("exploration", "x n=3..8", "premises", Verdict.HELD, "held", {"algorithm": "x"})
    >>> rows = monitor_rows(base, {"monitors": {"nclb": {"held": 0, "violated": 0, "vacuous": 5,
    ...                                                  "inconclusive": 0}}, "violation": None})
    >>> [(r.property, r.verdict.value, r.detail) for r in rows]
    [('premises:nclb', 'inconclusive', 'vacuous in all 5 judged scenarios (no instance with every premise holding): not a pass')]
    """
    from swarmproof.invariants.premises import MONITOR_LEMMAS

    out = []
    for name, c in sorted((entry.get("monitors") or {}).items()):
        n = sum(c.values())
        lemma = MONITOR_LEMMAS.get(name, "?")
        if c.get("violated"):
            verdict = Verdict.VIOLATED
            detail = (f"failed in {c['violated']} of {n} judged scenarios (lemma {lemma}); the counterexample "
                      "file is the premises row's (the monitor that failed first in its smallest scenario)")
        elif c.get("held"):
            verdict = Verdict.HELD
            detail = (f"held in {c['held']} of {n} judged scenarios (lemma {lemma}; vacuous in {c.get('vacuous', 0)}) "
                      "(explored, not proved)")
        elif c.get("vacuous") == n:
            verdict = Verdict.INCONCLUSIVE
            detail = f"vacuous in all {n} judged scenarios (no instance with every premise holding): not a pass"
        else:
            verdict = Verdict.INCONCLUSIVE
            detail = f"could not judge in {c.get('inconclusive', 0)} of {n} scenarios, vacuous in {c.get('vacuous', 0)}"
        data = {**premises_row.data, "monitor": name, "lemma": lemma, "tally": dict(c)}
        out.append(Row("exploration", premises_row.subject, f"premises:{name}", verdict, detail, data,
                       claim=premises_row.claim, paper=premises_row.paper))
    return out


def section_formulas(*, progress: Progress | None = None) -> list[Row]:
    """Exact checks of the published formulas an algorithm declares (its class's ``exact_checks``:
    a callable returning rows ``{subject, property, status, detail, cites, data}``; 003's ID,
    neighbor and pattern formulas, exhaustively for n = 2..64).  One row per check, claimed with the
    paper's citation; each check runs once even when several registered variants share it."""
    from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names

    rows: list[Row] = []
    seen = set()
    for name in algorithm_names():
        fn = getattr(algorithm_factory(name), "exact_checks", None)
        if not callable(fn) or fn in seen:
            continue
        seen.add(fn)
        if progress:
            progress(name)
        for r in fn():
            rows.append(Row("formulas", r["subject"], r["property"], Verdict(r["status"]), r["detail"],
                            dict(r.get("data") or {}), claim=r["cites"]))
    return rows


def exhaustive_command(ref: str, cell) -> str:
    """The ``swarmproof explore --exhaustive`` command that repeats one cell's rows.

    >>> from swarmproof.reference_impl.protocol import ExhaustiveCell
    >>> exhaustive_command("song2014", ExhaustiveCell(("connectivity",), steps=15))
    'swarmproof explore song2014 --exhaustive --property connectivity --choices activate --max-steps 15 --deviations 2 --robots 3 --seed 0 --starts 1 --budget none --out DIR'
    """
    props = " ".join(f"--property {p}" for p in cell.properties)
    extra = (f" --max-delay {cell.max_delay}" if "delay" in cell.kinds else "") + \
            (f" --max-crashes {cell.max_crashes}" if "crash" in cell.kinds else "") + \
            (f" --target {cell.target}" if cell.target else "")
    return (f"swarmproof explore {ref} --exhaustive {props} --choices {','.join(cell.kinds)} --max-steps "
            f"{cell.steps} --deviations {cell.deviations} --robots {cell.robots} --seed {cell.seed} --starts 1{extra} "
            "--budget none --out DIR")


_EXHAUSTIVE_STATUS = {"held": Verdict.HELD, "violated": Verdict.VIOLATED, "inconclusive": Verdict.INCONCLUSIVE}


def section_exhaustive(*, subjects=None, progress: Progress | None = None, out_dir: str | None = None) -> list[Row]:
    """``exhaustive`` rows (issue 33): each algorithm's :class:`ExhaustiveCell` s, one row per
    property, bounded by steps, K and choice kinds only (no wall time, no run cap), so a row
    is ``complete`` unless it found a violation; held means held for every choice sequence
    within the bound (the detail says the bound), never beyond it."""
    from swarmproof.checkers.exhaustive import Bound, exhaustive

    rows: list[Row] = []
    for s in (verify_subjects() if subjects is None else subjects):
        for cell in s.plan.exhaustive:
            if progress:
                progress(f"{s.label} {cell.label()}")
            bound = Bound(steps=cell.steps, deviations=cell.deviations, kinds=tuple(cell.kinds),
                          max_delay=cell.max_delay, max_crashes=cell.max_crashes)
            rep = exhaustive(s.ref, list(cell.properties), target=cell.target, robots=cell.robots, seed=cell.seed,
                             bound=bound, out_dir=out_dir)
            subject = f"{s.label} {cell.label()}"
            for prop, v in rep.properties.items():
                data: dict[str, Any] = {"algorithm": s.label, "robots": cell.robots, "seed": cell.seed,
                                        "reproduce": exhaustive_command(s.ref, cell),
                                        "exhaustive": v.as_dict(bound)["exhaustive"], "cpu": round(v.cpu, 2),
                                        "broken_assumptions": list(rep.broken_assumptions)}
                claim = rep.claim(s.claims, prop)
                if v.status == "not_applicable":
                    rows.append(not_applicable_row("exhaustive", subject, prop, v.message.removeprefix(
                        "not applicable: "), data, claim, s.paper))
                    continue
                verdict = _EXHAUSTIVE_STATUS.get(v.status, Verdict.INCONCLUSIVE)
                detail = v.message + (f" (the choices break {', '.join(rep.broken_assumptions)})"
                                      if rep.broken_assumptions else "")
                if v.counterexample is not None:
                    data["violation"] = dict(v.counterexample.violation)
                    data["counterexample_robots"] = len(v.counterexample.robots)
                    data["deviations"] = v.deviations
                    data["counterexample"] = v.counterexample_path
                    detail += (f"; replay: swarmproof replay {v.counterexample_path}" if v.counterexample_path
                               else "; the file: swarmproof verify --out DIR")
                rows.append(Row("exhaustive", subject, prop, verdict, detail, data, claim=claim,
                                artifact=v.counterexample if verdict is Verdict.VIOLATED else None, paper=s.paper))
    return rows


def section_recorded(*, folders=None, progress: Progress | None = None, out_dir: str | None = None) -> list[Row]:
    """Recorded runs as rows (issue 34): each log of a ``--recorded`` folder's manifest (default: the
    bundled ones), one row per property, judged as ``swarmproof check-run`` judges it
    (:mod:`swarmproof.checkers.recorded_rows`)."""
    from swarmproof.checkers.recorded_rows import recorded_cells

    return [not_applicable_row("recorded", subject, prop, detail, data, claim) if verdict is None
            else Row("recorded", subject, prop, verdict, detail, data, claim=claim)
            for subject, prop, verdict, detail, data, claim in recorded_cells(folders=folders, progress=progress)]


SECTIONS: dict[str, Callable[..., list[Row]]] = {
    "lattices": section_lattices,
    "algorithms": section_algorithms,
    "lemmas": section_lemmas,
    "formulas": section_formulas,
    "exploration": section_exploration,
    "exhaustive": section_exhaustive,
    "recorded": section_recorded,
}


def run_report(sections: list[str] | None = None, progress: Progress | None = None,
               options: dict[str, dict[str, Any]] | None = None) -> Report:
    """Run the named sections (all by default, in :data:`SECTIONS` order) into one report.

    Parameters
    ----------
    sections : list of str, optional
        Names from :data:`SECTIONS`.
    progress : callable, optional
        Called with short status texts (``"exploration: song2014 connectivity:
        example 3 (max 200 + shrinking)"``) while sections run.
    options : dict, optional
        Keyword arguments per section, e.g. ``{"exploration": {"out_dir": "cx"}}``.
    """
    names = list(SECTIONS) if sections is None else list(sections)
    options = options or {}
    by_name: dict[str, list[Row]] = {}
    seconds: dict[str, float] = {}
    with _shared_workers(names, options) as (client, elsewhere):
        # the sections of this process first (the exploration's tasks queue behind the Dask
        # tasks of the others, so no core waits for them), then the Dask tasks' rows
        for name in names:
            if name not in elsewhere:
                _run_section(name, options, progress, by_name.setdefault(name, []), seconds, client)
        for name, fut in elsewhere.items():
            by_name[name], seconds[name] = fut.result()
    return Report([row for name in names for row in by_name.get(name, [])],
                  {name: seconds[name] for name in names if name in seconds})


def _run_section(name: str, options: dict, progress, rows: list, seconds: dict, client) -> None:
    """Run one section here (exploration on ``client``'s workers when there is one)."""
    sub = None
    if progress:
        progress(name)

        def sub(text: str, name=name) -> None:
            progress(f"{name}: {text}")
    kw = dict(options.get(name, {}))
    if name == "exploration" and client is not None:
        kw["client"] = client
    got, seconds[name] = _timed_section(name, progress=sub, **kw)
    rows.extend(got)


def _timed_section(name: str, **kw) -> tuple:
    """One section's rows and its wall seconds."""
    t0 = time.perf_counter()
    got = SECTIONS[name](**kw)
    return got, time.perf_counter() - t0


#: The sections that run as Dask tasks beside the exploration rows when exploration runs on
#: several workers (they would otherwise run alone first, one core idle: about 50 s of make verify).
_SECTIONS_ON_WORKERS = ("algorithms", "lemmas", "exhaustive")


def _section_task(name: str, kw: dict):
    """One section's rows and wall seconds, in a Dask worker (:func:`run_report`)."""
    from swarmproof.checkers.campaign import worker_warnings

    with worker_warnings():
        return _timed_section(name, **kw)


@contextlib.contextmanager
def _shared_workers(names: list, options: dict):
    """When exploration runs on several local workers (``workers`` > 1, no section budget), one
    Dask cluster for the whole report: the algorithms and lemmas sections are submitted first, at
    a priority below the exploration rows, and the exploration's tasks queue behind them
    (:func:`run_report` collects their rows last), so no core waits;
    yields ``(client, {section: future})``.  Otherwise ``(None, {})``: every section here."""
    ex = options.get("exploration", {})
    workers = ex.get("workers")
    if ("exploration" not in names or not isinstance(workers, int) or isinstance(workers, bool) or workers < 2
            or ex.get("section_budget") is not None):
        yield None, {}
        return
    from swarmproof.checkers.campaign import local_client

    with local_client(workers) as client:
        elsewhere = {name: client.submit(_section_task, name, dict(options.get(name, {})), pure=False,
                                         key=f"swarmproof-verify-section-{name}", priority=-1)
                     for name in names if name in _SECTIONS_ON_WORKERS}
        yield client, elsewhere
