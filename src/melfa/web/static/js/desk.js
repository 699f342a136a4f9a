// The instructor's desk (/desk, docs/ide.md "The instructor's desk"): the accounts staff
// manage (instructors their students, admins everyone — the server decides, the page
// shows what it was given), adding one, importing a class list (the CSV `melfa users
// import` reads), a new password shown once, removing; and the lab robot's simulation
// gate and the lab's networks switched live, Stop and hold (students' commands refused, naming who holds it, until
// released), and resetting an alarm without taking over; the audit log and each robot's
// log in their own tabs (desk-audit.js). Every word comes from /vocab.js (melfa.vocab.desk).

import { api, downloadText } from "./api.js";
import { signedIn } from "./page.js";
import { $, el, readTextFile, showError, toast } from "./ui.js";
import { listRobots, loadAudit, loadRobotLog, wireAudit, wireRobotLog } from "./desk-audit.js";
import { DESK_WORDS as W, ROBOT_LOG_WORDS as RL, ROLE_WORDS } from "/vocab.js";

const state = { me: null, users: [], gate: false, heldBy: null };
const fill = (text, facts) => text.replace(/\{(\w+)\}/g, (_, k) => String(facts[k] ?? ""));
const when = (iso) => (iso ? new Date(iso).toLocaleString([], { dateStyle: "medium", timeStyle: "short" }) : W.never);

async function main() {
  const session = await signedIn("desk-user");
  if (!session) return;
  state.me = session.user;
  showWords();
  $("desk-title").textContent = W.title;
  $("acc-title").textContent = W.accounts;
  $("acc-note").textContent = state.me.role === "admin" ? "" : W["only-students"];
  $("acc-add").textContent = W.add + "…";
  $("acc-import").textContent = W.import;
  $("add-title").textContent = W.add;
  $("import-title").textContent = W.import.replace("…", "");
  $("import-help").textContent = W["import-help"];
  $("once-help").textContent = W["shown-once"];
  $("gate-title").textContent = W.gate;
  $("acc-none").textContent = W["no-accounts"];
  const roles = state.me.role === "admin" ? ["student", "instructor", "admin"] : ["student"];
  $("add-role").replaceChildren(...roles.map((r) => el("option", { value: r }, ROLE_WORDS[r])));
  $("acc-find").addEventListener("input", () => drawUsers());
  wireAdd();
  wireImport();
  $("gate-toggle").addEventListener("click", () => setGate(!state.gate));
  wireNetworks();
  $("hold-title").textContent = W["hold-title"];
  $("reset-alarm").textContent = W["reset-alarm"];
  $("hold-toggle").addEventListener("click", () => setHold(!state.heldBy));
  $("reset-alarm").addEventListener("click", () => resetAlarm());
  wireAudit();
  await Promise.all([loadUsers(), loadDesk()]);
  wireRobotLog(state.users);
  wireTabs();
  document.body.dataset.ready = "true";
}

/** The page's own words: each element's `data-w` (its text) and `data-w-<attribute>`. */
function showWords() {
  document.title = fill(W["page-title"], { title: W.title });
  for (const node of document.querySelectorAll("[data-w]")) node.textContent = W[node.dataset.w];
  for (const attribute of ["aria-label", "placeholder"]) {
    for (const node of document.querySelectorAll(`[data-w-${attribute}]`)) node.setAttribute(attribute, W[node.getAttribute(`data-w-${attribute}`)]);
  }
}

async function loadUsers() {
  state.users = (await api("GET", "/api/users")).users;
  drawUsers();
  if (document.body.dataset.ready) listRobots(state.users);
}

function drawUsers() {
  const find = $("acc-find").value.trim().toLowerCase();
  const shown = state.users.filter((u) => !find || [u.username, u.display_name, u.group || ""].some((s) => s.toLowerCase().includes(find)));
  $("acc-none").hidden = shown.length > 0;
  $("acc-rows").replaceChildren(...shown.map((u) => el("tr", { "data-user": u.username },
    el("td", {}, el("strong", {}, u.username)),
    el("td", {}, u.display_name || "—"),
    el("td", {}, u.group || "—"),
    el("td", {}, ROLE_WORDS[u.role] ?? u.role),
    el("td", { title: u.last_login || "" }, when(u.last_login)),
    el("td", { class: "desk-actions" },
      u.username === state.me.username ? null // their work opens read-only (docs/ide.md)
        : el("a", { class: "btn btn-sm", "data-act": "work", href: `/?user=${encodeURIComponent(u.username)}`, target: "_blank", rel: "noopener" }, W["open-work"]),
      el("button", { type: "button", class: "btn btn-sm", "data-act": "reset", onclick: () => resetPassword(u) }, W.reset),
      u.username === state.me.username ? null
        : el("button", { type: "button", class: "btn btn-sm btn-danger-ghost", "data-act": "remove", onclick: () => remove(u) }, W.remove)))));
}

