"""The words melfa says about the robot, in one place every part reads.

Pure: enums with a stable wire value (what the server sends, what the browser and the
desktop client switch on) and, beside each member, the student's words for it and the fix
to offer. Nothing downstream parses English: a client shows the words of a code it was
sent. The browser gets this vocabulary as a generated module, the desktop client imports
it, and the service, the web routes and ROS raise and send its codes.

One module per family of words:

- ``commands``: what a student can ask of the robot (load, run, jog, …), its label and
  whether it moves the arm.
- ``refusals``: why the service refused a command (the lease, the instructor's gate, a
  program with errors …), with the fix.
- ``jog``: why a jog ended.
- ``lease``: control of the robot: why it changed hands, how its holder is connected, the
  header's words and toasts.
- ``queue``: the shared robot's queue: its steps, each student's place, every word of its
  panel, its claim dialog and the desktop's queue line.
- ``activity``: what the robot is doing, as one word every view shows the same way.
"""
