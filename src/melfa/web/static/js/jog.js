// The robot control tab: the thesis's keyboard jog on a canvas that lights the pressed keys.
// Hold-to-move rides on the WebSocket: `jog_start` on key down, `jog_heartbeat` every 80 ms
// while held, `jog_release` on key up, on blur and when the tab is hidden. Only one key
// moves at a time and nothing is queued: a key let go stops at once, even if its start is
// still on the way. Step mode sends one increment per press (REST jog-step).

import { api } from "./api.js";
import { describeActivity, directionWords, jogEndExpected, jogEndWords } from "./activity.js";
import { motionBody } from "./fixes.js";
import { $, showError, toast } from "./ui.js";
import { JOINT_NAMES, POSE_NAMES } from "/model/controller.js"; // generated from melfa.protocol

const HEARTBEAT_MS = 80;
// key → [axis offset within the group, direction]; w/s ±X, a/d ±Y, up/down ±Z (thesis 6.8).
const KEYS = {
  w: { slot: 0, dir: 1, label: "W" },
  s: { slot: 0, dir: -1, label: "S" },
  a: { slot: 1, dir: 1, label: "A" },
  d: { slot: 1, dir: -1, label: "D" },
  ArrowUp: { slot: 2, dir: 1, label: "↑" },
  ArrowDown: { slot: 2, dir: -1, label: "↓" },
  " ": { hand: true, label: "Space" },
};
const AXIS_NAMES = { xyz: POSE_NAMES, tool: POSE_NAMES, joint: JOINT_NAMES };

export class JogPad {
  constructor(app) {
    this.app = app;
    this.canvas = $("jog-canvas");
    this.ctx = this.canvas.getContext("2d");
    this.held = null; // the key moving the arm
    this.lit = new Set(); // keys drawn pressed
    this.heartbeat = null;
    this.stepping = false;
    this.layout = this.computeLayout();

    const keyName = (e) => (e.key.length === 1 ? e.key.toLowerCase() : e.key);
    this.canvas.addEventListener("keydown", (e) => {
      const key = keyName(e);
      if (!(key in KEYS)) return;
      e.preventDefault(); // arrows and space must not scroll
      if (e.repeat) return; // the heartbeat keeps it alive, not the key repeat
      this.press(key);
    });
    this.canvas.addEventListener("keyup", (e) => {
      const key = keyName(e);
      if (key in KEYS) {
        e.preventDefault();
        this.releaseKey(key);
      }
    });
    this.canvas.addEventListener("blur", () => this.releaseAll("blur"));
    this.canvas.addEventListener("focus", () => this.draw());
    document.querySelectorAll('input[name="jog-mode"]').forEach((r) => r.addEventListener("change", () => {
      this.releaseAll("mode changed");
      this.draw();
    }));
    window.addEventListener("blur", () => this.releaseAll("window blur"));
    document.addEventListener("visibilitychange", () => {
      if (document.visibilityState === "hidden") this.releaseAll("hidden");
    });
    // Mouse / touch on the drawn keys.
    this.canvas.addEventListener("pointerdown", (e) => {
      const key = this.keyAt(e);
      this.canvas.focus();
      if (!key) return;
      e.preventDefault();
      this.canvas.setPointerCapture(e.pointerId);
      this.pointerKey = key;
      this.press(key);
    });
    const pointerUp = () => {
      if (this.pointerKey) this.releaseKey(this.pointerKey);
      this.pointerKey = null;
    };
    this.canvas.addEventListener("pointerup", pointerUp);
    this.canvas.addEventListener("pointercancel", pointerUp);

    $("jog-frame").addEventListener("change", () => {
      this.releaseAll("frame changed");
      $("joint-group-label").hidden = $("jog-frame").value !== "joint";
      this.app.view?.setFrame(this.frame);
      this.draw();
    });
    $("jog-joints").addEventListener("change", () => this.draw());
    const speed = $("jog-speed");
    speed.addEventListener("input", () => ($("jog-speed-out").textContent = `${speed.value} %`));
    app.live.on("jog", (m) => {
      // Why it ended comes as a code (`end`); letting the key go needs no word, and a
      // refusal is told by the error reply of the jog_start.
      if (!m.active && this.held && m.actor?.user === app.user && m.end && !jogEndExpected(m.end) && m.end !== "refused") {
        toast("Jog stopped", { kind: "warning", text: jogEndWords(m.end, m.by) });
        this.stopHeartbeat();
        this.held = null;
        this.lit.clear();
        this.draw();
      }
    });
    this.draw();
  }

