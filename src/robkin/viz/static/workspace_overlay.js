// Workspace overlay for the GUI's viewer: the robot's reachable voxels (POST /api/workspace, answered by
// robkin.viz.workspace_api) drawn as translucent points in the robot base frame, coloured by how many
// approach directions reach each voxel (dark blue: few, yellow: all). A module of its own: the page
// makes one `new WorkspaceOverlay(viewer)` and calls `show(request, post)` / `hide()`.
import * as THREE from "three";

// viridis at 0, 0.25, 0.5, 0.75, 1
const RAMP = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551], [0.369, 0.789, 0.383],
              [0.993, 0.906, 0.144]];

function ramp(t) {
  const x = Math.min(Math.max(t, 0), 1) * (RAMP.length - 1), k = Math.min(Math.floor(x), RAMP.length - 2);
  const f = x - k;
  return RAMP[k].map((a, i) => a + f * (RAMP[k + 1][i] - a));
}

export class WorkspaceOverlay {
  constructor(viewer) {
    this.viewer = viewer;
    this.group = new THREE.Group();
    viewer.scene.add(this.group);
    this.last = null;   // the last answer (voxel, orientations, samples, points, counts, volume)
  }

  // Ask the server for the map of the robot of `request` (the fields of /api/describe: text, fmt,
  // base_link, tip_link, tool_row; optional voxel, samples) and draw it. Returns the answer.
  async show(request, post) {
    const res = await post("/api/workspace", request);
    if (!res.ok) return res;
    this.clear();
    const n = res.points.length, pos = new Float32Array(3 * n), col = new Float32Array(3 * n);
    res.points.forEach((p, i) => {
      pos.set(p, 3 * i);
      col.set(ramp((res.counts[i] - 1) / Math.max(res.orientations - 1, 1)), 3 * i);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(pos, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(col, 3));
    const material = new THREE.PointsMaterial({ size: 0.5 * res.voxel, vertexColors: true, transparent: true,
                                                opacity: 0.5, depthWrite: false, sizeAttenuation: true });
    this.group.add(new THREE.Points(geometry, material));
    this.last = res;
    this.viewer.render();
    return res;
  }

  hide() { this.clear(); this.viewer.render(); }

  clear() {
    for (const c of [...this.group.children]) {
      this.group.remove(c);
      c.geometry.dispose();
      c.material.dispose();
    }
  }
}
