// Control of the robot (the operator lease) in the header: who holds it, since when and
// how they are connected; the buttons that take, give back and take over; and the toasts
// when control changes hands under this user. Every word is melfa.vocab.lease's
// (/vocab.js: CONTROL_WORDS, HOLDER_STATES), as the desktop client's control row says it.

import { api } from "./api.js";
import { commandLabel, fill } from "./activity.js";
import { $, el, showError, toast } from "./ui.js";
import { CONTROL_WORDS as W, HOLDER_STATES, ROLE_WORDS } from "/vocab.js"; // generated from melfa.vocab.lease, .roles

/** The header's buttons: their words, and what they ask; `setLease(holder)` takes the answer. */
export function wireControl(setLease) {
  $("lease-group").setAttribute("aria-label", W.group);
  const buttons = [
    ["lease-take", W.take, "POST", "/api/lease", W.take_failed],
    ["lease-release", W.release, "DELETE", "/api/lease", W.release_failed],
    ["lease-takeover", W.take_over, "POST", "/api/lease/takeover", W.take_over_failed],
  ];
  for (const [id, words, method, path, failed] of buttons) {
    $(id).textContent = words;
    $(id).addEventListener("click", async () => {
      try {
        const out = await api(method, path);
        if (out && "holder" in out) setLease(out.holder);
        else if (method === "DELETE") setLease(null);
      } catch (err) {
        showError(failed, err);
      }
    });
  }
}

/** Who holds control, since when, and their connection (one user's tabs share it). */
export function renderControl({ holder, since, state, queued }, me, staff) {
  const text = $("lease-text");
  const mine = holder?.user === me;
  const when = holder && since ? new Date(since) : null;
  const connection = state && HOLDER_STATES[state];
  text.replaceChildren(
    W.control + " ",
    el("strong", {}, holder ? (mine ? W.you : holder.user) : queued ? W.by_queue : W.free),
    holder && !mine && holder.role ? el("span", { class: "lease-role" }, ` (${ROLE_WORDS[holder.role] ?? holder.role})`) : "",
    when && !isNaN(when) ? el("span", { class: "lease-since" }, " " + fill(W.since, { time: when.toLocaleTimeString([], { hour: "2-digit", minute: "2-digit" }) })) : "",
    holder && connection && state !== "connected" ? el("span", { class: "lease-state" }, ` · ${connection}`) : "",
  );
  text.title = holder ? (mine ? W.you_hold : fill(W.holds, { user: holder.user })) + (connection ? ` (${connection})` : "") : `${W.nobody}: ${queued ? W.queue_gives : W.first_takes}`;
  text.classList.toggle("mine", mine);
  text.dataset.holder = holder?.user ?? "";
  $("lease-take").hidden = !!holder || queued; // the queue gives it: a take would be refused
  $("lease-release").hidden = !mine;
  $("lease-takeover").hidden = !(holder && !mine && staff);
}

/** The toasts of a `lease` message that concern `me`: control taken from me (only an
 * instructor's take-over does that), or taken by a command of mine (nothing takes control
 * silently; on the shared robot only: My simulator is the user's alone). */
export function tellControl(m, me, shared) {
  if (m.previous?.user === me && m.holder && m.holder.user !== me) {
    toast(W.taken_over_title, { kind: "warning", text: fill(W.taken_over, { by: m.holder.user ?? W.an_instructor }) });
  }
  if (m.holder?.user === me && m.command && shared) {
    toast(W.yours_title, { kind: "info", text: fill(W.yours, { command: commandLabel(m.command), release: W.release }) });
  }
}
