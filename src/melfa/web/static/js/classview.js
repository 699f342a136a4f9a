// The instructor's page (/classroom, docs/ide.md "The class view"): publish an assignment
// folder (a zip or its files, checked by the server before anything is stored), and per
// assignment one row per student — variant, latest check, best submission, submissions and
// attempts left, time since the last save, pre-flight — with filters, CSV export, and a
// student's workspace opened read-only with its history, each revision's diff against the
// one before, and their reports. The words it fills in come from /vocab.js
// (melfa.vocab.classroom); the page's fixed labels are in static/classroom.html.

import { api } from "./api.js";
import { signedIn } from "./page.js";
import { lineDiff } from "./opener.js";
import { $, el, readTextFile, showError, toast } from "./ui.js";
import { CLASS_COLUMNS, CLASS_FILTERS, CLASS_VIEW_WORDS as W, GRADE_WORDS, PANE_WORDS, RESULT_WORDS, VISIT_WORDS } from "/vocab.js"; // melfa.vocab.classroom, .desk
import { dueWords, fill } from "./assign.js";

const REFRESH_MS = 10_000;
const state = { assignments: [], selected: null, view: null, folder: null, student: null };

/** "4 min ago", from the server's own clock (`now` of the reply). */
export function ago(iso, nowIso) {
  if (!iso) return "—";
  const s = Math.max(0, (new Date(nowIso) - new Date(iso)) / 1000);
  if (s < 60) return W["just-now"];
  if (s < 3600) return fill(W["minutes-ago"], { n: Math.floor(s / 60) });
  if (s < 86400) return fill(W["hours-ago"], { n: Math.floor(s / 3600) });
  return fill(W["days-ago"], { n: Math.floor(s / 86400) });
}

function result(g, opened) {
  if (!g) return el("span", { class: "muted" }, RESULT_WORDS[opened ? "none" : "not-opened"]);
  return el("span", { class: `verdict ${g.passed ? "pass" : "fail"}`, title: W["score-hint"] }, g.summary);
}

function flight(g) {
  if (!g || g.preflight == null) return el("span", { class: "muted" }, RESULT_WORDS.unknown);
  return el("span", { class: `verdict ${g.preflight ? "pass" : "fail"}` }, RESULT_WORDS[g.preflight ? "preflight-ok" : "preflight-failed"]);
}

async function main() {
  const session = await signedIn("cv-user");
  if (!session) return;
  $("cv-filter").replaceChildren(...Object.entries(CLASS_FILTERS).map(([value, w]) => el("option", { value, title: w.hint }, w.label)));
  $("cv-filter").addEventListener("change", () => loadView());
  $("cv-columns").replaceChildren(...Object.values(CLASS_COLUMNS).map((w) => el("th", { scope: "col" }, w)), el("th", { scope: "col" }, el("span", { class: "sr-only" }, W.open)));
  $("cv-publish").addEventListener("click", () => openPublish());
  $("cv-student-close").addEventListener("click", () => closeStudent());
  wirePublish();
  await loadList();
  const wanted = Number(new URLSearchParams(location.hash.slice(1)).get("a"));
  const first = state.assignments.find((a) => a.id === wanted) || state.assignments[0];
  if (first) await select(first.id);
  setInterval(() => { if (!document.hidden && state.selected) loadView(true); }, REFRESH_MS);
  document.body.dataset.ready = "true";
}

async function loadList() {
  state.assignments = (await api("GET", "/api/assignments")).assignments;
  $("cv-empty").hidden = state.assignments.length > 0;
  $("cv-list").replaceChildren(...state.assignments.map((a) => {
    const item = el("li", {}, el("button", { type: "button", class: "cv-item", "data-id": String(a.id), "aria-current": String(a.id === state.selected) },
      el("strong", {}, a.title),
      el("span", { class: "muted" }, [a.group ? fill(W.group, { group: a.group }) : W["whole-class"], dueWords(a.due)].filter(Boolean).join(" · "))));
    item.querySelector("button").addEventListener("click", () => select(a.id));
    return item;
  }));
}

