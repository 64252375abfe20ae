"""`swarmproof check-lattice`: exit codes 0/1/2/3, JSON, human lines, --range, --plot."""

from __future__ import annotations

import json

import pytest

from swarmproof.cli import main

SQ3 = """format: lattice-graph/1
name: sq3
range: 1.2
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, 0, 1, 0]
  - [A, A, -1, 0, 0]
"""

SQUARE_NO_RANGE = """format: lattice-graph/1
name: sq
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, 0, 1, 0]
  - [A, A, -1, 0, 0]
  - [A, A, 0, -1, 0]
"""

# a ring of 1000 robots of one role: rotation order 1000 > max_rotation_order (720)
BIG_RING = """format: lattice-graph/1
name: big-ring
range: 1.5
angle_unit: deg
roles: [R]
edges:
  - [R, R, 1, 0, 0.36]
  - [R, R, -0.99998026085613712, 0.0062831439655589511, -0.36]
"""


def _file(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_valid_bundled_lattice_exits_0(capsys):
    assert main(["check-lattice", "square"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == ["square (library:square): valid and self-consistent for range 1.2 "
                   "(periodic pattern, rotation order 1, translation rank 2)",
                   "verdict: held"]


def test_defect_exits_1_with_the_edge_row_to_add(tmp_path, capsys):
    path = _file(tmp_path, "sq3.yaml", SQ3)
    assert main(["check-lattice", path]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0] == (f"sq3 ({path}): 1 defect for range 1.2 (periodic pattern, rotation order 1, "
                      "translation rank 2)")
    assert out[1].startswith("- missing_inverse: edges[1]: A -> A (0, 1, 0deg) has no inverse")
    assert out[2] == "  fix: add the edge row  - [A, A, 0, -1, 0]"
    assert out[-1] == "verdict: violated"


def test_range_overrides_the_file(capsys):
    assert main(["check-lattice", "square", "--range", "1.5"]) == 1
    assert "range 1.5" in capsys.readouterr().out
    assert main(["check-lattice", "square", "--range", "1.4142135623730951"]) == 0


def test_json_is_one_document_with_the_design_fields(capsys):
    assert main(["check-lattice", "square", "--range", "1.5", "--json"]) == 1
    out = capsys.readouterr().out
    doc = json.loads(out)  # exactly one document: json.loads rejects trailing data
    for k in ("file", "range", "valid", "self_consistent", "classification", "defects",
              "suggested_edges", "verdict"):
        assert k in doc
    assert doc["range"] == 1.5 and doc["valid"] is False and doc["self_consistent"] is False
    assert doc["classification"]["kind"] == "periodic"
    assert doc["classification"]["rotation_order"] == 1
    assert doc["classification"]["translation_rank"] == 2
    assert {d["kind"] for d in doc["defects"]} == {"self_consistency"}
    assert sorted(map(tuple, doc["suggested_edges"])) == [
        ("A", "A", -1.0, -1.0, 0.0), ("A", "A", -1.0, 1.0, 0.0), ("A", "A", 1.0, -1.0, 0.0),
        ("A", "A", 1.0, 1.0, 0.0)]
    assert doc["verdict"] == "violated"


def test_inconclusive_exits_3(tmp_path, capsys):
    path = _file(tmp_path, "ring.yaml", BIG_RING)
    assert main(["check-lattice", path, "--json"]) == 3
    doc = json.loads(capsys.readouterr().out)
    assert doc["verdict"] == "inconclusive" and doc["valid"] is False
    assert doc["self_consistent"] is None and "max_rotation_order" in doc["inconclusive_reason"]


@pytest.mark.parametrize("args,match", [
    (["check-lattice", "no-such-lattice"], "no-such-lattice"),
    (["check-lattice", "{tmp}/norange.yaml"], r"norange.yaml: range is not given.*fix: pass --range PHI"),
    (["check-lattice", "square", "--range", "0"], r"--range='0' must be a finite number > 0"),
    (["check-lattice", "square", "--range", "abc"], r"--range='abc' is not a number"),
    (["check-lattice", "{tmp}/broken.yaml"], r"broken.yaml"),
], ids=["unknown-name", "no-range-anywhere", "zero-range", "non-numeric-range", "malformed-yaml"])
def test_usage_errors_exit_2_without_traceback(tmp_path, capsys, args, match):
    _file(tmp_path, "norange.yaml", SQUARE_NO_RANGE)
    _file(tmp_path, "broken.yaml", "format: lattice-graph/1\nroles: [A\n")
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    try:
        code = main(args)
    except SystemExit as exc:  # argparse type errors exit from the parser
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    import re
    assert re.search(match, err), err


def test_no_range_in_file_but_given_on_the_command_line(tmp_path):
    path = _file(tmp_path, "norange.yaml", SQUARE_NO_RANGE)
    assert main(["check-lattice", path, "--range", "1.2"]) == 0


def test_plot_is_written(tmp_path, capsys):
    png = tmp_path / "out.png"
    assert main(["check-lattice", "square", "--range", "1.5", "--plot", str(png)]) == 1
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_json_mode_keeps_stdout_clean_with_plot(tmp_path, capsys):
    png = tmp_path / "out.png"
    assert main(["check-lattice", "hexagon", "--json", "--plot", str(png)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["valid"] is True and png.exists()


RAD_HEXAGON_MISSING = """format: lattice-graph/1
name: hexagon-rad
range: 1.2
angle_unit: rad
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, 0.5, 0.8660254037844386, 0]
  - [A, A, -0.5, 0.8660254037844386, 0]
  - [A, A, -1, 0, 0]
  - [A, A, -0.5, -0.8660254037844386, 0]
"""


def test_fix_rows_of_a_radian_file_are_in_radians_and_paste_back(tmp_path, capsys):
    """Issue 13 item 8: the suggested rows are printed, and written to JSON, in the file's unit;
    pasting the printed rows into the file makes it valid (in degrees it became dense)."""
    path = _file(tmp_path, "hex-rad.yaml", RAD_HEXAGON_MISSING)
    assert main(["check-lattice", path]) == 1
    out = capsys.readouterr().out
    rows = [line.split("  - ", 1)[1] for line in out.splitlines() if "fix: add the edge row  - " in line]
    assert rows == ["[A, A, 0.5, -0.866025404, 0]"]
    assert main(["check-lattice", path, "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["angle_unit"] == "rad" and doc["suggested_edges"] == [["A", "A", 0.5, -0.866025403784, 0.0]]
    fixed = _file(tmp_path, "fixed.yaml", RAD_HEXAGON_MISSING + "".join(f"  - {r}\n" for r in rows))
    assert main(["check-lattice", fixed]) == 0


def test_fix_rows_with_a_rotation_in_radians(tmp_path, capsys):
    text = RAD_HEXAGON_MISSING.replace("  - [A, A, 1, 0, 0]\n", "  - [A, A, 1, 0, 1.5707963267948966]\n")
    path = _file(tmp_path, "turned.yaml", text)
    main(["check-lattice", path, "--json"])
    doc = json.loads(capsys.readouterr().out)
    inverse = [r for r in doc["suggested_edges"] if r[2] == 0.0]
    assert inverse == [["A", "A", 0.0, 1.0, -1.570796326795]]
