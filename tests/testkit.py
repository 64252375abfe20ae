"""Helpers shared by test modules (``from testkit import ...``; conftest puts this folder on the path)."""

from __future__ import annotations

import os
import re


class Recorder:
    """A test algorithm whose controllers record every observation (``seen``: (robot_id, obs), in
    engine order) and answer ``command(robot_id, k, obs, rng)`` (k: the controller's call count);
    by default a random move and a message of what the robot saw."""

    name = "recorder"
    assumptions = ()

    def __init__(self, model, command=None):
        self.model = model
        self.command = command
        self.seen: list = []

    def controller(self, robot_id, params, target, rng):
        from swarmproof.reference_impl.protocol import Command

        algo = self

        class C:
            def __init__(self):
                self.k = 0

            def step(self, obs):
                algo.seen.append((robot_id, obs))
                self.k += 1
                if algo.command is not None:
                    return algo.command(robot_id, self.k - 1, obs, rng)
                msg = ("saw", len(obs.neighbor_poses), obs.step, round(float(rng.uniform()), 6))
                return Command(message=msg, turn=float(rng.uniform(-1, 1)), forward=float(rng.uniform(0, 0.1)))

            def state(self):
                return (("k", self.k),)

        return C()

    def finished(self, states):
        return False


# -- the CI gate's mutation test (issue 14) ----------------------------------------------------

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHIPPED = os.path.join(ROOT, "verify-baseline.json")
MUTANT = "song2016_children_none"


def write_mutant(folder) -> str:
    """A copy of reference_impl/song2016/algorithm.py in ``folder`` whose robots see no children: the
    NCLB safe region (Sec. V-C) no longer constrains a moving parent."""
    src = open(os.path.join(ROOT, "reference_impl", "song2016", "algorithm.py"), encoding="utf-8").read()
    src = re.sub(r"^(\s*)from \.\.", r"\1from swarmproof.reference_impl.", src, flags=re.M)
    src = re.sub(r"^(\s*)from \.", r"\1from swarmproof.reference_impl.song2016.", src, flags=re.M)
    line = "children = tuple([sid for sid, m in zip(keys, inbox) if m.parent_id == me and sid in ids])"
    assert src.count(line) == 1, "the mutation point moved: update this test"
    src = src.replace(line, "children = ()  # mutation: NCLB no longer constrains the parent")
    path = os.path.join(folder, MUTANT + ".py")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(src)
    return path