async function select(id) {
  state.selected = id;
  history.replaceState(null, "", `#a=${id}`);
  for (const b of document.querySelectorAll(".cv-item")) b.setAttribute("aria-current", String(Number(b.dataset.id) === id));
  closeStudent();
  await loadView();
}

function closeStudent() {
  $("cv-student").hidden = true;
  document.querySelector(".cv-layout").classList.remove("reading");
  state.student = null;
}

async function loadView(quiet = false) {
  const id = state.selected;
  const which = $("cv-filter").value;
  let view;
  try {
    view = await api("GET", `/api/assignments/${id}/class?filter=${encodeURIComponent(which)}`);
  } catch (err) {
    if (!quiet) showError(W["view-failed"], err);
    return;
  }
  state.view = view;
  const a = view.assignment;
  $("cv-title").textContent = a.title;
  $("cv-meta").textContent = [a.group ? fill(W["for-group"], { group: a.group }) : W["for-whole-class"], dueWords(a.due), a.attempts == null ? RESULT_WORDS["attempts-unlimited-all"] : fill(RESULT_WORDS["attempts-each"], { total: a.attempts }), a.variants ? W["variants-on"] : "", fill(W["published-by"], { author: a.author })].filter(Boolean).join(" · ");
  $("cv-csv").href = `/api/assignments/${id}/class.csv?filter=${encodeURIComponent(which)}`;
  $("cv-zip").href = `/api/assignments/${id}/export`;
  $("cv-none").hidden = view.rows.length > 0;
  $("cv-rows").replaceChildren(...view.rows.map((r) => row(r, view.now)));
  $("cv-main").dataset.rows = String(view.rows.length);
}

function row(r, now) {
  const opened = r.opened != null;
  const open = el("button", { type: "button", class: "btn btn-sm", disabled: !opened, "aria-label": fill(W["open-label"], { student: r.student }) }, W.open);
  open.addEventListener("click", () => openStudent(r));
  const cells = {
    student: el("span", {}, el("strong", {}, r.display_name || r.student), r.display_name && r.display_name !== r.student ? el("span", { class: "muted" }, ` ${r.student}`) : null,
      r.stuck ? el("span", { class: "pill warn", title: CLASS_FILTERS.stuck.hint }, CLASS_FILTERS.stuck.label) : null),
    group: r.group || "—",
    variant: r.seed == null ? "—" : String(r.seed),
    latest: el("span", { title: r.latest ? `${GRADE_WORDS[r.latest.kind]}, ${ago(r.latest.at, now)}` : "" }, result(r.latest, opened)),
    best: r.best ? result(r.best, opened) : el("span", { class: "muted" }, "—"),
    attempts: r.attempts_left == null ? String(r.submissions) : fill(W.attempts, { submissions: r.submissions, left: r.attempts_left }),
    "last-saved": ago(r.last_saved, now),
    preflight: flight(r.latest),
    ran: r.ran_on_arm ? fill(W[r.ran_on_arm === 1 ? "runs-one" : "runs-many"], { n: r.ran_on_arm }) : el("span", { class: "muted" }, "—"),
  };
  return el("tr", { "data-student": r.student, class: r.stuck ? "stuck" : "" },
    ...Object.keys(CLASS_COLUMNS).map((k) => el("td", { "data-column": k }, cells[k])), el("td", {}, open));
}

// --- a student's work, read-only ------------------------------------------------------------

