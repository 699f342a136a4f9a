// The workspace: program + points, edited live with everyone who has it open (coedit.js:
// a Yjs document kept in step with the server's and every partner's). Every edit reaches
// the server as it is typed; the server saves the document as revisions (History). Two
// people typing at once both keep their lines, so no dialog ever asks anyone to choose;
// offline, edits stay in this browser and merge when the connection is back. One object
// follows the CURRENT workspace: switching to another (or creating one) saves first, then
// swaps id and texts, so everything holding `app.workspace` (editor, points, history,
// debugger, load, export) acts on it.

import { api, downloadText } from "./api.js";
import { CoeditSession, EDITOR, spliceTo } from "./coedit.js";
import { showDiff } from "./opener.js";
import { $, el, showError, toast } from "./ui.js";

export class Workspace extends EventTarget {
  constructor(user) {
    super();
    this.user = user;
    this.id = null;
    this.owner = "";
    this.name = "";
    this.kind = "personal";
    this.shared = false;
    this.list = []; // what GET /api/workspaces gave: [{id, kind, owner, name, shared}]
    this.defaultId = null;
    this.base = 0; // the newest revision the server saved
    this.program = "";
    this.points = "";
    this.live = null; // the CoeditSession of the current workspace
    this.pending = false; // edits since the last revision
    this.offlineEdits = false; // edits the server has not had yet (typed offline)
  }

  /** The workspace's name as a file name stem (downloads are named after it). */
  get fileStem() {
    return (this.name || this.owner || "program").replace(/[^A-Za-z0-9._-]+/g, "_").replace(/^[._]+|[._]+$/g, "") || "program";
  }

  /** Edits not in a revision yet (the server saves them shortly), or typed offline (kept
   * in this browser until the server has them). */
  get dirty() {
    return this.pending || this.offlineEdits;
  }

  /** Resolves once the live document is here (or after `ms`, offline). */
  whenSynced(ms = 10000) {
    const live = this.live;
    if (!live || live.synced) return Promise.resolve(Boolean(live));
    return new Promise((resolve) => {
      live.on("welcome", () => resolve(true));
      setTimeout(() => resolve(live.synced), ms);
    });
  }

  /** This browser may type here (synced, and a member or staff who chose to edit). */
  get writable() {
    return Boolean(this.live && this.live.synced && this.live.writable);
  }

  emit(type, detail = {}) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  on(type, handler) {
    this.addEventListener(type, (e) => handler(e.detail));
  }

  status(text, kind = "") {
    const node = $("save-state");
    node.textContent = text;
    node.className = "save-state " + kind;
  }

  get lastKey() {
    return `melfa.workspace.${this.user}`;
  }

  /** The workspaces this user may open (and which is the default); my archived ones too
   * (marked `archived`: the switcher lists them apart, and their names stay taken). */
  async refreshList() {
    const out = await api("GET", "/api/workspaces?archived=true");
    this.list = out.workspaces;
    this.defaultId = out.default_id;
    this.emit("list", {});
    return this.list;
  }

  /** Open the workspace the address names (`/?workspace=12`: the class view's "Open in
   * the editor"; `/?user=alice`: the desk's "Open work"), else the one opened last in this browser, else the default one; edits
   * this browser kept (typed offline) merge into it. */
  async open() {
    await this.refreshList();
    const params = new URLSearchParams(location.search);
    const whose = params.get("user"); // the desk's "Open work": that user's first own workspace
    const theirs = whose && this.list.find((w) => w.kind === "personal" && w.owner === whose && !w.archived);
    const asked = theirs ? theirs.id : Number(params.get("workspace"));
    let last = null;
    try { last = Number(localStorage.getItem(this.lastKey)); } catch { /* no storage */ }
    const known = (id) => this.list.some((w) => w.id === id && !w.archived);
    await this.load(known(asked) ? asked : known(last) ? last : this.defaultId);
  }

