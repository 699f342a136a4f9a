// Assignments in the IDE (docs/ide.md "Assignments"). The "Assignments" button lists what
// the instructor handed out; opening one makes it a workspace (the starter of this
// student's variant), the IDE drives their own simulator, and the assignment's pane stands
// beside the editor: the statement, the checks, *Check my solution* (each check passed or
// failed, the line that caused a failure one click away) and *Submit* with the attempts
// left. The 3D view shows the assignment's cell while its workspace is open. Every word
// comes from /vocab.js.

import { api } from "./api.js";
import { $, el, showError, toast } from "./ui.js";
import { GRADED_WORDS, GRADE_WORDS, PANE_WORDS as W, RESULT_WORDS } from "/vocab.js"; // generated from melfa.vocab.classroom

export const fill = (template, values) => template.replace(/\{(\w+)\}/g, (_, k) => String(values[k] ?? ""));

/** "Due Mon 1 Dec, 14:00" in the browser's own time zone. */
export function dueWords(iso) {
  if (!iso) return "";
  const when = new Date(iso).toLocaleString(undefined, { weekday: "short", day: "numeric", month: "short", hour: "2-digit", minute: "2-digit" });
  return fill(RESULT_WORDS.due, { due: when });
}

export function attemptsWords(left, total) {
  if (total == null) return RESULT_WORDS["attempts-unlimited"];
  if (left === 0) return RESULT_WORDS.closed;
  return fill(RESULT_WORDS["attempts-left"], { left: left ?? total, total });
}

/**
 * What a grading says: "Submitted: 5 of 14 checks passed", "Checked: every check passed".
 * `grading` is the server's record of it: its `summary` is the same words the class view shows.
 */
export function graded(kind, grading) {
  return fill(GRADED_WORDS[kind], { verdict: grading.summary });
}

export class AssignmentsPanel {
  constructor(app) {
    this.app = app;
    this.list = []; // GET /api/assignments
    this.current = null; // the open assignment (GET /api/assignments/{id}) when its workspace is current
    this.busy = false;
    this.build();
    app.workspace.on("switched", () => this.follow());
  }

  build() {
    this.button = el("button", { type: "button", class: "btn btn-sm", id: "assign-open", title: W["button-hint"] },
      W.button, el("span", { class: "badge", id: "assign-count", hidden: true }));
    this.button.addEventListener("click", () => this.showList());
    $("open-mb4").before(this.button);

    this.statement = el("div", { class: "assign-statement", id: "assign-statement" });
    this.checks = el("ol", { class: "assign-checks", id: "assign-checks" });
    this.summary = el("p", { class: "assign-summary", id: "assign-summary", "aria-live": "polite" });
    this.meta = el("p", { class: "assign-meta muted", id: "assign-meta" });
    this.variant = el("p", { class: "assign-variant", id: "assign-variant", hidden: true });
    this.checkButton = el("button", { type: "button", class: "btn btn-primary btn-sm", id: "assign-check" }, GRADE_WORDS.check);
    this.submitButton = el("button", { type: "button", class: "btn btn-sm", id: "assign-submit" }, GRADE_WORDS.submit);
    this.checkButton.addEventListener("click", () => this.grade("check"));
    this.submitButton.addEventListener("click", () => this.grade("submit"));
    this.attempts = el("span", { class: "assign-attempts muted", id: "assign-attempts" });
    this.title = el("strong", { id: "assign-title" });
    const hide = el("button", { type: "button", class: "btn btn-sm btn-icon", "aria-label": W.hide, title: W.hide }, "✕");
    hide.addEventListener("click", () => { this.pane.hidden = true; });
    this.pane = el("aside", { class: "assignment", id: "assignment", "aria-label": W.pane, hidden: true },
      el("div", { class: "assign-head" }, this.title, hide),
      el("div", { class: "assign-body", tabindex: "0", "aria-label": W.body }, this.meta, this.variant, this.statement,
        el("h3", {}, W.checks), this.checks),
      el("div", { class: "assign-foot" }, this.summary,
        el("div", { class: "assign-actions" }, this.checkButton, this.submitButton, this.attempts)));
    $("editor").after(this.pane);
  }

