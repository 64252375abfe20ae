"""A mistyped name gets the closest known one (issue 29: "no did-you-mean for list, target or
algorithm names"): exit 2, the value, the suggestion, then the fix with every choice."""

from __future__ import annotations

import pytest

from swarmproof.cli import main

CASES = [
    (["simulate", "song2061", "--lattice", "square", "--seed", "0", "--robots", "4"],
     "algorithm='song2061' is not known; did you mean 'song2016'?"),
    (["simulate", "song2016", "--lattice", "sqaure", "--seed", "0", "--robots", "4"],
     "sqaure: no such file and no bundled lattice target of that name; did you mean 'square'?"),
    (["simulate", "song2016", "--target", "sqaure", "--seed", "0", "--robots", "4"],
     "no bundled target of that name; did you mean 'square'?"),
    (["simulate", "wang2020", "--target", "shape:leter-l", "--seed", "0", "--robots", "4"],
     "did you mean 'letter-l'?"),
    (["list", "algorithm"], "kind='algorithm' is not something swarmproof lists; did you mean 'algorithms'?"),
    (["explore", "song2016", "--property", "conectivity"],
     "property='conectivity' is not known; did you mean 'connectivity'?"),
    (["prove", "bounded_rnage"], "lemma='bounded_rnage' is not a known lemma id; did you mean 'bounded_range'?"),
    (["check-lattice", "sqare"], "no bundled lattice of that name; did you mean 'square'?"),
    (["check-pattern", "rhombus-triangle"], "did you mean 'rhombus-triangles'?"),
    (["verify", "--section", "lemma"], "invalid choice: 'lemma' (choose from 'lattices', 'algorithms', 'lemmas', "
                                       "'formulas', 'exploration', 'exhaustive', 'recorded'); did you mean 'lemmas'?"),
    (["simulate", "song2016", "--lattice", "square", "--seed", "0", "--robots", "4",
      "--param", "comunication_timeout=3"], "did you mean 'communication_timeout'?"),
]


@pytest.mark.parametrize("argv,expected", CASES, ids=[" ".join(c[0][:2]) + f"-{i}" for i, c in enumerate(CASES)])
def test_a_mistyped_name_gets_the_closest_one(capsys, argv, expected):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert expected in err, err
    assert "; fix: " in err.split(expected, 1)[1]       # the suggestion comes before the fix


def test_no_suggestion_when_nothing_is_close(capsys):
    assert main(["simulate", "zzzzzz", "--lattice", "square", "--seed", "0", "--robots", "4"]) == 2
    err = capsys.readouterr().err
    assert "did you mean" not in err and "algorithm='zzzzzz' is not known; fix: use one of" in err
