"""``swarmproof list``: what is registered -- algorithms, properties, lemmas, targets, patterns, shapes.

Read from the registries themselves (``reference_impl/registry.py``, ``invariants/registry.py``,
``checkers/proofs.py`` ``LEMMAS`` / ``EXTRA_LEMMAS``, the bundled lattices of
``models/library.py``, the repeating patterns of ``models/repeating_pattern.py``, the line
patterns of ``models/line_patterns.py`` and the shapes of ``models/shapes.py``): an algorithm
or property you register (entry point, ``register_property``) is listed too.  Each entry has a
one-line description and, where there is one, its citation.  No KIND lists every kind.

``targets`` lists every bundled target as ``KIND:NAME`` (what ``--target`` accepts: lattices,
repeating patterns, line patterns, shapes); ``patterns`` the repeating (``pattern:``) and line
(``lines:``) patterns; ``shapes`` the goal shapes (``shape:``).

Exit codes: 0 listed; 2 an unknown KIND (the message names the kinds).
"""

from __future__ import annotations

from swarmproof.commands import emit_json, human
from swarmproof.models.errors import UsageError, did_you_mean

NAME = "list"
HELP = "list what is registered: algorithms, properties, lemmas, targets, patterns, shapes"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP

#: The kinds, in the order ``swarmproof list`` prints them.
KINDS = ("algorithms", "properties", "lemmas", "targets", "patterns", "shapes")


