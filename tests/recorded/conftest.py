"""tests/recorded: recorded runs (issue 34) -- ``swarmproof check-run``, ``swarmproof export`` and
``simulate --export`` on CSV, MCAP and rosbag2 logs (both storages).

``logkit`` (this folder) writes hand-made logs with the libraries' own writers; the tests import
it as ``from logkit import ...`` (importlib import mode does not put this folder on the path by
itself).  Every file goes under ``tmp_path``; every run is seeded.
"""

from __future__ import annotations

import json
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture
def check_run(cli):
    """``check_run(path, *args) -> (exit code, JSON document or None, stderr)``: ``swarmproof
    check-run`` in-process with ``--json`` (the document is None when stdout is empty); stderr
    never holds a traceback."""

    def run(path, *args):
        code, out, err = cli("check-run", str(path), "--json", *args)
        assert "Traceback" not in err and "Traceback" not in out, err
        return code, (json.loads(out) if out.strip() else None), err
    return run
