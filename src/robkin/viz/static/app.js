// robkin GUI: one page, no libraries. The server does all kinematics (POST /api/describe); this file
// only draws what it answers: a canvas 3D view (orthographic, drag to turn, wheel to zoom), joint
// sliders, the tool pose and a table per representation, and downloads (POST /api/export).
"use strict";

const $ = (id) => document.getElementById(id);
const COLORS = { link: "#3a3a3a", axis: "#1f4fe0", tool: "#ff3fa4", base: "#000000", grid: "#e4e4e4" };
// Link colours of overlaid representations (as in the matplotlib pictures).
const OVERLAY_COLORS = ["#f28e2b", "#2ca02c", "#9467bd", "#8c564b"];
// Lengths drawn relative to the robot's size (same fractions as the matplotlib pictures).
const AXIS_BACK = 0.12, AXIS_FRONT = 0.22, TRIAD = 0.16;

const state = {
  robot: null,          // last good answer of /api/describe
  jointKey: "",         // joints' names/types/limits: sliders are rebuilt when it changes
  tablesText: null,     // input the tables were drawn for
  inflight: false, pending: null,
  view: { az: -60 * Math.PI / 180, el: 25 * Math.PI / 180, zoom: 1, center: [0, 0, 0], radius: 1 },
};

// ------------------------------------------------------------------ talking to the server
async function post(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "Content-Type": "application/json" },
                                body: JSON.stringify(body) });
  return r.json();
}

function inputs() {
  return { text: $("robot-text").value, fmt: $("format").value,
           base_link: $("base-link").value.trim(), tip_link: $("tip-link").value.trim() };
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
  const body = { ...inputs(), q: state.robot ? currentQ() : null, strict_q: false, overlay: overlayList() };
  if (state.inflight) { state.pending = body; return; }
  send(body);
}

function send(body) {
  state.inflight = true;
  document.body.dataset.state = "busy";
  post("/api/describe", body)
    .then((res) => apply(res, body))
    .catch((err) => showError("connection to the robkin server failed: " + err))
    .finally(() => {
      state.inflight = false;
      if (state.pending) { const next = state.pending; state.pending = null; send(next); }
    });
}

// ------------------------------------------------------------------ applying an answer
function apply(res, body) {
  if (!res.ok) { showError(res.error); return; }
  $("error").hidden = true;
  $("error").textContent = "";
  const w = $("warnings");
  w.hidden = !res.warnings.length;
  w.textContent = res.warnings.length ? "Input adjusted:\n" + res.warnings.join("\n") : "";
  const key = JSON.stringify(res.joints);
  if (key !== state.jointKey) {
    state.jointKey = key;
    buildSliders(res);
    fitView(res);
  }
  state.robot = res;
  $("robot-name").textContent = (res.name || "robot") + " — " + res.n + " joints";
  showPose(res);
  showAgreement(res);
  if (state.tablesText !== body.text + "\u0000" + body.fmt + body.base_link + "\u0000" + body.tip_link) {
    state.tablesText = body.text + "\u0000" + body.fmt + body.base_link + "\u0000" + body.tip_link;
    showTables(res);
  }
  draw();
  document.body.dataset.state = "ready";
  document.body.dataset.updates = String(Number(document.body.dataset.updates) + 1);
}

function showError(message) {
  const e = $("error");
  e.textContent = message;
  e.hidden = false;
  document.body.dataset.state = "error";
}

function fmt(x, digits = 4) {
  if (x === null || x === undefined) return "";
  const s = x.toFixed(digits);
  return /^-0\.0*$/.test(s) ? s.slice(1) : s;  // a rounding-size negative shows as 0, not -0
}

function el(tag, attrs = {}, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") e.textContent = v; else if (k === "class") e.className = v; else e.setAttribute(k, v);
  }
  for (const kid of kids) if (kid) e.append(kid);
  return e;
}

// ------------------------------------------------------------------ sliders
function buildSliders(res) {
  const box = $("sliders");
  box.replaceChildren();
  res.joints.forEach((j, i) => {
    const prismatic = j.type === "prismatic";
    const span = prismatic ? res.scale : Math.PI;
    const lo = j.lower !== null ? j.lower : -span, hi = j.upper !== null ? j.upper : span;
    const s = el("input", { type: "range", min: String(lo), max: String(hi), step: String((hi - lo) / 2000),
                            "data-joint": String(i), id: "q" + i, "aria-label": j.name });
    s.value = String(Math.min(Math.max(res.q[i], lo), hi));
    const out = el("output", { for: "q" + i, id: "qv" + i });
    out.textContent = fmt(parseFloat(s.value), 3) + (prismatic ? "" : " rad");
    s.addEventListener("input", () => {
      out.textContent = fmt(parseFloat(s.value), 3) + (prismatic ? "" : " rad");
      refresh();
    });
    box.append(el("div", { class: "slider" }, el("span", { class: "jname", title: j.name + " (" + j.type + ")",
      text: j.name + (prismatic ? " (P)" : " (R)") }), s, out));
  });
}

