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
* ``lemmas`` — the z3 proof suite.

Examples
--------
>>> r = Report([Row("lattices", "square", "self-consistent", Verdict.HELD, "ok")])
>>> r.verdict, r.exit_code
(<Verdict.HELD: 'held'>, 0)
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable

from swarmproof.models.verdict import Verdict

__all__ = ["Row", "Report", "SECTIONS", "run_report"]


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

    @property
    def claimed(self) -> bool:
        return self.claim is not None

    def to_json(self) -> dict[str, Any]:
        return {"section": self.section, "subject": self.subject, "property": self.property,
                "verdict": self.verdict.value, "detail": self.detail, "claim": self.claim,
                **self.data}


@dataclass
class Report:
    rows: list[Row]
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def verdict(self) -> Verdict:
        """Worst verdict over the rows that check a claim (unclaimed rows are findings)."""
        return Verdict.combine(r.verdict for r in self.rows if r.claimed)

    @property
    def exit_code(self) -> int:
        return self.verdict.exit_code

    def to_json(self, *, timings: bool = False) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "verdict": self.verdict.value,
            "rows": [r.to_json() for r in self.rows],
            "counts": {v.value: sum(r.verdict is v for r in self.rows) for v in Verdict},
        }
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
            mark = "" if r.claimed else "*"
            lines.append(f"{r.subject:<{w_subj}}  {r.property:<{w_prop}}  "
                         f"{r.verdict.value + mark:<12}  {r.detail}")
        counts = ", ".join(f"{sum(r.verdict is v for r in self.rows)} {v.value}" for v in Verdict)
        lines.append("")
        if any(not r.claimed for r in self.rows):
            lines.append("* not claimed by the paper: a finding about the algorithm, "
                         "not counted in the verdict")
        lines.append(f"verify: {self.verdict.value.upper()} ({counts})")
        return "\n".join(lines)


# ---------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------

def _count(n: int, noun: str) -> str:
    """``_count(1, 'role') == '1 role'``, ``_count(2, 'role') == '2 roles'``."""
    return f"{n} {noun}" + ("" if n == 1 else "s")


def section_lattices() -> list[Row]:
    """Every bundled lattice at its recommended range (001 Defs. 1, 4)."""
    from swarmproof.checkers.lattice_check import check_lattice
    from swarmproof.models import library

    rows = []
    for name in library.names():
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


#: The algorithm rows: each reference implementation on each periodic lattice of
#: the papers (000 Figs. 2, 3, 7), ``VERIFY_ROBOTS`` robots from the seeded
#: connected starts ``VERIFY_SEEDS``.  Small on purpose: ``make verify`` must stay
#: within 10 minutes; the acceptance runs (``make test-slow``) go wider.
VERIFY_ALGORITHMS = ("song2016", "song2014")
VERIFY_LATTICES = ("square", "hexagon", "octagon-square")
VERIFY_ROBOTS = 10
VERIFY_SEEDS = (0, 1, 2)


def _run_property_verdicts(checked) -> dict[str, tuple[Verdict, str]]:
    """Verdict and a short detail for each registry property of one checked run."""
    doc = checked.doc
    out: dict[str, tuple[Verdict, str]] = {}
    status = doc["status"]
    if status == "step_cap":
        out["termination"] = (Verdict.INCONCLUSIVE, f"step cap {doc['steps']} reached")
    elif checked.termination is not None and checked.termination.violated:
        out["termination"] = (Verdict.VIOLATED, checked.termination.message)
    else:
        out["termination"] = (Verdict.HELD, f"{status} at step {doc['execution_steps']}")
    sat = checked.satisfaction
    out["formation"] = (Verdict(sat.status) if status != "step_cap" else Verdict.INCONCLUSIVE,
                        sat.message)
    conn = checked.connectivity
    out["connectivity"] = (Verdict(conn.status), conn.message)
    links = checked.tree_links
    out["tree_links"] = (Verdict(links.status), links.message)
    return out


def section_algorithms() -> list[Row]:
    """Each reference implementation on each lattice: its claims, run by run (001, 000)."""
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.models import library
    from swarmproof.reference_impl.registry import PROPERTIES, claims_of

    rows = []
    for algo in VERIFY_ALGORITHMS:
        claims = claims_of(algo)
        for lname in VERIFY_LATTICES:
            lattice = library.load(lname)
            per_prop: dict[str, list[tuple[int, Verdict, str]]] = {p: [] for p in PROPERTIES}
            for seed in VERIFY_SEEDS:
                checked = run_and_check(algo, lattice, seed=seed, robots=VERIFY_ROBOTS)
                for prop, (verdict, msg) in _run_property_verdicts(checked).items():
                    per_prop[prop].append((seed, verdict, msg))
            for prop in PROPERTIES:
                results = per_prop[prop]
                verdict = Verdict.combine(v for _, v, _ in results)
                held = sum(v.passed for _, v, _ in results)
                detail = f"{held}/{len(results)} runs held"
                worst = next(((s, m) for s, v, m in results if v is verdict and not v.passed), None)
                if worst is not None:
                    detail += f"; seed {worst[0]}: {worst[1]}"
                rows.append(Row("algorithms", f"{algo} {lname} n={VERIFY_ROBOTS}", prop, verdict,
                                detail, {"algorithm": algo, "lattice": lname, "robots": VERIFY_ROBOTS,
                                         "seeds": list(VERIFY_SEEDS)}, claim=claims.get(prop)))
    return rows


SECTIONS: dict[str, Callable[[], list[Row]]] = {
    "lattices": section_lattices,
    "algorithms": section_algorithms,
}


def run_report(sections: list[str] | None = None, progress: Callable[[str], None] | None = None) -> Report:
    """Run the named sections (all by default) and collect one report."""
    names = list(SECTIONS) if sections is None else sections
    rows: list[Row] = []
    seconds: dict[str, float] = {}
    for name in names:
        if progress:
            progress(name)
        t0 = time.perf_counter()
        rows.extend(SECTIONS[name]())
        seconds[name] = time.perf_counter() - t0
    return Report(rows, seconds)
