"""The GUI shows self collision and the workspace map (issue 35, items 3 and 4).

The answer of ``describe`` and ``ik`` with ``collision`` names the colliding link pairs at the q shown;
its verdict must be ``Robot.self_collision(q, level='parts')``'s (the library's own model of the same
file, built independently of the server's) and each named pair must touch for the exact mesh check
(coal) at the configurations used here. In the browser the Franka Panda, moved by its sliders into a
configuration folded onto itself (joint 4 at -3 rad: the wrist on the shoulder; coal says the meshes
touch), draws red pixels and names the pairs; Franka's "ready" pose draws none. The workspace checkbox
draws the server's reachable voxels as points and removes them.
"""

from __future__ import annotations

import io
import math

import numpy as np
import pytest

import robkin
from robkin.viz import collision_api, gui_api
from robkin.viz.gui import make_server
from test_gui import PANDA, RRPR_TEXT, _open, _serving, _settled, _shot, _updates, _wait_update, browser  # noqa: F401

CHAIN = {"base_link": "panda_link0", "tip_link": "panda_link8"}
READY = [0, -math.pi / 4, 0, -3 * math.pi / 4, 0, math.pi / 2, math.pi / 4]  # Franka's "ready" pose: free
FOLDED = [0, 0, 0, -3.0, 0, 0, 0]  # joint 4 folded: link 7 and the hand on link 1


@pytest.fixture(scope="module")
def panda():
    """The Panda (text, robot, the library's own self-collision model of the file)."""
    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    from robkin.self_collision import self_collision_model

    robot = robkin.load(str(PANDA), **CHAIN)
    return PANDA.read_text(), robot, self_collision_model(robot, str(PANDA))


def _answer(text: str, q, wait: float = 120.0) -> dict:
    """The server's collision answer at q, once its model is built (the first asks start the build)."""
    robot, _, _ = gui_api._robot(text, "urdf", CHAIN["base_link"], CHAIN["tip_link"])
    key = (text, "urdf", CHAIN["base_link"], CHAIN["tip_link"], False)
    return collision_api.collision_answer(robot, key, text, np.asarray(q, float), wait=wait)


def test_api_collision_answer_is_robot_self_collision(panda):
    text, robot, model = panda
    collision_api.register_source(text, PANDA)
    first = gui_api.describe(text, "urdf", READY, collision=True, **CHAIN)["collision"]
    assert first["state"] in ("building", "ready")  # answered at once, never waiting for the build
    assert _answer(text, READY)["state"] == "ready"
    Q = np.vstack([READY, FOLDED, robot.random_q(200, rng=7)])
    want = robot.self_collision(Q, level="parts")
    assert want[1] and not want[0] and 0 < want.sum() < len(Q)  # both verdicts occur
    for q, hit in zip(Q, want):
        got = gui_api.describe(text, "urdf", q.tolist(), collision=True, **CHAIN)["collision"]
        assert got["state"] == "ready" and got["level"] == "parts"
        assert got["collides"] == bool(hit), q
        assert got["links"] == sorted({n for p in got["pairs"] for n in p}, key=model.links.index)
    folded = _answer(text, FOLDED)
    assert ["panda_link1", "panda_link7"] in folded["pairs"]
    # the named pairs touch for the meshes (coal): the verdict is not only the conservative shapes'
    exact = robot.self_collision(np.array(FOLDED), level="exact")
    assert exact
    # the stick figure's segments drawn red: all joints revolute, so segment k (J_k to J_k+1; 0: base to
    # J1, 7: J7 to the tool) is the body moving with joint k: panda_link<k>, and 7 for the hand and fingers
    bodies = {int(n[-1]) if n.startswith("panda_link") else 7 for n in folded["links"]}
    assert folded["segments"] == sorted(bodies) and {1, 7} <= bodies
    # IK answers carry it too, at the q they answer with
    ik = gui_api.solve_ik(text, "urdf", robot.fk(np.array(FOLDED)).tolist(), FOLDED, collision=True, **CHAIN)
    assert ik["collision"]["collides"] == bool(robot.self_collision(np.array(ik["q"]), level="parts"))
    # not asked: not computed
    assert gui_api.describe(text, "urdf", READY, **CHAIN)["collision"] is None


