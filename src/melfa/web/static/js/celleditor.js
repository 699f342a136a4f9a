// The cell editor for instructors (docs/ide.md "The lab's cell"): a form for the table,
// the gripper, the fixtures and the parts, and the cell's JSON underneath (sensors,
// conveyors and anything else), side by side with the 3D view, which shows every change
// as it is typed. "Start from the thesis's bench" loads the shipped template. The server
// checks the cell when it is saved and says what is wrong in the instructor's words.

import { POSE_NAMES } from "/model/controller.js"; // generated from melfa.protocol
import { api } from "./api.js";
import { el, toast } from "./ui.js";

const GRIPPER = [
  ["hand", "Hand", "The HOPEN/HCLOSE number that works the gripper", 1],
  ["grip", "Grip (mm)", "From the flange along its Z axis to where a held part's centre is", 1],
  ["tolerance", "Tolerance (mm)", "How far a part's centre may be from the grip point when the hand closes", 1],
  ["length", "Body length (mm)", "The gripper's body from the flange, checked for collisions (end it above a held part)", 1],
  ["radius", "Body radius (mm)", "The body's radius", 1],
];

const num = (v) => (v === "" || v == null ? NaN : Number(v));
const clone = (v) => JSON.parse(JSON.stringify(v));

export class CellEditor {
  /** `scene` is the 3D view's CellScene; `onSaved(cell)` gets the cell the server kept. */
  constructor(scene, onSaved) {
    this.scene = scene;
    this.onSaved = onSaved;
    this.dialog = null;
  }

  open(cell) {
    this.dialog?.remove();
    this.original = clone(cell);
    this.draft = clone(cell);
    this.draft.gripper = { hand: 1, grip: 0, tolerance: 10, length: 0, radius: 30, ...(cell.gripper ?? {}) };
    for (const key of ["fixtures", "parts", "sensors", "conveyors", "boxes"]) this.draft[key] ??= [];
    const dialog = el("dialog", { id: "cell-dialog", class: "cell-editor", "aria-labelledby": "cell-title" });
    this.dialog = dialog;
    this.problem = el("p", { class: "form-problems", id: "cell-problem", "aria-live": "polite" });
    this.json = el("textarea", { id: "cell-json", rows: "16", spellcheck: "false", "aria-label": "The cell as JSON" });
    this.json.addEventListener("input", () => this.fromJson(false));
    this.formPane = el("div", { class: "cell-form", id: "cell-form" });
    this.jsonPane = el("div", { class: "cell-json", id: "cell-json-pane", hidden: true }, this.json,
      el("p", { class: "help" }, "Millimetres in the robot's base frame (Z up, 0 at its mounting surface). The format is in docs/simulator.md."));
    const tab = (id, label, pane) => {
      const b = el("button", { type: "button", role: "tab", class: "cell-tab", id, "aria-selected": "false" }, label);
      b.addEventListener("click", () => this.show(pane));
      return b;
    };
    this.tabs = { form: tab("cell-tab-form", "Form", "form"), json: tab("cell-tab-json", "JSON", "json") };
    const template = el("button", { type: "button", class: "btn btn-sm", id: "cell-template", title: "The thesis's bench and its six blocks, for examples/pyramid.MB4" }, "Start from the thesis's bench");
    template.addEventListener("click", () => this.loadTemplate("thesis-bench"));
    const save = el("button", { type: "button", class: "btn btn-primary", id: "cell-save" }, "Save cell");
    const cancel = el("button", { type: "button", class: "btn", id: "cell-cancel" }, "Cancel");
    cancel.addEventListener("click", () => this.close(this.original));
    save.addEventListener("click", () => this.save());
    dialog.append(
      el("div", { class: "cell-head" }, el("h2", { id: "cell-title" }, "The lab's cell"), template),
      el("p", { class: "help" }, "Pre-flight and every student's simulator run programs in this cell: the 3D view shows your changes as you type. Click a part in the 3D view to find its row."),
      el("div", { class: "cell-tabs", role: "tablist" }, this.tabs.form, this.tabs.json),
      this.formPane, this.jsonPane, this.problem, el("div", { class: "dialog-actions" }, cancel, save));
    document.body.append(dialog);
    dialog.show(); // not modal: the 3D view beside it stays live
    this.pick = (event) => this.select(this.scene.partAt(event));
    this.scene.view.renderer?.domElement.addEventListener("click", this.pick);
    this.buildForm();
    this.show("form");
    this.preview();
  }

