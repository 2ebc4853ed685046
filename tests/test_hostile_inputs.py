"""Hostile inputs: numbers beyond the documents' bound, huge files, malformed data. Each gets exit
status 2 and one line on stderr naming the file and field (no traceback), leaves no output file behind,
and stays within a generous bound of time and memory (the test machine may have 2 shared cores)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

TIMEOUT = 120  # seconds: a generous bound; the defects took minutes or ran out of memory


def robkin(*args: str, cwd: Path | None = None, timeout: float = TIMEOUT) -> subprocess.CompletedProcess:
    """Run the command line in a subprocess (its exit status, stderr, and its own memory)."""
    return subprocess.run([sys.executable, "-m", "robkin.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env={**os.environ, "PYTHONWARNINGS": "default"})


def one_error_line(r: subprocess.CompletedProcess, *needles: str) -> str:
    """The run failed with exit 2 and one error line (no traceback, no warnings) naming every needle."""
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "Traceback" not in r.stderr
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


# --- 19b: URDF/MJCF/SDF numbers beyond 1e100 -------------------------------------------------------------

def _urdf(mass: str = "1", ixx: str = "1", mass2: str = "1") -> str:
    inertial = ('<inertial><mass value="{m}"/><inertia ixx="{i}" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>'
                '</inertial>')
    return (f'<robot name="r"><link name="base">{inertial.format(m=mass, i="1")}</link>'
            f'<link name="l1">{inertial.format(m=mass2, i=ixx)}</link>'
            '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


@pytest.mark.parametrize("to,ext", [("mjcf", ".xml"), ("yaml", ".yaml"), ("urdf", ".urdf"), ("rtb", ".py")])
@pytest.mark.parametrize("field,kw", [("mass value", {"mass": "1e308", "mass2": "1e308"}),
                                      ("inertia ixx", {"ixx": "1e308"})])
def test_urdf_inertial_beyond_bound(tmp_path: Path, to: str, ext: str, field: str, kw: dict) -> None:
    src = tmp_path / "big.urdf"
    src.write_text(_urdf(**kw))
    out = tmp_path / ("out" + ext)
    r = robkin("convert", src, "--to", to, "-o", out)
    line = one_error_line(r, str(src), "link '", field, "1e308", "1e+100")
    assert "inf" not in line.replace("inertial", "").replace("inertia", "")
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.urdf"]


def test_urdf_limit_beyond_bound(tmp_path: Path) -> None:
    src = tmp_path / "lim.urdf"
    src.write_text(_urdf().replace('effort="1"', 'effort="1e308"'))
    one_error_line(robkin("fk", src, "--q", "0"), str(src), "j1", "limit effort", "1e+100")


@pytest.mark.parametrize("name,text,needles", [
    ("big.xml", '<mujoco model="r"><worldbody><body name="b1"><joint name="j1" type="hinge"/>'
                '<inertial pos="0 0 0" mass="1e308" diaginertia="1 1 1"/></body></worldbody></mujoco>',
     ("body 'b1'", "mass")),
    ("big.sdf", '<sdf version="1.7"><model name="r"><link name="a"/><link name="b"><inertial><mass>1</mass>'
                '<inertia><ixx>1e308</ixx></inertia></inertial></link><joint name="j" type="revolute">'
                '<parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint></model></sdf>',
     ("link 'b'", "ixx")),
])
def test_mjcf_sdf_inertial_beyond_bound(tmp_path: Path, name: str, text: str, needles: tuple) -> None:
    src = tmp_path / name
    src.write_text(text)
    out = tmp_path / "out.xml"
    one_error_line(robkin("convert", src, "--to", "mjcf", "-o", out), str(src), *needles)
    assert not out.exists()


def test_convert_removes_output_when_check_fails(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Whatever fails in the check after writing (here: made to fail), exit 2 leaves no output file."""
    from robkin.cli import main
    from robkin.commands.convert_parts import output_check
    from robkin.errors import InputError

    def failing(*a: object, **k: object) -> str:
        raise InputError("the check failed")

    monkeypatch.setattr(output_check, "check_written", failing)
    src = tmp_path / "ok.urdf"
    src.write_text(_urdf())
    out = tmp_path / "out.xml"
    assert main(["convert", str(src), "--to", "mjcf", "-o", str(out)]) == 2
    assert not out.exists()


