"""melfa.desktop: the small Qt client (the thesis's RQt frontend, chapter 5).

It talks to a running `melfa serve` through the same HTTP and WebSocket API as the
browser (docs/api.md) and nothing private, which is the point the thesis made: any client
can drive the robot service. Layers, from the bottom (each imports only its own and those
below; `tests/architecture/test_desktop_layers.py` checks it):

- no Qt: `files` and `api` (file rules and the HTTP client), `live` (the WebSocket feed in
  a thread), `messages` (its typed messages, and the one-click fixes this client offers),
  `words` (what it says);
- Qt's plumbing: `tasks` (API calls off the GUI thread), `hold`, `style`, `dialogs`, `view`
  (what the presenter tells its view);
- side by side, neither importing the other: `presenter` and `live_state` (user intents
  into API calls; what the live feed says, and the held jog), and the panels (`position`,
  `robot_box`, `program_box`, `jogpad`, `login`);
- `window` wires the panels to the presenter; `app.main` starts it all.

Only the first layer is importable without PySide6 (the `desktop` extra).
"""
