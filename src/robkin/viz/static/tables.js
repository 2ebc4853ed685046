// The Representations panel: a table per registered representation (GET /api/representations), rounded
// for display (full precision on hover and in copies), each link's mass properties, base/tool matrices.
// Every table fits its panel at 1400 px wide: wide content is split into narrower tables, not cut.
import { $, el, num, cell, display } from "./dom.js";

// A copy button: the table's numbers as tab-separated text at full precision (shortest round trip).
export function copyButton(rows) {
  const b = el("button", { type: "button", class: "copy", text: "copy" });
  b.addEventListener("click", () => {
    const text = rows.map((r) => r.join("\t")).join("\n") + "\n";
    document.body.dataset.copied = text;
    if (navigator.clipboard) navigator.clipboard.writeText(text).catch(() => {});
  });
  return b;
}

export function matrixTable(M, caption, id) {
  const t = el("table", { class: "num" });
  if (id) t.id = id;
  for (const row of M) t.append(el("tr", {}, ...row.map((v) => cell(v))));
  return el("div", {}, el("div", { class: "caption", text: caption }, copyButton(M)), t);
}

// A table with a header row and one labelled row per entry; `digits` significant digits shown.
export function plainTable(id, header, labels, rows, angleCols = [], digits = 10) {
  const t = el("table", { class: "num", id });
  const unit = display.deg ? " (°)" : "";
  t.append(el("tr", {}, ...header.map((h, k) => el("th", { text: h + (angleCols.includes(k - 1) ? unit : ""),
                                                          class: k === 0 ? "label" : "" }))));
  rows.forEach((r, i) => {
    t.append(el("tr", {}, el("td", { class: "label", text: labels[i] }),
                ...r.map((v, k) => cell(v, angleCols.includes(k), digits))));
  });
  return t;
}

function rowsTable(id, header, labels, rows, angleCols) {
  return el("div", {}, plainTable(id, header, labels, rows, angleCols),
            copyButton([header, ...rows.map((r, i) => [labels[i], ...r])]));
}

// Each link's mass properties (m, r, I: the robot document's row fields) when the rows carry them;
// `frame` says which frame r and I are in. Three narrow tables (m and r; the moments of inertia; the
// products), 6 significant digits (what URDF files carry), so that nothing is cut at 1400 px; "copy"
// copies all 11 columns at full precision. Empty (nothing shown) for a robot without them.
const MASS_HEADER = ["joint", "m (kg)", "rx (m)", "ry (m)", "rz (m)", "Ixx (kg m²)", "Iyy (kg m²)",
                     "Izz (kg m²)", "Ixy (kg m²)", "Iyz (kg m²)", "Ixz (kg m²)"];
const MASS_PARTS = [["mass", 1, 5], ["inertia", 5, 8], ["products", 8, 11]];  // id prefix, columns [from, to)
export const MASS_DIGITS = 6;
function massTable(key, entries, names, frame, base) {
  if (!entries || !entries.length || entries.some((e) => e.m === undefined)) return [];
  const all = base && base.m !== undefined ? [base, ...entries] : entries;  // the base body's first, if known
  const rows = all.map((e) => [e.m, ...e.r, ...e.I]);
  const labels = all === entries ? names : ["base", ...names];
  const tables = MASS_PARTS.map(([prefix, from, to]) =>
    plainTable(prefix + "-" + key, [MASS_HEADER[0], ...MASS_HEADER.slice(from, to)], labels,
               rows.map((r) => r.slice(from - 1, to - 1)), [], MASS_DIGITS));
  return [el("div", { class: "caption", text: "Mass properties, r and I in " + frame +
                      "; I about the centre of mass (everything fixed to a link merged in)" }),
          el("div", { class: "mass-tables" }, ...tables),
          copyButton([MASS_HEADER, ...rows.map((r, i) => [labels[i], ...r])])];
}

function section(title, key, ...kids) {
  return el("details", { id: "section-" + key, open: "" }, el("summary", { text: title }), ...kids);
}

function angleColumns(rep) { return rep.columns.flatMap((c, k) => (c.angle ? [k] : [])); }

// layout -> the section's contents; a section the document does not hold (Hayati, only where
// consecutive axes are nearly parallel) is left out.
const LAYOUTS = {
  "link-table": (rep, sec, names) => [
    rowsTable("table-" + rep.section, ["joint", ...rep.columns.map((c) => c.label)], names,
              sec.rows.map((r) => rep.columns.map((c) => r[c.key])), angleColumns(rep)),
    ...massTable(rep.section, sec.rows, names, rep.mass_frame, sec.base_mass),
    el("div", { class: "matrices" }, matrixTable(sec.base, "base"), matrixTable(sec.tool, "tool"))],
  screws: (rep, sec, names) => [
    rowsTable("table-" + rep.section, ["joint", ...rep.columns.map((c) => c.label)], names, sec.screws,
              angleColumns(rep)),
    ...massTable(rep.section, sec.masses, names, rep.mass_frame, sec.base_mass),
    el("div", { class: "matrices" }, matrixTable(sec.M, "M (tool at home)"))],
  rpy: (rep, sec, names) => [
    rowsTable("table-" + rep.section, ["", ...rep.columns.map((c) => c.label)], ["world → base", ...names, "→ tool"],
              sec.rows.map((r) => rep.columns.map((c) => r[c.key])), angleColumns(rep)),
    ...massTable(rep.section, sec.rows.slice(1, -1), names, rep.mass_frame, sec.rows[0])],
  frames: (rep, sec, names, res) => {
    const box = el("div", { class: "matrices", id: "table-" + rep.section });
    sec.frames.forEach((F, i) => box.append(matrixTable(F, i < res.n ? "J" + (i + 1) + " " + res.joints[i].name : "tool")));
    return [box];
  },
};

// The panel's sections, in the registry's order, then the URDF.
export function representationSections(res, reps) {
  const doc = res.document, names = res.joints.map((j) => j.name + (j.type === "prismatic" ? " (P)" : " (R)"));
  const parts = reps.representations.filter((rep) => doc[rep.section] && LAYOUTS[rep.layout])
    .map((rep) => section(rep.title, rep.section, ...LAYOUTS[rep.layout](rep, doc[rep.section], names, res)));
  const urdf = res.urdf !== null ? el("pre", { class: "urdf", id: "urdf-text", text: res.urdf })
                                 : el("p", { id: "urdf-text", text: "URDF: " + res.urdf_error });
  parts.push(section("URDF", "urdf", urdf));
  return parts;
}

// The tool pose at q: its 4x4 matrix and roll, pitch, yaw (the #pose-table under the sliders).
export function showPose(res) {
  const t = $("pose-table");
  t.replaceChildren();
  const T = res.T;
  const heads = ["", "x axis", "y axis", "z axis", "position"];
  t.append(el("tr", {}, ...heads.map((h) => el("th", { text: h }))));
  ["x", "y", "z"].forEach((name, r) => {
    t.append(el("tr", {}, el("th", { text: name }), ...[0, 1, 2, 3].map((c) =>
      el("td", { text: num(T[r][c]), title: String(T[r][c]), "data-rc": r + "," + c }))));
  });
  const p = res.rpy_xyz;
  t.append(el("tr", {}, el("th", { text: "rpy" }), ...[0, 1, 2].map((k) => cell(p[k], true)),
              el("td", { text: display.deg ? "°" : "rad" })));
}
