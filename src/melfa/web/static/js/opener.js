// Nothing replaced without asking: opening a file over work that differs asks first —
// replace (the current text is saved as a revision first, so History brings it back),
// open beside as a new workspace named after the file (the current one untouched), or
// cancel. And History's "Compare": a line diff of a revision against the text now.

import { api } from "./api.js";
import { el, toast } from "./ui.js";

let dialog = null;

function makeDialog() {
  dialog = el("dialog", { id: "open-dialog", class: "open-dialog", "aria-labelledby": "open-dialog-title", "aria-describedby": "open-dialog-text" },
    el("h2", { id: "open-dialog-title" }),
    el("p", { id: "open-dialog-text" }),
    el("div", { class: "open-choices" },
      el("button", { type: "button", class: "open-choice", id: "open-beside" },
        el("strong", {}, "Open beside as a new workspace"),
        el("span", { id: "open-beside-note" })),
      el("button", { type: "button", class: "open-choice", id: "open-replace" },
        el("strong", {}, "Replace"),
        el("span", { id: "open-replace-note" }))),
    el("div", { class: "dialog-actions" },
      el("button", { type: "button", class: "btn", id: "open-cancel" }, "Cancel")));
  document.body.append(dialog);
}

/** The stem of a file name ("PYRAMID.MB4" -> "PYRAMID"). */
export function fileStem(fileName) {
  return fileName.replace(/\.[^.]*$/, "").trim() || fileName;
}

/** `wanted`, or `wanted (2)`, `(3)`…: the first name not taken (compared without case). */
export function freeName(wanted, taken) {
  const used = new Set(taken.map((t) => t.toLowerCase()));
  const base = wanted.replace(/\s+/g, " ").trim().slice(0, 60) || "Opened file";
  if (!used.has(base.toLowerCase())) return base;
  for (let n = 2; ; n++) {
    const name = `${base.slice(0, 60 - ` (${n})`.length).trim()} (${n})`;
    if (!used.has(name.toLowerCase())) return name;
  }
}

/**
 * A file is about to go into the workspace's `part` (program | points). Resolves
 * "replace" (the current text already saved as a revision), "beside" or "cancel". Asks
 * only when there is something to lose: the part holds text that differs from the file.
 */
export function confirmReplace(workspace, fileName, newText, part = "program") {
  const current = workspace[part];
  if (!current.trim() || current === newText) return Promise.resolve("replace");
  if (!dialog) makeDialog();
  const lines = current.split("\n").filter((l) => l.trim()).length;
  const what = part === "program" ? "program" : "points";
  const unsaved = workspace.dirty ? " (with edits not saved yet)" : "";
  dialog.querySelector("#open-dialog-title").textContent = `Open ${fileName}?`;
  dialog.querySelector("#open-dialog-text").textContent =
    `“${workspace.name}” already holds ${what === "program" ? "a program" : "points"} of ${lines} line${lines === 1 ? "" : "s"}${unsaved}. Nothing is lost either way.`;
  dialog.querySelector("#open-beside-note").textContent =
    `A new workspace “${freeName(fileStem(fileName), workspace.myNames())}” holds the file; “${workspace.name}” stays as it is, one click away in the workspace menu.`;
  dialog.querySelector("#open-replace-note").textContent =
    `${fileName} replaces the ${what} in “${workspace.name}”. The current ${what} is kept as a revision: History brings it back.`;
  return new Promise((resolve) => {
    const done = async (choice) => {
      dialog.close();
      if (choice === "replace") {
        await workspace.save("save").catch(() => {});
        if (workspace.dirty) {
          toast(`${fileName} was not opened`, { kind: "warning", text: "The current text could not be saved first, so nothing was replaced. Try again once the status says Saved." });
          choice = "cancel";
        }
      }
      resolve(choice);
    };
    dialog.querySelector("#open-cancel").onclick = () => done("cancel");
    dialog.querySelector("#open-replace").onclick = () => done("replace");
    dialog.querySelector("#open-beside").onclick = () => done("beside");
    dialog.oncancel = (e) => { e.preventDefault(); done("cancel"); };
    dialog.showModal();
    dialog.querySelector("#open-beside").focus();
  });
}

/** Open `content` (from `fileName`) as a new workspace of mine named after the file. */
export async function openBeside(workspace, fileName, content) {
  const before = workspace.name;
  const made = await workspace.create(freeName(fileStem(fileName), workspace.myNames()), { ...content, fromFile: fileName });
  if (made) toast(`Opened ${fileName} as “${made.name}”`, { kind: "ok", text: `A new workspace. “${before}” is unchanged: switch back to it with the workspace menu.` });
  return made;
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
    el("pre", { class: "diff program-lines", tabindex: "0", "aria-label": "Differences" },
      lines.map((l) => el("span", { class: l.op === "+" ? "add" : l.op === "-" ? "del" : "same" }, `${l.op} ${l.text}\n`))),
    el("div", { class: "dialog-actions" },
      el("button", { type: "button", class: "btn", onclick: () => diffDialog.close() }, "Close"),
      el("button", { type: "button", class: "btn btn-primary", onclick: () => { diffDialog.close(); restore(number); } }, `Restore revision ${number}`)));
  diffDialog.showModal();
}
