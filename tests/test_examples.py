"""Every example in every ``--help`` and every command and Python block of the README runs as printed.

The examples are extracted from the parsers' epilogs and from README.md, expanded by bash exactly as a
user's shell would (variables, quoting, comments, line continuations), and run in a scratch folder that
holds the files they name: the bundled robots, real URDFs from example-robot-data (UR5, Panda), and
files made from them (a URDF of the RRPR robot, a DH table typed with 4 decimals, estimation results).
``robkin`` commands run in-process through ``robkin.cli.main``; ``robkin gui`` is only parsed and its
input loaded (it serves until stopped). The README's tour starts with ``cd "$(mktemp -d)"`` and makes
its own files there (TMPDIR points into the test's folder); a ``cd`` line moves the test into the folder
bash ends up in. A failing example names itself.
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import build_parser, main
from robkin.examples import EXAMPLES_DIR

ROOT = Path(__file__).resolve().parent.parent
ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
REAL = {"ur5.urdf": "ur_description/urdf/ur5_robot.urdf", "panda.urdf": "panda_description/urdf/panda.urdf"}
BASH = shutil.which("bash")
pytestmark = pytest.mark.skipif(BASH is None, reason="bash is needed to expand the examples as a shell does")


def help_examples() -> list[str]:
    """The 'examples:' lines of every command's --help, continuation lines joined."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = []
    for name, p in sub.choices.items():
        text = p.format_help()
        if "examples:" not in text:
            continue
        block = text.split("examples:", 1)[1].split("\n\n", 1)[0]
        out += [f"{name}: {cmd}" for cmd in _commands(block)]
    return out


def _commands(block: str) -> list[str]:
    lines = re.sub(r"\\\n\s*", " ", block).splitlines()
    return [line.strip() for line in lines if line.strip().startswith("robkin ")]


def readme_shell_lines() -> list[str]:
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```sh\n(.*?)```", text, flags=re.S)
    tour = next(b for b in blocks if "robkin convert" in b)
    return [line for line in re.sub(r"\\\n\s*", " ", tour).splitlines() if line.strip()]


def readme_python() -> str:
    text = (ROOT / "README.md").read_text()
    return next(b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "robkin.load" in b)


@pytest.fixture(scope="module")
def kit(tmp_path_factory):
    """Every file the examples name, made once from the bundled and the real robots."""
    tmp_path = tmp_path_factory.mktemp("kit")
    old = os.getcwd()
    try:
        yield _make_kit(tmp_path)
    finally:
        os.chdir(old)


@pytest.fixture
def workdir(kit, tmp_path, monkeypatch):
    """A fresh copy of the kit as the current folder (the examples write files)."""
    work = tmp_path / "work"
    shutil.copytree(kit, work, symlinks=True)
    monkeypatch.chdir(work)
    # the real robots' meshes are found as in a ROS workspace: an MJCF whose visuals would all be missing is
    # refused (it would render empty), and the examples write MJCF of the Panda copied here alone
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(Path(ROBOTS_DIR).parent.parent))
    return work


def _make_kit(tmp_path: Path) -> Path:
    for name, rel in REAL.items():
        src = os.path.join(ROBOTS_DIR, rel)
        if not os.path.isfile(src):
            pytest.skip(f"example-robot-data's {rel} is not installed")
        shutil.copy(src, tmp_path / name)
    for f in EXAMPLES_DIR.glob("*.yaml"):
        shutil.copy(f, tmp_path / f.name)
    (tmp_path / "src" / "robkin").mkdir(parents=True)
    (tmp_path / "src" / "robkin" / "examples").symlink_to(EXAMPLES_DIR)
    os.chdir(tmp_path)
    from robkin.io.documents.reader import document_from_robot, dump
    from robkin.io.urdf import urdf_from_robot

    rrpr = robkin.load(EXAMPLES_DIR / "rrpr.yaml")
    for name in ("robot.yaml", "a.yaml", "b.yaml", "original.yaml"):
        shutil.copy(EXAMPLES_DIR / "rrpr.yaml", name)
    Path("converted.yaml").write_text(dump(document_from_robot(rrpr, ("poe",))))
    for name in ("robot.urdf", "c.urdf"):
        Path(name).write_text(urdf_from_robot(rrpr))
    vendor = document_from_robot(rrpr, ("dh",))
    for row in vendor["dh"]["rows"]:
        row.update({k: round(v, 4) for k, v in row.items()})   # as a vendor prints it: 4 decimals
    Path("vendor_dh.yaml").write_text(dump(vendor))
    ur5 = robkin.load("ur5.urdf", tip_link="tool0")
    Path("ur5_dh.yaml").write_text(dump(document_from_robot(ur5, ("dh",))))
    Q = ur5.random_q(20, rng=0)
    Path("q.csv").write_text(",".join(j.name for j in ur5.joints) + "\n"
                             + "".join(",".join(repr(float(v)) for v in q) + "\n" for q in Q))
    assert main(["fk", "ur5.urdf", "--tip-link", "tool0", "--q-file", "q.csv", "-o", "targets.csv"]) == 0
    assert main(["convert", "ur5.urdf", "--base-link", "base", "--tip-link", "tool0", "--to", "dh", "--format",
                 "csv", "-o", "ur5_dh.csv"]) == 0
    Path("ur5_rows.txt").write_text("# UR5, Universal Robots' DH\n0 0.089159 pi/2 0\n-0.425 0 0 0\n"
                                    "-0.39225 0 0 0\n0 0.10915 pi/2 0\n0 0.09465 -pi/2 0\n0 0.0823 0 0\n")
    _measurements(ur5, rrpr)
    assert main(["estimate", "--pose", "-1,0.9,0.8,-3.08232,-1.04169,-3.01168", "--joints", "4", "--type",
                 "all", "-o", "estimates"]) == 0
    for k in "ABCD":
        shutil.copy(f"estimates/estimate_{k}.yaml", f"pose1_{k}.yaml")
    return tmp_path


