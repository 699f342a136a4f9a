// The RV-6S in 3D, built from its standard DH table (docs rv6s.md §4):
//   T_i = Rz(θi)·Tz(di)·Tx(ai)·Rx(αi),  θi = qi + offset_i  (mm, degrees).
// Each joint is a group that rotates about its local Z (Rz(θi)); a fixed child applies
// Tz(di)·Tx(ai)·Rx(αi). Link geometry hangs on the rotating group, so it moves with its
// joint. Check: q = (0,0,90,0,90,0) puts the flange at (400, 0, 645) pointing down.
// The robot's frame is Z-up in mm; the scene is Y-up in metres (one rotation at the root).

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

import { DH, HOME } from "/model/rv6s.js"; // generated from melfa.kin: one DH table

const DEG = Math.PI / 180;

/** Materials: light grey castings, dark joint covers, a blue accent on the gripper. */
function materials() {
  const std = (color, roughness = 0.55, metalness = 0.1) => new THREE.MeshStandardMaterial({ color, roughness, metalness });
  return { body: std(0xe8ebef, 0.45), dark: std(0x3b4552, 0.6), base: std(0x59636f, 0.7, 0.2), steel: std(0xa9b2bd, 0.35, 0.6), accent: std(0x1f5fbf, 0.5) };
}

/** A cylinder along local Z from z0 to z1 (three's cylinders stand on Y). */
function cylZ(radius, z0, z1, material, radiusTop = radius) {
  const mesh = new THREE.Mesh(new THREE.CylinderGeometry(radiusTop, radius, Math.abs(z1 - z0), 40), material);
  mesh.rotation.x = Math.PI / 2;
  mesh.position.z = (z0 + z1) / 2;
  if (z1 < z0) mesh.rotation.x = -Math.PI / 2;
  return mesh;
}

/** A cylinder along local Y centred at (x, y, z). */
function cylY(radius, length, material, x = 0, y = 0, z = 0) {
  const mesh = new THREE.Mesh(new THREE.CylinderGeometry(radius, radius, length, 40), material);
  mesh.position.set(x, y, z);
  return mesh;
}

