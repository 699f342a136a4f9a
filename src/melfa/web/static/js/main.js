// The IDE's entry point: signs the page in (session + CSRF), opens the workspace, the live
// socket, and wires the header (connections, lease, STOP, user menu), the main buttons
// (load, run, stop, save, check, clear) and the tabs.

import { api } from "./api.js";
import { signedIn } from "./page.js";
import { ProgramEditor } from "./editor.js";
import { PresenceView } from "./coedit-view.js";
import { ActionLog } from "./actionlog.js";
import { AssignmentsPanel } from "./assign.js";
import { describeActivity, fill } from "./activity.js";
import { renderControl, tellControl, wireControl } from "./control.js";
import { installFixes, moving } from "./fixes.js";
import { keyboardExit, robotBadge, welcome } from "./first.js";
import { Guide } from "./guide.js";
import { JogPad } from "./jog.js";
import { ToolbarOverflow } from "./layout.js";
import { Live } from "./live.js";
import { PointsTab } from "./points.js";
import { $, el, setActivity, showError, toast, took } from "./ui.js";
import { activityLine, endTask, lease, loaded, robot, session as sessionStore, startTask } from "./stores.js";
import { DebugPanel } from "./debugger.js";
import { PreflightPanel } from "./preflight.js";
import { RunsPanel } from "./replay.js";
import { QueuePanel } from "./queue.js";
import { TargetSwitch } from "./targets.js";
import { PasswordDialog } from "./password.js";
import { TokensDialog } from "./tokens.js";
import { RobotView } from "./view3d.js";
import { signOut } from "./signout.js";
import { SlotChip, adoptSlot, askBeforeRun, programErrorText, slotOwner, stoppedWhenLeftText } from "./slot.js";
import { Workspace } from "./workspace.js";
import { WorkspaceSwitcher } from "./switcher.js";
import { JOINT_NAMES, OVERRIDE_PERCENT, POSE_NAMES } from "/model/controller.js"; // generated from melfa.protocol
import { ACTIVITY, FIX_LABELS, HEADER_LINK_WORDS, IDE_WORDS as W, ROLE_WORDS, SLOT_WORDS } from "/vocab.js"; // generated from melfa.vocab

// The IDE's parts, wired once in main(); what changes lives in the stores (stores.js), and
// the getters below read them for the parts that were handed `app`.
const app = {
  live: null,
  view: null,
  events: new EventTarget(), // what the student's actions came to: "load" {ok, err}
  get user() { return sessionStore.get().user; },
  get role() { return sessionStore.get().role; },
  get state() { return robot.get().state; }, // the latest `state` message
  get virtual() { return robot.get().virtual; }, // the robot is a simulated one (the hello says so)
  get debugging() { return robot.get().debugging; }, // the debugger's arm owns the 3D view
  get replaying() { return robot.get().replay; }, // a recorded run owns the 3D view and the run line
  get leaseHolder() { return lease.get().holder; },
  get loaded() { return loaded.get().program === null ? null : loaded.get(); },
  // Whose program the controller's slot holds, for this browser (slot.js): only "mine"
  // marks the editor's lines; another person's run never does.
  get slotOwner() { return slotOwner(app.state?.slot ?? null, app.user, loaded.get(), app.editor?.text); },
  lineOf: (step) => (app.slotOwner === "mine" ? loaded.lineOf(step, app.editor.text) : null),
  busy: (text, progress = null) => startTask("operation", text, progress),
  idle: (text = ACTIVITY.idle.said, error = false) => endTask(text, error),
  // `before`: the state message when the student clicked (an "At P1" of the last move
  // is not this move's word)
  moved: (before) => untilTheRobotSays(MOTION_SEEN, before).then(() => endTask()),
};

