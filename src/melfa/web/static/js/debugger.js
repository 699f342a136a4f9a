// The debugger on "My simulator" (docs/ide.md "Debugging", docs/api.md "Debugger"):
// a toolbar (debug, pause, continue, step, step over, step out, run to cursor, end, speed),
// breakpoints in the editor's gutter (a breakpoint on a *LABEL line is kept as the label),
// the current statement highlighted, a variables panel with the last step's changes
// marked, inputs to release a WAIT, run-time errors shown on their line, and how the run
// starts (servo, where the arm stands, override, lines for INPUT #: startopts.js).
//
// The server holds the session (GET /api/debug), so a reloaded page shows where the
// program is. Live updates come as `debug` messages on the simulator's socket.

import { api } from "./api.js";
import { $, el, showError, toast } from "./ui.js";
import { robot } from "./stores.js";
import { StartOptions } from "./startopts.js";

const Range = ace.require("ace/range").Range;
const SPEEDS = [["real", "Real time"], ["x2", "×2"], ["x4", "×4"], ["x10", "×10"], ["instant", "Instant"]];

export class DebugPanel {
  constructor(app) {
    this.app = app;
    this.editor = app.editor;
    this.session = null; // the last {status, variables, program} seen
    this.marker = null;
    this.errorMarker = null;
    this.breakKey = () => `melfa.breakpoints.${app.user}.${app.workspace.id}`;
    this.buildToolbar();
    this.buildPanel();
    this.wireGutter();
    app.live.on("debug", (m) => this.onMessage(m));
    app.targets.addEventListener("change", () => this.onTarget());
    app.workspace.on("replaced", () => this.restoreBreakpoints());
    this.editor.session.on("change", () => this.renderLocation());
  }

  // ---- layout ----
  buildToolbar() {
    const b = (id, icon, label, title, handler) => {
      const button = el("button", { type: "button", class: "btn", id, title, "aria-label": label }, el("span", { class: "ico", "aria-hidden": "true" }, icon), " " + label);
      button.addEventListener("click", handler);
      return button;
    };
    this.speed = el("select", { id: "dbg-speed", "aria-label": "Debugger speed", title: "How fast the simulated program runs" },
      ...SPEEDS.map(([v, t]) => el("option", { value: v }, t)));
    this.speed.addEventListener("change", () => this.setSpeed());
    this.bar = el("div", { class: "debug-bar", id: "debug-bar", role: "group", "aria-label": "Debugger", hidden: "" },
      el("span", { class: "debug-title" }, "Debugger"),
      b("dbg-start", "▶", "Debug", "Run the editor's program under the debugger (F5)", () => this.start()),
      b("dbg-pause", "❚❚", "Pause", "Stop where the program is", () => this.command("pause")),
      b("dbg-continue", "▷", "Continue", "Go on to the next breakpoint (F5)", () => this.command("continue")),
      b("dbg-step", "↓", "Step", "One statement, into GOSUB (F11)", () => this.command("step")),
      b("dbg-next", "↷", "Step over", "One statement; a GOSUB runs whole (F10)", () => this.command("step-over")),
      b("dbg-out", "↑", "Step out", "Until the subroutine returns (Shift+F11)", () => this.command("step-out")),
      b("dbg-cursor", "→|", "Run to cursor", "Run to the line the cursor is on", () => this.runToCursor()),
      b("dbg-end", "■", "End", "End the debug session", () => this.end()),
      this.speed,
    );
    const toolbar = document.querySelector(".toolbar");
    toolbar.insertBefore(this.bar, $("activity"));
    const keys = { F5: () => this.command("continue"), F10: () => this.command("step-over"), F11: () => this.command("step") };
    document.addEventListener("keydown", (e) => {
      if (!this.app.targets.isPrivate) return;
      if (e.key === "F11" && e.shiftKey) { e.preventDefault(); this.command("step-out"); return; }
      const fn = keys[e.key];
      if (fn) { e.preventDefault(); fn(); }
    });
  }

