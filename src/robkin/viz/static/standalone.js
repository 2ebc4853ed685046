// The self-contained page of `robkin plot -o robot.html`: the GUI's 3D viewer on the scene data
// embedded in the page (no server: orbit, pan, zoom and the view buttons; q is the one plotted).
import { Viewer, overlayLegend } from "robkin/viewer.js";
import { loadVisuals } from "robkin/meshes.js";

const data = JSON.parse(document.getElementById("robkin-data").textContent);
const viewer = new Viewer(document.getElementById("view"));
viewer.show(data);
if (data.view) viewer.look(data.view);
document.querySelectorAll("[data-view]").forEach((b) => b.addEventListener("click", () => viewer.view(b.dataset.view)));
document.getElementById("overlays").append(...overlayLegend(data.overlays));
document.getElementById("grid-unit").textContent = "grid: " + document.getElementById("view").dataset.gridCell + " per cell";
// the robot file's meshes, embedded as base64 by id: drawn from blob URLs, placed by data.motions
const urls = {};
for (const [id, b64] of Object.entries(data.meshes || {})) {
  const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
  urls[id] = URL.createObjectURL(new Blob([bytes]));
}
if ((data.visuals || []).length) {
  loadVisuals(data.visuals, (id) => urls[id]).then((visuals) => {
    viewer.setMeshes(visuals);
    document.body.dataset.meshes = String(visuals.length);
    document.body.dataset.state = "ready";
  }).catch((err) => {
    document.body.dataset.state = "error";
    document.getElementById("missing-meshes")?.remove();
    const p = document.createElement("p");
    p.id = "missing-meshes";
    p.textContent = "meshes could not be drawn: " + err;
    document.querySelector("pre").before(p);
  });
} else {
  document.body.dataset.state = "ready";
}