// ------------------------------------------------------------------ tables
function matrixTable(M, caption, id) {
  const t = el("table", { class: "num" });
  if (id) t.id = id;
  for (const row of M) t.append(el("tr", {}, ...row.map((v) => el("td", { text: fmt(v), title: String(v) }))));
  return el("div", {}, el("div", { class: "caption", text: caption }), t);
}

function rowsTable(id, header, labels, rows) {
  const t = el("table", { class: "num", id });
  t.append(el("tr", {}, ...header.map((h, k) => el("th", { text: h, class: k === 0 ? "label" : "" }))));
  rows.forEach((r, i) => {
    t.append(el("tr", {}, el("td", { class: "label", text: labels[i] }),
                ...r.map((v) => el("td", { text: fmt(v), title: String(v) }))));
  });
  return t;
}

function section(title, key, ...kids) {
  const d = el("details", { id: "section-" + key, open: "" }, el("summary", { text: title }), ...kids);
  return d;
}

function showTables(res) {
  const doc = res.document, names = res.joints.map((j) => j.name + (j.type === "prismatic" ? " (P)" : " (R)"));
  const dhRows = (sec) => sec.rows.map((r) => [r.a, r.d, r.alpha, r.theta]);
  const parts = [];
  parts.push(section("Standard DH  A = Rz(θ) Tz(d) Tx(a) Rx(α)", "dh",
    rowsTable("table-dh", ["joint", "a", "d", "α", "θ"], names, dhRows(doc.dh)),
    el("div", { class: "matrices" }, matrixTable(doc.dh.base, "base"), matrixTable(doc.dh.tool, "tool"))));
  parts.push(section("Modified DH  A = Rx(α) Tx(a) Rz(θ) Tz(d)", "mdh",
    rowsTable("table-mdh", ["joint", "a(i-1)", "d", "α(i-1)", "θ"], names, dhRows(doc.mdh)),
    el("div", { class: "matrices" }, matrixTable(doc.mdh.base, "base"), matrixTable(doc.mdh.tool, "tool"))));
  for (const [key, title] of [["poe", "PoE, space frame  T = exp(S1 q1)…exp(Sn qn) M"],
                              ["poe_body", "PoE, body frame  T = M exp(B1 q1)…exp(Bn qn)"]]) {
    parts.push(section(title, key,
      rowsTable("table-" + key, ["joint", "ωx", "ωy", "ωz", "vx", "vy", "vz"], names, doc[key].screws),
      el("div", { class: "matrices" }, matrixTable(doc[key].M, "M (tool at home)"))));
  }
  const rpyLabels = ["world → base", ...names, "→ tool"];
  parts.push(section("RPY-XYZ (URDF joint origins)", "rpy_xyz",
    rowsTable("table-rpy_xyz", ["", "roll", "pitch", "yaw", "x", "y", "z"], rpyLabels,
              doc.rpy_xyz.rows.map((r) => [r.roll, r.pitch, r.yaw, r.x, r.y, r.z]))));
  const gjd = el("div", { class: "matrices", id: "table-gjd" });
  doc.gjd.frames.forEach((F, i) => gjd.append(matrixTable(F, i < res.n ? "J" + (i + 1) + " " + res.joints[i].name : "tool")));
  parts.push(section("GJD: joint frames at home, in the base frame", "gjd", gjd));
  const urdf = res.urdf !== null ? el("pre", { class: "urdf", id: "urdf-text", text: res.urdf })
                                 : el("p", { id: "urdf-text", text: "URDF: " + res.urdf_error });
  parts.push(section("URDF", "urdf", urdf));
  $("tables").replaceChildren(...parts);
}