  async refresh() {
    try {
      this.list = (await api("GET", "/api/assignments")).assignments;
    } catch (err) {
      showError(W["read-failed"], err);
      return;
    }
    this.badge();
    await this.follow();
  }

  /** The count beside the button: assignments without a passing submission yet. */
  badge() {
    const waiting = this.list.filter((a) => !a.mine?.best?.passed).length;
    const badge = $("assign-count");
    badge.hidden = waiting === 0;
    badge.textContent = String(waiting);
  }

  /** The assignment whose workspace is the current one, if any. */
  of(workspaceId) {
    return this.list.find((a) => a.mine?.workspace_id === workspaceId) || null;
  }

  /** Show the pane when the current workspace is an assignment's; put the lab's cell back otherwise. */
  async follow() {
    const found = this.of(this.app.workspace.id);
    if (!found) {
      if (this.current) this.app.preflight?.load();
      this.current = null;
      this.pane.hidden = true;
      document.body.dataset.assignment = "";
      return;
    }
    if (this.current?.id !== found.id) {
      try {
        this.current = await api("GET", `/api/assignments/${found.id}`);
      } catch (err) {
        showError(W["open-failed"], err);
        return;
      }
      this.render();
      this.app.preflight?.setCell(this.current.cell);
    }
    this.pane.hidden = false;
    document.body.dataset.assignment = String(found.id);
  }

  render(result = null) {
    const a = this.current;
    this.title.textContent = a.title;
    this.meta.textContent = [dueWords(a.due), a.group ? fill(W["for-group"], { group: a.group }) : ""].filter(Boolean).join(" · ");
    this.variant.hidden = !a.mine?.variant;
    this.variant.textContent = a.mine?.variant || "";
    this.statement.innerHTML = a.statement_html; // rendered by the server; raw HTML escaped there
    const results = result ? result.report.checks : null;
    this.checks.replaceChildren(...a.checks.map((c, i) => {
      const r = results?.[i];
      const item = el("li", { class: r ? (r.passed ? "pass" : "fail") : "", "data-kind": c.kind },
        el("span", { class: "mark", "aria-hidden": "true" }, r ? (r.passed ? "✓" : "✗") : "·"),
        el("span", { class: "what" }, el("span", { class: "check-title" }, c.title),
          r && !r.passed ? el("span", { class: "why" }, r.message) : null),
        r && !r.passed && r.line ? el("button", { type: "button", class: "linkish line", "data-line": String(r.line), title: W["line-hint"] }, fill(W.line, { line: r.line })) : null);
      item.querySelector(".line")?.addEventListener("click", () => this.goTo(r.line));
      item.setAttribute("aria-label", `${c.title}: ${r ? RESULT_WORDS[r.passed ? "passed" : "failed"] : RESULT_WORDS.none}`);
      return item;
    }));
    const latest = result?.grading || a.mine?.latest;
    if (result) {
      this.summary.textContent = `${graded(result.grading.kind, result.grading)}.`;
      this.summary.dataset.passed = String(result.report.passed);
    } else {
      this.summary.textContent = latest ? graded(latest.kind, latest) : RESULT_WORDS.none;
      this.summary.dataset.passed = latest ? String(latest.passed) : "";
    }
    const left = result ? result.attempts_left : a.mine?.attempts_left;
    this.attempts.textContent = attemptsWords(left, a.attempts);
    this.submitButton.disabled = left === 0;
  }

  goTo(line) {
    const editor = this.app.editor.editor;
    editor.gotoLine(line, 0, true);
    editor.focus();
  }

