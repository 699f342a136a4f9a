// Small shared UI helpers: toasts (human error messages from the API's error shape, with
// the controller's code and a one-click fix button),
// the activity indicator, element lookup.

export const $ = (id) => document.getElementById(id);

/** Make an element: el("li", {class: "x"}, "text", child…). */
export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (value === false || value == null) continue;
    if (key === "class") node.className = value;
    else if (key.startsWith("on")) node.addEventListener(key.slice(2), value);
    else node.setAttribute(key, value === true ? "" : value);
  }
  for (const child of children.flat()) {
    if (child == null || child === false) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

/**
 * A toast. kind: "info" | "ok" | "warning" | "error". `items` are extra lines (for
 * example diagnostics). Errors stay until closed; the others fade after a while.
 */
export function toast(title, { kind = "info", text = "", items = [], timeout, code = "", actions = [] } = {}) {
  const close = el("button", { class: "close", "aria-label": "Dismiss", type: "button" }, "✕");
  const buttons = actions.map(({ label, run }) => el("button", {
    type: "button", class: "btn btn-sm btn-primary toast-action",
    onclick: async () => { node.remove(); await run(); },
  }, label));
  const node = el(
    "div",
    { class: `toast ${kind}`, role: kind === "error" ? "alert" : "status" },
    el("div", {}, el("strong", {}, title, code ? " " : null, code ? el("span", { class: "code", title: "The controller's error code (see its manual)" }, code) : null),
      text ? el("span", {}, text) : null,
      items.length ? el("ul", {}, items.slice(0, 6).map((i) => el("li", {}, i))) : null,
      items.length > 6 ? el("span", { class: "muted" }, `… and ${items.length - 6} more`) : null,
      buttons.length ? el("div", { class: "toast-actions" }, buttons) : null),
    close,
  );
  close.addEventListener("click", () => node.remove());
  const box = document.getElementById("toasts");
  box.append(node);
  // Four at most: an unread error outlasts the notices (the oldest notice goes first).
  while (box.children.length > 4) {
    const notice = [...box.children].find((t) => t !== node && !t.classList.contains("error"));
    (notice || box.firstElementChild).remove();
  }
  // Errors stay until dismissed or acted on; the others fade after a while.
  const ms = timeout ?? (kind === "error" ? 0 : 4000);
  if (ms > 0) setTimeout(() => node.remove(), ms);
  return node;
}

/** One line per diagnostic: "line 3:5 — message (suggestion)". */
export function describeDiagnostic(d) {
  const where = d.line ? `line ${d.line}:${d.column} — ` : "";
  return `${where}${d.message}${d.suggestion ? " " + d.suggestion : ""}`;
}

const fixHandlers = new Map();
/** Register the handler of a one-click fix (`detail.fix` of an API error: docs/api.md). */
export function onFix(action, handler) {
  fixHandlers.set(action, handler);
}

/**
 * An API error in the student's words and where. The server's message already is them (a
 * refusal says what happened and its fix in the words of melfa.vocab.refusals: "ann holds
 * the robot. Ask them to release it…"); nothing is re-worded here.
 */
export function errorText(err) {
  let text = err?.message || String(err);
  if (err?.where?.line) text += ` (line ${err.where.line}${err.where.column ? ":" + err.where.column : ""})`;
  return text;
}

/**
 * Show an API error as a toast that says what went wrong, where known where, the
 * controller's code (L2000) and the one-click fix as a button. `retry(extra)` repeats the
 * refused action (the servo fix retries with `{servo_on: true}`).
 */
export function showError(what, err, { retry = null } = {}) {
  if (err?.name === "AbortError") return;
  const items = [];
  const diags = err?.detail?.diagnostics;
  if (Array.isArray(diags)) for (const d of diags) items.push(describeDiagnostic(d));
  // A list of diagnostics says where each is: the message is not followed by "(line 2:1)".
  const text = items.length ? err?.message || String(err) : errorText(err);
  const actions = [];
  const fix = err?.detail?.fix;
  // What the refusal says is no longer so (pre-flight's "the lab robot may run it") goes.
  if (fix) document.dispatchEvent(new CustomEvent("melfa:fix-offered", { detail: fix }));
  if (fix && fixHandlers.has(fix)) {
    actions.push({ label: err.detail.fix_label || "Fix", run: () => fixHandlers.get(fix)({ err, retry }) });
  }
  return toast(what, { kind: "error", text, items, code: err?.detail?.code || "", actions });
}

/**
 * "Project loaded in 1.3 s", or just "Project loaded" when it took under 0.1 s (My simulator
 * loads at once: "in 0.0 s" read as broken). Two significant digits: 0.42 s, 1.3 s, 12 s.
 */
export function took(what, seconds) {
  if (!(seconds >= 0.1)) return what;
  return `${what} in ${Number(seconds.toPrecision(2))} s`;
}

/** The toolbar's activity line: busy spinner, text, optional progress 0…1. */
export function setActivity(text, { busy = false, error = false, progress = null, hint = "" } = {}) {
  const box = document.getElementById("activity");
  box.title = hint;
  box.classList.toggle("busy", busy);
  box.classList.toggle("error", error);
  document.getElementById("activity-spinner").hidden = !busy;
  document.getElementById("activity-text").textContent = text;
  const bar = document.getElementById("upload-progress");
  bar.hidden = progress == null;
  if (progress != null) bar.value = progress;
}

/** Debounce: run fn `ms` after the last call. `.flush()` runs a pending call now. */
export function debounce(fn, ms) {
  let timer = null;
  let lastArgs = [];
  const run = () => {
    timer = null;
    return fn(...lastArgs);
  };
  const wrapped = (...args) => {
    lastArgs = args;
    clearTimeout(timer);
    timer = setTimeout(run, ms);
  };
  wrapped.cancel = () => {
    clearTimeout(timer);
    timer = null;
  };
  wrapped.flush = () => (timer ? (clearTimeout(timer), run()) : undefined);
  wrapped.pending = () => timer !== null;
  return wrapped;
}

/** Read a chosen file as text: UTF-8, else Windows-1252 (the controller era's encoding). */
export async function readTextFile(file) {
  const bytes = await file.arrayBuffer();
  try {
    return new TextDecoder("utf-8", { fatal: true }).decode(bytes);
  } catch {
    return new TextDecoder("windows-1252").decode(bytes);
  }
}

/** True when `name` ends with `.ext` (any case). */
export function hasExtension(name, ext) {
  return name.toLowerCase().endsWith("." + ext.toLowerCase());
}