  buildPanel() {
    this.statusLine = el("p", { class: "dbg-status", id: "dbg-status", "aria-live": "polite" }, "Not debugging.");
    this.errorBox = el("div", { class: "dbg-error", id: "dbg-error", role: "alert", hidden: "" });
    this.waitBox = el("div", { class: "dbg-wait", id: "dbg-wait", hidden: "" });
    this.inBit = el("input", { id: "dbg-in-bit", type: "number", min: "0", max: "32767", value: "0", "aria-label": "Input number" });
    this.inValue = el("select", { id: "dbg-in-value", "aria-label": "Input value" }, el("option", { value: "1" }, "1"), el("option", { value: "0" }, "0"));
    const set = el("button", { type: "button", class: "btn btn-sm", id: "dbg-in-set" }, "Set");
    set.addEventListener("click", () => this.setInput(Number(this.inBit.value), Number(this.inValue.value)));
    this.vars = el("tbody", { id: "dbg-vars" });
    this.startOptions = new StartOptions(this.app.user);
    this.panel = el("section", { class: "debug-panel", id: "debug-panel", "aria-label": "Debugger", hidden: "" },
      el("div", { class: "dbg-head" }, el("h2", {}, "Debugger"), this.statusLine),
      this.errorBox,
      this.waitBox,
      this.startOptions.box,
      el("div", { class: "dbg-inputs" }, el("label", { for: "dbg-in-bit" }, "M_IN("), this.inBit, ") =", this.inValue, set),
      el("div", { class: "dbg-vars-wrap" },
        el("table", { class: "dbg-vars", "aria-label": "Variables" },
          el("thead", {}, el("tr", {}, el("th", { scope: "col" }, "Variable"), el("th", { scope: "col" }, "Value"))),
          this.vars)),
    );
    const side = document.querySelector(".sidepanel");
    side.insertBefore(this.panel, side.querySelector(".readouts"));
  }

  // ---- breakpoints in the gutter ----
  wireGutter() {
    const editor = this.editor.editor;
    editor.on("guttermousedown", (e) => {
      const target = e.domEvent.target;
      if (!target.classList.contains("ace_gutter-cell")) return;
      const row = e.getDocumentPosition().row;
      this.toggleBreakpoint(row);
      e.stop();
    });
    this.restoreBreakpoints();
  }

  /** Rows (0-based) with a breakpoint. */
  get breakRows() {
    const rows = [];
    this.editor.session.getBreakpoints().forEach((cls, row) => { if (cls) rows.push(row); });
    return rows;
  }

  toggleBreakpoint(row) {
    const s = this.editor.session;
    if (s.getBreakpoints()[row]) s.clearBreakpoint(row);
    else s.setBreakpoint(row, "melfa-breakpoint");
    this.saveBreakpoints();
    if (this.active) this.sendBreakpoints();
  }

  saveBreakpoints() {
    localStorage.setItem(this.breakKey(), JSON.stringify(this.breakRows));
  }

  restoreBreakpoints() {
    const s = this.editor.session;
    s.clearBreakpoints();
    let rows = [];
    try { rows = JSON.parse(localStorage.getItem(this.breakKey()) || "[]"); } catch { rows = []; }
    for (const row of rows) if (row < s.getLength()) s.setBreakpoint(row, "melfa-breakpoint");
  }

  /** Lines and labels for the server: a breakpoint on a `*LABEL` line is the label's. */
  breakpointSpec() {
    const lines = [];
    const labels = [];
    for (const row of this.breakRows) {
      const text = this.editor.session.getLine(row).trim().replace(/^\d+\s+/, "");
      const label = /^\*([A-Za-z][A-Za-z0-9_]*)/.exec(text);
      if (label) labels.push(label[1]);
      else lines.push(row + 1);
    }
    return { lines, labels };
  }

  /** Breakpoints are sent one PUT after another, and every command waits for the last:
   *  a breakpoint removed just before *Continue* must be gone when the run goes on (two
   *  requests on two connections may otherwise arrive in either order). */
  sendBreakpoints() {
    const spec = this.breakpointSpec();
    this.breakpointsSent = (this.breakpointsSent || Promise.resolve()).then(async () => {
      try {
        this.show(await api("PUT", "/api/debug/breakpoints", spec));
      } catch (err) {
        showError("Could not set the breakpoints", err);
      }
    });
    return this.breakpointsSent;
  }

  // ---- commands ----
  get active() {
    const state = this.session?.status?.state;
    return !!this.session && state !== undefined;
  }

  /** Load the editor's program (with its points and breakpoints), then `then` (a path
   *  and body: run it by default). */
  async start(then = ["/api/debug/command/run"]) {
    const app = this.app;
    try {
      this.clearError();
      const body = { program: this.editor.text, points: app.workspace.points, workspace_id: app.workspace.id, check: true, speed: this.speed.value, start: this.startOptions.spec(), ...this.breakpointSpec() };
      this.show(await api("POST", "/api/debug", body));
      app.view.clearPath();
      this.show(await api("POST", ...then));
    } catch (err) {
      if (err.code === "program-has-errors" && err.detail?.diagnostics) this.editor.show(err.detail.diagnostics);
      showError(err.code === "program-has-errors" ? "Not debugged: the program has errors" : "Could not start the debugger", err);
    }
  }

