// The desk's audit log and each robot's log (/desk, docs/ide.md "The instructor's desk"),
// read from the server's one audit log (GET /api/audit): sign-ins, robot commands (one row
// each, with how it ended), refusals, control changing hands, alarms, the link, the queue,
// accounts, gate, hold, cell edits and students' work edited by staff, in the browser's
// local time and plain words. A robot's log is the entries naming that robot (the lab
// robot, or a user's simulator). Every word comes from /vocab.js (melfa.vocab).

import { api, downloadText } from "./api.js";
import { stepWords } from "./queue.js";
import { $, el, showError } from "./ui.js";
import {
  AUDIT_ACTIONS, COMMANDS, CONTROL_WORDS, DESK_WORDS as W, LEASE_REASONS, LINK_WORDS, NOTE_WORDS,
  QUEUE_STEPS, ROBOT_LOG_WORDS as RL,
} from "/vocab.js";

const LIMIT = 500;
const ROBOT_LIMIT = 200;
const fill = (text, facts) => text.replace(/\{(\w+)\}/g, (_, k) => String(facts[k] ?? ""));
const local = (iso) => new Date(iso).toLocaleString();
const quote = (v) => `"${String(v).replaceAll('"', '""')}"`;
const csv = (header, rows) => [header, ...rows.map((r) => r.map(quote).join(","))].join("\n") + "\n";

/** One row per event: a robot command's "accepted" entry is dropped when its outcome (same
 * command id) is on the page, so each command reads once, with how it ended. */
export function oneRowEach(entries) {
  const ended = new Set(entries.filter((e) => e.action.startsWith("robot.") && e.result !== "accepted").map((e) => e.details.command_id));
  return entries.filter((e) => !(e.result === "accepted" && ended.has(e.details.command_id)));
}

/** What happened, in words (never the stored action or its JSON). */
export function said(e) {
  const d = e.details || {};
  if (e.action.startsWith("robot.")) {
    const command = COMMANDS[e.action.slice(6)];
    const label = command ? command.label : e.action.slice(6);
    return command?.detail && d.detail ? `${label} · ${d.detail}` : label; // "Servo · on", "Speed override · 30%"
  }
  if (e.action === "control.changed") {
    const reason = LEASE_REASONS[d.reason];
    return reason ? fill(reason.words, { by: d.by || CONTROL_WORDS.someone, command: d.command || CONTROL_WORDS.a_command }) : "";
  }
  if (e.action === "alarm.raised") return fill(NOTE_WORDS[d.line ? "alarm-line" : "alarm.raised"], d);
  if (e.action === "link.changed") return fill(NOTE_WORDS["link.changed"], { words: LINK_WORDS[d.status] || d.status });
  if (e.action in NOTE_WORDS) return fill(NOTE_WORDS[e.action], d);
  if (e.action.startsWith("queue.")) {
    // The step's words from its code and facts; the sentence stored with an entry only for
    // a step the vocabulary no longer has.
    const kind = e.action.slice(6);
    return kind in QUEUE_STEPS ? stepWords({ ...d, kind }) : d.words || "";
  }
  const words = AUDIT_ACTIONS[e.action];
  return words ? fill(words, d) : e.action;
}

/** How it ended, in words: done, asked (no answer yet), or the refusal's or failure's own. */
export function outcome(result) {
  return W[`result-${result}`] ?? result;
}

/** A robot's name in words: the lab robot, or whose simulator. */
export function robotName(robot) {
  if (!robot) return "";
  if (robot === "lab") return RL.lab;
  return robot.startsWith("sim:") ? fill(RL.simulator, { who: robot.slice(4) }) : robot;
}

const KINDS = {
  all: () => true,
  robot: (e) => e.action.startsWith("robot."),
  control: (e) => e.action === "control.changed" || (e.action.startsWith("robot.") && COMMANDS[e.action.slice(6)]?.control), // a refused take too
  alarm: (e) => e.action.startsWith("alarm.") || e.action === "link.changed",
  refused: (e) => e.result.startsWith("refused"),
  queue: (e) => e.action.startsWith("queue.") || (e.action.startsWith("robot.") && COMMANDS[e.action.slice(6)]?.queue), // a refused request too
  desk: (e) => e.action in AUDIT_ACTIONS && e.action !== "session.sign-in",
  "sign-in": (e) => e.action === "session.sign-in",
};