def _measurements(ur5: robkin.Robot, rrpr: robkin.Robot) -> None:
    """The measurement files of the calibrate and check examples: the UR5 as its URDF says (so that check
    finds it the same robot), a UR5 with compliant joints and a 10 kg payload at every other pose, a
    perturbed Panda, and the RRPR robot probed in its own base frame with a
    marker 5 cm along the tool's z (--base-known --marker 0,0,0.05)."""
    from robkin.calibration import simulate, write_measurements_csv
    from robkin.calibration.simulation import perturbed

    sim = simulate(ur5, 60, offset=0.0, angle=0.0, seed=1)
    write_measurements_csv("measurements.csv", ur5, sim.q, sim.positions)
    loaded = simulate(ur5, 60, seed=4, stiffness=[3e4, 2e4, 1.5e4, 5e4, 6e4, 7e4], payload=[10.0, 0.0] * 30)
    write_measurements_csv("loaded.csv", ur5, loaded.q, loaded.positions, payloads=loaded.payloads)
    panda = robkin.load("panda.urdf", tip_link="panda_link8")
    sim = simulate(panda, 60, seed=2)
    write_measurements_csv("panda_poses.csv", panda, sim.q, sim.positions)
    rng = np.random.default_rng(3)
    real = perturbed(rrpr, rng.normal(0, 1e-3, (rrpr.n, 6)))
    Q = simulate(rrpr, 40, seed=3).q
    T = real.fk(Q) @ robkin.se3.trans(0, 0, 0.05)
    write_measurements_csv("probe.csv", rrpr, Q, T[:, :3, 3] + rng.normal(0, 20e-6, (40, 3)))


def _env(extra: dict[str, str]) -> dict[str, str]:
    env = dict(os.environ, **extra)
    env["PATH"] = os.path.dirname(sys.executable) + os.pathsep + env.get("PATH", "")
    # a 'python -c "import robkin ..."' line imports the robkin under test, from any folder
    package_parent = str(Path(robkin.__file__).resolve().parent.parent)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (package_parent, env.get("PYTHONPATH", "")) if p)
    return env


def _argv(line: str, env: dict[str, str]) -> list[str]:
    """The words bash makes of a command line in the current folder (variables expanded, comments
    dropped, file patterns such as ``pose*_?.yaml`` expanded as a reader's shell does)."""
    script = f'words=(\n{line}\n)\nprintf "%s\\0" "${{words[@]}}"'
    out = subprocess.run([BASH, "-c", script], env=_env(env), capture_output=True, text=True, check=True).stdout
    return out.split("\0")[:-1]


def run_example(line: str, env: dict[str, str]) -> None:
    """Run one printed command: 'robkin ...' in-process (exit status 0), anything else in bash."""
    command = line.split(" | ")[0]          # 'robkin demo | less': the pager is the user's business
    if command.split(maxsplit=1)[:1] != ["robkin"]:   # a shell line (redirections and all): bash runs it
        assignment = re.match(r"^([A-Za-z_]\w*)=", command)
        moves = command.startswith("cd ")
        script = (f"{command}\nprintf %s \"${assignment.group(1)}\"" if assignment else
                  f"set -e\n{command}\npwd" if moves else command)
        done = subprocess.run([BASH, "-c", script], env=_env(env), capture_output=True, text=True)
        assert done.returncode == 0, f"{line}\n{done.stderr}"
        if assignment:
            env[assignment.group(1)] = done.stdout
        if moves:
            os.chdir(done.stdout.strip())   # the workdir fixture's monkeypatch restores the folder
        return
    argv = _argv(command, env)
    if argv[1] == "gui":                    # serves until stopped: parse and load its input only
        args = build_parser().parse_args(argv[1:])
        if args.input:
            robkin.load(args.input, base_link=args.base_link, tip_link=args.tip_link)
        return
    assert main(argv[1:]) == 0, line