  /** Whether the session can go on from here (same text, stopped or running). */
  get resumable() {
    const state = this.session?.status?.state;
    return this.active && this.session.program === this.editor.text && (state === "paused" || state === "running");
  }

  async command(name) {
    if (!this.resumable && name !== "pause") {
      return this.start([`/api/debug/command/${name === "continue" ? "run" : name}`]);
    }
    try {
      if (name === "run" || name === "continue") this.clearError();
      await this.breakpointsSent;
      this.show(await api("POST", `/api/debug/command/${name}`));
    } catch (err) {
      showError("The debugger could not do that", err);
    }
  }

  async runToCursor() {
    const line = this.editor.editor.getCursorPosition().row + 1;
    if (!this.resumable) return this.start(["/api/debug/run-to", { line }]);
    try {
      await this.breakpointsSent;
      this.show(await api("POST", "/api/debug/run-to", { line }));
    } catch (err) {
      showError("Could not run to the cursor", err);
    }
  }

  async end() {
    try {
      await api("DELETE", "/api/debug");
    } catch (err) {
      showError("Could not end the debug session", err);
    }
    this.session = null;
    robot.set({ debugging: false });
    this.render();
  }

  async setSpeed() {
    if (!this.active) return;
    try {
      this.show(await api("POST", "/api/debug/speed", { speed: this.speed.value }));
    } catch (err) {
      showError("Could not change the speed", err);
    }
  }

  async setInput(bit, value) {
    if (!this.active) return;
    try {
      this.show(await api("POST", "/api/debug/input", { bit, value }));
      toast(`M_IN(${bit}) = ${value}`, { kind: "ok", text: "A WAIT on it goes on now." });
    } catch (err) {
      showError("Could not set the input", err);
    }
  }

  // ---- following the server ----
  async onTarget() {
    const mine = this.app.targets.isPrivate;
    this.bar.hidden = !mine;
    this.panel.hidden = !mine;
    if (!mine) {
      robot.set({ debugging: false });
      this.clearMarkers();
      return;
    }
    try {
      const now = await api("GET", "/api/debug"); // null: nothing is being debugged
      if (now) return this.show(now);
    } catch (err) {
      showError("Could not read the debugger", err);
    }
    this.session = null;
    this.render();
  }

  onMessage(m) {
    if (m.ended) {
      this.session = null;
      this.app.cell?.resetParts();
      robot.set({ debugging: false });
      this.render();
      return;
    }
    const running = m.status.state === "running";
    if (m.joints) this.app.view.setJoints(m.joints);
    if (running && m.pose) this.app.view.addPathPoint(m.pose);
    if (m.parts) this.app.cell?.setParts(m.parts); // the cell's parts, carried and dropped
    robot.set({ debugging: true });
    this.show({ session: m.session, seq: m.seq, status: m.status, variables: m.variables ?? this.session?.variables ?? [], program: this.session?.program ?? this.editor.text });
  }

  show(out) {
    // A command's reply and the socket's messages may cross: the highest `seq` wins.
    if (this.session && out.session === this.session.session && out.seq < this.session.seq) return;
    const before = this.session?.status;
    this.session = out;
    robot.set({ debugging: true });
    const stop = out.status.stop;
    const fresh = stop && JSON.stringify(stop) !== JSON.stringify(before?.stop);
    if (fresh && stop.location && out.program === this.editor.text) this.editor.editor.scrollToLine(stop.location.line - 1, true, true, () => {});
    this.render();
  }

  // ---- drawing ----
  render() {
    const out = this.session;
    const mine = this.app.targets.isPrivate;
    this.bar.hidden = !mine;
    this.panel.hidden = !mine;
    const state = out?.status?.state ?? "none";
    document.body.dataset.debug = state;
    const running = state === "running";
    const stopped = state === "paused";
    $("dbg-pause").disabled = !running;
    $("dbg-continue").disabled = !stopped;
    $("dbg-out").disabled = !stopped;
    $("dbg-end").disabled = !out;
    if (out?.status?.speed) {
      const map = { "real time": "real", instant: "instant" };
      const value = map[out.status.speed] ?? out.status.speed;
      if ([...this.speed.options].some((o) => o.value === value)) this.speed.value = value;
    }
    this.renderStatus();
    this.renderVariables();
    this.renderLocation();
  }

