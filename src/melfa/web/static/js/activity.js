// One truth for what the robot does: the service's `activity` word (docs/api.md "state"),
// told the same way by the header pill, the activity line, the jog pad and the 3D view.
// And the words for a jog direction in each frame: which way the hand really goes.

/**
 * {text, pill, busy, error, hint} for a state message. `lineOf(step)` maps the controller's
 * step number to the editor's line when this browser knows the loaded text (then the words
 * name the line the editor marks); otherwise the step number of the loaded .MB4 is said.
 */
export function describeActivity(m, lineOf = null) {
  let detail = m?.activity_detail || "";
  const line = (m?.activity === "running" || m?.activity === "paused") && m.line && lineOf ? lineOf(m.line) : null;
  if (line) detail = `line ${line}`;
  const program = m?.program ? ` ${m.program}` : "";
  switch (m?.activity) {
    case "uploading": return { text: "Uploading…", pill: "uploading", busy: true };
    case "alarm": return { text: `Alarm ${m.alarm?.code || m.alarm?.number || ""}`.trim(), pill: "alarm", error: true };
    case "jogging": return { text: `Jogging${detail ? " " + jogWords(detail) : ""}`, pill: "jogging", busy: true };
    case "moving-to": return { text: `Moving to ${detail || "a point"}`, pill: "moving", busy: true };
    case "running": return { text: `Running${program}${detail ? " · " + detail : ""}`, pill: `running${detail ? " · " + detail : ""}`, busy: true };
    case "paused": return { text: `Paused${detail ? " at " + detail : ""}`, pill: "paused", hint: "Run continues; Reset program starts over" };
    case "moving": return { text: "Robot moving", pill: "moving", busy: true };
    case "offline": return { text: "Robot not connected", pill: "offline", error: true };
    default: return { text: "Idle", pill: "idle" };
  }
}

function jogWords(label) {
  // "xyz X+" → "X+ (base)"; "tool Z-" → "Z- (tool)"; "joint J3+" → "J3+".
  const [frame, axis] = label.split(" ");
  return frame === "joint" ? axis : `${axis} (${frame === "tool" ? "tool" : "base"})`;
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
