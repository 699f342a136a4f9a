// Recorded runs in the IDE (docs/ide.md "Recorded runs"): every run on the lab robot is
// recorded by the server (GET /api/runs: a student's own, an instructor's everyone's).
// *Runs* lists them; *Replay* plays one back in the 3D view: the arm moves as it moved, the
// real TCP path is drawn in orange with the simulated path it is compared with (the passed
// pre-flight of the same text) as a blue ghost beside it, the line that was running is
// marked in the editor, and the report gives the largest deviation (a red mark between the
// real and the simulated point) and the cycle-time difference. The live robot does not
// touch the view while a replay owns it (the robot store's `replay`).

import * as THREE from "three";
import { api } from "./api.js";
import { robot } from "./stores.js";
import { $, el, showError } from "./ui.js";
import { RUN_OUTCOMES } from "/vocab.js"; // generated from melfa.vocab.runs

const REAL = 0xd97706;
const GHOST = 0x2563eb;
const MARK = 0xdc2626;

const seconds = (s) => (s == null ? "—" : `${s.toFixed(s < 10 ? 2 : 1)} s`);
const signed = (s) => `${s >= 0 ? "+" : "−"}${Math.abs(s).toFixed(2)} s`;

/** A line through points in robot coordinates (mm), with a dot at each sample (a
 * one-pixel line alone is hard to see beside the arm). */
function polyline(points, colour, opacity = 1, dots = true) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.Float32BufferAttribute(points.flat(), 3));
  const material = new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity });
  const line = new THREE.Line(geometry, material);
  line.frustumCulled = false;
  if (dots) {
    const marks = new THREE.Points(geometry, new THREE.PointsMaterial({ color: colour, size: 5, sizeAttenuation: false, transparent: opacity < 1, opacity }));
    marks.frustumCulled = false;
    line.add(marks);
  }
  return line;
}

export class RunsPanel {
  constructor(app) {
    this.app = app;
    this.run = null;
    this.index = 0;
    this.playing = false;
    this.group = new THREE.Group(); // the replay's paths and marks, in robot coordinates
    this.group.visible = false;
    app.view.root.add(this.group);
    this.build();
    // A run that ends while the list is open appears in it (the server stores it a moment
    // after the controller shows the end).
    robot.subscribe(({ state }, previous) => {
      const ended = previous.state?.program_running && state && !state.program_running;
      if (ended && !this.listPanel.hidden) setTimeout(() => this.load(), 1500);
    });
  }

  build() {
    this.button = el("button", { type: "button", class: "btn btn-sm", id: "runs-button", "aria-expanded": "false", "aria-controls": "runs", title: "Your recorded runs on the lab robot: replay one beside its simulation" }, "Runs");
    this.button.addEventListener("click", () => this.toggleList());
    document.querySelector(".view-head").append(this.button);

    this.list = el("ol", { class: "runs-list", id: "runs-list" });
    this.listNote = el("p", { class: "muted runs-note" });
    const close = el("button", { type: "button", class: "btn btn-sm btn-icon", "aria-label": "Close the runs" }, "✕");
    close.addEventListener("click", () => this.toggleList(false));
    this.listPanel = el("section", { class: "runs", id: "runs", "aria-label": "Recorded runs", hidden: true },
      el("div", { class: "runs-head" }, el("strong", {}, "Recorded runs"), el("span", { class: "muted" }, "on the lab robot"), close),
      this.listNote, this.list);

    this.play = el("button", { type: "button", class: "btn btn-sm btn-icon", id: "replay-play", "aria-label": "Play" }, "▶");
    this.play.addEventListener("click", () => (this.playing ? this.pause() : this.start()));
    this.slider = el("input", { type: "range", id: "replay-slider", min: "0", max: "0", value: "0", "aria-label": "Replay position" });
    this.slider.addEventListener("input", () => { this.pause(); this.seek(Number(this.slider.value)); });
    this.clock = el("span", { class: "replay-clock", id: "replay-clock" });
    this.lineText = el("span", { class: "replay-line", id: "replay-line" });
    this.report = el("div", { class: "replay-report", id: "replay-report" });
    this.title = el("strong", { id: "replay-title" });
    const exit = el("button", { type: "button", class: "btn btn-sm", id: "replay-close" }, "Back to live");
    exit.addEventListener("click", () => this.close());
    this.bar = el("section", { class: "replay", id: "replay", "aria-label": "Replay of a recorded run", hidden: true },
      el("div", { class: "replay-head" }, this.title, el("span", { class: "spacer" }), exit),
      el("div", { class: "replay-controls" }, this.play, this.slider, this.clock),
      this.lineText, this.report,
      el("p", { class: "replay-legend" },
        el("span", { class: "swatch real" }), "real path ",
        el("span", { class: "swatch ghost" }), "simulated (pre-flight) ",
        el("span", { class: "swatch mark" }), "largest deviation"));
    const stage = document.querySelector(".view-stage");
    stage.after(this.listPanel, this.bar);
  }