  renderStatus() {
    const s = this.session?.status;
    const loc = s?.location;
    let text = "Not debugging. Set breakpoints in the gutter, then Debug (F5).";
    if (s) {
      const at = loc ? ` at line ${loc.line}` : "";
      const why = s.stop?.reason;
      text = {
        idle: "Loaded; not started.",
        running: s.waiting ? `Waiting${at}` : `Running${at}`,
        paused: why === "breakpoint" ? `Stopped at a breakpoint${at}` : why === "hlt" ? `Paused by HLT${at}` : `Stopped${at}`,
        finished: `Finished${at} after ${s.time.toFixed(2)} s (simulated)`,
        failed: `Stopped by an error${at}`,
      }[s.state] ?? s.state;
      if (s.state !== "finished") text += ` · ${s.time.toFixed(2)} s`;
    }
    this.statusLine.textContent = text;
    this.statusLine.dataset.state = s?.state ?? "none";
    this.statusLine.dataset.line = loc?.line ?? "";
    const err = s?.state === "failed" ? s.stop?.error : null;
    this.errorBox.hidden = !err;
    if (err) {
      this.errorBox.replaceChildren(
        el("strong", {}, `Error ${err.code} at line ${err.location.line}`),
        el("div", {}, err.message + (err.explanation && err.explanation !== err.message ? ` — ${err.explanation}` : "")),
        el("code", {}, err.location.source),
      );
      this.errorBox.dataset.line = String(err.location.line);
    }
    // A WAIT on an input: say which and offer to set it.
    const waitInput = s?.waiting ? /M_IN\s*\(\s*(\d+)\s*\)/i.exec(loc?.source ?? "") : null;
    this.waitBox.hidden = !s?.waiting;
    // Rebuilt only when what it says changes: status events arrive many times a second while
    // the program waits, and a button replaced between press and release never gets the click.
    const waitKey = s?.waiting ? `${loc?.line}|${loc?.source ?? ""}` : "";
    if (s?.waiting && waitKey !== this.waitKey) {
      const parts = [el("span", {}, `The program waits at line ${loc?.line}: ${loc?.source ?? ""}`)];
      if (waitInput) {
        const bit = Number(waitInput[1]);
        const release = el("button", { type: "button", class: "btn btn-sm btn-primary", id: "dbg-release" }, `Set M_IN(${bit}) = 1`);
        release.addEventListener("click", () => this.setInput(bit, 1));
        parts.push(release);
        this.inBit.value = String(bit);
      }
      this.waitBox.replaceChildren(...parts);
    }
    this.waitKey = waitKey;
  }

  renderVariables() {
    const rows = this.session?.variables ?? [];
    const tr = (v, sub = false) => el("tr", { class: (v.changed ? "changed " : "") + (sub ? "element" : ""), "data-name": v.name, "data-kind": v.kind },
      el("th", { scope: "row" }, v.name), el("td", {}, v.value));
    const out = [];
    for (const v of rows) {
      out.push(tr(v));
      for (const e of v.elements ?? []) out.push(tr(e, true));
    }
    this.vars.replaceChildren(...out);
  }

  clearError() {
    this.errorBox.hidden = true;
  }

  clearMarkers() {
    const s = this.editor.session;
    if (this.marker != null) s.removeMarker(this.marker);
    if (this.errorMarker != null) s.removeMarker(this.errorMarker);
    this.marker = this.errorMarker = null;
    if (this.markedRow != null) s.removeGutterDecoration(this.markedRow, "melfa-debug-arrow");
    this.markedRow = null;
    delete this.editor.editor.container.dataset.debugLine;
  }

  /** The current statement, highlighted while the editor holds the program debugged. */
  renderLocation() {
    this.clearMarkers();
    const s = this.session?.status;
    if (!s || !this.app.targets.isPrivate) return;
    const same = this.session.program === this.editor.text;
    this.panel.classList.toggle("stale", !same);
    if (!same) return; // edited since: the line numbers may no longer match
    const loc = s.location;
    if (!loc || s.state === "idle" && !s.stop) return;
    const row = loc.line - 1;
    const session = this.editor.session;
    const cls = s.state === "failed" ? "melfa-debug-error" : "melfa-debug-line";
    const marker = session.addMarker(new Range(row, 0, row, 1), cls, "fullLine", false);
    if (s.state === "failed") this.errorMarker = marker;
    else this.marker = marker;
    session.addGutterDecoration(row, "melfa-debug-arrow");
    this.markedRow = row;
    this.editor.editor.container.dataset.debugLine = String(loc.line);
  }
}
