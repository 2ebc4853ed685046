// The visual check against robot B: `robkin check`'s verdict on the whole robot (kinematics and mass
// properties, from the same library calls: robkin.viz.check_view), the first difference, the
// per-joint table, and each body's mass in A beside B's. B itself is drawn by viewer.js (dashed orange).
import { el, num } from "./dom.js";

// res.check -> the contents of #check; zoom(res) puts the camera on the first difference.
export function checkContents(res, zoom) {
  const c = res.check, cmp = c.comparison;
  const kind = c.same ? "same" : cmp.equivalent && c.mass.same !== false ? "convention" : "differs";
  const headline = c.same ? "same robot: kinematics and mass properties agree (as robkin check says)"
    : "DIFFER: not the same robot (robkin check exits 1)";
  const verdict = el("div", { class: "verdict " + kind, id: "check-verdict" },
    el("div", { class: "headline", text: headline }),
    ...c.lines.map((line) => el("div", { class: "line", text: line })));
  const first = el("div", { id: "check-first", text:
    c.first_joint !== null ? "first joint that differs: J" + (c.first_joint + 1) + " (red in the view)"
    : c.first_difference ? "first difference: " + c.first_difference : "" });
  const button = el("button", { type: "button", id: "zoom-first", text: "zoom to the first difference" });
  button.disabled = c.first_joint === null && !c.arrows.length;
  button.addEventListener("click", () => zoom(res));
  first.append(button);
  const scaled = c.exaggerate > 1 ? ", differences ×" + c.exaggerate : "";
  const arrows = c.arrows.length ? "; red arrows: where B's axes are (true distance at the arrow head)" : "";
  return [el("div", { class: "about", text: "B: " + (c.name || "robot") + ", " + c.n + " joints, drawn dashed orange" +
                                            scaled + arrows }),
          verdict, first, jointTable(c), el("div", { text: "tool: " + cmp.tool }), massTable(c)];
}

function both(a, b) { return a === b || !b ? a : !a ? b : a + " / " + b; }

// The joints, as `robkin check` tabulates them: the mapping q_A = sign q_B + offset and how they differ.
function jointTable(c) {
  const t = el("table", { class: "num check", id: "check-joints" });
  t.append(el("tr", {}, ...["joint", "A / B", "status", "q_A =", "detail"].map((h) => el("th", { text: h }))));
  for (const j of c.comparison.joints) {
    const mapping = (j.sign < 0 ? "−q_B" : "q_B") + (j.offset ? (j.offset > 0 ? " + " : " − ") + num(Math.abs(j.offset), true) : "");
    t.append(el("tr", { class: j.joint - 1 === c.first_joint ? "differs" : "" },
      el("td", { text: String(j.joint) }), el("td", { class: "label", text: both(j.name_a, j.name_b) }),
      el("td", { class: "label", text: j.status }), el("td", { class: "label", text: mapping, title: String(j.offset) }),
      el("td", { class: "label detail", text: j.detail })));
  }
  return t;
}

// Each body's mass in A and in B, and where `check` compared them, how far apart their centres of mass
// are and by how much their inertias differ (red: the body differs).
function massTable(c) {
  const rows = c.masses.filter((m) => m.mass_a !== null || m.mass_b !== null);
  if (!rows.length) return el("div", { id: "check-masses", text: "no mass properties in A or B" });
  const t = el("table", { class: "num check", id: "check-masses" });
  t.append(el("tr", {}, ...["body", "link (A / B)", "m A (kg)", "m B (kg)", "Δr (m)", "ΔI (kg m²)", ""]
    .map((h) => el("th", { text: h }))));
  const small = (x) => (x === null ? "" : num(x, false, 3));
  for (const m of rows) {
    t.append(el("tr", { class: m.same === false ? "differs" : "" },
      el("td", { text: m.body ? String(m.body) : "base" }), el("td", { class: "label", text: both(m.name_a, m.name_b) }),
      el("td", { text: m.mass_a === null ? "—" : num(m.mass_a, false, 6), title: String(m.mass_a) }),
      el("td", { text: m.mass_b === null ? "—" : num(m.mass_b, false, 6), title: String(m.mass_b) }),
      el("td", { text: small(m.centre_distance), title: String(m.centre_distance) }),
      el("td", { text: small(m.inertia_difference), title: String(m.inertia_difference) }),
      el("td", { class: "label", text: m.same === null ? "" : m.same ? "same" : "differs" })));
  }
  return el("div", { class: "wide" }, t);
}

// The camera on the first joint that differs (its difference arrow, else its axis on robot A), close
// enough to see the difference as drawn.
export function zoomToFirstDifference(viewer, res) {
  const c = res.check, L = res.scale || 1;
  const label = c.first_joint === null ? null : "J" + (c.first_joint + 1);
  const arrow = c.arrows.find((a) => a.label === label) || (label === null ? c.arrows[0] : null);
  if (arrow) {
    const mid = arrow.start.map((v, k) => (v + arrow.end[k]) / 2);
    const len = Math.hypot(...arrow.end.map((v, k) => v - arrow.start[k]));
    viewer.zoomTo(mid, Math.max(1.5 * len, 0.08 * L));
  } else if (label !== null) {
    viewer.zoomTo(res.scene.axis_points[c.first_joint], 0.15 * L);
  }
}
