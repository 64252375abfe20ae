"""Run every module's docstring examples as tests (DESIGN.md section 3).

Modules are imported through ``swarmproof.`` only, never as ``models.x``
(DESIGN.md section 4), which is why this runs doctests itself instead of
``pytest --doctest-modules`` on the folders.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import swarmproof

# Modules whose import needs optional heavy work are still imported: every
# module must be importable.
SKIP: set[str] = set()


def _modules() -> list[str]:
    names = ["swarmproof"]
    for info in pkgutil.walk_packages(swarmproof.__path__, "swarmproof."):
        names.append(info.name)
    for sub in ("models", "invariants", "checkers", "reference_impl"):
        pkg = importlib.import_module(f"swarmproof.{sub}")
        names.append(pkg.__name__)
        for info in pkgutil.walk_packages(pkg.__path__, f"swarmproof.{sub}."):
            names.append(info.name)
    return sorted(set(names) - SKIP)


@pytest.mark.parametrize("modname", _modules())
def test_doctests(modname: str) -> None:
    mod = importlib.import_module(modname)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    globs = {}
    for test in finder.find(mod, modname, globs=vars(mod).copy()):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} doctest(s) failed in {modname}"
