// Small DOM helpers shared by the GUI's modules: making elements, and numbers as the page shows them.

// How numbers are shown: angles in degrees or radians, and the robot's size (noise below 1e-10 of it
// is shown as 0). app.js keeps it up to date.
export const display = { deg: false, scale: 1 };
const DEG = 180 / Math.PI;

export const $ = (id) => document.getElementById(id);

export function el(tag, attrs = {}, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") e.textContent = v; else if (k === "class") e.className = v; else e.setAttribute(k, v);
  }
  for (const kid of kids) if (kid) e.append(kid);
  return e;
}

// A number for display: `digits` significant digits (10 unless told); below 1e-10 of the robot's size
// shown as 0 (rounding of conversions and IK, ~1e-12, lies under it; typed tables, 1e-6 at best, far
// above). The full value is in the cell's title and in copies.
export function num(x, angle = false, digits = 10) {
  if (x === null || x === undefined) return "";
  let v = angle && display.deg ? x * DEG : x;
  if (Math.abs(v) < 1e-10 * Math.max(display.scale, 1)) v = 0;
  return String(Number(v.toPrecision(digits)));
}

// A table cell: the number rounded for display, the full value as its title.
export function cell(v, angle = false, digits = 10) { return el("td", { text: num(v, angle, digits), title: String(v) }); }

// A counter in the body's dataset (data-updates, data-ik-updates, ...): what tests wait for.
export function count(name) { document.body.dataset[name] = String(Number(document.body.dataset[name] || 0) + 1); }
