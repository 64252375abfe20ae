"""The ``swarmproof-campaign/1`` file: a matrix of explorations and experiments (docs/campaigns.md).

YAML (or JSON, a subset of YAML)::

    format: swarmproof-campaign/1
    name: small
    explore:                          # explorer cells
      - algorithm: song2014           # a registry name or module:qualname
        properties: [connectivity, tree_links]   # default: every registered property
        robots: [3, 6]                # [MIN, MAX] robots per scenario
        seeds: [0, 1]                 # Hypothesis seeds: one task per property and seed
        max_examples: 20              # per task (no wall clock: results do not depend on the machine)
        lattices: [square, hexagon]   # optional: the targets scenarios draw from
        draw_faults: [schedule]       # optional: asynchronous schedules, crashes, ... (explorer FAULT_KINDS)
        speeds: [0.05, 0.4]           # optional: speeds scenarios draw v from
        max_steps: 4000               # optional: the engine's step cap
    simulate:                         # experiment cells: seeded runs with metrics
      - algorithm: song2016
        targets: [square, hexagon]    # bundled target names ([KIND:]NAME)
        robots: [10, 20, 40]          # team sizes: one task per target, size and seed
        seeds: [0, 1, 2]              # or  seeds: {count: 20}  (seeds 0..19)
        max_steps: 20000              # optional
        start: {uniform: 15.0, separation: 0.14}   # optional: uniform starts in a square (default: connected)
    experiment:                       # a paper experiment's seeded trials
      - algorithm: wang2020           # a registry name or module:qualname
        experiment: fig10             # an experiment the algorithm declares (its ``experiments``)
        robots: [16, 64]              # team sizes: one task per size and seed
        seeds: {count: 200}
        options: {arena: 32}          # the experiment's own options (checked against its declaration)
    exhaustive:                       # exhaustive bounded checking (docs/exhaustive.md)
      - algorithm: song2014
        properties: [connectivity]    # default: every property that applies
        robots: [3, 4]                # team sizes: one task per property, size and start
        seeds: [0, 1]                 # seeded starts (simulate --robots N --seed S)
        choices: [activate]           # the choice kinds enumerated
        steps: 15                     # the bound: steps, and deviations (K)
        deviations: 2

Every problem is an :class:`~swarmproof.models.errors.InputFileError` naming
the file, the line and the field (``explore[0].robots``) and how to fix it.
This module checks the form; names (algorithms, properties, targets, experiments and their options) are
checked against the registries by :mod:`swarmproof.checkers.campaign`, with
the same locations (:meth:`CampaignSpec.error`).

Examples
--------
>>> spec = loads_campaign('''
... format: swarmproof-campaign/1
... name: small
... explore:
...   - algorithm: song2014
...     properties: [connectivity, tree_links]
...     robots: [3, 6]
...     seeds: [0, 1]
...     max_examples: 20
... ''')
>>> spec.name, len(spec.explore), spec.explore[0].seeds
('small', 1, (0, 1))
>>> loads_campaign("format: swarmproof-campaign/1\\nname: x\\nexplore:\\n  - algorithm: song2014\\n    robots: [6, 3]\\n")
Traceback (most recent call last):
...
swarmproof.models.errors.InputFileError: <string>:5: field 'explore[0].robots': explore[0].robots=[6, 3] must be [MIN, MAX] with 1 <= MIN <= MAX <= 100000; fix: e.g. robots: [3, 8]
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from typing import Any

import yaml

from swarmproof.models.errors import InputFileError
from swarmproof.models.lattice_io import _field   # one field-path notation for every input file

__all__ = ["CAMPAIGN_FORMAT", "CampaignSpec", "ExploreCell", "SimulateCell", "ExperimentCell", "ExhaustiveSpecCell",
           "loads_campaign", "load_campaign_file"]

CAMPAIGN_FORMAT = "swarmproof-campaign/1"

#: Upper bounds that keep one spec's work and memory bounded (a typo of 10**9 seeds is an error,
#: not an afternoon of scheduling).
MAX_SEEDS = 100_000
MAX_TASKS = 1_000_000
MAX_ROBOTS = 100_000

_TOP = ("format", "name", "explore", "simulate", "experiment", "exhaustive", "description")
_EXPLORE = ("algorithm", "properties", "robots", "seeds", "max_examples", "lattices", "draw_faults", "speeds",
            "max_steps", "params", "allow_violations")
_SIMULATE = ("algorithm", "targets", "robots", "seeds", "max_steps", "start")
_EXPERIMENT = ("algorithm", "experiment", "robots", "seeds", "options")
_EXHAUSTIVE = ("algorithm", "properties", "robots", "seeds", "choices", "steps", "deviations", "max_delay",
               "max_crashes", "target")


@dataclass(frozen=True)
class ExploreCell:
    """One explorer cell: ``explore(algorithm, [property], ...)`` for each property and seed."""

    index: int
    algorithm: str
    properties: tuple[str, ...] | None
    robots: tuple[int, int]
    seeds: tuple[int, ...]
    max_examples: int
    lattices: tuple[str, ...] | None = None
    draw_faults: tuple[str, ...] = ()
    speeds: tuple[float, ...] | None = None
    max_steps: int | None = None
    params: dict = field(default_factory=dict)
    allow_violations: bool = False

    @property
    def path(self) -> tuple:
        return ("explore", self.index)

    @property
    def label(self) -> str:
        faults = f" faults={'+'.join(self.draw_faults)}" if self.draw_faults else ""
        return f"explore[{self.index}] {self.algorithm} n={self.robots[0]}..{self.robots[1]}{faults}"


@dataclass(frozen=True)
class SimulateCell:
    """One experiment cell: a seeded run for each target, team size and seed."""

    index: int
    algorithm: str
    targets: tuple[str, ...]
    robots: tuple[int, ...]
    seeds: tuple[int, ...]
    max_steps: int | None = None
    #: None: seeded connected starts (``random_connected`` at the target's range); or
    #: ``{"uniform": SIDE, "separation": D}``: uniform in ``[0, SIDE]^2``, ``D`` apart.
    start: dict | None = None

    @property
    def path(self) -> tuple:
        return ("simulate", self.index)

    @property
    def label(self) -> str:
        return f"simulate[{self.index}] {self.algorithm}"


@dataclass(frozen=True)
class ExperimentCell:
    """One paper-experiment cell: the experiment's trial ``fn(n, seed, **options)`` for each team
    size and seed (the function is the one the algorithm declares under ``experiment``)."""

    index: int
    algorithm: str
    experiment: str
    robots: tuple[int, ...]
    seeds: tuple[int, ...]
    #: the options as written (the checker adds the defaults of the others)
    options: dict = field(default_factory=dict)

    @property
    def path(self) -> tuple:
        return ("experiment", self.index)

    @property
    def label(self) -> str:
        opts = "".join(f" {k}={v}" for k, v in sorted(self.options.items()))
        return f"experiment[{self.index}] {self.algorithm} {self.experiment}{opts}"


@dataclass(frozen=True)
class ExhaustiveSpecCell:
    """One exhaustive cell: every choice sequence within the bound, for each property, team size
    and seeded start (one task each: the starts are independent)."""

    index: int
    algorithm: str
    properties: tuple[str, ...] | None
    robots: tuple[int, ...]
    seeds: tuple[int, ...]
    choices: tuple[str, ...] = ("activate",)
    steps: int = 20
    deviations: int = 2
    max_delay: int = 1
    max_crashes: int = 1
    target: str | None = None

    @property
    def path(self) -> tuple:
        return ("exhaustive", self.index)

    @property
    def label(self) -> str:
        return (f"exhaustive[{self.index}] {self.algorithm} {'+'.join(self.choices)} S={self.steps} "
                f"K={self.deviations}")


@dataclass
class CampaignSpec:
    """A checked campaign file."""

    name: str
    explore: list[ExploreCell]
    simulate: list[SimulateCell]
    document: dict
    source: str = "<string>"
    lines: dict = field(default_factory=dict, repr=False)
    experiment: list[ExperimentCell] = field(default_factory=list)
    exhaustive: list[ExhaustiveSpecCell] = field(default_factory=list)

    @property
    def digest(self) -> str:
        """SHA-256 of the document's canonical JSON: what a results store is tied to."""
        text = json.dumps(self.document, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    def line(self, path) -> int | None:
        """The line of ``path`` (or of its nearest enclosing field)."""
        from swarmproof.models.lattice_io import _Ctx

        return _Ctx(self.source, self.lines).line(path)

    def error(self, path, message: str, fix: str) -> InputFileError:
        """An error located at ``path`` (e.g. ``("explore", 0, "algorithm")``) of this file."""
        from swarmproof.models.lattice_io import _Ctx

        return _Ctx(self.source, self.lines).error(path, message, fix)


def _walk(node, path: tuple, lines: dict, depth: int = 0) -> None:
    if depth > 6:
        return
    lines[path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        for knode, vnode in node.value:
            if isinstance(knode, yaml.ScalarNode):
                lines[path + (knode.value,)] = knode.start_mark.line + 1
                _walk(vnode, path + (knode.value,), lines, depth + 1)
                lines[path + (knode.value,)] = knode.start_mark.line + 1
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _walk(item, path + (i,), lines, depth + 1)


def _parse(text: str, source: str) -> tuple[Any, dict]:
    from swarmproof.models.lattice_io import parse_yaml_node

    data, node = parse_yaml_node(text, source, nesting="a campaign file nests at most five levels")
    lines: dict = {}
    if node is not None:
        _walk(node, (), lines)
    return data, lines


class _Check:
    def __init__(self, source: str, lines: dict) -> None:
        self.spec = CampaignSpec("", [], [], {}, source, lines)

    def fail(self, path, message: str, fix: str):
        raise self.spec.error(path, message, fix)

    def int_(self, path, v, lo: int, hi: int, example: str) -> int:
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            self.fail(path, f"{_field(path)}={v!r} must be an integer in {lo}..{hi}", f"e.g. {example}")
        return v

    def names(self, path, v, example: str) -> tuple[str, ...]:
        if isinstance(v, str):
            v = [v]
        if not isinstance(v, list) or not v or not all(isinstance(x, str) and x for x in v):
            self.fail(path, f"{_field(path)}={v!r} must be a non-empty list of names", f"e.g. {example}")
        if len(set(v)) != len(v):
            self.fail(path, f"{_field(path)}={v!r} repeats a name", "list each once")
        return tuple(v)

    def seeds(self, path, v) -> tuple[int, ...]:
        if isinstance(v, dict):
            extra = set(v) - {"count", "start"}
            if extra or "count" not in v:
                self.fail(path, f"{_field(path)}={v!r} must be a list of seeds or {{count: N, start: S}}",
                          "e.g. seeds: [0, 1, 2]  or  seeds: {count: 20}")
            n = self.int_(path + ("count",), v["count"], 1, MAX_SEEDS, "count: 20")
            s = self.int_(path + ("start",), v.get("start", 0), 0, 2**31 - 1, "start: 0")
            return tuple(range(s, s + n))
        if not isinstance(v, list) or not v:
            self.fail(path, f"{_field(path)}={v!r} must be a non-empty list of seeds", "e.g. seeds: [0, 1, 2]")
        out = tuple(self.int_(path + (i,), x, 0, 2**31 - 1, "seeds: [0, 1]") for i, x in enumerate(v))
        if len(set(out)) != len(out):
            self.fail(path, f"{_field(path)}={v!r} repeats a seed", "list each seed once")
        if len(out) > MAX_SEEDS:
            self.fail(path, f"{_field(path)} has {len(out)} seeds (more than {MAX_SEEDS})", "split the campaign")
        return out

    def keys(self, path, d, allowed) -> None:
        if not isinstance(d, dict):
            self.fail(path, f"{_field(path) or 'the document'}={d!r} must be a mapping (key: value)",
                      "see docs/campaigns.md for the layout")
        from swarmproof.models.errors import did_you_mean

        for k in d:
            if k not in allowed:
                self.fail(path + (k,), f"key {k!r} is not known here{did_you_mean(str(k), allowed)}",
                          f"use only {list(allowed)!r}")

    def cell_head(self, p: tuple, d, allowed) -> str:
        """Check a cell's keys and return its algorithm."""
        self.keys(p, d, allowed)
        algo = d.get("algorithm")
        if not isinstance(algo, str) or not algo:
            self.fail(p + ("algorithm",), f"{_field(p + ('algorithm',))}={algo!r} must be a registry name or "
                                          "module:qualname", "e.g. algorithm: song2014")
        return algo


def _explore_cell(c: _Check, i: int, d) -> ExploreCell:
    p = ("explore", i)
    algo = c.cell_head(p, d, _EXPLORE)
    props = None if d.get("properties") is None else c.names(p + ("properties",), d["properties"],
                                                              "properties: [connectivity, tree_links]")
    r = d.get("robots", [3, 8])
    if (not isinstance(r, list) or len(r) != 2 or not all(isinstance(x, int) and not isinstance(x, bool) for x in r)
            or not 1 <= r[0] <= r[1] <= MAX_ROBOTS):
        c.fail(p + ("robots",), f"explore[{i}].robots={r!r} must be [MIN, MAX] with 1 <= MIN <= MAX <= {MAX_ROBOTS}",
               "e.g. robots: [3, 8]")
    seeds = c.seeds(p + ("seeds",), d.get("seeds", [0]))
    mx = c.int_(p + ("max_examples",), d.get("max_examples", 100), 1, 1_000_000, "max_examples: 100")
    lats = None if d.get("lattices") is None else c.names(p + ("lattices",), d["lattices"], "lattices: [square]")
    faults = () if d.get("draw_faults") is None else c.names(p + ("draw_faults",), d["draw_faults"],
                                                             "draw_faults: [schedule]")
    speeds = d.get("speeds")
    if speeds is not None:
        if (not isinstance(speeds, list) or not speeds
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and x > 0 for x in speeds)):
            c.fail(p + ("speeds",), f"explore[{i}].speeds={speeds!r} must be a non-empty list of numbers > 0",
                   "e.g. speeds: [0.05, 0.4]")
        speeds = tuple(float(x) for x in speeds)
    max_steps = d.get("max_steps")
    if max_steps is not None:
        max_steps = c.int_(p + ("max_steps",), max_steps, 1, 10_000_000, "max_steps: 4000")
    params = d.get("params") or {}
    if not isinstance(params, dict):
        c.fail(p + ("params",), f"explore[{i}].params={params!r} must be a mapping", "e.g. params: {v: 0.1}")
    allow = d.get("allow_violations", False)
    if not isinstance(allow, bool):
        c.fail(p + ("allow_violations",), f"explore[{i}].allow_violations={allow!r} must be true or false",
               "e.g. allow_violations: false")
    return ExploreCell(i, algo, props, (r[0], r[1]), seeds, mx, lats, faults, speeds, max_steps, dict(params), allow)


def _simulate_cell(c: _Check, i: int, d) -> SimulateCell:
    p = ("simulate", i)
    algo = c.cell_head(p, d, _SIMULATE)
    targets = c.names(p + ("targets",), d.get("targets"), "targets: [square, hexagon]")
    sizes = d.get("robots")
    if isinstance(sizes, int) and not isinstance(sizes, bool):
        sizes = [sizes]
    if not isinstance(sizes, list) or not sizes:
        c.fail(p + ("robots",), f"simulate[{i}].robots={sizes!r} must be a list of team sizes", "e.g. robots: [10, 20]")
    sizes = tuple(c.int_(p + ("robots", k), n, 1, MAX_ROBOTS, "robots: [10, 20]") for k, n in enumerate(sizes))
    seeds = c.seeds(p + ("seeds",), d.get("seeds", [0]))
    max_steps = d.get("max_steps")
    if max_steps is not None:
        max_steps = c.int_(p + ("max_steps",), max_steps, 1, 10_000_000, "max_steps: 20000")
    start = d.get("start")
    if start is not None:
        sp = p + ("start",)
        example = "start: {uniform: 15.0, separation: 0.14}"
        if not isinstance(start, dict) or "uniform" not in start or set(start) - {"uniform", "separation"}:
            c.fail(sp, f"{_field(sp)}={start!r} must be {{uniform: SIDE, separation: D}}", f"e.g. {example}")
        vals = {}
        for key, lo in (("uniform", 0.0), ("separation", 0.0)):
            v = start.get(key, 0.0)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (lo <= v <= 1e6) or v != v \
                    or (key == "uniform" and v <= 0):
                c.fail(sp + (key,), f"{_field(sp + (key,))}={v!r} must be a number in "
                                    f"{'(0' if key == 'uniform' else '[0'}, 1e6]", f"e.g. {example}")
            vals[key] = float(v)
        start = vals
    return SimulateCell(i, algo, targets, sizes, seeds, max_steps, start)


def _robots_list(c: _Check, p: tuple, d) -> tuple[int, ...]:
    """A cell's team sizes: a list (or one number), each 1..MAX_ROBOTS."""
    sizes = d.get("robots")
    if isinstance(sizes, int) and not isinstance(sizes, bool):
        sizes = [sizes]
    if not isinstance(sizes, list) or not sizes:
        c.fail(p + ("robots",), f"{_field(p + ('robots',))}={sizes!r} must be a list of team sizes",
               "e.g. robots: [10, 20]")
    out = tuple(c.int_(p + ("robots", k), n, 1, MAX_ROBOTS, "robots: [10, 20]") for k, n in enumerate(sizes))
    if len(set(out)) != len(out):
        c.fail(p + ("robots",), f"{_field(p + ('robots',))}={sizes!r} repeats a team size", "list each size once")
    return out


def _experiment_cell(c: _Check, i: int, d) -> ExperimentCell:
    p = ("experiment", i)
    algo = c.cell_head(p, d, _EXPERIMENT)
    name = d.get("experiment")
    if not isinstance(name, str) or not name:
        c.fail(p + ("experiment",), f"experiment[{i}].experiment={name!r} must be the name of an experiment the "
                                    "algorithm declares", "e.g. experiment: fig10")
    sizes = _robots_list(c, p, d)
    seeds = c.seeds(p + ("seeds",), d.get("seeds", [0]))
    options = d.get("options") or {}
    if not isinstance(options, dict):
        c.fail(p + ("options",), f"experiment[{i}].options={options!r} must be a mapping (name: value)",
               "e.g. options: {arena: 32}")
    for k, v in options.items():
        if not isinstance(k, str) or not (v is None or isinstance(v, (bool, int, float, str))):
            c.fail(p + ("options", k), f"experiment[{i}].options.{k}={v!r} must be a number, a text or true/false",
                   "e.g. options: {arena: 32}")
    return ExperimentCell(i, algo, name, sizes, seeds, dict(options))


def _exhaustive_cell(c: _Check, i: int, d) -> ExhaustiveSpecCell:
    p = ("exhaustive", i)
    algo = c.cell_head(p, d, _EXHAUSTIVE)
    props = None if d.get("properties") is None else c.names(p + ("properties",), d["properties"],
                                                              "properties: [connectivity]")
    sizes = _robots_list(c, p, dict(d, robots=d.get("robots", [3])))
    seeds = c.seeds(p + ("seeds",), d.get("seeds", [0]))
    kinds = c.names(p + ("choices",), d.get("choices", ["activate"]), "choices: [activate, loss]")
    steps = c.int_(p + ("steps",), d.get("steps", 20), 1, 1_000_000, "steps: 20")
    k = c.int_(p + ("deviations",), d.get("deviations", 2), 0, 1000, "deviations: 2")
    delay = c.int_(p + ("max_delay",), d.get("max_delay", 1), 0, 1000, "max_delay: 1")
    crashes = c.int_(p + ("max_crashes",), d.get("max_crashes", 1), 0, 1000, "max_crashes: 1")
    target = d.get("target")
    if target is not None and not (isinstance(target, str) and target):
        c.fail(p + ("target",), f"exhaustive[{i}].target={target!r} must be a target name", "e.g. target: square")
    return ExhaustiveSpecCell(i, algo, props, sizes, seeds, kinds, steps, k, delay, crashes, target)


def loads_campaign(text: str, source: str = "<string>") -> CampaignSpec:
    """Parse and check a campaign document (YAML or JSON).

    Raises
    ------
    InputFileError
        Malformed YAML/JSON, another format, an unknown key, a missing or
        mistyped field, more than :data:`MAX_TASKS` tasks -- with the file,
        line, field and a fix.
    """
    data, lines = _parse(text, source)
    c = _Check(source, lines)
    c.keys((), data, _TOP)
    if data.get("format") != CAMPAIGN_FORMAT:
        c.fail(("format",), f"format={data.get('format')!r} must be {CAMPAIGN_FORMAT!r}",
               f"start the file with  format: {CAMPAIGN_FORMAT}")
    name = data.get("name")
    if not isinstance(name, str) or not name.strip() or len(name) > 100:
        c.fail(("name",), f"name={name!r} must be a short non-empty text", "e.g. name: small")
    cells: dict[str, list] = {}
    for part, build in (("explore", _explore_cell), ("simulate", _simulate_cell), ("experiment", _experiment_cell),
                        ("exhaustive", _exhaustive_cell)):
        items = data.get(part) or []
        if not isinstance(items, list):
            c.fail((part,), f"{part}={items!r} must be a list of cells", f"write each cell as '- algorithm: ...'")
        cells[part] = [build(c, i, d) for i, d in enumerate(items)]
    if not any(cells.values()):
        c.fail((), "the campaign has no cells (neither explore, simulate, experiment nor exhaustive)",
               "add an explore:, simulate:, experiment: or exhaustive: list (docs/campaigns.md)")
    n_tasks = (sum(len(x.seeds) * len(x.properties or (0,) * 8) for x in cells["explore"])
               + sum(len(x.targets) * len(x.robots) * len(x.seeds) for x in cells["simulate"])
               + sum(len(x.robots) * len(x.seeds) for x in cells["experiment"])
               + sum(len(x.robots) * len(x.seeds) * len(x.properties or (0,) * 8) for x in cells["exhaustive"]))
    if n_tasks > MAX_TASKS:
        c.fail((), f"the campaign has {n_tasks} tasks (more than {MAX_TASKS})", "split it into several campaigns")
    spec = CampaignSpec(name.strip(), cells["explore"], cells["simulate"], data, source, lines, cells["experiment"],
                        cells["exhaustive"])
    return spec


def load_campaign_file(path: str | os.PathLike) -> CampaignSpec:
    """Read a campaign file (``.yaml``, ``.yml`` or ``.json``)."""
    from swarmproof.models.doclines import read_text

    name = os.fspath(path)
    text = read_text(name, what="campaign file", max_bytes=10_000_000,
                     fix="give the path of a swarmproof-campaign/1 file (campaigns/ has examples)")
    return loads_campaign(text, name)
