"""README's "Check your own algorithm" block runs as written (imports included)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_readme_example_runs_as_written(tmp_path):
    text = README.read_text(encoding="utf-8")
    section = text.split("## Check your own algorithm", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "my_check.py").write_text(code)
    out = subprocess.run([sys.executable, "my_check.py"], cwd=tmp_path, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    lines = out.stdout.splitlines()
    assert [ln.split()[0] for ln in lines[:3]] == ["connectivity", "collision", "no_crash"]
    assert all(ln.split()[1] in ("held", "violated", "inconclusive") for ln in lines[:3])
    assert lines[-1].startswith("exit code: ")
    # from the command line, from the folder of my_check.py, without PYTHONPATH
    cli = subprocess.run([sys.executable, "-c", "import sys; from swarmproof.cli import main; "
                          "sys.exit(main(sys.argv[1:]))", "explore", "my_check:StepTowardNearest",
                          "--property", "connectivity", "--max-examples", "5", "--robots", "3..4"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert cli.returncode in (0, 1, 3) and "Traceback" not in cli.stderr, cli.stderr[-2000:]
    assert "connectivity" in cli.stdout
    # importing my_check must not run the script's own exploration too (issue 29 item 14): its
    # lines ("collision ...", "exit code: ...") are not printed by the command line
    assert "exit code:" not in cli.stdout and "collision" not in cli.stdout, cli.stdout
