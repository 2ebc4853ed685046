"""``robkin fk --q-file`` / ``robkin ik --poses``: files of many rows through the batch kernels, checked
against the Python batch API (Robot.fk on (N, n), Robot.ik on (N, 4, 4)), every input and output
format, per-row success and errors, and one clear line for bad files."""

from __future__ import annotations

import io
import json
import sys

import numpy as np
import pytest

import robkin
from robkin.cli import main
from test_urdf import robot_file


@pytest.fixture(scope="module")
def ur5():
    path = robot_file("ur_description/urdf/ur5_robot.urdf")
    return path, robkin.load(path, tip_link="tool0")


def _csv(path) -> tuple[list[str], list[list[str]]]:
    lines = [line.split(",") for line in path.read_text().splitlines()]
    return lines[0], lines[1:]


def test_fk_file_equals_the_batch_api(tmp_path, ur5):
    path, robot = ur5
    Q = robot.random_q(1000, rng=7)
    qfile = tmp_path / "q.csv"
    qfile.write_text(",".join(j.name for j in robot.joints) + "\n"
                     + "\n".join(",".join(repr(float(v)) for v in q) for q in Q) + "\n")
    assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(qfile), "-o", str(tmp_path / "T.npy")]) == 0
    np.testing.assert_array_equal(np.load(tmp_path / "T.npy"), robot.fk(Q))  # bit for bit
    assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(qfile), "-o", str(tmp_path / "p.csv")]) == 0
    header, rows = _csv(tmp_path / "p.csv")
    assert header[:8] == ["row", *[j.name for j in robot.joints], "x"] and len(rows) == 1000
    xyz = np.array([[float(r[header.index(c)]) for c in "xyz"] for r in rows])
    np.testing.assert_array_equal(xyz, robot.fk(Q)[:, :3, 3])  # the CSV reads back bit for bit


def test_1000_targets_from_a_file_equal_the_batch_api(tmp_path, ur5):
    path, robot = ur5
    T = robot.fk(robot.random_q(1000, rng=8))
    T[::97, 0, 3] += 3.0  # 11 targets out of reach
    np.save(tmp_path / "T.npy", T)
    assert main(["ik", path, "--tip-link", "tool0", "--poses", str(tmp_path / "T.npy"),
                 "-o", str(tmp_path / "sol.npz")]) == 0
    got = np.load(tmp_path / "sol.npz")
    want = robot.ik(T)
    ok = np.asarray(want.success)
    assert ok.sum() == 1000 - 11
    np.testing.assert_array_equal(got["success"], ok)
    np.testing.assert_array_equal(got["q"][ok], want.q[ok])
    # rows without a solution: the reason, and the closest configuration with its finite distance
    assert all("out of reach" in m for m in got["error"][~ok]) and not any(got["error"][ok])
    # 3 m beyond a reachable pose of an arm reaching ~0.95 m: more than 1 m from anything it reaches
    assert np.all(np.isfinite(got["q"][~ok])) and np.all(got["position_error"][~ok] > 1.0)
    dist = np.linalg.norm(robot.fk(got["q"][~ok])[:, :3, 3] - T[~ok, :3, 3], axis=1)
    np.testing.assert_allclose(dist, got["position_error"][~ok], rtol=1e-12)


def test_fk_output_feeds_ik_and_back_through_stdin(tmp_path, ur5, monkeypatch, capsys):
    path, robot = ur5
    Q = robot.random_q(50, rng=9)
    np.save(tmp_path / "q.npy", Q)
    assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(tmp_path / "q.npy"), "-o",
                 str(tmp_path / "poses.csv")]) == 0
    # the CSV fk wrote is the input of ik (x, y, z and the quaternion), read here from stdin
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO((tmp_path / "poses.csv").read_bytes())))
    capsys.readouterr()
    assert main(["ik", path, "--tip-link", "tool0", "--poses", "-", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["success"] for r in doc["results"]] == [True] * 50
    q = np.array([r["q"] for r in doc["results"]])
    np.testing.assert_allclose(robot.fk(q), robot.fk(Q), atol=1e-9)


def test_progress_on_a_terminal(tmp_path, ur5, monkeypatch, capsys):
    from robkin.commands.support import batches as _batches

    path, robot = ur5
    np.save(tmp_path / "q.npy", robot.random_q(30, rng=1))
    monkeypatch.setattr(_batches, "BLOCK", 8)
    monkeypatch.setattr(_batches, "PROGRESS_FROM", 10)
    monkeypatch.setattr(_batches, "_is_terminal", lambda stream: True)
    assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(tmp_path / "q.npy"), "--json"]) == 0
    err = capsys.readouterr().err
    assert "fk: 8/30" in err and "fk: 30/30 (100%)" in err
    monkeypatch.setattr(_batches, "_is_terminal", lambda stream: False)
    assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(tmp_path / "q.npy"), "--json"]) == 0
    assert "30/30" not in capsys.readouterr().err  # a pipe or a log gets no progress lines


