// Presence in the editor: who has this workspace open (a chip each, in their colour) and
// where their cursor is (a caret with their name, drawn over Ace and kept on its character
// while anyone types: positions are Yjs relative positions). Staff looking at someone
// else's workspace read it only, under a banner saying whose work it is, with an
// audited "Edit as instructor" (the server refuses their writes until then).

import { $, el } from "./ui.js";
import { VISIT_WORDS as V } from "/vocab.js";

const fill = (text, facts) => text.replace(/\{(\w+)\}/g, (_, k) => String(facts[k] ?? ""));

const CURSOR_SEND_MS = 80;
const FLAG_MS = 4000; // a partner's name flag shows this long after their cursor moved

export class PresenceView {
  constructor(workspace, editor) {
    this.workspace = workspace;
    this.editor = editor;
    this.ace = editor.editor;
    this.bar = $("presence");
    this.layer = el("div", { class: "peer-cursors", "aria-hidden": "true" });
    this.ace.container.append(this.layer);
    this.peers = [];
    this.heads = new Map(); // peer → its last head, to know when it moved
    this.moved = new Map(); // peer → when its cursor last moved
    workspace.on("presence", ({ peers }) => {
      this.peers = peers;
      this.render();
    });
    workspace.on("switched", () => {
      this.peers = [];
      this.render();
    });
    workspace.on("access", () => this.render());
    workspace.on("remote", () => this.drawCursors());
    this.ace.renderer.on("afterRender", () => this.drawCursors());
    let timer = null;
    const sendCursor = () => {
      clearTimeout(timer);
      timer = setTimeout(() => this.sendCursor(), CURSOR_SEND_MS);
    };
    this.ace.selection.on("changeCursor", sendCursor);
    this.ace.selection.on("changeSelection", sendCursor);
    this.ace.on("focus", sendCursor);
    this.ace.on("blur", sendCursor);
  }

  sendCursor() {
    const live = this.workspace.live;
    if (!live || !live.online) return;
    const doc = this.ace.session.doc;
    const selection = this.ace.selection;
    live.cursor(doc.positionToIndex(selection.getSelectionAnchor()), doc.positionToIndex(selection.getSelectionLead()));
  }

  /** The chips: everyone else here (one per person, however many tabs). */
  render() {
    const live = this.workspace.live;
    const people = new Map();
    for (const p of this.peers) {
      if (p.user !== this.workspace.user && !people.has(p.user)) people.set(p.user, p);
    }
    const chips = [];
    if (people.size) {
      chips.push(el("span", { class: "presence-label" }, "Here now:"));
      for (const p of people.values()) {
        chips.push(el("span", {
          class: `peer-chip peer-${p.colour}`,
          title: `${p.user} has this workspace open${p.writable ? "; you see each other's edits as they are typed" : " (read-only)"}`,
        }, el("span", { class: "peer-dot", "aria-hidden": "true" }), p.user));
      }
    }
    if (live && live.synced && !live.writable) chips.push(el("span", { class: "peer-readonly" }, "Read-only"));
    this.banner(live);
    this.bar.replaceChildren(...chips);
    this.bar.hidden = !chips.length;
    const now = Date.now();
    for (const p of this.peers) {
      if (this.heads.get(p.peer) !== p.head) this.moved.set(p.peer, now);
      this.heads.set(p.peer, p.head);
    }
    clearTimeout(this.quietTimer);
    this.quietTimer = setTimeout(() => this.drawCursors(), FLAG_MS + 50);
    this.drawCursors();
  }

  /** Staff in someone else's workspace: whose work it is, read-only or edited as
   * instructor, and the one button that switches (the server decides and audits). */
  banner(live) {
    const node = $("visit-banner");
    const visiting = Boolean(live && live.synced && live.visiting);
    node.hidden = !visiting;
    if (!visiting) return node.replaceChildren();
    const facts = { who: live.owner, workspace: this.workspace.name || live.owner };
    const editing = live.writable;
    const act = async () => {
      try {
        await (editing ? this.workspace.readOnlyAgain() : this.workspace.editHere());
      } catch (err) {
        node.querySelector(".visit-error")?.remove();
        node.append(el("span", { class: "visit-error", role: "alert" }, err.message));
      }
    };
    node.className = "visit-banner" + (editing ? " editing" : "");
    node.replaceChildren(
      el("div", { class: "visit-text" },
        el("strong", {}, fill(V[editing ? "editing" : "reading"], facts)),
        el("span", {}, " " + V[editing ? "editing-help" : "reading-help"])),
      el("button", { type: "button", class: editing ? "btn btn-sm" : "btn btn-sm btn-primary", id: "visit-edit", onclick: act },
        V[editing ? "stop-editing" : "edit"]));
  }

  /** Each partner's caret where their cursor is now. */
  drawCursors() {
    const live = this.workspace.live;
    const renderer = this.ace.renderer;
    const doc = this.ace.session.doc;
    const box = this.ace.container.getBoundingClientRect();
    const marks = [];
    for (const p of this.peers) {
      if (!live || p.peer === live.peer || p.user === this.workspace.user) continue;
      const index = live.indexOf(p.head);
      if (index == null) continue;
      const pos = doc.indexToPosition(index, 0);
      const at = renderer.textToScreenCoordinates(pos.row, pos.column);
      const top = at.pageY - box.top;
      const left = at.pageX - box.left;
      if (top < -2 || top > box.height - 4 || left < renderer.gutterWidth - 2) continue;
      const quiet = Date.now() - (this.moved.get(p.peer) ?? 0) > FLAG_MS;
      marks.push(el("div", {
        class: `peer-cursor peer-${p.colour}${quiet ? " quiet" : ""}`,
        style: `top:${top}px;left:${left}px;height:${renderer.lineHeight}px`,
        "data-user": p.user,
        "data-line": String(pos.row + 1),
      }, el("span", { class: "peer-flag" }, p.user)));
    }
    this.layer.replaceChildren(...marks);
  }
}
