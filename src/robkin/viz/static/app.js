// robkin GUI. The server does all kinematics (POST /api/describe, /api/ik); this module shows what it
// answers: the 3D view (viewer.js, three.js), joint sliders, the tool pose, a table per representation
// (rounded for display, full precision on hover and in copies), downloads (POST /api/export), the
// tool-frame gizmo driving IK, and the visual check against a second robot.
import { Viewer, overlayLegend } from "./viewer.js";
import { loadVisuals } from "./meshes.js";
import { $, el, num, display, count } from "./dom.js";
import { representationSections, showPose } from "./tables.js";
import { checkContents, zoomToFirstDifference } from "./check.js";
import { CollisionPoll } from "./collision.js";
import { WorkspaceOverlay } from "./workspace_overlay.js";

const state = {
  robot: null,          // last good answer of /api/describe
  jointKey: "",         // joints' names/types/limits: sliders are rebuilt when it changes
  tablesKey: null,      // input (and angle unit) the tables were drawn for
  asked: null,          // the request of the robot shown (its text, fmt, chain, tool row)
  inflight: false, pending: null,
  qSeq: 0,              // user actions that set q (sliders, branch buttons, home, edits): IK answers asked before are stale
  ik: { inflight: false, pending: null, count: 0, since: 0, applied: 0 },  // applied: IK answers shown
  start: null,          // /api/start: the command-line robot and its visuals
  reps: null,           // /api/representations: the tables, overlays and downloads to offer
  meshKey: null,        // whether the visuals are shown (only for the command-line robot, unedited)
};
let viewer = null, workspace = null, poll = null;

// ------------------------------------------------------------------ talking to the server
async function post(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "Content-Type": "application/json" },
                                body: JSON.stringify(body) });
  return r.json();
}

function isUrdf() {
  const f = $("format").value;
  return ["urdf", "mjcf", "sdf"].includes(f) || (f === "auto" && $("robot-text").value.trimStart().startsWith("<"));
}

function inputs() {
  const urdf = isUrdf(), rows = ["dh-rows", "mdh-rows"].includes($("format").value);
  return { text: $("robot-text").value, fmt: $("format").value, base_link: urdf ? $("base-link").value : "",
           tip_link: urdf ? $("tip-link").value : "", tool_row: rows && $("last-row").value === "tool" };
}

function otherInputs() {
  const text = $("other-text").value, given = state.start && state.start.other;
  if (!text.trim()) return null;
  // robot B from the command line keeps its URDF chain (the same links as A's) while unedited
  const chain = given && text === given.text ? { base_link: given.base_link, tip_link: given.tip_link } : {};
  return { text, fmt: $("other-format").value, exaggerate: Number($("exaggerate").value), ...chain };
}

function overlayList() {
  return Array.from(document.querySelectorAll("#overlay input:checked")).map((c) => c.value);
}

function currentQ() {
  return Array.from(document.querySelectorAll("#sliders input[type=range]")).map((s) => parseFloat(s.value));
}

// Ask for the robot at q; while a request is in flight only the latest wish is kept. The sliders'
// q may belong to the robot before an edit changed its joint count: then the server answers at home
// (strict_q false) instead of with an error.
function refresh() {
  const body = { ...inputs(), q: state.robot ? currentQ() : null, strict_q: false, overlay: overlayList(),
                 other: otherInputs(), collision: $("check-collision").checked };
  if (state.inflight) { state.pending = body; return; }
  send(body);
}

function send(body) {
  state.inflight = true;
  document.body.dataset.state = "busy";
  const ik = state.ik.applied;
  post("/api/describe", body)
    // an IK answer shown since this was asked (a drag began): its q is older; the drag's end asks again
    .then((res) => { if (ik !== state.ik.applied) count("describeStale"); else apply(res, body); })
    .catch((err) => showError("connection to the robkin server failed: " + err))
    .finally(() => {
      state.inflight = false;
      if (state.pending) { const next = state.pending; state.pending = null; send(next); }
    });
}