# --- 18: measurement values beyond 1e100 -----------------------------------------------------------------

@pytest.mark.parametrize("command", ["check", "calibrate"])
def test_measurement_value_beyond_bound_is_named(tmp_path: Path, command: str) -> None:
    model = tmp_path / "r.urdf"
    model.write_text(_urdf())
    rows = [f"{0.02 * k},{0.1 + 0.001 * k},0,0" for k in range(60)]
    rows[37] = "0.5,1e308,0,0"  # line 39 of the file (after the header)
    meas = tmp_path / "meas.csv"
    meas.write_text("j1,x,y,z\n" + "\n".join(rows) + "\n")
    out = tmp_path / "cal.urdf"
    extra = ["-o", out] if command == "calibrate" else []
    one_error_line(robkin(command, model, meas, *extra), str(meas), "line 39", "column 'x'", "1e308", "1e+100")
    assert not out.exists()


def test_measurement_array_beyond_bound_is_named(tmp_path: Path) -> None:
    import numpy as np

    model = tmp_path / "r.urdf"
    model.write_text(_urdf())
    a = np.zeros((60, 4))
    a[:, 0] = np.linspace(-1, 1, 60)
    a[12, 2] = -1e308
    meas = tmp_path / "meas.npy"
    np.save(meas, a)
    one_error_line(robkin("check", model, meas), str(meas), "pose 13", "column 3", "1e+100")


# --- 19: --kp / --kv beyond 1e100 -------------------------------------------------------------------------

@pytest.mark.parametrize("flag,value", [("--kp", "1e308"), ("--kv", "1e308"), ("--kv", "1e101"), ("--kp", "nan"),
                                        ("--kp", "-1")])
def test_gain_beyond_bound_is_refused(tmp_path: Path, flag: str, value: str) -> None:
    src = tmp_path / "r.urdf"
    src.write_text(_urdf())
    out = tmp_path / "out.xml"
    one_error_line(robkin("convert", src, "--to", "mjcf", "--actuators", "position", flag, value, "-o", out),
                   flag, "1e+100")
    assert not out.exists()


def test_gain_at_bound_is_accepted(tmp_path: Path) -> None:
    src = tmp_path / "r.urdf"
    src.write_text(_urdf())
    out = tmp_path / "out.xml"
    r = robkin("convert", src, "--to", "mjcf", "--actuators", "position", "--kp", "1e100", "-o", out)
    assert r.returncode == 0, r.stderr
    assert out.exists()


# --- 20: messages name the field: recursive YAML alias, GUI request types, alias bomb beside flip ------------

@pytest.mark.parametrize("dh,field", [("&d {rows: [[0, 0, 0, 0]], x: *d}", "dh.x"),
                                      ("{rows: &r [[0, 0, 0, *r]]}", "dh.rows[0][3]")])
def test_recursive_alias_names_the_field(tmp_path: Path, dh: str, field: str) -> None:
    src = tmp_path / "rec.yaml"
    src.write_text(f"robkin: 1\njoints: [revolute]\ndh: {dh}\n")
    one_error_line(robkin("fk", src, "--q", "0"), str(src), field, "recursive alias")


def _flip_bomb(levels: int) -> str:
    """A joint whose flip holds nested aliases: 10**levels values once expanded, in ~50 bytes a level."""
    inner = "&a [x, x, x, x, x, x, x, x, x, x], " + ", ".join(
        f"&{k} [{', '.join(['*' + p] * 10)}]" for p, k in zip("abcdefgh", "bcdefghi"[:levels - 1]))
    return f"robkin: 1\njoints: [{{name: j, type: revolute, flip: [{inner}]}}]\ndh: {{rows: [[0, 0, 0, 0]]}}\n"