async function openStudent(r) {
  state.student = r;
  $("cv-student").hidden = false;
  document.querySelector(".cv-layout").classList.add("reading");
  $("cv-student-name").textContent = `${r.display_name || r.student} · ${state.view.assignment.title}`;
  $("cv-open-editor").textContent = VISIT_WORDS["open-in-editor"];
  $("cv-open-editor").href = `/?workspace=${r.workspace_id}`; // read-only there too
  try {
    const [revs, grades] = await Promise.all([
      api("GET", `/api/workspaces/${r.workspace_id}/revisions?limit=200`),
      api("GET", `/api/assignments/${state.selected}/history?student=${encodeURIComponent(r.student)}`),
    ]);
    const list = revs.revisions;
    $("cv-revisions").replaceChildren(...list.map((v, i) => {
      const b = el("button", { type: "button", class: "linkish", "data-number": String(v.number) }, fill(W.revision, { number: v.number }));
      b.addEventListener("click", () => showRevision(r, v.number, list[i + 1]?.number ?? null));
      return el("li", {}, b, el("span", { class: "muted" }, ` ${v.reason} · ${ago(v.created, state.view.now)}`));
    }));
    $("cv-gradings").replaceChildren(...grades.gradings.map((g) => {
      const b = el("button", { type: "button", class: "linkish", "data-grading": String(g.id) }, fill(W.graded, { kind: GRADE_WORDS[g.kind], revision: g.revision }));
      b.addEventListener("click", () => showReport(g.id));
      return el("li", {}, b, " ", result(g, true), el("span", { class: "muted" }, ` ${ago(g.at, state.view.now)}`));
    }));
    $("cv-report").replaceChildren();
    if (list.length) await showRevision(r, list[0].number, list[1]?.number ?? null);
  } catch (err) {
    showError(W["work-failed"], err);
  }
}

let shown = 0; // the newest revision asked for: an older answer arriving late is dropped

async function showRevision(r, number, previous) {
  const asked = ++shown;
  const get = (n) => api("GET", `/api/workspaces/${r.workspace_id}/revisions/${n}`);
  const [now, before] = await Promise.all([get(number), previous ? get(previous) : null]);
  if (asked !== shown) return;
  const lines = before ? lineDiff(before.program, now.program) : now.program.split("\n").map((text) => ({ op: " ", text }));
  const changed = lines.filter((l) => l.op !== " ").length;
  const count = changed === 1 ? W["lines-one"] : fill(W["lines-many"], { n: changed });
  $("cv-diff-note").textContent = before ? fill(W.diff, { number, previous, lines: count }) : fill(W["first-revision"], { number });
  let line = 0;
  const digits = Math.max(3, String(lines.length).length);
  // Number, mark and a space before each line's text: the wrapped rest of a long line hangs
  // below its text (app.css .program-lines).
  $("cv-program").style.setProperty("--gutter", `${digits + 3}ch`);
  $("cv-program").replaceChildren(...lines.map((l) => {
    if (l.op !== "-") line += 1;
    return el("span", { class: l.op === "+" ? "add" : l.op === "-" ? "del" : "same" }, `${l.op === "-" ? " ".repeat(digits) : String(line).padStart(digits)} ${l.op} ${l.text}\n`);
  }));
  for (const b of document.querySelectorAll("#cv-revisions button")) b.setAttribute("aria-current", String(Number(b.dataset.number) === number));
}

async function showReport(id) {
  try {
    const out = await api("GET", `/api/assignments/${state.selected}/gradings/${id}`);
    $("cv-report").replaceChildren(...out.report.checks.map((c) => el("li", { class: c.passed ? "pass" : "fail" },
      el("span", { class: "mark", "aria-hidden": "true" }, c.passed ? "✓" : "✗"),
      el("span", { class: "what" }, el("span", {}, c.title), c.passed ? null : el("span", { class: "why" }, c.message)),
      c.line && !c.passed ? el("span", { class: "line" }, fill(PANE_WORDS.line, { line: c.line })) : null)));
    await showRevision(state.student, out.grading.revision, out.grading.revision > 1 ? out.grading.revision - 1 : null);
  } catch (err) {
    showError(W["report-failed"], err);
  }
}

