// The robot's visuals as three.js objects: meshes fetched by the id the server gave them (GET
// /api/mesh/<id>, or the URL urlOf(id) gives, e.g. a blob in the self-contained page; STL, COLLADA or
// OBJ) and primitive shapes. Each comes back with the body it moves
// with and its pose at home in the base frame; viewer.js places it at q with the body's motion.
import * as THREE from "three";
import { STLLoader } from "three/addons/loaders/STLLoader.js";
import { ColladaLoader } from "three/addons/loaders/ColladaLoader.js";
import { OBJLoader } from "three/addons/loaders/OBJLoader.js";

const GREY = [0.7, 0.7, 0.72, 1];

function material(rgba) {
  const c = rgba || GREY;
  return new THREE.MeshStandardMaterial({ color: new THREE.Color(c[0], c[1], c[2]), opacity: c[3],
                                          transparent: c[3] < 1, roughness: 0.55, metalness: 0.1 });
}

const serverUrl = (id) => "/api/mesh/" + encodeURIComponent(id);

async function meshObject(v, urlOf) {
  const url = urlOf(v.mesh);
  if (v.format === "stl") {
    const geometry = await new STLLoader().loadAsync(url);
    geometry.computeVertexNormals();
    return new THREE.Mesh(geometry, material(v.rgba));
  }
  if (v.format === "dae") {
    const dae = await new ColladaLoader().loadAsync(url);
    // URDF meshes are in their link's frame, z up: undo the loader's turn of Z_UP files into y-up
    dae.scene.rotation.set(0, 0, 0);
    if (v.rgba) dae.scene.traverse((o) => { if (o.isMesh) o.material = material(v.rgba); });
    return dae.scene;
  }
  const obj = await new OBJLoader().loadAsync(url);
  obj.traverse((o) => { if (o.isMesh) o.material = material(v.rgba); });
  return obj;
}

function primitive(v) {
  const s = v.size;
  const geometry = v.kind === "box" ? new THREE.BoxGeometry(s[0], s[1], s[2]) :
    v.kind === "sphere" ? new THREE.SphereGeometry(s[0], 24, 16) :
    v.kind === "capsule" ? new THREE.CapsuleGeometry(s[0], s[1], 8, 24).rotateX(Math.PI / 2) :
    new THREE.CylinderGeometry(s[0], s[0], s[1], 24).rotateX(Math.PI / 2);  // cylinders, capsules lie along z
  return new THREE.Mesh(geometry, material(v.rgba));
}

// visuals: the server's list (robkin.viz.meshes.MeshRegistry.visuals) -> [{body, link, pose, object}].
export async function loadVisuals(visuals, urlOf = serverUrl) {
  return Promise.all(visuals.map(async (v) => {
    const inner = v.kind === "mesh" ? await meshObject(v, urlOf) : primitive(v);
    if (v.kind === "mesh") inner.scale.multiply(new THREE.Vector3(...v.size));
    const object = new THREE.Group();
    object.add(inner);
    return { body: v.body, link: v.link, pose: v.pose, object };
  }));
}