/** A confirmation in the page's own dialog; resolves true on the confirming button. */
function confirmed(text, label) {
  const dialog = $("confirm-dialog");
  $("confirm-text").textContent = text;
  $("confirm-ok").textContent = label.replace("…", "");
  dialog.returnValue = "";
  dialog.showModal();
  return new Promise((resolve) => dialog.addEventListener("close", () => resolve(dialog.returnValue === "yes"), { once: true }));
}

/** The passwords just generated, shown this once (with a CSV for the hand-out sheet). */
function showOnce(passwords) {
  const entries = Object.entries(passwords);
  if (!entries.length) return;
  $("once-rows").replaceChildren(...entries.map(([user, pw]) => el("tr", {}, el("td", {}, user), el("td", { class: "desk-password" }, pw))));
  $("once-csv").onclick = () => downloadText("username,password\n" + entries.map(([u, p]) => `${u},${p}`).join("\n") + "\n", "passwords.csv", "text/csv");
  $("once-dialog").showModal();
}

async function resetPassword(u) {
  if (!(await confirmed(fill(W["reset-confirm"], { who: u.username }), W.reset))) return;
  try {
    const reply = await api("PUT", `/api/users/${encodeURIComponent(u.username)}/password`, {});
    showOnce({ [u.username]: reply.password });
  } catch (err) {
    showError(W.reset.replace("…", ""), err);
  }
}

async function remove(u) {
  if (!(await confirmed(fill(W["remove-confirm"], { who: u.username }), W.remove))) return;
  try {
    await api("DELETE", `/api/users/${encodeURIComponent(u.username)}`);
    toast(fill(W.removed, { who: u.username }), { kind: "ok" });
    await loadUsers();
  } catch (err) {
    showError(W.remove.replace("…", ""), err);
  }
}

function wireAdd() {
  const dialog = $("add-dialog");
  $("acc-add").addEventListener("click", () => { $("add-form").reset(); $("add-problems").replaceChildren(); dialog.showModal(); $("add-username").focus(); });
  $("add-cancel").addEventListener("click", () => dialog.close());
  $("add-form").addEventListener("submit", async (event) => {
    event.preventDefault();
    const body = { username: $("add-username").value, display_name: $("add-name").value, group: $("add-group").value || null, role: $("add-role").value };
    try {
      const reply = await api("POST", "/api/users", body);
      dialog.close();
      await loadUsers();
      showOnce({ [reply.user.username]: reply.password });
    } catch (err) {
      $("add-problems").replaceChildren(el("li", { class: "error" }, err.message));
    }
  });
}

function wireImport() {
  const dialog = $("import-dialog");
  let text = null;
  $("acc-import").addEventListener("click", () => { $("import-form").reset(); text = null; $("import-ok").disabled = true; $("import-problems").replaceChildren(); dialog.showModal(); });
  $("import-cancel").addEventListener("click", () => dialog.close());
  $("import-file").addEventListener("change", async () => {
    const file = $("import-file").files[0];
    text = file ? await readTextFile(file) : null;
    $("import-ok").disabled = !text;
    $("import-problems").replaceChildren();
  });
  $("import-form").addEventListener("submit", async (event) => {
    event.preventDefault();
    $("import-ok").disabled = true;
    $("import-ok").textContent = W.importing;
    try {
      const reply = await api("POST", "/api/users/import", { csv: text });
      dialog.close();
      toast(fill(W.imported, { created: reply.created.length, skipped: reply.skipped.length }), { kind: "ok" });
      await loadUsers();
      showOnce(reply.passwords);
    } catch (err) {
      const problems = err.detail?.problems || [];
      $("import-problems").replaceChildren(el("li", { class: "error" }, err.message),
        ...problems.map((p) => el("li", {}, fill(W["import-problem"], p))));
    } finally {
      $("import-ok").textContent = W["import-ok"];
      $("import-ok").disabled = !text;
    }
  });
}

async function loadDesk() {
  drawDesk(await api("GET", "/api/desk"));
}

function drawDesk(desk) {
  drawGate(desk.require_simulation);
  drawFrom("gate-from", desk.require_simulation_from);
  drawNetworks(desk);
  drawFrom("net-from", desk.lab_networks_from);
  state.heldBy = desk.held_by;
  const held = desk.held_by != null;
  $("hold-state").textContent = held ? fill(W.held, { who: desk.held_by }) : W["hold-free"];
  $("hold-state").className = "desk-state" + (held ? " held" : "");
  $("hold-toggle").textContent = held ? W.release : W.hold;
  $("hold-toggle").setAttribute("aria-pressed", String(held));
}

