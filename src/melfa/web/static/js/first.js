// The student's first hour: a clear "Virtual robot" badge, a welcome project for an empty
// workspace (guide.js walks through it), and the keyboard way out of the editor (Esc, then
// Tab), stated on screen. (The workspace's name and sharing: switcher.js.)

import { $, el } from "./ui.js";

/** A clear badge when the robot is the virtual one (no arm moves in the lab); true if virtual. */
export function robotBadge(hello) {
  let badge = $("robot-badge");
  if (!badge) {
    badge = el("span", { id: "robot-badge", class: "robot-badge", role: "note" });
    document.querySelector(".brand").append(badge);
  }
  const virtual = (hello.robot || "").trim() === "sim" || hello.target?.kind === "private";
  badge.textContent = virtual ? "Virtual robot" : "Real robot";
  badge.classList.toggle("real", !virtual);
  badge.title = virtual ? "A simulated RV-6S: nothing moves in the lab." : "The lab's RV-6S: the real arm moves.";
  return virtual;
}

let welcomeFiles = null;
/** The welcome project's [program, points] (fetched once). */
export function welcomeProject() {
  welcomeFiles ??= Promise.all(
    ["welcome.MB4", "welcome.POS"].map((f) => fetch(`/static/welcome/${f}`).then((r) => (r.ok ? r.text() : ""))),
  );
  return welcomeFiles;
}

/** An empty workspace starts with the welcome project (the guide then walks through it). */
export async function welcome(workspace, editor) {
  if (workspace.program.trim() || workspace.points.trim()) return false;
  const id = workspace.id;
  const [program, points] = await welcomeProject();
  // Typed (or switched workspace) while the project was fetched: nothing is replaced.
  if (!program || workspace.id !== id || workspace.program.trim() || workspace.points.trim()) return false;
  workspace.replace({ program, points }, "welcome");
  editor.check();
  return true;
}

const FOCUSABLE = 'a[href], button:not([disabled]), input:not([disabled]):not([type=hidden]), select, textarea, [tabindex]:not([tabindex="-1"])';

/** Esc, then Tab (or Shift+Tab) leaves the editor; the hint under it says so. */
export function keyboardExit(editor) {
  const box = editor.editor.container;
  let armed = false;
  const hint = el("p", { class: "hint editor-hint", id: "editor-hint" },
    "In the editor Tab indents. To leave it with the keyboard press ", el("kbd", {}, "Esc"), " then ", el("kbd", {}, "Tab"), ".");
  box.closest(".editor-wrap").after(hint);
  box.setAttribute("aria-describedby", "editor-hint");
  box.addEventListener("keydown", (e) => {
    if (e.key === "Escape") { armed = true; return; }
    if (e.key === "Tab" && armed) {
      e.preventDefault();
      e.stopPropagation();
      armed = false;
      editor.editor.blur();
      // The next (or previous) focusable control in page order, outside the editor.
      const all = [...document.querySelectorAll(FOCUSABLE)].filter((n) => n.offsetParent !== null && !box.contains(n));
      const after = all.filter((n) => box.compareDocumentPosition(n) & Node.DOCUMENT_POSITION_FOLLOWING);
      const before = all.filter((n) => box.compareDocumentPosition(n) & Node.DOCUMENT_POSITION_PRECEDING);
      (e.shiftKey ? before.at(-1) : after[0])?.focus();
      return;
    }
    if (!["Shift", "Control", "Alt", "Meta"].includes(e.key)) armed = false;
  }, true);
}
