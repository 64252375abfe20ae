"""Issue 34, must hold 3: bad logs.  ``swarmproof check-run`` exits 2 with one message naming the
file -- and the topic, the message index and the field where they apply -- never a traceback.

One table per area (tests/README.md): bags and MCAP files (each case in every format with
topics), CSV files, paths; then the optional extra missing."""

from __future__ import annotations

import builtins
import os
import shutil
import sys

import pytest

import logkit as lk
from swarmproof.models.errors import InputFileError
from swarmproof.models.recorded_io import read_log


def _no_traceback(out: str, err: str) -> None:
    assert "Traceback" not in err and "Traceback" not in out
    assert "internal error" not in err


def _exit_2(cli, path, *args) -> str:
    """Run check-run, expect exit 2 and nothing on stdout; return stderr."""
    code, out, err = cli("check-run", str(path), "--range", "1.2", *args)
    _no_traceback(out, err)
    assert code == 2, (code, out, err)
    assert out == ""
    assert err.startswith("swarmproof check-run: error: ")
    return err


def _edited(msgs, topic: str, index: int, **change):
    """``msgs`` with message ``index`` of ``topic`` changed (fields of its value)."""
    out, k = [], 0
    for m in msgs:
        if m.topic == topic:
            if k == index:
                m = lk.Msg(m.topic, m.msgtype, m.log_ns, {**m.value, **change})
            k += 1
        out.append(m)
    return out


def _storage(fmt: str, path: str) -> str:
    return path if fmt == "mcap" else lk.storage_file(path)


# ----------------------------------------------------------------------------
# bags and MCAP files: (id, build(fmt, base) -> path, extra args, fragments of the message)
# ----------------------------------------------------------------------------

def _corrupt(fmt, base):
    path = lk.write(fmt, base, lk.split_run())
    with open(_storage(fmt, path), "wb") as fh:
        fh.write(b"\x00not a log\x00" * 64)
    return path


