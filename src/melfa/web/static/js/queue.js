// The lab robot's queue in the IDE: who is at the arm and until when, everyone waiting
// with their place and an estimate of their turn, "Run on the lab robot" (join with the
// editor's text; pre-flight first when the lab asks for it), the claim prompt when the arm
// is offered to you (a dialog that cannot be missed, with its countdown), your turn's
// warning, and the instructor's controls. Every change arrives as a `queue` message on the
// live socket (whichever robot this tab follows); the words of its steps are the server's
// (/vocab.js QUEUE_STEPS).

import { api } from "./api.js";
import { $, el, showError, toast } from "./ui.js";
import { QUEUE_STATES, QUEUE_STEPS } from "/vocab.js"; // generated from melfa.vocab.queue

/** A step's words (`{user}` and friends filled in), as the desktop client fills them. */
export function stepWords(step) {
  const words = QUEUE_STEPS[step.kind]?.words ?? step.kind;
  return words
    .replaceAll("{user}", step.user ?? "someone")
    .replaceAll("{by}", step.by ?? "the instructor")
    .replaceAll("{position}", step.position ?? "?")
    .replaceAll("{seconds}", step.seconds != null ? Math.round(step.seconds) : "?");
}

/** "3:05" for seconds; "now" at zero. */
export function clock(seconds) {
  if (seconds <= 0) return "now";
  const s = Math.round(seconds);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, "0")}`;
}

export class QueuePanel {
  constructor(app) {
    this.app = app;
    this.queue = null;
    this.offset = 0; // server time − this browser's time, from the last message
    this.box = $("queue");
    this.dialog = $("claim-dialog");
    this.title = document.title;
    $("claim-go").addEventListener("click", () => this.claim());
    $("claim-later").addEventListener("click", () => this.dialog.close());
    app.live.on("queue", (m) => this.update(m));
    setInterval(() => this.tick(), 1000);
    // The socket's first queue message may have come before this panel was made.
    api("GET", "/api/queue").then((q) => this.queue || this.update({ ...q, steps: [] }), () => {});
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
    for (const step of m.steps || []) this.tell(step);
    this.render();
  }

  /** What happened, said to whom it concerns (everyone sees the list change anyway). */
  tell(step) {
    const me = this.app.user;
    if (step.user !== me) return;
    const kind = {
      missed: "warning", warned: "warning", ending: "warning", stopped: "warning",
      skipped: "warning", gone: "warning", stale: "warning",
    }[step.kind];
    if (kind || ["claimed", "ended", "run-waiting", "arm-ready"].includes(step.kind)) {
      toast(step.kind === "warned" ? "Your turn ends soon" : "Lab robot queue", { kind: kind || "info", text: stepWords(step) });
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
      el("h2", {}, "Lab robot queue"),
      q.paused ? el("span", { class: "pill warn", id: "queue-paused" }, "paused") : null,
      q.attended ? el("span", { class: "pill", title: "Each run waits for the supervisor's Arm ready" }, "attended") : null,
      el("span", { class: "queue-count" }, q.active ? `${q.entries.length} waiting` : "empty: the arm is free"),
    );
    const atArm = turn ? el("div", { class: "queue-turn" + (turn.user === me ? " mine" : ""), id: "queue-turn", "data-user": turn.user },
      el("span", { class: "queue-label" }, "At the arm"),
      el("strong", {}, turn.user === me ? "you" : turn.user),
      el("span", { class: "queue-left", "data-ends": turn.ends, "data-held": turn.held ? "1" : "" },
        turn.held ? ` · held by the instructor (${clock(turn.left_s)} kept)` : ` · ${clock(this.left(turn.ends))} left`),
      turn.away ? el("span", { class: "tag" }, "away") : null,
      turn.ending ? el("span", { class: "tag warn" }, "time is up: finishing") : null,
      turn.run_waiting ? el("span", { class: "tag warn", id: "queue-run-waiting" }, "run waits for Arm ready") : null,
      turn.user === me ? el("button", { type: "button", class: "btn btn-sm", id: "queue-done", onclick: () => this.post("/api/queue/done", {}, "Could not give the arm back") }, "Done: give the arm back") : null,
    ) : null;
    const list = el("ol", { class: "queue-list", id: "queue-list" },
      q.entries.map((e) => this.row(e)));
    const actions = el("div", { class: "queue-actions" });
    if (this.app.role !== "observer") {
      actions.append(el("button", {
        type: "button", class: "btn btn-sm " + (mine ? "" : "btn-primary"), id: "queue-join",
        title: "Queue the editor's program and points for the lab robot (they must pass pre-flight)",
        onclick: () => this.join(),
      }, mine ? "Update my queued program" : "Run on the lab robot"));
      if (mine) actions.append(el("button", { type: "button", class: "btn btn-sm", id: "queue-leave", onclick: () => this.leave() }, "Leave the queue"));
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
      el("span", { class: "queue-user" }, e.user === me ? `${e.user} (you)` : e.user),
      el("span", { class: "queue-when", "data-estimate": e.estimate },
        offered ? `${QUEUE_STATES.offered.words} · ${clock(this.left(e.offer_ends))}` : start <= 0 ? "next" : `in ≈ ${clock(start)}`),
      e.cycle_s != null ? el("span", { class: "muted queue-cycle", title: "Its cycle time in pre-flight" }, `runs ${e.cycle_s.toFixed(e.cycle_s < 10 ? 1 : 0)} s`) : null,
      e.stale ? el("span", { class: "tag warn", title: "The program in the workspace changed since it was queued: update it, or the queued one runs" }, "changed since queued") : null,
      e.away ? el("span", { class: "tag" }, "away") : null,
      this.staff ? el("span", { class: "queue-staff" },
        el("button", { type: "button", class: "btn btn-sm btn-icon", title: `Move ${e.user} up one place`, "aria-label": `Move ${e.user} up`,
          disabled: e.position === 1, onclick: () => this.post("/api/queue/move", { user: e.user, position: e.position - 1 }, "Could not move") }, "↑"),
        el("button", { type: "button", class: "btn btn-sm", title: `Take ${e.user} out of the queue`,
          onclick: () => this.post("/api/queue/skip", { user: e.user }, "Could not skip") }, "Skip"),
      ) : null,
    );
  }

  controls(q) {
    const turn = q.turn;
    return el("div", { class: "queue-controls", role: "group", "aria-label": "Instructor's queue controls" },
      el("button", { type: "button", class: "btn btn-sm", id: "queue-pause",
        onclick: () => this.post(q.paused ? "/api/queue/resume" : "/api/queue/pause", {}, "Could not change the queue") }, q.paused ? "Resume" : "Pause"),
      el("button", { type: "button", class: "btn btn-sm", id: "queue-take", title: "Take the arm now; the queue pauses and the turn keeps its time",
        onclick: () => this.post("/api/queue/take", {}, "Could not take the arm") }, "Take the arm"),
      turn ? el("button", { type: "button", class: "btn btn-sm", id: "queue-extend", onclick: () => this.post("/api/queue/extend", { seconds: 60 }, "Could not extend") }, "+1 min") : null,
      turn ? el("button", { type: "button", class: "btn btn-sm", title: `End ${turn.user}'s turn`, onclick: () => this.post("/api/queue/skip", { user: turn.user }, "Could not skip") }, "End turn") : null,
      el("label", { class: "queue-attended" },
        el("input", { type: "checkbox", id: "queue-attended", checked: q.attended,
          onchange: (ev) => this.post("/api/queue/attended", { on: ev.target.checked }, "Could not switch attended mode", "PUT") }),
        " Attended"),
      q.attended ? el("button", { type: "button", class: "btn btn-sm " + (turn?.run_waiting ? "btn-primary attention" : ""), id: "queue-ready",
        disabled: !turn, onclick: () => this.post("/api/queue/ready", {}, "Could not say arm ready") }, "Arm ready") : null,
    );
  }

  /** The arm is offered to me: the dialog (modal, with its countdown) and the tab's title. */
  prompt() {
    const mine = this.mine();
    const offered = mine?.state === "offered";
    if (offered && !this.dialog.open) {
      $("claim-position").textContent = mine.missed ? `You missed it ${mine.missed} time${mine.missed > 1 ? "s" : ""} already.` : "";
      this.dialog.showModal();
    } else if (!offered && this.dialog.open) {
      this.dialog.close();
    }
    this.tick();
  }

  tick() {
    const q = this.queue;
    if (!q) return;
    const mine = this.mine();
    if (mine?.state === "offered") {
      const left = this.left(mine.offer_ends);
      $("claim-countdown").textContent = clock(left);
      document.title = (Math.floor(Date.now() / 1000) % 2 ? "▶ Your turn! " : "▶ ") + this.title;
    } else if (document.title !== this.title) {
      document.title = this.title;
    }
    for (const node of this.box.querySelectorAll(".queue-left[data-ends]")) {
      if (!node.dataset.held) node.textContent = ` · ${clock(this.left(node.dataset.ends))} left`;
    }
  }

  async join() {
    const app = this.app;
    const body = { program: app.editor.text, points: app.workspace.points, workspace_id: app.workspace.id };
    try {
      this.update({ ...(await api("POST", "/api/queue", body)), steps: [] });
    } catch (err) {
      if (err.code === "simulation-required" && (await app.preflight.run())) {
        return this.join(); // pre-flight passed this very text: in it goes
      }
      if (err.code === "program-has-errors" && err.detail?.diagnostics) app.editor.show(err.detail.diagnostics);
      showError("Could not join the queue", err);
    }
  }

  async leave() {
    await this.post("/api/queue/me", null, "Could not leave the queue", "DELETE");
  }

  /** Claims the arm: the queued program loads and runs on the lab robot, so the IDE turns
   * to it (a student who queued from My simulator watches the arm they claimed). */
  async claim() {
    this.dialog.close();
    if (await this.post("/api/queue/claim", { start: true }, "Could not claim the arm")) {
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