@pytest.mark.parametrize("text,fmt,field", [
    (5, "auto", "text"),
    ("robkin: 1\njoints: [revolute]\ndh: {rows: [[0, 0, 0, 0]]}\n", ["yaml"], "format"),
    (_flip_bomb(5), "auto", "joints[0] ('j').flip"),   # 10^5 values: refused as no boolean, quoted briefly
    (_flip_bomb(7), "auto", "joints[0].flip"),          # 10^7 values: refused while composing
])
def test_gui_api_messages_name_the_field(text: object, fmt: object, field: str) -> None:
    import time

    from robkin.errors import InputError
    from robkin.viz import gui_api

    t0 = time.perf_counter()
    with pytest.raises(InputError) as info:
        gui_api.describe(text, fmt)  # type: ignore[arg-type]
    message = str(info.value)
    assert field in message, message
    assert "\n" not in message and len(message) < 600, message
    assert time.perf_counter() - t0 < 30


def test_flip_bomb_through_the_command_line(tmp_path: Path) -> None:
    src = tmp_path / "bomb.yaml"
    src.write_text(_flip_bomb(7))
    one_error_line(robkin("fk", src, "--q", "0"), str(src), "joints[0].flip", "aliases")


# --- 15: one joint cap (MAX_JOINTS) wherever a robot is read ------------------------------------------------

def _max_joints() -> int:
    from robkin.compiled.scanners.vocabulary import MAX_JOINTS

    return MAX_JOINTS


def test_pasted_rows_beyond_the_joint_cap_gui() -> None:
    import resource
    import time

    from robkin.errors import InputError
    from robkin.viz import gui_api

    text = "0.1 0.2 1.5707963 0 R\n" * 154_545  # 3.4 MB: under the GUI's text cap
    t0 = time.perf_counter()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(InputError) as info:
        gui_api.describe(text, "dh-rows")
    assert f"at most {_max_joints()} joints" in str(info.value) and "line " in str(info.value)
    assert time.perf_counter() - t0 < 30
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 400_000  # kB: was > 1.2 GB


def _rows(n: int) -> str:
    return "".join(f"0.{k % 7 + 1} 0.1 1.5707963 0\n" for k in range(n))


@pytest.mark.parametrize("name,text,needle", [
    ("rows.txt", _rows(200_000), "line 10003"),                                   # bare rows, --from dh
    ("table.csv", "a,d,alpha,theta\n" + _rows(10_100).replace(" ", ","), "line "),  # a header table
])
def test_table_files_beyond_the_joint_cap(tmp_path: Path, name: str, text: str, needle: str) -> None:
    src = tmp_path / name
    src.write_text(text)
    out = tmp_path / "out.yaml"
    r = robkin("convert", src, "--from", "dh", "--to", "mdh", "-o", out)
    one_error_line(r, str(src), needle, f"at most {_max_joints()}")
    assert not out.exists()


def test_document_beyond_the_joint_cap(tmp_path: Path) -> None:
    import json

    n = _max_joints() + 1
    src = tmp_path / "many.json"
    src.write_text(json.dumps({"robkin": 1, "joints": ["revolute"] * n, "dh": {"rows": [[0.1, 0, 0, 0]] * n}}))
    one_error_line(robkin("info", src), str(src), "joints:", f"at most {_max_joints()}")


def test_urdf_chain_beyond_the_joint_cap(tmp_path: Path) -> None:
    n = _max_joints() + 1
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(f'<joint name="j{i}" type="continuous"><parent link="l{i}"/><child link="l{i + 1}"/>'
                     f'<origin xyz="0 0 0.01"/></joint>' for i in range(n))
    src = tmp_path / "long.urdf"
    src.write_text(f'<robot name="r">{links}{joints}</robot>')
    one_error_line(robkin("info", src), str(src), f"{n} joints", f"at most {_max_joints()}")


