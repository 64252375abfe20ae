"""Every command block of README.md and docs/*.md runs as the page shows it (issue 29).

A command block is a fenced block marked ``sh``, ``bash`` or ``console``:

* ``sh`` / ``bash``: every line is a command (``\\`` continues a line; ``#`` starts a comment);
* ``console``: a line ``$ COMMAND`` is a command, and the lines under it, up to the next ``$``,
  are its output as the page shows it.  ``$ echo $?`` shows the exit code of the command before.

Each block runs in a fresh temporary folder (its commands share it: an ``explore --out cx`` and
the ``replay cx/...`` after it), with the venv's ``bin`` first on ``PATH``.  A command must be
accepted and must not crash: exit 2 (usage) only where the page shows the error, never 4
(internal) or 130.  The output is compared by its *shape*: the page's lines in order, a line
``...`` standing for any number of lines, a line ending in ``...`` for a line the page
shortened; runs of blanks and numbers with a decimal point (times, coordinates) are not compared,
integers (counts, exit codes) are.  A ``--json`` command must print one JSON document (its
``exit_code``, when it has one, the exit code); a ``--plot``/``--gif``/``--trace`` file must be
written.

An HTML comment on the line right before a fence says how to treat the block:

* ``<!-- doc-test: skip (reason: ...) -->``: not run (placeholders for the reader's own
  package, the whole gate, a cluster, benchmarks of many minutes); the reason is required;
* ``<!-- doc-test: slow (reason: ...) -->``: run only by the slow suite (``pytest -m slow``,
  ``make test-slow``); the reason is required;
* ``<!-- doc-test: file NAME -->`` before a block of any language: the block is the file
  ``NAME`` that the command blocks after it on the same page read (written into their folder).

Blocks without a language that hold commands are refused (so a new one cannot be missed), and
so are commands other than ``swarmproof``, ``echo $?`` and ``python`` in a block that runs.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
COMMAND_LANGS = {"sh", "bash", "console"}
KINDS = {"skip", "slow", "file"}
OPEN = re.compile(r"^(\s*)```([\w-]*)\s*$")
CLOSE = re.compile(r"^\s*```\s*$")
DIRECTIVE = re.compile(r"^\s*<!--\s*doc-test:\s*(\w+)\s*(.*?)\s*-->\s*$")
REASON = re.compile(r"^\(reason:\s*(\S.*)\)$")
#: a line that reads as a command (not an error message such as "swarmproof check-lattice: error: ...")
LOOKS_LIKE_COMMAND = re.compile(r"^\s*(\$ |(swarmproof|python3?|make|\.venv/bin/\S+) (?![\w-]+:))")
FLOAT = re.compile(r"-?\d+\.\d+(?:e[-+]?\d+)?")
#: output options whose file must exist after a run that judged something (exit 0, 1 or 3)
FILE_OPTIONS = ("--plot", "--gif", "--trace", "--junit", "--html", "--markdown")


@dataclass
class Block:
    page: str                 # path relative to the repository
    line: int                 # line of the opening fence (1-based)
    lang: str
    body: list[str]
    directives: dict[str, str] = field(default_factory=dict)   # kind -> its text
    files: dict[str, str] = field(default_factory=dict)        # files defined before it on the page

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def _blocks(page: Path) -> list[Block]:
    lines = page.read_text(encoding="utf-8").splitlines()
    rel = page.relative_to(ROOT).as_posix()
    out, files, i = [], {}, 0
    while i < len(lines):
        m = OPEN.match(lines[i])
        if not m:
            i += 1
            continue
        indent, lang, start = m.group(1), m.group(2), i
        i += 1
        while i < len(lines) and not CLOSE.match(lines[i]):
            i += 1
        body = [ln[len(indent):] if ln.startswith(indent) else ln.lstrip() for ln in lines[start + 1:i]]
        directives, k = {}, start - 1
        while k >= 0 and DIRECTIVE.match(lines[k]):
            d = DIRECTIVE.match(lines[k])
            directives[d.group(1)] = d.group(2)
            k -= 1
        block = Block(rel, start + 1, lang, body, directives, dict(files))
        if "file" in directives:
            files[directives["file"]] = "\n".join(body) + "\n"
        out.append(block)
        i += 1
    return out


ALL_BLOCKS = [b for page in PAGES for b in _blocks(page)]
COMMAND_BLOCKS = [b for b in ALL_BLOCKS if b.lang in COMMAND_LANGS]


def _reason(block: Block, kind: str) -> str | None:
    m = REASON.match(block.directives.get(kind, ""))
    return m.group(1) if m else None


def _commands(block: Block) -> list[tuple[str, list[str] | None]]:
    """``(command, the output the page shows or None)`` of a command block, in order."""
    if block.lang == "console":
        cmds: list[tuple[str, list[str] | None]] = []
        for ln in block.body:
            if ln.startswith("$ "):
                cmds.append((ln[2:].strip(), []))
            elif cmds:
                cmds[-1][1].append(ln)
        return [(c, out if out else None) for c, out in cmds]
    joined, cmds = "", []
    for ln in block.body:
        joined += ln
        if joined.endswith("\\"):
            joined = joined[:-1] + " "
            continue
        if joined.strip() and not joined.strip().startswith("#"):
            cmds.append((joined.strip(), None))
        joined = ""
    return cmds


def _norm(line: str) -> str:
    return " ".join(FLOAT.sub("#", line).split())


def _line_matches(doc: str, out: str) -> bool:
    d = _norm(doc)
    if d.endswith("..."):      # a line the page shortened
        return _norm(out).startswith(d[:-3].rstrip())
    return _norm(out) == d


def _shape_problem(shown: list[str], actual: list[str]) -> str | None:
    """What differs between the output the page shows and the actual one (None: the same shape)."""
    while actual and not actual[-1].strip():
        actual = actual[:-1]
    shown = [s for s in shown if s.strip()]
    pos, gap = 0, False
    for s in shown:
        if s.strip() == "...":
            gap = True
            continue
        if gap:
            hit = next((j for j in range(pos, len(actual)) if _line_matches(s, actual[j])), None)
        else:
            hit = pos if pos < len(actual) and _line_matches(s, actual[pos]) else None
        if hit is None:
            near = actual[pos] if pos < len(actual) else "(end of output)"
            return f"the page shows {s!r}, the command printed at that place {near!r}"
        pos, gap = hit + 1, False
    if not gap and pos < len(actual):
        return f"the command printed more than the page shows (and no '...'): {actual[pos]!r}"
    return None


def _argv(command: str, block: Block) -> list[str]:
    argv = shlex.split(command, comments=True)
    if argv[0] == "swarmproof":
        return [str(BIN / "swarmproof"), *argv[1:]]
    if argv[0] in ("python", "python3", ".venv/bin/python"):
        return [sys.executable, *argv[1:]]
    pytest.fail(f"{block.id}: {command!r}: only swarmproof, python and `echo $?` run here; "
                f"mark the block `<!-- doc-test: skip (reason: ...) -->` if it must not run")


def _option_values(argv: list[str], option: str) -> list[str]:
    vals = [argv[i + 1] for i, a in enumerate(argv[:-1]) if a == option]
    return vals + [a.split("=", 1)[1] for a in argv if a.startswith(option + "=")]


def _params():
    for b in COMMAND_BLOCKS:
        if "skip" in b.directives:
            yield pytest.param(b, id=b.id, marks=pytest.mark.skip(reason=_reason(b, "skip") or "no reason"))
        elif "slow" in b.directives:
            yield pytest.param(b, id=b.id, marks=pytest.mark.slow)
        else:
            yield pytest.param(b, id=b.id)


@pytest.mark.parametrize("block", list(_params()))
def test_command_block_runs_as_the_page_shows(block: Block, tmp_path):
    slow = "slow" in block.directives
    env = dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}", MPLBACKEND="Agg")
    env.pop("CI", None)
    for name, text in block.files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    commands = _commands(block)
    assert commands, f"{block.id}: a command block without a command"
    rc = None
    for command, shown in commands:
        where = f"{block.id}: `{command}`"
        if command == "echo $?":
            assert rc is not None, f"{where}: no command before it"
            assert shown is not None and [s.strip() for s in shown if s.strip()] == [str(rc)], \
                f"{where}: the page shows exit code {shown}, the command exited {rc}"
            continue
        argv = _argv(command, block)
        proc = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=1800 if slow else 300)
        rc = proc.returncode
        tail = f"\n--- stdout (end) ---\n{proc.stdout[-2000:]}\n--- stderr (end) ---\n{proc.stderr[-2000:]}"
        shows_error = shown is not None and any(": error:" in s for s in shown)
        assert rc not in (4, 130), f"{where}: exit {rc} (an internal error or an interrupt){tail}"
        assert rc != 2 or shows_error, f"{where}: exit 2, a usage error the page does not show{tail}"
        if shown is not None:
            stream = proc.stderr if shows_error else proc.stdout
            problem = _shape_problem(shown, stream.splitlines())
            assert problem is None, f"{where}: {problem}{tail}"
        if "--json" in argv and rc != 2:
            doc = json.loads(proc.stdout)     # exactly one JSON document
            if isinstance(doc, dict) and "exit_code" in doc:
                assert doc["exit_code"] == rc, f"{where}: JSON exit_code {doc['exit_code']}, exit {rc}"
        if rc in (0, 1, 3):
            for option in FILE_OPTIONS:
                for value in _option_values(argv, option):
                    path = tmp_path / value
                    assert path.is_file() and path.stat().st_size > 0, f"{where}: {option} {value} was not written"


def test_every_skip_and_slow_block_says_why():
    problems = []
    for b in ALL_BLOCKS:
        for kind, text in b.directives.items():
            if kind not in KINDS:
                problems.append(f"{b.id}: unknown `doc-test: {kind}` (one of {sorted(KINDS)})")
            elif kind in ("skip", "slow") and _reason(b, kind) is None:
                problems.append(f"{b.id}: `doc-test: {kind}` needs its reason: `{kind} (reason: ...)`, got {text!r}")
            elif kind in ("skip", "slow") and b.lang not in COMMAND_LANGS:
                problems.append(f"{b.id}: `doc-test: {kind}` on a block that is not a command block ({b.lang!r})")
            elif kind == "file" and not re.fullmatch(r"[\w.-]+", text):
                problems.append(f"{b.id}: `doc-test: file NAME` needs a plain file name, got {text!r}")
    assert not problems, "\n".join(problems)


def test_every_directive_stands_right_before_a_fence():
    problems = []
    for page in PAGES:
        lines = page.read_text(encoding="utf-8").splitlines()
        for i, ln in enumerate(lines):
            if DIRECTIVE.match(ln):
                k = i + 1
                while k < len(lines) and DIRECTIVE.match(lines[k]):
                    k += 1
                if k >= len(lines) or not OPEN.match(lines[k]):
                    problems.append(f"{page.relative_to(ROOT)}:{i + 1}: a doc-test comment not right before a fence")
            elif "doc-test" in ln and "<!--" in ln:
                problems.append(f"{page.relative_to(ROOT)}:{i + 1}: a malformed doc-test comment: {ln.strip()!r}")
    assert not problems, "\n".join(problems)


def test_no_command_block_without_a_language():
    """A block of commands must say sh/bash/console (else it would escape this test); usage
    synopses and sample output are ``text``."""
    unmarked = [f"{b.id}: {next(ln for ln in b.body if ln.strip())!r}" for b in ALL_BLOCKS
                if b.lang == "" and any(LOOKS_LIKE_COMMAND.match(ln) for ln in b.body)]
    assert not unmarked, ("blocks of commands without a language (mark them sh or console, or text "
                          "for a synopsis):\n" + "\n".join(unmarked))


def test_the_parser_reads_what_the_pages_hold():
    """The extraction itself: console commands with their output, continued sh lines, files."""
    blocks = {b.id: b for b in COMMAND_BLOCKS}
    assert len(COMMAND_BLOCKS) >= 20
    readme = [b for b in COMMAND_BLOCKS if b.page == "README.md" and b.lang == "console"]
    cmds = _commands(readme[1])
    assert [c for c, _ in cmds] == ["swarmproof check-lattice square --range 1.5", "echo $?"]
    assert cmds[1][1] == ["1"]
    assert _shape_problem(["a 1.5", "...", "c ..."], ["a 2.25", "b", "c d e"]) is None
    assert _shape_problem(["a", "c"], ["a", "b", "c"]) is not None
    assert _shape_problem(["10 lemmas"], ["18 lemmas"]) is not None
    assert any(b.files for b in blocks.values())


def test_the_documented_entry_point_pyproject_registers_an_algorithm(tmp_path, monkeypatch):
    """docs/explorer.md's whole pyproject.toml: its entry-point group is the one the registry reads,
    and the names it declares resolve to the class (as an installed package's would; the
    registry's own entry-point route is tests/test_one_algorithm_one_module.py's)."""
    tomllib = pytest.importorskip("tomllib")
    import importlib.metadata as md

    from swarmproof.reference_impl import registry

    shown = [b for b in ALL_BLOCKS if b.directives.get("file") == "pyproject.toml"]
    assert [b.page for b in shown] == ["docs/explorer.md"], "one documented pyproject.toml"
    doc = tomllib.loads("\n".join(shown[0].body))
    assert doc["build-system"]["build-backend"] == "setuptools.build_meta"
    assert {"name", "version"} <= set(doc["project"])
    group = doc["project"]["entry-points"][registry.ENTRY_POINT_GROUP]
    assert group == {"mine": "my_package.my_module:MyAlgorithm"}
    packages = doc["tool"]["setuptools"]["packages"]
    # the package the pyproject.toml describes, with a class of the documented name in it
    for name, value in group.items():
        module, _, qualname = value.partition(":")
        assert module.split(".")[0] in packages and qualname.isidentifier()
    pkg = tmp_path / "my_package"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "my_module.py").write_text(
        "from swarmproof.reference_impl.examples import GatherToLowestId\n\n\n"
        "class MyAlgorithm(GatherToLowestId):\n    name = 'mine'\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    eps = [md.EntryPoint(name=n, value=v, group=registry.ENTRY_POINT_GROUP) for n, v in group.items()]
    monkeypatch.setattr(md, "entry_points", lambda group=None: eps if group == registry.ENTRY_POINT_GROUP else [])
    monkeypatch.setattr(registry, "_PLUGINS_LOADED", False)
    monkeypatch.setattr(registry, "ALGORITHMS", dict(registry.ALGORITHMS))
    assert "mine" in registry.algorithm_names()
    assert registry.algorithm_factory("mine").__name__ == "MyAlgorithm"
    assert registry.get_algorithm("mine").name == "mine"


def test_the_premises_table_names_what_the_code_declares():
    """docs/explorer.md's table of premise monitors: each row's algorithm declares exactly the
    monitors it lists, each monitor is registered for the lemma(s) the row names, and those are
    the proof suite's lemmas."""
    from swarmproof.checkers.proofs import LEMMAS
    from swarmproof.invariants.premises import MONITOR_LEMMAS, MONITORS
    from swarmproof.reference_impl import registry

    text = (ROOT / "docs" / "explorer.md").read_text(encoding="utf-8")
    table = text.split("| algorithm | monitors | lemmas (`swarmproof prove` ids) |", 1)[1].split("\n\n", 1)[0]
    rows = [r for r in table.splitlines() if r.startswith("| ") and not r.startswith("|---")]
    declared = {}
    variants = set()
    for row in rows:
        algo, monitors, lemmas = (c.strip() for c in row.strip("|").split(" | "))
        name = algo.split()[0]
        if name == "anything":
            continue
        listed = re.findall(r"`(\w+)`", monitors)
        declared[name] = listed
        assert tuple(listed) == registry.algorithm_factory(name).premise_monitors, row
        # registered variants the row names ("song2016 and its variants ...") declare the same monitors
        for other in set(re.findall(r"[\w-]+", algo.split("(`")[0])) & set(registry.algorithm_names()) - {name}:
            assert registry.algorithm_factory(other).premise_monitors == tuple(listed), (row, other)
            variants.add(other)
        if "(`reference_impl/" in algo:
            assert (ROOT / algo.split("`")[1]).is_file(), row
        for m in listed:
            assert m in MONITORS and f"`{MONITOR_LEMMAS[m]}`" in lemmas, (row, m)
        cases = "".join(p.read_text(encoding="utf-8") for p in (ROOT / "reference_impl").glob("*/monitors.py"))
        cases += "".join(p.read_text(encoding="utf-8") for p in (ROOT / "reference_impl").glob("*/lemmas.py"))
        for lemma in re.findall(r"`(\w+)`", lemmas):   # a lemma, a monitor or a case a monitor names
            assert lemma in LEMMAS or lemma in MONITORS or f"case {lemma}" in cases, (row, lemma)
    assert set(declared) == {n for n in ("song2016", "song2014", "wang2020", "example-gather")}
    others = {n for n in registry.algorithm_names()
              if getattr(registry.algorithm_factory(n), "premise_monitors", None)
              and n not in declared and n not in variants}
    assert not others, f"algorithms with premise monitors the table does not list: {sorted(others)}"
