// Self collision in the page: the status line under the view for the answer's `collision`
// (robkin.viz.collision_api: the links colliding with each other at the q shown, at the convex-parts
// level; viewer.js draws them red). While the server builds the robot's model (a few seconds, once
// per robot) the line says so and the page asks again; a robot without collision geometry is said
// once, in the line, and nothing turns red.
import { $ } from "./dom.js";

let retry = null;

// c: the answer's collision (null when not asked); again(): ask for the q shown once more.
export function showCollision(c, again) {
  const s = $("collision-status");
  const state = !c ? "off" : c.state === "ready" ? (c.collides ? "colliding" : "free") : c.state;
  document.body.dataset.collision = state;
  s.className = state;
  if (!c) { s.textContent = ""; return; }
  if (c.state === "building") {
    s.textContent = "self collision: building this robot's model…";
    if (!retry) retry = setTimeout(() => { retry = null; again(); }, 500);
  } else if (c.state === "none") {
    s.textContent = "self collision: not checked — " + c.message;
  } else {
    s.textContent = c.collides ? "self collision: " + c.pairs.map((p) => p.join(" / ")).join(", ")
                               : "self collision: none";
    s.title = "checked at the '" + c.level + "' level: conservative (a near miss of a few mm may count)";
  }
}
