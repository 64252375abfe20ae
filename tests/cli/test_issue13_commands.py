"""Issue 13's exact commands (items 3, 4, 5, 13): outputs are checked before any work, a file
that is not UTF-8 is an input error -- exit 2 with the cause and the fix, never a traceback."""

from __future__ import annotations

import pytest


@pytest.fixture
def place(tmp_path):
    (tmp_path / "folder").mkdir()
    (tmp_path / "existing").write_text("x")
    (tmp_path / "notutf8.json").write_bytes(b"\xff\xfe\x00bad")
    return tmp_path


@pytest.mark.parametrize("argv, match", [
    (["check-lattice", "square", "--plot", "{folder}"], r"--plot='.*folder' is a folder"),
    (["simulate", "example-gather", "--lattice", "square", "--robots", "3", "--seed", "0", "--trace", "{folder}"],
     r"--trace='.*folder' is a folder"),
    (["simulate", "example-gather", "--lattice", "square", "--robots", "3", "--seed", "0", "--plot", "{folder}"],
     r"--plot='.*folder' is a folder"),
    (["simulate", "example-gather", "--lattice", "square", "--robots", "3", "--seed", "0", "--plot", ""],
     r"--plot='' is empty"),
    (["explore", "example-gather", "--property", "connectivity", "--max-examples", "2", "--out", "{existing}"],
     r"--out='.*existing' is a file, not a folder"),
    (["verify", "--section", "lattices", "--out", "{existing}"], r"--out='.*existing' is a file, not a folder"),
    (["replay", "{notutf8}"], r"notutf8.json: the file is not UTF-8 text"),
])
def test_bad_outputs_and_inputs_exit_2_before_any_work(cli, place, argv, match):
    import re

    argv = [a.format(folder=place / "folder", existing=place / "existing", notutf8=place / "notutf8.json")
            for a in argv]
    code, out, err = cli(*argv)
    assert code == 2 and "Traceback" not in err and re.search(match, err), err
    assert out == ""                      # no report was produced before the error (checked first)
    assert sorted(p.name for p in place.iterdir()) == ["existing", "folder", "notutf8.json"]