  close(cell) {
    this.scene.view.renderer?.domElement.removeEventListener("click", this.pick);
    this.dialog?.remove();
    this.dialog = null;
    if (cell) this.scene.setCell(cell);
  }

  show(pane) {
    if (pane === "form" && !this.fromJson(true)) return;
    if (pane === "json") this.json.value = JSON.stringify(this.draft, null, 2);
    this.formPane.hidden = pane !== "form";
    this.jsonPane.hidden = pane !== "json";
    for (const [name, b] of Object.entries(this.tabs)) b.setAttribute("aria-selected", String(name === pane));
    this.dialog.dataset.pane = pane;
  }

  /** The JSON text into the draft (and the form when `rebuild`); false when it is not JSON. */
  fromJson(rebuild) {
    if (this.jsonPane.hidden) return true;
    try {
      const parsed = JSON.parse(this.json.value);
      if (!parsed || typeof parsed !== "object" || Array.isArray(parsed)) throw new Error("a cell is a JSON object");
      this.draft = parsed;
      for (const key of ["fixtures", "parts", "sensors", "conveyors", "boxes"]) this.draft[key] ??= [];
      this.draft.gripper ??= {};
      this.problem.textContent = "";
    } catch (err) {
      this.problem.textContent = `Not JSON: ${err.message}`;
      return false;
    }
    if (rebuild) this.buildForm();
    this.preview();
    return true;
  }

  preview() {
    try {
      this.scene.setCell(this.draft);
    } catch {
      // a half-typed solid (no size yet) is drawn once it is complete
    }
  }

  async loadTemplate(name) {
    try {
      this.draft = await api("GET", `/api/preflight/templates/${name}`);
      this.problem.textContent = "";
      this.buildForm();
      this.json.value = JSON.stringify(this.draft, null, 2);
      this.preview();
    } catch (err) {
      this.problem.textContent = err.message;
    }
  }

  async save() {
    if (!this.fromJson(false)) return;
    try {
      const out = await api("PUT", "/api/preflight/cell", this.draft);
      this.close(out.cell);
      this.onSaved(out.cell);
      const gate = out.require_simulation // what passed in the old cell no longer counts (the gate)
        ? " The gate is on: a program that passed before runs on the lab robot only once it passes pre-flight again in this cell."
        : "";
      toast("Cell saved", { kind: "ok", text: "Pre-flight and the simulators use it from now on." + gate });
    } catch (err) {
      this.problem.textContent = err.message;
    }
  }

  // ---- the form ----
  buildForm() {
    const d = this.draft;
    const floorOn = el("input", { type: "checkbox", id: "cell-floor-on", checked: d.floor_z != null });
    const floor = el("input", { type: "number", id: "cell-floor", step: "1", value: d.floor_z ?? 0, disabled: d.floor_z == null, "aria-label": "Table height (mm)" });
    const syncFloor = () => {
      floor.disabled = !floorOn.checked;
      d.floor_z = floorOn.checked ? num(floor.value) || 0 : null;
      this.preview();
    };
    floorOn.addEventListener("change", syncFloor);
    floor.addEventListener("input", syncFloor);
    const gripper = el("div", { class: "cell-grid" }, ...GRIPPER.map(([key, label, title, step]) => {
      const input = el("input", { type: "number", step: String(step), id: `cell-gripper-${key}`, value: d.gripper[key] ?? "", title });
      input.addEventListener("input", () => { d.gripper[key] = num(input.value); this.preview(); });
      return el("label", { title }, label, input);
    }));
    const extras = [["sensors", "sensor"], ["conveyors", "conveyor"], ["boxes", "box obstacle"]]
      .map(([key, word]) => [d[key].length, word]).filter(([n]) => n)
      .map(([n, word]) => `${n} ${word}${n === 1 ? "" : "s"}`);
    this.formPane.replaceChildren(
      el("fieldset", {}, el("legend", {}, "Table"), el("label", { class: "check" }, floorOn, " Check the table plane at"), floor, " mm"),
      el("fieldset", {}, el("legend", {}, "Gripper"), gripper),
      this.solids("fixtures", "Fixtures", "fixture"),
      this.solids("parts", "Parts", "part"),
      el("p", { class: "help", id: "cell-extras" }, extras.length ? `Also ${extras.join(", ")}: edit them in JSON.` : "Sensors and conveyors: add them in JSON (docs/simulator.md)."),
    );
  }

