// Personal access tokens in the user menu: make one (shown once, to paste into a roslibjs
// page's URL as ?token=, a roslibpy script or curl's Authorization: Bearer), see which
// exist and when they were last used, revoke one (its open connections close at once).

import { api } from "./api.js";
import { fill } from "./activity.js";
import { $, el, showError, toast } from "./ui.js";
import { ACCOUNT_WORDS as W } from "/vocab.js"; // generated from melfa.vocab.account

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
            type: "button", class: "btn btn-sm", "aria-label": fill(W["revoke-label"], { label: t.label }),
            onclick: () => this.revoke(t),
          }, W.revoke))));
      this.list.replaceChildren(
        ...(rows.length ? rows : [el("tr", {}, el("td", { colspan: "4" }, W["no-tokens"]))]));
    } catch (err) {
      showError(W["list-failed"], err);
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
      showError(W["make-failed"], err);
    }
  }

  async revoke(token) {
    try {
      await api("DELETE", `/api/tokens/${token.id}`);
      toast(fill(W.revoked, { label: token.label }));
      await this.refresh();
    } catch (err) {
      showError(W["revoke-failed"], err);
    }
  }
}