// --- publishing -------------------------------------------------------------------------------

function wirePublish() {
  $("pub-cancel").addEventListener("click", () => $("publish-dialog").close());
  $("pub-zip").addEventListener("change", async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    const form = new FormData();
    form.append("file", file);
    await preview(() => api("POST", "/api/assignments/folder.zip", form));
  });
  $("pub-files").addEventListener("change", async (e) => {
    const files = {};
    for (const f of e.target.files) files[f.webkitRelativePath ? f.webkitRelativePath.split("/").slice(1).join("/") || f.name : f.name] = await readTextFile(f);
    await preview(() => api("POST", "/api/assignments/folder", { files }));
  });
  $("publish-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    if (!state.folder) return;
    const due = $("pub-due").value;
    const attempts = $("pub-attempts").value;
    try {
      const made = await api("POST", "/api/assignments", {
        files: state.folder.files,
        group: $("pub-group").value || null,
        variants: $("pub-variants").checked,
        due: due ? new Date(due).toISOString() : null,
        attempts: attempts ? Number(attempts) : null,
      });
      $("publish-dialog").close();
      toast(W["published-title"], { kind: "ok", text: fill(W[made.group ? "published-group" : "published-class"], { title: made.title, group: made.group }) });
      await loadList();
      await select(made.id);
    } catch (err) {
      const problems = err.detail?.problems;
      $("pub-problems").replaceChildren(...(problems ? problems.map((p) => el("li", {}, `${p.file}${p.where ? ": " + p.where : ""}: ${p.message}`)) : [el("li", {}, err.message)]));
    }
  });
}

async function openPublish() {
  state.folder = null;
  $("publish-form").reset();
  $("pub-ok").disabled = true;
  $("pub-problems").replaceChildren();
  $("pub-preview").replaceChildren(el("p", { class: "muted" }, W["choose-folder"]));
  try {
    const { groups } = await api("GET", "/api/assignments/groups");
    $("pub-group").replaceChildren(el("option", { value: "" }, W["whole-class"]), ...groups.map((g) => el("option", { value: g }, fill(W.group, { group: g }))));
  } catch (err) {
    showError(W["groups-failed"], err);
  }
  $("publish-dialog").showModal();
}

/** Ask the server what the folder holds; show it, or every problem with where it is. */
async function preview(read) {
  let folder;
  try {
    folder = await read();
  } catch (err) {
    $("pub-problems").replaceChildren(el("li", {}, err.message));
    return;
  }
  const ok = folder.problems.length === 0;
  state.folder = ok ? folder : null;
  $("pub-ok").disabled = !ok;
  $("pub-problems").replaceChildren(...folder.problems.map((p) => el("li", {}, `${p.file}${p.where ? ": " + p.where : ""}: ${p.message}`)));
  if (!ok) {
    $("pub-preview").replaceChildren(el("p", { class: "error" }, W["cannot-publish"]));
    return;
  }
  const statement = el("div", { class: "assign-statement pub-statement", tabindex: "0", "aria-label": W.statement });
  statement.innerHTML = folder.statement_html; // rendered by the server; raw HTML escaped there
  $("pub-preview").replaceChildren(
    el("strong", { id: "pub-title" }, folder.title),
    statement,
    el("p", { class: "muted" }, fill(W.checks, { count: folder.checks.length, titles: folder.checks.map((c) => c.title).join("; ") })),
    folder.variants.length ? el("p", { class: "muted" }, fill(W["variant-groups"], { names: folder.variants.join(", ") })) : null);
  $("pub-variants").checked = folder.variants.length > 0;
  $("pub-variants").disabled = folder.variants.length === 0;
  if (folder.attempts) $("pub-attempts").value = String(folder.attempts);
  if (folder.due) $("pub-due").value = new Date(new Date(folder.due).getTime() - new Date().getTimezoneOffset() * 60000).toISOString().slice(0, 16);
}

main();
