// The guided first run (issue 16): for a student whose workspace was empty, a callout that
// points at one thing at a time (a ring around it, the callout beside it, never over it)
// and follows what the student really does: read the program → Load project (on to the
// next step when the load succeeded; when it failed, why and what to do, in the words of
// the error) → Run (the servo question and its "Turn on and retry") → the arm moving and
// the running line → done, with where to go next (Points, jogging).
//
// Skippable at every step (the button, or Esc outside the editor), keyboard reachable (it
// sits after the toolbar in the page order), read out by screen readers (a polite live
// region). Finished or skipped, it does not come back on its own for that user (kept in
// this browser, per user); the user menu's "Show the first-run guide" opens it again.

import { welcome, welcomeProject } from "./first.js";
import { fill } from "./activity.js";
import { $, el, errorText } from "./ui.js";
import { CONTROL_WORDS, FIX_LABELS, GUIDE_WORDS as W } from "/vocab.js"; // melfa.vocab.lease, .guide

/** A paragraph of the guide's words: `**…**` bold (a button's or a tab's name). */
const para = (text, facts = {}, attrs = {}) =>
  el("p", attrs, ...fill(text, facts).split("**").map((part, i) => (i % 2 ? el("strong", {}, part) : part)));

const REMEMBER = (user) => `melfa.guide.${user}`;
const GAP = 12; // between the callout and what it points at, px
const MARGIN = 8; // from the window's edges, px

export class Guide {
  constructor(app) {
    this.app = app;
    this.step = null;
    this.sawRunning = false;
    this.build();
    app.live.on("state", (m) => this.onState(m));
    app.events.addEventListener("load", (e) => this.onLoad(e.detail));
    // A refused Run shows an error toast: the guide points at its fix or tells its reason.
    new MutationObserver(() => this.onToasts()).observe($("toasts"), { childList: true });
    document.addEventListener("keydown", (e) => this.onKey(e));
    window.addEventListener("resize", () => this.place());
    $("guide-open").addEventListener("click", () => this.start());
  }

  get remembered() {
    return localStorage.getItem(REMEMBER(this.app.user));
  }

  /** Opens by itself for a first run: the workspace was empty, or still holds the welcome program. */
  async autoStart(welcomed) {
    if (this.remembered) return false;
    if (!welcomed) {
      const [program] = await welcomeProject().catch(() => [""]);
      const same = (t) => t.replace(/\r\n/g, "\n").trim();
      if (!program || same(this.app.workspace.program) !== same(program)) return false;
    }
    // A first-timer tries on their own simulated arm: in a full lab the one shared robot is
    // held by someone else, and a first run should move nothing real.
    this.app.targets?.choose("mine");
    this.start();
    return true;
  }

  /** From the first step; an empty workspace gets the welcome project first (nothing to lose). */
  async start() {
    this.sawRunning = false;
    await welcome(this.app.workspace, this.app.editor).catch(() => false);
    this.show("program", { focus: true });
  }

  /** Skip (the button or Esc) or finish: either way it stays closed for this user. */
  close(how) {
    if (!this.step) return;
    localStorage.setItem(REMEMBER(this.app.user), how);
    this.step = null;
    this.box.hidden = true;
    this.rings.replaceChildren();
    this.live.textContent = how === "done" ? W.finished : W.closed;
    clearInterval(this.follow);
    document.body.dataset.guide = "";
  }

  // ---- the steps ----
  steps() {
    const app = this.app;
    const real = app.virtual === false;
    return {
      program: {
        title: W["program-title"],
        anchor: () => $("editor"),
        body: () => [para(W["program-lines"]), para(W["program-points"])],
        next: W.next,
        enter: () => app.selectTab?.("editor"),
      },
      load: {
        title: W["load-title"],
        anchor: () => $("act-load"),
        body: () => [para(W["load-press"])],
      },
      run: {
        title: W["run-title"],
        anchor: () => $("act-run"),
        also: () => (real ? [$("estop")] : []),
        body: () => [para(W["run-press"]), real ? para(W["run-real"], {}, { class: "guide-warn" }) : para(W["run-virtual"])],
      },
      servo: {
        title: W["servo-title"],
        anchor: () => document.querySelector("#toasts .toast.error .toast-action"),
        also: () => (real ? [$("estop")] : []),
        body: () => [para(W["servo-press"], { fix: this.fixLabel || FIX_LABELS["servo-on-retry"] })],
      },
      watch: {
        title: W["watch-title"],
        anchor: () => document.querySelector(".view-stage"),
        side: ["left-low", "left", "bottom"], // beside the view, low: the running line above stays clear
        also: () => [document.querySelector("#editor .melfa-runline"), ...(real ? [$("estop")] : [])],
        body: () => [para(W["watch-line"]), para(real ? W["watch-real"] : W["watch-virtual"])],
        next: W.next,
      },
      done: {
        title: W["done-title"],
        anchor: () => $("tab-points"),
        also: () => [$("tab-robot")],
        body: () => [para(W["done-points"]), para(W["done-jog"])],
        next: W.finish,
      },
    };
  }

