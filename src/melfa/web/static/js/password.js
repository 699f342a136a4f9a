// Changing one's own password from the user menu (PUT /api/session/password): the current
// password is needed; a weak or common new one is refused with the server's reason; other
// sessions of the user are signed out, this one stays.

import { api } from "./api.js";
import { $, toast } from "./ui.js";

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
      toast("Password changed; your other sessions were signed out");
    } catch (err) {
      this.error.textContent = err.message || "Could not change the password";
      this.error.hidden = false;
    }
  }
}