async function setHold(on) {
  try {
    drawDesk(await api(on ? "POST" : "DELETE", "/api/desk/hold"));
  } catch (err) {
    showError(W["hold-title"], err);
  }
}

async function resetAlarm() {
  try {
    await api("POST", "/api/robot/reset-alarm");
    toast(W["alarm-reset"], { kind: "ok" });
  } catch (err) {
    showError(W["reset-alarm"], err);
  }
}

function drawGate(on) {
  state.gate = on;
  $("gate-state").textContent = on ? W["gate-on"] : W["gate-off"];
  $("gate-state").className = "desk-state" + (on ? " on" : "");
  $("gate-toggle").textContent = on ? W["gate-turn-off"] : W["gate-turn-on"];
  $("gate-toggle").setAttribute("aria-pressed", String(on));
}

/** Where a setting came from, in words: the default, the server's start-up option, or who
 * chose it on the desk and when (whether a restart goes back to the option, and whether
 * only the part of the desk's networks inside the option holds). */
export function saidFrom(origin) {
  const cut = origin.cut_from ?? [];
  const facts = { who: origin.by, when: when(origin.at), flag: origin.command_line, saved: cut.join(", ") };
  if (origin.source !== "desk") return fill(W[`from-${origin.source}`] ?? "", facts);
  const key = origin.until_restart ? "from-desk-until-restart" : "from-desk";
  return fill(W[key + (cut.length ? "-cut" : "")], facts);
}

/** The origin's words, the start-up option kept on one line as the technician types it. */
function drawFrom(id, origin) {
  const text = saidFrom(origin);
  const flag = origin.command_line;
  const at = flag ? text.indexOf(flag) : -1;
  if (at < 0) $(id).textContent = text;
  else $(id).replaceChildren(text.slice(0, at), el("code", {}, flag), text.slice(at + flag.length));
}

async function setGate(on) {
  try {
    drawDesk(await api("PUT", "/api/desk/gate", { require_simulation: on }));
  } catch (err) {
    showError(W.gate, err);
  }
}

// --- where students may drive the lab robot from (the service decides, every door) ------

function wireNetworks() {
  $("net-title").textContent = W["lab-network"];
  $("net-label").textContent = W["lab-network-field"];
  $("net-help").textContent = W["lab-network-help"];
  $("net-save").textContent = W["lab-network-save"];
  $("net-clear").textContent = W["lab-network-clear"];
  $("net-form").addEventListener("submit", (event) => {
    event.preventDefault();
    const networks = $("net-input").value.split(",").map((n) => n.trim()).filter(Boolean);
    setNetworks(networks);
  });
  $("net-clear").addEventListener("click", () => setNetworks([]));
}

function drawNetworks(desk) {
  const only = desk.lab_networks.length > 0;
  const networks = desk.lab_networks.join(", ");
  $("net-state").textContent = only ? fill(W["lab-network-only"], { networks }) : W["lab-network-anywhere"];
  $("net-state").className = "desk-state" + (only ? " on" : "");
  $("net-input").value = networks;
  $("net-clear").hidden = !only;
  $("net-you").textContent = desk.your_address ? fill(W["lab-network-you"], { address: desk.your_address }) : "";
}

async function setNetworks(networks) {
  try {
    const desk = await api("PUT", "/api/desk/lab-network", { networks });
    drawDesk(desk);
    toast(fill(W["lab-network-saved"], { networks: desk.lab_networks.join(", ") || W.anywhere }), { kind: "ok" });
  } catch (err) {
    showError(W["lab-network"], err);
  }
}

// --- the tabs: accounts, the audit log, a robot's log ------------------------------------

const TABS = [
  ["tab-accounts", "acc-pane", "", null],
  ["tab-audit", "audit-pane", "#audit", loadAudit],
  ["tab-robots", "robots-pane", "#robots", loadRobotLog],
];

function showTab(tab) {
  for (const [t, pane, hash, load] of TABS) {
    const on = t === tab;
    $(t).setAttribute("aria-selected", String(on));
    $(pane).hidden = !on;
    if (on) {
      history.replaceState(null, "", hash || location.pathname);
      load?.();
    }
  }
}

function wireTabs() {
  for (const [tab] of TABS) $(tab).addEventListener("click", () => showTab(tab));
  $("tab-robots").textContent = RL.title;
  const asked = TABS.find(([, , hash]) => hash && hash === location.hash);
  if (asked) showTab(asked[0]); // /desk#audit: where the old /audit page leads
}

main();
