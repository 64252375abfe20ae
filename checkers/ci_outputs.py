"""The property matrix for CI systems: JUnit XML and a Markdown summary (``verify --junit / --markdown``).

Every row becomes one test case, judged the way the exit code judges it
(:func:`row_status`):

* ``failure`` -- the row fails the gate: a regression, a new kind of failure
  in a known-violated row, a new claimed violation (without a baseline: any
  claimed violation), and with ``--strict`` an improvement;
* ``error`` -- inconclusive (never a pass): counted like exit 3;
* ``skipped`` -- a known finding (violated, as the baseline says), a row the
  paper does not claim (a finding, not counted), or a row marked n/a (not applicable: no
  verdict; the message names what the algorithm lacks);
* passed -- held or proved (or better than the baseline).

A failure's text carries the counterexample as steps a person can run and the
replay (or repeat) command.  Citations read as papers ("Song & O'Kane 2016, Lemma 11"), as on
the terminal.  The XML validates against the JUnit schema
Jenkins reads (junit-10.xsd; tests/checkers/test_ci_outputs.py) and holds no
wall-clock time, so the same run gives the same bytes.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from swarmproof.models.citations import readable
from swarmproof.models.verdict import Verdict

__all__ = ["row_status", "junit_xml", "write_junit", "markdown", "write_markdown", "row_steps"]

def row_status(report, row) -> tuple[str, str]:
    """``(kind, message)`` of one row: kind is ``failure``, ``error``, ``skipped`` or ``passed``,
    as the exit code judges it (with a baseline: :meth:`~swarmproof.checkers.baseline.Comparison.fails`
    and :meth:`~swarmproof.checkers.baseline.Comparison.undecided`)."""
    cmp_ = report.comparison
    na = (row.data or {}).get("not_applicable") or row.detail
    if cmp_ is None:
        if not row.applicable:
            return ("skipped", f"not applicable: {na}" if not na.startswith("not applicable") else na)
        if row.verdict is Verdict.VIOLATED:
            return ("failure", f"violated [{row.claim}]") if row.claimed else ("skipped", "finding (not claimed)")
        if row.verdict is Verdict.INCONCLUSIVE:
            return ("error", f"inconclusive [{row.claim}]") if row.claimed else ("skipped", "inconclusive (not claimed)")
        return ("passed", row.verdict.value)
    c = cmp_.change_of((row.section, row.subject, row.property))
    outcome = None if c is None else c.outcome
    if c is not None and cmp_.fails(c):
        return ("failure", f"new claimed violation [{row.claim}]" if outcome == "new" else f"{outcome}: {c.note}")
    if c is not None and cmp_.undecided(c):
        return ("error", f"{outcome}: {c.note or 'inconclusive'}")
    if not row.applicable:
        return ("skipped", f"not applicable: {na}" if not na.startswith("not applicable") else na)
    if row.verdict is Verdict.VIOLATED:
        return ("skipped", "known finding (baseline)" if outcome in ("known", "resized") else "finding (not claimed)")
    if row.verdict is Verdict.INCONCLUSIVE:
        return ("skipped", "inconclusive (not claimed)")
    return ("passed", row.verdict.value if outcome != "improved" else f"improved: {c.note}")


def row_steps(row) -> list[str]:
    """The counterexample of a violated row as steps, then how to repeat it (may be empty)."""
    from swarmproof.checkers.baseline import _how_to_repeat

    lines: list[str] = []
    if row.artifact is not None and hasattr(row.artifact, "format_steps"):
        lines += list(row.artifact.format_steps())
    how = _how_to_repeat(row)
    if how:
        lines.append(how)
    return lines


def junit_xml(report) -> bytes:
    """The report as JUnit XML: one ``testsuite`` per section, one ``testcase`` per row."""
    root = ET.Element("testsuites", {"name": "swarmproof verify"})
    totals = {"tests": 0, "failures": 0, "errors": 0}
    sections: dict[str, list] = {}
    for r in report.rows:
        sections.setdefault(r.section, []).append(r)
    for section, rows in sections.items():
        suite = ET.SubElement(root, "testsuite", {"name": f"swarmproof.{section}"})
        counts = {"failure": 0, "error": 0, "skipped": 0}
        for r in rows:
            kind, message = row_status(report, r)
            case = ET.SubElement(suite, "testcase", {"classname": f"swarmproof.{section}.{r.subject}",
                                                     "name": r.property})
            text = "\n".join([r.detail] + row_steps(r)) if r.verdict is Verdict.VIOLATED else r.detail
            if kind in counts:
                counts[kind] += 1
                el = ET.SubElement(case, kind, {"message": readable(message), "type": r.verdict.value})
                el.text = readable(text)
            out = ET.SubElement(case, "system-out")
            out.text = readable(f"verdict: {r.verdict.value}; claim: {r.claim or 'not claimed'}\n{r.detail}")
        suite.set("tests", str(len(rows)))
        suite.set("failures", str(counts["failure"]))
        suite.set("errors", str(counts["error"]))
        suite.set("skipped", str(counts["skipped"]))
        totals["tests"] += len(rows)
        totals["failures"] += counts["failure"]
        totals["errors"] += counts["error"]
    for k, v in totals.items():
        root.set(k, str(v))
    ET.indent(root)
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def write_junit(report, path) -> str:
    """Write :func:`junit_xml` atomically."""
    from swarmproof.models.fileio import atomic_write_bytes

    return atomic_write_bytes(path, junit_xml(report))


def _cell(text: Any) -> str:
    """One Markdown table cell: citations readable, pipes and newlines escaped."""
    return readable(str(text)).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")


def summary_line(report) -> str:
    """The last line of the human table (the baseline's summary when there is one)."""
    return report.format_table().splitlines()[-1]


def markdown(report) -> str:
    """A Markdown summary for a CI job page: the summary line, the rows that need a look, then
    the whole matrix folded."""
    lines = ["## swarmproof verify", "", f"**{_cell(summary_line(report))}**", ""]
    header = ["| section | subject | property | verdict | status | claim | detail |",
              "|---|---|---|---|---|---|---|"]

    def row_line(r) -> str:
        kind, message = row_status(report, r)
        detail = r.detail
        steps = row_steps(r)
        if steps and r.verdict is Verdict.VIOLATED:
            detail += f" -- `{_cell(steps[-1])}`"
        return (f"| {r.section} | {_cell(r.subject)} | {_cell(r.property)} | {r.verdict.value} | "
                f"{kind}: {_cell(message)} | {_cell(r.claim or 'not claimed')} | {_cell(detail)} |")
    look = [r for r in report.rows if row_status(report, r)[0] != "passed"]
    if look:
        lines += ["### Rows to look at", ""] + header + [row_line(r) for r in look] + [""]
    lines += ["<details><summary>All rows</summary>", ""] + header + [row_line(r) for r in report.rows]
    lines += ["", "</details>", ""]
    return "\n".join(lines)


def write_markdown(report, path) -> str:
    """Write :func:`markdown` atomically."""
    from swarmproof.models.fileio import atomic_write_text

    return atomic_write_text(path, markdown(report))