function showAgreement(res) {
  const a = $("agreement");
  a.hidden = !res.agreement;
  if (!res.agreement) { a.textContent = ""; return; }
  const e = (x) => x.toExponential(1);
  const names = res.overlays.map((o, k) => {
    const span = el("span", { class: "ov-name", text: "– – " + o.label });
    span.style.color = OVERLAY_COLORS[k % OVERLAY_COLORS.length];  // CSSOM: allowed by the page's CSP
    return span;
  });
  a.replaceChildren(...names.flatMap((n, k) => (k ? [", ", n] : [n])),
    " vs. the robot as given: tool poses differ by " + e(res.agreement.position) + " (position), " +
    e(res.agreement.rotation) + " (rotation); joint axes by " + e(res.agreement.axes) + ".");
}

function showPose(res) {
  const t = $("pose-table");
  t.replaceChildren();
  const T = res.T;
  const heads = ["", "x axis", "y axis", "z axis", "position"];
  t.append(el("tr", {}, ...heads.map((h) => el("th", { text: h }))));
  ["x", "y", "z"].forEach((name, r) => {
    t.append(el("tr", {}, el("th", { text: name }), ...[0, 1, 2, 3].map((c) =>
      el("td", { text: fmt(T[r][c]), title: String(T[r][c]), "data-rc": r + "," + c }))));
  });
  const p = res.rpy_xyz;
  t.append(el("tr", {}, el("th", { text: "rpy" }), ...[0, 1, 2].map((k) => el("td", { text: fmt(p[k]) })),
              el("td", { text: "rad" })));
}

