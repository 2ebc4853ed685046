"""The command line around URDF/MJCF: convert to and from URDF and MJCF, batches, --json, the joint
mapping note, rich tables on a terminal, and the lazy-import promise of the start-up path."""

from __future__ import annotations

import io
import json
import subprocess
import sys

import numpy as np
import pytest

from robkin import Joint, Robot, se3
from robkin.cli import main
from robkin.io.documents.reader import read_document
from robkin.io.tables.terminal import show_blocks, use_rich
from robkin.io.urdf import robot_from_urdf, urdf_from_robot
from test_urdf import CASES, TILTED_SILENT, pin, pin_fk, robot_file, sample_q

PANDA = "panda_description/urdf/panda.urdf"


def test_convert_urdf_to_every_document_section_keeps_fk(tmp_path, capsys):
    path = robot_file(PANDA)
    original = robot_from_urdf(path, tip_link="panda_hand_tcp")
    Q = sample_q(original, 10, seed=1)
    for fmt in ("dh", "mdh", "poe", "poe-body", "rpy-xyz", "gjd", "json", "yaml"):
        out = tmp_path / f"p_{fmt}.{'json' if fmt == 'json' else 'yaml'}"
        assert main(["convert", path, "--tip-link", "panda_hand_tcp", "--to", fmt, "-o", str(out)]) == 0
        back = read_document(out)
        # documents are written with 15 significant digits: FK agrees to ~1e-15 relative
        np.testing.assert_allclose(back.fk(Q), original.fk(Q), atol=1e-12, err_msg=fmt)
        assert [j.name for j in back.joints] == [j.name for j in original.joints]
        assert back.joints[3].lower == -3.0718 and back.joints[3].upper == -0.0698
    err = capsys.readouterr().err
    assert "joint variables: q_i in this dh output is the URDF position of joint i (panda_joint1" in err


