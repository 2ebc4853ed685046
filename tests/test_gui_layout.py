"""The GUI at 1400x900 and 1920x1080 hides nothing (issue 32, item 8), in headless Chromium.

No table is cut at its panel's right edge (every panel and table container: scrollWidth <= clientWidth),
in compare mode the verdict and the per-joint table are on screen without scrolling, the first picture
shows the whole robot (nothing drawn touches the view's edge), slider tracks start at the same x on
every row, the Example list names the example shown, and the IK branch clicked is the one highlighted.
The screenshots of the docs' gallery are taken here (``ROBKIN_UPDATE_DOCS=1``).
"""

from __future__ import annotations

import io

import numpy as np
import pytest

from robkin.viz.gui import make_server
from test_gui import (ERD, PANDA, RRPR_TEXT, _open, _settled, _shot, _updates, _wait_update, ur5_server,  # noqa: F401
                      browser, page, server)
from test_gui_check import heavy  # noqa: F401  (the Panda with a heavier link 4)

SIZES = [(1400, 900), (1920, 1080)]

#: Every panel, table and table container whose content is wider than its box (cut, or scrolled sideways),
#: and every table cell whose text is wider than the cell. Text boxes (the robot text, the URDF listing)
#: scroll by design and are not counted.
_OVERFLOW = """() => {
  const out = [];
  const boxes = document.querySelectorAll("main > section, table, .wide, .mass-tables, .matrices, #check, details");
  for (const e of boxes) {
    if (e.offsetParent === null) continue;  // not shown
    if (e.scrollWidth > e.clientWidth + 1)  // 1 px: sub-pixel rounding of the layout
      out.push(`${e.tagName}#${e.id}.${e.className}: ${e.scrollWidth} > ${e.clientWidth}`);
  }
  for (const sec of document.querySelectorAll("main > section")) {
    const right = sec.getBoundingClientRect().right + 1;
    for (const t of sec.querySelectorAll("table")) {
      const r = t.getBoundingClientRect();
      if (r.width && r.right > right) out.push(`table#${t.id} ends ${r.right - right} px past ${sec.id}`);
    }
  }
  for (const c of document.querySelectorAll("td, th"))
    if (c.offsetParent !== null && c.scrollWidth > c.clientWidth + 1) out.push(`cell '${c.textContent}' cut`);
  return out;
}"""


def _server(**kwargs):
    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    srv = make_server(port=0, text=PANDA.read_text(), fmt="urdf", base_link="panda_link0", tip_link="panda_link8",
                      source=str(PANDA), **kwargs)
    srv.serve_in_thread()
    return srv


def _sized_page(browser, url, size):  # noqa: F811
    for pg in _open(browser, url):
        pg.set_viewport_size({"width": size[0], "height": size[1]})
        pg.reload()
        pg.wait_for_selector("body[data-state=ready]", timeout=15000)
        pg.wait_for_function("() => document.body.dataset.meshes == '11'", timeout=30000)
        _settled(pg)
        pg.wait_for_timeout(300)  # a layout pass and a frame after the meshes are placed
        yield pg


@pytest.mark.parametrize("size", SIZES, ids=["1400x900", "1920x1080"])
def test_browser_no_table_overflows_its_panel(browser, size, tmp_path):  # noqa: F811
    srv = _server()
    try:
        for pg in _sized_page(browser, srv.url, size):
            assert pg.evaluate("() => document.documentElement.scrollWidth - window.innerWidth") <= 0
            assert pg.evaluate(_OVERFLOW) == []
            # the DH table's theta column and the inertia columns are there, whole
            assert pg.inner_text("#table-dh tr:first-child th:last-child") == "θ"
            assert pg.query_selector("#products-dh tr:first-child th:last-child").inner_text() == "Ixz (kg m²)"
            _shot(pg, tmp_path, f"gui_{size[0]}x{size[1]}.png")
    finally:
        srv.shutdown()
        srv.server_close()


@pytest.mark.parametrize("size", SIZES, ids=["1400x900", "1920x1080"])
def test_browser_compare_verdict_and_table_above_the_fold(browser, heavy, size, tmp_path):  # noqa: F811
    srv = _server(other={"text": heavy.read_text(), "fmt": "urdf", "source": str(heavy),
                         "base_link": "panda_link0", "tip_link": "panda_link8"})
    try:
        for pg in _sized_page(browser, srv.url, size):
            pg.wait_for_selector("#check:not([hidden])")
            assert pg.evaluate("() => window.scrollY") == 0
            for sel in ("#check-verdict", "#check-first", "#check-joints"):
                box = pg.query_selector(sel).bounding_box()
                assert box["y"] >= 0 and box["y"] + box["height"] <= size[1], f"{sel} is below the fold: {box}"
            assert len(pg.query_selector_all("#check-joints tr")) == 1 + 7
            assert pg.evaluate(_OVERFLOW) == []  # the detail column included: wrapped, not cut
            _shot(pg, tmp_path, f"gui_check_{size[0]}x{size[1]}.png")
    finally:
        srv.shutdown()
        srv.server_close()


