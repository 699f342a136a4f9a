// Whose program is in the controller's slot (the state's `slot`: who loaded it, when, its
// fingerprint, from which workspace; docs/api.md "state"), told in the words of the served
// vocabulary (SLOT_WORDS in /vocab.js, from melfa.vocab.slot). The toolbar's chip says it;
// *Run* asks first when the slot does not hold the text in this editor, and names the
// program it means (`expect`), so the service refuses it if someone loads in between;
// the editor marks lines only for a program this browser loaded from the text it holds.

import { SLOT_WORDS } from "/vocab.js";
import { api } from "./api.js";
import { loaded } from "./stores.js";
import { $, el } from "./ui.js";

export function fill(template, values) {
  return template.replace(/\{(\w+)\}/g, (all, key) => (key in values ? String(values[key]) : all));
}

function clock(iso) {
  const when = new Date(iso);
  return isNaN(when) ? "" : when.toLocaleTimeString([], { hour: "2-digit", minute: "2-digit" });
}

function facts(slot) {
  return {
    user: slot.user,
    time: clock(slot.at),
    workspace: slot.workspace,
    from: slot.workspace ? fill(SLOT_WORDS.from, { workspace: slot.workspace }) : "",
  };
}

/**
 * Whose the slot is for this browser: "none" (nothing known), "mine" (this browser loaded
 * it from the text its editor holds), "changed" (the user's own load, but not this text)
 * or "theirs" (someone else's).
 */
export function slotOwner(slot, me, loaded, text) {
  if (!slot) return "none";
  const same = !!loaded.fingerprint && loaded.fingerprint === slot.fingerprint;
  if (same && loaded.program === text) return "mine";
  return slot.user === me ? "changed" : "theirs";
}

/** The chip's sentence for the slot. */
export function slotText(slot, owner) {
  if (!slot) return SLOT_WORDS.empty;
  const key = owner === "mine" ? "mine" : owner === "changed" ? "mine_changed" : "theirs";
  return fill(SLOT_WORDS[key], facts(slot));
}

/** The chip's few words (whose program, first: they fit the view's head at 1024 px). */
export function slotChipText(slot, owner) {
  if (!slot) return SLOT_WORDS.chip_empty;
  const key = owner === "mine" ? "chip_mine" : owner === "changed" ? "chip_mine_changed" : "chip_theirs";
  return fill(SLOT_WORDS[key], facts(slot));
}

/** The toolbar's chip: rewritten only when what it says changes (state comes ~20/s). */
export class SlotChip {
  constructor(node) {
    this.node = node;
    this.shown = null;
  }

  render(slot, owner) {
    const text = slotText(slot, owner);
    const key = `${owner}|${text}`;
    if (key === this.shown) return;
    this.shown = key;
    this.node.dataset.owner = owner;
    this.node.title = text;
    this.node.setAttribute("aria-label", text);
    this.node.replaceChildren(
      el("span", { class: "slot-dot", "aria-hidden": "true" }),
      el("span", { class: "slot-text", "aria-hidden": "true" }, slotChipText(slot, owner)),
    );
  }
}

/**
 * Before *Run*: what to do, asked when the slot does not hold this editor's text.
 * Resolves {expect} to run (the fingerprint the student agreed to), {load: true} to load
 * theirs first, or null (cancelled).
 */
export function askBeforeRun(slot, owner) {
  if (owner === "mine") return Promise.resolve({ expect: slot.fingerprint });
  const dialog = $("run-dialog");
  const f = slot ? facts(slot) : {};
  const kind = owner === "none" ? "unknown" : owner;
  $("run-title").textContent = fill(SLOT_WORDS[`ask_title_${kind}`], f);
  $("run-text").textContent = fill(SLOT_WORDS[`ask_${kind}`], f);
  const go = $("run-anyway");
  go.textContent = fill(SLOT_WORDS[{ theirs: "run_theirs", changed: "run_old", unknown: "run_unknown" }[kind]], f);
  $("run-load").textContent = SLOT_WORDS.load_mine;
  dialog.dataset.kind = kind;
  return new Promise((resolve) => {
    const finish = (value) => {
      dialog.removeEventListener("close", onClose);
      for (const [node, fn] of handlers) node.removeEventListener("click", fn);
      if (dialog.open) dialog.close();
      resolve(value);
    };
    const onClose = () => finish(null);
    const handlers = [
      [go, () => finish(slot ? { expect: slot.fingerprint } : {})],
      [$("run-load"), () => finish({ load: true })],
      [$("run-cancel"), () => finish(null)],
    ];
    for (const [node, fn] of handlers) node.addEventListener("click", fn);
    dialog.addEventListener("close", onClose);
    dialog.showModal();
    $("run-load").focus(); // the safe choice first
  });
}

/**
 * A run-time alarm's headline: "Error L9100 at line 4" (the student's line when the slot is
 * theirs to read here), naming whose program it is when it is not this browser's.
 */
export function programErrorText(alarm, slot, owner, line) {
  const code = alarm.code || String(alarm.number);
  if (line) return fill(SLOT_WORDS.program_error, { code, line });
  if (owner === "theirs" && alarm.line && slot) return fill(SLOT_WORDS.program_error_theirs, { code, line: alarm.line, user: slot.user });
  if (alarm.step) return fill(SLOT_WORDS.program_error_step, { code, step: alarm.step });
  return "";
}

/** The words for a run stopped because every page of this user had closed. */
export function stoppedWhenLeftText(iso) {
  return fill(SLOT_WORDS.stopped_when_left, { time: clock(iso) });
}

let asked = "";

/**
 * The user's own program is in the slot but this page did not load it (the queue's claim
 * loaded it, another tab did, or a sign-in since): asks the server whether the editor's
 * text is that program and, if so, takes its step map, so the running line is marked and
 * the chip does not say the editor changed. Asked once per slot and text.
 */
export async function adoptSlot(slot, me, program, points) {
  if (!slot || slot.user !== me || loaded.get().fingerprint === slot.fingerprint) return;
  const key = `${slot.fingerprint}\u0000${program}\u0000${points}`;
  if (key === asked) return;
  asked = key;
  try {
    const out = await api("POST", "/api/robot/slot/match", { program, points });
    if (out.same) loaded.remember(program, out.step_lines, out.fingerprint);
  } catch {
    /* the chip keeps saying what this page knows */
  }
}
