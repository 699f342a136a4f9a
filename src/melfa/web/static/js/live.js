// The one WebSocket of this tab (/api/ws): reconnects with back-off, dispatches messages by
// type, and offers request/acknowledge for client messages (ids echoed in `ack`/`error`).

import { IDE_WORDS as W } from "/vocab.js"; // generated from melfa.vocab.ide

export class Live extends EventTarget {
  constructor(url) {
    super();
    this.url = url;
    this.socket = null;
    this.connected = false;
    this.nextId = 1;
    this.pending = new Map(); // id -> {resolve, reject}
    this.retryMs = 500;
    this.retryTimer = null;
    this.closedByUs = false;
  }

  /** Open (or reopen now, e.g. the user clicked the status). */
  connect() {
    clearTimeout(this.retryTimer);
    if (this.socket && this.socket.readyState <= WebSocket.OPEN) return;
    this.emit("status", { state: "connecting" });
    const socket = new WebSocket(this.url);
    this.socket = socket;
    socket.addEventListener("open", () => {
      this.connected = true;
      this.retryMs = 500;
      this.emit("status", { state: "open" });
    });
    socket.addEventListener("message", (event) => {
      let message;
      try {
        message = JSON.parse(event.data);
      } catch {
        return;
      }
      if ((message.type === "ack" || message.type === "error" || message.type === "pong") && message.id != null) {
        const waiter = this.pending.get(message.id);
        if (waiter) {
          this.pending.delete(message.id);
          if (message.type === "error") waiter.reject(message.error);
          else waiter.resolve(message);
        }
      }
      this.emit(message.type, message);
    });
    socket.addEventListener("close", (event) => {
      if (this.socket !== socket) return;
      this.connected = false;
      this.socket = null;
      for (const waiter of this.pending.values()) waiter.reject({ code: "offline", message: W["socket-lost"] });
      this.pending.clear();
      this.emit("status", { state: "closed", code: event.code, reason: event.reason });
      if (event.code === 1008) return; // signed out or foreign origin: reconnecting will not help
      // Back-off up to 10 s; the user can click the status to retry at once.
      this.retryTimer = setTimeout(() => this.connect(), this.retryMs);
      this.retryMs = Math.min(this.retryMs * 2, 10000);
    });
  }

  /** Follow another stream (another target): close this socket, open `url` now. */
  retarget(url) {
    this.url = url;
    const old = this.socket;
    this.socket = null; // its close event is ignored: this is not a lost connection
    if (old) old.close(1000, W["socket-retargeted"]);
    this.connected = false;
    for (const waiter of this.pending.values()) waiter.reject({ code: "offline", message: W["socket-retargeted"] });
    this.pending.clear();
    this.retryMs = 500;
    this.connect();
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  on(type, handler) {
    this.addEventListener(type, (event) => handler(event.detail));
  }

  /** Send without waiting. Returns false when the socket is not open. */
  send(message) {
    if (!this.socket || this.socket.readyState !== WebSocket.OPEN) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }

  /** Send with an id and wait for its ack (rejects with the error shape on `error`). */
  request(message, timeoutMs = 5000) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      if (!this.send({ ...message, id })) {
        reject({ code: "offline", message: W["socket-closed"] });
        return;
      }
      this.pending.set(id, { resolve, reject });
      setTimeout(() => {
        if (this.pending.delete(id)) reject({ code: "timeout", message: W["socket-timeout"] });
      }, timeoutMs);
    });
  }
}