  /** Load workspace `id` into this object (nothing of the previous one is kept here) and
   * join its live document. */
  async load(id) {
    const ws = await api("GET", `/api/workspaces/${id}`);
    this.live?.close();
    this.id = ws.id;
    this.owner = ws.owner;
    this.name = ws.name;
    this.kind = ws.kind; // personal | group
    this.shared = ws.shared;
    try { localStorage.setItem(this.lastKey, String(ws.id)); } catch { /* no storage */ }
    this.base = ws.revision;
    this.program = ws.program;
    this.points = ws.points;
    this.pending = false;
    this.offlineEdits = false;
    const live = new CoeditSession(ws.id, this.user);
    this.live = live;
    const mine = (fn) => (detail) => { if (this.live === live) fn(detail); };
    const synced = mine(() => {
      this.program = live.program.toString();
      this.points = live.points.toString();
      this.base = live.revision;
      this.offlineEdits = false;
      this.emit("replaced", { source: "live" });
      this.emit("points", {});
      this.emit("access", {});
      this.showStatus();
    });
    live.on("welcome", synced);
    live.on("reset", synced);
    live.on("change", mine(({ field, delta, local, fromEditor }) => {
      this.pending = true;
      if (local && !live.online) this.offlineEdits = true;
      if (field === "program") {
        this.program = live.program.toString();
        if (!fromEditor) this.emit("remote", { delta }); // a partner's, an undo, a file
      } else {
        this.points = live.points.toString();
        this.emit("points", {});
      }
      this.showStatus();
    }));
    live.on("status", mine(() => this.showStatus()));
    live.on("saved", mine((saved) => {
      this.base = saved.revision;
      this.pending = false;
      this.showStatus();
      this.emit("saved", { number: saved.revision, authors: saved.authors });
    }));
    live.on("presence", mine(({ peers }) => this.emit("presence", { peers })));
    this.emit("replaced", { source: "open" });
    this.emit("switched", {});
    this.emit("access", {});
    this.showStatus();
    await this.whenSynced(5000); // typing starts on the live document
  }

  /** Staff: edit this workspace of someone else (it opens read-only); the server grants
   * it to this sign-in and audits it. */
  async editHere() {
    await api("PUT", `/api/workspaces/${this.id}/staff-edit`);
    await this.load(this.id);
  }

  /** Staff: back to reading this workspace of someone else only. */
  async readOnlyAgain() {
    await api("DELETE", `/api/workspaces/${this.id}/staff-edit`);
    await this.load(this.id);
  }

  /** Save what is typed before leaving this workspace (a revision, when online).
   * Offline, the edits are kept in this browser and merge on the next visit. */
  async flush() {
    if (!this.live) return true;
    this.live.keepNow();
    if (this.live.online) await this.live.flush();
    return true; // offline edits are kept in this browser and merge on the next visit
  }

  /** Switch to workspace `id`, never losing edits: false (and a message) if they could
   * not be saved first. */
  async switchTo(id) {
    if (id === this.id) return true;
    if (!(await this.flush())) {
      toast("Still on " + this.name, { kind: "warning", text: "Your edits here are not saved yet, so the workspace was not switched. Once the status says Saved, switch again." });
      return false;
    }
    await this.load(id);
    return true;
  }

  /** A new workspace of mine named `name` (holding `content` if given), then switch to it.
   * The current one is saved first and left as it is. */
  async create(name, { program = "", points = "", fromFile = null } = {}) {
    if (!(await this.flush())) {
      toast("Nothing created yet", { kind: "warning", text: `Your edits to ${this.name} are not saved yet. Once the status says Saved, try again.` });
      return null;
    }
    const made = await api("POST", "/api/workspaces", { name, program, points, from_file: fromFile });
    await this.refreshList();
    await this.load(made.id);
    return made;
  }

  /** Give the current workspace a new name. */
  async rename(name) {
    const out = await api("PATCH", `/api/workspaces/${this.id}`, { name });
    this.name = out.name;
    await this.refreshList();
    this.emit("switched", {});
    return out;
  }

  /** Hide (or bring back) one of my workspaces; nothing in it is deleted. Archiving the
   * current one switches to the default first. */
  async archive(id, archived = true) {
    if (archived && id === this.id && !(await this.switchTo(this.defaultId))) return null;
    const out = await api("PATCH", `/api/workspaces/${id}`, { archived });
    await this.refreshList();
    return out;
  }

  /** The names of my own workspaces, archived ones included (for a free name). */
  myNames() {
    return this.list.filter((w) => w.kind === "personal" && w.owner === this.user).map((w) => w.name);
  }

  /** The points tab (or anything but the editor) changed a text: as edits of the live
   * document, so partners' concurrent edits elsewhere in it stay. */
  update({ program, points }) {
    if (!this.writable) return;
    if (program !== undefined) spliceTo(this.live.program, program);
    if (points !== undefined) spliceTo(this.live.points, points);
  }

