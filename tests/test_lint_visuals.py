"""robkin lint's checks of visual meshes: missing, unreadable, above the face budget, in millimetres; and the
COLLADA summary (triangle count, box through the scene's node transforms) against trimesh's full parse."""

from __future__ import annotations

import glob
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from robkin.lint import lint_file

from lint_files import arm, line_of, write

ROBOTS = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                 "example-robot-data", "robots")) or [""])[0]


def _with_visual(mesh: str) -> str:
    """The sound arm with a visual mesh on link2 (beside its collision box)."""
    return arm().replace('<collision><origin xyz="0 0 0.15"/><geometry><box size="0.08 0.08 0.3"/>',
                         f'<visual><geometry><mesh filename="{mesh}"/></geometry></visual>\n    '
                         '<collision><origin xyz="0 0 0.15"/><geometry><box size="0.08 0.08 0.3"/>')


def _hit(path, text, code, severity):
    hits = [f for f in lint_file(path) if f.code == code]
    assert hits, code
    assert (hits[0].severity, hits[0].line, hits[0].element) == (severity, line_of(text, "<visual>"), "link 'link2'")
    assert "visual mesh" in hits[0].message and hits[0].fix
    return hits[0]


def test_visual_mesh_sound(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    trimesh.creation.box(extents=(0.08, 0.08, 0.3)).export(str(tmp_path / "l2.stl"))
    assert lint_file(write(tmp_path, _with_visual("l2.stl"))) == []


def test_visual_mesh_missing(tmp_path):
    text = _with_visual("gone.dae")
    _hit(write(tmp_path, text), text, "mesh-missing", "error")


def test_visual_mesh_unreadable(tmp_path):
    (tmp_path / "bad.dae").write_text("<COLLADA><library_geometries>")
    text = _with_visual("bad.dae")
    _hit(write(tmp_path, text), text, "mesh-unreadable", "warning")


def test_visual_mesh_in_millimetres(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    trimesh.creation.box(extents=(80.0, 80.0, 300.0)).export(str(tmp_path / "l2.stl"))
    text = _with_visual("l2.stl")
    f = _hit(write(tmp_path, text), text, "mesh-unit", "warning")
    assert 'scale="0.001 0.001 0.001"' in f.fix
    # the same mesh with its scale given: nothing to say
    text = text.replace('filename="l2.stl"/>', 'filename="l2.stl" scale="0.001 0.001 0.001"/>')
    assert lint_file(write(tmp_path, text)) == []


def test_visual_mesh_face_budget(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    trimesh.creation.icosphere(subdivisions=3, radius=0.05).export(str(tmp_path / "l2.stl"))  # 1280 triangles
    text = _with_visual("l2.stl")
    path = write(tmp_path, text)
    hits = [f for f in lint_file(path, max_faces=1000) if f.code == "mesh-faces"]
    assert hits and "1280 triangles" in hits[0].message and hits[0].line == line_of(text, "<visual>")
    assert not [f for f in lint_file(path, max_faces=2000) if f.code == "mesh-faces"]


@pytest.mark.skipif(not ROBOTS, reason="example-robot-data is not installed")
@pytest.mark.parametrize("mesh", ["anymal_b_simple_description/meshes/base/anymal_base.dae",   # mm, node-scaled
                                  "panda_description/meshes/visual/link0.dae",
                                  "ur_description/meshes/ur5/visual/base.dae"])
def test_collada_summary_is_trimeshs(mesh):
    trimesh = pytest.importorskip("trimesh")
    pytest.importorskip("collada")
    from robkin.lint.mesh_summary import dae_summary

    s = dae_summary(Path(ROBOTS) / mesh)
    m = trimesh.load(str(Path(ROBOTS) / mesh), force="mesh")
    assert s.faces == len(m.faces)
    # trimesh's bounds are of the transformed vertices; ours of the transformed boxes: equal for
    # axis-aligned node transforms (these files), to float32 text rounding (1e-6 m)
    assert np.allclose(s.lo, m.bounds[0], atol=1e-6) and np.allclose(s.hi, m.bounds[1], atol=1e-6)


def test_zero_size_primitive(tmp_path):
    # pybullet_data's Laikago has visual spheres of radius 0: MuJoCo refuses them once written as geoms
    text = arm(l2_geometry='<sphere radius="0"/>')
    hits = [f for f in lint_file(write(tmp_path, text)) if f.code == "geom-size"]
    assert hits and hits[0].severity == "error" and hits[0].element == "link 'link2'"
    assert hits[0].line == line_of(text, 'radius="0"') and "MuJoCo refuses" in hits[0].message
    visual = _with_visual("x.stl").replace('<mesh filename="x.stl"/>', '<box size="0.1 0 0.1"/>')
    hits = [f for f in lint_file(write(tmp_path, visual)) if f.code == "geom-size"]
    assert hits and hits[0].severity == "warning" and hits[0].line == line_of(visual, "<visual>")


def test_inertia_without_mass(tmp_path):
    # pybullet_data's Panda: panda_link8 and panda_grasptarget have mass 0 and inertia 0.1 * identity
    text = arm(extra='<link name="ghost"><inertial><mass value="0"/><inertia ixx="0.1" iyy="0.1" izz="0.1" '
                     'ixy="0" ixz="0" iyz="0"/></inertial></link>\n'
                     '<joint name="g" type="fixed"><parent link="tool"/><child link="ghost"/></joint>')
    hits = [f for f in lint_file(write(tmp_path, text)) if f.code == "inertia-without-mass"]
    assert hits and hits[0].severity == "warning" and hits[0].element == "link 'ghost'"
    assert hits[0].line == line_of(text, '<link name="ghost">')
