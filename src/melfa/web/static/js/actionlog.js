// The session's robot actions (time, action, result), kept for this browser tab and opened
// from the toolbar's "Robot log": what the student did and what the robot answered, in
// words (the server's `result` events carry the action's label and the student text, never
// a wire request).

import { el } from "./ui.js";

const KEY = "melfa.action-log";

export class ActionLog {
  constructor(app) {
    this.app = app;
    try { this.entries = JSON.parse(sessionStorage.getItem(KEY) || "[]"); } catch { this.entries = []; }
    app.live.on("result", (m) => {
      if (m.actor?.user !== app.user) return;
      this.add(m.label || "Robot command", m.ok ? "done" : m.error || "failed", m.ok);
    });
    const button = el("button", { type: "button", class: "btn btn-sm", id: "action-log-button", "aria-haspopup": "dialog",
      title: "What you asked the robot to do in this session, and what it answered", onclick: () => this.open() }, "Robot log");
    document.getElementById("activity").after(button);
  }

  add(action, result, ok) {
    this.entries.push({ at: new Date().toISOString(), action, result, ok });
    if (this.entries.length > 300) this.entries.splice(0, this.entries.length - 300);
    try { sessionStorage.setItem(KEY, JSON.stringify(this.entries)); } catch { /* full */ }
  }

  open() {
    let dialog = document.getElementById("action-log");
    if (!dialog) {
      dialog = el("dialog", { id: "action-log", "aria-labelledby": "action-log-title", class: "diff-dialog" });
      document.body.append(dialog);
    }
    const rows = [...this.entries].reverse().map((e) => el("tr", { class: e.ok ? "" : "failed" },
      el("td", {}, new Date(e.at).toLocaleTimeString()), el("td", {}, e.action), el("td", {}, e.result)));
    dialog.replaceChildren(
      el("h2", { id: "action-log-title" }, "Robot log of this session"),
      rows.length
        ? el("div", { class: "table-wrap log-wrap" }, el("table", { class: "points action-log" },
          el("thead", {}, el("tr", {}, el("th", { scope: "col" }, "Time"), el("th", { scope: "col" }, "Action"), el("th", { scope: "col" }, "Result"))),
          el("tbody", {}, rows)))
        : el("p", { class: "muted" }, "Nothing yet: load, run or move the robot and it is listed here."),
      el("div", { class: "dialog-actions" }, el("button", { type: "button", class: "btn", onclick: () => dialog.close() }, "Close")));
    dialog.showModal();
  }
}