def _robot_pixels_on_edge(png: bytes, inset: int = 2) -> int:
    """Pixels of the robot (dark or coloured: links, axes, frames, labels, the meshes' dark parts) in the
    outer ring of the view's picture; the grid (light grey) and the white background do not count."""
    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    ring = np.concatenate([img[inset:inset + 3].reshape(-1, 3), img[-inset - 3:-inset].reshape(-1, 3),
                           img[:, inset:inset + 3].reshape(-1, 3), img[:, -inset - 3:-inset].reshape(-1, 3)])
    # the grid's lines are grey 200-228 (viewer.js); 150 and 60 leave room for antialiasing
    dark = ring.min(axis=1) < 150
    coloured = ring.max(axis=1) - ring.min(axis=1) > 60
    return int(np.count_nonzero(dark | coloured))


@pytest.mark.parametrize("size", SIZES, ids=["1400x900", "1920x1080"])
def test_browser_first_picture_shows_the_whole_panda(browser, size):  # noqa: F811
    srv = _server()
    try:
        for pg in _sized_page(browser, srv.url, size):
            view = pg.query_selector("#view")
            assert _robot_pixels_on_edge(view.screenshot()) == 0  # the Panda's top (J5..J7, tool) not cut
            x, y = map(float, view.get_attribute("data-tool-xy").split(","))
            box = view.bounding_box()
            assert 0.05 * box["height"] < y < 0.95 * box["height"] and 0 < x < box["width"]
    finally:
        srv.shutdown()
        srv.server_close()


#: Three joints whose names differ in length: each slider's track must still start at the same x.
NAMES_URDF = """<robot name="names">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="a_rather_long_elbow_joint_name" type="revolute"><parent link="b"/><child link="c"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="w" type="prismatic"><parent link="c"/><child link="d"/><origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="1" velocity="1"/></joint>
</robot>"""


def test_browser_slider_tracks_start_at_the_same_x(page):
    pg = page
    pg.set_viewport_size({"width": 1400, "height": 900})
    for text, fmt, n in ((RRPR_TEXT, "auto", 4), (NAMES_URDF, "urdf", 3)):
        before = _updates(pg)
        pg.select_option("#format", fmt)
        pg.fill("#robot-text", text)
        _wait_update(pg, before)
        _settled(pg)
        boxes = [pg.query_selector(f"#q{i}").bounding_box() for i in range(n)]
        xs, widths = [b["x"] for b in boxes], [b["width"] for b in boxes]
        assert max(xs) - min(xs) < 0.5 and max(widths) - min(widths) < 0.5, (xs, widths)
        names = pg.query_selector_all("#sliders .jname")
        assert all(e.bounding_box()["x"] + e.bounding_box()["width"] <= min(xs) for e in names)  # no overlap


def test_browser_example_list_names_the_example_shown(page):
    """The server fixture starts with the bundled RRPR example's text: the list says 'rrpr', not '—'."""
    pg = page
    assert pg.input_value("#example") == "rrpr"
    before = _updates(pg)
    pg.select_option("#example", "arbitrary_3r")
    _wait_update(pg, before)
    assert pg.input_value("#example") == "arbitrary_3r"
    before = _updates(pg)
    pg.fill("#robot-text", pg.input_value("#robot-text").replace("name:", "name: edited_", 1))
    _wait_update(pg, before)
    assert pg.input_value("#example") == ""  # an edited example is no longer the example


def test_browser_ik_branch_clicked_is_highlighted(browser, tmp_path):  # noqa: F811
    """UR5 (closed form, 8 branches): after a drag lists them, clicking a branch moves the robot to that
    solution and the highlight with it."""
    srv = ur5_server()
    try:
        for pg in _open(browser, srv.url):
            before = _updates(pg)
            pg.evaluate("""(q) => q.forEach((v, i) => { const s = document.getElementById('q' + i);
                                                        s.value = String(v); s.dispatchEvent(new Event('input')); })""",
                        [0.3, -1.2, 1.4, -0.8, 1.1, 0.5])
            _wait_update(pg, before)
            _settled(pg)
            view = pg.query_selector("#view")
            box = view.bounding_box()
            x, y = map(float, view.get_attribute("data-tool-xy").split(","))
            before = _updates(pg)
            pg.mouse.move(box["x"] + x, box["y"] + y)
            pg.mouse.down()
            pg.mouse.move(box["x"] + x - 10, box["y"] + y + 8, steps=5)
            pg.mouse.up()
            _wait_update(pg, before)  # the page asks for the robot once the drag's last IK answer is in
            _settled(pg)
            assert pg.is_visible("#branches")
            buttons = pg.query_selector_all("#branches button")
            assert len(buttons) == 8
            current = [b.inner_text() for b in buttons if "current" in (b.get_attribute("class") or "")]
            assert len(current) == 1
            pick = "3" if current != ["3"] else "5"
            target = next(b for b in buttons if b.inner_text() == pick)
            before = _updates(pg)
            target.click()
            _wait_update(pg, before)
            _settled(pg)
            now = [b.inner_text() for b in pg.query_selector_all("#branches button.current")]
            assert now == [pick]
            q = [float(pg.input_value(f"#q{i}")) for i in range(6)]
            # the button's title lists its solution with 10 significant digits: 1e-8 rad covers that rounding
            np.testing.assert_allclose(q, [float(v) for v in target.get_attribute("title").split(", ")], atol=1e-8)
    finally:
        srv.shutdown()
        srv.server_close()
