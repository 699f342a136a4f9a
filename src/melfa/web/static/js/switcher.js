// The workspace switcher next to the editor's buttons: the current workspace's name (a
// group's clearly "shared with group X"), and a menu to switch to another, make a new one
// or rename this one. Switching goes through Workspace.switchTo, which saves first.

import { $, el, showError, toast } from "./ui.js";

/** How a workspace is described to this user: {name, note, shared}. */
export function describeWorkspace(ws, user) {
  if (ws.kind === "group") return { name: ws.name, note: `shared with group ${ws.owner}`, shared: true };
  if (ws.owner !== user) return { name: ws.name, note: `${ws.owner}'s`, shared: false };
  return { name: ws.name, note: "", shared: false };
}

export class WorkspaceSwitcher {
  constructor(workspace, user) {
    this.workspace = workspace;
    this.user = user;
    this.showArchived = false;
    this.build();
    workspace.on("switched", () => this.render());
    workspace.on("list", () => this.render());
  }

  build() {
    this.label = el("span", { class: "ws-name", id: "ws-current-name" });
    this.note = el("span", { class: "ws-shared", id: "ws-shared-note", hidden: true });
    this.button = el("button", {
      type: "button", class: "ws-button", id: "ws-switch", "aria-haspopup": "menu", "aria-expanded": "false",
      "aria-controls": "ws-menu", onclick: () => this.toggle(this.menu.hidden),
    }, el("span", { class: "ws-icon", "aria-hidden": "true" }), this.label, this.note, el("span", { class: "ws-caret", "aria-hidden": "true" }, "▾"));
    this.menu = el("div", { class: "ws-menu", id: "ws-menu", role: "menu", "aria-label": "Workspaces", hidden: true });
    this.menu.addEventListener("keydown", (e) => this.onKey(e));
    this.box = el("div", { class: "ws-switcher", id: "ws-switcher" }, this.button, this.menu);
    $("open-mb4").before(this.box);
    // composedPath: the item clicked may already be replaced by fill() when this runs.
    document.addEventListener("click", (e) => { if (!e.composedPath().includes(this.box)) this.toggle(false); });
    this.dialog = new NameDialog();
  }

  render() {
    const ws = this.workspace;
    const said = describeWorkspace(ws, this.user);
    this.label.textContent = said.name;
    this.note.hidden = !said.shared && !said.note;
    // "shared" stays when the bar is narrow; " with group X" gives way (workspaces.css).
    const [first, ...rest] = said.note.split(" ");
    this.note.replaceChildren(first, el("span", { class: "ws-note-rest" }, rest.length ? " " + rest.join(" ") : ""));
    this.box.classList.toggle("shared", said.shared);
    this.button.title = said.shared
      ? `Everyone in group ${ws.owner} edits this program: changes are saved for all of you. Click to switch workspace.`
      : "Your workspace: only you edit it. Click to switch, make a new one or rename it.";
    this.button.setAttribute("aria-label", `Workspace: ${said.name}${said.note ? ", " + said.note : ""}. Switch, new or rename`);
    if (!this.menu.hidden) this.fill();
  }