  /** A table of solids (fixtures or parts): name, shape, size, position, heading. */
  solids(key, title, word) {
    const list = this.draft[key];
    const body = el("tbody", {});
    const [x, y, z] = POSE_NAMES;
    const head = el("tr", {}, ...["Name", "Shape", `${x} size / ⌀`, `${y} size`, "Height", x, y, z, "Turn °", ""].map((h) => el("th", { scope: "col" }, h)));
    list.forEach((solid, index) => body.append(this.solidRow(key, solid, index)));
    const add = el("button", { type: "button", class: "btn btn-sm", id: `cell-add-${word}` }, `Add a ${word}`);
    add.addEventListener("click", () => {
      const n = list.length + 1;
      list.push(key === "parts"
        ? { name: `part ${n}`, shape: "cylinder", diameter: 50, height: 25, position: [400, 0, 0] }
        : { name: `fixture ${n}`, shape: "box", size: [200, 200, 100], position: [450, 0, 0] });
      this.buildForm();
      this.preview();
    });
    return el("fieldset", { id: `cell-${key}` }, el("legend", {}, `${title} (${list.length})`),
      el("table", { class: "cell-solids" }, el("thead", {}, head), body), add);
  }

  solidRow(key, solid, index) {
    const row = el("tr", { "data-name": solid.name });
    const cyl = solid.shape === "cylinder";
    const cell = (value, label, onInput, attrs = {}) => {
      const input = el("input", { value: value ?? "", "aria-label": `${solid.name}: ${label}`, ...attrs });
      input.addEventListener("input", () => { onInput(input.value); this.preview(); });
      return el("td", {}, input);
    };
    const number = (value, label, set) => cell(value, label, (v) => set(num(v)), { type: "number", step: "any" });
    const shape = el("select", { "aria-label": `${solid.name}: shape` }, el("option", { value: "box", selected: !cyl }, "box"), el("option", { value: "cylinder", selected: cyl }, "cylinder"));
    shape.addEventListener("change", () => {
      const size = cyl ? [solid.diameter, solid.diameter, solid.height] : solid.size;
      delete solid.size; delete solid.diameter; delete solid.height;
      solid.shape = shape.value;
      if (shape.value === "cylinder") Object.assign(solid, { diameter: size[0], height: size[2] });
      else solid.size = size;
      this.buildForm();
      this.preview();
    });
    const remove = el("button", { type: "button", class: "btn btn-sm btn-icon", "aria-label": `Remove ${solid.name}` }, "✕");
    remove.addEventListener("click", () => { this.draft[key].splice(index, 1); this.buildForm(); this.preview(); });
    solid.position ??= [0, 0, 0];
    row.append(
      cell(solid.name, "name", (v) => { solid.name = v; row.dataset.name = v; }),
      el("td", {}, shape),
      number(cyl ? solid.diameter : solid.size?.[0], cyl ? "diameter" : `${POSE_NAMES[0]} size`, (v) => { if (cyl) solid.diameter = v; else solid.size[0] = v; }),
      cyl ? el("td", { class: "same" }, "=") : number(solid.size?.[1], `${POSE_NAMES[1]} size`, (v) => { solid.size[1] = v; }),
      number(cyl ? solid.height : solid.size?.[2], "height", (v) => { if (cyl) solid.height = v; else solid.size[2] = v; }),
      ...[0, 1, 2].map((i) => number(solid.position[i], POSE_NAMES[i], (v) => { solid.position[i] = v; })),
      number(solid.rz ?? 0, "turn", (v) => { solid.rz = v; }),
      el("td", {}, remove),
    );
    return row;
  }

  /** A part clicked in the 3D view: show its row. */
  select(part) {
    if (!part || !this.dialog) return;
    this.show("form");
    for (const row of this.formPane.querySelectorAll("tr.selected")) row.classList.remove("selected");
    const row = [...this.formPane.querySelectorAll("#cell-parts tr[data-name]")].find((r) => r.dataset.name === part.name);
    if (!row) return;
    row.classList.add("selected");
    row.scrollIntoView({ block: "nearest" });
    row.querySelector("input")?.focus();
  }
}