// What the service says once it has taken a *Move to*: the reply to the POST can come
// before the state message that says so (messages are paced), and the line must not fall
// back meanwhile on the older word ("Paused at line 35", or "At P1" before the arm went).
const MOTION_SEEN = new Set(["moving-to", "at", "moving", "alarm", "offline"]);
const MOTION_WAIT_MS = 3000; // a lost message must not keep "Moving to…" for ever

function untilTheRobotSays(codes, before) {
  const says = (state) => state !== before && codes.has(state?.activity);
  return new Promise((resolve) => {
    if (says(robot.get().state)) return resolve();
    const done = () => { stop(); clearTimeout(timer); resolve(); };
    const stop = robot.subscribe((value) => { if (says(value.state)) done(); });
    const timer = setTimeout(done, MOTION_WAIT_MS);
  });
}
// For the console and the browser tests: a read-only view (the stores are the state).
window.melfa = new Proxy(app, {
  set: () => { throw new TypeError("window.melfa is read-only"); },
  defineProperty: () => { throw new TypeError("window.melfa is read-only"); },
  deleteProperty: () => { throw new TypeError("window.melfa is read-only"); },
});

async function main() {
  const session = await signedIn("user-name");
  if (!session) return;
  sessionStore.set({ user: session.user.username, role: session.user.role });
  loaded.restore(app.user);
  $("web-status-label").textContent = W.server;
  $("robot-status-label").textContent = W.robot;
  setStatus("web-status", "down", W["server-connecting"]);
  setStatus("robot-status", "down", W["robot-unknown"]);
  showSaveKind("program");
  $("user-role").textContent = fill(W["signed-in-as"], { user: app.user, role: ROLE_WORDS[app.role] ?? app.role });
  $("audit-link").hidden = app.role === "student";
  $("classroom-link").hidden = app.role === "student";
  $("desk-link").hidden = app.role === "student";

  app.view = new RobotView($("view3d"));
  const workspace = new Workspace(app.user);
  app.workspace = workspace;
  const editor = new ProgramEditor(workspace);
  app.editor = editor;
  app.presence = new PresenceView(workspace, editor);
  const points = new PointsTab(workspace, app);
  app.points = points;
  editor.onAddPoint = (name) => points.addFromRobot(name);
  installFixes(app);
  keyboardExit(editor);
  editor.addEventListener("checked", (e) => {
    points.diagnostics = e.detail.points.diagnostics;
    points.render();
  });

  app.targets = new TargetSwitch(app, $("target-switch"));
  app.live = new Live(app.targets.socketUrl());
  wireLive(app.live);
  app.actionLog = new ActionLog(app);
  app.jog = new JogPad(app);
  app.view.setFrame($("jog-frame").value);
  wireHeader();
  wireToolbar(workspace, editor);
  wireTabs();
  wireRobotTab();
  renderReadouts(null);
  app.slotChip = new SlotChip($("slot-info"));
  app.slotChip.render(null, "none");
  robot.subscribe(onState);
  const showControl = (held) => renderControl(held, app.user, app.role === "instructor" || app.role === "admin");
  lease.subscribe(showControl);
  showControl(lease.get()); // "Control: free" until the socket says who holds it
  activityLine.subscribe(renderActivity);
  app.live.connect();

  let welcomed = false;
  try {
    app.switcher = new WorkspaceSwitcher(workspace, app.user);
    await workspace.open();
    await workspace.whenSynced();
    // The welcome project greets an empty default workspace, never one made empty on purpose.
    if (workspace.id === workspace.defaultId) welcomed = await welcome(workspace, editor);
  } catch (err) {
    showError(W["open-workspace-failed"], err);
  }
  app.debug = new DebugPanel(app); // after the workspace: breakpoints are kept per workspace
  app.preflight = new PreflightPanel(app);
  app.assignments = new AssignmentsPanel(app);
  app.assignments.refresh();
  app.runs = new RunsPanel(app);
  app.queue = new QueuePanel(app); // the lab robot's queue, whichever robot this tab follows
  // Every toolbar button is in place now: fit the row (secondary actions into "More").
  app.overflow = new ToolbarOverflow(document.querySelector(".toolbar"), {
    wrap: $("toolbar-more"), button: $("more-button"), menu: $("more-menu"),
    ids: ["act-clear", "action-log-button", "act-save", "act-preflight", "act-check"],
  });
  app.guide = new Guide(app);
  app.guide.autoStart(welcomed);
  app.debug.onTarget();
  points.render();
  points.check();
  if (editor.liveBox.checked) editor.check();
  window.addEventListener("beforeunload", (e) => {
    workspace.live?.keepNow(); // edits not yet at the server stay in this browser
    if (app.jog.held) app.jog.stopJog();
  });
  document.body.dataset.ready = "true"; // every panel in place, the welcome project decided
}

