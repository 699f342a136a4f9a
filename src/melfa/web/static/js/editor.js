// The editor tab: Ace with the MELFA BASIC IV mode, diagnostics from POST /api/check shown
// as gutter annotations, wavy underlines (hover for the message and the suggestion) and a
// problems list; on-the-fly checking (debounced) that can be switched off; open .MB4.

import "./melfa-mode.js";
import { api } from "./api.js";
import { confirmReplace, openBeside } from "./opener.js";
import { $, debounce, describeDiagnostic, el, hasExtension, readTextFile, showError, toast } from "./ui.js";

const ace = window.ace;
const Range = ace.require("ace/range").Range;
const CHECK_DELAY_MS = 300;
const LIVE_KEY = "melfa.liveCheck";

export class ProgramEditor extends EventTarget {
  constructor(workspace) {
    super();
    this.workspace = workspace;
    this.diagnostics = [];
    this.markers = [];
    this.seq = 0;
    this.settingText = false;

    ace.config.set("basePath", "/static/vendor/ace-builds-1.45.2/");
    ace.config.set("loadWorkerFromBlob", false);
    const editor = ace.edit("editor", {
      mode: "ace/mode/melfa",
      theme: "ace/theme/melfa",
      useWorker: false,
      tabSize: 2,
      useSoftTabs: true,
      showPrintMargin: false,
      fontSize: "14px",
      fontFamily: 'ui-monospace, "DejaVu Sans Mono", Menlo, Consolas, monospace',
      enableBasicAutocompletion: true,
      enableLiveAutocompletion: false,
      highlightActiveLine: true,
      scrollPastEnd: 0.3,
    });
    editor.textInput.getElement().setAttribute("aria-label", "Program (MELFA BASIC IV)");
    // Undo and redo take back this page's own edits, never a partner's (coedit.js).
    editor.commands.addCommand({ name: "undo", bindKey: { win: "Ctrl-Z", mac: "Command-Z" }, exec: () => workspace.live?.undo.undo() });
    editor.commands.addCommand({ name: "redo", bindKey: { win: "Ctrl-Shift-Z|Ctrl-Y", mac: "Command-Shift-Z|Command-Y" }, exec: () => workspace.live?.undo.redo() });
    editor.commands.addCommand({ name: "melfaCheck", bindKey: { win: "F7", mac: "F7" }, exec: () => this.check() });
    // Tab should leave the editor for keyboard users when pressed with Escape first (Ace default keeps it).
    this.editor = editor;
    this.session = editor.session;

    this.liveBox = $("live-check");
    this.liveBox.checked = localStorage.getItem(LIVE_KEY) !== "off";
    this.liveBox.addEventListener("change", () => {
      localStorage.setItem(LIVE_KEY, this.liveBox.checked ? "on" : "off");
      if (this.liveBox.checked) this.check();
      else this.liveCheck.cancel();
    });
    this.liveCheck = debounce(() => this.check(), CHECK_DELAY_MS);

    // Typing is an edit of the live document (workspace.js, coedit.js); partners' edits
    // come back as Yjs deltas applied in place, so this editor's cursor stays put.
    this.session.on("change", (delta) => {
      if (this.settingText) return;
      this.workspace.editProgram(delta, this.session.doc);
      if (this.liveBox.checked) this.liveCheck();
    });
    workspace.on("replaced", () => this.setText(workspace.program));
    workspace.on("remote", ({ delta }) => this.applyRemote(delta));
    // Someone else's work read (staff from the desk or the class view): long lines wrap,
    // so a reader sees each line whole without scrolling sideways; one's own work does not.
    workspace.on("access", () => {
      this.editor.setReadOnly(!workspace.writable);
      const live = workspace.live;
      this.session.setUseWrapMode(Boolean(live?.synced && live.visiting && !live.writable));
    });
    this.editor.setReadOnly(true); // until the live document is here
    workspace.on("points", () => {
      if (this.liveBox.checked) this.liveCheck();
    });

    this.installHover();
    $("open-mb4").addEventListener("click", () => $("file-mb4").click());
    $("file-mb4").addEventListener("change", (e) => this.openFile(e.target));
  }

  get text() {
    return this.session.getValue();
  }

  setText(text) {
    if (text === this.session.getValue()) return;
    this.settingText = true;
    const cursor = this.editor.getCursorPosition();
    this.session.setValue(text);
    this.editor.moveCursorToPosition(cursor);
    this.editor.clearSelection();
    this.settingText = false;
    this.clear();
    if (this.liveBox.checked) this.liveCheck();
  }

