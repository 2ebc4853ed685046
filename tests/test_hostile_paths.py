"""Hostile inputs and output folders: each refused with one line on stderr naming the path or field
and exit status 2 (or neutralised in the output), and nothing written outside the output folder.

9. a ``meshes`` symbolic link already in the output folder (or a link above it) leading outside;
10. a symbolic link inside a ``package://`` folder leading out of the package (used, said in one line);
11. CSV cells starting with ``= + - @``, tab or CR (spreadsheet formulas), read back as written;
12. HTML and Markdown link markup in Markdown table cells;
13. ``<!--<script>`` in a name embedded as JSON in an HTML page.
"""

from __future__ import annotations

import dataclasses
import json
import struct
import warnings
from html.parser import HTMLParser
from pathlib import Path

import pytest

import robkin
from robkin.cli import main
from robkin.examples import EXAMPLES_DIR

#: a small binary STL (a tetrahedron: the four vertices MuJoCo needs; it reads binary STL only, and the
#: MJCF writer leaves out a mesh MuJoCo would refuse)
_TETRA = ((0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1))
STL = b"\0" * 80 + struct.pack("<I", 4) + b"".join(
    struct.pack("<12fH", 0, 0, 1, *_TETRA[a], *_TETRA[b], *_TETRA[c], 0)
    for a, b, c in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)))


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


# ---- 10: a symbolic link inside a package leading out of it -----------------------------------------------