def test_convert_document_to_urdf_and_mjcf_loads_in_peers(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    f = tmp_path / "t.urdf"
    f.write_text(TILTED_SILENT())
    assert main(["convert", str(f), "--to", "yaml", "-o", str(tmp_path / "t.yaml")]) == 0
    robot = read_document(tmp_path / "t.yaml")
    assert main(["convert", str(tmp_path / "t.yaml"), "--to", "urdf", "-o", str(tmp_path / "back.urdf")]) == 0
    assert main(["convert", str(tmp_path / "t.yaml"), "--to", "mjcf", "-o", str(tmp_path / "back.xml")]) == 0
    model = pin.buildModelFromUrdf(str(tmp_path / "back.urdf"))
    mj = mujoco.MjModel.from_xml_path(str(tmp_path / "back.xml"))
    data = mujoco.MjData(mj)
    for q in sample_q(robot, 5, seed=4):
        data.qpos[:] = q
        mujoco.mj_kinematics(mj, data)
        site = mj.site("tool").id
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = data.site_xmat[site].reshape(3, 3), data.site_xpos[site]
        # the world link's transform survives the document (its rpy_xyz row 0) and both exports
        np.testing.assert_allclose(pin_fk(model, robot, q, "tool"), robot.world @ robot.fk(q), atol=1e-12)
        np.testing.assert_allclose(T, robot.world @ robot.fk(q), atol=1e-12)
    assert not np.allclose(robot.world, np.eye(4))


def test_batch_convert_of_urdfs_and_documents(tmp_path, capsys):
    a = tmp_path / "tilted.urdf"
    a.write_text(TILTED_SILENT())
    xarm = robot_file(CASES[6][0])
    outdir = tmp_path / "out"
    outdir.mkdir()
    assert main(["convert", str(a), xarm, "--to", "urdf", "-o", str(outdir)]) == 0
    assert sorted(p.name for p in outdir.iterdir()) == ["tilted.urdf", "xarm7.urdf"]
    for name, src in (("tilted.urdf", str(a)), ("xarm7.urdf", xarm)):
        r0, r1 = robot_from_urdf(src), robot_from_urdf(str(outdir / name))
        Q = sample_q(r0, 5, seed=6)
        np.testing.assert_allclose(r1.world @ r1.fk(Q), r0.world @ r0.fk(Q), atol=1e-12)
    err = capsys.readouterr().err.splitlines()
    assert [line for line in err if line.startswith("wrote")] == [f"wrote {outdir / 'tilted.urdf'}",
                                                                  f"wrote {outdir / 'xarm7.urdf'}"]
    # then each written file read back and checked: one note each (tilted.urdf has no inertials)
    notes = [line for line in err if not line.startswith("wrote")]
    assert len(notes) == 2 and all(line.startswith("robkin: note: ") for line in notes)
    assert "mass properties not checked (the robot has no inertials)" in notes[0]
    assert "FK and mass properties equal the source's" in notes[1]


def test_convert_json_flag_prints_the_section(capsys):
    assert main(["convert", robot_file(PANDA), "--tip-link", "panda_hand_tcp", "--to", "mdh", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc) == {"robkin", "name", "joints", "mdh"} and len(doc["mdh"]["rows"]) == 7
    # Craig's modified DH of the Panda (Franka's published table): d1 = 0.333, d3 = 0.316,
    # a3 = 0.0825, a4 = -0.0825, d5 = 0.384, a6 = 0.088
    rows = doc["mdh"]["rows"]
    np.testing.assert_allclose([r["d"] for r in rows], [0.333, 0, 0.316, 0, 0.384, 0, 0], atol=1e-12)
    np.testing.assert_allclose([abs(r["a"]) for r in rows], [0, 0, 0, 0.0825, 0.0825, 0, 0.088], atol=1e-12)


def test_xml_special_characters_in_names_survive(tmp_path):
    robot = Robot(np.stack([np.eye(4), se3.trans(0, 0, 0.5)]), (Joint('a"b<c>&d'),), name="r&<>'\"")
    text = urdf_from_robot(robot)
    back = robot_from_urdf(text)
    assert back.joints[0].name == 'a"b<c>&d' and back.name == "r&<>'\""


def test_rich_tables_on_a_terminal_plain_in_a_pipe(monkeypatch):
    pytest.importorskip("rich")

    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    monkeypatch.delenv("NO_COLOR", raising=False)
    monkeypatch.delenv("ROBKIN_PLAIN", raising=False)
    items = [("title", ["i", "joint", "a"], [["1", "j1", 0.25], ["2", "j2", -1.5]]), "a note"]
    tty, pipe = Tty(), io.StringIO()
    assert use_rich(tty) and not use_rich(pipe)
    show_blocks(items, tty)
    show_blocks(items, pipe)
    assert "│" in tty.getvalue() or "┃" in tty.getvalue()  # rich box drawing
    assert "│" not in pipe.getvalue() and "j2" in pipe.getvalue() and "-1.5" in pipe.getvalue()
    monkeypatch.setenv("NO_COLOR", "1")
    assert not use_rich(tty)


def test_convert_startup_imports_nothing_heavy():
    """The start-up promise, checked without timing: the convert path of a URDF imports none of
    the heavy optional libraries, nor numpy.random (~10 ms; the FK checks use fixed samples instead),
    nor the representations, command modules and URDF writer it does not use (each costs its import).
    The XML tree is imported now: a DH table carries the links' masses, read from the inertials
    (benchmarks/bench_cli_startup.py measures the time itself)."""
    code = ("import sys; from robkin.cli import main; "
            f"rc = main(['convert', {robot_file(PANDA)!r}, '--tip-link', 'panda_hand_tcp', '--to', 'dh']); "
            "heavy = {'scipy', 'matplotlib', 'rich', 'pinocchio', 'mujoco', 'yourdfpy', 'xacro', 'http', "
            "'email', 'hypothesis', 'trimesh'}; "
            "unused = {'robkin.representations.' + m for m in ('mdh', 'hayati', 'poe', 'rpy_xyz')} "
            "| {'robkin.commands.' + m for m in ('fk', 'ik', 'check', 'info', 'estimate', 'plot', 'gui', 'demo')} "
            "| {'robkin.io.urdf.writer'}; "
            "print(rc, sorted({m.split('.')[0] for m in sys.modules} & heavy), 'numpy.random' in sys.modules, "
            "sorted(unused & set(sys.modules)), 'robkin.representations.dh' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"ROBKIN_PLAIN": "1", "PATH": ""}).stdout.strip().splitlines()[-1]
    assert out == "0 [] False [] True"


def test_import_robkin_loads_no_representation_until_asked():
    """``import robkin`` costs the hub only; robkin.DHTable & co. are imported on first use and then
    are the classes of their modules (``from robkin import *`` gives every exported name)."""
    code = ("import sys, robkin; before = sorted(m for m in sys.modules if m.startswith('robkin.representations')); "
            "from robkin.representations.poe import PoE; ns = {}; exec('from robkin import *', ns); "
            "print(before, robkin.PoE is PoE, sorted(set(robkin.__all__) - set(ns)), 'PoE' in dir(robkin))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[] True [] True"
    import robkin

    with pytest.raises(AttributeError, match="no attribute 'DHTabel'"):
        robkin.DHTabel  # noqa: B018 - a typo is an AttributeError naming the name, as for any module