// ---- live socket ----
function wireLive(live) {
  live.on("status", ({ state }) => {
    const up = state === "open";
    setStatus("web-status", up ? "up" : state === "connecting" ? "wait" : "down",
      W[up ? "server-connected" : state === "connecting" ? "server-connecting" : "server-disconnected"]);
    if (!up) setStatus("robot-status", "down", W["robot-unknown"]);
  });
  live.on("hello", (m) => {
    robot.set({ virtual: robotBadge(m) });
    app.targets.confirm(m.target);
    setLink(m.link);
    setLease(m.lease_holder);
    if (m.jog_override_ceiling) app.jog.setCeiling(m.jog_override_ceiling);
    if (m.stopped_when_you_left) {
      toast(SLOT_WORDS.stopped_when_left_title, { kind: "warning", text: stoppedWhenLeftText(m.stopped_when_you_left), timeout: 0 });
    }
  });
  live.on("link", (m) => setLink(m.status, m.detail));
  live.on("state", (m) => robot.set({ state: m }));
  live.on("lease", (m) => {
    setLease(m.holder, m.since, m.holder_state);
    tellControl(m, app.user, !app.targets.isPrivate);
  });
  live.on("progress", (m) => {
    // Only while our load waits for its answer: the last progress event can arrive after
    // it, and must not cover "Loaded…" with a progress bar that never ends.
    if (m.actor?.user !== app.user || activityLine.get().task?.kind !== "load") return;
    const share = m.total ? m.sent / m.total : 0;
    startTask("load", fill(W["loading-share"], { percent: Math.round(share * 100) }), share);
  });
}

function setStatus(id, state, text) {
  const node = $(id);
  node.dataset.state = state;
  $(`${id}-text`).textContent = text;
  // The accessible name starts with the visible text ("Server connected"), then the hint.
  const what = id === "web-status" ? W.server : W.robot;
  node.setAttribute("aria-label", fill(W["status-label"], { what, text }));
  node.title = fill(W[node.dataset.detail ? "status-title-detail" : "status-title"], { what, text, detail: node.dataset.detail });
}

function setLink(status, detail = "") {
  const state = status === "connected" ? "up" : status === "connecting" || status === "reconnecting" ? "wait" : "down";
  $("robot-status").dataset.detail = state === "up" ? "" : detail; // in the tooltip: the header stays one line
  setStatus("robot-status", state, HEADER_LINK_WORDS[status] ?? W["robot-unknown"]);
}

/** Control changed hands (or its holder's connection): `holder` {user, role} or null. */
function setLease(holder, since = undefined, state = undefined) {
  const patch = { holder };
  if (since !== undefined) patch.since = since;
  if (state !== undefined) patch.state = state;
  lease.set(patch);
}

