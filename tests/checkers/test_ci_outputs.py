"""verify's CI outputs (checkers/ci_outputs.py, checkers/html_report.py): JUnit XML valid against
the JUnit schema Jenkins reads, Markdown, and a self-contained HTML page; deterministic bytes."""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET

import pytest

from swarmproof.checkers.baseline import Baseline, compare
from swarmproof.checkers.ci_outputs import junit_xml, markdown, row_status
from swarmproof.checkers.html_report import CSP, render_html
from swarmproof.checkers.report import Report, Row, section_exploration, section_lattices
from swarmproof.models.verdict import Verdict

# One worker builds the module's rows (two explorations, 2-2.5 s of CPU) and the JUnit schema once:
# on two workers, two of the tests that read the rows built them each (measured).
pytestmark = pytest.mark.xdist_group("ci-outputs-rows")

XSD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "junit-10.xsd")


@pytest.fixture(scope="module")
def rows():
    """Lattice rows, a song2014 tree_links violation (claimed) and a song2016 held row."""
    found = section_exploration(algorithms=["song2014"], properties=["tree_links"], max_examples=30,
                                robots=(3, 4))
    held = section_exploration(algorithms=["song2016"], properties=["connectivity"], max_examples=3, robots=(3, 3))
    assert found[0].verdict is Verdict.VIOLATED and found[0].artifact is not None
    return section_lattices()[:2] + found + held


@pytest.fixture(scope="module")
def schema():
    import xmlschema   # a dev dependency (pyproject.toml)

    return xmlschema.XMLSchema(XSD)


def test_junit_validates_and_counts_without_a_baseline(rows, schema):
    data = junit_xml(Report(rows))
    schema.validate(data.decode())                     # raises on any schema violation
    root = ET.fromstring(data)
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("4", "1", "0")
    (failure,) = root.iter("failure")
    assert failure.get("message") == ("violated [Song & O'Kane 2014, Lemma 7 (a descendant stays within range of "
                                      "its parent)]")
    assert "run song2014 with seed" in failure.text                        # the counterexample's steps
    assert "repeat: swarmproof explore song2014 --property tree_links" in failure.text
    assert [s.get("name") for s in root.iter("testsuite")] == ["swarmproof.lattices", "swarmproof.exploration"]
    assert data == junit_xml(Report(rows))             # no wall clock: same bytes


def test_junit_known_finding_is_skipped_and_regression_fails(rows, schema):
    base = Baseline.from_rows(rows, {})
    rep = Report(rows, comparison=compare(rows, base))
    root = ET.fromstring(junit_xml(rep))
    assert root.get("failures") == "0" and [s.get("message") for s in root.iter("skipped")] == ["known finding (baseline)"]
    flipped = [Row(r.section, r.subject, r.property, Verdict.VIOLATED if r.verdict is Verdict.HELD else r.verdict,
                   "boom", r.data, r.claim) for r in rows]
    rep = Report(flipped, comparison=compare(flipped, base))
    data = junit_xml(rep)
    schema.validate(data.decode())
    assert ET.fromstring(data).get("failures") == "3"
    assert {row_status(rep, r)[0] for r in flipped} == {"failure", "skipped"}


def test_the_schema_check_can_fail(schema):
    with pytest.raises(Exception, match="testcase|name"):
        schema.validate('<testsuites><testsuite name="s" tests="1" failures="0" errors="0"><testcase/>'
                        "</testsuite></testsuites>")


def test_markdown_lists_the_rows_to_look_at_first(rows):
    text = markdown(Report(rows))
    assert text.startswith("## swarmproof verify\n\n**verify: VIOLATED (")
    look = text.split("### Rows to look at")[1].split("<details>")[0]
    assert "| exploration | song2014 n=3..4 | tree_links | violated | failure: violated" in look
    assert "`repeat: swarmproof explore song2014" in look and "| lattices |" not in look
    assert text.count("| lattices |") == 2


def test_html_is_self_contained_with_pictures(rows):
    page = render_html(Report(rows))
    assert CSP in page and "<script" not in page
    assert not re.search(r"""(?:src|href)=["']?(?:https?:|//)""", page)          # nothing fetched
    assert page.count('<tr class="row ') == len(rows)
    assert page.count('src="data:image/png;base64,') == 3                    # the replay and two lattices
    assert page.count('src="data:image/gif;base64,') == 1                    # the animation
    assert '<a href="#cx-2">counterexample</a>' in page and 'id="cx-2"' in page
    assert render_html(Report(rows)) == page                                 # same bytes