def test_api_robot_without_collision_geometry_says_so():
    robot, _, _ = gui_api._robot(RRPR_TEXT, "auto")
    got = collision_api.collision_answer(robot, (RRPR_TEXT, "auto", None, None, False), RRPR_TEXT,
                                         robot.home(), wait=60.0)
    assert got["state"] == "none" and "collision geometry" in got["message"]


def test_pasted_robot_never_reads_mesh_files(panda):
    """A robot pasted in the page names its meshes itself: the server opens no path a request names, so
    its model cannot be built (the command-line robot's can: ``register_source``)."""
    text = panda[0].replace("<robot ", "<robot  ", 1)  # another text: not the registered one
    got = gui_api.describe(text, "urdf", READY, collision=True, **CHAIN)["collision"]
    got = got if got["state"] != "building" else _answer(text, READY)
    assert got["state"] == "none" and "mesh" in got["message"]


def _red_pixels(png: bytes) -> int:
    """Pixels of the view drawn in a red like the colliding links' (0xe02020 under the lights): strongly
    red, little green or blue (the tool frame's pink has much blue, the meshes are grey; the drag
    handle's x arrow is red too, the same at the same q)."""
    from PIL import Image

    a = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    r, g, b = a[..., 0], a[..., 1], a[..., 2]
    return int(np.count_nonzero((r > 120) & (r > 2.5 * g) & (r > 2.5 * b)))


def _set_q(pg, q) -> None:
    before = _updates(pg)
    pg.evaluate("""(q) => q.forEach((v, i) => { const s = document.getElementById('q' + i);
                                                s.value = String(v); s.dispatchEvent(new Event('input')); })""", q)
    _wait_update(pg, before)
    _settled(pg)


@pytest.fixture()
def panda_page(browser, panda):  # noqa: F811 - the imported fixture, used by name
    srv = make_server(port=0, text=panda[0], fmt="urdf", source=str(PANDA), **CHAIN)
    yield from _serving(browser, srv)


def test_browser_colliding_links_turn_red(panda_page, panda, tmp_path):
    pg, (_, robot, _) = panda_page, panda
    pg.wait_for_function("() => document.body.dataset.meshes == '11'", timeout=30000)
    _set_q(pg, READY)
    pg.wait_for_function("() => document.body.dataset.collision == 'free'", timeout=120000)  # model built
    view = pg.query_selector("#view")
    assert pg.inner_text("#collision-status") == "self collision: none"
    assert view.get_attribute("data-colliding") == ""
    free = _red_pixels(view.screenshot())  # the drag handle's red x arrow only

    _set_q(pg, FOLDED)
    pg.wait_for_function("() => document.body.dataset.collision == 'colliding'", timeout=30000)
    status = pg.inner_text("#collision-status")
    assert status.startswith("self collision: ") and "panda_link1 / panda_link7" in status
    red = view.get_attribute("data-colliding").split(",")
    assert {"panda_link1", "panda_link7"} <= set(red)
    assert int(view.get_attribute("data-colliding-meshes")) == len(red)  # one visual mesh per Panda link
    assert _red_pixels(view.screenshot()) > free + 2000  # whole links, not a few stray pixels
    _shot(pg, tmp_path, "gui_collision.png")

    _set_q(pg, READY)  # back to free: the links get their own colours again
    pg.wait_for_function("() => document.body.dataset.collision == 'free'", timeout=30000)
    assert view.get_attribute("data-colliding") == "" and _red_pixels(view.screenshot()) == free

    # unchecked: not asked, nothing said
    pg.click("#check-collision")
    pg.wait_for_function("() => document.body.dataset.collision == 'off'", timeout=30000)
    assert pg.inner_text("#collision-status") == ""


