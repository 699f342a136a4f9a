"""The first-run guide's words: each step's title and paragraphs, its buttons, and what it
says when a load or a run did not go through.

Pure: the browser gets `GUIDE_WORDS` through ``/vocab.js`` (``static/js/guide.js`` shows
them). Text between ``**`` is shown bold (a button's or a tab's name, a point's); a
``{placeholder}`` is filled by the guide (``{fix}``: the red message's button, ``{step}``
of ``{steps}``).
"""

from __future__ import annotations

__all__ = ["GUIDE_WORDS"]

GUIDE_WORDS: dict[str, str] = {
    "count": "Step {step} of {steps}",
    "next": "Next",
    "finish": "Finish",
    "skip": "Skip guide",
    "skip-hint": "Close the guide (Esc). Your user menu opens it again.",
    "finished": "First-run guide finished.",
    "closed": "First-run guide closed. Open it again from your user menu.",
    "program-title": "This is your program",
    "program-lines": (
        "Each line is one instruction for the robot. The grey text after **'** is a "
        "comment: it says what the line does. Read them from the top."
    ),
    "program-points": (
        "The points the program moves to (**PHOME**, **PPICK**, **PPLACE**) are in the Points tab."
    ),
    "load-title": "Send it to the robot",
    "load-press": (
        "Press **Load project**: the program and its points are checked and go to the "
        "robot's memory."
    ),
    "run-title": "Run it",
    "run-press": (
        "Press **Run**. The robot's motors (the servo) start switched off: melfa asks "
        "whether to switch them on. Say yes."
    ),
    "run-real": (
        "This is the lab's real arm: it will move. Keep clear of it. **STOP** (red, top "
        "right, or Esc twice) stops it at once."
    ),
    "run-virtual": "This is a virtual robot: only the arm on the right moves, nothing in the lab.",
    "servo-title": "Switch the servo on",
    "servo-press": (
        "The servo is off, so the robot refused to move. Press **{fix}**: melfa switches it "
        "on and runs the program."
    ),
    "watch-title": "Watch it move",
    "watch-line": (
        "The arm on the right follows the robot. In the editor the line running now is "
        "marked in blue; the label above the arm names it too."
    ),
    "watch-real": "STOP (top right) stops the arm at any moment.",
    "watch-virtual": "The program ends by itself after a few moves.",
    "done-title": "Your first run worked",
    "done-points": (
        "Next: the **Points** tab lists where the arm goes; change a point, or import where "
        "the robot stands."
    ),
    "done-jog": (
        "In **Robot control** you move the arm yourself: hold W A S D and the arrow keys."
    ),
    "load-failed": "The project was not loaded",
    "load-fix": "Fix it, then press Load project again.",
    "load-fix-errors": (
        "The problems are listed under the editor, each with its line: fix them, then press "
        "Load project again."
    ),
    "load-fix-press": "Press {fix} in the red message, then Load project again.",
    "run-failed": "Run did not start",
    "run-fix-press": "Press {fix} in the red message.",
    "run-fix": "Do what the red message says, then press Run again.",
}
"""The guide's steps in order: program, load, run (servo when the servo was off), watch,
done; ``-real`` and ``-virtual`` are said on the lab's arm and on a simulated one."""
