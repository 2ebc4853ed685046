"""The GUI's answers arriving out of turn (issue 35, item 4): neither race can show a wrong robot.

1. While the server builds a robot's self-collision model, the page asks again every 0.5 s. Those polls
   ask for the collision answer alone (``POST /api/collision``) of the q shown: they change only the
   status line and the red links, never count as an update (``data-updates``, which tests wait for
   after a user action), and one answered after the user moved on is dropped. Shown with the build
   held back (``collision_api._building`` taken by the test), so the model is "building" for as long as
   the test needs, and with the poll's request held by the browser (``page.route``) until the user has
   moved: its answer, that the arm collides at the q it asked about, must not be drawn at the new q.
2. An IK answer of a drag that lands after the user clicked an IK branch must not undo the click: the
   drag's IK request is held (``page.route``) until after the click, then let through.

The robot of the first test is three boxes on revolute z axes (hand-checkable): link 1 and link 3 lie
in the plane z = 0.1, link 2 above them (z = 0.2). At q = 0 the arm is stretched (link 3 from x = 1.0
to 1.5): free. At q = (0, 2.9, 2.9) link 2 folds back to (0.015, 0.120) and link 3 turns to -0.48 rad,
its axis crossing y = 0 at x = 0.24, over link 1 (x in 0..0.5) in the same plane: they collide.
"""

from __future__ import annotations

import numpy as np
import pytest

from robkin.errors import InputError
from robkin.viz import collision_api, gui_api
from robkin.viz.gui import make_server
from test_gui import ERD, _open, _post, _settled, _updates, _wait_update, browser, ur5_server  # noqa: F401

_BOX = '<collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.08 0.08"/></geometry></collision>'
_LIMIT = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'


def _boxes(name: str) -> str:
    """The three-box arm of the module doc, named ``name`` (a robot not asked for before: built anew)."""
    joints = [("j1", "base", "l1", "0 0 0.1"), ("j2", "l1", "l2", "0.5 0 0.1"), ("j3", "l2", "l3", "0.5 0 -0.1")]
    return (f'<robot name="{name}"><link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry>'
            f'</collision></link>' + "".join(f'<link name="l{k}">{_BOX}</link>' for k in (1, 2, 3)) +
            "".join(f'<joint name="{j}" type="revolute"><parent link="{p}"/><child link="{c}"/><origin xyz="{o}"/>'
                    f'<axis xyz="0 0 1"/>{_LIMIT}</joint>' for j, p, c, o in joints) + "</robot>")


FREE = [0.0, 0.0, 0.0]
FOLDED = [0.0, 2.9, 2.9]


def _built(text: str) -> None:
    """Wait (in the test process, where the server runs) for the model of ``text`` to be built."""
    builds = [b for k, b in list(collision_api._BUILDS.items()) if k[0] == text]
    assert builds and builds[0].done.wait(120)


def test_api_collision_is_describes_answer_alone():
    text = _boxes("boxes-api")
    robot, _, _ = gui_api._robot(text, "urdf")
    collision_api.collision_answer(robot, (text, "urdf", None, None, False), text, robot.home(), wait=120.0)
    for q, hit in ((FREE, False), (FOLDED, True)):
        got = gui_api.collision_at(text, "urdf", q)
        assert got["q"] == q
        assert got["collision"] == gui_api.describe(text, "urdf", q, collision=True)["collision"]
        assert got["collision"]["state"] == "ready" and got["collision"]["collides"] is hit
    assert gui_api.collision_at(text, "urdf", FOLDED)["collision"]["pairs"] == [["l1", "l3"]]
    with pytest.raises(InputError, match="q: expected 3 numbers"):  # the q shown: no lenient home
        gui_api.collision_at(text, "urdf", [0, 0])
    srv = make_server(port=0, text=text, fmt="urdf")
    srv.serve_in_thread()
    try:
        res = _post(srv.url + "api/collision", {"text": text, "fmt": "urdf", "q": FOLDED})
        assert res["ok"] is True and res["collision"]["pairs"] == [["l1", "l3"]]
        bad = _post(srv.url + "api/collision", {"text": text, "fmt": "urdf", "q": "folded"})
        assert bad["ok"] is False and "q: expected 3 numbers" in bad["error"]
    finally:
        srv.shutdown()
        srv.server_close()


