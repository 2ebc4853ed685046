// Self collision in the page: the status line under the view for the answer's `collision`
// (robkin.viz.collision_api: the links colliding with each other at the q shown, at the convex-parts
// level; viewer.js draws them red). While the server builds the robot's model (a few seconds, once
// per robot) the line says so and the page polls (CollisionPoll); a robot without collision geometry
// is said once, in the line, and nothing turns red.
import { $, count } from "./dom.js";

const EVERY = 500;  // ms between two asks while the model is being built

// c: the answer's collision (null when not asked): the line and data-collision (for tests).
export function showCollision(c) {
  const s = $("collision-status");
  const state = !c ? "off" : c.state === "ready" ? (c.collides ? "colliding" : "free") : c.state;
  document.body.dataset.collision = state;
  s.className = state;
  if (!c) { s.textContent = ""; return; }
  if (c.state === "building") {
    s.textContent = "self collision: building this robot's model…";
  } else if (c.state === "none") {
    s.textContent = "self collision: not checked — " + c.message;
  } else {
    s.textContent = c.collides ? "self collision: " + c.pairs.map((p) => p.join(" / ")).join(", ")
                               : "self collision: none";
    s.title = "checked at the '" + c.level + "' level: conservative (a near miss of a few mm may count)";
  }
}

// The poll while the model is being built: every 0.5 s the collision answer alone for the q shown
// (POST /api/collision), never a whole answer: nothing the user is doing is redrawn or reset, and
// data-updates (what tests wait for after a user action) does not move. Its answers are counted in
// data-collision-polls; one that comes back when the q it asked about is no longer the q shown (the
// user moved, another answer came) is dropped, counted in data-collision-stale.
//   post(path, body): the page's JSON POST;
//   current(): {body: the shown robot's request fields and q, still(): whether that is still what is
//            shown}, or null while another answer is on its way (it carries the collision state);
//   apply(c): draw a poll's collision answer for what is shown; error(message): say a failure.
export class CollisionPoll {
  constructor({ post, current, apply, error }) {
    Object.assign(this, { post, current, apply, error });
    this.timer = null;
    this.asking = false;  // one poll at a time
  }

  // An answer's collision `c` (null: not asked), shown: its line, and while its model is being built,
  // ask again in 0.5 s; else stop asking.
  show(c) {
    showCollision(c);
    clearTimeout(this.timer);
    this.timer = c && c.state === "building" ? setTimeout(() => this.ask(), EVERY) : null;
  }

  ask() {
    this.timer = null;
    const now = this.asking ? null : this.current();
    if (!now) { this.timer = setTimeout(() => this.ask(), EVERY); return; }  // busy: try again later
    this.asking = true;
    this.post("/api/collision", now.body)
      .then((res) => {
        if (!now.still()) { count("collisionStale"); return; }  // the answer shown since follows on its own
        if (!res.ok) { this.error(res.error); return; }
        count("collisionPolls");
        this.show(res.collision);
        this.apply(res.collision);
      })
      .catch((err) => this.error("connection to the robkin server failed: " + err))
      .finally(() => { this.asking = false; });
  }
}