  fill() {
    const ws = this.workspace;
    const open = ws.list.filter((w) => !w.archived);
    const mine = open.filter((w) => w.kind === "personal" && w.owner === this.user);
    const groups = open.filter((w) => w.kind === "group");
    const others = open.filter((w) => w.kind === "personal" && w.owner !== this.user);
    const archived = ws.list.filter((w) => w.archived);
    const own = ws.kind === "personal" && ws.owner === this.user;
    const item = (w) => {
      const said = describeWorkspace(w, this.user);
      const current = w.id === ws.id;
      return el("button", {
        type: "button", role: "menuitemradio", class: "ws-item", "aria-checked": String(current), "data-id": String(w.id),
        onclick: () => this.switchTo(w.id),
      }, el("span", { class: "ws-check", "aria-hidden": "true" }, current ? "✓" : ""),
      el("span", { class: "ws-item-name" }, said.name),
      w.id === ws.defaultId && !said.shared ? el("span", { class: "ws-tag" }, "default") : null,
      said.note ? el("span", { class: said.shared ? "ws-tag shared" : "ws-tag" }, said.note) : null);
    };
    const section = (title, list) => (list.length ? [el("div", { class: "ws-section", role: "presentation" }, title), ...list.map(item)] : []);
    this.menu.replaceChildren(...[
      ...section("My workspaces", mine),
      ...section("Group", groups),
      ...section("Other people's", others),
      el("div", { class: "ws-sep", role: "separator" }),
      el("button", { type: "button", role: "menuitem", class: "ws-action", id: "ws-new", onclick: () => this.create() }, "New workspace…"),
      el("button", { type: "button", role: "menuitem", class: "ws-action", id: "ws-rename", onclick: () => this.rename() }, `Rename “${ws.name}”…`),
      own && ws.id !== this.firstOwnId() ? el("button", { type: "button", role: "menuitem", class: "ws-action", id: "ws-archive", onclick: () => this.archive() }, `Archive “${ws.name}”…`) : null,
      archived.length ? el("div", { class: "ws-sep", role: "separator" }) : null,
      archived.length ? el("button", {
        type: "button", role: "menuitem", class: "ws-action ws-archived-toggle", id: "ws-show-archived", "aria-expanded": String(this.showArchived),
        onclick: () => { this.showArchived = !this.showArchived; this.fill(); this.menu.querySelector("#ws-show-archived").focus(); },
      }, `${this.showArchived ? "Hide" : "Show"} archived (${archived.length})`) : null,
      ...(this.showArchived ? archived.map((w) => el("button", {
        type: "button", role: "menuitem", class: "ws-item archived", "data-id": String(w.id),
        title: "Bring it back to the list (its program and history are all there)", onclick: () => this.unarchive(w),
      }, el("span", { class: "ws-check", "aria-hidden": "true" }), el("span", { class: "ws-item-name" }, w.name), el("span", { class: "ws-tag" }, "bring back"))) : []),
    ].filter(Boolean));
  }

  /** My first workspace ("My programs"): never archived. */
  firstOwnId() {
    const ids = this.workspace.list.filter((w) => w.kind === "personal" && w.owner === this.user).map((w) => w.id);
    return ids.length ? Math.min(...ids) : null;
  }

  async archive() {
    this.toggle(false);
    const ws = this.workspace;
    const name = ws.name;
    if (!confirm(`Archive “${name}”?\n\nIt leaves this list; nothing in it is deleted. “Show archived” at the bottom of this menu brings it back.`)) return;
    try {
      if (await ws.archive(ws.id)) toast(`“${name}” archived`, { kind: "ok", text: "Nothing was deleted: “Show archived” in the workspace menu brings it back." });
    } catch (err) {
      showError(`Could not archive “${name}”`, err);
    }
  }

  async unarchive(w) {
    try {
      await this.workspace.archive(w.id, false);
      await this.switchTo(w.id);
    } catch (err) {
      showError(`Could not bring back “${w.name}”`, err);
    }
  }

  toggle(open) {
    if (open) this.fill();
    this.menu.hidden = !open;
    this.button.setAttribute("aria-expanded", String(open));
    if (open) (this.menu.querySelector('[aria-checked="true"]') || this.menu.querySelector("[role^=menuitem]"))?.focus();
  }

  onKey(e) {
    const items = [...this.menu.querySelectorAll("[role^=menuitem]")];
    const i = items.indexOf(document.activeElement);
    if (e.key === "Escape") { e.preventDefault(); this.toggle(false); this.button.focus(); }
    else if (e.key === "ArrowDown") { e.preventDefault(); items[(i + 1) % items.length].focus(); }
    else if (e.key === "ArrowUp") { e.preventDefault(); items[(i - 1 + items.length) % items.length].focus(); }
    else if (e.key === "Home") { e.preventDefault(); items[0].focus(); }
    else if (e.key === "End") { e.preventDefault(); items.at(-1).focus(); }
    else if (e.key === "Tab") this.toggle(false);
  }

