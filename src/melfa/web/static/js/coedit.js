// Live co-editing of one workspace: a Yjs document (the program and the points as two
// texts) kept in step with the server's copy over /api/workspaces/{id}/live, and with
// every partner's. Edits go out as they are typed and partners' edits come in the same
// way; the CRDT merges what two people type at once, so no line is ever dropped and no
// dialog asks anyone to choose. Offline, edits stay in this document (and in this
// browser's storage, for a reload) and merge when the socket is back. The server saves
// the document as revisions (History). Messages: melfa.live.coedit (docs/coedit-schema.json).

import * as Y from "yjs";

const PING_MS = 5000; // the server lets a socket go after 15 s of silence
const SILENT_MS = 12000; // no message from the server this long: the connection is dead
const RETRY_MS = [500, 1000, 2000, 4000]; // reconnect back-off, then every 4 s
const FLUSH_MS = 8000;

export const REMOTE = "remote"; // the origin of changes that came from the server
export const EDITOR = "editor"; // the origin of this page's editor's own keystrokes

export function toBase64(bytes) {
  let text = "";
  for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(text);
}

export function fromBase64(text) {
  const raw = atob(text);
  const out = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
  return out;
}

/** The socket and document of one workspace; events: "status" {state}, "welcome",
 * "saved" {revision, authors, flushed}, "presence" {peers}, "change" {field, delta, local}. */
export class CoeditSession extends EventTarget {
  constructor(workspaceId, user) {
    super();
    this.id = workspaceId;
    this.user = user;
    this.doc = new Y.Doc();
    this.program = this.doc.getText("program");
    this.points = this.doc.getText("points");
    this.epoch = null;
    this.peer = null;
    this.writable = false; // the server decides: members, or staff who chose to edit
    this.visiting = false; // staff reading someone else's workspace
    this.owner = "";
    this.synced = false; // the first welcome has arrived
    this.revision = 0;
    this.peers = [];
    this.state = "connecting";
    this.closed = false;
    this.attempt = 0;
    this.flushes = [];
    this.edits = 0; // this page's own edits (and a kept copy's), counted...
    this.confirmed = 0; // ...and how many of them the server confirmed it saved (a flush)
    this.restore();
    this.watch();
    this.connect();
  }

  get storageKey() {
    return keptKey(this.user, this.id);
  }

  emit(type, detail = {}) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  on(type, handler) {
    this.addEventListener(type, (e) => handler(e.detail));
  }

  /** A document this browser kept (offline edits, a reload): it merges on the next hello. */
  restore() {
    try {
      const kept = JSON.parse(localStorage.getItem(this.storageKey) || "null");
      if (kept && kept.epoch && kept.update) {
        Y.applyUpdate(this.doc, fromBase64(kept.update), REMOTE);
        this.epoch = kept.epoch;
        this.edits = 1; // it may hold edits the server never got: unsynced until a flush
      }
    } catch {
      /* no storage, or not ours: start from the server's */
    }
  }

  keep() {
    clearTimeout(this.keepTimer);
    this.keepTimer = setTimeout(() => this.keepNow(), 300);
  }

  /** Write the document to this browser's storage now (leaving, switching, a reload). */
  keepNow() {
    clearTimeout(this.keepTimer);
    if (!this.epoch || this.forgotten) return;
    try {
      localStorage.setItem(this.storageKey, JSON.stringify({ epoch: this.epoch, update: toBase64(Y.encodeStateAsUpdate(this.doc)), at: Date.now() }));
    } catch {
      /* storage full: the server's copy still has every edit sent */
    }
  }

  watch() {
    this.doc.on("update", (update, origin) => {
      this.keep();
      if (origin !== REMOTE) this.edits++;
      if (origin !== REMOTE) this.send({ type: "update", update: toBase64(update) });
    });
    for (const [field, text] of [["program", this.program], ["points", this.points]]) {
      text.observe((event) => {
        const origin = event.transaction.origin;
        this.emit("change", { field, delta: event.delta, local: origin !== REMOTE, fromEditor: origin === EDITOR });
      });
    }
    // Undo takes back this page's own edits only, never a partner's line.
    this.undo = new Y.UndoManager([this.program, this.points], { trackedOrigins: new Set([EDITOR, null]) });
  }

