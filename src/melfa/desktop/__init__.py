"""melfa.desktop: the small Qt client (the thesis's RQt frontend, chapter 5).

It talks to a running `melfa serve` through the same HTTP and WebSocket API as the
browser (docs/api.md) and nothing private, which is the point the thesis made: any client
can drive the robot service. Layers, thinnest at the top:

- `files` and `api`: file rules and the HTTP client (pure Python, no Qt);
- `live`: the WebSocket feed in a thread (no Qt) and its typed messages;
- `presenter`: turns user intents into API calls off the GUI thread (`tasks`); what the
  live feed says, and the held jog, is `live_state`;
- `window`, `login`, `dialogs`: the widgets; `app.main` wires them up.

Only `files`, `api` and `live` are importable without PySide6 (the `desktop` extra).
"""