  toggleList(open = this.listPanel.hidden) {
    this.listPanel.hidden = !open;
    this.button.setAttribute("aria-expanded", String(open));
    if (open) this.load();
  }

  async load() {
    let runs;
    try {
      runs = await api("GET", "/api/runs");
    } catch (err) {
      showError("Could not read the recorded runs", err);
      return;
    }
    const staff = this.app.role === "instructor" || this.app.role === "admin";
    this.listNote.textContent = runs.length
      ? staff ? "Everyone's runs, newest first." : "Your runs, newest first."
      : "No runs yet. Every run on the lab robot is recorded here: load your project and press Run.";
    this.list.replaceChildren(...runs.map((r) => this.item(r, staff)));
  }

  item(r, staff) {
    const when = new Date(r.started);
    const outcome = RUN_OUTCOMES[r.outcome]?.words ?? r.outcome;
    const deviation = r.report.deviation ? `${r.report.deviation.mm.toFixed(1)} mm from the simulation` : r.simulated_by ? "" : "not simulated";
    const replay = el("button", { type: "button", class: "btn btn-sm", "data-run": r.id, disabled: r.thinned || !r.frame_count }, "Replay");
    replay.title = r.thinned ? "An old run: its samples were thinned, its summary kept" : "Play it back in the 3D view";
    replay.addEventListener("click", () => this.open(r.id));
    return el("li", { class: `run-item run-${r.outcome}`, "data-run": r.id },
      el("span", { class: "run-when" }, when.toLocaleString([], { month: "short", day: "numeric", hour: "2-digit", minute: "2-digit" })),
      staff ? el("span", { class: "run-user" }, r.user) : null,
      el("span", { class: "run-outcome" }, outcome),
      el("span", { class: "run-time" }, seconds(r.duration)),
      el("span", { class: "run-dev" }, deviation),
      replay);
  }

  async open(id) {
    let run;
    try {
      run = await api("GET", `/api/runs/${id}`);
    } catch (err) {
      showError("Could not open the run", err);
      return;
    }
    if (!run.frames?.t.length) {
      showError("Nothing to replay", { message: "This run's samples were thinned; its summary is kept." });
      return;
    }
    this.show(run);
  }

  show(run) {
    const app = this.app;
    this.pause();
    this.run = run;
    this.toggleList(false);
    robot.set({ replay: true }); // the live robot leaves the 3D view and the editor alone
    app.view.pathLine.visible = false;
    document.querySelector(".readouts").hidden = true;
    const f = run.frames;
    const real = f.pose.map((p, i) => (p && f.running[i] ? p.slice(0, 3) : null)).filter(Boolean);
    const ghost = run.simulated?.path.map(([, x, y, z]) => [x, y, z]) ?? [];
    this.group.clear();
    if (real.length > 1) this.group.add(polyline(real, REAL));
    if (ghost.length > 1) this.group.add(polyline(ghost, GHOST, 0.55));
    const d = run.report.deviation;
    if (d) {
      const dot = new THREE.Mesh(new THREE.SphereGeometry(6), new THREE.MeshBasicMaterial({ color: MARK }));
      dot.position.set(...d.real);
      this.group.add(dot, polyline([d.real, d.simulated], MARK, 1, false));
    }
    this.group.visible = true;
    this.frame([...real, ...ghost]);
    const view = app.view.container.dataset;
    view.replayRun = String(run.id);
    view.replayRealPoints = String(real.length);
    view.replayGhostPoints = String(ghost.length);
    this.sameText = run.program != null && run.program === app.editor.text;
    this.title.textContent = `Run of ${run.user}, ${new Date(run.started).toLocaleString([], { dateStyle: "medium", timeStyle: "short" })} · ${RUN_OUTCOMES[run.outcome]?.words ?? run.outcome}`;
    this.report.replaceChildren(...this.reportLines(run));
    this.slider.max = String(f.t.length - 1);
    this.bar.hidden = false;
    this.bar.dataset.run = String(run.id);
    app.view.requestRender();
    this.seek(0);
  }

  /** Turn the camera to the paths (robot mm), close enough to see a few mm. */
  frame(points) {
    const view = this.app.view;
    if (!points.length || !view.controls) return;
    const box = new THREE.Box3();
    for (const p of points) box.expandByPoint(new THREE.Vector3(...p).applyMatrix4(view.root.matrixWorld));
    const centre = box.getCenter(new THREE.Vector3());
    const size = Math.max(0.9, box.getSize(new THREE.Vector3()).length() * 2.5); // m
    const away = view.camera.position.clone().sub(view.controls.target).normalize();
    view.controls.target.copy(centre);
    view.camera.position.copy(centre).addScaledVector(away, size);
    view.controls.update();
    view.requestRender();
  }