def test_single_pose_without_solution_gives_the_closest_distance(ur5, capsys):
    path, robot = ur5
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "2,0,0.3,pi,0,0", "--json"]) == 0
    out, err = capsys.readouterr()
    closest = json.loads(out)["closest"]
    # UR5 reaches ~0.95 m from the shoulder: a target 2 m out is at least ~1 m away from any pose
    assert 0.9 < closest["position_error"] < 1.2
    assert np.linalg.norm(robot.fk(closest["q"])[:3, 3] - [2, 0, 0.3]) == pytest.approx(closest["position_error"])
    assert "closest: " in err and " m from the target position" in err and err.count("\n") == 1


def _bad(tmp_path, name: str, data: bytes | str) -> str:
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode())
    return str(p)


def test_bad_batch_files_are_one_line(tmp_path, ur5, capsys):
    path, robot = ur5
    buf = io.BytesIO()
    np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    npz = io.BytesIO()
    np.savez(npz, a=np.zeros((2, 6)), b=np.zeros((2, 6)))
    cases = [
        (["fk", "--q-file", _bad(tmp_path, "obj.npy", buf.getvalue())], "expected numbers"),
        (["fk", "--q-file", _bad(tmp_path, "two.npz", npz.getvalue())], "name the array 'q'"),
        (["fk", "--q-file", _bad(tmp_path, "w.csv", "q1,q2\n0,0\n")], "no joint columns"),
        (["fk", "--q-file", _bad(tmp_path, "n.csv", "1,2,3\n")], "3 values per row; the robot has 6"),
        (["fk", "--q-file", _bad(tmp_path, "x.csv", "q1,q2,q3,q4,q5,q6\n0,0,0,0,0,nan\n")], "not a finite number"),
        (["ik", "--poses", _bad(tmp_path, "p.csv", "x,y,z\n0,0,0\n")], "no pose columns"),
        (["ik", "--poses", _bad(tmp_path, "q.csv", "x,y,z,qw,qx,qy,qz\n0,0,0,2,0,0,0\n")], "unit quaternion"),
        (["ik", "--poses", _bad(tmp_path, "fake.npy", "x,y\n")], "not a NumPy"),
        (["fk", "--q-file", _bad(tmp_path, "ok.csv", "q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0\n"), "-o",
          str(tmp_path / "out.txt")], "-o writes .csv, .npy, .npz or .json"),
        (["fk", "--q", "0,0,0,0,0,0", "-o", str(tmp_path / "one.csv")], "writes the results of --q-file"),
    ]
    for argv, words in cases:
        assert main([argv[0], path, "--tip-link", "tool0", *argv[1:]]) == 2, argv
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1, (argv, err)
    assert not (tmp_path / "out.txt").exists() and not (tmp_path / "one.csv").exists()