def load_benchmark(name: str):
    """The script ``benchmarks/NAME.py`` as a module (benchmarks/ is not a package), loaded once per
    process under ``swarmproof_bench_NAME``: tests of a benchmark's pieces share one copy.  A paper's
    scripts live in its folder, so NAME names it: ``wang2020/bench_wang2020``, ``jiang/experiments``;
    the shared tools are at the top: ``bench_mutations``."""
    import importlib.util
    import sys

    mod_name = "swarmproof_bench_" + name.replace("/", "_")
    if mod_name in sys.modules:
        return sys.modules[mod_name]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = os.path.join(root, "benchmarks", f"{name}.py")
    if not os.path.isfile(path):
        raise FileNotFoundError(f"load_benchmark: name={name!r}: no file {path}; a paper's benchmark scripts "
                                "are in its folder: use 'PAPER/NAME' (e.g. 'wang2020/bench_wang2020')")
    spec = importlib.util.spec_from_file_location(mod_name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[mod_name] = mod
    spec.loader.exec_module(mod)
    return mod


# -- readings (issue 29) ----------------------------------------------------------------------

def gather_reading(reading: str):
    """A subclass of ``example-gather`` that declares another reading version (behaviour unchanged):
    what a change that bumps an algorithm's reading leaves registered under a new name."""
    from swarmproof.reference_impl.examples import GatherToLowestId

    return type(f"GatherReading{reading}", (GatherToLowestId,), {"reading": reading, "__module__": __name__})


GatherReading0 = gather_reading("0")


#: Each suite lemma's proof, once per test process (``proved``).
_PROVED: dict = {}


#: The wall-clock ceiling of a proof made for the tests (``proved``): a ceiling that a loaded
#: machine cannot reach, never the thing checked (tests/README.md).  wang2020's separation lemma
#: took 7.5 s of the old 10 s timeout on an idle machine here, and timed out (inconclusive) at
#: load 5; z3's rlimit budget decides now (docs/proofs.md "Budgets"), the ceiling stays an outer cap.
PROOF_CEILING_S = 120.0


def proved(lemma, timeout_s: float = 10.0):
    """``swarmproof.checkers.proofs.prove(lemma, ...)``, run once per test process: the
    per-lemma test (tests/checkers/test_proofs.py), verify's lemma section
    (tests/cli/test_verify.py, whose ``run_suite`` is patched to call this) and the tests of a
    suite lemma's control counterexample (tests/checkers/test_proofs_wang2020.py) judge the same z3
    results.  All are in the xdist group ``z3-suite``, so one worker proves each lemma once (the
    suite was proved twice, 12 s of CPU).

    The proof runs with :data:`PROOF_CEILING_S`, whatever ``timeout_s`` the caller names (the
    timeout the code under test is given): z3's answers and models do not depend on the time left
    (each call's limit is the time left to a deadline, which differs from run to run;
    test_suite_json_is_deterministic_except_timings), so a lemma proved within 10 s on an idle
    machine gives the same result, and a loaded test machine cannot turn it inconclusive.  What a
    timeout does is tested with ``prove`` itself (test_timeout_is_inconclusive_never_proved)."""
    from swarmproof.checkers import proofs

    key = lemma.id
    if key not in _PROVED:
        _PROVED[key] = proofs.prove(lemma, max(float(timeout_s), PROOF_CEILING_S))
    return _PROVED[key]


class FakeTerminal:
    """stdout and stderr of one terminal: both write into one screen buffer."""

    def __init__(self) -> None:
        self.text = ""

    def write(self, s: str) -> int:
        self.text += s
        return len(s)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return True

    def lines(self) -> list:
        """What the terminal shows: each line after its last carriage return, erase codes dropped."""
        return [ln.rsplit("\r", 1)[-1].replace("\033[K", "") for ln in self.text.split("\n")]


# -- exhaustive checking's toy (issue 33) -------------------------------------------------------

class Toggle:
    """A toy for exhaustive checking: robots that never move; a robot that acts flips its bit ``x``
    and broadcasts ``("t", step)``.  ``bug(robot_id, obs, x)`` returning True makes that robot's
    controller raise (a planted bug, found by ``no_crash``)."""

    name = "toggle"
    assumptions = ()
    bug = None

    def __init__(self):
        from swarmproof.reference_impl.protocol import RobotModel

        self.model = RobotModel(sensing="local", communication="neighbors", motion="holonomic", clocks="sync")

    def controller(self, robot_id, params, target, rng):
        from swarmproof.reference_impl.protocol import Command

        algo = self

        class C:
            x = 0

            def step(self, obs):
                if algo.bug is not None and algo.bug(robot_id, obs, self.x):
                    raise RuntimeError(f"planted bug: robot {robot_id} at step {obs.step}")
                self.x = 1 - self.x
                return Command(message=("t", obs.step))

            def state(self):
                return (("x", self.x),)

        return C()

    def finished(self, states):
        return False


class ToggleBuggy(Toggle):
    """Toggle whose robot 2 raises when it acts at step 1 having heard nobody: only when robots 1
    and 3 (its only neighbours) were both left out at step 0 -- 2 deviations, the fewest."""

    name = "toggle-buggy"

    @staticmethod
    def bug(robot_id, obs, x):
        return robot_id == 2 and obs.step == 1 and len(obs.messages) == 0


def toggle_start():
    """Three robots in a line, each within range 1 of the next."""
    from swarmproof.models.trace import InitialConfiguration

    return InitialConfiguration([1, 2, 3], [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]])


class ToggleRows(Toggle):
    """Toggle with ``verify`` rows: ``no_crash`` for every schedule within 4 steps and 3 robots
    idle; its robots raise when one acts at step 1 having heard nobody (always reachable: leave
    all but one robot out at step 0)."""

    name = "toggle-rows"

    @staticmethod
    def bug(robot_id, obs, x):
        return obs.step == 1 and len(obs.messages) == 0

    @classmethod
    def _plan(cls):
        from swarmproof.reference_impl.protocol import ExhaustiveCell, VerifyPlan

        return VerifyPlan(explore=False, exhaustive=(
            ExhaustiveCell(("no_crash",), ("activate",), steps=4, deviations=3, target="square"),
            ExhaustiveCell(("no_crash",), ("loss",), steps=3, deviations=1, target="square")))


ToggleRows.verify = ToggleRows._plan()
