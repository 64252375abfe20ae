"""The pytest plugin (entry point pytest11): fixture, budget marker, assert_held, session property table."""

import subprocess
import sys
import textwrap

import pytest

USER_TESTS = textwrap.dedent('''
    import pytest

    @pytest.mark.swarmproof_budget(20)
    def test_song2016_keeps_contact(swarmproof_explore):
        swarmproof_explore("song2016", ["connectivity"], max_examples=3, robots=(3, 4)).assert_held()

    @pytest.mark.swarmproof_budget(4)
    def test_song2014_keeps_contact(swarmproof_explore):
        swarmproof_explore("song2014", ["connectivity"], max_examples=15, robots=(4, 6),
                           lattices=["square"]).assert_held()
''')


@pytest.mark.slow
def test_plugin_gate_fails_with_counterexample_and_prints_table(tmp_path):
    (tmp_path / "test_user.py").write_text(USER_TESTS)
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    out = proc.stdout
    assert proc.returncode == 1, out
    assert "1 failed, 1 passed" in out
    assert "connectivity: violated" in out and "counterexample: song2014 violates connectivity" in out
    assert "replay: swarmproof replay" in out
    assert "swarmproof property table (explored, not proved)" in out
    table = out.split("swarmproof property table")[1]
    assert "song2016" in table and "held" in table and "song2014" in table and "violated" in table