let lastRunning = false;
function onState({ state: m }, previous) {
  if (m === previous.state) return; // the view's owner changed, not the robot
  if (!m) {
    renderActivity();
    return;
  }
  if (m.link) setLink(m.link);
  const owned = app.debugging || app.replaying; // the debugger's arm or a replay wins
  if (m.joints && !owned) app.view.setJoints(m.joints);
  if (m.link === "connected" && !owned && "joints" in m) app.view.setPositionKnown(m.joints != null);
  if (m.hands?.length && !app.replaying) app.view.setHand(m.hands[0]);
  const held = lease.get();
  if ((m.lease_holder ?? null) !== (held.holder?.user ?? null) || (m.lease_since ?? null) !== (held.since ?? null) || (m.lease_state ?? null) !== (held.state ?? null)) {
    setLease(m.lease_holder ? { user: m.lease_holder, role: m.lease_holder === held.holder?.user ? held.holder.role : "" } : null, m.lease_since ?? null, m.lease_state ?? null);
  }
  // The program's path: TCP samples while it runs (cleared when a new run starts).
  if (m.running && !lastRunning) app.view.clearPath();
  if (m.running && m.pose) app.view.addPathPoint(m.pose);
  lastRunning = !!m.running;
  // The running (or paused) step, in the editor: mapped through the real numbering of
  // the loaded text (the server's step_lines), as long as the editor still holds it.
  const shows = (m.program_running || m.paused || m.running) && m.line;
  const line = shows ? app.lineOf(m.line) : null;
  if (!app.replaying) app.editor.markRunLine(line ? line - 1 : null);
  // A run-time error of the program this editor loaded: its line, marked as the error.
  const errorLine = m.alarm?.step ? app.lineOf(m.alarm.step) : null;
  if (!app.replaying) app.editor.markErrorLine(errorLine ? errorLine - 1 : null);
  if (app.workspace) adoptSlot(m.slot ?? null, app.user, app.workspace.program, app.workspace.points);
  app.slotChip.render(m.slot ?? null, app.slotOwner);
  renderReadouts(m);
  renderActivity();
}

function renderActivity() {
  const m = app.state;
  const said = describeActivity(m, app.lineOf);
  const pill = $("run-state");
  pill.textContent = said.pill;
  pill.className = said.error ? "pill bad" : said.busy ? "pill busy" : "pill";
  pill.dataset.activity = m?.activity || "";
  renderAlarm(m?.alarm ?? null, m?.slot ?? null);
  $("servo-state").textContent = m?.servo == null ? "—" : m.servo ? W.on : W.off;
  $("servo-state").className = m?.servo ? "pill on" : "pill";
  const hand = m?.hands?.[0];
  $("hand-state").textContent = hand == null ? "—" : hand ? W["hand-open"] : W["hand-closed"];
  if (app.jog && (app.jog.shownActivity !== said.text || app.jog.shownHand !== hand)) app.jog.draw();
  // The activity line has one owner: an operation of ours in progress, else its result
  // ("Loaded…", "Load failed") until the robot does something else, else the robot.
  const { task, result } = activityLine.get();
  if (task) return setActivity(task.text, { busy: true, progress: task.progress });
  // The result stays while the robot does what it did when it was set, or nothing.
  const now = `${m?.activity ?? ""}|${m?.activity_detail ?? ""}`;
  if (result && (said.pill === "idle" || result.at === now)) return setActivity(result.text, { error: result.error, progress: result.progress });
  if (result) activityLine.set({ result: null }); // the robot moved on: so does the line
  else setActivity(said.text, { busy: !!said.busy, error: !!said.error, hint: said.hint });
}

