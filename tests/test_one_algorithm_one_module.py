"""One algorithm, one module (issue 12): the shared packages never know an algorithm by name.

No registered algorithm's name appears as a string literal (docstrings aside)
in the code of checkers/, invariants/, models/ or swarmproof/; everything the
checkers need of an algorithm is declared on its class (claims, premise
monitors, verify plan).
"""

from __future__ import annotations

import ast
import pathlib

import pytest

from swarmproof.reference_impl.protocol import VerifyPlan
from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names, claims_of, verify_plans

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ("checkers", "invariants", "models", "swarmproof")


def _string_literals(path: pathlib.Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docs.add(id(body[0].value))
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            yield node.lineno, node.value


def test_no_registered_algorithm_name_in_shared_code():
    names = set(algorithm_names())
    assert {"song2016", "song2014", "example-gather", "example-anonymous-line", "example-grid-goals"} <= names
    hits = [f"{f.relative_to(ROOT)}:{line}: {value!r}"
            for pkg in SHARED for f in sorted((ROOT / pkg).rglob("*.py"))
            for line, value in _string_literals(f) if value in names]
    assert hits == []


def test_the_check_sees_a_name_planted_in_shared_code(tmp_path):
    planted = tmp_path / "planted.py"
    planted.write_text('"""Docstrings may say song2016."""\nX = "song2016"\n')
    assert [v for _, v in _string_literals(planted)] == ["song2016"]


@pytest.mark.parametrize("name", algorithm_names())
def test_every_algorithm_declares_what_the_checkers_read(name):
    factory = algorithm_factory(name)
    claims = claims_of(name)
    assert all(isinstance(v, (str, type(None))) for v in claims.values())
    plan = getattr(factory, "verify", None)
    assert plan is None or isinstance(plan, VerifyPlan)
    assert isinstance(getattr(factory, "premise_monitors", ()), tuple)


def test_verify_plans_order_and_content():
    plans = verify_plans()
    assert [n for n, _ in plans] == ["song2016", "song2016-literal", "song2016-subtree-clock", "song2014", "jiang",
                                     "jiang-literal",
                                     "wang2020", "wang2020-broadcast-handshake", "leechong-leader", "leechong-neighbor", "leechong-leader-printed", "leechong-neighbor-printed",
                                     "example-gather", "example-anonymous-line", "example-grid-goals"]
    for _, plan in (plans[0], plans[2], plans[3]):
        assert plan.targets == ("square", "hexagon", "octagon-square") and plan.robots == 10
        assert plan.seeds == (0, 1, 2)
    assert plans[0][1].more == (("square", 20, (1,)),)           # the Lemma 11 lag finding (issue 19)
    assert plans[1][1].runs() == (("hexagon", 40, (2,)),)       # the literal reading's deadlock
    assert plans[2][1].runs() == plans[0][1].runs()             # the subtree clock beside the default


def test_an_installed_package_adds_its_algorithm_by_entry_point(monkeypatch):
    import importlib.metadata as md

    from swarmproof.reference_impl import registry

    ep = md.EntryPoint(name="their-gather", value="swarmproof.reference_impl.examples:GatherToLowestId",
                       group=registry.ENTRY_POINT_GROUP)
    monkeypatch.setattr(md, "entry_points", lambda group=None: [ep] if group == registry.ENTRY_POINT_GROUP else [])
    monkeypatch.setattr(registry, "_PLUGINS_LOADED", False)
    monkeypatch.setattr(registry, "ALGORITHMS", dict(registry.ALGORITHMS))
    assert "their-gather" in registry.algorithm_names()
    assert registry.get_algorithm("their-gather").name == "example-gather"
