"""The GUI's visual check in Chromium: differences exaggerated, arrows with the true distance, zoom to
the first difference, and a camera that follows a robot leaving the picture."""

from __future__ import annotations

import numpy as np

from test_gui import RRPR_TEXT, _settled, _updates, _wait_update, browser, page, server  # noqa: F401 (fixtures)

RRPR_6MM = RRPR_TEXT.replace("{a: 0.3, d: 0,", "{a: 0.306, d: 0,")


def _look_at(pg) -> np.ndarray:
    return np.array([float(v) for v in pg.get_attribute("#view", "data-look-at").split(",")])


def test_browser_differences_exaggerated_and_zoomed(page):
    pg = page
    before = _updates(pg)
    pg.click("#check-panel summary")
    pg.fill("#other-text", RRPR_6MM)
    _wait_update(pg, before)
    _settled(pg)
    pg.wait_for_selector("#check:not([hidden])")
    labels = [e.inner_text() for e in pg.query_selector_all(".label3d.differs")]
    assert "J4: 0.006" in labels and "tool: 0.006" in labels  # true distances, whatever the factor
    before = _updates(pg)
    pg.select_option("#exaggerate", "100")
    _wait_update(pg, before)
    _settled(pg)
    assert "differences ×100" in pg.inner_text("#check")
    assert "J4: 0.006" in [e.inner_text() for e in pg.query_selector_all(".label3d.differs")]
    # zoom: the camera looks at the middle of J4's arrow (A's J4 point and 100 x 6 mm further)
    pg.click("#zoom-first")
    target = _look_at(pg)
    from robkin.viz import gui_api

    res = gui_api.describe(RRPR_TEXT, "yaml", q=[0, 0, 0, 0], other={"text": RRPR_6MM, "fmt": "yaml",
                                                                     "exaggerate": 100})
    arrow = next(a for a in res["check"]["arrows"] if a["label"] == "J%d" % (res["check"]["first_joint"] + 1))
    np.testing.assert_allclose(target, (np.array(arrow["start"]) + arrow["end"]) / 2, atol=1e-5)


def test_browser_camera_follows_a_robot_that_leaves_the_view(page):
    pg = page
    pg.click("[data-view=fit]")
    follows = int(pg.get_attribute("#view", "data-follows") or 0)
    before = _updates(pg)
    pg.fill("#robot-text", RRPR_TEXT.replace("{a: 0.2, d: 0,   alpha: pi,", "{a: 3.0, d: 0,   alpha: pi,"))
    _wait_update(pg, before)
    _settled(pg)
    assert int(pg.get_attribute("#view", "data-follows") or 0) > follows
    x, y = map(float, pg.get_attribute("#view", "data-tool-xy").split(","))
    box = pg.query_selector("#view").bounding_box()
    assert 0 <= x <= box["width"] and 0 <= y <= box["height"]  # the tool (3 m out) is in the picture
