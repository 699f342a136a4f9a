// Sign-out on a shared lab PC: the copies of workspaces co-editing keeps in this browser
// (coedit.js, for offline edits and a reload) are removed — but only once everything in
// them is saved on the server. If an edit is not (the connection is down), the student is
// told so and chooses: wait (signed out as soon as it is saved) or throw it away; nothing
// is ever dropped without that choice. Words: melfa.vocab.signout.

import { api } from "./api.js";
import { CoeditSession, keptIds } from "./coedit.js";
import { $, toast } from "./ui.js";
import { SIGN_OUT_WORDS as W } from "/vocab.js";

const OPEN_MS = 5000; // how long a kept copy's workspace has to answer before it counts as unsaved
const RETRY_MS = 2000; // while waiting: how often saving is tried again

/** Open (briefly) every other workspace whose copy this browser keeps, so what is in it
 * merges with the server's; the sessions, the current one first. */
async function sessions(workspace, user) {
  const open = workspace.live ? [workspace.live] : [];
  const others = keptIds(user).filter((id) => id !== workspace.id);
  const visits = others.map((id) => new CoeditSession(id, user));
  await Promise.all(visits.map((s) => new Promise((resolve) => {
    if (s.synced) resolve();
    s.on("welcome", resolve);
    s.on("status", ({ state }) => { if (state === "refused") resolve(); });
    setTimeout(resolve, OPEN_MS);
  })));
  return [...open, ...visits];
}

/** The sessions with edits the server has not saved yet (each asked to save first). */
async function unsaved(all) {
  const settled = await Promise.all(all.map((s) => s.settle()));
  return all.filter((_, i) => !settled[i]);
}

function names(workspace, left) {
  const named = (s) => workspace.list.find((w) => w.id === s.id)?.name || `workspace ${s.id}`;
  return left.map(named).join(", ");
}

async function leave(all, loaded) {
  for (const s of all) s.forget();
  loaded.forget(); // nor the last loaded program's text
  try {
    await api("DELETE", "/api/session");
  } finally {
    location.href = "/login";
  }
}

/** Ask what to do about `left` (unsaved), in the page's dialog: resolves "wait",
 * "discard" or "stay". While waiting the dialog stays open (saying so), so throwing the
 * edits away or staying is still one click: `choice()` then gives that answer. */
function ask(workspace, left) {
  const dialog = $("signout-dialog");
  $("signout-title").textContent = W.title;
  $("signout-text").textContent = W.text.replace("{names}", names(workspace, left));
  for (const choice of ["wait", "discard", "stay"]) $(`signout-${choice}`).textContent = W[choice];
  $("signout-wait").hidden = false;
  dialog.showModal();
  const asked = { now: null };
  const first = new Promise((resolve) => {
    const pick = (choice) => () => {
      asked.now = choice;
      if (choice !== "wait") dialog.close();
      resolve(choice);
    };
    $("signout-wait").onclick = pick("wait");
    $("signout-discard").onclick = pick("discard");
    $("signout-stay").onclick = pick("stay");
    dialog.oncancel = (event) => { event.preventDefault(); pick("stay")(); };
  });
  return { first, choice: () => asked.now };
}

/** Sign out: everything saved on the server first, or the student's explicit choice. */
export async function signOut(app, loaded) {
  const workspace = app.workspace;
  toast(W.checking, { kind: "info" });
  const all = await sessions(workspace, app.user);
  let left = await unsaved(all);
  if (left.length === 0) return leave(all, loaded);
  const asked = ask(workspace, left);
  let choice = await asked.first;
  if (choice === "wait") {
    document.body.dataset.signingOut = "waiting";
    $("signout-text").textContent = W.waiting;
    $("signout-wait").hidden = true;
    while (left.length > 0 && asked.choice() === "wait") {
      await new Promise((resolve) => setTimeout(resolve, RETRY_MS));
      left = await unsaved(left);
    }
    choice = left.length === 0 ? "wait" : asked.choice();
    $("signout-dialog").close();
    delete document.body.dataset.signingOut;
  }
  if (choice === "stay") {
    for (const s of all) if (s !== workspace.live) s.close(); // kept, as before
    return;
  }
  return leave(all, loaded);
}
