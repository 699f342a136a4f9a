// Pre-flight in the IDE (docs/ide.md "Pre-flight"): a simulated run of the editor's program
// checked before the real arm moves. The report lists each finding with its line (click:
// the editor goes there); the 3D view shows the simulated path as a ghost over the arm,
// coloured where a finding happens (red: error, amber: warning), and the lab's cell (the
// table, fixtures, parts: cellview.js), which instructors edit here (celleditor.js). When the lab's gate refuses a
// program, `offer` explains why and offers the simulation.

import * as THREE from "three";
import { api } from "./api.js";
import { CellEditor } from "./celleditor.js";
import { CellScene } from "./cellview.js";
import { $, el, onFix, showError, toast } from "./ui.js";
import { QUEUE_WORDS, REFUSAL_ASKED } from "/vocab.js"; // generated from melfa.vocab

const COLOURS = { ok: 0x2563eb, error: 0xdc2626, warning: 0xf59e0b };

export class PreflightPanel {
  constructor(app) {
    this.app = app;
    this.report = null;
    this.cell = null;
    this.gate = false;
    this.group = new THREE.Group(); // the ghost path, in robot coordinates (mm)
    app.view.root.add(this.group);
    app.cell = new CellScene(app.view); // the lab's cell: the debugger moves its parts
    this.editor = new CellEditor(app.cell, (cell) => { this.cell = cell; });
    this.build();
    this.load();
    onFix("preflight", ({ err }) => this.offer(err)); // the gate's refusal: its button runs this
    // The gate refused (an instructor edited the cell since): the report's pass is no
    // longer what lets the lab robot run it.
    document.addEventListener("melfa:fix-offered", (e) => e.detail === "preflight" && this.noLongerCounts());
  }

  /** The report's pass no longer lets the lab robot run the text (the cell was edited). */
  noLongerCounts() {
    if (this.report) this.summarize(false);
  }

  build() {
    const run = el("button", { type: "button", class: "btn", id: "act-preflight", title: "Run the program on a simulated arm and check it before the robot moves" },
      el("span", { class: "ico", "aria-hidden": "true" }, "✈"), " Pre-flight");
    run.addEventListener("click", () => this.run());
    $("act-check").after(run);
    this.ghost = el("input", { type: "checkbox", id: "ghost-toggle", checked: true });
    this.ghost.addEventListener("change", () => { this.group.visible = this.ghost.checked; this.app.view.requestRender(); });
    const editCell = el("button", { type: "button", class: "btn btn-sm", id: "cell-edit", hidden: true, title: "The table, fixtures and parts that pre-flight and the simulators use" }, "Cell…");
    editCell.addEventListener("click", () => this.editCell());
    // In the 3D view's corner tools, before its own buttons.
    $("path-clear").before(el("label", { class: "check ghost-label", title: "The path of the last pre-flight, over the arm" }, this.ghost, " Simulated path"), editCell);
    this.list = el("ul", { id: "preflight-findings" });
    this.summary = el("p", { class: "pf-summary", id: "preflight-summary" });
    const close = el("button", { type: "button", class: "btn btn-sm btn-icon", "aria-label": "Close the pre-flight report" }, "✕");
    close.addEventListener("click", () => this.clear());
    this.panel = el("section", { class: "preflight", id: "preflight", "aria-label": "Pre-flight report", hidden: true },
      el("div", { class: "pf-head" }, el("strong", {}, "Pre-flight"), this.summary, close), this.list);
    $("problems").before(this.panel);
  }

  async load() {
    try {
      const out = await api("GET", "/api/preflight");
      this.gate = out.require_simulation;
      this.setCell(out.cell);
      $("cell-edit").hidden = !(this.app.role === "instructor" || this.app.role === "admin");
      document.body.dataset.gate = this.gate ? "on" : "off";
    } catch (err) {
      showError("Could not read the lab's cell", err);
    }
  }

  async run() {
    const app = this.app;
    const button = $("act-preflight");
    button.disabled = true;
    app.busy("Pre-flight: simulating…");
    try {
      const out = await api("POST", "/api/preflight", { program: app.editor.text, points: app.workspace.points, check: true });
      this.setCell(out.cell);
      this.show(out.report, out.passed);
      app.idle(out.passed ? "Pre-flight passed" : "Pre-flight found errors", !out.passed);
      return out.passed;
    } catch (err) {
      app.idle("Pre-flight failed", true);
      if (err.code === "program-has-errors" && err.detail?.diagnostics) app.editor.show(err.detail.diagnostics);
      showError("Could not run pre-flight", err);
      return false;
    } finally {
      button.disabled = false;
    }
  }

  /** The report's one line; `mayRun`: the gate is on and this pass opens it. */
  summarize(mayRun) {
    const report = this.report;
    const errors = report.findings.filter((f) => f.severity === "error").length;
    const warnings = report.findings.length - errors;
    const cycle = report.cycle_time != null ? `cycle time ${report.cycle_time.toFixed(2)} s` : "did not reach END";
    this.summary.textContent = `${errors ? `${errors} error${errors > 1 ? "s" : ""}` : "no errors"}, ${warnings} warning${warnings === 1 ? "" : "s"} · ${cycle}` + (mayRun ? " · the lab robot may run it" : "");
    this.panel.dataset.mayRun = String(mayRun);
  }