  connect() {
    if (this.closed) return;
    const url = new URL(`/api/workspaces/${this.id}/live`, location.href);
    url.protocol = url.protocol === "https:" ? "wss:" : "ws:";
    const socket = new WebSocket(url);
    this.socket = socket;
    this.setState("connecting");
    socket.onopen = () => {
      this.send({ type: "hello", state_vector: toBase64(Y.encodeStateVector(this.doc)), epoch: this.epoch }, true);
      this.heard = Date.now();
      clearInterval(this.pinger);
      this.pinger = setInterval(() => {
        if (Date.now() - this.heard > SILENT_MS) this.lost(socket); // a dead line
        else this.send({ type: "ping" });
      }, PING_MS);
    };
    socket.onmessage = (event) => {
      this.heard = Date.now();
      this.receive(JSON.parse(event.data));
    };
    socket.onclose = (event) => {
      if (this.socket !== socket) return;
      if (event.code === 1008) {
        this.drop(socket);
        this.setState("refused", event.reason);
        return;
      }
      this.lost(socket);
    };
  }

  drop(socket) {
    clearInterval(this.pinger);
    if (this.socket === socket) this.socket = null;
    this.welcomed = false;
  }

  /** The connection is gone (closed, or silent: a network that went away may never say
   * so). Edits keep going into the document; a new socket is tried with back-off. */
  lost(socket) {
    if (this.socket !== socket) return;
    this.drop(socket);
    try { socket.close(); } catch { /* already closing */ }
    if (this.closed) return;
    this.setState("offline");
    clearTimeout(this.retry);
    const delay = RETRY_MS[Math.min(this.attempt++, RETRY_MS.length - 1)];
    this.retry = setTimeout(() => this.connect(), delay);
  }

  receive(message) {
    switch (message.type) {
      case "welcome": {
        if (!message.merged && this.epoch !== null) {
          // Another document than the one kept here (the server's was made anew): start
          // from the server's; what was kept here no longer fits it.
          this.replaceDoc();
        }
        this.epoch = message.epoch;
        this.peer = message.peer;
        this.writable = message.writable;
        this.visiting = message.visiting;
        this.owner = message.owner;
        this.revision = message.revision;
        Y.applyUpdate(this.doc, fromBase64(message.update), REMOTE);
        // What the server lacks (typed offline, or before this socket opened).
        const missing = Y.encodeStateAsUpdate(this.doc, fromBase64(message.state_vector));
        this.welcomed = true;
        this.send({ type: "update", update: toBase64(missing) });
        this.attempt = 0;
        this.synced = true;
        this.keep();
        this.setState("live");
        this.emit("welcome", message);
        break;
      }
      case "update":
        Y.applyUpdate(this.doc, fromBase64(message.update), REMOTE);
        break;
      case "presence":
        this.peers = message.peers;
        this.emit("presence", { peers: message.peers });
        break;
      case "saved":
        this.revision = message.revision;
        this.emit("saved", message);
        if (message.flushed) for (const done of this.flushes.splice(0)) done(true);
        break;
      default:
        break;
    }
  }

  replaceDoc() {
    // Keep the same Y.Text objects' observers simple: clear the texts, then apply.
    this.doc.transact(() => {
      this.program.delete(0, this.program.length);
      this.points.delete(0, this.points.length);
    }, REMOTE);
    const fresh = new Y.Doc();
    this.undo.destroy();
    this.doc.destroy();
    this.doc = fresh;
    this.program = fresh.getText("program");
    this.points = fresh.getText("points");
    this.watch();
    this.emit("reset", {});
  }