// ------------------------------------------------------------------ 3D view
function fitView(res) {
  const pts = [...res.scene.links, [0, 0, 0]];
  const lo = [0, 1, 2].map((k) => Math.min(...pts.map((p) => p[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...pts.map((p) => p[k])));
  state.view.center = lo.map((v, k) => (v + hi[k]) / 2);
  // Big enough for the robot at home and most of its reach (about scale from the base) when it moves.
  // (1e-9 keeps the projection finite for a robot drawn as a single point.)
  state.view.radius = Math.max(res.scale * 0.8, ...hi.map((v, k) => (v - lo[k]) * 0.6), 1e-9);
}

function projector(canvas) {
  const v = state.view, ca = Math.cos(v.az), sa = Math.sin(v.az), ce = Math.cos(v.el), se = Math.sin(v.el);
  const right = [-sa, ca, 0], up = [-se * ca, -se * sa, ce];
  const s = Math.min(canvas.width, canvas.height) * 0.5 * v.zoom / v.radius;
  const cx = canvas.width / 2, cy = canvas.height / 2;
  return (p) => {
    const d = [p[0] - v.center[0], p[1] - v.center[1], p[2] - v.center[2]];
    return [cx + s * (d[0] * right[0] + d[1] * right[1]), cy - s * (d[0] * up[0] + d[1] * up[1] + d[2] * up[2])];
  };
}

function draw() {
  const canvas = $("view"), res = state.robot;
  const ratio = window.devicePixelRatio || 1;
  const w = Math.round(canvas.clientWidth * ratio), h = Math.round(canvas.clientHeight * ratio);
  if (w > 0 && (canvas.width !== w || canvas.height !== h)) { canvas.width = w; canvas.height = h; }
  const g = canvas.getContext("2d");
  g.setTransform(1, 0, 0, 1, 0, 0);
  g.clearRect(0, 0, canvas.width, canvas.height);
  if (!res) return;
  const P = projector(canvas), sc = res.scene, L = res.scale, px = ratio;
  const line = (a, b, color, width, dash) => {
    const A = P(a), B = P(b);
    g.strokeStyle = color; g.lineWidth = width * px; g.setLineDash(dash ? dash.map((x) => x * px) : []);
    g.beginPath(); g.moveTo(A[0], A[1]); g.lineTo(B[0], B[1]); g.stroke();
  };
  const label = (p, text, color) => {
    const A = P(p);
    g.fillStyle = color; g.font = (11 * px) + "px system-ui, sans-serif"; g.fillText(text, A[0] + 3 * px, A[1] - 3 * px);
  };
  const add = (p, d, k) => [p[0] + k * d[0], p[1] + k * d[1], p[2] + k * d[2]];
  // ground grid on the base x-y plane
  const R = state.view.radius, step = Math.pow(10, Math.floor(Math.log10(R)));
  // (1e-12: include the last grid line despite the rounding of the repeated additions)
  for (let x = -Math.ceil(R / step) * step; x <= R + 1e-12 * R; x += step) {
    line([x, -R, 0], [x, R, 0], COLORS.grid, 1); line([-R, x, 0], [R, x, 0], COLORS.grid, 1);
  }
  const triad = (T, color, names) => {
    const o = [T[0][3], T[1][3], T[2][3]];
    for (let c = 0; c < 3; c++) {
      const tip = add(o, [T[0][c], T[1][c], T[2][c]], TRIAD * L);
      line(o, tip, color, 2.5);
      if (names) label(tip, names[c], color);
    }
  };
  triad([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]], COLORS.base, ["x0", "y0", "z0"]);
  // overlaid representations first, dashed, so the robot as given stays on top
  res.overlays.forEach((o, k) => {
    const color = OVERLAY_COLORS[k % OVERLAY_COLORS.length];
    for (let i = 1; i < o.links.length; i++) line(o.links[i - 1], o.links[i], color, 3, [7, 4]);
    o.axis_points.forEach((p, i) => {
      line(add(p, o.axis_dirs[i], -AXIS_BACK * L), add(p, o.axis_dirs[i], AXIS_FRONT * L), COLORS.axis, 1.2, [3, 3]);
    });
  });
  // links
  g.lineJoin = "round"; g.lineCap = "round";
  const pts = sc.links.map(P);
  g.strokeStyle = COLORS.link; g.lineWidth = 5 * px; g.setLineDash([]);
  g.beginPath(); pts.forEach((p, i) => (i ? g.lineTo(p[0], p[1]) : g.moveTo(p[0], p[1]))); g.stroke();
  g.fillStyle = COLORS.link;
  for (const p of pts) { g.beginPath(); g.arc(p[0], p[1], 3.5 * px, 0, 2 * Math.PI); g.fill(); }
  // joint axes, positive direction longer
  sc.axis_points.forEach((p, i) => {
    const z = sc.axis_dirs[i];
    line(add(p, z, -AXIS_BACK * L), add(p, z, AXIS_FRONT * L), COLORS.axis, 3, sc.prismatic[i] ? [6, 3] : null);
    label(add(p, z, (AXIS_FRONT + 0.02) * L), sc.joint_names[i], COLORS.axis);
  });
  triad(sc.tool, COLORS.tool, ["x", "y", "z"]);
}

function setupView() {
  const canvas = $("view");
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const v = state.view;
    v.az -= (e.clientX - drag[0]) * 0.01;
    v.el = Math.max(-1.55, Math.min(1.55, v.el + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    state.view.zoom = Math.max(0.1, Math.min(20, state.view.zoom * Math.exp(-e.deltaY * 0.001)));
    draw();
  }, { passive: false });
  window.addEventListener("resize", draw);
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

function showUrdfFields() {
  const text = $("robot-text").value.trimStart(), f = $("format").value;
  const urdf = ["urdf", "mjcf", "sdf"].includes(f) || (f === "auto" && text.startsWith("<"));
  document.querySelectorAll(".urdf-only").forEach((e) => { e.hidden = !urdf; });
}

async function start() {
  setupView();
  let timer = null;
  const edited = () => { showUrdfFields(); clearTimeout(timer); timer = setTimeout(() => refresh(), 250); };
  $("robot-text").addEventListener("input", edited);
  $("format").addEventListener("change", edited);
  $("base-link").addEventListener("input", edited);
  $("tip-link").addEventListener("input", edited);
  $("file").addEventListener("change", async () => {
    const f = $("file").files[0];
    if (!f) return;
    $("robot-text").value = await f.text();
    $("format").value = formatOf(f.name);
    $("example").value = "";
    edited();
  });
  $("home").addEventListener("click", () => {
    document.querySelectorAll("#sliders input[type=range]").forEach((s) => {
      s.value = "0"; s.dispatchEvent(new Event("input"));
    });
  });
  document.querySelectorAll("#overlay input").forEach((c) => c.addEventListener("change", () => refresh()));
  document.querySelectorAll("[data-download]").forEach((b) => b.addEventListener("click", () => download(b.dataset.download)));
  const init = await fetch("/api/start").then((r) => r.json());
  const ex = $("example");
  for (const name of Object.keys(init.examples)) ex.append(el("option", { value: name, text: name }));
  ex.addEventListener("change", () => {
    if (!ex.value) return;
    $("robot-text").value = init.examples[ex.value];
    $("format").value = "auto";
    $("file").value = "";
    edited();
  });
  if (init.text) {
    $("robot-text").value = init.text;
    $("format").value = init.fmt || "auto";
    $("base-link").value = init.base_link; $("tip-link").value = init.tip_link;
  } else {
    const first = Object.keys(init.examples)[0];
    if (first) { ex.value = first; $("robot-text").value = init.examples[first]; }
  }
  showUrdfFields();
  refresh();
}

document.addEventListener("DOMContentLoaded", start);
