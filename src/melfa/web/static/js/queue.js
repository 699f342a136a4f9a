// The lab robot's queue in the IDE: who is at the arm and until when, everyone waiting
// with their place and an estimate of their turn, "Run on the lab robot" (join with the
// editor's text; pre-flight first when the lab asks for it), the claim prompt when the arm
// is offered to you (a dialog that cannot be missed, with its countdown; "Not yet" closes
// it for that offer — in every tab of this browser and across a reload — and the panel
// keeps the offer's countdown and a Claim button), your
// turn's warning, and the instructor's controls. Every change arrives as a `queue` message on the
// live socket (whichever robot this tab follows). Every word is melfa.vocab.queue's
// (/vocab.js: QUEUE_STEPS for what happened, QUEUE_WORDS for the rest).

import { fill } from "./activity.js";
import { api } from "./api.js";
import { lease } from "./stores.js";
import { $, el, showError, toast } from "./ui.js";
import { QUEUE_STATES, QUEUE_STEPS, QUEUE_WORDS as W } from "/vocab.js"; // generated from melfa.vocab.queue

/** A queue step telling a student their queued text must pass pre-flight (again). */
const GATE_STEPS = new Set(["preflight-again", "preflight-needed"]);

/** How long the instructor's extend button adds (its words say it in minutes). */
const EXTEND_S = 60;

/** A step's words (`{user}` and friends filled in), as the desktop client fills them. */
export function stepWords(step) {
  const words = QUEUE_STEPS[step.kind]?.words ?? step.kind;
  return words
    .replaceAll("{user}", step.user ?? W.someone)
    .replaceAll("{by}", step.by ?? W.the_instructor)
    .replaceAll("{position}", step.position ?? "?")
    .replaceAll("{seconds}", step.seconds != null ? Math.round(step.seconds) : "?");
}