def test_a_chain_at_the_joint_cap_is_read() -> None:
    from robkin.viz import gui_api

    assert gui_api.describe(_rows(2000), "dh-rows")["n"] == 2000


# --- 14: fk --q-file: rows capped (MAX_ROWS) and no Python row objects for array output -----------------------

SIX_DH = ("robkin: 1\njoints: [revolute, revolute, revolute, revolute, revolute, revolute]\n"
          "dh: {rows: [[0, 0.089, 1.5708, 0], [-0.425, 0, 0, 0], [-0.392, 0, 0, 0], [0, 0.109, 1.5708, 0],"
          " [0, 0.095, -1.5708, 0], [0, 0.082, 0, 0]]}\n")
#: Peak resident memory allowed to one batch run (kB): MAX_ROWS rows of a 6-joint arm peak at ~340 MB;
#: 2.7 * 10^6 rows took 1.9 GB before the cap.
PEAK_KB = 600_000


def _peak_of(*args: str) -> tuple[int, str, int]:
    """(exit status, stderr, peak RSS in kB) of one robkin run, measured in a fresh process so that no
    earlier child's peak counts (RUSAGE_CHILDREN is the largest of all waited-for children)."""
    code = ("import resource, subprocess, sys\n"
            "r = subprocess.run([sys.executable, '-m', 'robkin.cli', *sys.argv[1:]], capture_output=True, text=True)\n"
            "sys.stderr.write(r.stderr)\n"
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
            "sys.exit(r.returncode)\n")
    r = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=TIMEOUT)
    return r.returncode, r.stderr, int(r.stdout.strip().splitlines()[-1])


def _q_file(path: Path, rows: int) -> Path:
    with open(path, "w") as f:
        f.write("q1,q2,q3,q4,q5,q6\n")
        f.write("0.1,0,0,0,0,0\n" * rows)
    return path


def test_fk_q_file_beyond_the_row_cap(tmp_path: Path) -> None:
    from robkin.io.batch_files import MAX_ROWS

    model = tmp_path / "six.yaml"
    model.write_text(SIX_DH)
    q = _q_file(tmp_path / "q.csv", 2_700_000)  # 38 MB: under MAX_BYTES and MAX_VALUES
    out = tmp_path / "poses.npy"
    rc, err, peak = _peak_of("fk", str(model), "--q-file", str(q), "-o", str(out))
    one_error_line(subprocess.CompletedProcess([], rc, "", err), str(q), f"more than {MAX_ROWS} rows", "split")
    assert peak < 300_000, peak  # kB: the file's bytes and text, no row objects
    assert not out.exists()


@pytest.mark.parametrize("ext", [".npy", ".csv"])
def test_fk_q_file_at_the_row_cap_stays_in_memory_bound(tmp_path: Path, ext: str) -> None:
    from robkin.io.batch_files import MAX_ROWS

    model = tmp_path / "six.yaml"
    model.write_text(SIX_DH)
    rows = MAX_ROWS if ext == ".npy" else MAX_ROWS // 5  # CSV output costs ~50 us a row: keep the test short
    q = _q_file(tmp_path / "q.csv", rows)
    out = tmp_path / ("poses" + ext)
    rc, err, peak = _peak_of("fk", str(model), "--q-file", str(q), "-o", str(out))
    assert rc == 0, err
    assert peak < PEAK_KB, peak
    if ext == ".npy":
        assert __import__("numpy").load(out).shape == (rows, 4, 4)