// ------------------------------------------------------------------ IK from the gizmo
// Each drag event asks for IK seeded with the q shown; while one is in flight only the latest target
// waits, so the robot follows at the rate the server answers (counted in data-ik-rate).
function dragged(T) {
  if (!state.robot) return;
  $("view").dataset.target = JSON.stringify(T);
  const body = { ...inputs(), target: T, q0: currentQ(), collision: $("check-collision").checked };
  if (!$("arm-angle").hidden && $("arm-angle-hold").checked) body.arm_angle = armAngle();
  if (state.ik.inflight) { state.ik.pending = body; return; }
  sendIK(body);
}

function sendIK(body) {
  state.ik.inflight = true;
  if (!state.ik.since) state.ik.since = performance.now();
  const seq = state.qSeq;
  post("/api/ik", { ...body, q0: currentQ() })
    .then((res) => {
      if (seq !== state.qSeq) { count("ikStale"); return; }  // the user set q since: that q stays (data-ik-stale)
      if (!res.ok) { showError(res.error); return; }
      state.ik.count += 1;
      state.ik.applied += 1;
      const secs = (performance.now() - state.ik.since) / 1000;
      if (secs > 0) document.body.dataset.ikRate = (state.ik.count / secs).toFixed(1);
      setQ(res.q);
      showIK(res);
      showArmAngle(res);
      const scene = res.scene;
      state.robot = { ...state.robot, q: res.q, T: res.T, rpy_xyz: res.rpy_xyz, scene, motions: res.motions,
                      overlays: [], check: null, collision: res.collision };
      state.asked = body;
      poll.show(res.collision);
      viewer.show(state.robot, { keepTarget: true });
      showPose(state.robot);
      count("ikUpdates");
    })
    .catch((err) => showError("connection to the robkin server failed: " + err))
    .finally(() => {
      state.ik.inflight = false;
      if (state.ik.pending) { const next = state.ik.pending; state.ik.pending = null; sendIK(next); }
    });
}

// SRS arms: the elbow's swivel about the shoulder-wrist line (arm angle). Moving the slider solves for
// the tool pose shown at that arm angle, on the branch shown; "hold" keeps the arm angle while dragging.
function armAngle() { return Number($("arm-angle-slider").value) * Math.PI / 180; }

function showArmAngle(res) {
  $("arm-angle").hidden = !res.srs;
  if (!res.srs) return;
  const ok = res.arm_angle !== null && res.arm_angle !== undefined;
  if (ok && document.activeElement !== $("arm-angle-slider")) $("arm-angle-slider").value = (res.arm_angle * 180 / Math.PI).toFixed(1);
  $("arm-angle-value").textContent = ok ? (res.arm_angle * 180 / Math.PI).toFixed(1) + "\u00b0" : "undefined (stretched elbow)";
}

function swivel() {
  if (!state.robot) return;
  const body = { ...inputs(), target: state.robot.T, q0: currentQ(), arm_angle: armAngle(),
                 collision: $("check-collision").checked };
  if (state.ik.inflight) { state.ik.pending = body; return; }
  sendIK(body);
}

function dragEnded() {
  state.ik.since = 0;
  state.ik.count = 0;
  const settle = () => (state.ik.inflight || state.ik.pending ? setTimeout(settle, 20) : refresh());
  settle();
}

function showIK(res) {
  const s = $("ik-status"), names = state.robot.joints.map((j) => j.name);
  const limits = res.at_limit.map((i) => names[i]);
  document.querySelectorAll("#sliders .slider").forEach((d, i) => d.classList.toggle("limit", res.at_limit.includes(i)));
  s.className = !res.success ? "bad" : limits.length ? "limit" : "";
  s.textContent = !res.found ? (res.method === "srs-arm-angle" && res.message ? "no configuration: " + res.message :
                                "target out of reach: no configuration puts the tool there") :
    !res.success ? "target out of reach (closest: " + num(res.position_error) + " away, " +
                   num(res.orientation_error) + " rad turned)" +
                   (limits.length ? "; against the limit of " + limits.join(", ") : "") :
    limits.length ? "reached, against the limit of " + limits.join(", ") : "reached (" + res.method + " IK)";
  document.body.dataset.ikSuccess = String(res.success);
  showBranches(res.solutions);
}

