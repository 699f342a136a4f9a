"""What the robot is doing: moved to `melfa.vocab.activity` (the word and its sentence live
together, for every view). Kept so the service's imports read as before."""

from melfa.vocab.activity import Activity, Facts, Motion, MotionKind, activity_of

__all__ = ["Activity", "Facts", "Motion", "MotionKind", "activity_of"]