  /** A partner's edit (a Yjs delta on the program): applied where it was made. */
  applyRemote(delta) {
    const doc = this.session.doc;
    this.settingText = true;
    try {
      let index = 0;
      for (const op of delta) {
        if (op.retain) {
          index += op.retain;
        } else if (typeof op.insert === "string") {
          doc.insert(doc.indexToPosition(index, 0), op.insert);
          index += op.insert.length;
        } else if (op.delete) {
          const from = doc.indexToPosition(index, 0);
          const to = doc.indexToPosition(index + op.delete, 0);
          doc.remove(new Range(from.row, from.column, to.row, to.column));
        }
      }
    } finally {
      this.settingText = false;
    }
    if (this.session.getValue() !== this.workspace.program) this.setText(this.workspace.program);
    if (this.liveBox.checked) this.liveCheck();
  }

  /** Check now (manual button, F7, or the debounced on-the-fly call). */
  async check({ announce = false } = {}) {
    const seq = ++this.seq;
    const program = this.text;
    try {
      const out = await api("POST", "/api/check", { program, points: this.workspace.points });
      if (seq !== this.seq || program !== this.text) return null; // a newer check is coming
      this.show(out.program.diagnostics);
      this.dispatchEvent(new CustomEvent("checked", { detail: out }));
      if (announce) {
        const { errors, warnings } = out.program;
        if (!errors && !warnings) toast("No problems found", { kind: "ok", text: "The program and its points look right." });
      }
      return out;
    } catch (err) {
      if (announce) showError("Could not check", err);
      return null;
    }
  }

  /** Show diagnostics (1-based lines/columns, end exclusive). */
  show(diagnostics) {
    this.clear();
    this.diagnostics = diagnostics;
    const type = { error: "error", warning: "warning", info: "info" };
    this.session.setAnnotations(
      diagnostics.map((d) => ({
        row: d.line - 1,
        column: d.column - 1,
        type: type[d.severity] || "info",
        text: d.message + (d.suggestion ? "\n" + d.suggestion : "") + (d.code ? `  [${d.code}]` : ""),
      })),
    );
    for (const d of diagnostics) {
      const range = this.rangeOf(d);
      const cls = d.severity === "error" ? "melfa-err" : d.severity === "warning" ? "melfa-warn" : "melfa-info";
      this.markers.push(this.session.addMarker(range, cls, "text", true));
    }
    this.renderProblems();
  }

  rangeOf(d) {
    const row = d.line - 1;
    const endRow = Math.max(row, (d.end_line || d.line) - 1);
    let start = d.column - 1;
    let end = (d.end_column || d.column + 1) - 1;
    if (endRow === row && end <= start) {
      // A point (e.g. "missing THEN"): underline the word there, or the line's last char.
      const line = this.session.getLine(row);
      end = Math.min(line.length, start + 1);
      if (end <= start) start = Math.max(0, line.length - 1);
      end = Math.max(end, start + 1);
    }
    return new Range(row, start, endRow, end);
  }

  clear() {
    for (const id of this.markers) this.session.removeMarker(id);
    this.markers = [];
    this.diagnostics = [];
    this.session.clearAnnotations();
    this.renderProblems();
  }

  renderProblems() {
    const list = $("problem-list");
    const errors = this.diagnostics.filter((d) => d.severity === "error").length;
    const warnings = this.diagnostics.filter((d) => d.severity === "warning").length;
    const summary = $("diag-summary");
    summary.replaceChildren();
    if (errors || warnings) {
      summary.append(
        el("span", { class: errors ? "e" : "" }, `${errors} error${errors === 1 ? "" : "s"}`), ", ",
        el("span", { class: warnings ? "w" : "" }, `${warnings} warning${warnings === 1 ? "" : "s"}`),
      );
    }
    list.replaceChildren(
      ...this.diagnostics.map((d) => {
        // A real button per problem (its visible words are its name); the fix beside it.
        // With fix buttons beside it the buttons are the fix: the suggestion's words stay in
        // the tooltip and the editor's hover, and the whole message fits (it wraps, never cut).
        const fixes = this.fixButton(d);
        return el("li", {},
          el("button", { type: "button", class: "problem-go", title: `Line ${d.line}: ${d.message}${d.suggestion ? " — " + d.suggestion : ""}`, onclick: () => this.goTo(d) },
            el("span", { class: `sev ${d.severity}` }, d.severity),
            el("span", { class: "loc" }, `${d.line}:${d.column}`),
            el("span", { class: "what" }, d.message, d.suggestion && !fixes ? el("span", { class: "sugg" }, " — " + d.suggestion) : null,
              d.code ? el("span", { class: "code" }, `  ${d.code}`) : null)),
          fixes,
        );
      }),
    );
  }