// Several closed-form solutions: one button per branch; choosing one moves the robot there and the
// next drags stay on it (IK is seeded with the q shown).
function showBranches(solutions) {
  const box = $("branches");
  box.hidden = solutions.length < 2;
  if (box.hidden) { box.replaceChildren(); return; }
  const q = currentQ();
  const dist = (s) => Math.max(...s.map((v, i) => Math.abs(v - q[i])));
  const buttons = solutions.map((sol, k) => {
    const b = el("button", { type: "button", text: String(k + 1), title: sol.map((v) => num(v)).join(", ") });
    if (dist(sol) < 1e-9) b.className = "current";  // the solution shown (1e-9: same numbers, rounding only)
    b.addEventListener("click", () => {  // the robot moves there, and so does the highlight
      buttons.forEach((o) => o.classList.toggle("current", o === b));
      setQ(sol);
      qSet();
      refresh();
    });
    return b;
  });
  box.replaceChildren("IK branches:", ...buttons);
}

// ------------------------------------------------------------------ applying an answer
function apply(res, body) {
  if (!res.ok) { showError(res.error); return; }
  $("error").hidden = true;
  $("error").textContent = "";
  const w = $("warnings");
  w.hidden = !res.warnings.length;
  w.textContent = res.warnings.length ? "Input adjusted:\n" + res.warnings.join("\n") : "";
  showLinks(res.links, body);
  const key = JSON.stringify(res.joints);
  const changed = key !== state.jointKey;
  if (changed) {
    state.jointKey = key;
    buildSliders(res);
    // a q outside a joint's limits (the server starts at Robot.home, inside them): the slider sits on the limit; show the robot there
    if (currentQ().some((v, i) => v !== res.q[i])) { refresh(); return; }
  }
  state.robot = res;
  state.asked = body;
  display.scale = res.scale;
  $("robot-name").textContent = (res.name || "robot") + " — " + res.n + " joints";
  viewer.show(res);
  if (changed) viewer.view("fit");
  $("grid-unit").textContent = "grid: " + num(Number($("view").dataset.gridCell)) + " per cell";
  showPose(res);
  showArmAngle(res);
  showAgreement(res);
  showCheck(res);
  poll.show(res.collision);
  const tkey = [body.text, body.fmt, body.base_link, body.tip_link, body.tool_row, $("units").value].join("\u0000");
  if (state.tablesKey !== tkey) {
    state.tablesKey = tkey;
    showTables(res);
    if ($("show-workspace").checked) showWorkspace();  // the map of the robot now shown
  }
  showMeshes(body);
  document.body.dataset.state = "ready";
  count("updates");
}

// The user set q (a slider, a branch button, home) or edited the robot: IK answers asked for before
// are stale (one landing late would undo it), and a drag's waiting target is dropped.
function qSet() {
  state.qSeq += 1;
  state.ik.pending = null;
}

function showError(message) {
  const e = $("error");
  e.textContent = message;
  e.hidden = false;
  document.body.dataset.state = "error";
}

// URDF: base and tip link chosen from the file's links; a choice that is not among them (given on
// the command line for a format without a link list) stays selectable.
function showLinks(links, body) {
  for (const [id, chosen] of [["base-link", body.base_link], ["tip-link", body.tip_link]]) {
    const sel = $(id), names = Array.from(sel.options).slice(1).map((o) => o.value);
    const wanted = chosen && !links.includes(chosen) ? [...links, chosen] : links;
    if (JSON.stringify(names) !== JSON.stringify(wanted)) {
      sel.replaceChildren(sel.options[0], ...wanted.map((n) => el("option", { value: n, text: n })));
    }
    sel.value = chosen || "";
  }
}

