// The self-contained page of `robkin plot -o robot.html`: the GUI's 3D viewer on the scene data
// embedded in the page (no server: orbit, pan, zoom and the view buttons; q is the one plotted).
import { Viewer, overlayLegend } from "robkin/viewer.js";

const data = JSON.parse(document.getElementById("robkin-data").textContent);
const viewer = new Viewer(document.getElementById("view"));
viewer.show(data);
if (data.view) viewer.look(data.view);
document.querySelectorAll("[data-view]").forEach((b) => b.addEventListener("click", () => viewer.view(b.dataset.view)));
document.getElementById("overlays").append(...overlayLegend(data.overlays));
document.getElementById("grid-unit").textContent = "grid: " + document.getElementById("view").dataset.gridCell + " per cell";
document.body.dataset.state = "ready";
