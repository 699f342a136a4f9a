// The IDE's state, a small store per concern instead of one global bag: who is signed in,
// the robot as the socket last told it, who holds control, what this browser loaded, and
// the activity line. A store holds one frozen value; `set` replaces it and tells the views
// that follow it. Components read stores; only the part that owns a concern writes it.

export class Store {
  constructor(value) {
    this.value = Object.freeze(value);
    this.listeners = new Set();
  }

  get() {
    return this.value;
  }

  /** Replace fields of the value (a new frozen value) and tell every listener. */
  set(patch) {
    const previous = this.value;
    this.value = Object.freeze({ ...previous, ...patch });
    for (const listener of this.listeners) listener(this.value, previous);
  }

  /** Follow the value; returns the function that stops following. */
  subscribe(listener) {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }
}

/** Who is signed in (set once, from GET /api/session). */
export const session = new Store({ user: "", role: "" });

/**
 * The robot of the current target: the latest `state` message, whether it is a simulated
 * one (the hello says), and whether the debugger's arm or a recorded run's replay owns the
 * 3D view (and the editor's running line).
 */
export const robot = new Store({ state: null, virtual: null, debugging: false, replay: false });

/**
 * Who holds control, since when, and their connection (`lease` messages and snapshots);
 * `queued`: someone waits in the lab robot's queue, so only the queue gives control (the
 * queue's panel says so).
 */
export const lease = new Store({ holder: null, since: null, state: null, queued: false });

/**
 * The activity line of the toolbar: one owner at a time. `task` is an operation of this
 * browser in progress ({kind, text, progress}: a load, a move, a pre-flight) and owns the
 * line; `result` is how the last one ended ({text, error}), shown until the robot does
 * something else. Neither: the robot's own activity is shown.
 */
export const activityLine = new Store({ task: null, result: null });

/** An operation of this browser starts (or moves on): it owns the activity line. */
export function startTask(kind, text, progress = null) {
  activityLine.set({ task: { kind, text, progress }, result: null });
}

/**
 * The operation ended: its result ({text, error}, a full bar with `progress` 1) stays until
 * the robot does something else ("Idle": no result to keep). `at` is what the robot was
 * doing then (its activity and detail): while that stays, so does the result.
 */
export function endTask(text = "Idle", error = false, progress = null) {
  const m = robot.get().state;
  const at = `${m?.activity ?? ""}|${m?.activity_detail ?? ""}`;
  activityLine.set({ task: null, result: text === "Idle" ? null : { text, error, progress, at } });
}

/**
 * What this browser loaded on the robot: the program text, its step -> line map (the load
 * reply's `step_lines`) and its fingerprint (the state's `slot` names it while the slot
 * holds it), kept in localStorage so a reload still marks the running line; sign-out
 * forgets it (a shared lab PC keeps no program text).
 */
export class LoadedProgram extends Store {
  constructor() {
    super({ program: null, lines: {}, fingerprint: null });
    this.key = null;
  }

  /** Read what this user loaded before (after sign-in). */
  restore(user) {
    this.key = `melfa.loaded.${user}`;
    try {
      const saved = JSON.parse(localStorage.getItem(this.key) || "null");
      if (saved) this.set({ program: saved.program, lines: saved.lines || {}, fingerprint: saved.fingerprint ?? null });
    } catch { /* unreadable: nothing known */ }
  }

  remember(program, lines, fingerprint = null) {
    this.set({ program, lines: lines || {}, fingerprint });
    if (!this.key) return; // signed out: an answer still on its way keeps nothing
    try {
      localStorage.setItem(this.key, JSON.stringify(this.get()));
    } catch { /* storage full: the highlight just will not survive a reload */ }
  }

  /** Signing out: the text leaves this browser's storage. */
  forget() {
    this.set({ program: null, lines: {}, fingerprint: null });
    try {
      if (this.key) localStorage.removeItem(this.key);
    } catch { /* storage unavailable: nothing kept either */ }
    this.key = null;
  }

  /** The editor's line of a controller step, when `text` is what was loaded. */
  lineOf(step, text) {
    const { program, lines } = this.get();
    if (program === null || program !== text) return null;
    return lines[String(step)] ?? null;
  }
}

export const loaded = new LoadedProgram();