  /**
   * The fixes beside a problem: the checker's replacement first ("Did you mean Phome?":
   * one click writes it), then for "P1 is not defined" defining it from where the robot
   * stands.
   */
  fixButton(d) {
    const r = this.rangeOf(d);
    const fixes = [];
    if (d.replace) {
      fixes.push(el("button", {
        type: "button", class: "btn btn-sm btn-primary fix-replace",
        onclick: () => {
          this.session.replace(r, d.replace);
          this.editor.focus();
        },
      }, `Replace with ${d.replace}`));
    }
    const name = this.session.getTextRange(r).trim();
    if (d.rule === "undefined-point" && this.onAddPoint && /^[A-Za-z][A-Za-z0-9]*$/.test(name)) {
      fixes.push(el("button", {
        type: "button", class: "btn btn-sm fix-add-point",
        onclick: () => this.onAddPoint(name),
      }, `Add ${name} from the current position`));
    }
    return fixes.length ? el("span", { class: "fixes" }, ...fixes) : null;
  }

  goTo(d) {
    this.editor.focus();
    this.editor.gotoLine(d.line, d.column - 1, true);
  }

  /** Mark the line the robot is running (row 0-based), or none (null); the editor follows it. */
  markRunLine(row) {
    this.markLine("run", "melfa-runline", "runLine", row);
  }

  /** Mark the line a run-time error stopped the program at (row 0-based), or none (null). */
  markErrorLine(row) {
    this.markLine("error", "melfa-errorline", "errorLine", row);
  }

  /** One full-line marker per `kind`, named on the container's `data-*` for tests and styles. */
  markLine(kind, css, data, row) {
    this.lineMarks ??= {};
    const mark = this.lineMarks[kind] ?? { row: null, id: null };
    if (row === mark.row) return;
    if (mark.id != null) this.session.removeMarker(mark.id);
    this.lineMarks[kind] = { row, id: null };
    if (row == null || row < 0 || row >= this.session.getLength()) {
      delete this.editor.container.dataset[data];
      return;
    }
    this.lineMarks[kind].id = this.session.addMarker(new Range(row, 0, row, 1), css, "fullLine", false);
    this.editor.container.dataset[data] = String(row + 1);
    this.follow(row);
  }

  /** Scroll `row` into view when it is off screen (the program's line, not the cursor). */
  follow(row) {
    const first = this.editor.getFirstVisibleRow();
    const last = this.editor.getLastVisibleRow();
    if (row > first && row < last) return;
    this.editor.scrollToLine(row, true, false, () => {});
  }

  /** Hovering an underlined range shows its message and suggestion. */
  installHover() {
    const tip = $("tooltip");
    let shown = null;
    const hide = () => {
      tip.hidden = true;
      shown = null;
    };
    this.editor.on("mousemove", (e) => {
      const pos = e.getDocumentPosition();
      const hit = this.diagnostics.find((d) => {
        const r = this.rangeOf(d);
        return r.contains(pos.row, pos.column) || (r.start.row === pos.row && pos.column === r.end.column);
      });
      if (!hit) return hide();
      // Only over real text, not the empty space right of the line.
      const screen = this.editor.renderer.textToScreenCoordinates(pos.row, this.session.getLine(pos.row).length);
      if (e.clientX > screen.pageX + 8) return hide();
      if (shown !== hit) {
        tip.replaceChildren(
          el("span", { class: "sevline" }, `${hit.severity[0].toUpperCase()}${hit.severity.slice(1)}${hit.code ? " " + hit.code : ""}: `),
          hit.message,
          hit.suggestion ? el("span", { class: "sugg" }, hit.suggestion) : null,
        );
        shown = hit;
      }
      tip.hidden = false;
      tip.style.left = `${Math.min(e.clientX + 12, window.innerWidth - tip.offsetWidth - 8)}px`;
      tip.style.top = `${e.clientY + 18}px`;
    });
    this.editor.container.addEventListener("mouseleave", hide);
    this.session.on("changeScrollTop", hide);
  }

  /** Open an .MB4 from the computer: step numbers stripped (jump targets kept). */
  async openFile(input) {
    const file = input.files[0];
    input.value = "";
    if (!file) return;
    if (!hasExtension(file.name, "MB4")) {
      toast(`${file.name} was not opened`, { kind: "error", text: "Programs are .MB4 files. Choose a file ending in .MB4 (points files, .POS, go in the Points tab)." });
      return;
    }
    try {
      const text = (await readTextFile(file)).replace(/\r\n?/g, "\n");
      const out = await api("POST", "/api/strip", { program: text });
      if (!out.ok) {
        toast(`${file.name}: step numbers kept`, { kind: "warning", text: "Some numbers could not be removed without changing the program.", items: out.diagnostics.map(describeDiagnostic) });
      }
      const choice = await confirmReplace(this.workspace, file.name, out.text, "program");
      if (choice === "cancel") return;
      if (choice === "beside") {
        if (await openBeside(this.workspace, file.name, { program: out.text })) this.check();
        return;
      }
      this.workspace.replace({ program: out.text }, "file");
      toast(`Opened ${file.name}`, { kind: "ok", text: "Step numbers are added back when you save or load the project." });
      this.check();
    } catch (err) {
      showError(`Could not open ${file.name}`, err);
    }
  }
}
