// Personal access tokens in the user menu: make one (shown once, to paste into a roslibjs
// page's URL as ?token=, a roslibpy script or curl's Authorization: Bearer), see which
// exist and when they were last used, revoke one (its open connections close at once).

import { api } from "./api.js";
import { $, el, showError, toast } from "./ui.js";

function when(text) {
  return text ? new Date(text).toLocaleString() : "never";
}

export class TokensDialog {
  constructor() {
    this.dialog = $("tokens-dialog");
    this.list = $("tokens-list");
    this.made = $("token-made");
    $("tokens-open").addEventListener("click", () => this.open());
    $("tokens-close").addEventListener("click", () => this.dialog.close());
    $("token-form").addEventListener("submit", (e) => {
      e.preventDefault();
      this.make();
    });
  }

  async open() {
    this.made.hidden = true;
    this.dialog.showModal();
    await this.refresh();
  }

  async refresh() {
    try {
      const { tokens } = await api("GET", "/api/tokens");
      const rows = tokens.map((t) =>
        el("tr", {},
          el("td", {}, t.label),
          el("td", {}, when(t.created)),
          el("td", {}, when(t.last_used)),
          el("td", {}, el("button", {
            type: "button", class: "btn btn-sm", "aria-label": `Revoke the token ${t.label}`,
            onclick: () => this.revoke(t),
          }, "Revoke"))));
      this.list.replaceChildren(
        ...(rows.length ? rows : [el("tr", {}, el("td", { colspan: "4" }, "No tokens yet."))]));
    } catch (err) {
      showError("Could not list your tokens", err);
    }
  }

  async make() {
    const label = $("token-label").value.trim();
    try {
      const out = await api("POST", "/api/tokens", { label });
      $("token-value").value = out.token;
      this.made.hidden = false;
      $("token-value").select();
      $("token-label").value = "";
      await this.refresh();
    } catch (err) {
      showError("Could not make a token", err);
    }
  }

  async revoke(token) {
    try {
      await api("DELETE", `/api/tokens/${token.id}`);
      toast(`Token “${token.label}” revoked`);
      await this.refresh();
    } catch (err) {
      showError("Could not revoke the token", err);
    }
  }
}