def test_fk_json_beyond_its_row_cap(tmp_path: Path) -> None:
    from robkin.io.batch_files import MAX_JSON_ROWS

    model = tmp_path / "six.yaml"
    model.write_text(SIX_DH)
    q = _q_file(tmp_path / "q.csv", MAX_JSON_ROWS + 1)
    one_error_line(robkin("fk", model, "--q-file", q, "--json"), str(q), f"at most {MAX_JSON_ROWS}", ".npy")


# --- 17: malformed meshes are left out of the MJCF with one warning line, the rest loads in MuJoCo -----------

def _binary_stl(triangles: list, claimed: int | None = None) -> bytes:
    import struct

    body = b"".join(struct.pack("<12fH", 0, 0, 1, *[c for v in t for c in v], 0) for t in triangles)
    return b"\0" * 80 + struct.pack("<I", len(triangles) if claimed is None else claimed) + body


TRI = [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0)]
_P = [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1)]
TETRA = [[_P[a], _P[b], _P[c]] for a, b, c in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))]


def test_malformed_meshes_left_out_of_the_mjcf(tmp_path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    src_dir = tmp_path / "robot"
    (src_dir / "meshes").mkdir(parents=True)
    files = {
        "good.stl": _binary_stl(TETRA),
        "flat.stl": _binary_stl([TRI]),
        "empty.stl": b"",
        "truncated.stl": _binary_stl([TRI, TRI, TRI])[:-70],
        "huge.stl": _binary_stl([TRI], claimed=4_000_000_000),
        "nan.stl": _binary_stl([[(float("nan"), 0, 0), (0.1, 0, 0), (0, 0.1, 0)]]),
        "nan.obj": b"v 0 0 0\nv nan 0 0\nv 0 1 inf\nf 1 2 3\n",
        "good.obj": b"v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    }
    for name, data in files.items():
        (src_dir / "meshes" / name).write_bytes(data)
    visuals = "".join(f'<visual><geometry><mesh filename="meshes/{name}"/></geometry></visual>' for name in files)
    (src_dir / "r.urdf").write_text(
        f'<robot name="r"><link name="base"/><link name="l1">{visuals}'
        '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
        '</link><joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    out = tmp_path / "out" / "r.xml"
    r = robkin("convert", src_dir / "r.urdf", "--to", "mjcf", "-o", out, timeout=TIMEOUT)
    assert r.returncode == 0, r.stderr
    warning = [line for line in r.stderr.splitlines() if "MuJoCo would refuse" in line]
    assert len(warning) == 1, r.stderr
    assert warning[0].count("(") >= 3 and "6 mesh file(s)" in warning[0], warning
    assert "good.stl" not in warning[0] and "good.obj" not in warning[0]
    model = mujoco.MjModel.from_xml_path(str(out))  # what robkin writes loads
    assert model.nmesh == 2
    text = out.read_text()
    assert "good.stl" in text and "good.obj" in text and "huge" not in text and "nan." not in text
    assert sorted(p.name for p in (out.parent / "meshes").rglob("*") if p.is_file()) == ["good.obj", "good.stl"]


# --- 16: check MODEL MEASUREMENTS on measurements not of the model: bounded, and said ----------------------

def test_check_on_random_measurements_is_bounded(tmp_path: Path) -> None:
    """The base fit only: no per-joint fits (12 full fits took 15-60 s; the base fit alone ~2 s). Not
    timed here (shared machines): bounded by what runs, which the output shows."""
    import numpy as np

    from robkin import load
    from robkin.calibration import write_measurements_csv

    model = tmp_path / "six.yaml"
    model.write_text(SIX_DH)
    robot = load(model)
    rng = np.random.default_rng(0)
    meas = tmp_path / "random.csv"
    write_measurements_csv(meas, robot, rng.uniform(-3, 3, (1000, 6)), rng.uniform(-1, 1, (1000, 3)))
    r = robkin("check", model, meas)
    assert r.returncode == 1, r.stderr   # a valid answer: the model is not the measured robot
    assert "not of this model" in r.stdout and "share of the error" not in r.stdout, r.stdout
