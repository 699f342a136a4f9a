"""A debugger on the simulated RV-6S: `engine.Debugger` (run, pause, step, breakpoints,
variables), `view` (values as MELFA writes them), `cell` and `preflight` (what a run would
do to the real arm). Pure logic with an injected clock; `melfa debug` and the web server
drive it. See docs/debugger.md."""
