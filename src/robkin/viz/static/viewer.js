// robkin 3D viewer on three.js: draws what the server computed (robkin.viz.scene.Scene as JSON), in
// the robot base frame (z up). Perspective camera with orbit (left drag), pan (right drag / shift),
// zoom (wheel); fit, reset and front/side/top views; a ground grid whose cell size is shown; the
// conversion paper's style on top: joint axes blue with the longer end on the positive side, tool
// frame pink, base frame black. A transform gizmo on the tool frame reports drags (for IK).
// Used by the GUI (app.js) and by the self-contained page `robkin plot -o robot.html` (standalone.js).
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { TransformControls } from "three/addons/controls/TransformControls.js";

export const COLORS = { link: 0x3a3a3a, axis: 0x1f4fe0, tool: 0xff3fa4, base: 0x000000, differs: 0xe02020,
                        other: 0xf28e2b, colliding: 0xe02020 };
// Links in self collision (the answer's collision.links): their meshes and stick segments drawn in this.
const COLLIDING = new THREE.MeshStandardMaterial({ color: COLORS.colliding, roughness: 0.5 });
// Link colours of overlaid representations (as in the matplotlib pictures).
export const OVERLAY_COLORS = [0xf28e2b, 0x2ca02c, 0x9467bd, 0x8c564b];
// Lengths relative to the robot's size (same fractions as the matplotlib pictures).
const AXIS_BACK = 0.12, AXIS_FRONT = 0.22, TRIAD = 0.16, LINK_RADIUS = 0.012;

// Legend entries "– – label" in each overlay's colour.
export function overlayLegend(overlays) {
  return (overlays || []).map((o, k) => {
    const span = document.createElement("span");
    span.className = "ov-name";
    span.textContent = "– – " + o.label;
    span.style.color = "#" + OVERLAY_COLORS[k % OVERLAY_COLORS.length].toString(16).padStart(6, "0");
    return span;
  });
}

const v3 = (p) => new THREE.Vector3(p[0], p[1], p[2]);
const mat4 = (T) => new THREE.Matrix4().set(...T[0], ...T[1], ...T[2], ...T[3]);

