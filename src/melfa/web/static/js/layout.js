// Narrow windows (1024 px and up): when the toolbar's row does not fit, its secondary
// actions move into a "More" menu, lowest priority first, and come back when there is room
// (the priority+ pattern). The buttons themselves move, so their ids, handlers, titles and
// accessible names stay. Measured, not guessed: the row is re-fitted whenever the toolbar
// or the activity text changes size.

export class ToolbarOverflow {
  /**
   * `bar`: the toolbar; `wrap`: the More button's box (hidden when unused); `button`, `menu`:
   * the More button and its list; `ids`: the movable buttons, lowest priority first.
   */
  constructor(bar, { wrap, button, menu, ids }) {
    this.bar = bar;
    this.wrap = wrap;
    this.button = button;
    this.menu = menu;
    // Each button remembers its place in the row by a marker left before it.
    this.items = ids.map((id) => document.getElementById(id)).filter(Boolean).map((node) => {
      const home = document.createComment(`${node.id} lives here`);
      node.before(home);
      return { node, home };
    });
    this.lastKey = "";
    this.scheduled = false;
    this.wireMenu();
    const observer = new ResizeObserver(() => this.schedule());
    for (const node of [bar, ...bar.querySelectorAll("#activity, #save-state")]) observer.observe(node);
    this.fit();
  }

  /** Buttons now in the More menu (for tests and the guide). */
  get moved() {
    return this.items.filter(({ node }) => this.menu.contains(node)).map(({ node }) => node.id);
  }

  schedule() {
    if (this.scheduled) return;
    this.scheduled = true;
    requestAnimationFrame(() => {
      this.scheduled = false;
      if (this.sizeKey() === this.lastKey) return; // our own moves settle here
      this.fit();
      this.lastKey = this.sizeKey();
    });
  }

  sizeKey() {
    return [this.bar.clientWidth, ...[...this.bar.querySelectorAll("#activity, #save-state")].map((n) => n.scrollWidth)].join(",");
  }

  /** One row: nothing spills sideways and nothing wrapped under the first item. */
  fits() {
    if (this.bar.scrollWidth > this.bar.clientWidth + 1) return false;
    const row = [...this.bar.children].filter((n) => !n.hidden && n.offsetParent !== null && !n.classList.contains("debug-bar"));
    if (!row.length) return true;
    const first = row[0].getBoundingClientRect();
    return row.every((n) => {
      const r = n.getBoundingClientRect();
      const middle = (r.top + r.bottom) / 2;
      return middle >= first.top && middle <= first.bottom;
    });
  }

  fit() {
    this.close();
    for (const { node, home } of this.items) home.after(node);
    this.wrap.hidden = true;
    if (this.fits()) return;
    this.wrap.hidden = false;
    for (const { node } of this.items) {
      this.menu.append(node);
      if (this.fits()) break;
    }
  }

  // ---- the menu: a button that opens a list of the moved buttons ----
  wireMenu() {
    this.button.addEventListener("click", () => (this.menu.hidden ? this.open() : this.close()));
    this.menu.addEventListener("click", (e) => {
      if (e.target.closest("button")) this.close();
    });
    this.menu.addEventListener("keydown", (e) => {
      const buttons = [...this.menu.querySelectorAll("button:not([disabled])")];
      const i = buttons.indexOf(document.activeElement);
      if (e.key === "Escape") {
        e.stopPropagation();
        this.close();
        this.button.focus();
      } else if (e.key === "ArrowDown" || e.key === "ArrowUp") {
        e.preventDefault();
        const step = e.key === "ArrowDown" ? 1 : buttons.length - 1;
        buttons[(i + step) % buttons.length]?.focus();
      }
    });
    document.addEventListener("click", (e) => {
      if (!this.wrap.contains(e.target)) this.close();
    });
  }

  open() {
    this.menu.hidden = false;
    this.button.setAttribute("aria-expanded", "true");
    this.menu.querySelector("button:not([disabled])")?.focus();
  }

  close() {
    this.menu.hidden = true;
    this.button.setAttribute("aria-expanded", "false");
  }
}