// ------------------------------------------------------------------ sliders
function jointUnit(j) { return j.type === "prismatic" ? "" : display.deg ? "°" : " rad"; }

function showSliderValue(i) {
  const j = state.robot ? state.robot.joints[i] : null, s = $("q" + i);
  if (!j || !s) return;
  $("qv" + i).textContent = num(parseFloat(s.value), j.type !== "prismatic").replace(/(\.\d{4})\d+/, "$1") + jointUnit(j);
}

function buildSliders(res) {
  const box = $("sliders");
  box.replaceChildren();
  res.joints.forEach((j, i) => {
    const prismatic = j.type === "prismatic";
    const span = prismatic ? res.scale : Math.PI;
    const lo = j.lower !== null ? j.lower : -span, hi = j.upper !== null ? j.upper : span;
    const s = el("input", { type: "range", min: String(lo), max: String(hi), step: "any",
                            "data-joint": String(i), id: "q" + i, "aria-label": j.name });
    s.value = String(Math.min(Math.max(res.q[i], lo), hi));
    if (lo === hi) {  // equal limits: locked at that value (robkin.io.trees.joint_limits), as IK and sampling hold it
      s.disabled = true;
      s.title = "locked: its lower limit equals its upper limit";
    }
    const out = el("output", { for: "q" + i, id: "qv" + i });
    s.addEventListener("input", () => { showSliderValue(i); qSet(); refresh(); });
    box.append(el("div", { class: "slider" }, el("span", { class: "jname", title: j.type,
      text: (i + 1) + " " + j.name + (prismatic ? " (P)" : " (R)") }), s, out));
  });
  state.robot = res;
  display.scale = res.scale;
  res.joints.forEach((_, i) => showSliderValue(i));
}

function setQ(q) {
  q.forEach((v, i) => { const s = $("q" + i); if (s) { s.value = String(v); showSliderValue(i); } });
}

// ------------------------------------------------------------------ tables (tables.js)
function showTables(res) { $("tables").replaceChildren(...representationSections(res, state.reps)); }

// The overlay checkboxes and the representations' download buttons (after YAML, JSON and URDF), as
// GET /api/representations lists them.
function buildControls(reps) {
  for (const o of reps.overlays) {
    const box = el("input", { type: "checkbox", value: o.name, id: "ov-" + o.name });
    $("overlay").append(" ", el("label", {}, box, " " + o.label));
  }
  for (const d of reps.downloads) {
    $("downloads").append(" ", el("button", { type: "button", "data-download": d.name, id: "dl-" + d.name, text: d.label }));
  }
}

function showAgreement(res) {
  const a = $("agreement");
  a.hidden = !res.agreement;
  if (!res.agreement) { a.textContent = ""; return; }
  const e = (x) => x.toExponential(1);
  const names = overlayLegend(res.overlays);
  a.replaceChildren(...names.flatMap((n, k) => (k ? [", ", n] : [n])),
    " vs. the robot as given: tool poses differ by " + e(res.agreement.position) + " (position), " +
    e(res.agreement.rotation) + " (rotation); joint axes by " + e(res.agreement.axes) + ".");
}

// The visual check (check.js): robot B drawn dashed orange, `robkin check`'s verdict on the whole robot
// (kinematics and mass properties), the per-joint table and both robots' masses, under the view.
function showCheck(res) {
  const box = $("check"), c = res.check;
  box.hidden = !c;
  document.body.classList.toggle("comparing", !!c);
  box.replaceChildren(...(c ? checkContents(res, (r) => zoomToFirstDifference(viewer, r)) : []));
}



// ------------------------------------------------------------------ self collision (collision.js)
// What the poll asks about: the robot and q shown, unless another answer (which carries the collision
// state) is on its way or the tool frame is being dragged; still() is false once the q shown changed.
function shownForPoll() {
  const robot = state.robot, seq = state.qSeq, ik = state.ik;
  if (!robot || !state.asked || state.inflight || state.pending || ik.inflight || ik.pending || viewer.dragging) return null;
  const still = () => state.robot === robot && state.qSeq === seq && !viewer.dragging && $("check-collision").checked;
  const { text, fmt, base_link, tip_link, tool_row } = state.asked;
  return still() ? { body: { text, fmt, base_link, tip_link, tool_row, q: robot.q }, still } : null;
}

