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

    def to_json(self) -> dict[str, Any]:
        return {"section": self.section, "subject": self.subject, "property": self.property,
                "verdict": self.verdict.value, "detail": self.detail, **self.data}


@dataclass
class Report:
    rows: list[Row]
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def verdict(self) -> Verdict:
        return Verdict.combine(r.verdict for r in self.rows)

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
            lines.append(f"{r.subject:<{w_subj}}  {r.property:<{w_prop}}  {r.verdict.value:<12}  {r.detail}")
        counts = ", ".join(f"{sum(r.verdict is v for r in self.rows)} {v.value}" for v in Verdict)
        lines.append("")
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
                         "defects": [d.kind for d in rep.defects]}))
    return rows


SECTIONS: dict[str, Callable[[], list[Row]]] = {
    "lattices": section_lattices,
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