def add_arguments(p) -> None:
    p.add_argument("kind", nargs="?", metavar="KIND",
                   help=f"one of {', '.join(KINDS)} (default: all of them)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _first_line(text: str | None) -> str:
    r"""A docstring's first paragraph on one line, without reST quotes or "see the module docstring".

    >>> _first_line("004's algorithm (registry name ``wang2020``); see the module docstring.\n\nMore.")
    "004's algorithm (registry name wang2020)."
    >>> _first_line("Fixed IDs (labels 0..n-1; label 0 leads).")
    'Fixed IDs (labels 0..n-1; label 0 leads).'
    >>> _first_line("Its controller is :class:`BroadcastHandshakeController`.")
    'Its controller is BroadcastHandshakeController.'
    """
    import re

    para = " ".join((text or "").strip().split("\n\n", 1)[0].split()).replace("``", "")
    para = re.sub(r":(?:class|func|meth|mod|attr):`~?([^`]+)`", r"\1", para)
    para = re.sub(r"[;.]?\s*[Ss]ee the module docstring\.?", ".", para)
    return re.sub(r"\.\.(?=\s|$)", ".", para)      # a sentence's stop doubled, not a range "0..n-1"


def _entry(name: str, description: str, citation: str | None = None, **more) -> dict:
    return {"name": name, "description": description, "citation": citation or None, **more}


def list_algorithms() -> list[dict]:
    """Every registered algorithm: its class's docstring's first line, its paper and claims."""
    from swarmproof.models.citations import PAPERS
    from swarmproof.reference_impl.registry import ALGORITHMS, algorithm_factory, algorithm_names

    out = []
    for name in algorithm_names():
        factory = algorithm_factory(name)
        paper = getattr(factory, "paper", None)
        paper = paper if isinstance(paper, str) and paper else None
        claims = {k: v for k, v in dict(getattr(factory, "claims", None) or {}).items()}
        model = getattr(factory, "model", None)
        departs = [str(x) for x in (getattr(factory, "departs_from", None) or ())]
        # only the experiments its own class body declares (a campaign's experiment: cells; a
        # subclass inherits none, swarmproof.checkers.campaign.resolve_experiment)
        experiments = sorted(getattr(factory, "__dict__", {}).get("experiments") or {})
        desc = _first_line(getattr(factory, "__doc__", ""))
        if departs:
            desc += " Departs from " + "; ".join(departs) + "."
        if experiments:
            desc += " Experiments (campaign experiment: cells): " + ", ".join(experiments) + "."
        out.append(_entry(name, desc, PAPERS.get(paper) if paper else None,
                          ref=ALGORITHMS[name], paper=paper, claims=claims, departs_from=departs,
                          experiments=experiments,
                          model=None if model is None else {k: getattr(model, k) for k in
                                                           ("sensing", "communication", "motion", "clocks")}))
    return out


def list_properties() -> list[dict]:
    """Every registered property: its kind, what it reads, what it needs of an algorithm; the
    algorithms' own properties last (by name), each with the algorithms that declare it."""
    from swarmproof.invariants.registry import own_properties_of, properties
    from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names

    owners: dict = {}
    for name in algorithm_names():        # (imports every bundled package: their own properties register)
        for prop in own_properties_of(algorithm_factory(name)):
            owners.setdefault(prop, []).append(name)
    out = []
    for p in sorted(properties(), key=lambda p: (p.own, p.name if p.own else "")):
        desc = f"{p.kind}; reads {', '.join(p.reads) or '-'}"
        if p.own:
            desc += f"; own property of {', '.join(owners.get(p.name, [])) or 'an algorithm not bundled'}"
        out.append(_entry(p.name, desc, p.cites, kind=p.kind, needs=list(p.needs), blind_spots=p.blind_spots,
                          own=p.own, algorithms=owners.get(p.name, []) if p.own else None))
    return out


def list_lemmas() -> list[dict]:
    """Every lemma of ``swarmproof prove`` (``LEMMAS``), then those run only when named (``EXTRA_LEMMAS``)."""
    from swarmproof.checkers.proofs import EXTRA_LEMMAS, LEMMAS, algorithms_of_lemmas

    algos = algorithms_of_lemmas()
    out = []
    for table, extra in ((LEMMAS, False), (EXTRA_LEMMAS, True)):
        for lid, lem in table.items():
            desc = " ".join(lem.statement.split())
            if algos[lid]:
                desc += f" (algorithms: {', '.join(algos[lid])})"
            out.append(_entry(lid, desc, "; ".join(lem.cites) or None,
                              kind=lem.kind, only_when_named=extra, algorithms=algos[lid]))
    return out


def _lattice_entry(name: str) -> dict:
    from swarmproof.models import library

    g = library.load(name)
    comments, source = [], None
    for line in library.text(name).splitlines():
        if not line.startswith("#"):
            break
        text = line.lstrip("#").strip()
        if text.startswith("Source:"):
            source = text[len("Source:"):].strip()
            break
        comments.append(text)
    first = " ".join(" ".join(comments).split(". ", 1)[0].split()).rstrip(".")
    if source is not None:        # "Song & O'Kane, ICRA 2014 (seeds/000_....txt), Fig. 2:" -> without the path
        import re

        source = re.sub(r"\s*\(seeds/[^)]*\)", "", source).rstrip(":,. ")
    roles = len(g.roles)
    desc = (f"{first}: {roles} role{'s' if roles != 1 else ''}, {len(g.edges)} edges, "
            f"recommended range {g.range:g}")
    return _entry(f"lattice:{name}", desc, source, kind="lattice")


def _pattern_entries() -> list[dict]:
    from swarmproof.models.repeating_pattern import load_pattern, pattern_names

    out = []
    for name in pattern_names():
        pat = load_pattern(name)
        desc = getattr(pat, "description", "") or name
        cite = None
        if "(" in desc and desc.endswith(")"):
            desc, _, cite = desc[:-1].partition(" (")
        out.append(_entry(f"pattern:{name}", f"repeating pattern: {desc}", cite, kind="pattern"))
    return out


def _line_entries() -> list[dict]:
    from swarmproof.models import line_patterns as lp
    from swarmproof.models.targets import target_names

    out = []
    for _, name in target_names("lines"):       # every bundled one: 003's patterns and the plain "line"
        if name not in lp.PATTERN_NAMES:
            out.append(_entry(f"lines:{name}", "line pattern: robots evenly spaced on one straight line "
                              "(the example algorithm example-anonymous-line's target)", None, kind="lines"))
            continue
        info = lp.pattern_info(name)
        kind = "uni-line (Alg. 2)" if info["type"] == "uni" else "multi-line (Alg. 3)"
        k = "" if info["k"] is None else f", k = {info['k']}"
        out.append(_entry(f"lines:{name}", f"line pattern: {kind}, family {info['family']}{k}", info["citation"],
                          kind="lines"))
    return out


def _shape_entries() -> list[dict]:
    from swarmproof.models.shapes import bundled_shape, bundled_shape_names
    from swarmproof.models.targets import target_names

    bitmaps = set(bundled_shape_names())
    out = []
    for _, name in target_names("shape"):
        g = bundled_shape(name)
        n = len(g.cells)
        if name in bitmaps:
            desc, cite = f"goal shape from a bitmap, {n} cells at full size (scaled to the robots)", "004 Fig. 9"
        else:
            desc, cite = f"small goal shape of {n} cells (spacing {g.spacing:g}, range {g.range:g})", None
        out.append(_entry(f"shape:{name}", desc, cite, kind="shape"))
    return out


def list_targets() -> list[dict]:
    """Every bundled target, ``KIND:NAME``, in the order of the registered kinds."""
    from swarmproof.models.targets import target_kinds, target_names

    by_kind = {"lattice": lambda: [_lattice_entry(n) for _, n in target_names("lattice")],
               "pattern": _pattern_entries, "lines": _line_entries, "shape": _shape_entries}
    out: list[dict] = []
    for kind in target_kinds():
        if kind in by_kind:
            out += by_kind[kind]()
        else:                              # a kind a user registered: names only
            out += [_entry(f"{kind}:{n}", f"{kind} target") for _, n in target_names(kind)]
    return out


def list_patterns() -> list[dict]:
    """The repeating patterns (002) and the line patterns (003)."""
    return _pattern_entries() + _line_entries()


def list_shapes() -> list[dict]:
    """The bundled goal shapes (004)."""
    return _shape_entries()


LISTERS = {"algorithms": list_algorithms, "properties": list_properties, "lemmas": list_lemmas,
           "targets": list_targets, "patterns": list_patterns, "shapes": list_shapes}


def check_kind(kind: str | None) -> tuple[str, ...]:
    """The kinds to list: all for None; an unknown one is a usage error naming the kinds."""
    if kind is None:
        return KINDS
    if kind not in LISTERS:
        raise UsageError(f"kind={kind!r} is not something swarmproof lists{did_you_mean(kind, KINDS)}",
                         fix=f"use one of {', '.join(KINDS)}, or no KIND for all of them")
    return (kind,)


def entry_line(e: dict, width: int) -> str:
    """``  NAME  DESCRIPTION [CITATION]``: one line per entry."""
    cite = f" [{e['citation']}]" if e.get("citation") else ""
    return f"  {e['name']:<{width}}  {e['description']}{cite}"


def run(args) -> int:
    kinds = check_kind(args.kind)
    doc = {kind: LISTERS[kind]() for kind in kinds}
    if args.json:
        emit_json({"kinds": list(kinds), **doc})
        return 0
    lines: list[str] = []
    for kind in kinds:
        entries = doc[kind]
        if lines:
            lines.append("")
        lines.append(f"{kind} ({len(entries)}):")
        width = max([len(e["name"]) for e in entries] + [4])
        lines += [entry_line(e, width) for e in entries]
    human(args, *lines)
    return 0