// A poll's answer: only the red links and the status line change (the gizmo stays where it is).
function pollAnswered(c) {
  state.robot.collision = c;
  viewer.show(state.robot, { keepTarget: true });
}

// ------------------------------------------------------------------ workspace overlay
// The robot's reachable voxels as points (workspace_overlay.js, POST /api/workspace); data-workspace
// counts the points drawn (for tests).
function showWorkspace() {
  $("workspace-status").textContent = "workspace: sampling…";
  workspace.show(inputs(), post).then((res) => {
    if (!$("show-workspace").checked) { workspace.hide(); return; }  // unchecked meanwhile
    if (!res.ok) { $("workspace-status").textContent = ""; showError(res.error); return; }
    document.body.dataset.workspace = String(workspace.group.children.reduce(
      (k, c) => k + c.geometry.getAttribute("position").count, 0));  // points drawn
    $("workspace-status").textContent = "workspace: " + res.points.length + " voxels of " + res.voxel.toPrecision(2) +
      " reached (" + res.samples + " samples; colour: approach directions reached, of " + res.orientations + ")";
  }).catch((err) => showError("connection to the robkin server failed: " + err));
}

// ------------------------------------------------------------------ meshes
// Only the robot given on the command line, unedited and with its chain, has visuals the server serves.
function showMeshes(body) {
  const st = state.start;
  const mine = !!(st && body.text === st.text && body.base_link === st.base_link && body.tip_link === st.tip_link);
  const on = mine && st.visuals.length > 0;
  if (mine && st.missing_line) {  // also when no mesh at all was found (apply() has just reset the box)
    $("warnings").hidden = false;
    $("warnings").textContent = ($("warnings").textContent + "\n" + st.missing_line).trim();
  }
  if (on === state.meshKey) return;
  state.meshKey = on;
  if (!on) { viewer.setMeshes([]); return; }
  loadVisuals(st.visuals).then((visuals) => {
    if (state.meshKey) viewer.setMeshes(visuals);
    document.body.dataset.meshes = String(visuals.length);
  }).catch((err) => showError("meshes: " + err));
}

