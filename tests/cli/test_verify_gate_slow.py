"""The CI gate end to end (issue 14, "Must hold"), slow: minutes each (`make test-slow`).

* `swarmproof verify --baseline verify-baseline.json` -- what `make verify` runs -- exits 0 on
  this tree, prints the known findings with their citations, and `--update-baseline` rewrites
  the shipped file byte for byte (deterministic, bounded by example counts only);
* the same gate on a copy of song2016 whose robots treat their children as none exits 1 and
  names the regressed connectivity and tree-link rows, each with a counterexample that replays.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys

import pytest

from testkit import MUTANT, ROOT, SHIPPED, write_mutant

pytestmark = pytest.mark.slow


def swarmproof(*argv, cwd=ROOT, timeout=900):
    exe = os.path.join(os.path.dirname(sys.executable), "swarmproof")
    return subprocess.run([exe, *argv], cwd=cwd, capture_output=True, text=True, timeout=timeout)


def test_make_verify_gate_is_green_on_this_tree_and_the_baseline_is_reproduced(tmp_path):
    proc = swarmproof("verify", "--baseline", "verify-baseline.json")
    out = proc.stdout
    assert proc.returncode == 0, out[-4000:] + proc.stderr[-2000:]
    known = out.split("-- known findings (violated, as the baseline says)")[1]
    assert ("  exploration: song2014 n=3..8 / tree_links: violated [Song & O'Kane 2014, Lemma 7" in known)
    assert "  algorithms: song2016 square n=20 / tree_links: violated [Song & O'Kane 2016, Lemma 11" in known
    assert "  algorithms: song2016-literal hexagon n=40 / termination: violated [Song & O'Kane 2016, Thm. 13" in known
    assert "repeat: swarmproof simulate song2016 --target square --robots 20 --seed 1" in known
    assert re.fullmatch(r"verify: PASS: 0 regressions, \d+ known findings, 0 improvements, \d+ held "
                        r"\(against verify-baseline.json\)", out.splitlines()[-1])
    copy = tmp_path / "b.json"
    shutil.copy(SHIPPED, copy)
    proc = swarmproof("verify", "--baseline", str(copy), "--update-baseline", "--json")
    assert proc.returncode == 0
    assert copy.read_bytes() == open(SHIPPED, "rb").read()       # the shipped baseline is this tree's, exactly


def test_mutant_song2016_fails_the_whole_gate_with_replayable_counterexamples(tmp_path):
    write_mutant(tmp_path)
    env_cwd = str(tmp_path)
    proc = swarmproof("verify", "--algorithm", f"{MUTANT}:Song2016", "--baseline", SHIPPED, "--out", "cx",
                      "--json", cwd=env_cwd)
    assert proc.returncode == 1, proc.stderr[-3000:]
    doc = json.loads(proc.stdout)
    regressed = {(c["section"], c["subject"], c["property"]) for c in doc["baseline"]["changes"]
                 if c["outcome"] == "regressed"}
    assert ("exploration", "song2016 n=3..8", "connectivity") in regressed
    assert ("algorithms", "song2016 square n=10", "tree_links") in regressed
    rows = {(r["section"], r["subject"], r["property"]): r for r in doc["rows"]}
    for key in regressed:
        cx = rows[key]["counterexample"]
        assert cx and os.path.exists(os.path.join(env_cwd, cx)), key
        again = swarmproof("replay", cx, cwd=env_cwd)
        assert again.returncode == 1, (key, again.stdout, again.stderr)   # still reproduces on the mutant
