// The simulated cell in the 3D view (docs/simulator.md "The simulated cell"): the table,
// fixtures, conveyor belts, sensors' regions, the first cells' box obstacles and the parts,
// in robot coordinates (mm, Z up). A solid is placed by the centre of its bottom face and
// turned `rz` degrees about the vertical. `setParts` moves the parts where a simulated run
// carries and drops them (the debugger's `parts`); `resetParts` puts them back.
//
// For tests and curious students the view's container carries data-cell-parts (how many),
// data-cell-fixtures, and data-parts: {name: [x, y, z, held]} rounded to 0.1 mm.

import * as THREE from "three";

const DEG = Math.PI / 180;
const PART_COLOURS = [0xd97706, 0x0f766e, 0x7c3aed, 0xbe185d, 0x2563eb, 0x65a30d, 0xb45309, 0x0891b2];

function material(color, opacity = 1) {
  return new THREE.MeshStandardMaterial({ color, roughness: 0.6, metalness: 0.05, transparent: opacity < 1, opacity, depthWrite: opacity >= 1 });
}

/** A solid's mesh in a group whose origin is the centre of its bottom face. */
function solidMesh(solid, mat, edges = 0x334155) {
  const group = new THREE.Group();
  let geometry;
  let body;
  if (solid.shape === "cylinder") {
    const r = solid.diameter / 2;
    geometry = new THREE.CylinderGeometry(r, r, solid.height, 40);
    body = new THREE.Mesh(geometry, mat);
    body.rotation.x = Math.PI / 2; // three's cylinders stand on Y; ours on Z
    body.position.z = solid.height / 2;
  } else {
    const [sx, sy, sz] = solid.size;
    geometry = new THREE.BoxGeometry(sx, sy, sz);
    body = new THREE.Mesh(geometry, mat);
    body.position.z = sz / 2;
  }
  const outline = new THREE.LineSegments(new THREE.EdgesGeometry(geometry, 30), new THREE.LineBasicMaterial({ color: edges, transparent: true, opacity: 0.55 }));
  body.add(outline);
  group.add(body);
  place(group, solid.position, solid.rz ?? 0);
  return group;
}

function place(group, position, rz) {
  group.position.set(position[0], position[1], position[2]);
  group.rotation.z = (rz ?? 0) * DEG;
}

function regionMesh(lo, hi, color) {
  const size = [0, 1, 2].map((i) => Math.max(1, hi[i] - lo[i]));
  const geometry = new THREE.BoxGeometry(...size);
  const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.12, depthWrite: false }));
  mesh.position.set(...[0, 1, 2].map((i) => (lo[i] + hi[i]) / 2));
  mesh.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry), new THREE.LineBasicMaterial({ color })));
  return mesh;
}

export class CellScene {
  constructor(view) {
    this.view = view;
    this.group = new THREE.Group();
    view.root.add(this.group);
    this.cell = null;
    this.partMeshes = new Map();
  }

  /** Draw `cell` (its JSON form) from scratch; the parts where the cell puts them. */
  setCell(cell) {
    this.cell = cell;
    this.group.clear();
    this.partMeshes.clear();
    if (cell.floor_z != null) {
      const table = new THREE.Mesh(new THREE.PlaneGeometry(1600, 1600), new THREE.MeshBasicMaterial({ color: 0x8b5e34, transparent: true, opacity: cell.floor_z > 1 ? 0.22 : 0.08, side: THREE.DoubleSide, depthWrite: false }));
      table.position.z = cell.floor_z;
      this.group.add(table);
    }
    for (const f of cell.fixtures ?? []) this.group.add(solidMesh(f, material(0xc8a978), 0x6b5433));
    for (const c of cell.conveyors ?? []) {
      const belt = solidMesh({ shape: "box", size: c.size, position: c.position }, material(0x475569), 0x0f172a);
      // an arrow on the belt's top: which way it carries
      const [vx, vy] = c.velocity;
      const speed = Math.hypot(vx, vy);
      if (speed > 0) {
        const dir = new THREE.Vector3(vx / speed, vy / speed, 0);
        const arrow = new THREE.ArrowHelper(dir, new THREE.Vector3(0, 0, c.size[2] + 2), Math.min(c.size[0], c.size[1], 200) * 0.8, 0xfacc15, 30, 20);
        arrow.position.sub(dir.clone().multiplyScalar(Math.min(c.size[0], c.size[1], 200) * 0.4));
        belt.add(arrow);
      }
      this.group.add(belt);
    }
    for (const s of cell.sensors ?? []) this.group.add(regionMesh(s.min, s.max, 0x16a34a));
    for (const b of cell.boxes ?? []) this.group.add(regionMesh(b.min, b.max, 0xdc2626));
    (cell.parts ?? []).forEach((p, i) => {
      const mesh = solidMesh(p, material(PART_COLOURS[i % PART_COLOURS.length]));
      mesh.userData.part = p;
      this.partMeshes.set(p.name, mesh);
      this.group.add(mesh);
    });
    const grip = cell.gripper?.grip ?? 0;
    this.view.setJawReach(grip > 40 ? grip + 5 : 88); // fingers round a held part's middle
    const data = this.view.container.dataset;
    data.cellBoxes = String((cell.boxes ?? []).length);
    data.cellFloor = cell.floor_z == null ? "" : String(cell.floor_z);
    data.cellParts = String((cell.parts ?? []).length);
    data.cellFixtures = String((cell.fixtures ?? []).length);
    this.resetParts();
  }

  /** Where a run has the parts: [{name, position, rz, held}] (unknown names are skipped). */
  setParts(states) {
    for (const s of states) {
      const mesh = this.partMeshes.get(s.name);
      if (!mesh) continue;
      place(mesh, s.position, s.rz);
      mesh.userData.held = s.held;
    }
    this.publish(states);
  }

  /** The parts back where the cell puts them (no run, or a run ended). */
  resetParts() {
    const states = (this.cell?.parts ?? []).map((p) => ({ name: p.name, position: p.position, rz: p.rz ?? 0, held: false }));
    this.setParts(states);
  }

  publish(states) {
    const round = (v) => Math.round(v * 10) / 10;
    this.view.container.dataset.parts = JSON.stringify(Object.fromEntries(states.map((s) => [s.name, [...s.position.map(round), s.held ? 1 : 0]])));
    this.view.requestRender();
  }

  /** The part under a click on the 3D view's canvas (for the cell editor), or null. */
  partAt(event) {
    const canvas = this.view.renderer?.domElement;
    if (!canvas) return null;
    const rect = canvas.getBoundingClientRect();
    const pointer = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(pointer, this.view.camera);
    const hits = ray.intersectObjects([...this.partMeshes.values()], true);
    let object = hits[0]?.object;
    while (object && !object.userData.part) object = object.parent;
    return object?.userData.part ?? null;
  }
}