export class Viewer {
  constructor(container, { onDrag = null, onDragEnd = null } = {}) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0xffffff);
    container.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
    this.camera.up.set(0, 0, 1);  // robot base frames are z-up
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x777777, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(2, -3, 5);
    this.scene.add(sun);
    this.orbit = new OrbitControls(this.camera, this.renderer.domElement);
    this.orbit.addEventListener("change", () => this.render());
    this.orbit.addEventListener("start", () => { this.userMoved = true; });  // the user turned, panned or zoomed
    this.world = new THREE.Group();      // ground grid and base frame
    this.robot = new THREE.Group();      // stick figure, overlays, robot B
    this.meshes = new THREE.Group();     // visuals (meshes) placed per joint frame
    this.scene.add(this.world, this.robot, this.meshes);
    this.target = new THREE.Object3D();  // what the gizmo moves: the wished tool pose
    this.target.matrixAutoUpdate = true;
    this.scene.add(this.target);
    this.gizmo = null;
    if (onDrag) {
      this.gizmo = new TransformControls(this.camera, this.renderer.domElement);
      this.gizmo.setSize(0.9);
      this.gizmo.attach(this.target);
      this.scene.add(this.gizmo.getHelper());
      this.gizmo.addEventListener("dragging-changed", (e) => {
        this.orbit.enabled = !e.value;
        this.dragging = e.value;
        // the camera holds still during a drag (it would move the gizmo under the mouse); after it,
        // it follows a robot the drag took out of the picture
        if (e.value) this.inViewAtDrag = this.inView();
        else if (this.follow && this.inViewAtDrag && !this.inView()) this.followRobot();
        if (!e.value && onDragEnd) onDragEnd();
      });
      this.gizmo.addEventListener("objectChange", () => onDrag(this.targetMatrix()));
      this.gizmo.addEventListener("change", () => this.render());
    }
    this.labels = [];   // [{el, p: Vector3}] HTML labels placed at projected points
    this.follow = true;     // fit the view again when the robot leaves it (see inView)
    this.dragging = false;  // the gizmo is being dragged: the camera holds still
    this.res = null;
    this.scale = 0;     // the robot's size; 0 until the first show()
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  // The gizmo's pose as a row-major 4x4 (robot base frame).
  targetMatrix() {
    this.target.updateMatrix();
    const e = this.target.matrix.elements;  // column-major
    return [0, 1, 2, 3].map((r) => [0, 1, 2, 3].map((c) => e[c * 4 + r]));
  }

  setGizmoMode(mode) { if (this.gizmo) { this.gizmo.setMode(mode); this.render(); } }

  placeTarget(T) {
    mat4(T).decompose(this.target.position, this.target.quaternion, this.target.scale);
    this.render();
  }

  resize() {
    const w = this.container.clientWidth, h = this.container.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // ------------------------------------------------------------------ what is drawn
  // res: {scene, overlays, check?: {scene, first_joint}, scale, collision?: {links, segments}} (the links
  // in self collision, robkin.viz.collision_api); keepTarget: leave the gizmo where it is.
  show(res, { keepTarget = false } = {}) {
    const first = !this.res, rescaled = (res.scale || 1) !== this.scale;
    const wasInView = !first && this.inView();  // a view the user zoomed into stays as it is
    this.res = res;
    this.scale = res.scale || 1;
    this.clear(this.robot);
    this.labels.forEach((l) => l.el.remove());
    this.labels = [];
    (res.overlays || []).forEach((o, k) => this.stick(o, OVERLAY_COLORS[k % OVERLAY_COLORS.length], true));
    const check = res.check;
    if (check) this.stick(check.scene, COLORS.other, true, check.first_joint);
    const hit = res.collision && res.collision.state === "ready" ? res.collision : null;
    this.stick(res.scene, COLORS.link, false, check ? check.first_joint : null, new Set(hit ? hit.segments : []));
    this.triad(res.scene.tool, COLORS.tool, 1, this.robot);
    if (res.show_frames) for (const F of res.scene.frames) this.rgbTriad(F);
    for (const a of (check ? check.arrows : res.arrows) || []) this.differenceArrow(a);
    if (!keepTarget) this.placeTarget(res.scene.tool);
    if (first || rescaled) this.buildWorld();  // grid and base frame sized to the robot
    if (first) this.view("iso");
    this.posesMeshes(res);
    this.paintColliding(hit ? hit.links : []);
    if (wasInView && this.follow && !this.dragging && !this.inView()) this.followRobot();
    this.render();
  }

  // A red arrow from robot A's point to robot B's (exaggerated) one, labelled with the true distance
  // (robkin.viz.difference.DifferenceArrow as JSON).
  differenceArrow(a) {
    const from = v3(a.start), d = v3(a.end).sub(from), len = d.length(), L = this.scale;
    if (!(len > 0)) return;
    const head = Math.min(0.05 * L, 0.4 * len);
    this.robot.add(new THREE.ArrowHelper(d.clone().normalize(), from, len, COLORS.differs, head, 0.5 * head));
    this.label(v3(a.end), a.label + ": " + Number(a.distance.toPrecision(3)), "true distance", "differs");
  }

  // Is everything drawn inside the view (with a small margin)? The camera follows the robot: when a
  // robot that was entirely in the picture moves (or grows) out of it, show() fits it again, keeping
  // the direction; a view the user zoomed into is left alone.
  inView() {
    const box = this.bounds(), m = 0.98;
    for (let i = 0; i < 8; i++) {
      const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                  i & 4 ? box.max.z : box.min.z).project(this.camera);
      if (Math.abs(p.x) > m || Math.abs(p.y) > m || p.z > 1) return false;
    }
    return true;
  }

  followRobot() {
    this.view("fit");
    this.container.dataset.follows = String(Number(this.container.dataset.follows || 0) + 1);  // for tests
  }

  // Camera on a point, close enough to see a detail of size `radius` (zoom to a differing joint).
  zoomTo(point, radius) {
    const c = v3(point), r = Math.max(radius, 1e-6 * this.scale);
    const dist = r / Math.sin((this.camera.fov * Math.PI / 180) / 2);
    const dir = this.camera.position.clone().sub(this.orbit.target).normalize();
    this.orbit.target.copy(c);
    this.camera.position.copy(c).addScaledVector(dir, dist);
    this.camera.near = dist / 1000;
    this.camera.far = dist * 1000;
    this.camera.updateProjectionMatrix();
    this.orbit.update();
    this.render();
  }

  // A stick figure: the links' polyline (segments in `red` drawn in the colliding colour), joint axes.
  stick(sc, color, dashed, highlight = null, red = new Set()) {
    const L = this.scale, g = this.robot;
    const pts = sc.links.map(v3);
    if (dashed) {
      const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts),
        new THREE.LineDashedMaterial({ color, dashSize: 0.04 * L, gapSize: 0.025 * L }));
      line.computeLineDistances();
      g.add(line);
    } else {
      const mat = new THREE.MeshStandardMaterial({ color, roughness: 0.6 });
      for (let i = 1; i < pts.length; i++) {
        g.add(this.rod(pts[i - 1], pts[i], (red.has(i - 1) ? 1.4 : 1) * LINK_RADIUS * L, red.has(i - 1) ? COLLIDING : mat));
      }
      const ball = new THREE.SphereGeometry(LINK_RADIUS * L * 1.6, 16, 12);
      for (const p of pts) { const m = new THREE.Mesh(ball, mat); m.position.copy(p); g.add(m); }
    }
    sc.axis_points.forEach((p, i) => {
      const z = v3(sc.axis_dirs[i]), o = v3(p);
      const from = o.clone().addScaledVector(z, -AXIS_BACK * L), len = (AXIS_BACK + AXIS_FRONT) * L;
      const c = i === highlight ? COLORS.differs : COLORS.axis;
      const arrow = new THREE.ArrowHelper(z, from, len, c, 0.06 * L, 0.035 * L);
      if (dashed) arrow.line.material = new THREE.LineDashedMaterial({ color: c, dashSize: 0.02 * L, gapSize: 0.02 * L });
      arrow.line.computeLineDistances();
      g.add(arrow);
      if (i === highlight) {
        const ring = new THREE.Mesh(new THREE.TorusGeometry(0.05 * L, 0.006 * L, 8, 32),
                                    new THREE.MeshBasicMaterial({ color: COLORS.differs }));
        ring.position.copy(o);
        ring.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), z);
        g.add(ring);
      }
      if (!dashed) this.label(o.clone().addScaledVector(z, (AXIS_FRONT + 0.03) * L), "J" + (i + 1),
                              sc.joint_names[i], i === highlight ? "differs" : "axis");
    });
  }

  rod(a, b, r, mat) {
    const d = b.clone().sub(a), len = d.length();
    const m = new THREE.Mesh(new THREE.CylinderGeometry(r, r, Math.max(len, 1e-12), 12), mat);
    m.position.copy(a).addScaledVector(d, 0.5);
    if (len > 0) m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), d.normalize());
    return m;
  }

  triad(T, color, size, group, names) {
    const M = mat4(T), o = new THREE.Vector3().setFromMatrixPosition(M), L = this.scale;
    ["x", "y", "z"].forEach((n, c) => {
      const dir = new THREE.Vector3().setFromMatrixColumn(M, c).normalize();
      group.add(new THREE.ArrowHelper(dir, o, TRIAD * L * size, color, 0.04 * L, 0.02 * L));
      if (names) this.label(o.clone().addScaledVector(dir, TRIAD * L * size * 1.1), names[c], "", "base");
    });
  }

  // A joint frame as red/green/blue x/y/z arrows (plot --frames).
  rgbTriad(T) {
    const M = mat4(T), o = new THREE.Vector3().setFromMatrixPosition(M), L = this.scale;
    [0xd62728, 0x2ca02c, 0x1f77b4].forEach((color, c) => {
      const dir = new THREE.Vector3().setFromMatrixColumn(M, c).normalize();
      this.robot.add(new THREE.ArrowHelper(dir, o, 0.6 * TRIAD * L, color, 0.03 * L, 0.015 * L));
    });
  }

  // The ground grid (base x-y plane) and base frame; the grid's cell is a power of ten of the robot size.
  buildWorld() {
    this.clear(this.world);
    const L = this.scale, cell = Math.pow(10, Math.floor(Math.log10(L / 3)));  // 3-30 cells across the robot
    const cells = 2 * Math.ceil(1.5 * L / cell);
    const grid = new THREE.GridHelper(cells * cell, cells, 0xc8c8c8, 0xe4e4e4);
    grid.rotation.x = Math.PI / 2;  // GridHelper lies in x-z; the robot's ground is x-y
    this.world.add(grid);
    this.triad([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], COLORS.base, 1, this.world, ["x0", "y0", "z0"]);
    this.container.dataset.gridCell = String(cell);
  }

  clear(group) {
    for (const c of [...group.children]) {
      group.remove(c);
      c.traverse((o) => { if (o.geometry) o.geometry.dispose(); });
    }
  }

  label(p, text, title, kind) {
    const el = document.createElement("span");
    el.className = "label3d " + kind;
    el.textContent = text;
    if (title) el.title = title;
    this.container.append(el);
    this.labels.push({ el, p });
  }

  // ------------------------------------------------------------------ meshes
  // visuals: [{body, pose: 4x4 at home in the base frame, object}] (meshes.js); placed at q by the
  // answer's motions (motion of body i from home to q, robkin.bodies.body_motions).
  setMeshes(visuals) {
    this.clear(this.meshes);
    this.visuals = visuals;
    for (const v of visuals) this.meshes.add(v.object);
    if (this.res) {
      this.posesMeshes(this.res);
      const c = this.res.collision;
      this.paintColliding(c && c.state === "ready" ? c.links : []);
    }
    // meshes arrive after the first picture: frame them too, unless the user has moved the camera since
    if (visuals.length && this.res && !this.userMoved) this.view("fit");
    this.render();
  }

  // The visuals of the links in `links` drawn in the colliding colour, the others in their own.
  paintColliding(links) {
    const on = new Set(links);
    let painted = 0;
    for (const v of this.visuals || []) {
      const red = on.has(v.link);
      painted += red ? 1 : 0;
      v.object.traverse((o) => {
        if (!o.isMesh) return;
        if (!o.userData.own) o.userData.own = o.material;
        o.material = red ? COLLIDING : o.userData.own;
      });
    }
    this.container.dataset.colliding = links.join(",");           // for tests
    this.container.dataset.collidingMeshes = String(painted);
  }

  posesMeshes(res) {
    if (!res.motions) return;
    for (const v of this.visuals || []) {
      v.object.matrixAutoUpdate = false;
      v.object.matrix.copy(mat4(res.motions[v.body]).multiply(mat4(v.pose)));
      v.object.matrixWorldNeedsUpdate = true;
    }
  }

  // ------------------------------------------------------------------ camera
  // Everything drawn of the robot at its shown pose: links, joint axes, tool frame, overlays, robot B,
  // difference arrows, the meshes, and the base frame (not the grid).
  bounds() {
    const box = new THREE.Box3().setFromObject(this.robot);
    if (this.visuals && this.visuals.length) box.union(new THREE.Box3().setFromObject(this.meshes));
    box.expandByPoint(new THREE.Vector3()).expandByPoint(new THREE.Vector3(1, 1, 1).multiplyScalar(TRIAD * this.scale));
    box.expandByScalar(0.03 * this.scale);  // the axis labels, beside their points
    return box;
  }

  // The camera distance along `d` (unit, from the centre c toward the camera) at which the whole box
  // is in the picture: for each corner, its offset across the view over the tangent of the half field
  // of view, plus its depth toward the camera (a perspective fit of the box, not of its sphere).
  fitDistance(box, c, d) {
    const cam = this.camera;
    cam.position.copy(c).add(d);
    cam.lookAt(c);
    cam.updateMatrixWorld();
    const right = new THREE.Vector3().setFromMatrixColumn(cam.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(cam.matrixWorld, 1);
    const tv = Math.tan(cam.fov * Math.PI / 360), th = tv * cam.aspect;
    let dist = 1e-6 * this.scale;
    for (let i = 0; i < 8; i++) {
      const q = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                  i & 4 ? box.max.z : box.min.z).sub(c);
      const z = q.dot(d);
      dist = Math.max(dist, z + Math.abs(q.dot(right)) / th, z + Math.abs(q.dot(up)) / tv);
    }
    return dist * 1.06;  // 6%: a margin inside the frame's edge
  }

  // Camera looking at the robot: "iso" (the reset view), "front" (from +x), "side" (from -y), "top"
  // (from +z), or "fit" (keep the direction, frame the robot).
  view(name, direction = null) {
    const box = this.bounds(), c = box.getCenter(new THREE.Vector3());
    // top: a hair off the vertical, where the orbit's z-up frame is singular
    const dirs = { iso: [1, -1.3, 0.8], front: [1, 0, 0], side: [0, -1, 0], top: [-1e-4, 0, 1] };
    const cur = this.camera.position.clone().sub(this.orbit.target);
    const d = direction ? v3(direction).normalize() :
      name === "fit" && cur.lengthSq() > 0 ? cur.normalize() : v3(dirs[name] || dirs.iso).normalize();
    const dist = this.fitDistance(box, c, d);
    this.userMoved = false;
    this.orbit.target.copy(c);
    this.camera.position.copy(c).addScaledVector(d, dist);
    this.camera.near = dist / 1000;
    this.camera.far = dist * 100;
    this.camera.updateProjectionMatrix();
    this.orbit.update();
    this.render();
  }

  // Camera from a direction given as elevation and azimuth in degrees (like matplotlib's view_init).
  look([elev, azim]) {
    const e = elev * Math.PI / 180, a = azim * Math.PI / 180;
    this.view("fit", [Math.cos(e) * Math.cos(a), Math.cos(e) * Math.sin(a), Math.sin(e)]);
  }

  render() {
    if (!this.renderer) return;
    this.renderer.render(this.scene, this.camera);
    const w = this.container.clientWidth, h = this.container.clientHeight;
    for (const { el, p } of this.labels) {
      const s = p.clone().project(this.camera);
      el.hidden = s.z > 1;
      el.style.left = ((s.x + 1) / 2 * w) + "px";
      el.style.top = ((1 - s.y) / 2 * h) + "px";
    }
    // where the tool frame (the gizmo's centre) is on screen, in CSS pixels of the view: for tests
    const t = this.target.position.clone().project(this.camera);
    this.container.dataset.toolXy = [(t.x + 1) / 2 * w, (1 - t.y) / 2 * h].map((v) => v.toFixed(1)).join(",");
    this.container.dataset.lookAt = this.orbit.target.toArray().map((v) => v.toPrecision(6)).join(",");
    this.container.dataset.frames = String(Number(this.container.dataset.frames || 0) + 1);
  }
}