/** A rounded box from (x0,y0,z0) to (x1,y1,z1). */
function box(x0, x1, y0, y1, z0, z1, material) {
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(x1 - x0, y1 - y0, z1 - z0), material);
  mesh.position.set((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
  return mesh;
}

export class RobotView {
  constructor(container) {
    this.container = container;
    this.joints = HOME.slice();
    this.handOpen = true;
    this.path = [];
    try {
      this.renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true });
    } catch (err) {
      container.append(Object.assign(document.createElement("div"), { className: "nogl", textContent: "3D view unavailable: this browser has no WebGL. Joint values are still shown below." }));
      this.renderer = null;
    }
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 50);
    this.build();
    if (this.renderer) {
      this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
      container.append(this.renderer.domElement);
      this.renderer.domElement.setAttribute("aria-hidden", "true");
      this.controls = new OrbitControls(this.camera, this.renderer.domElement);
      this.controls.enableDamping = true;
      this.controls.addEventListener("change", () => this.requestRender());
      this.resetView();
      new ResizeObserver(() => this.resize()).observe(container);
      this.resize();
    }
    this.setJoints(HOME);
  }

  build() {
    const scene = this.scene;
    scene.add(new THREE.HemisphereLight(0xffffff, 0xb9c2cc, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(2, 4, 3);
    scene.add(sun);
    const fill = new THREE.DirectionalLight(0xffffff, 0.5);
    fill.position.set(-3, 2, -2);
    scene.add(fill);

    const grid = new THREE.GridHelper(2, 20, 0x8d99a6, 0xc6ced7); // 10 cm squares, 2 m
    scene.add(grid);
    const axes = new THREE.AxesHelper(0.25); // red X, green Y(up in three = robot Z)…
    scene.add(axes);

    // Robot root: Z-up mm → Y-up m.
    const root = new THREE.Group();
    root.rotation.x = -Math.PI / 2;
    root.scale.setScalar(0.001);
    scene.add(root);
    this.root = root;
    // The robot's own axes (X red, Y green, Z blue) at its base, in robot coordinates.
    const robotAxes = new THREE.AxesHelper(250);
    robotAxes.position.z = 1;
    root.add(robotAxes);
    scene.remove(axes);

    const m = materials();
    this.materials = m;
    // Base pedestal (fixed).
    root.add(cylZ(125, 0, 30, m.base));
    root.add(cylZ(105, 30, 170, m.dark, 100));

    this.rot = [];
    let parent = root;
    DH.forEach((p, i) => {
      const rot = new THREE.Group(); // Rz(θi)
      const fixed = new THREE.Group(); // Tz(d)·Tx(a)·Rx(α)
      fixed.matrixAutoUpdate = false;
      fixed.matrix.copy(
        new THREE.Matrix4().makeTranslation(p.a, 0, p.d).multiply(new THREE.Matrix4().makeRotationX(p.alpha * DEG)),
      );
      parent.add(rot);
      rot.add(fixed);
      this.rot.push(rot);
      parent = fixed;
    });
    this.flange = parent;

    // Link 1 (turns with J1): turret and shoulder housing; J2 axis along this frame's Y.
    const [r1, r2, r3, r4, r5, r6] = this.rot;
    r1.add(cylZ(98, 170, 270, m.body, 92));
    r1.add(box(-40, 135, -85, 85, 250, 420, m.body));
    r1.add(cylY(95, 230, m.dark, 85, 0, 350));
    // Link 2 (J2): upper arm along +X (280 mm), housings at both ends (axes along Z here).
    r2.add(box(0, 280, -55, 55, 40, 130, m.body));
    r2.add(cylZ(80, 40, 140, m.body));
    const elbowCover = cylZ(68, 30, 140, m.body);
    elbowCover.position.x = 280;
    r2.add(elbowCover);
    // Link 3 (J3): elbow, offset 100 along X; forearm root along +Y of this frame (the J4 axis).
    r3.add(cylZ(70, -60, 60, m.dark));
    r3.add(box(-30, 130, -10, 130, -65, 65, m.body));
    // Link 4 (J4 roll): forearm along Z to the wrist centre at 315.
    r4.add(cylZ(62, 0, 220, m.body, 50));
    r4.add(box(-48, 48, -62, 62, 200, 290, m.body));
    // Link 5 (J5): wrist housing, axis along this frame's Z.
    r5.add(cylZ(46, -58, 58, m.dark));
    // Link 6 (J6): flange along Z (85 mm) with the gripper on the flange frame.
    r6.add(cylZ(36, 20, 78, m.body));
    r6.add(cylZ(40, 78, 85, m.steel));
    const gripper = new THREE.Group();
    gripper.add(box(-45, 45, -22, 22, 0, 28, m.dark));
    this.jaws = [box(-8, 8, -16, 16, 28, 88, m.accent), box(-8, 8, -16, 16, 28, 88, m.accent)];
    for (const jaw of this.jaws) gripper.add(jaw);
    this.flange.add(gripper);
    this.tcpAxes = new THREE.AxesHelper(60);
    this.flange.add(this.tcpAxes);
    // The jog frame's axes at the tool: base-aligned for XYZ, turning with the hand for
    // Tool, none for Joint (setFrame).
    this.baseAxesAtTool = new THREE.AxesHelper(80);
    this.baseAxesAtTool.visible = false;
    root.add(this.baseAxesAtTool);

    // The program's path (TCP positions while it runs), in robot coordinates.
    this.pathGeometry = new THREE.BufferGeometry();
    this.pathLine = new THREE.Line(this.pathGeometry, new THREE.LineBasicMaterial({ color: 0xd97706 }));
    this.pathLine.frustumCulled = false;
    root.add(this.pathLine);
  }

  resetView() {
    // From the front-left of the robot (its -Y side), a little above the table.
    this.camera.position.set(0.95, 0.85, 1.55);
    this.controls?.target.set(0.2, 0.4, 0);
    this.controls?.update();
    this.requestRender();
  }

  resize() {
    if (!this.renderer) return;
    const { clientWidth: w, clientHeight: h } = this.container;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  /** Pose the arm (controller joint values, degrees). */
  /** The controller shows **** (origin or encoders not set): say so over the arm, which
   * stays drawn where it was last known. */
  setPositionKnown(known) {
    this.container.dataset.positionUnknown = known ? "" : "true";
    let note = this.container.querySelector(".position-unknown");
    if (known) {
      note?.remove();
      return;
    }
    if (!note) {
      note = Object.assign(document.createElement("div"), {
        className: "position-unknown",
        textContent: "Position unknown: the controller shows **** (origin or encoder data not set). The arm is drawn where it was last known.",
      });
      note.setAttribute("role", "status");
      this.container.append(note);
    }
  }

  setJoints(joints) {
    if (!joints || joints.length < 6) return;
    this.joints = joints.slice(0, 6);
    this.rot.forEach((rot, i) => (rot.rotation.z = (this.joints[i] + DH[i].offset) * DEG));
    this.root.updateMatrixWorld(true);
    // For tests and curious students: the joints shown, and the flange computed by the chain.
    const flange = this.flangePosition();
    this.container.dataset.joints = JSON.stringify(this.joints.map((v) => Math.round(v * 100) / 100));
    this.container.dataset.flange = JSON.stringify(flange.map((v) => Math.round(v * 10) / 10));
    this.baseAxesAtTool?.position.set(...flange);
    this.requestRender();
  }

  /** Flange position in robot coordinates (mm) from the scene graph. */
  flangePosition() {
    const world = new THREE.Vector3().setFromMatrixPosition(this.flange.matrixWorld);
    const inv = new THREE.Matrix4().copy(this.root.matrixWorld).invert();
    const p = world.applyMatrix4(inv);
    return [p.x, p.y, p.z];
  }

  /** Show the jog frame's axes (X red, Y green, Z blue) at the tool. */
  setFrame(frame) {
    this.jogFrame = frame;
    this.tcpAxes.visible = frame === "tool";
    this.baseAxesAtTool.visible = frame === "xyz";
    this.baseAxesAtTool.position.set(...this.flangePosition());
    this.container.dataset.frameAxes = frame;
    this.requestRender();
  }

  setHand(open) {
    if (open == null) return;
    this.handOpen = open;
    const gap = open ? 38 : 14;
    this.jaws[0].position.x = -gap;
    this.jaws[1].position.x = gap;
    this.container.dataset.hand = open ? "open" : "closed";
    this.requestRender();
  }

  /** The jaws reach `mm` below the flange (the cell's gripper holds parts there). */
  setJawReach(mm) {
    const length = Math.max(20, mm - 28); // the jaws hang from the gripper's body at 28 mm
    for (const jaw of this.jaws) {
      jaw.scale.z = length / 60;
      jaw.position.z = 28 + length / 2;
    }
    this.requestRender();
  }

  /** Add a TCP sample (X, Y, Z mm) to the drawn path. */
  addPathPoint(xyz) {
    const last = this.path.at(-1);
    if (last && Math.hypot(last[0] - xyz[0], last[1] - xyz[1], last[2] - xyz[2]) < 1) return;
    this.path.push(xyz.slice(0, 3));
    if (this.path.length > 20000) this.path.splice(0, 5000);
    this.pathGeometry.setAttribute("position", new THREE.Float32BufferAttribute(this.path.flat(), 3));
    this.pathGeometry.computeBoundingSphere();
    this.container.dataset.pathPoints = String(this.path.length);
    this.requestRender();
  }

  clearPath() {
    this.path = [];
    this.pathGeometry.setAttribute("position", new THREE.Float32BufferAttribute([], 3));
    this.container.dataset.pathPoints = "0";
    this.requestRender();
  }

  /** Render on demand (and while the orbit controls are damping), not 60 fps forever. */
  requestRender() {
    if (!this.renderer || this.frame) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = null;
      const moved = this.controls?.update();
      this.renderer.render(this.scene, this.camera);
      if (moved) this.requestRender();
    });
  }
}