  /** The server's jog override ceiling caps the speed slider. */
  setCeiling(ceiling) {
    const speed = $("jog-speed");
    speed.max = String(ceiling);
    if (Number(speed.value) > ceiling) speed.value = String(ceiling);
    $("jog-speed-out").textContent = `${speed.value} %`;
    speed.title = `The server caps jog speed at ${ceiling} %`;
  }

  get frame() {
    return $("jog-frame").value;
  }

  get mode() {
    return document.querySelector('input[name="jog-mode"]:checked').value;
  }

  /** Axis index (0–5) and label for a movement key in the current frame. */
  axisOf(key) {
    const spec = KEYS[key];
    const base = this.frame === "joint" ? Number($("jog-joints").value) : 0;
    const axis = base + spec.slot;
    return { axis, label: AXIS_NAMES[this.frame][axis], dir: spec.dir };
  }

  async press(key) {
    this.lit.add(key);
    this.draw();
    const spec = KEYS[key];
    if (spec.hand) {
      try {
        const ack = await this.app.live.request({ type: "hand_toggle", hand: 1 });
        this.app.view.setHand(ack.open);
      } catch (err) {
        showError("Could not open or close the hand", err);
      }
      return;
    }
    if (this.mode === "step") return this.step(key);
    if (this.held && this.held !== key) this.stopJog(); // one axis at a time
    this.held = key;
    const { axis, dir } = this.axisOf(key);
    await this.applySpeed();
    if (this.held !== key) return; // let go while the speed was being set
    this.startHeartbeat();
    try {
      await this.app.live.request({ type: "jog_start", frame: this.frame, axis, direction: dir, ...motionBody() });
    } catch (err) {
      if (this.held === key) {
        this.stopHeartbeat();
        this.held = null;
        this.lit.delete(key);
        this.draw();
      }
      // The fix switches the servo on; the student presses the key again to move.
      showError("Could not jog", err, { retry: () => api("POST", "/api/robot/servo", { on: true }) });
      return;
    }
    // Released before the start was acknowledged: make sure it stops now.
    if (this.held !== key) this.app.live.send({ type: "jog_release" });
  }

  async step(key) {
    if (this.stepping) return; // never queue a move behind another
    this.stepping = true;
    const { axis, dir } = this.axisOf(key);
    try {
      await this.applySpeed();
      await api("POST", "/api/robot/jog-step", { frame: this.frame, axis, direction: dir, ...motionBody() });
    } catch (err) {
      const retry = (extra) => api("POST", "/api/robot/jog-step", { frame: this.frame, axis, direction: dir, ...extra });
      if (err.code !== "jog-busy") showError("Could not step", err, { retry });
    } finally {
      this.stepping = false;
    }
  }

  /** Jog speed = the OP override while jogging (the server caps it at its ceiling). */
  async applySpeed() {
    const want = Number($("jog-speed").value);
    if (this.app.state?.override === want) return;
    try {
      await api("POST", "/api/robot/override", { percent: want });
    } catch {
      /* the jog still runs at the server's capped override */
    }
  }

  releaseKey(key) {
    this.lit.delete(key);
    this.draw();
    if (this.held === key) this.stopJog();
  }

  releaseAll() {
    this.lit.clear();
    this.draw();
    if (this.held) this.stopJog();
  }

  stopJog() {
    this.held = null;
    this.stopHeartbeat();
    this.app.live.send({ type: "jog_release" });
  }

  startHeartbeat() {
    this.stopHeartbeat();
    this.heartbeat = setInterval(() => {
      if (!this.held || !this.app.live.send({ type: "jog_heartbeat" })) this.stopHeartbeat();
    }, HEARTBEAT_MS);
  }

  stopHeartbeat() {
    clearInterval(this.heartbeat);
    this.heartbeat = null;
  }

  // ---- drawing ----
  computeLayout() {
    // Keys laid out like a keyboard: WASD on the left, arrows in the middle, space below.
    const k = 64;
    const g = 10;
    const x0 = 34;
    const y0 = 26;
    return {
      w: [x0 + k + g, y0, k, k],
      a: [x0, y0 + k + g, k, k],
      s: [x0 + k + g, y0 + k + g, k, k],
      d: [x0 + 2 * (k + g), y0 + k + g, k, k],
      ArrowUp: [x0 + 3 * (k + g) + 44, y0, k, k],
      ArrowDown: [x0 + 3 * (k + g) + 44, y0 + k + g, k, k],
      " ": [x0, y0 + 2 * (k + g) + 6, 3 * k + 2 * g + 44 + k + g, 50],
    };
  }