def _set_q(pg, q) -> None:
    """Set every slider, then one input event: one request, one update."""
    before = _updates(pg)
    pg.evaluate("""(q) => { q.forEach((v, i) => { document.getElementById('q' + i).value = String(v); });
                            document.getElementById('q0').dispatchEvent(new Event('input')); }""", q)
    _wait_update(pg, before)
    _settled(pg)


def _data(pg, name: str) -> int:
    return int(pg.get_attribute("body", f"data-{name}") or 0)


def _until(pg, check, what: str) -> None:
    """Let the page run (and the browser call route handlers) until ``check()`` holds."""
    for _ in range(600):  # 30 s of 50 ms turns: generous for a loaded machine
        if check():
            return
        pg.wait_for_timeout(50)
    raise AssertionError(f"waited 30 s for {what}")


def test_browser_collision_polls_are_not_updates_and_stale_ones_are_dropped(browser):  # noqa: F811
    text = _boxes("boxes-poll")
    srv = make_server(port=0, text=text, fmt="urdf")
    srv.serve_in_thread()
    collision_api._building.acquire()  # every model build waits: the page sees "building" until released
    released = False
    try:
        for pg in _open(browser, srv.url):
            assert pg.get_attribute("body", "data-collision") == "building"
            updates = _updates(pg)
            pg.wait_for_function("() => Number(document.body.dataset.collisionPolls) >= 3", timeout=30000)
            assert _updates(pg) == updates  # three answers came, none of them an update

            # a user action while the model builds: exactly one update, however many polls around it
            _set_q(pg, FOLDED)
            assert _updates(pg) == updates + 1
            polls = _data(pg, "collision-polls")
            pg.wait_for_function("(n) => Number(document.body.dataset.collisionPolls) >= n + 2", arg=polls,
                                 timeout=30000)
            assert _updates(pg) == updates + 1 and pg.get_attribute("body", "data-collision") == "building"

            # a poll asked at FOLDED, answered after the user moved back to FREE: not drawn
            held = []
            pg.route("**/api/collision", lambda route: held.append(route))
            _until(pg, lambda: held, "a poll")
            assert held[0].request.post_data_json["q"] == FOLDED
            _set_q(pg, FREE)
            collision_api._building.release()
            released = True
            _built(text)
            held[0].continue_()  # the server answers: colliding (at FOLDED)
            pg.wait_for_function("() => document.body.dataset.collisionStale == '1'", timeout=30000)
            assert pg.get_attribute("body", "data-collision") == "building"  # FREE's answer said so; not replaced
            assert pg.get_attribute("#view", "data-colliding") in (None, "")
            assert pg.inner_text("#collision-status") == "self collision: building this robot's model…"
            polls = _data(pg, "collision-polls")
            _until(pg, lambda: len(held) == 2, "the next poll")  # asked for the q shown now
            assert held[1].request.post_data_json["q"] == FREE
            held[1].continue_()
            pg.wait_for_function("() => document.body.dataset.collision == 'free'", timeout=30000)
            pg.unroute("**/api/collision")
            assert len(held) == 2  # the model is built: no more polls
            assert _data(pg, "collision-polls") == polls + 1 and _updates(pg) == updates + 2
            assert pg.inner_text("#collision-status") == "self collision: none"

            # once built, sliders are answered directly: FOLDED collides, link 1 and link 3 red, no poll
            _set_q(pg, FOLDED)
            assert pg.get_attribute("body", "data-collision") == "colliding"
            assert pg.get_attribute("#view", "data-colliding") == "l1,l3"
            assert _data(pg, "collision-polls") == polls + 1
    finally:
        if not released:
            collision_api._building.release()
        srv.shutdown()
        srv.server_close()


def _drag(pg) -> None:
    """Drag the tool frame by a few pixels (the page asks for IK on each move)."""
    view = pg.query_selector("#view")
    box = view.bounding_box()
    x, y = map(float, view.get_attribute("data-tool-xy").split(","))
    pg.mouse.move(box["x"] + x, box["y"] + y)
    pg.mouse.down()
    pg.mouse.move(box["x"] + x - 10, box["y"] + y + 8, steps=5)
    pg.mouse.up()


