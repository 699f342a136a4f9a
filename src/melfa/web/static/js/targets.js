// Which robot the IDE drives: the lab's (shared, leased) or the user's own simulator
// (docs/api.md "Targets"). The choice is shown in the header in two ways nobody can
// confuse: a labelled switch and the whole header's colour (dark for the lab robot, teal
// for "My simulator"), and it is remembered per user in this browser. Every robot call
// follows it (api.js adds `?target=`), and the live socket is reopened on the new target.

import { api, setTarget } from "./api.js";
import { el, showError } from "./ui.js";
import { robot } from "./stores.js";
import { fill } from "./activity.js";
import { TARGET_LABELS, TARGET_WORDS as W } from "/vocab.js"; // generated from melfa.vocab.targets

const LABELS = TARGET_LABELS; // the server's names of them too (melfa.vocab.targets)

export class TargetSwitch extends EventTarget {
  constructor(app, root) {
    super();
    this.app = app;
    this.root = root;
    this.key = `melfa.target.${app.user}`;
    this.id = localStorage.getItem(this.key) === "mine" ? "mine" : "lab";
    this.labHeld = false; // we held the lab's lease when we last looked at it
    setTarget(this.id);
    this.render();
  }

  get label() {
    return LABELS[this.id];
  }

  get isPrivate() {
    return this.id === "mine";
  }

  socketUrl(id = this.id) {
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    return `${scheme}://${location.host}/api/ws${id === "lab" ? "" : "?target=" + id}`;
  }

  render() {
    const button = (id) => {
      const b = el("button", { type: "button", role: "radio", "aria-checked": String(this.id === id), "data-target": id, class: `target-opt target-${id}` }, LABELS[id]);
      b.addEventListener("click", () => this.choose(id));
      return b;
    };
    this.root.replaceChildren(
      el("span", { class: "target-label", id: "target-label" }, W.driving),
      button("lab"),
      button("mine"),
    );
    document.body.dataset.target = this.id;
    const lease = document.querySelector(".lease");
    if (lease) lease.hidden = this.isPrivate; // a private simulator has no lease
    document.title = fill(W["page-title"], { robot: this.label });
    const view = document.querySelector(".view-head h2");
    if (view) view.textContent = this.label; // the 3D view says whose arm it shows
  }

  /** Switch to `id` ("lab" | "mine"); no-op when already there. */
  choose(id) {
    if (id === this.id || !(id in LABELS)) return;
    if (this.id === "lab") this.labHeld = this.app.leaseHolder?.user === this.app.user;
    this.id = id;
    localStorage.setItem(this.key, id);
    setTarget(id);
    this.render();
    robot.set({ state: null }); // the new target's state comes with its socket
    this.app.view?.clearPath();
    this.app.live.retarget(this.socketUrl());
    this.dispatchEvent(new CustomEvent("change", { detail: { id } }));
  }

  /** The socket's hello names its target: the header follows what the server says. */
  confirm(target) {
    if (target && target.id !== this.id) {
      showError(W["other-robot"], new Error(fill(W["other-robot-detail"], { expected: this.label, got: target.label })));
    }
  }

  /**
   * The STOP button: the active target, and the lab robot too when this user may have it
   * moving while the view shows their simulator: they left it holding control, or the
   * queue gave them the arm (a claim from My simulator) — whatever the 3D view shows.
   */
  async stopOthers() {
    const myTurn = this.app.queue?.queue?.turn?.user === this.app.user;
    if (!this.isPrivate || !(this.labHeld || myTurn)) return;
    try {
      await api("POST", "/api/robot/stop?target=lab");
    } catch {
      /* the lab robot's own STOP is still in its header */
    }
  }
}
