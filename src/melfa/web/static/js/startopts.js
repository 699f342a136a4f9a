// "How the run starts" in the debugger panel (docs/ide.md "Debugging"): the
// servo, where the arm starts (as the simulator's stands, at joint angles, or at a position
// in XYZ the server solves to joints), the override and lines for the program's INPUT #.
// Sent as `start` with POST /api/debug; the words come from /vocab.js (melfa.vocab.start),
// the axis names from /model/controller.js. Kept per user in this browser.

import { el } from "./ui.js";
import { START_PLACE, START_SERVO, START_WORDS as W } from "/vocab.js"; // generated from melfa.vocab
import { JOINT_NAMES, OVERRIDE_PERCENT, POSE_NAMES } from "/model/controller.js"; // generated from melfa.protocol

const DEFAULTS = { servo: "as-it-is", place: "as-it-stands", joints: [0, 0, 90, 0, 90, 0], pose: [400, 0, 645, 180, 0, 180], fl1: 7, fl2: "", override: "", feed: [] };

export class StartOptions {
  constructor(user) {
    this.key = `melfa.start.${user}`;
    let saved = {};
    try { saved = JSON.parse(localStorage.getItem(this.key) || "{}"); } catch { saved = {}; }
    this.state = { ...DEFAULTS, ...saved };
    this.box = this.build();
    this.show();
  }

  build() {
    const choice = (id, label, words, value) => {
      const select = el("select", { id }, ...Object.entries(words).map(([v, t]) => el("option", { value: v }, t)));
      select.value = value;
      select.addEventListener("change", () => this.changed());
      return [el("label", { for: id }, label), select];
    };
    const numbers = (prefix, names, values) => names.map((name, i) => {
      const input = el("input", { type: "number", step: "any", id: `${prefix}-${i}`, value: String(values[i] ?? 0), "aria-label": name, title: name });
      input.addEventListener("change", () => this.changed());
      return el("label", { class: "start-axis" }, el("span", {}, name), input);
    });
    const [servoLabel, servo] = choice("start-servo", W.servo, START_SERVO, this.state.servo);
    const [placeLabel, place] = choice("start-place", W.place, START_PLACE, this.state.place);
    this.servo = servo;
    this.place = place;
    this.jointsRow = el("div", { class: "start-axes", id: "start-joints" }, ...numbers("start-j", JOINT_NAMES, this.state.joints));
    this.fl1 = el("input", { type: "number", min: "0", max: "7", id: "start-fl1", value: String(this.state.fl1), "aria-label": "FL1" });
    this.fl2 = el("input", { type: "number", min: "0", id: "start-fl2", value: String(this.state.fl2), placeholder: "–", "aria-label": "FL2" });
    for (const input of [this.fl1, this.fl2]) input.addEventListener("change", () => this.changed());
    this.poseRow = el("div", { class: "start-axes", id: "start-pose" }, ...numbers("start-p", POSE_NAMES, this.state.pose),
      el("label", { class: "start-axis start-flags" }, el("span", {}, W.flags), this.fl1, this.fl2));
    this.override = el("input", { type: "number", min: String(OVERRIDE_PERCENT.min), max: String(OVERRIDE_PERCENT.max), id: "start-override", value: String(this.state.override), placeholder: W.override_hint, "aria-label": W.override });
    this.override.addEventListener("change", () => this.changed());
    this.feedList = el("div", { class: "start-feed", id: "start-feed" });
    const add = el("button", { type: "button", class: "btn btn-sm", id: "start-feed-add" }, "+ " + W.feed_add);
    add.addEventListener("click", () => { this.addFeed(1, ""); this.changed(); });
    for (const f of this.state.feed) this.addFeed(f.file, f.line);
    this.summary = el("summary", {}, W.title);
    return el("details", { class: "start-opts", id: "start-opts" }, this.summary,
      el("div", { class: "start-grid" }, servoLabel, servo, placeLabel, place),
      this.jointsRow, this.poseRow,
      el("div", { class: "start-grid" }, el("label", { for: "start-override" }, W.override), this.override),
      el("div", { class: "start-feed-head" }, el("span", {}, W.feed), add),
      this.feedList);
  }

  addFeed(file, line) {
    const number = el("input", { type: "number", min: "1", value: String(file), class: "start-feed-file", "aria-label": W.feed_file, title: W.feed_file });
    const text = el("input", { type: "text", maxlength: "127", value: line, class: "start-feed-line", "aria-label": W.feed_line, placeholder: W.feed_line });
    const remove = el("button", { type: "button", class: "btn btn-sm", title: W.feed_remove, "aria-label": W.feed_remove }, "×");
    const row = el("div", { class: "start-feed-row" }, el("span", {}, "#"), number, text, remove);
    remove.addEventListener("click", () => { row.remove(); this.changed(); });
    for (const input of [number, text]) input.addEventListener("change", () => this.changed());
    this.feedList.append(row);
  }

  read() {
    const nums = (prefix, n) => Array.from({ length: n }, (_, i) => Number(document.getElementById(`${prefix}-${i}`)?.value ?? 0));
    const feed = [...this.feedList.querySelectorAll(".start-feed-row")].map((row) => ({
      file: Number(row.querySelector(".start-feed-file").value), line: row.querySelector(".start-feed-line").value,
    }));
    return {
      servo: this.servo.value, place: this.place.value,
      joints: this.box.isConnected ? nums("start-j", 6) : this.state.joints,
      pose: this.box.isConnected ? nums("start-p", 6) : this.state.pose,
      fl1: this.fl1.value, fl2: this.fl2.value, override: this.override.value, feed,
    };
  }

  changed() {
    this.state = this.read();
    try { localStorage.setItem(this.key, JSON.stringify(this.state)); } catch { /* private mode */ }
    this.show();
  }

  show() {
    this.jointsRow.hidden = this.state.place !== "joints";
    this.poseRow.hidden = this.state.place !== "pose";
    const custom = this.state.servo !== "as-it-is" || this.state.place !== "as-it-stands" || this.state.override !== "" || this.state.feed.length > 0;
    this.box.dataset.custom = String(custom);
  }

  /** The `start` of POST /api/debug. */
  spec() {
    const s = this.read();
    const start = { servo: s.servo, place: s.place, feed: s.feed.filter((f) => f.file >= 1) };
    if (s.place === "joints") start.joints = s.joints;
    if (s.place === "pose") {
      const [x, y, z, a, b, c] = s.pose;
      start.pose = { x, y, z, a, b, c, fl1: Number(s.fl1 || 7) };
      if (s.fl2 !== "") start.pose.fl2 = Number(s.fl2);
    }
    if (s.override !== "") start.override = Number(s.override);
    return start;
  }
}