// The alarm banner: rebuilt only when what it says changes. State messages come about 20
// a second; a button replaced between press and release never gets the click.
let alarmShown = "";
function renderAlarm(a, slot) {
  const box = $("alarm");
  box.hidden = !a;
  const owner = app.slotOwner;
  const line = a?.step ? app.lineOf(a.step) : null;
  const headline = a ? programErrorText(a, slot, owner, line) : "";
  const key = a ? JSON.stringify([a.number, a.code, a.message, a.text, a.fix, a.fix_label, headline]) : "";
  if (key === alarmShown) return;
  alarmShown = key;
  box.dataset.line = line ? String(line) : "";
  if (!a) return box.replaceChildren();
  const reset = a.fix === "reset-alarm" ? el("button", { type: "button", class: "btn btn-sm btn-primary", id: "alarm-fix",
    onclick: () => api("POST", "/api/robot/reset-alarm").catch((err) => showError(W["reset-alarm-failed"], err)) },
  a.fix_label || FIX_LABELS["reset-alarm"]) : null;
  const go = line ? el("button", { type: "button", class: "btn btn-sm", id: "alarm-line",
    onclick: () => { selectTab("editor"); app.editor.editor.gotoLine(line, 0, true); app.editor.editor.focus(); } },
  fill(W["show-line"], { line })) : null;
  const parts = [
    headline ? el("strong", {}, headline) : el("strong", {}, W.alarm, " ", el("span", { class: "code" }, a.code || String(a.number))),
    " ", a.message || a.text, " ", go, " ", reset,
  ];
  box.replaceChildren(...parts.filter((p) => p != null)); // it would write "null" where no line is
}

function renderReadouts(m) {
  const row = (label, value, unit = "") => el("tr", {}, el("th", { scope: "row" }, label), el("td", {}, value == null ? "—" : (Math.abs(value) < 0.005 ? 0 : value).toFixed(2) + unit));
  $("joints-out").replaceChildren(...JOINT_NAMES.map((n, i) => row(n, m?.joints?.[i])));
  $("pose-out").replaceChildren(...POSE_NAMES.map((n, i) => row(n, m?.pose?.[i])));
  $("fact-flags").textContent = m?.flags ? fill(W.flags, { fl1: m.flags[0], fl2: m.flags[1] }) : "—";
  $("fact-speed").textContent = m?.speed == null ? "—" : fill(W.speed, { speed: m.speed.toFixed(1) });
  $("fact-measured").textContent = m?.pose ? W[m.pose_measured ? "pose-measured" : "pose-computed"] : "—";
  const pose = $("pose-out");
  pose.dataset.pose = m?.pose ? JSON.stringify(m.pose) : "";
}

// ---- header ----
function wireHeader() {
  $("web-status").addEventListener("click", () => app.live.connect());
  $("robot-status").addEventListener("click", () => {
    app.live.connect();
    api("GET", "/api/health").then((h) => setLink(h.robot.link)).catch(() => {});
  });
  $("estop").addEventListener("click", stopAll);
  let lastEscape = 0;
  document.addEventListener("keydown", (e) => {
    if (e.key !== "Escape") return;
    if (e.timeStamp - lastEscape < 500) stopAll(); // Esc Esc stops from anywhere
    lastEscape = e.timeStamp;
  });
  wireControl(setLease);
  const button = $("user-button");
  const menu = $("user-menu");
  const toggle = (open) => {
    menu.hidden = !open;
    button.setAttribute("aria-expanded", String(open));
    if (open) menu.querySelector("[role=menuitem]:not([hidden])").focus();
  };
  button.addEventListener("click", () => toggle(menu.hidden));
  document.addEventListener("click", (e) => { if (!e.target.closest(".usermenu")) toggle(false); });
  menu.addEventListener("keydown", (e) => {
    if (e.key === "Escape") { toggle(false); button.focus(); }
  });
  new TokensDialog();
  new PasswordDialog();
  $("logout").addEventListener("click", async () => {
    await signOut(app, loaded); // a shared lab PC keeps no copy, once the server has it all
  });
}

/** STOP: over the socket (fastest), and over REST when the socket is not there. */
async function stopAll() {
  app.jog.releaseAll();
  app.targets.stopOthers();
  const sent = app.live.send({ type: "stop", id: 0 });
  if (!sent) {
    try {
      await api("POST", "/api/robot/stop");
    } catch (err) {
      showError(W["stop-failed"], err);
      return;
    }
  }
  toast(W["stop-sent"], { kind: "warning", text: W["stop-sent-text"] });
}