  send(message, beforeWelcome = false) {
    const socket = this.socket;
    if (!socket || socket.readyState !== WebSocket.OPEN) return false;
    if (!beforeWelcome && !this.welcomed) return false; // the welcome's exchange sends it
    socket.send(JSON.stringify(message));
    return true;
  }

  setState(state, why = "") {
    this.state = state;
    this.emit("status", { state, why });
  }

  get online() {
    return this.state === "live";
  }

  /** Where this editor's cursor is (Yjs relative positions, or null when not focused). */
  cursor(anchor, head) {
    const rel = (index) => index == null ? null : toBase64(Y.encodeRelativePosition(Y.createRelativePositionFromTypeIndex(this.program, index)));
    const key = `${anchor},${head}`;
    if (key === this.lastCursor && this.online) return;
    this.lastCursor = key;
    this.send({ type: "cursor", anchor: rel(anchor), head: rel(head) });
  }

  /** A peer's cursor as an index into the program now (null if gone). */
  indexOf(relative) {
    if (!relative) return null;
    try {
      const abs = Y.createAbsolutePositionFromRelativePosition(Y.decodeRelativePosition(fromBase64(relative)), this.doc);
      return abs && abs.type === this.program ? abs.index : null;
    } catch {
      return null;
    }
  }

  /** Ask the server to save now; true once it has (false offline or after FLUSH_MS). */
  flush() {
    const upTo = this.edits;
    if (!this.send({ type: "flush" })) return Promise.resolve(false);
    return new Promise((resolve) => {
      this.flushes.push((saved) => {
        if (saved) this.confirmed = Math.max(this.confirmed, upTo);
        resolve(saved);
      });
      setTimeout(() => resolve(false), FLUSH_MS);
    });
  }

  /** Whether an edit made here (or kept here from before) is not yet saved on the server. */
  get unsynced() {
    return this.edits > this.confirmed;
  }

  /** Every edit made here on the server and saved: true; false offline (or no answer). */
  async settle() {
    if (!this.unsynced) return true;
    if (!this.online) return false;
    await this.flush();
    return !this.unsynced;
  }

  /** Close, and remove the copy kept in this browser (sign-out: only once `settle()`d, or
   * when the student chose to discard it). */
  forget() {
    this.forgotten = true;
    this.close();
    try { localStorage.removeItem(this.storageKey); } catch { /* no storage */ }
  }

  close() {
    this.keepNow();
    this.closed = true;
    clearTimeout(this.retry);
    clearInterval(this.pinger);
    this.socket?.close();
    this.socket = null;
  }
}

/** Where this browser keeps `user`'s copy of workspace `id` (offline edits, a reload). */
export function keptKey(user, id) {
  return `melfa.coedit.${user}.${id}`;
}

/** The workspaces of which this browser keeps a copy of `user`'s (their ids). */
export function keptIds(user) {
  const prefix = keptKey(user, "");
  const ids = [];
  try {
    for (let i = 0; i < localStorage.length; i++) {
      const key = localStorage.key(i);
      if (key && key.startsWith(prefix)) ids.push(Number(key.slice(prefix.length)));
    }
  } catch { /* no storage */ }
  return ids.filter((id) => Number.isInteger(id) && id > 0);
}

/** Make `text` read `target` with one splice (the common start and end kept): for whole
 * texts replaced at once (the points table, a restored or opened file). */
export function spliceTo(text, target) {
  const now = text.toString();
  if (now === target) return;
  let head = 0;
  while (head < now.length && head < target.length && now[head] === target[head]) head++;
  let tail = 0;
  while (tail < now.length - head && tail < target.length - head && now[now.length - 1 - tail] === target[target.length - 1 - tail]) tail++;
  text.doc.transact(() => {
    if (now.length - head - tail > 0) text.delete(head, now.length - head - tail);
    if (target.length - head - tail > 0) text.insert(head, target.slice(head, target.length - tail));
  }, null);
}
