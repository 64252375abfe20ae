"""`swarmproof list [KIND] [--json]`: what is registered, from the registries themselves."""

from __future__ import annotations

import json

import pytest

from swarmproof.cli import main


def run(capsys, *argv):
    code = main(["list", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_algorithms_exact_lines(capsys):
    code, out, _ = run(capsys, "algorithms")
    lines = out.splitlines()
    assert code == 0 and lines[0].startswith("algorithms (") and lines[0].endswith("):")
    width = max(len(line.split()[0]) for line in lines[1:] if line.strip()) + 2   # the longest name's column
    assert ("  " + "song2016".ljust(width) + "The Song & O'Kane 2016 algorithm (Song & O'Kane 2016, Sec. V), for the "
            "engine. [Song & O'Kane 2016]") in lines
    # the registered readings of a paper are listed beside its default
    assert any(line.startswith("  " + "song2016-subtree-clock".ljust(width) + "Song & O'Kane 2016 with the relocate "
                               "robot's movement timeout counted from its own subtree marker (Song & O'Kane 2016, "
                               "Alg. 1 line 29)") for line in lines)
    # a class without a paper has no citation
    assert "  " + "example-gather".ljust(width) + 'The example algorithm (registry name "example-gather").' in lines


def test_properties_exact_line_with_citation(capsys):
    code, out, _ = run(capsys, "properties")
    lines = out.splitlines()
    assert code == 0
    assert lines[0] == "properties (15):"           # 11, and the algorithms' own 4 (issue 32), last
    assert lines[1] == ("  connectivity      safety; reads poses, presence, range "
                        "[Song & O'Kane 2016, Lemma 11 (connectivity is preserved)]")
    assert "  no_crash          safety; reads exceptions the algorithm's code raised [swarmproof: the algorithm " \
           "under test raises no exception (a crash is a finding)]" in lines
    assert lines[11] == ("  completion_sound  safety; reads poses, states, the algorithm's completion_invariants "
                         "[the algorithm's own completion detection is sound: whenever a robot declares the "
                         "formation complete, it is formed (its completion_invariants)]")
    assert [line.split()[0] for line in lines[12:]] == ["grid_claims", "grid_heard", "grid_spacing", "tree_link_cases"]
    assert "own property of song2016, song2016-literal, song2016-subtree-clock [" in lines[-1]


def test_targets_patterns_shapes_lines(capsys):
    code, out, _ = run(capsys, "targets")
    lines = out.splitlines()
    assert code == 0
    assert ("  lattice:square              Square lattice, unit edge length: 1 role, 4 edges, recommended "
            "range 1.2 [Song & O'Kane, ICRA 2014, Fig. 2]") in lines
    # every bundled target, the plain line of example-anonymous-line too (it was left out)
    assert any(line.startswith("  lines:line ") for line in lines)
    code, out, _ = run(capsys, "patterns")
    assert ("  pattern:square-dots         repeating pattern: a square formation of repeating dots "
            "[Jiang et al., Sec. V-B, Fig. 2]") in out.splitlines()
    code, out, _ = run(capsys, "shapes")
    assert out.splitlines() == [
        "shapes (4):",
        "  shape:letter-l  small goal shape of 5 cells (spacing 0.2, range 0.6)",
        "  shape:letter-n  goal shape from a bitmap, 82 cells at full size (scaled to the robots) "
        "[Wang & Rubenstein 2020, Fig. 9]",
        "  shape:letter-u  goal shape from a bitmap, 70 cells at full size (scaled to the robots) "
        "[Wang & Rubenstein 2020, Fig. 9]",
        "  shape:square-9  small goal shape of 9 cells (spacing 0.2, range 0.6)",
    ]


def test_no_kind_lists_every_kind_in_order(capsys):
    code, out, _ = run(capsys)
    heads = [line.split(" (")[0] for line in out.splitlines() if line and not line.startswith(" ")]
    assert code == 0 and heads == ["algorithms", "properties", "lemmas", "targets", "patterns", "shapes"]


def test_json_is_one_document_with_the_fields(capsys):
    code, out, err = run(capsys, "--json")
    doc = json.loads(out)
    assert code == 0 and err == ""
    assert doc["kinds"] == ["algorithms", "properties", "lemmas", "targets", "patterns", "shapes"]
    song = next(e for e in doc["algorithms"] if e["name"] == "song2016")
    assert song["paper"] == "001" and song["citation"] == "Song & O'Kane 2016"
    assert song["ref"] == "swarmproof.reference_impl.song2016:Song2016"
    assert song["claims"]["tree_links"].startswith("001 Lemma 11")
    assert song["model"] == {"sensing": "local", "communication": "neighbors", "motion": "differential",
                             "clocks": "sync"}
    gather = next(e for e in doc["algorithms"] if e["name"] == "example-gather")
    assert gather["paper"] is None and gather["citation"] is None
    # a variant that adds what its paper assumes away says so; the default keeps the paper's model
    bh = next(e for e in doc["algorithms"] if e["name"] == "wang2020-broadcast-handshake")
    assert bh["departs_from"] and "Sec. II-A e)" in bh["departs_from"][0] and "Departs from" in bh["description"]
    assert next(e for e in doc["algorithms"] if e["name"] == "wang2020")["departs_from"] == []
    # the experiments a campaign's experiment: cell can run are listed; a variant inherits none
    assert next(e for e in doc["algorithms"] if e["name"] == "wang2020")["experiments"] == ["fig10"]
    assert bh["experiments"] == [] and song["experiments"] == []
    conn = next(e for e in doc["properties"] if e["name"] == "connectivity")
    assert conn["needs"] == ["range_graph"] and conn["kind"] == "safety"
    lemma = doc["lemmas"][0]
    assert set(lemma) >= {"name", "description", "citation", "kind", "only_when_named"}
    assert all(set(e) >= {"name", "description", "citation"} for kind in doc["kinds"] for e in doc[kind])
    assert [e["name"] for e in doc["shapes"]] == ["shape:letter-l", "shape:letter-n", "shape:letter-u",
                                                  "shape:square-9"]
    assert doc["shapes"][1]["citation"] == "004 Fig. 9"      # JSON keeps the seed key
    code, out2, _ = run(capsys, "--json")
    assert out2 == out                       # deterministic


def test_a_registered_property_is_listed(capsys):
    from swarmproof.invariants.registry import Property, register_property, unregister_property

    register_property(Property("my_prop", "liveness", lambda t, c: None, ("poses",), cites="mine"))
    try:
        code, out, _ = run(capsys, "properties")
        assert "  my_prop           liveness; reads poses [mine]" in out.splitlines()
    finally:
        unregister_property("my_prop")


@pytest.mark.parametrize("argv", [["lattices"], ["lattices", "--json"]], ids=["text", "json"])
def test_an_unknown_kind_exits_2_naming_the_kinds(capsys, argv):
    code, out, err = run(capsys, *argv)
    assert code == 2
    text = out if "--json" in argv else err
    assert "kind='lattices' is not something swarmproof lists" in text
    assert "algorithms, properties, lemmas, targets, patterns, shapes" in text
    if "--json" in argv:
        assert json.loads(out)["exit_code"] == 2
