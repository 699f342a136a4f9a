// Changing one's own password from the user menu (PUT /api/session/password): the current
// password is needed; a weak or common new one is refused with the server's reason; other
// sessions of the user are signed out, this one stays.

import { api } from "./api.js";
import { $, toast } from "./ui.js";
import { ACCOUNT_WORDS as W } from "/vocab.js"; // generated from melfa.vocab.account

export class PasswordDialog {
  constructor() {
    this.dialog = $("password-dialog");
    this.error = $("password-error");
    $("password-open").addEventListener("click", () => this.open());
    $("password-cancel").addEventListener("click", () => this.dialog.close());
    $("password-form").addEventListener("submit", (e) => {
      e.preventDefault();
      this.change();
    });
  }

  open() {
    $("password-form").reset();
    this.error.hidden = true;
    this.dialog.showModal();
    $("password-current").focus();
  }

  async change() {
    try {
      await api("PUT", "/api/session/password", {
        current: $("password-current").value,
        new: $("password-new").value,
      });
      this.dialog.close();
      toast(W["password-changed"]);
    } catch (err) {
      this.error.textContent = err.message || W["password-failed"];
      this.error.hidden = false;
    }
  }
}