def test_browser_drag_keeps_the_verdict(panda_page, panda):
    """While the tool frame is dragged, each IK answer says whether the q it shows collides."""
    pg, (_, robot, _) = panda_page, panda
    _set_q(pg, READY)
    pg.wait_for_function("() => document.body.dataset.collision == 'free'", timeout=120000)
    view = pg.query_selector("#view")
    box = view.bounding_box()
    x, y = map(float, view.get_attribute("data-tool-xy").split(","))
    before = int(pg.get_attribute("body", "data-ik-updates") or 0)
    pg.mouse.move(box["x"] + x, box["y"] + y)
    pg.mouse.down()
    pg.mouse.move(box["x"] + x - 30, box["y"] + y + 20, steps=10)
    pg.mouse.up()
    pg.wait_for_function("(n) => Number(document.body.dataset.ikUpdates) > n", arg=before, timeout=30000)
    _settled(pg)
    q = [float(pg.input_value(f"#q{i}")) for i in range(7)]
    want = "colliding" if robot.self_collision(np.array(q), level="parts") else "free"
    pg.wait_for_function("(w) => document.body.dataset.collision == w", arg=want, timeout=30000)


def test_browser_robot_without_collision_geometry(browser):  # noqa: F811
    srv = make_server(port=0, text=RRPR_TEXT, fmt="yaml")
    srv.serve_in_thread()
    try:
        for pg in _open(browser, srv.url):
            pg.wait_for_function("() => document.body.dataset.collision == 'none'", timeout=30000)
            assert "collision geometry" in pg.inner_text("#collision-status")
            assert pg.query_selector("#view").get_attribute("data-colliding") == ""
    finally:
        srv.shutdown()
        srv.server_close()


def test_browser_workspace_overlay_draws_and_hides(panda_page, tmp_path):
    """Checked: the points drawn are the server's reachable voxels (as many as its map has) and change the
    picture; unchecked: gone, the picture as before."""
    from PIL import Image

    from robkin.viz.workspace_api import workspace_overlay

    pg = panda_page
    pg.wait_for_function("() => document.body.dataset.meshes == '11'", timeout=30000)
    _settled(pg)
    view = pg.query_selector("#view")
    pixels = lambda: np.asarray(Image.open(io.BytesIO(view.screenshot())).convert("RGB")).astype(int)  # noqa: E731
    before = pixels()
    pg.click("#show-workspace")
    pg.wait_for_function("() => Number(document.body.dataset.workspace) > 0", timeout=120000)
    n = int(pg.get_attribute("body", "data-workspace"))  # points in the drawn geometry
    want = workspace_overlay(PANDA.read_text(), "urdf", **CHAIN)  # the server's map (the same, cached)
    assert n == len(want["points"]) > 100 and f"workspace: {n} voxels" in pg.inner_text("#workspace-status")
    shown = pixels()
    assert np.count_nonzero(np.any(shown != before, axis=2)) > 5000  # a cloud around the arm, not a speck
    _shot(pg, tmp_path, "gui_workspace.png")
    pg.click("#show-workspace")
    pg.wait_for_function("() => document.body.dataset.workspace == '0'", timeout=30000)
    assert pg.inner_text("#workspace-status") == ""
    assert np.count_nonzero(np.any(pixels() != before, axis=2)) == 0


def test_only_the_robot_asked_for_last_is_built():
    """Typing asks for a model per edit: builds run one at a time, and one whose robot is no longer the
    latest asked for is skipped (built anew if asked again), not answered as unavailable."""
    texts = [RRPR_TEXT.replace("name: rrpr", f"name: rrpr-{k}") for k in "cd"]  # two robots not asked before
    assert texts[0] != texts[1]
    robots = [gui_api._robot(t, "auto")[0] for t in texts]
    keys = [(t, "auto", None, None, False) for t in texts]
    with collision_api._building:  # a build in progress: both requests wait behind it
        first = [collision_api.collision_answer(r, k, t, r.home()) for r, k, t in zip(robots, keys, texts)]
        assert [a["state"] for a in first] == ["building", "building"]
        stale = collision_api._BUILDS[keys[0]]
    assert stale.done.wait(60) and stale.superseded and stale.model is None and stale.error is None
    again = collision_api.collision_answer(robots[0], keys[0], texts[0], robots[0].home(), wait=60.0)
    assert again["state"] == "none" and "collision geometry" in again["message"]  # built anew, answered