/** "3:05" for seconds; "now" at zero. */
export function clock(seconds) {
  if (seconds <= 0) return W.now;
  const s = Math.round(seconds);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, "0")}`;
}

/** "3:05 left" (the turn's time, counting down). */
function timeLeft(seconds) {
  return fill(W.left, { left: clock(seconds) });
}

export class QueuePanel {
  constructor(app) {
    this.app = app;
    this.queue = null;
    this.offset = 0; // server time − this browser's time, from the last message
    this.box = $("queue");
    this.dialog = $("claim-dialog");
    this.declinedKey = `melfa.claim-declined.${app.user}`; // the offer said "Not yet" to
    this.declinedHere = null; // the same, where this browser keeps no storage
    this.blink = ""; // what the tab's title starts with while the arm is offered to you
    this.words();
    $("claim-go").addEventListener("click", () => this.claim());
    $("claim-later").addEventListener("click", () => { this.decline(); this.dialog.close(); });
    this.dialog.addEventListener("cancel", () => this.decline()); // Esc says "Not yet" too
    // "Not yet" said in another tab of this browser: this tab's dialog for the offer closes.
    window.addEventListener("storage", (e) => {
      if (e.key === this.declinedKey && this.dialog.open && this.offer() === this.declined()) this.dialog.close();
    });
    app.live.on("queue", (m) => this.update(m));
    setInterval(() => this.tick(), 1000);
    // The socket's first queue message may have come before this panel was made.
    api("GET", "/api/queue").then((q) => this.queue || this.update({ ...q, steps: [] }), () => {});
  }

  /** The claim dialog's words (the page holds only its shape). */
  words() {
    this.box.setAttribute("aria-label", W.title);
    $("claim-title").textContent = W.claim_title;
    const [before, after = ""] = W.claim_text.split("{countdown}");
    const countdown = $("claim-countdown");
    $("claim-text").replaceChildren(before, countdown, after);
    $("claim-later").textContent = W.later;
    $("claim-go").textContent = W.claim;
  }

  get staff() {
    return this.app.role === "instructor" || this.app.role === "admin";
  }

  now() {
    return Date.now() + this.offset;
  }

  left(iso) {
    return (Date.parse(iso) - this.now()) / 1000;
  }

  update(m) {
    this.offset = Date.parse(m.now) - Date.now();
    this.queue = m;
    if (lease.get().queued !== !!m.active) lease.set({ queued: !!m.active }); // the header's control
    for (const step of m.steps || []) this.tell(step);
    this.render();
  }

  /** What happened, said to whom it concerns (everyone sees the list change anyway). */
  tell(step) {
    const me = this.app.user;
    if (step.user !== me) return;
    if (GATE_STEPS.has(step.kind)) { // at once, not when the turn comes: what to do, one click
      toast(W.title, { kind: "warning", timeout: 0, text: stepWords(step),
        actions: [{ label: W.preflight, run: () => this.preflightAgain() }] });
      this.app.preflight.noLongerCounts(); // its report's pass does not open the gate now
      return;
    }
    const kind = {
      missed: "warning", warned: "warning", ending: "warning", stopped: "warning",
      skipped: "warning", gone: "warning", stale: "warning",
    }[step.kind];
    if (kind || ["claimed", "ended", "run-waiting", "arm-ready"].includes(step.kind)) {
      toast(step.kind === "warned" ? W.warned_title : W.title, { kind: kind || "info", text: stepWords(step) });
    }
  }

  mine() {
    return this.queue?.entries.find((e) => e.user === this.app.user) ?? null;
  }

  render() {
    const q = this.queue;
    if (!q) return;
    const me = this.app.user;
    const mine = this.mine();
    const turn = q.turn;
    const head = el("div", { class: "queue-head" },
      el("h2", {}, W.title),
      q.paused ? el("span", { class: "pill warn", id: "queue-paused" }, W.paused) : null,
      q.attended ? el("span", { class: "pill", title: W.attended_hint }, W.attended) : null,
      el("span", { class: "queue-count" }, q.active ? fill(W.waiting, { count: q.entries.length }) : W.empty),
    );
    const atArm = turn ? el("div", { class: "queue-turn" + (turn.user === me ? " mine" : ""), id: "queue-turn", "data-user": turn.user },
      el("span", { class: "queue-label" }, W.at_arm),
      el("strong", {}, turn.user === me ? W.you : turn.user),
      el("span", { class: "queue-left", "data-ends": turn.ends, "data-held": turn.held ? "1" : "" },
        " · " + (turn.held ? fill(W.held, { left: clock(turn.left_s) }) : timeLeft(this.left(turn.ends)))),
      turn.away ? el("span", { class: "tag" }, W.away) : null,
      turn.ending ? el("span", { class: "tag warn" }, W.ending) : null,
      turn.run_waiting ? el("span", { class: "tag warn", id: "queue-run-waiting" }, W.run_waiting) : null,
      turn.user === me ? el("button", { type: "button", class: "btn btn-sm", id: "queue-done", onclick: () => this.post("/api/queue/done", {}, W.done_failed) }, W.done) : null,
    ) : null;
    const list = el("ol", { class: "queue-list", id: "queue-list" },
      q.entries.map((e) => this.row(e)));
    const actions = el("div", { class: "queue-actions" });
    if (this.app.role !== "observer") {
      if (mine?.state === "offered") { // the dialog's claim, for when it was put away
        actions.append(el("button", { type: "button", class: "btn btn-sm btn-primary", id: "queue-claim",
          title: W.claim_hint, onclick: () => this.claim() }, W.claim));
      }
      actions.append(el("button", {
        type: "button", class: "btn btn-sm " + (mine ? "" : "btn-primary"), id: "queue-join",
        title: W.join_hint,
        onclick: () => this.join(),
      }, mine ? W.update : W.join));
      if (mine) actions.append(el("button", { type: "button", class: "btn btn-sm", id: "queue-leave", onclick: () => this.leave() }, W.leave));
    }
    const controls = this.staff ? this.controls(q) : null;
    this.box.replaceChildren(...[head, atArm, list, actions, controls].filter(Boolean));
    this.box.dataset.active = q.active ? "1" : "";
    this.prompt();
  }

  row(e) {
    const me = this.app.user;
    const start = this.left(e.estimate);
    const offered = e.state === "offered";
    return el("li", { class: "queue-entry" + (e.user === me ? " mine" : "") + (offered ? " offered" : ""), "data-user": e.user, "data-position": e.position },
      el("span", { class: "queue-pos" }, String(e.position)),
      el("span", { class: "queue-user" }, e.user === me ? fill(W.mine, { user: e.user }) : e.user),
      el("span", { class: "queue-when", "data-estimate": e.estimate, "data-offer-ends": offered ? e.offer_ends : null },
        offered ? this.offerLeft(e.offer_ends) : start <= 0 ? W.next : fill(W.starts_in, { left: clock(start) })),
      e.cycle_s != null ? el("span", { class: "muted queue-cycle", title: W.cycle_hint }, fill(W.cycle, { seconds: e.cycle_s.toFixed(e.cycle_s < 10 ? 1 : 0) })) : null,
      e.stale ? el("span", { class: "tag warn", title: W.stale_hint }, W.stale) : null,
      e.gate ? el("span", { class: "tag warn", "data-gate": e.gate, title: e.gate === "cell-changed" ? W.preflight_again_hint : W.preflight_needed_hint },
        e.gate === "cell-changed" ? W.preflight_again : W.preflight_needed) : null,
      e.gate && e.user === me && this.app.role !== "observer" ? el("button", { type: "button", class: "btn btn-sm btn-primary", id: "queue-preflight",
        onclick: () => this.preflightAgain() }, W.preflight) : null,
      e.away ? el("span", { class: "tag" }, W.away) : null,
      this.staff ? el("span", { class: "queue-staff" },
        el("button", { type: "button", class: "btn btn-sm btn-icon", title: fill(W.move_up_hint, { user: e.user }), "aria-label": fill(W.move_up, { user: e.user }),
          disabled: e.position === 1, onclick: () => this.post("/api/queue/move", { user: e.user, position: e.position - 1 }, W.move_failed) }, "↑"),
        el("button", { type: "button", class: "btn btn-sm", title: fill(W.skip_hint, { user: e.user }),
          onclick: () => this.post("/api/queue/skip", { user: e.user }, W.skip_failed) }, W.skip),
      ) : null,
    );
  }

  /** "the arm is offered: claim it · 0:42" */
  offerLeft(ends) {
    return `${QUEUE_STATES.offered.words} · ${clock(this.left(ends))}`;
  }

  controls(q) {
    const turn = q.turn;
    return el("div", { class: "queue-controls", role: "group", "aria-label": W.controls },
      el("button", { type: "button", class: "btn btn-sm", id: "queue-pause",
        onclick: () => this.post(q.paused ? "/api/queue/resume" : "/api/queue/pause", {}, W.pause_failed) }, q.paused ? W.resume : W.pause),
      el("button", { type: "button", class: "btn btn-sm", id: "queue-take", title: W.take_hint,
        onclick: () => this.post("/api/queue/take", {}, W.take_failed) }, W.take),
      turn ? el("button", { type: "button", class: "btn btn-sm", id: "queue-extend", onclick: () => this.post("/api/queue/extend", { seconds: EXTEND_S }, W.extend_failed) }, fill(W.extend, { minutes: EXTEND_S / 60 })) : null,
      turn ? el("button", { type: "button", class: "btn btn-sm", title: fill(W.end_turn_hint, { user: turn.user }), onclick: () => this.post("/api/queue/skip", { user: turn.user }, W.skip_failed) }, W.end_turn) : null,
      el("label", { class: "queue-attended" },
        el("input", { type: "checkbox", id: "queue-attended", checked: q.attended,
          onchange: (ev) => this.post("/api/queue/attended", { on: ev.target.checked }, W.attended_failed, "PUT") }),
        " " + W.attended_switch),
      q.attended ? el("button", { type: "button", class: "btn btn-sm " + (turn?.run_waiting ? "btn-primary attention" : ""), id: "queue-ready",
        disabled: !turn, onclick: () => this.post("/api/queue/ready", {}, W.ready_failed) }, W.ready) : null,
    );
  }

  /** The offer made to me, named by its robot and its end (one offer, one end: a new
   * offer ends later), or null. */
  offer() {
    const mine = this.mine();
    return mine?.state === "offered" ? `${this.queue.target} ${mine.offer_ends}` : null;
  }

  /** The offer this student said "Not yet" to in this browser, or null. */
  declined() {
    try { return localStorage.getItem(this.declinedKey); } catch { return null; }
  }

  /** "Not yet": the dialog stays closed for this offer (the panel still shows it, its
   * countdown and Claim), in this tab, the browser's other tabs and after a reload; a new
   * offer opens it again. Kept in this browser only: it is how this page shows the offer,
   * not a step of the queue (the server's offer and its countdown run on unchanged). */
  decline() {
    const offer = this.offer();
    if (offer == null) return;
    try { localStorage.setItem(this.declinedKey, offer); } catch { /* no storage: this page only */ this.declinedHere = offer; }
  }

  /** The arm is offered to me: the dialog (modal, with its countdown, unless declined) and
   * the tab's title. */
  prompt() {
    const mine = this.mine();
    const offer = this.offer();
    const offered = offer != null;
    const declined = offer === this.declined() || offer === this.declinedHere;
    if (offered && !declined && !this.dialog.open) {
      $("claim-position").textContent = !mine.missed ? "" : mine.missed === 1 ? W.missed_once : fill(W.missed_times, { count: mine.missed });
      this.dialog.showModal();
    } else if (!offered && this.dialog.open) {
      this.dialog.close();
    }
    this.tick();
  }

  /** The tab's title without the offer's blink (the page may have renamed it since:
   * switching between the lab robot and My simulator does). */
  untitled() {
    const t = document.title;
    return this.blink && t.startsWith(this.blink) ? t.slice(this.blink.length) : t;
  }

  tick() {
    const q = this.queue;
    if (!q) return;
    const mine = this.mine();
    if (mine?.state === "offered") {
      const left = this.left(mine.offer_ends);
      $("claim-countdown").textContent = clock(left);
      const base = this.untitled();
      this.blink = Math.floor(Date.now() / 1000) % 2 ? `▶ ${W.tab_turn} ` : "▶ ";
      document.title = this.blink + base;
    } else if (this.blink) {
      document.title = this.untitled();
      this.blink = "";
    }
    for (const node of this.box.querySelectorAll(".queue-left[data-ends]")) {
      if (!node.dataset.held) node.textContent = " · " + timeLeft(this.left(node.dataset.ends));
    }
    // The claim window's countdown in the list too (everyone sees it run, not only the dialog)
    for (const node of this.box.querySelectorAll(".queue-when[data-offer-ends]")) {
      node.textContent = this.offerLeft(node.dataset.offerEnds);
    }
  }

  async join() {
    const app = this.app;
    const body = { program: app.editor.text, points: app.workspace.points, workspace_id: app.workspace.id };
    try {
      this.update({ ...(await api("POST", "/api/queue", body)), steps: [] });
    } catch (err) {
      if (err.detail?.fix === "preflight" && (await app.preflight.run())) {
        return this.join(); // pre-flight passed this very text: in it goes
      }
      if (err.code === "program-has-errors" && err.detail?.diagnostics) app.editor.show(err.detail.diagnostics);
      showError(W.join_failed, err);
    }
  }

  /** The queued text's pass no longer counts: pre-flight the editor's text, and when it
   * passes it becomes the queued one (the same text, or the one the student now means). */
  async preflightAgain() {
    if (await this.app.preflight.run()) await this.join();
  }

  async leave() {
    await this.post("/api/queue/me", null, W.leave_failed, "DELETE");
  }

  /** Claims the arm: the queued program loads and runs on the lab robot, so the IDE turns
   * to it (a student who queued from My simulator watches the arm they claimed). */
  async claim() {
    this.dialog.close();
    if (await this.post("/api/queue/claim", { start: true }, W.claim_failed)) {
      this.app.targets?.choose("lab");
    }
  }

  /** Sends a queue request; true when the server took it. */
  async post(path, body, what, method = "POST") {
    try {
      this.update({ ...(await api(method, path, body ?? undefined)), steps: [] });
      return true;
    } catch (err) {
      showError(what, err);
      return false;
    }
  }
}