  keyAt(event) {
    const rect = this.canvas.getBoundingClientRect();
    const x = ((event.clientX - rect.left) * this.canvas.width) / rect.width;
    const y = ((event.clientY - rect.top) * this.canvas.height) / rect.height;
    for (const [key, [kx, ky, kw, kh]] of Object.entries(this.layout)) {
      if (x >= kx && x <= kx + kw && y >= ky && y <= ky + kh) return key;
    }
    return null;
  }

  draw() {
    this.canvas.dataset.lit = [...this.lit].join(",");
    const labels = {};
    const said = describeActivity(this.app.state, this.app.lineOf);
    this.shownActivity = said.text;
    this.shownHand = this.app.state?.hands?.[0];
    const ctx = this.ctx;
    const { width, height } = this.canvas;
    ctx.clearRect(0, 0, width, height);
    ctx.font = "600 20px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    for (const [key, [x, y, w, h]] of Object.entries(this.layout)) {
      const on = this.lit.has(key);
      ctx.fillStyle = on ? "#1f5fbf" : "#ffffff";
      ctx.strokeStyle = on ? "#194f9f" : "#b8c1cc";
      ctx.lineWidth = 1.5;
      roundRect(ctx, x, y + (on ? 2 : 0), w, h, 8);
      ctx.fill();
      ctx.stroke();
      if (!on) {
        ctx.fillStyle = "#d5dbe3";
        ctx.fillRect(x + 6, y + h - 3, w - 12, 3);
      }
      ctx.fillStyle = on ? "#ffffff" : "#1d2733";
      const spec = KEYS[key];
      ctx.font = "600 19px system-ui, sans-serif";
      const dy = on ? 2 : 0;
      ctx.fillText(spec.label, x + w / 2, y + (spec.hand ? h / 2 - 6 : 17) + dy);
      ctx.font = "500 12px system-ui, sans-serif";
      ctx.fillStyle = on ? "#dbe8ff" : "#4b5563";
      if (spec.hand) {
        const open = this.app.state?.hands?.[0];
        ctx.fillText(open == null ? "hand 1" : open ? "hand 1 is open: close" : "hand 1 is closed: open", x + w / 2, y + h - 9);
      } else {
        const { axis, label, dir } = this.axisOf(key);
        ctx.fillText(`${dir > 0 ? "+" : "−"}${label}`, x + w / 2, y + 37 + dy);
        // Where the hand really goes in this frame (tool axes turn with the hand).
        const words = directionWords(this.frame, axis, dir, this.app.state?.pose);
        ctx.font = "500 10px system-ui, sans-serif";
        if (words) ctx.fillText(words.length > 11 ? words.replace(" and ", "+") : words, x + w / 2, y + 53 + dy);
        labels[key] = `${dir > 0 ? "+" : "-"}${label}${words ? " " + words : ""}`;
      }
    }
    this.canvas.dataset.labels = JSON.stringify(labels);
    // Legend on the right.
    ctx.textAlign = "left";
    ctx.fillStyle = "#5f6b7a";
    ctx.font = "500 13px system-ui, sans-serif";
    const lx = 392;
    const frameName = { xyz: "Base XYZ", tool: "Tool", joint: "Joint" }[this.frame];
    ctx.fillText(`Frame: ${frameName}`, lx, 40);
    ctx.fillText(`Mode: ${this.mode === "step" ? "step" : "hold to move"}`, lx, 62);
    // What the robot does, as the service says it (the same words as the header), in a
    // line of text above the keys: read by screen readers, never cut to fit.
    this.canvas.dataset.activity = said.text;
    const line = $("jog-state");
    if (line) {
      $("jog-state-text").textContent = said.text;
      line.title = said.hint || "";
      line.dataset.kind = said.error ? "error" : said.busy ? "busy" : "idle";
    }
    if (document.activeElement !== this.canvas) {
      ctx.fillStyle = "#8a96a3";
      ctx.font = "400 12px system-ui, sans-serif";
      ctx.fillText("Click to use the keys", lx, 96);
    }
  }
}

function roundRect(ctx, x, y, w, h, r) {
  ctx.beginPath();
  ctx.moveTo(x + r, y);
  ctx.arcTo(x + w, y, x + w, y + h, r);
  ctx.arcTo(x + w, y + h, x, y + h, r);
  ctx.arcTo(x, y + h, x, y, r);
  ctx.arcTo(x, y, x + w, y, r);
  ctx.closePath();
}