const audit = { entries: [], shown: [] };

export function wireAudit() {
  $("audit-title").textContent = W.audit;
  $("audit-csv").textContent = W["audit-csv"];
  $("audit-columns").replaceChildren(...W["audit-columns"].split(",").map((c) => el("th", { scope: "col" }, c)));
  $("audit-kind").replaceChildren(...Object.keys(KINDS).map((k) => el("option", { value: k }, W[`audit-${k}`])));
  $("audit-kind").addEventListener("change", () => drawAudit());
  $("audit-who").addEventListener("change", () => loadAudit());
  $("audit-since").addEventListener("change", () => loadAudit());
  $("audit-csv").addEventListener("click", () => downloadText(csv(W["audit-columns"], audit.shown), W["audit-file"], "text/csv"));
}

export async function loadAudit() {
  const who = $("audit-who").value.trim();
  const since = $("audit-since").value; // a local day: from its midnight here
  const query = new URLSearchParams({ limit: String(LIMIT) });
  if (who) query.set("actor", who.toLowerCase());
  if (since) query.set("since", new Date(`${since}T00:00`).toISOString());
  try {
    audit.entries = oneRowEach((await api("GET", `/api/audit?${query}`)).entries);
  } catch (err) {
    showError(W.audit, err);
    return;
  }
  drawAudit();
}

function drawAudit() {
  const keep = KINDS[$("audit-kind").value] || KINDS.all;
  const entries = audit.entries.filter(keep);
  audit.shown = entries.map((e) => [local(e.at), e.actor || W["audit-by-melfa"], robotName(e.details?.robot), said(e), outcome(e.result)]);
  $("audit-rows").replaceChildren(...entries.map((e, i) => el("tr", { class: e.result.startsWith("refused") ? "refused" : "", "data-action": e.action },
    ...audit.shown[i].map((cell) => el("td", {}, cell)))));
}

// --- one robot's log -------------------------------------------------------------------

const log = { shown: [] };

/** The robots whose log staff may read: the lab robot and each account's simulator. */
export function wireRobotLog(users) {
  $("robots-title").textContent = RL.title;
  $("robots-help").textContent = fill(RL.help, { limit: ROBOT_LIMIT });
  $("robots-label-text").textContent = RL.robot;
  $("robots-csv").textContent = RL.csv;
  $("robots-columns").replaceChildren(...RL.columns.split(",").map((c) => el("th", { scope: "col" }, c)));
  $("robots-pick").addEventListener("change", () => loadRobotLog());
  $("robots-csv").addEventListener("click", () => downloadText(csv(RL.columns, log.shown), fill(RL.file, { robot: $("robots-pick").value.replace(":", "-") }), "text/csv"));
  listRobots(users);
}

export function listRobots(users) {
  const pick = $("robots-pick");
  const chosen = pick.value || "lab";
  const robots = ["lab", ...users.map((u) => `sim:${u.username}`)];
  pick.replaceChildren(...robots.map((r) => el("option", { value: r }, robotName(r))));
  pick.value = robots.includes(chosen) ? chosen : "lab";
}

export async function loadRobotLog() {
  const robot = $("robots-pick").value || "lab";
  const query = new URLSearchParams({ robot, limit: String(ROBOT_LIMIT) });
  let entries;
  try {
    entries = oneRowEach((await api("GET", `/api/audit?${query}`)).entries);
  } catch (err) {
    showError(RL.title, err);
    return;
  }
  log.shown = entries.map((e) => [local(e.at), e.actor || W["audit-by-melfa"], said(e), outcome(e.result)]);
  $("robots-none").textContent = RL.empty;
  $("robots-none").hidden = entries.length > 0;
  $("robots-rows").replaceChildren(...entries.map((e, i) => el("tr", {
    class: e.result.startsWith("refused") ? "refused" : e.action === "alarm.raised" ? "alarm" : "", "data-action": e.action,
  }, ...log.shown[i].map((cell) => el("td", {}, cell)))));
}
