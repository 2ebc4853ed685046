"""The GUI's workspace overlay: ``robkin.viz.workspace_api`` (the answer of ``POST /api/workspace``) and
its page module ``static/workspace_overlay.js``."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

import robkin
from robkin.errors import InputError
from robkin.examples import EXAMPLES_DIR
from robkin.viz.workspace_api import ORIENTATIONS, workspace_overlay
from robkin.workspace import reachability_map

IIWA = (EXAMPLES_DIR / "iiwa14.yaml").read_text()


def test_overlay_lists_the_maps_reachable_voxels():
    res = workspace_overlay(IIWA, "auto", voxel=0.1, samples=50_000)
    robot = robkin.load(EXAMPLES_DIR / "iiwa14.yaml")
    wmap = reachability_map(robot, 0.1, ORIENTATIONS, samples=50_000, seed=0, threads=1)
    idx = np.argwhere(wmap.reachable > 0)
    assert np.allclose(res["points"], wmap.origin + 0.1 * (idx + 0.5), rtol=0, atol=1e-12)
    assert res["counts"] == wmap.reachable[tuple(idx.T)].tolist()
    assert 1 <= min(res["counts"]) and max(res["counts"]) <= ORIENTATIONS
    # every point is where the arm reaches: within the iiwa's 1.18 m reach of the shoulder (0.36 m up)
    # plus half a voxel diagonal
    d = np.linalg.norm(np.array(res["points"]) - [0, 0, 0.36], axis=1)
    assert d.max() < 0.42 + 0.4 + 0.126 + 0.1 * np.sqrt(3) / 2 + 1e-9


def test_overlay_default_voxel_and_bad_requests():
    res = workspace_overlay(IIWA, samples=20_000)
    robot = robkin.load(EXAMPLES_DIR / "iiwa14.yaml")
    assert res["voxel"] == pytest.approx(robot.scale / 15) and res["samples"] == 20_000
    for bad in ({"voxel": 0.0}, {"voxel": "0.1"}, {"voxel": True}):
        with pytest.raises(InputError, match="voxel"):
            workspace_overlay(IIWA, **bad)
    for bad in ({"samples": 0}, {"samples": 10 ** 9}, {"samples": 1.5}):
        with pytest.raises(InputError, match="samples"):
            workspace_overlay(IIWA, **bad)


def test_overlay_module_is_served_and_parses():
    from robkin.viz.assets import STATIC_DIR
    from robkin.viz.http_policy import static_file

    f = static_file(STATIC_DIR, "workspace_overlay.js")
    assert f is not None and "export class WorkspaceOverlay" in f.read_text()
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the module's syntax is not checked")
    done = subprocess.run([node, "--check", str(f)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