  /** The editor's own change (an Ace delta on `aceDoc`), as the same edit of the program. */
  editProgram(delta, aceDoc) {
    if (!this.writable) return;
    const text = this.live.program;
    const index = aceDoc.positionToIndex(delta.start);
    const chunk = delta.lines.join("\n");
    this.live.doc.transact(() => {
      if (delta.action === "insert") text.insert(index, chunk);
      else text.delete(index, chunk.length);
    }, EDITOR);
  }

  /** Replace both texts (a file opened, the welcome project): the editor follows. */
  replace({ program, points }, source) {
    this.update({ program, points });
    this.emit("replaced", { source });
    this.emit("points", {});
  }

  showStatus() {
    const live = this.live;
    if (!live) return this.status("—");
    if (live.state === "refused") return this.status("Cannot open this workspace", "error");
    if (live.state === "offline") {
      return this.status(live.synced ? "Offline — edits kept here; they merge when the connection is back" : "Offline — connecting…", "error");
    }
    if (!live.synced) return this.status("Connecting…");
    if (!live.writable) return this.status(`Read-only · revision ${this.base}`);
    if (this.pending) return this.status("Live · saving…", "dirty");
    this.status(this.base ? `Saved · revision ${this.base}` : "Not saved yet");
  }

  /** Save now: the server makes a revision of the live document. Resolves true once it
   * has; false offline (the edits stay in this browser). */
  async save(reason = "autosave") {
    if (!this.live) return false;
    const done = await this.flush().then(() => this.live.online);
    if (!done && reason !== "autosave") {
      throw new Error("You are offline: your edits are kept in this browser and saved when the connection is back.");
    }
    return done;
  }

  /** Save, then download the server's numbered export (kind program|points). */
  async exportFile(kind) {
    await this.save("save");
    const response = await api("GET", `/api/workspaces/${this.id}/export/${kind}`, undefined, { raw: true });
    const text = await response.text();
    const disposition = response.headers.get("content-disposition") || "";
    const name = /filename="?([^"]+)"?/.exec(disposition)?.[1] || (kind === "program" ? "program.MB4" : "points.POS");
    downloadText(text, name);
    return name;
  }

  // ---- revision history ----
  async loadHistory() {
    const list = $("history-list");
    list.replaceChildren(el("li", { class: "muted" }, "Loading…"));
    try {
      const out = await api("GET", `/api/workspaces/${this.id}/revisions?limit=50`);
      list.replaceChildren(
        ...out.revisions.map((rev) =>
          el("li", {},
            el("span", {}, el("strong", {}, `#${rev.number}`), ` ${REASONS[rev.reason] ?? rev.reason}${rev.restored_from ? ` #${rev.restored_from}` : ""} · ${rev.author}`),
            el("span", { class: "when" }, formatTime(rev.created), ` · ${rev.program_chars} chars`),
            el("span", { class: "rev-actions" },
              el("button", { type: "button", class: "btn btn-sm", "aria-label": `Compare revision ${rev.number} with now`, onclick: () => showDiff(this, rev.number, (n) => this.restore(n)).catch((err) => showError("Could not compare", err)) }, "Compare"),
              el("button", { type: "button", class: "btn btn-sm", "aria-label": `Restore revision ${rev.number}`, onclick: () => this.restore(rev.number) }, "Restore")),
          )),
      );
      if (!out.revisions.length) list.replaceChildren(el("li", { class: "muted" }, "No revisions yet: the first save makes one."));
    } catch (err) {
      list.replaceChildren(el("li", { class: "err-text" }, err.message));
    }
  }

  /** Make revision `number` current again: the server saves what is typed first, then
   * edits the live document into the old text, for everyone who has it open. */
  async restore(number) {
    try {
      const out = await api("POST", `/api/workspaces/${this.id}/revisions/${number}/restore`, {});
      toast(`Revision ${number} restored`, { kind: "ok", text: `It is now revision ${out.revision.number}; the text it replaced stays in History.` });
      this.loadHistory();
    } catch (err) {
      showError("Could not restore", err);
    }
  }
}

// Revisions named by what made them.
const REASONS = { autosave: "Autosaved", save: "Saved", file: "Opened a file", restore: "Restored", import: "Imported" };

function formatTime(iso) {
  const date = new Date(/[zZ]|[+-]\d\d:?\d\d$/.test(iso) ? iso : iso + "Z"); // store times are UTC
  return isNaN(date) ? iso : date.toLocaleString([], { dateStyle: "short", timeStyle: "medium" });
}