  show(name, { focus = false, problem = null } = {}) {
    const all = this.steps();
    const spec = all[name];
    this.step = name;
    spec.enter?.();
    const order = ["program", "load", "run", "watch", "done"];
    const index = order.indexOf(name === "servo" ? "run" : name);
    this.counter.textContent = fill(W.count, { step: index + 1, steps: order.length });
    this.title.textContent = spec.title;
    this.body.replaceChildren(
      ...spec.body(),
      !problem ? "" : el("div", { class: "guide-problem", role: "alert" }, el("strong", {}, problem.title), el("p", {}, problem.text), el("p", {}, problem.todo)),
    );
    this.next.hidden = !spec.next;
    this.skip.hidden = name === "done"; // the last step only finishes
    this.next.textContent = spec.next || "";
    this.box.hidden = false;
    this.box.dataset.step = name;
    document.body.dataset.guide = name;
    // Screen readers hear each step once, whole.
    this.live.textContent = `${this.counter.textContent}: ${spec.title}. ${this.body.textContent}`;
    this.place();
    clearInterval(this.follow);
    this.follow = setInterval(() => this.place(), 250); // the anchor may move (toasts, resizes)
    if (focus) this.box.focus();
  }

  onNext() {
    const after = { program: "load", watch: "done" };
    if (this.step === "done") this.close("done");
    else if (after[this.step]) this.show(after[this.step], { focus: true });
  }

  // ---- following what the student does ----
  onLoad({ ok, err }) {
    if (!this.step || !["program", "load"].includes(this.step)) return;
    if (ok) {
      this.show("run");
      return;
    }
    const fix = err?.detail?.fix_label;
    let todo = W["load-fix"];
    if (err?.code === "program-has-errors" || err?.code === "points-have-errors") {
      todo = W["load-fix-errors"];
    } else if (err?.code === "lease-required") {
      todo = CONTROL_WORDS.held_load;
    } else if (fix) {
      todo = fill(W["load-fix-press"], { fix });
    }
    this.show("load", { problem: { title: W["load-failed"], text: errorText(err), todo } });
  }

  onToasts() {
    if (this.step !== "run") return;
    const refused = document.querySelector("#toasts .toast.error");
    if (!refused) return;
    const fix = refused.querySelector(".toast-action");
    if (fix && /servo/i.test(refused.textContent)) {
      this.fixLabel = fix.textContent;
      this.show("servo");
    } else {
      const todo = fix ? fill(W["run-fix-press"], { fix: fix.textContent }) : W["run-fix"];
      this.show("run", { problem: { title: W["run-failed"], text: refused.querySelector("span")?.textContent || "", todo } });
    }
  }

  onState(m) {
    if (!this.step) return;
    // Only the student's own run moves the guide on (on the lab robot someone else may run).
    const mine = this.app.targets?.isPrivate || m.lease_holder === this.app.user;
    const running = !!(m.running || m.program_running) && mine;
    if (running && ["load", "run", "servo"].includes(this.step)) {
      this.sawRunning = true;
      this.show("watch");
    } else if (running) {
      this.sawRunning = true;
    } else if (this.step === "watch" && this.sawRunning && !m.paused) {
      this.show("done", { focus: true });
    }
  }

  onKey(e) {
    if (e.key !== "Escape" || !this.step) return;
    // Esc in the editor starts its own way out (Esc, then Tab); in a dialog or menu it closes that.
    if (e.target.closest?.("#editor, dialog, [role=menu], .menu")) return;
    this.close("skipped");
  }

  // ---- the callout and its rings ----
  build() {
    this.counter = el("span", { class: "guide-count" });
    this.title = el("h2", { id: "guide-title" });
    this.body = el("div", { class: "guide-body", id: "guide-body" });
    this.next = el("button", { type: "button", class: "btn btn-sm btn-primary", id: "guide-next", onclick: () => this.onNext() });
    const skip = this.skip = el("button", { type: "button", class: "btn btn-sm", id: "guide-skip", title: W["skip-hint"], onclick: () => this.close("skipped") }, W.skip);
    this.box = el("section", { class: "guide", id: "guide", role: "dialog", "aria-modal": "false", "aria-labelledby": "guide-title", "aria-describedby": "guide-body", tabindex: "-1", hidden: true },
      el("div", { class: "guide-head" }, this.counter),
      this.title, this.body,
      el("div", { class: "guide-actions" }, skip, this.next),
    );
    this.rings = el("div", { class: "guide-rings", "aria-hidden": "true" });
    this.live = el("div", { class: "sr-only", id: "guide-live", "aria-live": "polite" });
    // After the toolbar in the page's order: Tab reaches it before the workspace.
    document.querySelector(".toolbar").after(this.box, this.rings, this.live);
  }

