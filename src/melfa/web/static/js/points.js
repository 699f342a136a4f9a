// The points tab: the points file as a table; add/edit in a dialog (name, X…C or J1…J6,
// FL1/FL2) with "import current robot position"; checks by the server (names, numbers,
// RV-6S reach) shown per row and in the dialog; move to a point; load and save .POS.
// The text stays the source of truth (comments and unknown lines are kept as they are).

import { api } from "./api.js";
import { moving } from "./fixes.js";
import { confirmReplace, openBeside } from "./opener.js";
import { $, debounce, describeDiagnostic, el, hasExtension, readTextFile, showError, toast } from "./ui.js";
import { JOINT_NAMES, POSE_NAMES } from "/model/controller.js"; // generated from melfa.protocol
import { IDE_WORDS } from "/vocab.js"; // generated from melfa.vocab.ide
import { fill } from "./activity.js";

const LINE = /^\s*(?:DEF\s+(POS|JNT)\s+)?([A-Za-z][A-Za-z0-9_]*)\s*=\s*\(([^)]*)\)\s*(?:\(([^)]*)\))?\s*(?:'.*)?$/i;
const MAX_NAME = 8;

/** Parse a points text into rows ({index, name, kind, values, fl1, fl2}) by line. */
export function parsePoints(text) {
  const rows = [];
  text.split("\n").forEach((line, index) => {
    const m = LINE.exec(line);
    if (!m) return;
    const name = m[2];
    const kind = (m[1] || (name[0].toUpperCase() === "J" ? "JNT" : "POS")).toUpperCase();
    const values = m[3].split(",").map((v) => (v.trim() === "" ? null : Number(v)));
    let fl1 = null;
    let fl2 = null;
    if (m[4] != null) {
      const [a, b] = m[4].split(",").map((v) => v.trim());
      fl1 = Number(a);
      fl2 = /^&H/i.test(b || "") ? parseInt(b.slice(2), 16) : Number(b ?? 0);
    }
    rows.push({ index, name, kind, values, fl1, fl2 });
  });
  return rows;
}

const fmt = (v) => (v == null || Number.isNaN(v) ? "" : (Math.abs(v) < 0.005 ? 0 : v).toFixed(2));

/** One points-file line in the project's form (as melfa.lang.points_write.format_points). */
export function formatPoint({ name, kind, values, fl1, fl2 }) {
  const body = `${name}=(${values.map(fmt).join(",")})`;
  if (kind === "JNT") return `DEF JNT ${body}`;
  const flag2 = !fl2 ? "0" : "&H" + fl2.toString(16).toUpperCase().padStart(8, "0");
  return `DEF POS ${body}(${fl1 ?? 7},${flag2})`;
}

export class PointsTab {
  constructor(workspace, app) {
    this.workspace = workspace;
    this.app = app;
    this.diagnostics = [];
    this.editing = null; // row being edited, or null for a new point
    this.seq = 0;
    this.recheck = debounce(() => this.check(), 300);
    this.dialogCheck = debounce(() => this.checkDialog(), 300);

    workspace.on("points", () => {
      this.render();
      this.recheck();
    });
    workspace.on("replaced", () => this.render());
    $("point-add").addEventListener("click", () => this.openDialog(null));
    $("open-pos").addEventListener("click", () => $("file-pos").click());
    $("file-pos").addEventListener("change", (e) => this.openFile(e.target));
    $("pt-import").addEventListener("click", () => this.importCurrent());
    $("pt-cancel").addEventListener("click", () => $("point-dialog").close());
    $("pt-kind").addEventListener("change", () => this.kindChanged());
    $("point-form").addEventListener("submit", (e) => {
      e.preventDefault();
      this.savePoint();
    });
    $("point-form").addEventListener("input", () => this.dialogCheck());
  }

  get rows() {
    return parsePoints(this.workspace.points);
  }

  /** Names the program may use (the points tab's points count as declared). */
  names() {
    return this.rows.map((r) => r.name);
  }

  async check() {
    const seq = ++this.seq;
    const points = this.workspace.points;
    try {
      const out = await api("POST", "/api/check", { program: "", points });
      if (seq !== this.seq || points !== this.workspace.points) return;
      this.diagnostics = out.points.diagnostics;
      this.render();
    } catch {
      /* shown next time; the toolbar check reports errors */
    }
  }

  render() {
    const rows = this.rows;
    $("points-count").textContent = String(rows.length);
    $("points-empty").hidden = rows.length > 0;
    const byLine = new Map();
    for (const d of this.diagnostics) {
      if (!byLine.has(d.line)) byLine.set(d.line, []);
      byLine.get(d.line).push(d);
    }
    const body = $("points-body");
    body.replaceChildren(
      ...rows.map((row) => {
        const diags = byLine.get(row.index + 1) || [];
        byLine.delete(row.index + 1);
        const worst = diags.find((d) => d.severity === "error") || diags.find((d) => d.severity === "warning");
        const status = worst
          ? el("span", { class: worst.severity === "error" ? "err-text" : "warn-text", title: diags.map(describeDiagnostic).join("\n") },
            worst.severity === "error" ? "✕ " : "⚠ ", worst.message)
          : el("span", { class: "ok-text" }, "✓ ok");
        return el("tr", { "data-point": row.name },
          el("td", { class: "name" }, row.name, el("span", { class: "kind" }, row.kind)),
          ...[0, 1, 2, 3, 4, 5].map((i) => el("td", {}, fmt(row.values[i]))),
          el("td", {}, row.kind === "POS" ? String(row.fl1 ?? "") : ""),
          el("td", {}, row.kind === "POS" ? String(row.fl2 ?? "") : ""),
          el("td", { class: "check-cell" }, status),
          el("td", { class: "actions" },
            el("button", { type: "button", class: "btn btn-sm", "aria-label": `Move to ${row.name}`, onclick: () => this.moveTo(row) }, "Move to"),
            el("button", { type: "button", class: "btn btn-sm", "aria-label": `Edit ${row.name}`, onclick: () => this.openDialog(row) }, "Edit"),
            el("button", { type: "button", class: "btn btn-sm btn-danger-ghost", "aria-label": `Delete ${row.name}`, onclick: () => this.remove(row) }, "Delete"),
          ),
        );
      }),
    );
    // Problems on lines that are not points (comments never have any; broken lines do).
    const rest = [...byLine.values()].flat();
    $("points-problems").replaceChildren(
      ...rest.map((d) => el("li", { class: d.severity === "error" ? "err-text" : "warn-text" }, describeDiagnostic(d))),
    );
    const errors = this.diagnostics.filter((d) => d.severity === "error").length;
    const warnings = this.diagnostics.filter((d) => d.severity === "warning").length;
    $("points-summary").textContent = rows.length
      ? `${rows.length} point${rows.length === 1 ? "" : "s"} · ${errors} error${errors === 1 ? "" : "s"}, ${warnings} warning${warnings === 1 ? "" : "s"}`
      : "";
  }

  // ---- dialog ----
  openDialog(row) {
    this.editing = row;
    $("point-dialog-title").textContent = row ? `Edit ${row.name}` : "New point";
    $("pt-name").value = row ? row.name : this.suggestName();
    $("pt-kind").value = row ? row.kind : "POS";
    for (let i = 0; i < 6; i++) $(`pt-v${i}`).value = row ? fmt(row.values[i]) : "";
    $("pt-fl1").value = row?.fl1 ?? 7;
    $("pt-fl2").value = row?.fl2 ?? 0;
    this.kindChanged();
    $("pt-problems").replaceChildren();
    $("point-dialog").showModal();
    $("pt-name").focus();
    if (row) this.dialogCheck();
  }

  suggestName() {
    const names = new Set(this.names().map((n) => n.toUpperCase()));
    for (let i = 1; ; i++) if (!names.has(`P${i}`)) return `P${i}`;
  }

  kindChanged() {
    const jnt = $("pt-kind").value === "JNT";
    const labels = jnt ? JOINT_NAMES : POSE_NAMES;
    document.querySelectorAll("#point-form .v-label").forEach((node, i) => (node.textContent = labels[i] + (jnt ? " (°)" : i < 3 ? " (mm)" : " (°)")));
    for (let i = 0; i < 6; i++) $(`pt-v${i}`).setAttribute("aria-label", labels[i]);
    $("pt-fl1").disabled = jnt;
    $("pt-fl2").disabled = jnt;
    this.dialogCheck();
  }

  /** Fill the dialog from where the robot stands now (pose and flags, or joints). */
  importCurrent() {
    const state = this.app.state;
    const jnt = $("pt-kind").value === "JNT";
    const values = jnt ? state?.joints : state?.pose;
    if (!values) {
      toast("No robot position yet", { kind: "warning", text: "The robot's position is not known: is the robot connected?" });
      return;
    }
    values.forEach((v, i) => ($(`pt-v${i}`).value = fmt(v)));
    if (!jnt && state.flags) {
      $("pt-fl1").value = state.flags[0];
      $("pt-fl2").value = state.flags[1];
    }
    this.dialogCheck();
  }

  /** Define `name` from where the robot stands now (the fix of "P1 is not defined"). */
  async addFromRobot(name) {
    const state = this.app.state;
    const jnt = name[0].toUpperCase() === "J";
    const values = jnt ? state?.joints : state?.pose;
    if (!values) {
      toast("No robot position yet", { kind: "warning", text: "The robot's position is not known: is the robot connected?" });
      return false;
    }
    const point = { name, kind: jnt ? "JNT" : "POS", values: values.map((v) => Number(fmt(v))),
      fl1: jnt ? null : state.flags?.[0] ?? 7, fl2: jnt ? null : state.flags?.[1] ?? 0 };
    const lines = this.workspace.points.split("\n");
    if (lines.length && lines[lines.length - 1] === "") lines.pop();
    lines.push(formatPoint(point), "");
    this.workspace.update({ points: lines.join("\n") });
    toast(`${name} added`, { kind: "ok", text: "From the robot's current position (Points tab)." });
    return true;
  }

  /** The dialog's point, and problems found without asking the server. */
  readDialog() {
    const problems = [];
    const name = $("pt-name").value.trim();
    const kind = $("pt-kind").value;
    const want = kind === "JNT" ? "J" : "P";
    const mark = (id, bad) => $(id).setAttribute("aria-invalid", bad ? "true" : "false");
    let badName = false;
    if (!name) { problems.push("Give the point a name."); badName = true; }
    else if (!/^[A-Za-z][A-Za-z0-9]*$/.test(name)) { problems.push("Names use letters and digits only, starting with a letter."); badName = true; }
    else if (name[0].toUpperCase() !== want) { problems.push(`A ${kind} point's name starts with ${want} (for example ${want}${name}).`); badName = true; }
    else if (name.length > MAX_NAME) { problems.push(`Names are at most ${MAX_NAME} characters (${name.length} now).`); badName = true; }
    const clash = this.rows.find((r) => r.name.toUpperCase() === name.toUpperCase() && r !== this.editing && r.index !== this.editing?.index);
    if (clash) { problems.push(`${clash.name} already exists.`); badName = true; }
    mark("pt-name", badName);
    const labels = kind === "JNT" ? JOINT_NAMES : POSE_NAMES;
    const values = [];
    for (let i = 0; i < 6; i++) {
      const raw = $(`pt-v${i}`).value.trim().replace(",", ".");
      const v = Number(raw);
      const bad = raw === "" || !Number.isFinite(v);
      mark(`pt-v${i}`, bad);
      if (bad) problems.push(`${labels[i]} must be a number${raw ? ` (not "${raw}")` : ""}.`);
      values.push(v);
    }
    let fl1 = 7;
    let fl2 = 0;
    if (kind === "POS") {
      fl1 = Number($("pt-fl1").value);
      const fl2raw = $("pt-fl2").value.trim();
      fl2 = /^&H/i.test(fl2raw) ? parseInt(fl2raw.slice(2), 16) : Number(fl2raw);
      const bad1 = !Number.isInteger(fl1) || fl1 < 0 || fl1 > 7;
      const bad2 = !Number.isInteger(fl2) || fl2 < 0;
      mark("pt-fl1", bad1);
      mark("pt-fl2", bad2);
      if (bad1) problems.push("FL1 is a whole number 0–7 (7: right, above, no flip).");
      if (bad2) problems.push("FL2 is a whole number ≥ 0 (turns of the joints).");
    }
    return { point: { name, kind, values, fl1, fl2 }, problems };
  }

  /** Server check of the dialog's point: name rules, numbers, RV-6S reach (warnings). */
  async checkDialog() {
    if (!$("point-dialog").open) return [];
    const { point, problems } = this.readDialog();
    const list = $("pt-problems");
    const local = problems.map((p) => el("li", { class: "err-text" }, "✕ " + p));
    if (problems.length) {
      list.replaceChildren(...local);
      return problems;
    }
    const seq = ++this.seq;
    try {
      const out = await api("POST", "/api/check", { program: "", points: formatPoint(point) + "\n" });
      if (seq !== this.seq) return [];
      const diags = out.points.diagnostics;
      list.replaceChildren(
        ...(diags.length
          ? diags.map((d) => el("li", { class: d.severity === "error" ? "err-text" : "warn-text" },
            d.severity === "error" ? "✕ " : "⚠ ", d.message, d.suggestion ? " " + d.suggestion : ""))
          : [el("li", { class: "ok-text" }, "✓ Reachable by the RV-6S")]),
      );
      return diags.filter((d) => d.severity === "error").map((d) => d.message);
    } catch {
      return [];
    }
  }

  async savePoint() {
    const { point, problems } = this.readDialog();
    if (problems.length) {
      await this.checkDialog();
      $("pt-problems").querySelector("li")?.scrollIntoView({ block: "nearest" });
      return;
    }
    const serverErrors = await this.checkDialog();
    if (serverErrors.length) return;
    const lines = this.workspace.points.split("\n");
    const text = formatPoint(point);
    if (this.editing) lines[this.editing.index] = text;
    else {
      if (lines.length && lines[lines.length - 1] === "") lines.pop();
      lines.push(text, "");
    }
    $("point-dialog").close();
    this.workspace.update({ points: lines.join("\n") });
    toast(this.editing ? `${point.name} updated` : `${point.name} added`, { kind: "ok" });
  }

  remove(row) {
    if (!confirm(`Delete point ${row.name}?`)) return;
    const lines = this.workspace.points.split("\n");
    lines.splice(row.index, 1);
    this.workspace.update({ points: lines.join("\n") });
  }

  async moveTo(row) {
    await moving(fill(IDE_WORDS["move-failed-to"], { point: row.name }), async (extra) => {
      const before = this.app.state;
      this.app.busy(fill(IDE_WORDS["moving-to"], { point: row.name }));
      await api("POST", "/api/robot/move", { point: row.name, points: this.workspace.points, ...extra });
      await this.app.moved(before); // then the robot's words: "Moving to P1", "At P1" on arrival
    }, () => this.app.idle(IDE_WORDS["move-failed"], true));
  }

  async openFile(input) {
    const file = input.files[0];
    input.value = "";
    if (!file) return;
    if (!hasExtension(file.name, "POS")) {
      toast(`${file.name} was not loaded`, { kind: "error", text: "Points files are .POS files. Choose a file ending in .POS (programs, .MB4, open in the Editor tab)." });
      return;
    }
    try {
      const text = (await readTextFile(file)).replace(/\r\n?/g, "\n");
      const choice = await confirmReplace(this.workspace, file.name, text, "points");
      if (choice === "cancel") return;
      if (choice === "beside") {
        await openBeside(this.workspace, file.name, { points: text });
        return;
      }
      this.workspace.update({ points: text });
      toast(`Loaded ${file.name}`, { kind: "ok", text: `${parsePoints(text).length} points.` });
    } catch (err) {
      showError(`Could not load ${file.name}`, err);
    }
  }
}
