// The workspace: program + points, autosaved to the server with the base revision, and a
// draft in localStorage on every keystroke so a reload, a dropped connection or a crashed
// tab never loses typing. A 409 conflict asks the student (keep mine / load theirs); edits
// are never dropped silently. One object follows the CURRENT workspace: switching to
// another (or creating one) saves the edits first, then swaps id and texts, so everything
// holding `app.workspace` (editor, points, history, debugger, load, export) acts on it.

import { api, ApiError, OfflineError, downloadText } from "./api.js";
import { showDiff } from "./opener.js";
import { $, debounce, el, showError, toast } from "./ui.js";

const AUTOSAVE_MS = 1200;
const RETRY_MS = 5000;

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
    this.base = 0; // the revision our texts are based on
    this.program = "";
    this.points = "";
    this.saved = { program: "", points: "" }; // what the server has at `base`
    this.saving = null; // the save in flight
    this.again = false; // another save is needed after it
    this.conflictOpen = false;
    this.autosave = debounce(() => this.save("autosave"), AUTOSAVE_MS);
    this.retryTimer = null;
  }

  get draftKey() {
    return `melfa.draft.${this.user}.${this.id}`;
  }

  /** The workspace's name as a file name stem (downloads are named after it). */
  get fileStem() {
    return (this.name || this.owner || "program").replace(/[^A-Za-z0-9._-]+/g, "_").replace(/^[._]+|[._]+$/g, "") || "program";
  }

  get dirty() {
    return this.program !== this.saved.program || this.points !== this.saved.points;
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

  /** Open the workspace opened last in this browser (else the default one); restore an
   * unsaved draft or ask when it conflicts. */
  async open() {
    await this.refreshList();
    let last = null;
    try { last = Number(localStorage.getItem(this.lastKey)); } catch { /* no storage */ }
    await this.load(this.list.some((w) => w.id === last && !w.archived) ? last : this.defaultId);
  }

  /** Load workspace `id` into this object (nothing of the previous one is kept here). */
  async load(id) {
    const ws = await api("GET", `/api/workspaces/${id}`);
    clearTimeout(this.retryTimer);
    this.autosave.cancel();
    this.id = ws.id;
    this.owner = ws.owner;
    this.name = ws.name;
    this.kind = ws.kind; // personal | group
    this.shared = ws.shared;
    try { localStorage.setItem(this.lastKey, String(ws.id)); } catch { /* no storage */ }
    this.base = ws.revision;
    this.saved = { program: ws.program, points: ws.points };
    this.program = ws.program;
    this.points = ws.points;
    const draft = this.readDraft();
    if (draft && (draft.program !== ws.program || draft.points !== ws.points)) {
      if (draft.base === ws.revision) {
        // Typed but never saved (reload, network gone): keep typing where it stopped.
        this.program = draft.program;
        this.points = draft.points;
        toast("Unsaved edits restored", { kind: "info", text: "Your last edits were kept in this browser; saving them now." });
        this.autosave();
      } else {
        this.program = draft.program;
        this.points = draft.points;
        this.emit("replaced", { source: "draft" });
        this.conflict({ number: ws.revision, author: "?", program: ws.program, points: ws.points, created: "" }, true);
      }
    } else if (draft) {
      this.clearDraft();
    }
    this.emit("replaced", { source: "open" });
    this.emit("switched", {});
    this.showStatus();
  }

  /** Save what is typed before leaving this workspace: true when the server has it. A
   * conflict opens the usual dialog (and stays here); offline keeps the draft here. */
  async flush() {
    if (this.saving) await this.saving.catch(() => {});
    if (this.dirty && !this.conflictOpen) await this.save("autosave").catch(() => {});
    return !this.dirty && !this.conflictOpen;
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

  readDraft() {
    try {
      const draft = JSON.parse(localStorage.getItem(this.draftKey) || "null");
      return draft && typeof draft.program === "string" ? draft : null;
    } catch {
      return null;
    }
  }

  writeDraft() {
    try {
      localStorage.setItem(this.draftKey, JSON.stringify({ base: this.base, program: this.program, points: this.points, at: Date.now() }));
    } catch {
      /* storage full or disabled: the server copy still saves */
    }
  }

  clearDraft() {
    localStorage.removeItem(this.draftKey);
  }

  /** The editor changed the program (or the points tab the points). */
  update({ program, points }) {
    if (program !== undefined) this.program = program;
    if (points !== undefined) this.points = points;
    if (this.dirty) {
      this.writeDraft();
      this.status("Unsaved changes…", "dirty");
      this.autosave();
    } else {
      this.showStatus();
    }
    if (points !== undefined) this.emit("points", {});
  }

  /** Replace both texts (restore, load theirs, file opened): the editor follows. */
  replace({ program, points }, source) {
    if (program !== undefined) this.program = program;
    if (points !== undefined) this.points = points;
    this.emit("replaced", { source });
    this.emit("points", {});
    this.update({});
  }

  showStatus() {
    if (this.dirty) this.status("Unsaved changes…", "dirty");
    else this.status(this.base ? `Saved · revision ${this.base}` : "Not saved yet");
  }

  /** Save now (reason autosave|save). Resolves when the server has our texts. */
  async save(reason = "autosave") {
    this.autosave.cancel();
    if (this.saving) {
      this.again = true;
      await this.saving.catch(() => {});
      if (!this.dirty && reason === "autosave") return;
    }
    if (!this.dirty && reason === "autosave") return;
    if (this.conflictOpen) return;
    const sent = { program: this.program, points: this.points };
    const id = this.id;
    this.status("Saving…");
    const job = api("PUT", `/api/workspaces/${id}`, { base: this.base, ...sent, reason });
    this.saving = job;
    try {
      const out = await job;
      if (id !== this.id) return; // switched meanwhile (never: switching waits for saves)
      this.base = out.revision.number;
      this.saved = { program: out.revision.program, points: out.revision.points };
      clearTimeout(this.retryTimer);
      if (!this.dirty) this.clearDraft();
      else this.writeDraft();
      this.showStatus();
      this.emit("saved", out.revision);
    } catch (err) {
      if (err instanceof ApiError && err.code === "save-conflict") {
        this.conflict(err.detail.current);
      } else if (err instanceof OfflineError || err.status >= 500) {
        this.status("Offline — edits kept in this browser", "error");
        clearTimeout(this.retryTimer);
        this.retryTimer = setTimeout(() => this.save("autosave"), RETRY_MS);
      } else {
        this.status("Not saved", "error");
        showError("Could not save the workspace", err);
      }
      if (reason !== "autosave") throw err;
    } finally {
      this.saving = null;
      if (this.again) {
        this.again = false;
        if (this.dirty) this.autosave();
      }
    }
  }

  /** Someone saved meanwhile (`current` is their revision): ask, never drop edits. */
  conflict(current, fromDraft = false) {
    if (this.conflictOpen) return;
    this.conflictOpen = true;
    this.status("Conflict — choose a version", "error");
    const dialog = $("conflict-dialog");
    const who = current.author && current.author !== "?" ? `${current.author} saved revision ${current.number}` : `The workspace is now at revision ${current.number}`;
    $("conflict-text").textContent = fromDraft
      ? `This browser holds edits made on revision ${this.readDraft()?.base ?? "?"}, but ${who.charAt(0).toLowerCase() + who.slice(1)}. Keep your edits (they become the newest revision; theirs stays in the history) or load theirs (yours can be downloaded first).`
      : `${who} while you were editing. Keep your edits (they become the newest revision; theirs stays in the history) or load theirs (download yours first if you want them).`;
    const finish = () => {
      this.conflictOpen = false;
      dialog.close();
    };
    $("conflict-mine").onclick = () => {
      finish();
      this.base = current.number;
      this.saved = { program: current.program, points: current.points };
      this.save("save").catch(() => {});
    };
    $("conflict-theirs").onclick = () => {
      finish();
      this.base = current.number;
      this.saved = { program: current.program, points: current.points };
      this.clearDraft();
      this.replace({ program: current.program, points: current.points }, "theirs");
    };
    $("conflict-download").onclick = () => {
      downloadText(this.program, `${this.fileStem}-mine.MB4`);
      if (this.points) downloadText(this.points, `${this.fileStem}-mine.POS`);
    };
    dialog.addEventListener("cancel", (e) => e.preventDefault(), { once: true }); // a choice is required
    if (!dialog.open) dialog.showModal();
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

  async restore(number) {
    await this.save("autosave").catch(() => {}); // the current text becomes a revision first
    try {
      const out = await api("POST", `/api/workspaces/${this.id}/revisions/${number}/restore`, { base: this.base });
      this.base = out.revision.number;
      this.saved = { program: out.revision.program, points: out.revision.points };
      this.clearDraft();
      this.replace({ program: out.revision.program, points: out.revision.points }, "restore");
      toast(`Revision ${number} restored`, { kind: "ok", text: `It is now revision ${out.revision.number}.` });
      this.loadHistory();
    } catch (err) {
      if (err.code === "save-conflict") this.conflict(err.detail.current);
      else showError("Could not restore", err);
    }
  }
}

// Revisions named by what made them.
const REASONS = { autosave: "Autosaved", save: "Saved", file: "Opened a file", restore: "Restored", import: "Imported", theirs: "Their version" };

function formatTime(iso) {
  const date = new Date(/[zZ]|[+-]\d\d:?\d\d$/.test(iso) ? iso : iso + "Z"); // store times are UTC
  return isNaN(date) ? iso : date.toLocaleString([], { dateStyle: "short", timeStyle: "medium" });
}