def test_a_link_out_of_a_package_is_said_in_the_warning_line(tmp_path, monkeypatch, capsys):
    """package://pkg/meshes/x.stl that is a link to a file outside pkg: used (as a file outside the
    model's folder is, and as colcon --symlink-install needs), and named in the one warning line."""
    from robkin.io.meshes.files import resolve_mesh_file, resolve_meshes

    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        monkeypatch.delenv(var, raising=False)
    pkg = tmp_path / "ws" / "pkg"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "meshes" / "in.stl").write_bytes(STL)
    secret = tmp_path / "home" / "secret.stl"
    secret.parent.mkdir()
    secret.write_bytes(STL)
    (pkg / "meshes" / "out.stl").symlink_to(secret)
    (pkg / "meshes" / "passwd.stl").symlink_to("/etc/passwd")
    robot_file = pkg / "urdf" / "r.urdf"
    inside = resolve_mesh_file("package://pkg/meshes/in.stl", robot_file)
    out = resolve_mesh_file("package://pkg/meshes/out.stl", robot_file)
    assert inside.path is not None and not inside.leaves_package
    assert out.path == secret.resolve() and out.leaves_package
    assert "not a mesh file" in resolve_mesh_file("package://pkg/meshes/passwd.stl", robot_file).reason
    robot_file.write_text(_urdf("package://pkg/meshes/out.stl"))
    robot = robkin.load(robot_file)
    with pytest.warns(UserWarning) as caught:
        resolve_meshes(robot, robot_file)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "1 mesh file(s) outside the model's folder or their package are used: " \
        "package://pkg/meshes/out.stl" in lines[0]
    # a linked package folder (colcon --symlink-install links share/pkg) is the folder it leads to: no warning
    (tmp_path / "share").mkdir()
    (tmp_path / "share" / "pkg").symlink_to(pkg)
    linked = resolve_mesh_file("package://pkg/meshes/in.stl", tmp_path / "r.urdf", {"pkg": tmp_path / "share" / "pkg"})
    assert linked.path == (pkg / "meshes" / "in.stl").resolve() and not linked.leaves_package
    robot_file.write_text(_urdf("package://pkg/meshes/in.stl"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        resolve_meshes(robkin.load(robot_file), robot_file)
    # the command line: the one line on stderr, and the copy made inside the output folder
    robot_file.write_text(_urdf("package://pkg/meshes/out.stl"))
    dest = tmp_path / "dest"
    dest.mkdir()
    assert _exit(["convert", str(robot_file), "--to", "mjcf", "-o", str(dest / "r.xml")]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if "mesh file" in line]
    assert len(err) == 1 and "outside the model's folder or their package" in err[0]
    assert (dest / "meshes" / "secret.stl").read_bytes() == STL


# ---- 11, 12: names in CSV and Markdown tables -----------------------------------------------------------

FORMULAS = ["=HYPERLINK(\"http://evil.example\",\"x\")", "+1+1", "-2+3", "@SUM(A1)", "=cmd|' /C calc'!A0",
            "'=quoted", "''+twice", "-1.5", "'plain", "ok_name"]


def _chain_urdf(names: list[str], robot: str = "r") -> str:
    from xml.sax.saxutils import quoteattr

    links = ['<link name="base"/>'] + [f'<link name="l{k}"/>' for k in range(len(names))]
    joints = [f'<joint name={quoteattr(n)} type="revolute"><parent link="{"base" if k == 0 else f"l{k - 1}"}"/>'
              f'<child link="l{k}"/><origin xyz="0 0 0.1" rpy="-0.3 0 0"/><axis xyz="0 0 1"/>'
              f'<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>' for k, n in enumerate(names)]
    return f'<robot name={quoteattr(robot)}>{"".join(links)}{"".join(joints)}</robot>'


def test_csv_text_cells_never_start_a_formula_and_read_back(tmp_path):
    import csv

    from robkin.io.tables.reader import read_table_file

    (tmp_path / "r.urdf").write_text(_chain_urdf(FORMULAS))
    out = tmp_path / "r.csv"
    assert _exit(["convert", str(tmp_path / "r.urdf"), "--to", "dh", "--format", "csv", "-o", str(out)]) == 0
    rows = list(csv.reader(out.read_text().splitlines()))
    names = [r[1] for r in rows[1:len(FORMULAS) + 1]]
    for cell in (c for r in rows for c in r[:3]):  # the text cells: no formula start
        assert not cell.startswith(("=", "+", "-", "@", "\t", "\r")), cell
    assert names[0] == "'" + FORMULAS[0] and names[5] == "''=quoted" and names[7] == "'-1.5"
    assert names[8] == "'plain" and names[9] == "ok_name"  # nothing to neutralise: as it was
    numbers = [c for r in rows[1:len(FORMULAS) + 1] for c in r[3:]]
    assert any(c.startswith("-") for c in numbers)  # negative numbers stay numbers (no quote)
    assert not any(c.startswith("'") for c in numbers)
    back = read_table_file(out, "dh")
    assert [j.name for j in back.joints] == FORMULAS  # the round trip gives the names themselves


def test_csv_cells_escape_and_unescape_are_inverse():
    from robkin.io.tables.cells import csv_read_cell, csv_text_cell

    for s in FORMULAS + ["", "'", "''", "\tx", "\rx", "'\t", "a=b", "=", "@"]:
        assert csv_read_cell(csv_text_cell(s)) == s, s
        assert not csv_text_cell(s).startswith(("=", "+", "-", "@", "\t", "\r"))


MARKUP = ["<img src=x onerror=alert(1)>", "<script>alert(1)</script>", "[x](javascript:alert(1))",
          "![i](http://evil.example/t.png)", "*em* _u_ `code` ~~s~~ a|b", "<!--c-->", "&lt;amp", "shoulder_pan"]


def test_batch_and_measurement_csv_files_hold_no_formula_and_read_back(tmp_path):
    """The other two CSV writers (batch results of fk/ik, calibration measurements) quote a joint name or
    a text cell that would start a formula, leave numbers alone, and their readers get the names back."""
    import numpy as np

    from robkin.calibration.measurements import read_measurements, write_measurements_csv
    from robkin.io.batch_files import csv_text, read_rows

    text = csv_text(["=j1", "+j2", "error"], [[-1.5, 2.0, "-cmd|' /C calc'!A0"], [0.25, -0.0, "ok"]])
    lines = text.splitlines()
    assert lines[0] == "'=j1,'+j2,error"
    assert lines[1].startswith("-1.5,2,") and "'-cmd" in lines[1]  # the number stays a number
    path = tmp_path / "q.csv"
    path.write_text(text)
    rows = read_rows(str(path))
    assert rows.columns == ["=j1", "+j2", "error"] and rows.values[0, 0] == -1.5

    robot = robkin.load(str(EXAMPLES_DIR / "rrpr.yaml"))
    named = robot.replace(joints=tuple(dataclasses.replace(j, name=name)
                                       for name, j in zip(("=a", "@b", "-c", "d"), robot.joints)))
    q = np.zeros((3, named.n))
    out = tmp_path / "meas.csv"
    write_measurements_csv(out, named, q, np.ones((3, 3)))
    assert out.read_text().splitlines()[0].startswith("'=a,'@b,'-c,d,x,y,z")
    assert np.array_equal(read_measurements(out, named).q, q)


def test_markdown_text_cells_hold_no_html_or_link_markup(tmp_path):
    (tmp_path / "r.urdf").write_text(_chain_urdf(MARKUP, robot="<b>bot</b>"))
    out = (tmp_path / "r").with_suffix(".md")
    assert _exit(["convert", str(tmp_path / "r.urdf"), "--to", "dh", "--format", "markdown", "-o", str(out)]) == 0
    text = out.read_text()
    assert "<" not in text and ">" not in text.replace("->", "")  # no tag, no comment
    assert "](" not in text.replace("\\](", "") and "[x]" not in text  # no link, no image
    assert "&lt;img src=x onerror=alert(1)&gt;" in text and "&lt;script&gt;" in text
    assert "\\[x\\](javascript:alert(1))" in text and "!\\[i\\]" in text
    assert "\\*em\\* \\_u\\_ \\`code\\` \\~\\~s\\~\\~ a\\|b" in text
    assert "&amp;lt;amp" in text and "| shoulder_pan |" in text  # an entity stays text; a word stays a word
    assert text.startswith("**&lt;b&gt;bot&lt;/b&gt;: ")
    # rendered, each cell is its own text (markdown-it, when installed, renders CommonMark + tables)
    mdit = pytest.importorskip("markdown_it")
    html = mdit.MarkdownIt("commonmark").enable("table").render(text)
    assert "<img" not in html and "<script" not in html and "<a " not in html and "<em>" not in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html and "[x](javascript:alert(1))" in html


# ---- 13: names in the JSON a page embeds ----------------------------------------------------------------

def _script_end(page: str, start: int) -> int:
    """Where a <script> element's text starting at ``start`` ends, as the HTML tokenizer finds it
    (script data, escaped and double-escaped states: after "<!--", a "<script" hides the next "</script>")."""
    low, i, state = page.lower(), start, "data"

    def tag(at: int, name: str) -> bool:
        j = at + len(name)
        return low.startswith(name, at) and j < len(low) and low[j] in " \t\n\f/>"

    while i < len(low):
        if state != "double" and tag(i, "</script"):
            return i
        if state == "data" and low.startswith("<!--", i):
            state, i = "escaped", i + 4
            continue
        if state != "data" and low.startswith("-->", i):
            state, i = "data", i + 3
            continue
        if state == "escaped" and tag(i, "<script"):
            state, i = "double", i + 7
            continue
        if state == "double" and tag(i, "</script"):
            state, i = "escaped", i + 8
            continue
        i += 1
    return -1


def _strings(x):
    if isinstance(x, str):
        yield x
    elif isinstance(x, dict):
        for k, v in x.items():
            yield k
            yield from _strings(v)
    elif isinstance(x, list):
        for v in x:
            yield from _strings(v)


@pytest.mark.parametrize("name", ["<!--<script>", "x</script><script>alert(1)</script>", "<!--<script>-->&amp;"])
def test_a_name_cannot_break_the_pages_embedded_json(tmp_path, name):
    (tmp_path / "r.urdf").write_text(_chain_urdf([name + "j", "j2"], robot=name))
    out = tmp_path / "page.html"
    assert _exit(["plot", str(tmp_path / "r.urdf"), "-o", str(out)]) == 0
    page = out.read_text()
    opening = '<script type="application/json" id="robkin-data">'
    start = page.index(opening) + len(opening)
    end = _script_end(page, start)
    assert page.startswith("</script>", end)
    data = json.loads(page[start:end])  # the page loads: the whole JSON, and nothing after it, is the data
    found = set(_strings(data))
    assert name + "j" in found and name in " ".join(found)
    # every module script after it is still its own element
    rest = page[end + len("</script>"):]
    assert rest.count('<script type="text/x-robkin-module"') == page.count('<script type="text/x-robkin-module"')

    class Scripts(HTMLParser):
        def __init__(self):
            super().__init__()
            self.inside, self.texts = False, []

        def handle_starttag(self, tag, attrs):
            self.inside = dict(attrs).get("id") == "robkin-data"

        def handle_data(self, text):
            if self.inside:
                self.texts.append(text)

        def handle_endtag(self, tag):
            self.inside = False

    parser = Scripts()
    parser.feed(page)
    assert json.loads("".join(parser.texts)) == data
