// Nothing replaced without asking: opening a file over work that differs asks first
// (replace, keeping the current text as a revision in History; download mine first;
// cancel). And History's "Compare": a line diff of a revision against the text now.

import { api, downloadText } from "./api.js";
import { el } from "./ui.js";

let dialog = null;

function makeDialog() {
  dialog = el("dialog", { id: "open-dialog", "aria-labelledby": "open-dialog-title" },
    el("h2", { id: "open-dialog-title" }, "Replace your program?"),
    el("p", { id: "open-dialog-text" }),
    el("div", { class: "dialog-actions" },
      el("button", { type: "button", class: "btn", id: "open-cancel", value: "cancel" }, "Cancel"),
      el("button", { type: "button", class: "btn", id: "open-download" }, "Download mine, then replace"),
      el("button", { type: "button", class: "btn btn-primary", id: "open-replace", value: "replace" }, "Replace")));
  document.body.append(dialog);
}

/** Resolve true to go on (the current text saved as a revision first), false to cancel. */
export function confirmReplace(workspace, fileName, newText) {
  const current = workspace.program;
  if (!current.trim() || current === newText) return Promise.resolve(true);
  if (!dialog) makeDialog();
  dialog.querySelector("#open-dialog-text").textContent =
    `${fileName} would replace the program in the editor (${current.split("\n").length} lines). ` +
    "Your current program is saved as a revision first, so History can bring it back.";
  return new Promise((resolve) => {
    const done = async (go, download = false) => {
      dialog.close();
      if (go) {
        if (download) downloadText(current, `${workspace.owner || "program"}-before-${fileName}`);
        await workspace.save("save").catch(() => {});
      }
      resolve(go);
    };
    dialog.querySelector("#open-cancel").onclick = () => done(false);
    dialog.querySelector("#open-replace").onclick = () => done(true);
    dialog.querySelector("#open-download").onclick = () => done(true, true);
    dialog.oncancel = (e) => { e.preventDefault(); done(false); };
    dialog.showModal();
    dialog.querySelector("#open-cancel").focus();
  });
}

/** Line diff (LCS): [{op: " "|"-"|"+", text}]. Small programs: O(n·m) is fine. */
export function lineDiff(before, after) {
  const a = before.split("\n");
  const b = after.split("\n");
  const n = a.length;
  const m = b.length;
  const lcs = Array.from({ length: n + 1 }, () => new Uint16Array(m + 1));
  for (let i = n - 1; i >= 0; i--) {
    for (let j = m - 1; j >= 0; j--) lcs[i][j] = a[i] === b[j] ? lcs[i + 1][j + 1] + 1 : Math.max(lcs[i + 1][j], lcs[i][j + 1]);
  }
  const out = [];
  let i = 0;
  let j = 0;
  while (i < n || j < m) {
    if (i < n && j < m && a[i] === b[j]) { out.push({ op: " ", text: a[i] }); i++; j++; }
    else if (j < m && (i === n || lcs[i][j + 1] >= lcs[i + 1][j])) { out.push({ op: "+", text: b[j] }); j++; }
    else { out.push({ op: "-", text: a[i] }); i++; }
  }
  return out;
}

let diffDialog = null;

/** Show revision `number` against the editor's text now. */
export async function showDiff(workspace, number, restore) {
  const rev = (await api("GET", `/api/workspaces/${workspace.id}/revisions/${number}`));
  const revision = rev.revision ?? rev;
  if (!diffDialog) {
    diffDialog = el("dialog", { id: "diff-dialog", "aria-labelledby": "diff-title", class: "diff-dialog" });
    document.body.append(diffDialog);
  }
  const lines = lineDiff(revision.program, workspace.program);
  const changed = lines.filter((l) => l.op !== " ").length;
  diffDialog.replaceChildren(
    el("h2", { id: "diff-title" }, `Revision ${number} compared with now`),
    el("p", { class: "muted" }, changed ? `${changed} line${changed === 1 ? "" : "s"} differ: − only in revision ${number}, + only now.` : "The program is the same as now."),
    el("pre", { class: "diff", tabindex: "0", "aria-label": "Differences" },
      lines.map((l) => el("span", { class: l.op === "+" ? "add" : l.op === "-" ? "del" : "same" }, `${l.op} ${l.text}\n`))),
    el("div", { class: "dialog-actions" },
      el("button", { type: "button", class: "btn", onclick: () => diffDialog.close() }, "Close"),
      el("button", { type: "button", class: "btn btn-primary", onclick: () => { diffDialog.close(); restore(number); } }, `Restore revision ${number}`)));
  diffDialog.showModal();
}
