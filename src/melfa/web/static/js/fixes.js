// One-click fixes for the errors a student meets (the API names them in `detail.fix`,
// docs/api.md "Student-facing errors"), and the servo rule for moves: the first move
// with the servo off asks ("Turn on and retry"); once the student said yes, every move of
// this browser session asks the server to switch the servo on first (audited there).

import { api } from "./api.js";
import { $, onFix, showError, toast } from "./ui.js";
import { CONTROL_WORDS, IDE_WORDS } from "/vocab.js"; // generated from melfa.vocab.lease, .ide

const SERVO_KEY = "melfa.servo-on-for-moves";

/** The body of a moving request: `servo_on` once the student has agreed. */
export function motionBody(body = {}) {
  return sessionStorage.getItem(SERVO_KEY) === "1" ? { ...body, servo_on: true } : body;
}

/** True when moves switch the servo on by themselves (the jog pad adds it to jog_start). */
export function servoAuto() {
  return sessionStorage.getItem(SERVO_KEY) === "1";
}

/**
 * Run a moving request; on "servo off" the toast offers "Turn on and retry". `call(body)`
 * sends the request with the given extra fields.
 */
export async function moving(what, call, onError = null) {
  try {
    return await call(motionBody());
  } catch (err) {
    if (onError) onError(err);
    showError(what, err, {
      retry: async (extra) => {
        try {
          return await call({ ...motionBody(), ...extra });
        } catch (again) {
          if (onError) onError(again);
          showError(what, again);
        }
      },
    });
    return undefined;
  }
}

/** Register every fix handler; `app` is the IDE's shared state (main.js). */
export function installFixes(app) {
  onFix("servo-on-retry", async ({ retry }) => {
    sessionStorage.setItem(SERVO_KEY, "1"); // asked once: later moves switch it on
    if (retry) await retry({ servo_on: true });
    else await call(() => api("POST", "/api/robot/servo", { on: true }), IDE_WORDS["servo-on-failed"]);
  });
  onFix("reset-alarm", async ({ retry }) => {
    const ok = await call(() => api("POST", "/api/robot/reset-alarm"), IDE_WORDS["reset-alarm-failed"]);
    if (ok) toast(IDE_WORDS["alarm-was-reset"], { kind: "ok", text: IDE_WORDS["alarm-was-reset-text"] });
    if (ok && retry) await retry({});
  });
  onFix("load-project", async () => $("act-load").click());
  onFix("stop", async () => $("estop").click());
  onFix("take-control", async () => {
    await call(() => api("POST", "/api/lease"), CONTROL_WORDS.take_failed);
  });
  onFix("add-point", async ({ err }) => {
    const name = err?.detail?.point;
    if (name && app.points?.addFromRobot) await app.points.addFromRobot(name);
  });
}

async function call(fn, what) {
  try {
    await fn();
    return true;
  } catch (err) {
    showError(what, err);
    return false;
  }
}
