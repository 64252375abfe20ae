"""Issue 13: user-facing text cites papers by name ("Song & O'Kane 2016, Lemma 11"), never by
seed key or seed file (docs/references.md); JSON may keep the short key."""

from __future__ import annotations

import re

import pytest

SEED_KEY = re.compile(r"(?<![\w./])00[0-4] (Sec\.|Def|Lemma|Thm|Theorem|Eq|Fig)|\b00[0-4]_[0-9a-f]{16}\.txt|DESIGN\.md")


@pytest.mark.parametrize("argv", [
    pytest.param(["prove"], marks=pytest.mark.slow),   # 18 lemmas, ~17 s of z3: the default suite has the two below
    ["prove", "bounded_range", "relocate_stays_in_range"],
    ["verify", "--section", "lattices"],
    ["simulate", "song2014", "--lattice", "square", "--robots", "5", "--seed", "0", "--v", "2"],
    ["simulate", "song2016", "--lattice", "square", "--robots", "4", "--seed", "0"],
    ["check-lattice", "hexagon-ring", "--range", "0.9"],
    ["explore", "song2014", "--property", "tree_links", "--max-examples", "15", "--robots", "3..4"],
])
def test_human_output_and_errors_cite_papers_by_name(cli, argv):
    code, out, err = cli(*argv)
    assert not SEED_KEY.search(out + err), (SEED_KEY.search(out + err), (out + err)[:2000])


def test_every_lemmas_human_citation_and_gap_is_readable():
    """What the whole-suite ``prove`` prints of each lemma, without running z3: ``prove``'s human
    table prints ``'; '.join(cites)`` and each ``not proved by ID: gap`` line through
    :func:`readable` (swarmproof.commands.human); the slow case above runs it for real."""
    from swarmproof.checkers import proofs
    from swarmproof.models.citations import readable

    lemmas = {**proofs.LEMMAS, **proofs.EXTRA_LEMMAS}
    assert len(proofs.LEMMAS) >= 18
    for lemma in lemmas.values():
        text = readable("; ".join(lemma.cites) + "\n" + "\n".join(lemma.not_proved) + "\n" + lemma.statement)
        assert not SEED_KEY.search(text), (lemma.id, text)


def test_the_assumption_error_names_the_paper():
    from swarmproof.models.citations import readable

    assert readable("000 Sec. IV-C, Lemma 7") == "Song & O'Kane 2014, Sec. IV-C, Lemma 7"