def _truncated(fmt, base):
    path = lk.write(fmt, base, lk.split_run())
    f = _storage(fmt, path)
    data = open(f, "rb").read()
    with open(f, "wb") as fh:
        fh.write(data[: len(data) // 2])
    return path


def _string_pose(fmt, base):
    msgs = [m for m in lk.split_run() if m.topic != "/robot_1/pose"]
    msgs.append(lk.Msg("/robot_1/pose", lk.STRING, lk.ns(0.1), {"data": "x=1 y=0"}))
    return lk.write(fmt, base, msgs)


def _custom_pose(fmt, base):
    return lk.write(fmt, base, lk.split_run(msgtype=lk.CUSTOM))


def _string_parent(fmt, base):
    msgs = [m for m in lk.split_run(parents=True) if m.topic != "/robot_1/parent"]
    msgs.append(lk.Msg("/robot_1/parent", lk.STRING, 0, {"data": "0"}))
    return lk.write(fmt, base, msgs)


def _out_of_order(fmt, base):
    # robot 2's message 5 is stamped 0.3 s, after message 4 at 0.4 s (log times stay in order)
    return lk.write(fmt, base, _edited(lk.split_run(), "/robot_2/pose", 5, stamp_ns=lk.ns(0.3)))


def _nan(fmt, base):
    return lk.write(fmt, base, _edited(lk.split_run(), "/robot_2/pose", 7, y=float("nan")))


def _inf(fmt, base):
    return lk.write(fmt, base, _edited(lk.split_run(), "/robot_0/pose", 12, quat=(0.0, 0.0, float("inf"), 1.0)))


def _duplicate_ids(fmt, base):
    msgs = lk.split_run() + [lk.pose(1, t, 1.0, 0.0, topic="/robot_01/pose") for t in lk.ticks(0, 1)]
    return lk.write(fmt, base, msgs)


def _no_messages(fmt, base):
    return lk.write_raw(fmt, base, [], topics=[("/robot_0/pose", lk.POSE), ("/robot_1/pose", lk.POSE)])


def _nothing(fmt, base):
    return lk.write_raw(fmt, base, [])


def _one_silent_topic(fmt, base):
    msgs = [m for m in lk.split_run() if m.topic != "/robot_2/pose"]
    return lk.write_raw(fmt, base, msgs, topics=[("/robot_2/pose", lk.POSE)])


def _some_parents(fmt, base):
    return lk.write(fmt, base, [m for m in lk.split_run(parents=True) if m.topic != "/robot_2/parent"])


def _orphan_parent(fmt, base):
    return lk.write(fmt, base, lk.split_run(parents=True) + [lk.parent(7, 0.0, 0)])


def _undecodable(fmt, base):
    msgs = [m for m in lk.split_run() if not (m.topic == "/robot_1/pose" and m.value["stamp_ns"] == lk.ns(0.3))]
    return lk.write_raw(fmt, base, msgs, raw=[("/robot_1/pose", lk.POSE, lk.ns(0.303), b"\x00\x01\x00\x00garbage")])


def _split(fmt, base):
    return lk.write(fmt, base, lk.split_run())


BAG_CASES = [
    ("corrupt", _corrupt, (), {"mcap": ["the MCAP file cannot be opened", "InvalidMagic", "truncated or corrupt"],
                               "rosbag2-sqlite3": ["the rosbag2 bag cannot be opened", "file is not a database"],
                               "rosbag2-mcap": ["the rosbag2 bag cannot be opened", "File magic is invalid"]}),
    ("truncated", _truncated, (), {"mcap": ["the MCAP file cannot be opened", "truncated or corrupt"],
                                   "rosbag2-sqlite3": ["the rosbag2 bag cannot be", "malformed"],
                                   "rosbag2-mcap": ["the rosbag2 bag cannot be opened", "File end magic is invalid"]}),
    ("no-topic-matches", _split, ("--topics", "/drone_{id}/odom"),
     ["field '--topics'", "no topic matches --topics='/drone_{id}/odom'",
      "the log's topics: ['/robot_0/pose', '/robot_1/pose', '/robot_2/pose']"]),
    ("no-parent-topic-matches", _split, ("--parent-topics", "/drone_{id}/parent"),
     ["field '--parent-topics'", "no topic matches --parent-topics='/drone_{id}/parent'"]),
    ("unsupported-pose-type", _string_pose, (),
     ["field '/robot_1/pose'", "topic '/robot_1/pose' (it matches --topics) has the message type "
      "'std_msgs/msg/String', which swarmproof does not read as a pose"]),
    ("unknown-pose-type", _custom_pose, (),
     ["field '/robot_0/pose'", "topic '/robot_0/pose' (it matches --topics) has the message type "
      "'my_robot_msgs/msg/RobotPose', which swarmproof does not read as a pose",
      "geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/Pose2D', 'nav_msgs/msg/Odometry'"]),
    ("unsupported-parent-type", _string_parent, (),
     ["field '/robot_1/parent'", "topic '/robot_1/parent'", "'std_msgs/msg/String'", "as a parent"]),
    ("out-of-order", _out_of_order, (),
     ["topic '/robot_2/pose' message 5: time t=0.3 s is earlier than the previous sample of robot 2 "
      "(0.4 s, topic '/robot_2/pose' message 4)", "(header time)", "--time log"]),
    ("nan-position", _nan, (),
     ["field 'pose.position.y'", "topic '/robot_2/pose' message 7: pose.position.y=nan is not a finite number"]),
    ("infinite-orientation", _inf, (),
     ["field 'pose.orientation.z'", "topic '/robot_0/pose' message 12: pose.orientation.z=inf is not a finite"]),
    ("duplicate-robot-ids", _duplicate_ids, (),
     ["robot id 1 has two pose topics: '/robot_01/pose' and '/robot_1/pose'", "duplicate robot ids"]),
    ("no-messages", _no_messages, (), ["the log is empty: its pose topics hold no message"]),
    ("no-topics-at-all", _nothing, (), ["the log is empty: it has no topic (no message)"]),
    ("one-pose-topic-empty", _one_silent_topic, (), ["robot 2's pose topic '/robot_2/pose' holds no message"]),
    ("parents-of-some-robots", _some_parents, (),
     ["robot 2 has no parent topic while robots [0, 1] have one"]),
    ("parent-without-pose", _orphan_parent, (),
     ["field '/robot_7/parent'", "robot 7 has a parent topic '/robot_7/parent' but no pose topic"]),
]

BAG_PARAMS = [pytest.param(fmt, build, args, frags, id=f"{name}-{fmt}")
              for name, build, args, frags in BAG_CASES for fmt in lk.BAG_FORMATS]


@pytest.mark.parametrize("fmt, build, args, fragments", BAG_PARAMS)
def test_bad_bags_and_mcap_files_exit_2_naming_where(fmt, build, args, fragments, tmp_path, cli):
    path = build(fmt, str(tmp_path / "log"))
    err = _exit_2(cli, path, *args)
    assert f"error: {path}: " in err            # the file, as given
    for frag in (fragments[fmt] if isinstance(fragments, dict) else fragments):
        assert frag in err, (frag, err)


@pytest.mark.parametrize("fmt", [f for f in lk.BAG_FORMATS if f != "mcap"])
def test_an_undecodable_bag_message_names_its_topic_and_index(fmt, tmp_path, cli):
    path = _undecodable(fmt, str(tmp_path / "log"))
    err = _exit_2(cli, path)
    assert f"error: {path}: field '/robot_1/pose[3]': topic '/robot_1/pose' message 3 cannot be decoded as " \
           "geometry_msgs/msg/PoseStamped" in err


def test_an_undecodable_mcap_message_names_its_topic_and_index(tmp_path, cli):
    path = _undecodable("mcap", str(tmp_path / "log"))
    err = _exit_2(cli, path)
    assert "topic '/robot_1/pose' message 3" in err


@pytest.mark.parametrize("fmt", lk.BAG_FORMATS)
def test_every_cut_of_a_log_is_bad_input(fmt, tmp_path, cli):
    """A log cut anywhere (its storage file for a bag) is exit 2 or -- where the cut lost nothing
    the reader needs -- judged; never a traceback.  SQLite bags are cut before their last page
    (test_a_bag_cut_in_its_last_page_is_bad_input: the bug there)."""
    src = lk.write(fmt, str(tmp_path / "src"), lk.split_run(parents=True))
    data = open(_storage(fmt, src), "rb").read()
    end = len(data) - 4096 if fmt == "rosbag2-sqlite3" else len(data)
    codes = []
    for i, cut in enumerate(sorted({0, 1, 7, end - 1} | set(range(0, end, max(1, end // 16))))):
        path = str(tmp_path / f"cut{i}") + (".mcap" if fmt == "mcap" else "")
        if fmt == "mcap":
            open(path, "wb").write(data[:cut])
        else:
            shutil.copytree(src, path)
            open(lk.storage_file(path), "wb").write(data[:cut])
        code, out, err = cli("check-run", path, "--range", "1.2")
        _no_traceback(out, err)
        assert code == 2 and path in err, (cut, code, err)
        codes.append(code)
    assert len(codes) >= 16


def test_a_bag_cut_in_its_last_page_is_bad_input(tmp_path, cli):
    src = lk.write("rosbag2-sqlite3", str(tmp_path / "src"), lk.split_run())
    full = read_log(src)
    db = lk.storage_file(src)
    data = open(db, "rb").read()
    open(db, "wb").write(data[:-16])
    try:
        cut = read_log(src)
    except InputFileError:
        cut = None
    if cut is not None:         # what it read must at least be what was written
        assert all((cut.robots[r].xyt == full.robots[r].xyt).all() for r in full.robots)
    _exit_2(cli, src)


def test_an_mcap_file_without_a_summary_section_is_read(tmp_path, check_run):
    from mcap.writer import IndexType, Writer
    from mcap_ros2._dynamic import serialize_dynamic

    path = str(tmp_path / "nosummary.mcap")
    encode = serialize_dynamic(lk.POSE, lk.MSGDEFS[lk.POSE])[lk.POSE]
    with open(path, "wb") as fh:
        w = Writer(fh, index_types=IndexType.NONE, repeat_channels=False, repeat_schemas=False,
                   use_statistics=False, use_summary_offsets=False)
        w.start("ros2", "swarmproof-tests")
        schema = w.register_schema(lk.POSE, "ros2msg", lk.MSGDEFS[lk.POSE].encode())
        channels = {}
        for m in lk.split_run():
            if m.topic not in channels:
                channels[m.topic] = w.register_channel(m.topic, "cdr", schema)
            w.add_message(channels[m.topic], m.log_ns, encode(lk.mcap_value(m)), m.log_ns)
        w.finish()
    from mcap.reader import make_reader

    with open(path, "rb") as fh:       # the library reads it whole
        assert sum(1 for _ in make_reader(fh).iter_messages()) == 93
    code, doc, _ = check_run(path, "--range", "1.2", "--property", "connectivity")
    assert code == 1 and doc["properties"]["connectivity"]["witness"]["time_s"] == 1.5


# ----------------------------------------------------------------------------
# CSV: (id, rows or raw text, message fragments)
# ----------------------------------------------------------------------------

H = "t,id,x,y,theta,parent\n"
GOOD = "".join(f"{k / 10},{i},{0.5 * i},0,0,\n" for k in range(5) for i in range(3))

CSV_CASES = [
    ("header-only", H, [":2: the log is empty: a header row and no samples"]),
    ("empty-file", "", [":1: the log is empty (no header row, no samples)"]),
    ("bad-number", H + GOOD + "0.5,1,1;5,0,0,\n", [":17: field 'x': x='1;5' is not a number"]),
    ("bad-time", H + "zero,1,0,0,0,\n", [":2: field 't': t='zero' is not a number"]),
    ("missing-column", "t,id,x,y\n0,1,0,0\n", [":1: field 'theta': the header row ['t', 'id', 'x', 'y'] lacks "
                                              "the column 'theta'"]),
    ("duplicate-column", "t,id,x,y,theta,x\n", [":1: field 'x': the header row names the column 'x' twice"]),
    ("short-row", H + GOOD + "0.5,1,0,0\n", [":17: the row has 4 fields, the header 6"]),
    ("bad-id", H + "0,r1,0,0,0,\n", [":2: field 'id': id='r1' is not an integer"]),
    ("bad-parent", H + "0,1,0,0,0,zero\n", [":2: field 'parent': parent='zero' is not an integer"]),
    ("nan", H + GOOD + "0.5,1,nan,0,0,\n", [":17: field 'x': ", "x=nan is not a finite number"]),
    ("infinite-heading", H + GOOD + "0.5,2,1,0,-inf,\n", [":17: field 'theta': ", "theta=-inf is not a finite"]),
    ("infinite-time", H + "inf,1,0,0,0,\n", [":2: field 't': ", "t=inf is not a finite number"]),
    ("out-of-order", H + GOOD + "0.3,1,0.5,0,0,\n", [":17: ", "time t=0.3 s is earlier than the previous sample "
                                                     "of robot 1 (0.4 s, line 15)", "sort the log by time"]),
    ("repeated-row", H + GOOD + "0.4,1,0.5,0,0,\n", [":17: ", "time t=0.4 s repeats the previous sample of robot 1"]),
    # two spellings of one robot id (the CSV analog of /robot_1/pose and /robot_01/pose)
    ("duplicate-robot-ids", H + "0,1,0,0,0,\n0,01,0,0,0,\n", [":3: ", "repeats the previous sample of robot 1"]),
    ("one-sample-each", H + "0,1,0,0,0,\n0,2,0.5,0,0,\n", ["every robot has one sample", "--period"]),
]


@pytest.mark.parametrize("text, fragments", [pytest.param(t, f, id=i) for i, t, f in CSV_CASES])
def test_bad_csv_files_exit_2_naming_the_line_and_field(text, fragments, tmp_path, cli):
    path = tmp_path / "run.csv"
    path.write_text(text, encoding="utf-8")
    err = _exit_2(cli, path)
    assert str(path) in err
    for frag in fragments:
        assert frag in err, (frag, err)


def test_a_csv_that_is_not_utf8_exits_2(tmp_path, cli):
    path = tmp_path / "run.csv"
    path.write_bytes(b"t,id,x,y,theta\n0,1,\xff,0,0\n")
    err = _exit_2(cli, path)
    assert f"{path}:" in err and "UTF-8" in err


def test_one_sample_each_is_judged_with_a_period(tmp_path, check_run):
    path = tmp_path / "run.csv"
    path.write_text("t,id,x,y,theta\n0,1,0,0,0\n0,2,0.5,0,0\n", encoding="utf-8")
    code, doc, _ = check_run(path, "--range", "1.2", "--period", "0.1", "--property", "connectivity")
    assert code == 0 and doc["clock"]["instants"] == 1 and doc["properties"]["connectivity"]["status"] == "held"


def test_extra_csv_columns_are_ignored_and_noted(tmp_path, check_run):
    path = tmp_path / "run.csv"
    path.write_text("theta,y,x,id,t,battery\n" + "".join(f"0,0,{0.5 * i},{i},{k / 10},0.9\n"
                                                        for k in range(5) for i in range(2)), encoding="utf-8")
    code, doc, _ = check_run(path, "--range", "1.2", "--property", "connectivity")
    assert code == 0 and doc["notes"] == ["CSV columns ignored: ['battery']"]
    assert doc["samples"] == 10 and doc["clock"]["period_s"] == 0.1


# ----------------------------------------------------------------------------
# paths
# ----------------------------------------------------------------------------

def _folder(tmp_path):
    (tmp_path / "notabag").mkdir()
    return tmp_path / "notabag", ["is a folder without metadata.yaml, not a rosbag2 bag"]


def _db3(tmp_path):
    bag = lk.write("rosbag2-sqlite3", str(tmp_path / "bag"), lk.split_run())
    return lk.storage_file(bag), ["is the database inside a rosbag2 bag", f"give the bag's folder: '{bag}'"]


def _bad_metadata(tmp_path):
    bag = lk.write("rosbag2-sqlite3", str(tmp_path / "bag"), lk.split_run())
    with open(os.path.join(bag, "metadata.yaml"), "w") as fh:
        fh.write("rosbag2_bagfile_information: [not: a, bag\n")
    return bag, ["the rosbag2 bag cannot be opened"]


def _missing(tmp_path):
    return tmp_path / "nope.mcap", ["does not exist"]


def _suffix(tmp_path):
    (tmp_path / "run.txt").write_text("t,id,x,y,theta\n")
    return tmp_path / "run.txt", ["the suffix '.txt' is not a log format swarmproof reads"]


@pytest.mark.parametrize("build", [_folder, _db3, _bad_metadata, _missing, _suffix],
                         ids=["folder-without-metadata", "db3-not-its-folder", "bad-metadata", "missing", "suffix"])
def test_bad_paths_exit_2(build, tmp_path, cli):
    path, fragments = build(tmp_path)
    err = _exit_2(cli, path)
    assert str(path) in err
    for frag in fragments:
        assert frag in err, (frag, err)


# ----------------------------------------------------------------------------
# the optional extra missing
# ----------------------------------------------------------------------------

@pytest.fixture
def without_ros_extra(monkeypatch):
    """``import rosbags``, ``import mcap`` and ``import mcap_ros2`` (and their submodules) fail."""
    tops = ("rosbags", "mcap", "mcap_ros2")
    for name in list(sys.modules):
        if name.split(".")[0] in tops:
            monkeypatch.setitem(sys.modules, name, None)
    for name in tops:
        monkeypatch.setitem(sys.modules, name, None)
    real_import = builtins.__import__

    def guarded(name, *args, **kwargs):
        if name.split(".")[0] in tops:
            raise ImportError(f"No module named {name!r} (tests/recorded: the ros extra is not installed)")
        return real_import(name, *args, **kwargs)
    monkeypatch.setattr(builtins, "__import__", guarded)


@pytest.mark.parametrize("fmt", lk.BAG_FORMATS)
def test_without_the_extra_a_bag_exits_2_with_the_install_command(fmt, tmp_path, cli, request):
    path = lk.write(fmt, str(tmp_path / "log"), lk.split_run())       # written while the extra is there
    request.getfixturevalue("without_ros_extra")
    with pytest.raises(ImportError):
        import rosbags  # noqa: F401
    with pytest.raises(ImportError):
        import mcap  # noqa: F401
    err = _exit_2(cli, path)
    assert "needs the optional extra that is not installed" in err and path in err
    assert "pip install 'swarmproof[ros]'" in err


def test_without_the_extra_csv_still_works_and_exports_refuse(tmp_path, cli, without_ros_extra, check_run):
    path = lk.write("csv", str(tmp_path / "log"), lk.split_run())
    code, doc, _ = check_run(path, "--range", "1.2", "--property", "connectivity")
    assert code == 1 and doc["properties"]["connectivity"]["witness"]["time_s"] == 1.5
    # writing MCAP or a bag needs the extra too; CSV does not
    from swarmproof.models.recorded_io import write_log

    rows = [(0, 1, 0.0, 0.0, 0.0, None), (100_000_000, 1, 0.1, 0.0, 0.0, None)]
    assert write_log(iter(rows), str(tmp_path / "w.csv"), ids=[1], has_parent=False) == str(tmp_path / "w.csv")
    for dest in ("w.mcap", "wbag"):
        from swarmproof.models.errors import UsageError

        with pytest.raises(UsageError, match=r"needs the optional extra .*pip install 'swarmproof\[ros\]'"):
            write_log(iter(rows), str(tmp_path / dest), ids=[1], has_parent=False)
        assert not os.path.exists(tmp_path / dest)


# ----------------------------------------------------------------------------
# numbers too large for the arrays: bad input (or judged), never an internal error
# ----------------------------------------------------------------------------

def _huge_id_mcap(tmp_path):
    msgs = [lk.pose(0, t, 0.0, 0.0, topic="/robot_99999999999999999999/pose") for t in lk.ticks(0, 1)]
    msgs += [lk.pose(1, t, 0.5, 0.0) for t in lk.ticks(0, 1)]
    return lk.write("mcap", str(tmp_path / "log"), msgs)


def _csv(text):
    def build(tmp_path):
        path = tmp_path / "run.csv"
        path.write_text(text, encoding="utf-8")
        return str(path)
    return build


@pytest.mark.parametrize("build", [
    pytest.param(_csv("t,id,x,y,theta\n1e20,0,0,0,0\n2e20,0,0,0,0\n"), id="csv-time-1e20-s"),
    pytest.param(_csv("t,id,x,y,theta\n0,99999999999999999999,0,0,0\n1,99999999999999999999,0,0,0\n"),
                 id="csv-id-past-int64"),
    pytest.param(_csv("t,id,x,y,theta\n0,0,1e308,0,0\n1,0,1e308,0,0\n0,1,-1e308,0,0\n1,1,-1e308,0,0\n"),
                 id="csv-coordinates-1e308"),
    pytest.param(_huge_id_mcap, id="mcap-topic-id-past-int64"),
])
@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_huge_numbers_are_not_an_internal_error(build, tmp_path, cli, monkeypatch):
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))     # where the CLI would write a crash report
    path = build(tmp_path)
    code, out, err = cli("check-run", path, "--range", "1")
    _no_traceback(out, err)
    assert code in (0, 1, 2, 3)
