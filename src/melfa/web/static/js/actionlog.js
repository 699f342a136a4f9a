// The toolbar's "Robot log": what this user asked the robot they drive (the lab robot or
// their simulator) and what it answered, and the control changes they caused, in words and
// local time. Kept on the server (GET /api/robot/log: their entries of that robot's log),
// so it is the same in every tab, after a reload and on another PC; nothing is kept in
// this browser. Words: melfa.vocab.robot_log (ROBOT_LOG_WORDS), the rows as the desk's.

import { api } from "./api.js";
import { oneRowEach, outcome, said } from "./desk-audit.js";
import { el, showError } from "./ui.js";
import { IDE_WORDS, ROBOT_LOG_WORDS as RL } from "/vocab.js";

export class ActionLog {
  constructor(app) {
    this.app = app;
    const button = el("button", { type: "button", class: "btn btn-sm", id: "action-log-button", "aria-haspopup": "dialog",
      title: RL["mine-help"], onclick: () => this.open() }, RL.title);
    document.getElementById("activity").after(button);
  }

  async open() {
    let entries;
    try {
      entries = oneRowEach((await api("GET", "/api/robot/log?limit=200")).entries);
    } catch (err) {
      showError(RL.title, err);
      return;
    }
    let dialog = document.getElementById("action-log");
    if (!dialog) {
      dialog = el("dialog", { id: "action-log", "aria-labelledby": "action-log-title", class: "robot-log" });
      document.body.append(dialog);
    }
    const failed = (e) => e.result.startsWith("failed") || e.result.startsWith("refused");
    const rows = entries.map((e) => el("tr", { class: failed(e) ? "failed" : "" },
      el("td", {}, new Date(e.at).toLocaleString()), el("td", {}, said(e)), el("td", {}, outcome(e.result))));
    dialog.replaceChildren(
      el("h2", { id: "action-log-title" }, RL["mine-title"]),
      rows.length
        ? el("div", { class: "table-wrap log-wrap" }, el("table", { class: "points action-log" }, // points: the tables' look
          el("thead", {}, el("tr", {}, ...RL["mine-columns"].split(",").map((c) => el("th", { scope: "col" }, c)))),
          el("tbody", {}, rows)))
        : el("p", { class: "muted" }, RL["mine-empty"]),
      el("div", { class: "dialog-actions" }, el("button", { type: "button", class: "btn", onclick: () => dialog.close() }, IDE_WORDS.close)));
    dialog.showModal();
  }
}