// ------------------------------------------------------------------ downloads
async function download(to) {
  const res = await post("/api/export", { ...inputs(), to }).catch((err) => ({ ok: false, error: String(err) }));
  if (!res.ok) { showError(res.error); return; }
  const url = URL.createObjectURL(new Blob([res.content], { type: res.mime }));
  const a = el("a", { href: url, download: res.filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

// ------------------------------------------------------------------ start
function formatOf(filename) {
  const f = filename.toLowerCase();
  if (f.endsWith(".urdf")) return "urdf";
  if (f.endsWith(".xml") || f.endsWith(".mjcf")) return "mjcf";
  if (f.endsWith(".sdf")) return "sdf";
  if (f.endsWith(".json")) return "json";
  return "yaml";
}

function showFields() {
  const urdf = isUrdf(), f = $("format").value;
  document.querySelectorAll(".urdf-only").forEach((e) => { e.hidden = !urdf; });
  document.querySelectorAll(".rows-only").forEach((e) => { e.hidden = !(f === "dh-rows" || f === "mdh-rows"); });
}

async function start() {
  viewer = new Viewer($("view"), { onDrag: dragged, onDragEnd: dragEnded });
  workspace = new WorkspaceOverlay(viewer);
  poll = new CollisionPoll({ post, current: shownForPoll, apply: pollAnswered, error: showError });
  $("show-workspace").addEventListener("change", (e) => {
    if (e.target.checked) { showWorkspace(); return; }
    workspace.hide();
    $("workspace-status").textContent = "";
    document.body.dataset.workspace = "0";
  });
  $("check-collision").addEventListener("change", () => refresh());
  let timer = null;
  const edited = () => { showFields(); showExample(); qSet(); clearTimeout(timer); timer = setTimeout(() => refresh(), 250); };
  $("robot-text").addEventListener("input", edited);
  $("other-text").addEventListener("input", edited);
  for (const id of ["format", "base-link", "tip-link", "last-row", "other-format"]) $(id).addEventListener("change", edited);
  $("exaggerate").addEventListener("change", () => refresh());
  $("units").addEventListener("change", () => { display.deg = $("units").value === "deg"; state.tablesKey = null; refresh(); });
  for (const [input, text, format] of [["file", "robot-text", "format"], ["other-file", "other-text", "other-format"]]) {
    $(input).addEventListener("change", async () => {
      const f = $(input).files[0];
      if (!f) return;
      $(text).value = await f.text();
      $(format).value = format === "format" ? formatOf(f.name) : "auto";
      if (format === "format") $("example").value = "";
      edited();
    });
  }
  $("other-clear").addEventListener("click", () => { $("other-text").value = ""; $("other-file").value = ""; refresh(); });
  $("arm-angle-slider").addEventListener("input", swivel);
  $("arm-angle-slider").addEventListener("change", () => { dragEnded(); });
  // home: the hub's (Robot.home: q = 0 clipped into the limits), the MJCF keyframe 'home' too
  $("home").addEventListener("click", () => {
    const home = state.robot && state.robot.home;
    setQ(home && home.length === currentQ().length ? home : currentQ().map(() => 0)); qSet(); refresh(); });
  document.querySelectorAll("[data-view]").forEach((b) => b.addEventListener("click", () => viewer.view(b.dataset.view)));
  $("gizmo-mode").addEventListener("change", () => viewer.setGizmoMode($("gizmo-mode").value));
  const [init, reps] = await Promise.all([fetch("/api/start").then((r) => r.json()),
                                          fetch("/api/representations").then((r) => r.json())]);
  state.start = init;
  state.reps = reps;
  buildControls(reps);
  document.querySelectorAll("#overlay input").forEach((c) => c.addEventListener("change", () => refresh()));
  document.querySelectorAll("[data-download]").forEach((b) => b.addEventListener("click", () => download(b.dataset.download)));
  const ex = $("example");
  for (const name of Object.keys(init.examples)) ex.append(el("option", { value: name, text: name }));
  ex.addEventListener("change", () => {
    if (!ex.value) return;
    $("robot-text").value = init.examples[ex.value];
    $("format").value = "auto";
    $("file").value = "";
    edited();
  });
  display.deg = $("units").value === "deg";
  if (init.text) {
    $("robot-text").value = init.text;
    $("format").value = init.fmt || "auto";
    for (const id of ["base-link", "tip-link"]) {
      const v = init[id.replace("-", "_")];
      if (v) $(id).append(el("option", { value: v, text: v }));
      $(id).value = v;
    }
  } else {
    const first = init.default_example in init.examples ? init.default_example : Object.keys(init.examples)[0];
    if (first) { ex.value = first; $("robot-text").value = init.examples[first]; }
  }
  if (init.other) {
    $("other-text").value = init.other.text;
    $("other-format").value = init.other.fmt || "auto";
    if (!$("other-format").value) $("other-format").value = "auto";  // a document or file format: auto-detected
    if (init.other.exaggerate) $("exaggerate").value = String(init.other.exaggerate);
    $("check-panel").open = true;
  }
  showFields();
  showExample();
  refresh();
}

// The Example list names the example shown (also when it came from the command line), "—" once the
// text is another robot (a file, an edit).
function showExample() {
  const examples = state.start ? state.start.examples : {}, text = $("robot-text").value;
  const auto = ["auto", "yaml"].includes($("format").value);
  $("example").value = (auto && Object.keys(examples).find((k) => examples[k] === text)) || "";
}

document.addEventListener("DOMContentLoaded", start);
