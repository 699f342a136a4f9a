// One truth for what the robot does: the service's `activity` word (docs/api.md "state"),
// told the same way by the header pill, the activity line, the jog pad and the 3D view, in
// the words of the served vocabulary (/vocab.js, generated from melfa.vocab: the desktop
// client reads the same). The codes the server sends are shown, never English parsed.
// And the words for a jog direction in each frame: which way the hand really goes.

import { ACTIVITY, COMMANDS, FRAME_WORDS, JOG_END_UNKNOWN, JOG_ENDS, LINK_UNKNOWN, LINK_WORDS, WHERE_WORDS } from "/vocab.js";

/**
 * {text, pill, busy, error, hint} for a state message, in the words of melfa.vocab (the
 * same sentence the desktop client shows). `lineOf(step)` maps the controller's step
 * number to the editor's line when this browser knows the loaded text (then the words name
 * the line the editor marks); otherwise the step number is said as such.
 */
export function describeActivity(m, lineOf = null) {
  const code = m?.activity in ACTIVITY ? m.activity : "idle";
  const words = ACTIVITY[code];
  return {
    text: said(code, detailOf(code, m, lineOf)),
    pill: words.pill,
    busy: words.tone === "busy",
    error: words.tone === "error",
    hint: words.hint,
  };
}

/** The activity's sentence with its detail, as `melfa.vocab.activity.said` fills it. */
export function said(code, detail = "") {
  const words = ACTIVITY[code] ?? ACTIVITY.idle;
  return detail ? words.said.replace("{detail}", detail) : words.bare;
}

function detailOf(code, m, lineOf) {
  switch (code) {
    case "running":
    case "paused": {
      if (!m.line) return "";
      const line = lineOf ? lineOf(m.line) : null;
      return line ? fill(WHERE_WORDS.line, { line }) : fill(WHERE_WORDS.step, { step: m.line });
    }
    case "jogging": return jogDetail(m.activity_detail || "");
    case "alarm": return m.alarm?.code || (m.alarm?.number != null ? String(m.alarm.number) : "");
    default: return m?.activity_detail || "";
  }
}

/** The service's jog detail ("xyz X+": a frame code and the key) as a student reads it. */
export function jogDetail(detail) {
  const [frame, axis] = detail.split(" ");
  if (!axis) return detail;
  return fill(FRAME_WORDS[frame] ?? "{axis}", { axis });
}

/** Why a jog ended (the `jog` message's `end` code, `by` whom), in the student's words. */
export function jogEndWords(end, by = null) {
  const words = JOG_ENDS[end]?.words ?? JOG_END_UNKNOWN;
  if (!words.includes("{by}")) return words;
  return by ? fill(words, { by }) : words.replace(" by {by}", "").replace("{by} ", "someone ");
}

/** A jog end the student caused themselves (letting the key go): nothing to tell them. */
export function jogEndExpected(end) {
  return !!JOG_ENDS[end]?.expected;
}

/** A command's label (the `result`/`lease` messages' `command` code). */
export function commandLabel(code) {
  return COMMANDS[code]?.label ?? String(code ?? "").replace(/_/g, " ").replace(/^./, (c) => c.toUpperCase());
}

/** The link's state ("connected", "lost" …) in the student's words. */
export function linkWords(status) {
  return LINK_WORDS[status] ?? LINK_UNKNOWN;
}

/** A template's `{placeholders}` filled; one not given stays as it is. */
export function fill(template, values) {
  return template.replace(/\{(\w+)\}/g, (all, key) => (key in values ? String(values[key]) : all));
}

const WORDS = [["forward", "back"], ["left", "right"], ["up", "down"]];

/** Rotation matrix columns for A, B, C in degrees: R = Rz(C)·Ry(B)·Rx(A) (melfa.kin.pose). */
export function toolAxes(pose) {
  const [a, b, c] = pose.slice(3, 6).map((v) => (v * Math.PI) / 180);
  const [ca, sa, cb, sb, cc, sc] = [Math.cos(a), Math.sin(a), Math.cos(b), Math.sin(b), Math.cos(c), Math.sin(c)];
  // Columns of Rz(C)·Ry(B)·Rx(A).
  return [
    [cc * cb, sc * cb, -sb],
    [cc * sb * sa - sc * ca, sc * sb * sa + cc * ca, cb * sa],
    [cc * sb * ca + sc * sa, sc * sb * ca - cc * sa, cb * ca],
  ];
}

/**
 * Where a jog key really moves the hand, in words seen from the robot ("up", "forward and
 * left"): base X/Y/Z are fixed; tool X/Y/Z turn with the hand (from the pose's A, B, C).
 */
export function directionWords(frame, axis, dir, pose) {
  if (frame === "joint" || axis > 2) return "";
  let v = [0, 0, 0];
  if (frame === "tool") {
    if (!pose) return "";
    v = toolAxes(pose)[axis].map((x) => x * dir);
  } else v[axis] = dir;
  const parts = [];
  const order = [0, 1, 2].sort((i, j) => Math.abs(v[j]) - Math.abs(v[i]));
  for (const i of order) {
    if (Math.abs(v[i]) < 0.38) continue; // under ~22°: not worth naming
    parts.push(WORDS[i][v[i] > 0 ? 0 : 1]);
  }
  return parts.slice(0, 2).join(" and ");
}
