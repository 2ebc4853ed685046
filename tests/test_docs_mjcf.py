"""docs/mjcf.md runs as printed (issue 32, item 9): its commands and its Python, in a folder holding the
UR5 and Panda URDFs copied alone (no ROS workspace: ``package://`` meshes are found only through the
``--package-path`` / ``package_paths`` the page gives), and ``write_mjcf`` makes its folder as
``robkin convert -o`` does.

The page's first command once had no ``--package-path``: its meshes could not be found. The Python
example wrote into a folder that did not exist (the command line makes it, ``write_mjcf`` raised).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from test_examples import ROOT, kit, run_example, workdir  # noqa: F401 - the fixtures, shared

import robkin

pytest.importorskip("trimesh")      # the URDFs' COLLADA meshes are converted for MuJoCo
DOC = ROOT / "docs" / "mjcf.md"


def _blocks(kind: str, doc: Path = DOC) -> list[str]:
    return re.findall(rf"```{kind}\n(.*?)```", doc.read_text(), flags=re.S)


@pytest.fixture
def bare(workdir, monkeypatch):
    """The kit's folder with no package search path: meshes come only from what the page passes."""
    for name in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        monkeypatch.delenv(name, raising=False)
    return workdir


def test_mjcf_page_commands_run_as_printed(bare, capsys):
    lines = [line for line in _blocks("sh")[0].splitlines() if line.strip() and not line.startswith("#")]
    assert sum(line.startswith("robkin convert") for line in lines) == 3
    env: dict[str, str] = {}
    for line in lines:
        if line.startswith("python -m mujoco.viewer"):   # an interactive window
            continue
        run_example(line, env)
    capsys.readouterr()
    # the meshes came along: the models are not empty
    for model in ("panda_mjcf/panda.xml", "ur5/ur5.xml"):
        folder = Path(model).parent
        assert any((folder / "meshes").glob("*.stl")), model
        assert '<geom class="visual"' in Path(model).read_text()
    assert Path("ur5/scene.xml").is_file() and Path("robot.xml").is_file()


def test_mjcf_page_python_runs_as_printed(bare):
    code = next(b for b in _blocks("python") if "write_mjcf" in b)
    assert not Path("panda_mjcf").exists()     # the example makes the folder
    namespace: dict[str, object] = {}
    exec(compile(code, str(DOC), "exec"), namespace)   # noqa: S102 - the page's own example
    text = Path("panda_mjcf/panda.xml").read_text()
    assert '<geom class="visual"' in text and any(Path("panda_mjcf/meshes").glob("*.stl"))
    assert "<mujoco" in namespace["text"]


def test_write_mjcf_makes_its_folder_and_removes_it_on_failure(bare):
    from robkin.errors import InputError
    from robkin.io.mjcf.files import write_mjcf

    rrpr = robkin.load("rrpr.yaml")
    assert write_mjcf(rrpr, "new/rrpr.xml") == Path("new/rrpr.xml") and Path("new/rrpr.xml").is_file()
    with pytest.raises(InputError):                 # only inside an existing folder, as the CLI
        write_mjcf(rrpr, "no/such/rrpr.xml")
    assert not Path("no").exists()
    # the Panda's meshes not found: refused (the model would render empty), and the folder made is gone
    panda = robkin.load("panda.urdf", tip_link="panda_hand_tcp")
    with pytest.warns(UserWarning, match=r"package_paths=\{'example-robot-data': DIR\}"), \
            pytest.raises(InputError, match="render empty"):
        write_mjcf(panda, "panda_out/panda.xml", source="panda.urdf")
    assert not Path("panda_out").exists()


def test_simulation_page_first_command_runs_as_printed(bare, capsys):
    """docs/simulation.md opens with the same Panda conversion (it had no --package-path either)."""
    block = _blocks("sh", ROOT / "docs" / "simulation.md")[0]
    env: dict[str, str] = {}
    for line in block.splitlines():
        if line.strip() and not line.startswith(("#", "python -m mujoco.viewer")):
            run_example(line, env)
    capsys.readouterr()
    assert any(Path("panda_mjcf/meshes").glob("*.stl")) and Path("panda_mjcf/scene.xml").is_file()