def test_all_solutions_of_every_target(tmp_path, ur5, capsys):
    path, robot = ur5
    T = robot.fk(robot.random_q(5, rng=3))
    T[2, 0, 3] += 3.0
    np.save(tmp_path / "T.npy", T)
    assert main(["ik", path, "--tip-link", "tool0", "--poses", str(tmp_path / "T.npy"), "--all", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    want = robot.ik(T, all_solutions=True)
    for k, r in enumerate(doc["results"]):
        got = np.array([s["q"] for s in r["solutions"]]).reshape(-1, robot.n)
        np.testing.assert_array_equal(got, np.atleast_2d(want.solutions[k]).reshape(-1, robot.n))
    assert [len(r["solutions"]) for r in doc["results"]][2] == 0 and not doc["results"][2]["success"]
    assert main(["ik", path, "--tip-link", "tool0", "--poses", str(tmp_path / "T.npy"), "--all",
                 "-o", str(tmp_path / "all.npz")]) == 0
    sols = np.load(tmp_path / "all.npz")["solutions"]
    assert sols.shape == (sum(len(r["solutions"]) for r in doc["results"]), 1 + robot.n)
    np.testing.assert_allclose(robot.fk(sols[:, 1:]), T[sols[:, 0].astype(int)], atol=1e-9)


def test_threads_option_bounds_the_batch_and_keeps_the_bits(tmp_path, ur5, monkeypatch, capsys):
    path, robot = ur5
    Q = robot.random_q(3000, rng=9)
    np.save(tmp_path / "q.npy", Q)
    T = robot.fk(Q)
    np.save(tmp_path / "T.npy", T[:300])
    seen = []
    import robkin.threads as threads

    real = threads.set_threads
    monkeypatch.setattr(threads, "set_threads", lambda n: (seen.append(n), real(n))[1])
    before = robkin.get_threads()
    for n in (1, 2):
        assert main(["fk", path, "--tip-link", "tool0", "--q-file", str(tmp_path / "q.npy"), "--threads", str(n),
                     "-o", str(tmp_path / f"T{n}.npy")]) == 0
        assert main(["ik", path, "--tip-link", "tool0", "--poses", str(tmp_path / "T.npy"), "--method", "numeric",
                     "--threads", str(n), "-o", str(tmp_path / f"q{n}.npy")]) == 0
    assert seen[::2] == [1, 1, 2, 2]  # set for each run, and the process default put back after it
    assert robkin.get_threads() == before
    np.testing.assert_array_equal(np.load(tmp_path / "T1.npy"), T)
    np.testing.assert_array_equal(np.load(tmp_path / "T2.npy"), T)
    np.testing.assert_array_equal(np.load(tmp_path / "q1.npy"), np.load(tmp_path / "q2.npy"))
    capsys.readouterr()
    with pytest.raises(SystemExit) as exc:
        main(["fk", path, "--tip-link", "tool0", "--q", "0,0,0,0,0,0", "--threads", "0"])
    assert exc.value.code == 2
    assert "--threads: 0: expected a whole number >= 1" in capsys.readouterr().err


def test_batch_rows_are_counted_as_data_lines_not_file_lines(tmp_path, monkeypatch):
    """Blank and # comment lines do not count towards the row cap, nor hide rows from it: the rows
    are counted as data lines (a count over the file's first lines sized the array too small when
    comments came first)."""
    import robkin.io.batch_files as batch_files
    from robkin.errors import InputError

    monkeypatch.setattr(batch_files, "MAX_ROWS", 10)
    path = tmp_path / "q.csv"
    path.write_text("# comments first\n" * 20 + "a,b\n" + "".join(f"{k},{-k}\n\n# note\n" for k in range(8)))
    rows = batch_files.read_rows(str(path))
    assert rows.columns == ["a", "b"] and rows.values.shape == (8, 2) and rows.values[7, 1] == -7
    path.write_text("# comments first\n" * 20 + "".join(f"{k},{-k}\n\n" for k in range(11)))
    with pytest.raises(InputError, match="more than 10 rows"):
        batch_files.read_rows(str(path))


@pytest.mark.parametrize("every", [False, True])
def test_every_output_of_ik_poses_holds_the_same_results(tmp_path, ur5, capsys, every):
    """The batch results are arrays, and each output is made from them: .npy, .npz, CSV (file and
    stdout) and JSON agree value for value, rows without a solution included (with --all: solution 0,
    first, then the target's solutions numbered from 1, in the order of the .npz's)."""
    path, robot = ur5
    T = robot.fk(robot.random_q(12, rng=11))
    T[[3, 7], 0, 3] += 3.0  # two targets out of reach
    np.save(tmp_path / "T.npy", T)
    base = ["ik", path, "--tip-link", "tool0", "--poses", str(tmp_path / "T.npy")] + (["--all"] if every else [])
    for ext in ("npy", "npz", "csv", "json"):
        assert main(base + ["-o", str(tmp_path / f"out.{ext}")]) == 0
    capsys.readouterr()
    assert main(base) == 0
    stdout = capsys.readouterr().out
    assert stdout == (tmp_path / "out.csv").read_text()
    z = np.load(tmp_path / "out.npz")
    np.testing.assert_array_equal(np.load(tmp_path / "out.npy"), z["q"])
    assert z["error"].dtype.kind == "U" and list(np.flatnonzero(~z["success"])) == [3, 7]
    assert all("out of reach" in e for e in z["error"][[3, 7]]) and not any(z["error"][z["success"]])
    doc = json.loads((tmp_path / "out.json").read_text())
    for k, r in enumerate(doc["results"]):
        assert r["success"] == z["success"][k] and (r["reason"] or "") == z["error"][k]
        np.testing.assert_array_equal(r["q"], z["q"][k])
        assert (r["position_error"], r["orientation_error"]) == (z["position_error"][k], z["orientation_error"][k])
    header, rows = _csv(tmp_path / "out.csv")
    joints = [header.index(j.name) for j in robot.joints]
    if not every:
        assert len(rows) == 12 and [int(r[0]) for r in rows] == list(range(1, 13))
        np.testing.assert_array_equal([[float(r[i]) for i in joints] for r in rows], z["q"])  # read back bit for bit
        assert [r[1] == "true" for r in rows] == list(z["success"])
        return
    S = z["solutions"]
    assert len(rows) == len(S) + 2 and len(S) > 12   # the UR5: up to 8 solutions a target
    assert [(int(r[0]), int(r[1])) for r in rows] == sorted((int(r[0]), int(r[1])) for r in rows)
    failed = [r for r in rows if r[1] == "0"]
    assert [int(r[0]) for r in failed] == [4, 8] and all(r[2] == "false" for r in failed)
    solved = [r for r in rows if r[1] != "0"]
    np.testing.assert_array_equal([[int(r[0]) - 1] + [float(r[i]) for i in joints] for r in solved], S)
    for k, r in enumerate(doc["results"]):
        np.testing.assert_array_equal(np.reshape([s["q"] for s in r["solutions"]], (-1, robot.n)),
                                      S[S[:, 0] == k, 1:])