  show(report, passed) {
    this.report = report;
    this.panel.hidden = false;
    this.panel.dataset.passed = String(passed);
    this.summarize(passed && this.gate);
    const tight = report.joints.filter((j) => j.margin != null && j.margin < 15).map((j) => `J${j.joint} comes within ${j.margin.toFixed(1)}° of its limit`);
    this.list.replaceChildren(
      ...report.findings.map((f) => {
        const item = el("li", { class: `pf-${f.severity}`, "data-line": f.line ?? "" },
          el("span", { class: "pf-sev" }, f.severity), " ",
          f.line ? el("button", { type: "button", class: "linkish pf-line" }, `line ${f.line}`) : null, " ",
          f.message.replace(/^line \d+: /, ""));
        item.querySelector(".pf-line")?.addEventListener("click", () => this.goTo(f.line));
        return item;
      }),
      ...(report.findings.length ? [] : [el("li", { class: "pf-ok" }, "Nothing to fix: the arm stays in its limits, above the table and out of the obstacles.")]),
      ...tight.map((t) => el("li", { class: "pf-note" }, t)),
      ...(report.parts ?? []).map((p) => el("li", { class: "pf-note pf-part", "data-part": p.name },
        `${p.name} ends at (${p.position.map((v) => v.toFixed(1)).join(", ")})`, p.held ? " in the gripper" : ` on ${p.on}`)),
    );
    this.drawPath(report);
  }

  goTo(line) {
    const editor = this.app.editor.editor;
    editor.gotoLine(line, 0, true);
    editor.focus();
  }

  clear() {
    this.report = null;
    this.panel.hidden = true;
    this.group.clear();
    this.app.view.requestRender();
  }

  /** The simulated path: blue, red or amber where a finding's segment is. */
  drawPath(report) {
    this.group.clear();
    const flagged = report.findings.filter((f) => f.segment);
    const colourAt = (t, move) => {
      let colour = COLOURS.ok;
      for (const f of flagged) {
        const s = f.segment;
        if (s.move === move && t >= s.start - 1e-6 && t <= s.end + 1e-6) {
          colour = COLOURS[f.severity] ?? colour;
          if (f.severity === "error") break;
        }
      }
      return new THREE.Color(colour);
    };
    const positions = [];
    const colours = [];
    for (const [t, x, y, z, move] of report.path) {
      positions.push(x, y, z);
      const c = colourAt(t, move);
      colours.push(c.r, c.g, c.b);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(positions, 3));
    geometry.setAttribute("color", new THREE.Float32BufferAttribute(colours, 3));
    const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.85 }));
    line.frustumCulled = false;
    this.group.add(line);
    // Dots where findings are, so a short segment still shows.
    for (const f of flagged) {
      const at = report.path.find(([t, , , , move]) => move === f.segment.move && t >= f.segment.start - 1e-6);
      if (!at) continue;
      const dot = new THREE.Mesh(new THREE.SphereGeometry(12), new THREE.MeshBasicMaterial({ color: COLOURS[f.severity] }));
      dot.position.set(at[1], at[2], at[3]);
      this.group.add(dot);
    }
    this.group.visible = this.ghost.checked;
    const flaggedPoints = report.path.filter(([t, , , , move]) => colourAt(t, move).getHex() !== COLOURS.ok).length;
    this.app.view.container.dataset.ghostPoints = String(report.path.length);
    this.app.view.container.dataset.ghostFlagged = String(flaggedPoints);
    this.app.view.requestRender();
  }

  /** The lab's cell in 3D (cellview.js): the table, fixtures, parts, devices. */
  setCell(cell) {
    this.cell = cell;
    this.app.cell.setCell(cell);
  }

  editCell() {
    this.editor.open(this.cell);
  }

  /** The lab's gate refused a program: run pre-flight now, and offer the simulator. Once
   * it passed, what to do next is what was refused's (`detail.asked`: a run of the program
   * the robot holds goes again with no new load). */
  async offer(err) {
    this.panel.dataset.offered = "true";
    const passed = await this.run();
    if (passed) {
      const next = REFUSAL_ASKED[err?.detail?.asked] ?? REFUSAL_ASKED.load;
      toast("Pre-flight passed", { kind: "ok", text: next.after_fix });
      return;
    }
    toast("Simulate it first", {
      kind: "warning",
      timeout: 0,
      text: "This lab runs a program on the robot only after the same program passed a simulated run without pre-flight errors.",
      actions: [
        { label: QUEUE_WORDS.preflight, run: () => this.run() }, // the queue's button's words
        { label: "Debug on My simulator", run: () => this.app.targets.choose("mine") },
      ],
    });
  }
}