  /** Check (or submit) what is typed: saved first, so the graded revision is this text. */
  async grade(kind) {
    if (this.busy || !this.current) return;
    this.busy = true;
    this.checkButton.disabled = this.submitButton.disabled = true;
    this.pane.dataset.grading = kind;
    this.app.busy(kind === "check" ? W.checking : W.submitting);
    try {
      if (!(await this.app.workspace.flush())) {
        toast(W["not-saved-title"], { kind: "warning", text: W["not-saved"] });
        this.app.idle();
        return;
      }
      const out = await api("POST", `/api/assignments/${this.current.id}/${kind}`);
      this.render(out);
      this.app.idle(graded(kind, out.grading), !out.report.passed);
      if (kind === "submit") toast(W["submitted-title"], { kind: out.report.passed ? "ok" : "info", text: fill(W.submitted, { revision: out.grading.revision, left: attemptsWords(out.attempts_left, this.current.attempts) }) });
      await this.refreshQuietly();
    } catch (err) {
      this.app.idle(fill(W["not-done"], { what: GRADE_WORDS[kind] }), true);
      showError(kind === "check" ? W["check-failed"] : W["submit-failed"], err);
    } finally {
      this.busy = false;
      this.checkButton.disabled = false;
      this.submitButton.disabled = this.attempts.textContent === RESULT_WORDS.closed;
      delete this.pane.dataset.grading;
    }
  }

  async refreshQuietly() {
    try {
      this.list = (await api("GET", "/api/assignments")).assignments;
      this.badge();
      const found = this.of(this.app.workspace.id);
      if (found && this.current) this.current = { ...this.current, mine: found.mine };
    } catch { /* the result is shown already */ }
  }

  /** Open assignment `id`: made a workspace the first time, then switched to. */
  async open(id) {
    try {
      const detail = await api("POST", `/api/assignments/${id}/open`);
      await this.app.workspace.refreshList();
      this.list = (await api("GET", "/api/assignments")).assignments;
      this.current = null;
      if (!(await this.app.workspace.switchTo(detail.mine.workspace_id))) return;
      // An assignment is worked on on one's own simulated arm, never the lab's.
      this.app.targets.choose("mine");
      await this.follow();
    } catch (err) {
      showError(W["open-failed"], err);
    }
  }

  async showList() {
    await this.refresh();
    let dialog = $("assign-dialog");
    if (!dialog) {
      dialog = el("dialog", { id: "assign-dialog", class: "assign-dialog", "aria-labelledby": "assign-dialog-title" });
      document.body.append(dialog);
    }
    const staff = this.app.role === "instructor" || this.app.role === "admin";
    const rows = this.list.map((a) => {
      const mine = a.mine;
      const state = !mine ? RESULT_WORDS["not-opened"]
        : mine.best ? graded("submit", mine.best)
          : mine.latest ? graded("check", mine.latest) : RESULT_WORDS.none;
      const open = el("button", { type: "button", class: "btn btn-sm btn-primary", "data-id": String(a.id) }, mine ? W.continue : W.open);
      open.addEventListener("click", () => { dialog.close(); this.open(a.id); });
      return el("li", { class: "assign-row", "data-id": String(a.id) },
        el("div", {}, el("strong", {}, a.title),
          el("div", { class: "muted" }, [dueWords(a.due), attemptsWords(mine?.attempts_left, a.attempts), state].filter(Boolean).join(" · "))),
        open);
    });
    dialog.replaceChildren(
      el("h2", { id: "assign-dialog-title" }, W["list-title"]),
      rows.length ? el("ul", { class: "assign-list" }, rows) : el("p", { class: "muted" }, W["list-empty"]),
      el("div", { class: "dialog-actions" },
        staff ? el("a", { class: "btn", href: "/classroom", target: "_blank", rel: "noopener", id: "assign-classroom" }, W["to-classroom"]) : null,
        el("button", { type: "button", class: "btn", onclick: () => dialog.close() }, W.close)));
    dialog.showModal();
  }
}
