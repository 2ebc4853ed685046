"""Hostile inputs and output folders: each refused with one line on stderr naming the path or field
and exit status 2 (or neutralised in the output), and nothing written outside the output folder.

9. a ``meshes`` symbolic link already in the output folder (or a link above it) leading outside;
10. a symbolic link inside a ``package://`` folder leading out of the package (used, said in one line);
11. CSV cells starting with ``= + - @``, tab or CR (spreadsheet formulas), read back as written;
12. HTML and Markdown link markup in Markdown table cells;
13. ``<!--<script>`` in a name embedded as JSON in an HTML page.
"""

from __future__ import annotations

import json
import os
import warnings
from html.parser import HTMLParser
from pathlib import Path

import pytest

import robkin
from robkin.cli import main

STL = b"solid x\nendsolid x\n"


def _urdf(mesh: str, name: str = "r", joint: str = "j0") -> str:
    return (f'<robot name="{name}"><link name="base"/><link name="l0"><visual><geometry>'
            f'<mesh filename="{mesh}"/></geometry></visual></link>'
            f'<joint name="{joint}" type="revolute"><parent link="base"/><child link="l0"/>'
            f'<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
            f'</joint></robot>')


def _exit(argv):
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


def _tree(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


# ---- 9: a symbolic link in the output folder leading outside it ----------------------------------------

@pytest.mark.parametrize("to, ext", [("mjcf", "xml"), ("urdf", "urdf")])
@pytest.mark.parametrize("layout", ["meshes-link", "parent-link", "dangling-link"])
def test_mesh_copies_never_follow_a_link_out_of_the_output_folder(tmp_path, capsys, to, ext, layout):
    src = tmp_path / "src"
    src.mkdir()
    (src / "link.stl").write_bytes(STL)
    (src / "r.urdf").write_text(_urdf("link.stl"))
    victim = tmp_path / "victim"
    victim.mkdir()
    (victim / "link.stl").write_bytes(b"precious")
    out = tmp_path / "out"
    out.mkdir()
    if layout == "meshes-link":
        (out / "meshes").symlink_to(victim)
    elif layout == "dangling-link":
        (out / "meshes").symlink_to(tmp_path / "nowhere")
    else:  # OUT/meshes is a real folder below OUT/sub, a link leading out
        (out / "sub").symlink_to(victim)
    target = out / f"robot.{ext}"
    if layout == "parent-link":  # a mesh folder OUT/sub/meshes, named through the link OUT/sub
        from robkin.io.meshes.files import copy_meshes, resolve_meshes
        robot = robkin.load(src / "r.urdf")
        with pytest.raises(robkin.errors.InputError, match="sub: a symbolic link .* leading outside"):
            copy_meshes(resolve_meshes(robot, src / "r.urdf"), out, "sub/meshes")
    else:
        assert _exit(["convert", str(src / "r.urdf"), "--to", to, "-o", str(target)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "meshes: a symbolic link" in err[0] and "outside the output folder" in err[0]
        assert "Traceback" not in err[0]
        assert not target.exists()
    assert _tree(victim) == {"link.stl": b"precious"}  # nothing written through the link
    assert not (tmp_path / "nowhere").exists()


def test_a_link_inside_the_output_folder_leading_inside_it_is_fine(tmp_path, capsys):
    src = tmp_path / "src"
    src.mkdir()
    (src / "link.stl").write_bytes(STL)
    (src / "r.urdf").write_text(_urdf("link.stl"))
    out = tmp_path / "out"
    (out / "real_meshes").mkdir(parents=True)
    (out / "meshes").symlink_to(out / "real_meshes")
    assert _exit(["convert", str(src / "r.urdf"), "--to", "mjcf", "-o", str(out / "robot.xml")]) == 0
    assert (out / "real_meshes" / "link.stl").read_bytes() == STL