  reportLines(run) {
    const r = run.report;
    const lines = [];
    if (r.deviation) {
      const d = r.deviation;
      lines.push(el("p", { id: "replay-deviation", "data-mm": d.mm.toFixed(2) },
        el("strong", {}, `Largest deviation ${d.mm.toFixed(1)} mm`),
        d.line ? ` at line ${d.line}` : "", ` (${seconds(d.t)} into the run)`,
        el("span", { class: "muted" }, " · measured against the simulated path of the same line")));
    } else {
      lines.push(el("p", { id: "replay-deviation" }, run.simulated_by == null
        ? "No passed pre-flight of this text to compare with: run Pre-flight before the lab robot, and the next run is compared."
        : "Nothing to compare: no sample with a known line and pose."));
    }
    if (run.cycle_real != null) {
      const sim = run.cycle_simulated;
      const override = run.frames.override.filter((v) => v != null).at(-1);
      lines.push(el("p", { id: "replay-cycle" }, `Cycle time ${seconds(run.cycle_real)} on the robot`,
        override != null ? ` at ${override} % override` : "",
        sim != null ? `, ${seconds(sim)} simulated (${signed(run.cycle_real - sim)})` : ""));
    } else {
      lines.push(el("p", { id: "replay-cycle" }, `No cycle time: the run ${RUN_OUTCOMES[run.outcome]?.words ?? run.outcome}.`));
    }
    if (run.simulated_by && run.simulated_by !== run.user) lines.push(el("p", { class: "muted" }, `Compared with ${run.simulated_by}'s pre-flight of the same text.`));
    if (!this.sameText) lines.push(el("p", { class: "muted", id: "replay-text-changed" }, "Your editor's text is not the one that ran, so no line is marked in it; the line numbers refer to the text that ran."));
    return lines;
  }

  /** Show sample `i`: the arm, the hand, the line (in the editor when it holds the text). */
  seek(i) {
    const run = this.run;
    if (!run) return;
    const f = run.frames;
    i = Math.max(0, Math.min(f.t.length - 1, i));
    this.index = i;
    this.slider.value = String(i);
    if (f.joints[i]) this.app.view.setJoints(f.joints[i]);
    if (f.hand[i] != null) this.app.view.setHand(f.hand[i]);
    const line = f.line[i];
    this.clock.textContent = `${seconds(f.t[i])} / ${seconds(f.t.at(-1))}`;
    const text = line && run.program ? run.program.split(/\r\n|\r|\n/)[line - 1]?.trim() : "";
    this.lineText.replaceChildren(line ? el("span", {}, el("strong", {}, `line ${line}`), text ? `: ${text}` : "") : el("span", { class: "muted" }, f.running[i] ? "line not read yet" : "not running"));
    this.bar.dataset.line = line ? String(line) : "";
    this.bar.dataset.frame = String(i);
    if (this.sameText) this.app.editor.markRunLine(line ? line - 1 : null);
  }

  start() {
    const f = this.run?.frames;
    if (!f) return;
    if (this.index >= f.t.length - 1) this.seek(0);
    this.playing = true;
    this.play.textContent = "⏸";
    this.play.setAttribute("aria-label", "Pause");
    const t0 = performance.now() / 1000 - f.t[this.index];
    const step = () => {
      if (!this.playing) return;
      const t = performance.now() / 1000 - t0;
      let i = this.index;
      while (i < f.t.length - 1 && f.t[i + 1] <= t) i += 1;
      if (i !== this.index) this.seek(i);
      if (i >= f.t.length - 1) this.pause();
      else requestAnimationFrame(step);
    };
    requestAnimationFrame(step);
  }

  pause() {
    this.playing = false;
    this.play.textContent = "▶";
    this.play.setAttribute("aria-label", "Play");
  }

  close() {
    const app = this.app;
    this.pause();
    this.run = null;
    this.bar.hidden = true;
    this.group.clear();
    this.group.visible = false;
    app.view.pathLine.visible = true;
    document.querySelector(".readouts").hidden = false;
    delete app.view.container.dataset.replayRun;
    if (this.sameText) app.editor.markRunLine(null);
    robot.set({ replay: false });
    const live = app.state;
    if (live?.joints && !app.debugging) app.view.setJoints(live.joints);
    if (live?.hands?.length) app.view.setHand(live.hands[0]);
    app.view.resetView();
  }
}
