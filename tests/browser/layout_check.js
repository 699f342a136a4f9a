// What is wrong with the IDE's layout now, in words (an empty list when it holds):
// clipped text, wrapped single-line labels, overlapping controls, anything past the
// window's edge, a STOP that is cut, small or outside the window. Called by
// tests/browser/test_layout.py with the CSS selector of the controls to check.
(selector) => {
  const problems = [];
  const vw = window.innerWidth, vh = window.innerHeight;
  if (document.documentElement.scrollWidth > vw + 1) problems.push(`page is ${document.documentElement.scrollWidth} px wide`);
  const shown = (n) => n.getClientRects().length > 0 && getComputedStyle(n).visibility !== 'hidden'
    && !n.closest('[hidden]') && !n.classList.contains('spacer') && !n.classList.contains('sep');
  const name = (n) => '#' + (n.id || n.className || n.tagName) + ' "' + n.textContent.trim().slice(0, 30) + '"';
  const nodes = [...document.querySelectorAll(selector)].filter(shown);
  // Lines of text in a node: its text's boxes, a new line where one starts below the last.
  const lines = (n) => {
    const range = document.createRange();
    range.selectNodeContents(n);
    const rects = [...range.getClientRects()].filter((r) => r.width > 0 && r.height > 0).sort((a, b) => a.top - b.top);
    let count = 0, bottom = -Infinity;
    for (const r of rects) { if (r.top >= bottom - 2) { count++; bottom = r.bottom; } else bottom = Math.max(bottom, r.bottom); }
    return count;
  };
  for (const n of nodes) {
    const r = n.getBoundingClientRect();
    const st = getComputedStyle(n);
    if (st.display !== 'inline' && (n.scrollWidth > n.clientWidth + 1 || n.scrollHeight > n.clientHeight + 1))
      problems.push(`${name(n)} clipped (${n.scrollWidth}x${n.scrollHeight} in ${n.clientWidth}x${n.clientHeight})`);
    if (n.textContent.trim() && lines(n) > 1) problems.push(`${name(n)} wraps onto ${lines(n)} lines`);
    const lh = parseFloat(st.lineHeight) || parseFloat(st.fontSize) * 1.4;
    if (st.display === 'inline' && r.height > lh * 1.6) problems.push(`${name(n)} is ${r.height} px high (line ${lh})`);
    if (r.right > vw + 1 || r.left < -1) problems.push(`${name(n)} outside the window (${r.left}..${r.right})`);
  }
  // No bar whose row spills past its own edge (its controls drawn over the panel's border).
  for (const bar of document.querySelectorAll('.toolbar, .debug-bar, .panel:not([hidden]) .subbar, .view-head')) {
    if (shown(bar) && bar.scrollWidth > bar.clientWidth + 1) problems.push(`${name(bar)} spills (${bar.scrollWidth} px in ${bar.clientWidth})`);
  }
  // No two controls overlap (a control and what it contains are one).
  const boxes = nodes.filter((n) => n.matches('button, select, input, label, .lease-text, .robot-badge, #activity, #save-state, #jog-state, #run-state, h2'));
  for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
    const a = boxes[i], b = boxes[j];
    if (a.contains(b) || b.contains(a)) continue;
    const p = a.getBoundingClientRect(), q = b.getBoundingClientRect();
    const w = Math.min(p.right, q.right) - Math.max(p.left, q.left);
    const h = Math.min(p.bottom, q.bottom) - Math.max(p.top, q.top);
    if (w > 1 && h > 1) problems.push(`${name(a)} overlaps ${name(b)}`);
  }
  // STOP: inside the window, its whole label shown, large.
  const stop = document.getElementById('estop');
  const s = stop.getBoundingClientRect();
  if (s.left < 0 || s.top < 0 || s.right > vw || s.bottom > vh) problems.push('STOP is not inside the window');
  if (stop.scrollWidth > stop.clientWidth || stop.scrollHeight > stop.clientHeight || lines(stop) !== 1) problems.push('STOP label cut or wrapped');
  if (s.height < 36 || s.width < 100) problems.push(`STOP is small (${s.width}x${s.height})`);
  if (!stop.textContent.includes('STOP')) problems.push('STOP says ' + stop.textContent);
  return problems;

}