// ---- main buttons ----
function wireToolbar(workspace, editor) {
  $("act-load").addEventListener("click", () => loadProject(workspace, editor));
  $("act-run").addEventListener("click", runProgram);
  $("act-stop").addEventListener("click", async () => {
    try {
      await api("POST", "/api/robot/stop");
    } catch (err) {
      showError(W["stop-program-failed"], err);
    }
  });
  $("act-save").addEventListener("click", async () => {
    const kind = currentTab() === "points" ? "points" : "program";
    try {
      const name = await workspace.exportFile(kind);
      toast(fill(W.saved, { name }), { kind: "ok", text: W[kind === "program" ? "saved-program" : "saved-points"] });
    } catch (err) {
      showError(W["save-failed"], err);
    }
  });
  $("act-check").addEventListener("click", async () => {
    const out = await editor.check({ announce: true });
    if (out && currentTab() === "points") app.points.render();
  });
  const history = $("history");
  const showHistory = (open) => {
    history.hidden = !open;
    $("history-button").setAttribute("aria-expanded", String(open));
    editor.editor.resize();
    if (open) workspace.loadHistory();
  };
  $("history-button").addEventListener("click", () => showHistory(history.hidden));
  $("history-close").addEventListener("click", () => showHistory(false));
  workspace.on("saved", () => {
    if (!history.hidden) workspace.loadHistory();
  });
  workspace.on("switched", () => {
    if (!history.hidden) workspace.loadHistory(); // History follows the current workspace
  });
  $("act-clear").addEventListener("click", () => {
    editor.clear();
    app.points.diagnostics = [];
    app.points.render();
  });
}

async function loadProject(workspace, editor) {
  const button = $("act-load");
  button.disabled = true;
  startTask("load", W.loading, 0);
  try {
    const program = workspace.program;
    const out = await api("POST", "/api/robot/project", { program, points: workspace.points, workspace_id: workspace.id ?? undefined, check: true });
    loaded.remember(program, out.step_lines, out.fingerprint);
    endTask(took(W.loaded, out.seconds), false, 1);
    toast(W.loaded, { kind: "ok", text: fill(W["loaded-text"], { bytes: out.bytes_sent }) });
    app.events.dispatchEvent(new CustomEvent("load", { detail: { ok: true } }));
    return true;
  } catch (err) {
    app.events.dispatchEvent(new CustomEvent("load", { detail: { ok: false, err } }));
    endTask(W["load-failed"], true);
    if (err.code === "program-has-errors" && err.detail?.diagnostics) {
      // The whole list again (the refusal names its errors only): warnings stay in view.
      if (!(await editor.check())) editor.show(err.detail.diagnostics);
      selectTab("editor");
    }
    showError(W[err.code === "program-has-errors" ? "load-program-errors" : err.code === "points-have-errors" ? "load-points-errors" : "load-could-not"], err);
    return false;
  } finally {
    button.disabled = false;
  }
}

/**
 * Run: asks first when the slot does not hold this editor's text, naming whose program it
 * holds (slot.js); the run names the program agreed to (`expect`), so a load by someone
 * else in between is refused rather than run.
 */
async function runProgram() {
  let choice = await askBeforeRun(app.state?.slot ?? null, app.slotOwner);
  if (!choice) return;
  if (choice.load) {
    if (!(await loadProject(app.workspace, app.editor))) return;
    choice = { expect: loaded.get().fingerprint ?? undefined };
  }
  const override = Number($("override").value);
  await moving(W["run-failed"], async (extra) => {
    if (app.state && app.state.override !== override) await api("POST", "/api/robot/override", { percent: override });
    app.view.clearPath();
    await api("POST", "/api/robot/run", { ...extra, expect: choice.expect });
  });
}