  /** Rings around the anchor (and companions); the callout on the first side with room. */
  place() {
    if (!this.step) return;
    const spec = this.steps()[this.step];
    const anchor = spec.anchor();
    const targets = [anchor, ...(spec.also?.() || [])].filter((n) => n && n.offsetParent !== null);
    // The same ring elements move (new ones would restart their pulse every time).
    while (this.rings.children.length > targets.length) this.rings.lastElementChild.remove();
    while (this.rings.children.length < targets.length) this.rings.append(el("div", { class: "guide-ring" }));
    targets.forEach((n, i) => {
      const r = n.getBoundingClientRect();
      Object.assign(this.rings.children[i].style, { left: `${r.left - 4}px`, top: `${r.top - 4}px`, width: `${r.width + 8}px`, height: `${r.height + 8}px` });
    });
    const box = this.box;
    const w = box.offsetWidth;
    const h = box.offsetHeight;
    const vw = window.innerWidth;
    const vh = window.innerHeight;
    if (!anchor || anchor.offsetParent === null) {
      Object.assign(box.style, { left: `${vw - w - 2 * MARGIN}px`, top: `${vh - h - 2 * MARGIN}px` });
      box.dataset.side = "none";
      return;
    }
    const a = anchor.getBoundingClientRect();
    const clampX = (x) => Math.max(MARGIN, Math.min(vw - w - MARGIN, x));
    const clampY = (y) => Math.max(MARGIN, Math.min(vh - h - MARGIN, y));
    const spots = {
      bottom: [clampX(a.left + a.width / 2 - w / 2), a.bottom + GAP],
      top: [clampX(a.left + a.width / 2 - w / 2), a.top - GAP - h],
      right: [a.right + GAP, clampY(a.top + a.height / 2 - h / 2)],
      left: [a.left - GAP - w, clampY(a.top + a.height / 2 - h / 2)],
      "left-low": [a.left - GAP - w, clampY(a.bottom - h)],
    };
    // Over the editor's text, below the bars, when beside the anchor would cover a control.
    const editor = $("editor");
    if (editor?.offsetParent && !editor.contains(anchor)) spots["over-editor"] = [clampX(a.left + a.width / 2 - w / 2), editor.getBoundingClientRect().top + GAP];
    const fits = ([x, y]) => x >= MARGIN && y >= MARGIN && x + w <= vw - MARGIN && y + h <= vh - MARGIN;
    const controls = visibleControls();
    const clear = ([x, y]) => !controls.some((r) => r.left < x + w && r.right > x && r.top < y + h && r.bottom > y);
    const order = [...(spec.side || []), "bottom", "right", "left", "top", "over-editor"];
    const side = order.find((s) => s in spots && fits(spots[s]) && clear(spots[s]))
      || order.find((s) => s in spots && fits(spots[s])) || "bottom";
    const [x, y] = side in spots && fits(spots[side]) ? spots[side] : [clampX(a.left), clampY(a.bottom + GAP)];
    Object.assign(box.style, { left: `${Math.round(x)}px`, top: `${Math.round(y)}px` });
    box.dataset.side = side;
    // The arrow points at the anchor's middle along the callout's edge.
    const along = side === "bottom" || side === "top" || side === "over-editor" ? a.left + a.width / 2 - x : side === "left-low" ? h - 28 : a.top + a.height / 2 - y;
    box.style.setProperty("--arrow", `${Math.round(Math.max(16, Math.min((side === "bottom" || side === "top" || side === "over-editor" ? w : h) - 16, along)))}px`);
  }
}

/** The page's controls a callout must not cover (the editor's text and the 3D view aside). */
function visibleControls() {
  const out = [];
  for (const n of document.querySelectorAll("button, [role=tab], select, input, a[href], [role=radio]")) {
    if (n.offsetParent === null || n.closest("#guide, #editor, .view-stage, dialog, #toasts")) continue;
    const r = n.getBoundingClientRect();
    if (r.width && r.height) out.push(r);
  }
  return out;
}