def test_every_help_example_runs(workdir, capsys):
    examples = help_examples()
    assert len(examples) >= 30 and any("--optimize" in e for e in examples)
    for example in examples:
        run_example(example.split(": ", 1)[1], {})
        capsys.readouterr()


def test_every_readme_command_runs(workdir, capsys):
    lines = [line for line in readme_shell_lines()
             if not line.startswith(("source ", "pip "))]   # the venv and the network: the user's setup
    assert sum(line.startswith("robkin ") for line in lines) >= 15
    before = sorted(p.name for p in workdir.iterdir())
    env: dict[str, str] = {"TMPDIR": str(workdir)}   # mktemp -d makes the tour's folder in the test's
    for line in lines:
        if line.startswith("#"):
            continue
        run_example(line, env)
        capsys.readouterr()
    tour = Path.cwd()
    # the tour worked in a folder of its own and left the one it started in as it was
    assert tour.parent == workdir and sorted(p.name for p in workdir.iterdir()) == sorted(before + [tour.name])
    assert sorted(p.name for p in Path("out").iterdir()) == ["3r.yaml", "rrpr.yaml", "scara.yaml"]
    # what the tour's comments promise: the MJCF folder carries its meshes, the calibrated URDF explains
    # the measurements (robkin check exited 0 above) where the nominal one does not
    assert Path("ur5_mjcf/ur5.xml").is_file() and any(Path("ur5_mjcf/meshes").glob("*.stl"))
    assert main(["check", "ur5.urdf", "measurements.csv", "--tip-link", "tool0"]) == 1


def test_readme_python_runs(workdir, capsys):
    code = readme_python()
    namespace: dict[str, object] = {}
    exec(compile(code, "README.md", "exec"), namespace)   # noqa: S102 - the README's own example
    out = capsys.readouterr().out
    # what the README's comments promise
    np.testing.assert_allclose(robkin.dh_from_robot(namespace["planar"]).rows, [[1, 0, 0, 0], [1, 0, 0, 0]],
                               atol=1e-15)
    assert "standard Denavit-Hartenberg table" in out and "verdict: different robots" in out
    # J's promised layout, (6, n) rows [v; w] at the tool origin in base axes, against central differences
    # of FK (J used to be compared with robot.jacobian(q) itself: a comparison that could not fail)
    robot, q, J = namespace["robot"], namespace["q"], namespace["J"]
    assert J.shape == (6, robot.n)
    h, R = 1e-6, robot.fk(q)[:3, :3]
    for i in range(robot.n):
        step = np.zeros(robot.n)
        step[i] = h
        dT = (robot.fk(q + step) - robot.fk(q - step)) / (2 * h)
        W = dT[:3, :3] @ R.T                               # skew(w)
        # truncation ~h^2 and rounding ~1e-16 / h ~ 1e-10 of a ~1 m robot
        np.testing.assert_allclose(J[:3, i], dT[:3, 3], atol=1e-8 * robot.scale)
        np.testing.assert_allclose(J[3:, i], [W[2, 1], W[0, 2], W[1, 0]], atol=1e-8)
    # the tool-frame Jacobian is the same twist in the tool's axes
    J_tool = namespace["J_tool"]
    np.testing.assert_allclose(J_tool[:3], R.T @ J[:3], atol=1e-12 * robot.scale)
    np.testing.assert_allclose(J_tool[3:], R.T @ J[3:], atol=1e-12)
    ur5, q6 = namespace["ur5"], namespace["q6"]
    # gravity torques are inverse dynamics at rest; a batch of mass matrices is symmetric
    np.testing.assert_allclose(namespace["g"], ur5.inverse_dynamics(q6, np.zeros(6), np.zeros(6)), rtol=1e-12)
    assert namespace["Mq"].shape == (1000, 6, 6)
    np.testing.assert_allclose(namespace["Mq"], namespace["Mq"].transpose(0, 2, 1), atol=1e-12)
    sol = namespace["sol"]
    assert len(sol.solutions) >= 1 and np.allclose(sol.solutions[:, 6], 0.4)
    np.testing.assert_allclose(namespace["panda"].fk(sol.solutions), np.broadcast_to(namespace["T"],
                               (len(sol.solutions), 4, 4)), atol=1e-9)