// ---- tabs (ARIA tabs: arrows move between them) ----
const TABS = ["editor", "points", "robot"];
function currentTab() {
  return TABS.find((t) => $(`tab-${t}`).getAttribute("aria-selected") === "true");
}
function selectTab(name, focus = false) {
  for (const t of TABS) {
    const on = t === name;
    const tab = $(`tab-${t}`);
    tab.setAttribute("aria-selected", String(on));
    tab.tabIndex = on ? 0 : -1;
    $(`panel-${t}`).hidden = !on;
    if (on && focus) tab.focus();
  }
  showSaveKind(name === "points" ? "points" : "program");
  if (name === "editor") app.editor.editor.resize();
  if (name !== "robot") app.jog.releaseAll();
  else app.jog.draw();
}
app.selectTab = selectTab;
/** The save button follows the tab: the program as .MB4, the points as .POS. */
function showSaveKind(kind) {
  $("act-save-label").textContent = W[`save-${kind}`];
  $("act-save").title = W[`save-${kind}-hint`];
}
function wireTabs() {
  for (const t of TABS) $(`tab-${t}`).addEventListener("click", () => selectTab(t));
  document.querySelector(".tabs").addEventListener("keydown", (e) => {
    const i = TABS.indexOf(currentTab());
    if (e.key === "ArrowRight") selectTab(TABS[(i + 1) % TABS.length], true);
    else if (e.key === "ArrowLeft") selectTab(TABS[(i + TABS.length - 1) % TABS.length], true);
  });
}

// ---- robot tab ----
function wireRobotTab() {
  const call = (what, method, path, body) => async () => {
    try {
      await api(method, path, body);
    } catch (err) {
      showError(what, err);
    }
  };
  $("servo-on").addEventListener("click", call(W["servo-on-failed"], "POST", "/api/robot/servo", { on: true }));
  $("servo-off").addEventListener("click", call(W["servo-off-failed"], "POST", "/api/robot/servo", { on: false }));
  $("hand-toggle").addEventListener("click", async () => {
    try {
      const out = await api("POST", "/api/robot/hand", { hand: 1, action: "toggle" });
      app.view.setHand(out.open);
    } catch (err) {
      showError(W["hand-failed"], err);
    }
  });
  const override = $("override");
  override.min = OVERRIDE_PERCENT.min;
  override.max = OVERRIDE_PERCENT.max;
  override.addEventListener("input", () => ($("override-out").textContent = fill(W.percent, { percent: override.value })));
  $("override-set").addEventListener("click", call(W["override-failed"], "POST", "/api/robot/override", { get percent() { return Number(override.value); } }));
  $("reset-program").addEventListener("click", call(W["reset-program-failed"], "POST", "/api/robot/reset-program"));
  $("reset-alarm").addEventListener("click", call(W["reset-alarm-failed"], "POST", "/api/robot/reset-alarm"));
  $("delete-program").addEventListener("click", async () => {
    if (!confirm(W["delete-confirm"])) return;
    await call(W["delete-failed"], "DELETE", "/api/robot/program")();
  });
  // Go to a point of the points tab.
  const select = $("goto-point");
  const fill = () => {
    const names = app.points.names();
    const keep = select.value;
    select.replaceChildren(...(names.length ? names.map((n) => el("option", { value: n }, n)) : [el("option", { value: "" }, W["no-points"])]));
    if (names.includes(keep)) select.value = keep;
    $("goto-move").disabled = !names.length;
  };
  app.workspace.on("points", fill);
  app.workspace.on("replaced", fill);
  fill();
  $("goto-move").addEventListener("click", async () => {
    const point = select.value;
    if (!point) return;
    const linear = $("goto-linear").checked;
    await moving(fill(W["move-failed-to"], { point }), async (extra) => {
      const before = app.state;
      app.busy(fill(W["moving-to"], { point }));
      await api("POST", "/api/robot/move", { point, points: app.workspace.points, linear, ...extra });
      await app.moved(before); // the robot's own words from here: "Moving to P1", then "At P1" on arrival
    }, () => app.idle(W["move-failed"], true));
  });
  $("path-clear").addEventListener("click", () => app.view.clearPath());
  $("view-reset").addEventListener("click", () => app.view.resetView());
}

main();
