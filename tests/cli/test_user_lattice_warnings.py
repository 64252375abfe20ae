"""Issue 13: a user's lattice file that check-lattice does not pass at the range in use is
explored and simulated with a warning, or refused with --strict (exit 2); bundled lattices
and files that pass get no warning."""

from __future__ import annotations

import json
import shutil

import pytest

from swarmproof.models import library

LOPSIDED = """format: lattice-graph/1
name: lopsided
range: 1.2
angle_unit: deg
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, 0, 1, 0]
  - [A, A, -1, 0, 0]
"""


@pytest.fixture
def lopsided(tmp_path):
    f = tmp_path / "lopsided.yaml"
    f.write_text(LOPSIDED)
    return str(f)


def test_explore_warns_and_strict_refuses(cli, lopsided):
    code, out, err = cli("explore", "example-gather", "--lattice", lopsided, "--property", "connectivity",
                         "--max-examples", "3", "--json")
    doc = json.loads(out)
    assert code in (0, 1, 3) and doc["warnings"] and "missing_inverse" in doc["warnings"][0]
    assert f"swarmproof explore: warning: lattice 'lopsided' ({lopsided}) is violated by check-lattice" in err
    assert f"run `swarmproof check-lattice {lopsided} --range 1.2`" in err
    code, out, err = cli("explore", "example-gather", "--lattice", lopsided, "--property", "connectivity",
                         "--max-examples", "3", "--strict")
    assert code == 2 and "drop --strict to explore it anyway" in err and out == ""


def test_simulate_warns_and_strict_refuses(cli, lopsided):
    code, out, err = cli("simulate", "example-gather", "--lattice", lopsided, "--robots", "3", "--seed", "0",
                         "--json")
    assert code in (0, 1, 3) and "missing_inverse" in json.loads(out)["warnings"][0] and "warning:" in err
    code, out, err = cli("simulate", "example-gather", "--lattice", lopsided, "--robots", "3", "--seed", "0",
                         "--strict")
    assert code == 2 and "drop --strict to run toward it anyway" in err


def test_no_warning_for_bundled_or_passing_lattices(cli, tmp_path):
    good = tmp_path / "sq.yaml"
    shutil.copy(library._folder() / "square.yaml", good)
    for target in ("square", str(good)):
        code, out, err = cli("simulate", "example-gather", "--lattice", target, "--robots", "3", "--seed", "0",
                             "--json", "--strict")
        assert "warnings" not in json.loads(out) and "warning" not in err


def test_simulate_warning_names_every_defect_kind_and_result_is_not_a_bare_ok(cli, lopsided):
    """Issue 29 item 15: the warning named the first defect kind only, then "result: ok"."""
    code, out, err = cli("simulate", "example-gather", "--lattice", lopsided, "--range", "1.5", "--robots", "1",
                         "--seed", "0")
    assert code == 0
    assert (f"is violated by check-lattice at range 1.5: 5 defects: missing_inverse (1), self_consistency (4); "
            f"run `swarmproof check-lattice {lopsided} --range 1.5`") in err
    assert out.splitlines()[-1] == ("result: ok for the checks above, but the lattice has defects "
                                    "(see the warning on stderr)")