  async switchTo(id) {
    this.toggle(false);
    try {
      if (await this.workspace.switchTo(id)) toast(`Switched to “${this.workspace.name}”`, { kind: "info", text: describeWorkspace(this.workspace, this.user).shared ? "Shared with your group: everyone in it edits this program." : "Your edits to the previous workspace are saved." });
    } catch (err) {
      showError("Could not switch workspace", err);
    }
    this.button.focus();
  }

  async create() {
    this.toggle(false);
    const names = this.workspace.myNames();
    const name = await this.dialog.ask({
      title: "New workspace", action: "Create", value: "",
      help: "An empty program and no points. The workspace you are in now stays as it is.",
      taken: names,
      submit: (value) => this.workspace.create(value),
    });
    if (name) toast(`Workspace “${name}” created`, { kind: "ok", text: "It is empty. Switch back to the others with the workspace menu." });
  }

  async rename() {
    this.toggle(false);
    const ws = this.workspace;
    const own = ws.kind === "personal" && ws.owner === this.user;
    const name = await this.dialog.ask({
      title: `Rename “${ws.name}”`, action: "Rename", value: ws.name,
      help: ws.kind === "group" ? `Everyone in group ${ws.owner} sees the new name.` : "Only the name changes: the program, points and history stay.",
      taken: own ? ws.myNames().filter((n) => n !== ws.name) : [],
      submit: (value) => ws.rename(value),
    });
    if (name) toast(`Renamed to “${name}”`, { kind: "ok" });
  }
}

/** One dialog that asks for a workspace name; checks it as the server will, and shows the
 * server's refusal under the field instead of closing. */
class NameDialog {
  constructor() {
    this.input = el("input", { id: "ws-name-input", type: "text", maxlength: "60", autocomplete: "off", required: true, "aria-describedby": "ws-name-help ws-name-error" });
    this.help = el("p", { class: "help", id: "ws-name-help" });
    this.error = el("p", { class: "ws-name-error", id: "ws-name-error", role: "alert" });
    this.title = el("h2", { id: "ws-name-title" });
    this.submitButton = el("button", { type: "submit", class: "btn btn-primary", id: "ws-name-submit" });
    this.form = el("form", { method: "dialog", novalidate: true },
      el("label", { for: "ws-name-input", class: "ws-name-label" }, "Name"), this.input, this.help, this.error,
      el("div", { class: "dialog-actions" },
        el("button", { type: "button", class: "btn", id: "ws-name-cancel", onclick: () => this.node.close() }, "Cancel"),
        this.submitButton));
    this.node = el("dialog", { id: "ws-name-dialog", class: "ws-name-dialog", "aria-labelledby": "ws-name-title" }, this.title, this.form);
    document.body.append(this.node);
  }

  /** Resolves the name given (after `submit` succeeded), or null when cancelled. */
  ask({ title, action, value, help, taken, submit }) {
    this.title.textContent = title;
    this.submitButton.textContent = action;
    this.help.textContent = help;
    this.error.textContent = "";
    this.input.value = value;
    this.input.removeAttribute("aria-invalid");
    return new Promise((resolve) => {
      let result = null;
      this.form.onsubmit = async (e) => {
        e.preventDefault();
        const name = this.input.value.replace(/\s+/g, " ").trim();
        const problem = !name ? "A workspace needs a name."
          : taken.some((t) => t.toLowerCase() === name.toLowerCase()) ? `You already have a workspace called “${name}”.` : "";
        if (problem) return this.refuse(problem);
        this.submitButton.disabled = true;
        try {
          const out = await submit(name);
          if (out) {
            result = out.name ?? name;
            this.node.close();
          } else {
            this.node.close();
          }
        } catch (err) {
          this.refuse(err.message.replace(/^name: /, ""));
        } finally {
          this.submitButton.disabled = false;
        }
      };
      this.node.onclose = () => resolve(result);
      this.node.showModal();
      this.input.select();
    });
  }

  refuse(text) {
    this.error.textContent = text.charAt(0).toUpperCase() + text.slice(1);
    this.input.setAttribute("aria-invalid", "true");
    this.input.focus();
  }
}