def test_browser_late_ik_answer_does_not_undo_a_branch_click(browser):  # noqa: F811
    """UR5 (closed form, 8 branches): a drag's IK answer held until after a branch click, then let
    through, leaves the robot on the branch clicked."""
    srv = ur5_server()
    try:
        for pg in _open(browser, srv.url):
            _set_q(pg, [0.3, -1.2, 1.4, -0.8, 1.1, 0.5])
            before = _updates(pg)
            _drag(pg)
            _wait_update(pg, before)  # the page asks for the robot once the drag's last IK answer is in
            _settled(pg)
            buttons = pg.query_selector_all("#branches button")
            assert len(buttons) == 8
            current = [b.inner_text() for b in buttons if "current" in (b.get_attribute("class") or "")]
            assert len(current) == 1

            held = []  # every IK request of the drag; the first is held, the others go through

            def hold_first(route) -> None:
                held.append(route)
                if len(held) > 1:
                    route.continue_()

            pg.route("**/api/ik", hold_first)
            ik_updates = _data(pg, "ik-updates")
            _drag(pg)
            _until(pg, lambda: held, "the drag's IK request")
            pick = "3" if current != ["3"] else "5"
            target = next(b for b in pg.query_selector_all("#branches button") if b.inner_text() == pick)
            before = _updates(pg)
            target.click()
            _wait_update(pg, before)
            # the button's title lists its solution with 10 significant digits: 1e-8 rad covers that rounding
            chosen = [float(v) for v in target.get_attribute("title").split(", ")]
            q = [float(pg.input_value(f"#q{i}")) for i in range(6)]
            np.testing.assert_allclose(q, chosen, atol=1e-8)
            before = _updates(pg)
            held[0].continue_()  # the late answer: seeded with the q before the click
            _wait_update(pg, before)  # the drag's end asks for the robot once no IK answer is awaited
            _settled(pg)
            q = [float(pg.input_value(f"#q{i}")) for i in range(6)]
            np.testing.assert_allclose(q, chosen, atol=1e-8)
            assert [b.inner_text() for b in pg.query_selector_all("#branches button.current")] == [pick]
            assert _data(pg, "ik-stale") == 1 and _data(pg, "ik-updates") == ik_updates
            assert len(held) == 1  # the drag's waiting target was dropped with the click: not asked after it
            pg.unroute("**/api/ik")
    finally:
        srv.shutdown()
        srv.server_close()


def test_browser_late_describe_answer_does_not_undo_a_drag(browser):  # noqa: F811
    """UR5: a robot description asked for (a slider moved) and held until a drag's IK answer is shown is
    dropped when it arrives (it would draw the robot at the q before the drag), with no update counted;
    the drag's end asks again for the q IK left, and that answer is the one update."""
    import json

    srv = ur5_server()
    try:
        for pg in _open(browser, srv.url):
            _set_q(pg, [0.3, -1.2, 1.4, -0.8, 1.1, 0.5])
            held = []  # the first description asked for is held, the others go through

            def hold_first(route) -> None:
                held.append(route)
                if len(held) > 1:
                    route.continue_()

            pg.route("**/api/describe", hold_first)
            pg.evaluate("""() => { const s = document.getElementById('q0'); s.value = String(Number(s.value) + 0.05);
                                   s.dispatchEvent(new Event('input')); }""")
            _until(pg, lambda: held, "the slider's description request")
            ik_updates = _data(pg, "ik-updates")
            _drag(pg)
            _until(pg, lambda: _data(pg, "ik-updates") > ik_updates, "the drag's IK answer")
            before = _updates(pg)
            held[0].continue_()  # the late description: the q from before the drag
            _until(pg, lambda: len(held) > 1, "the drag's end to ask again")  # queued behind the held one
            _settled(pg)
            assert _data(pg, "describe-stale") == 1 and _updates(pg) == before + 1
            asked = json.loads(held[1].request.post_data)["q"]
            q = [float(pg.input_value(f"#q{i}")) for i in range(6)]
            np.testing.assert_allclose(q, asked, atol=1e-12)
            assert abs(asked[0] - json.loads(held[0].request.post_data)["q"][0]) > 1e-6  # IK moved joint 1
            pg.unroute("**/api/describe")
    finally:
        srv.shutdown()
        srv.server_close()
